//! vkpath: a headless, progressive path tracer that runs the Path Tracing Workshop's GLSL
//! compute shaders through Vulkan.
#![warn(missing_docs)]

use shaderc_link as _;

pub mod contract {
    //! Binding indices, workgroup size, specialization-constant ids and enumerations shared
    //! with the shaders, generated from `glsl/shared.h` by `build.rs`.
    include!(concat!(env!("OUT_DIR"), "/contract.rs"));
}

pub mod shaders {
    //! The embedded SPIR-V of every kernel in `glsl/`, and the GLSL sources themselves.
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}

pub mod shader_compiler;

pub mod camera;
pub mod gpu_types;
pub mod scene;
