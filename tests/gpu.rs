//! The library's GPU tests on lavapipe: GLSL functions against their Rust twins, χ² tests of
//! the GPU samplers, analytic scenes (furnace), integrators and traversals against each other,
//! and image tests. One test binary for all of them, so that the crate is linked once; each
//! file below is a module, run alone with `cargo test --test gpu <module>::`.

mod common;

#[path = "brdf_twins.rs"]
mod brdf_twins;
#[path = "bvh_gpu.rs"]
mod bvh_gpu;
#[path = "compressed_bvh_render.rs"]
mod compressed_bvh_render;
#[path = "converged_pixels.rs"]
mod converged_pixels;
#[path = "denoise.rs"]
mod denoise;
#[path = "furnace.rs"]
mod furnace;
#[path = "glass_render.rs"]
mod glass_render;
#[path = "gltf_camera.rs"]
mod gltf_camera;
#[path = "gpu_chi2.rs"]
mod gpu_chi2;
#[path = "gpu_twins.rs"]
mod gpu_twins;
#[path = "guided_render.rs"]
mod guided_render;
#[path = "guided_twins.rs"]
mod guided_twins;
#[path = "guiding.rs"]
mod guiding;
#[path = "image_parity.rs"]
mod image_parity;
#[path = "integrators_agree.rs"]
mod integrators_agree;
#[path = "light_tree.rs"]
mod light_tree;
#[path = "light_tree_twins.rs"]
mod light_tree_twins;
#[path = "lights_render.rs"]
mod lights_render;
#[path = "long_paths.rs"]
mod long_paths;
#[path = "material_aov.rs"]
mod material_aov;
#[path = "materials_render.rs"]
mod materials_render;
#[path = "medium_render.rs"]
mod medium_render;
#[path = "medium_twins.rs"]
mod medium_twins;
#[path = "punctual_twins.rs"]
mod punctual_twins;
#[path = "smooth_render.rs"]
mod smooth_render;
#[path = "specializations_agree.rs"]
mod specializations_agree;
#[path = "surface_twins.rs"]
mod surface_twins;
#[path = "texture_twins.rs"]
mod texture_twins;
#[path = "traversals_agree.rs"]
mod traversals_agree;
#[path = "twins_named.rs"]
mod twins_named;
#[path = "validation.rs"]
mod validation;
#[path = "volume_scatter_render.rs"]
mod volume_scatter_render;
