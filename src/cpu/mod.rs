//! The CPU reference: Rust twins of the workshop's GLSL (same names, parameters and maths,
//! operation for operation) and a CPU renderer built from them, so that tests can check the
//! GPU against the CPU sample by sample and the CPU against analytic answers.

pub mod brdf;
pub mod camera;
pub mod environment;
pub mod fresnel;
pub mod gltf_surface;
pub mod guiding;
pub mod image;
pub mod importance_sampling;
pub mod integrator;
pub mod integrators;
pub mod layered_bsdf;
pub mod light_tree;
pub mod lights;
pub mod lobe_clearcoat;
pub mod lobe_dielectric;
pub mod lobe_sheen;
pub mod lobe_thin_wall;
pub mod materials;
pub mod medium;
pub mod path_guiding;
pub mod path_loop;
pub mod phase_function;
pub mod punctual_lights;
pub mod renderer;
pub mod sample_dimensions;
pub mod scattering_vertex;
pub mod shading_basis;
pub mod sheen_albedo_table;
pub mod sobol;
pub mod surface;
pub mod texels;
pub mod textures;
pub mod thin_lens;
pub mod workshop;

#[cfg(test)]
mod furnace_tests;

pub use image::{CpuImage, PixelAccumulator};
pub use renderer::{
    add_cpu_guided_samples, add_cpu_samples, get_camera_ray, render_cpu, train_cpu_guide,
    CpuGuiding, CpuRenderSettings,
};
