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

pub mod bench;
pub mod bvh;
pub mod camera;
#[cfg(feature = "cli")]
pub mod cli;
pub mod compare;
pub mod error;
pub mod exercise;
pub mod image_io;
pub mod render;
pub mod scene;
pub mod vk;

pub use camera::Camera;
pub use error::{Error, Result};
pub use image_io::data::RenderedImage;
pub use render::settings::{
    Accel, Integrator, LightSampling, PixelFilter, RenderSettings, SamplerKind,
};
pub use render::Renderer;
pub use scene::Scene;
pub mod check;
pub mod cpu;
pub mod probe;
pub mod stats;
