//! Debian 12's `libshaderc` leaves the glslang symbols undefined and ships no shared glslang,
//! so the static archives are linked here. Link directives printed by a package's own build
//! script do not reach that script, which is why this lives in its own crate that `vkpath`
//! uses both as a dependency and as a build-dependency (see `shared/PLATFORM.md`).

fn main() {
    println!("cargo:rustc-link-search=native=/usr/lib/x86_64-linux-gnu");
    for lib in [
        "glslang",
        "SPIRV",
        "MachineIndependent",
        "GenericCodeGen",
        "OSDependent",
        "OGLCompiler",
        "glslang-default-resource-limits",
        "SPIRV-Tools-opt",
        "SPIRV-Tools",
    ] {
        println!("cargo:rustc-link-lib=static={lib}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
