//! `libshaderc` needs glslang and SPIRV-Tools, and on Debian 12 it leaves their symbols
//! undefined and no shared glslang is shipped, so their static archives are linked here.
//! Link directives printed by a package's own build script do not reach that script, which
//! is why this lives in its own crate that `vkpath` uses both as a dependency and as a
//! build-dependency (see `shared/PLATFORM.md`).
//!
//! Where the archives are, first match wins:
//! 1. `VKPATH_GLSLANG_LIB_DIR` (or `SHADERC_LIB_DIR`, which the shaderc crate reads too);
//! 2. `pkg-config --variable=libdir glslang`;
//! 3. Debian's multiarch folder for the target, `/usr/lib/<arch>-linux-gnu`.
//!
//! Each archive that exists there is linked; glslang itself must exist.

use std::path::{Path, PathBuf};

/// The static archives, in link order (dependents before their dependencies). Debian 12
/// ships all of them; other distributions merge some into `libglslang.a`, which is why a
/// missing one other than glslang is skipped.
const ARCHIVES: [&str; 9] = [
    "glslang",
    "SPIRV",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "glslang-default-resource-limits",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    for variable in ["VKPATH_GLSLANG_LIB_DIR", "SHADERC_LIB_DIR"] {
        println!("cargo:rerun-if-env-changed={variable}");
    }
    let directory = library_directory();
    if !directory.join("libglslang.a").is_file() {
        panic!(
            "libglslang.a is not in {}: install glslang-dev and libshaderc-dev (Debian), or set \
             VKPATH_GLSLANG_LIB_DIR to the folder that holds glslang's static archives",
            directory.display()
        );
    }
    println!("cargo:rustc-link-search=native={}", directory.display());
    for archive in ARCHIVES {
        if directory.join(format!("lib{archive}.a")).is_file() {
            println!("cargo:rustc-link-lib=static={archive}");
        }
    }
}

/// The folder of the static archives (see the crate documentation).
fn library_directory() -> PathBuf {
    for variable in ["VKPATH_GLSLANG_LIB_DIR", "SHADERC_LIB_DIR"] {
        if let Ok(directory) = std::env::var(variable) {
            return PathBuf::from(directory);
        }
    }
    if let Ok(directory) = pkg_config::get_variable("glslang", "libdir") {
        if Path::new(&directory).join("libglslang.a").is_file() {
            return PathBuf::from(directory);
        }
    }
    // Debian's multiarch triple: x86_64-unknown-linux-gnu -> x86_64-linux-gnu.
    let target = std::env::var("TARGET").unwrap_or_else(|_| "x86_64-unknown-linux-gnu".into());
    let architecture = target.split('-').next().unwrap_or("x86_64");
    PathBuf::from(format!("/usr/lib/{architecture}-linux-gnu"))
}
