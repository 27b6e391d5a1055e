//! vkpath: a headless, progressive path tracer that runs the GLSL of Christoph Peters' *Path
//! Tracing Workshop* as Vulkan compute shaders, on any GPU or on lavapipe (Mesa's CPU
//! driver).
//!
//! A render takes a [`Scene`] (the workshop's Cornell box, a glTF 2.0 or OBJ file), a
//! [`Camera`], [`RenderSettings`] and a Vulkan [`Context`]; a [`Renderer`] adds samples to
//! an accumulation image batch by batch and reads the image back as a [`RenderedImage`]
//! (per-pixel mean, second moment and sample count), which [`save_image`] writes as EXR or
//! PNG (through a [`ToneMap`]). [`compare_images`] tests whether one image is an unbiased estimate of another.
//!
//! ```
//! use vkpath::{Context, ContextOptions, RenderSettings, Renderer, Scene};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let context = Context::new(&ContextOptions::default())?;
//! let scene = Scene::builtin_cornell_box()?; // or Scene::load(Path::new("scene.gltf"))?
//! let camera = scene.camera.expect("the built-in scene has a camera");
//! let mut settings = RenderSettings::default();
//! (settings.width, settings.height, settings.spp) = (32, 32, 4);
//! let mut renderer = Renderer::new(&context, &scene, &camera, settings)?;
//! // Batches of short frames until all samples are taken; the callback sees the progress.
//! let outcome = renderer.render_to_end(|spp| println!("{spp} spp"), None)?;
//! let image = outcome.image; // linear RGB, rows top-down
//! assert_eq!(outcome.samples, 4);
//! assert!(image.average()[0] > 0.0);
//! # Ok(())
//! # }
//! ```
//!
//! The modules marked hidden in these docs (`cpu`, `probe`, `stats`, `check`, `cli`, `vk`,
//! …) are vkpath's own machinery, public for its tests and binary, not a stable API.
#![warn(missing_docs)]
// The twins test NaN as the GLSL does, `!(density > 0.0)` (false for NaN, unlike
// `density <= 0.0`): the negated comparisons are the point, not a slip.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use shaderc_link as _;

#[doc(hidden)]
pub mod contract;

#[doc(hidden)]
pub mod shaders;

#[doc(hidden)]
pub mod shader_compiler;

pub mod accel;
#[doc(hidden)]
pub mod bench;
#[doc(hidden)]
pub mod bvh;
pub mod camera;
pub mod camera_data;
#[cfg(feature = "cli")]
#[doc(hidden)]
pub mod cli;
pub mod compare;
pub mod denoise;
mod digest;
pub mod error;
#[doc(hidden)]
pub mod exercise;
#[doc(hidden)]
pub mod files;
#[doc(hidden)]
pub mod guiding;
pub mod image_io;
#[doc(hidden)]
pub mod kernels;
pub mod lens_request;
pub mod lights;
pub mod medium;
pub mod render;
pub mod scene;
#[doc(hidden)]
pub mod shadertoy;
#[doc(hidden)]
pub mod vk;

#[cfg(test)]
mod house;

pub use camera::Camera;
pub use compare::{compare_images, CompareOptions, CompareReport};
pub use error::{Error, Result};
pub use image_io::data::RenderedImage;
pub use image_io::output::{save_image, SaveOptions};
pub use image_io::tonemap::{Exposure, ToneMap};
pub use render::settings::{
    Accel, Integrator, LightSampling, LightSelection, PixelFilter, RenderSettings, SamplerKind,
};
pub use render::RenderOutcome;
pub use render::Renderer;
pub use scene::Scene;
pub use vk::{list_devices, Context, ContextOptions, DeviceInfo};
#[doc(hidden)]
pub mod check;
#[doc(hidden)]
pub mod cpu;
#[doc(hidden)]
pub mod glsl_intake;
#[doc(hidden)]
pub mod probe;
#[doc(hidden)]
pub mod stats;
