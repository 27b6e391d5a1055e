//! Compiles every compute shader in `glsl/` to SPIR-V with shaderc and embeds it, and turns
//! the `#define`s of `glsl/shared.h` into Rust constants (`vkpath::contract`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use shaderc_link as _;

#[path = "src/shader_compiler.rs"]
mod shader_compiler;

/// Kernels compiled more than once with different macros: (source stem, variant stem, macros).
const VARIANTS: &[(&str, &str, &[(&str, &str)])] =
    &[("path_tracer", "path_tracer_bvh", &[("USE_BVH", "1")])];

fn main() {
    // Read at run time: a build script compiled for one checkout may run for another.
    let manifest_dir = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let glsl_dir = Path::new(&manifest_dir).join("glsl");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let optimize = std::env::var("PROFILE")
        .map(|p| p == "release")
        .unwrap_or(false);
    println!("cargo:rerun-if-changed=glsl");
    println!("cargo:rerun-if-changed=src/shader_compiler.rs");

    let mut files: Vec<PathBuf> = std::fs::read_dir(&glsl_dir)
        .expect("glsl/ is readable")
        .map(|entry| entry.expect("glsl/ entry").path())
        .collect();
    files.sort();
    for file in &files {
        println!("cargo:rerun-if-changed={}", file.display());
    }

    let resolve = |name: &str| -> Option<String> {
        let path = glsl_dir.join(name);
        // Includes stay inside glsl/.
        if name.contains("..") || name.starts_with('/') {
            return None;
        }
        std::fs::read_to_string(path).ok()
    };

    let mut shaders_rs = String::new();
    let mut failed = false;
    for file in files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "comp"))
    {
        let stem = file.file_stem().unwrap().to_string_lossy().to_string();
        let file_name = file.file_name().unwrap().to_string_lossy().to_string();
        let source = std::fs::read_to_string(file).expect("shader is readable");
        let mut builds: Vec<(String, &[(&str, &str)])> = vec![(stem.clone(), &[])];
        for (source_stem, variant, macros) in VARIANTS {
            if *source_stem == stem {
                builds.push((variant.to_string(), macros));
            }
        }
        for (name, macros) in builds {
            match shader_compiler::compile_compute_shader(
                &source, &file_name, &resolve, macros, optimize,
            ) {
                Ok(compiled) => {
                    for line in compiled.warnings.lines() {
                        println!("cargo:warning={line}");
                    }
                    let spv_path = out_dir.join(format!("{name}.spv"));
                    let bytes: Vec<u8> = compiled
                        .spirv
                        .iter()
                        .flat_map(|w| w.to_le_bytes())
                        .collect();
                    std::fs::write(&spv_path, bytes).expect("OUT_DIR is writable");
                    writeln!(
                    shaders_rs,
                    "/// SPIR-V of `glsl/{file_name}` ({name}).\npub const {}: &[u8] = include_bytes!({:?});",
                    name.to_uppercase(),
                    spv_path.display().to_string()
                )
                .unwrap();
                }
                Err(message) => {
                    eprintln!("{message}");
                    for line in message.lines() {
                        println!("cargo:warning={line}");
                    }
                    failed = true;
                }
            }
        }
    }
    if failed {
        panic!("GLSL compilation failed (messages above name file and line)");
    }

    // Every GLSL file's text, for run-time compilation against the same includes.
    writeln!(
        shaders_rs,
        "/// The text of every file in `glsl/`, by file name.\npub const GLSL_SOURCES: &[(&str, &str)] = &["
    )
    .unwrap();
    for file in &files {
        let file_name = file.file_name().unwrap().to_string_lossy();
        writeln!(
            shaders_rs,
            "    ({file_name:?}, include_str!({:?})),",
            file.display().to_string()
        )
        .unwrap();
    }
    shaders_rs.push_str("];\n");
    std::fs::write(out_dir.join("shaders.rs"), shaders_rs).expect("OUT_DIR is writable");

    std::fs::write(
        out_dir.join("contract.rs"),
        contract_constants(&glsl_dir.join("shared.h")),
    )
    .expect("OUT_DIR is writable");
}

/// Rust constants for every `#define NAME <integer>` line of the shared header.
fn contract_constants(header: &Path) -> String {
    let text = std::fs::read_to_string(header).expect("glsl/shared.h is readable");
    let mut rust = String::new();
    let mut comment = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if let Some(c) = line.strip_prefix("//") {
            comment.push(c.trim().to_string());
            continue;
        }
        let mut words = line.split_whitespace();
        if let (Some("#define"), Some(name), Some(value), None) =
            (words.next(), words.next(), words.next(), words.next())
        {
            if let Ok(value) = value.parse::<u32>() {
                let doc = if comment.is_empty() {
                    format!("`{name}` of glsl/shared.h.")
                } else {
                    comment.join(" ")
                };
                writeln!(rust, "/// {doc}\npub const {name}: u32 = {value};").unwrap();
            }
        }
        comment.clear();
    }
    rust
}
