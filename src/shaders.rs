//! The embedded SPIR-V of every kernel build in `glsl/` (one constant per build, named after
//! it, and `SPIRV` to look a build up by name), and the GLSL sources themselves, for
//! run-time compilation against the same includes. `build.rs` writes them; which builds a
//! kernel has is declared in `crate::kernels`.

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
