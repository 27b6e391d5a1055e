//! Outputs for compositing, denoising and debugging (`--aov`): the first hit's albedo,
//! shading normal, camera distance and material (metallic, roughness), each averaged over
//! the pixel's samples like the colour. Each is a render of its own with the same settings
//! (camera rays only: cheap next to the paths), by the kernels' INTEGRATOR_RAY_TRACING,
//! INTEGRATOR_NORMAL, INTEGRATOR_DEPTH and INTEGRATOR_MATERIAL. Where a ray escapes, all
//! four are 0.

use std::sync::Arc;

use crate::camera::Camera;
use crate::error::Result;
use crate::render::settings::{Integrator, RenderSettings};
use crate::render::Renderer;
use crate::scene::Scene;
use crate::vk::Context;

/// One output beside the colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Aov {
    /// The first hit's base colour (after textures), linear RGB.
    Albedo,
    /// The first hit's shading normal, world space, facing the camera.
    Normal,
    /// The first hit's distance from the camera.
    Depth,
    /// The first hit's (metallic, roughness, 0) after texture lookups (glTF: the factors
    /// times the metallic-roughness texture's B and G), as the BRDF gets them; (0, 1, 0) on
    /// the workshop's Lambertian triangles (scenes rendered without glTF materials).
    Material,
}

impl Aov {
    /// The EXR layer's name.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Material => "material",
        }
    }

    /// The integrator that computes it.
    fn integrator(self) -> Integrator {
        match self {
            Aov::Albedo => Integrator::RayTracing,
            Aov::Normal => Integrator::Normal,
            Aov::Depth => Integrator::Depth,
            Aov::Material => Integrator::Material,
        }
    }
}

/// Renders `aov` with `settings` (its integrator replaced) and returns each pixel's average,
/// rows top-down (depth in all three components).
pub fn render_aov(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    aov: Aov,
) -> Result<Vec<[f32; 3]>> {
    let settings = RenderSettings {
        integrator: aov.integrator(),
        // Every pixel of an AOV takes every sample (its noise is not the colour's).
        noise_threshold: None,
        ..settings.clone()
    };
    let mut renderer = Renderer::new(context, scene, camera, settings)?;
    let image = renderer.render_all()?;
    Ok(image.mean.iter().map(|p| [p[0], p[1], p[2]]).collect())
}
