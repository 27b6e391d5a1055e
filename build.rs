//! Compiles every compute shader in `glsl/` to SPIR-V with shaderc and embeds it, and turns
//! the `#define`s of `glsl/shared.h` into Rust constants (`vkpath::contract`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use shaderc_link as _;

#[path = "src/shader_compiler.rs"]
mod shader_compiler;

#[path = "src/kernels/builds.rs"]
#[allow(
    dead_code,
    reason = "the library uses the macro names; the build script only the list"
)]
mod builds;

/// One build of one kernel: its GLSL file, the build's name and the macros it defines.
struct KernelJob {
    file_name: String,
    name: String,
    source: String,
    macros: &'static [(&'static str, &'static str)],
}

fn main() {
    // Read at run time: a build script compiled for one checkout may run for another.
    let manifest_dir = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let glsl_dir = Path::new(&manifest_dir).join("glsl");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    // Every profile's kernels are optimized (shaderc's `Performance`, spirv-opt): lavapipe
    // turns unoptimized SPIR-V into NIR about 3 times slower (a glTF-material kernel's
    // pipeline took 2.6-2.8 s of CPU against 0.5-1.0 s), and the tests create hundreds of
    // pipelines. `VKPATH_UNOPTIMIZED_KERNELS=1` at build time keeps them as written, to read
    // the SPIR-V against the GLSL line by line.
    println!("cargo:rerun-if-env-changed=VKPATH_UNOPTIMIZED_KERNELS");
    let optimize = std::env::var_os("VKPATH_UNOPTIMIZED_KERNELS").is_none_or(|v| v != "1");
    println!("cargo:rerun-if-changed=glsl");
    println!("cargo:rerun-if-changed=src/shader_compiler.rs");
    println!("cargo:rerun-if-changed=src/kernels/builds.rs");

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

    let mut jobs: Vec<KernelJob> = Vec::new();
    for file in files
        .iter()
        .filter(|f| f.extension().is_some_and(|e| e == "comp"))
    {
        let stem = file.file_stem().unwrap().to_string_lossy().to_string();
        let file_name = file.file_name().unwrap().to_string_lossy().to_string();
        let source = std::fs::read_to_string(file).expect("shader is readable");
        jobs.push(KernelJob {
            file_name: file_name.clone(),
            name: stem.clone(),
            source: source.clone(),
            macros: &[],
        });
        for build in builds::EXTRA_BUILDS {
            if build.source == stem {
                jobs.push(KernelJob {
                    file_name: file_name.clone(),
                    name: build.name.to_string(),
                    source: source.clone(),
                    macros: build.macros,
                });
            }
        }
    }
    // Compiled on every core (optimizing the kernels takes minutes on one), each thread
    // taking every n-th job; the results are written in the jobs' order.
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    let mut compiled: Vec<Option<_>> = (0..jobs.len()).map(|_| None).collect();
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|first| {
                let (jobs, resolve) = (&jobs, &resolve);
                scope.spawn(move || {
                    (first..jobs.len())
                        .step_by(threads)
                        .map(|index| {
                            let job = &jobs[index];
                            let result = shader_compiler::compile_compute_shader(
                                &job.source,
                                &job.file_name,
                                resolve,
                                job.macros,
                                optimize,
                            );
                            (index, result)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for worker in workers {
            for (index, result) in worker.join().expect("a kernel compile thread") {
                compiled[index] = Some(result);
            }
        }
    });

    let mut shaders_rs = format!(
        "/// Whether the kernels' SPIR-V is optimized (spirv-opt drops what a build never reads);\n\
         /// false only when built with `VKPATH_UNOPTIMIZED_KERNELS=1`.\n\
         pub const KERNELS_OPTIMIZED: bool = {optimize};\n"
    );
    let mut build_names = Vec::new();
    let mut failed = false;
    for (
        KernelJob {
            file_name, name, ..
        },
        result,
    ) in jobs.iter().zip(compiled)
    {
        {
            match result.expect("every job compiled") {
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
                    build_names.push(name.clone());
                    writeln!(
                    shaders_rs,
                    "/// SPIR-V of `glsl/{file_name}` ({name}).\npub const {}: &[u8] = include_bytes!({:?});",
                    name.to_uppercase(),
                    spv_path.display().to_string()
                )
                .unwrap();
                }
                Err(error) => {
                    let message = error.to_string();
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

    // Every build by name, for `crate::kernels`.
    writeln!(
        shaders_rs,
        "/// Every build's SPIR-V, by build name.\npub const SPIRV: &[(&str, &[u8])] = &["
    )
    .unwrap();
    for name in &build_names {
        writeln!(shaders_rs, "    ({name:?}, {}),", name.to_uppercase()).unwrap();
    }
    shaders_rs.push_str("];\n");

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

/// Rust constants for every `#define NAME <value>` line of the shared header: a `u32` for a
/// plain decimal integer, an `f32` with the literal as written for a float literal. The
/// comment lines right above a define become its doc comment. Any other value fails the
/// build, so that nothing in the header is silently left out of the contract.
fn contract_constants(header: &Path) -> String {
    let text = std::fs::read_to_string(header).expect("glsl/shared.h is readable");
    let mut rust = String::new();
    let mut comment = Vec::new();
    for (line_index, line) in text.lines().enumerate() {
        let line = line.trim();
        if let Some(c) = line.strip_prefix("//") {
            comment.push(c.trim().to_string());
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if let ["#define", name, value @ ..] = words.as_slice() {
            if !value.is_empty() {
                let doc = if comment.is_empty() {
                    format!("`{name}` of glsl/shared.h.")
                } else {
                    comment.join(" ")
                };
                let (rust_type, literal) = match value {
                    [value] if value.parse::<u32>().is_ok() => ("u32", *value),
                    [value] if is_float_literal(value) => ("f32", *value),
                    _ => panic!(
                        "glsl/shared.h:{}: #define {name} {}: the contract holds plain decimal \
                         integers and float literals (that glslang and Rust round alike) only",
                        line_index + 1,
                        value.join(" ")
                    ),
                };
                writeln!(
                    rust,
                    "/// {doc}\npub const {name}: {rust_type} = {literal};"
                )
                .unwrap();
            }
        }
        comment.clear();
    }
    rust
}

/// Whether `text` is a float literal that GLSL and Rust both read, and read alike: decimal
/// digits with a fractional part (`1.15`), an exponent (`1e-3`) or both
/// (`7.62939453125e-06`); no sign, no suffix, no leading or trailing point. glslang reads a
/// float literal as a double and rounds that to float, Rust rounds it to the nearest f32
/// directly; a literal where the double rounding gives another float is refused too.
fn is_float_literal(text: &str) -> bool {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let (mantissa, exponent) = match text.split_once(['e', 'E']) {
        Some((mantissa, exponent)) => {
            let exponent = exponent.strip_prefix(['+', '-']).unwrap_or(exponent);
            (mantissa, Some(exponent))
        }
        None => (text, None),
    };
    let mantissa_ok = match mantissa.split_once('.') {
        Some((whole, fraction)) => digits(whole) && digits(fraction),
        None => digits(mantissa) && exponent.is_some(),
    };
    mantissa_ok
        && exponent.is_none_or(digits)
        && text.parse::<f32>().is_ok_and(|value| {
            value.is_finite() && text.parse::<f64>().map(|double| double as f32) == Ok(value)
        })
}
