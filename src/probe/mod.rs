//! GPU probe kernels: each `glsl/probe_<function>.comp` includes the same GLSL files as the
//! path tracer and evaluates one workshop function on a storage buffer of inputs, so that
//! tests can compare the GPU with the CPU twins (`crate::cpu`) input by input, and
//! `vkpath check` can compare a user's version of a function with the reference.
//!
//! - `kernel`: which kernels exist (`ProbeKind`) and their pipelines (`ProbePipeline`);
//! - `layout`: the input and output structs, byte for byte as the kernels declare them;
//! - `runner`: `Probe`, which runs any probe kernel on a `Vec` of inputs (the one runner),
//!   and `ProbeRunner`, which runs the workshop functions' probes against a scene;
//! - `inputs`: deterministic random inputs shared by the tests and `vkpath check`;
//! - `brdf_probe`: the glTF BRDF's probe (`glsl/probe_brdf.comp`), which binds only its
//!   inputs and outputs;
//! - `guiding_probe`: path guiding's guide (`glsl/probe_guiding.comp`);
//! - `light_tree_probe`: the light tree's probe (`glsl/probe_light_tree.comp`);
//! - `medium_probe`: a homogeneous medium and its phase function (`glsl/probe_medium.comp`),
//!   which binds only its inputs and outputs;
//! - `punctual_probe`: the punctual lights' probe (`glsl/probe_punctual_lights.comp`),
//!   which binds the lights' words instead of a scene;
//! - `surface_probe`: the surface functions' probe (`glsl/probe_surface.comp`), which
//!   binds a scene with its materials;
//! - `texture_probe`: the texture functions' probe (`glsl/probe_sample_texture.comp`),
//!   which binds textures instead of a scene;
//! - `compare`: error measures (ulps, relative errors) and the near-degenerate
//!   ray-triangle configurations where two correct algorithms may disagree.

pub mod brdf_probe;
pub mod compare;
pub mod guiding_probe;
pub mod inputs;
pub mod kernel;
pub mod layout;
pub mod light_tree_probe;
pub mod medium_probe;
pub mod punctual_probe;
pub mod runner;
pub mod surface_probe;
pub mod texture_probe;

pub use kernel::{ProbeKind, ProbePipeline};
pub use layout::*;
pub use runner::{Probe, ProbeRunner, ProbeScene};
