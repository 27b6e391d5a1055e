//! Outputs for compositing, denoising and debugging (`--aov`): the first hit's albedo,
//! shading normal, camera distance and material (metallic, roughness), each averaged over
//! the pixel's samples like the colour. Each is a render of its own with the same settings
//! (camera rays only: cheap next to the paths), by the kernels' INTEGRATOR_RAY_TRACING,
//! INTEGRATOR_NORMAL, INTEGRATOR_DEPTH and INTEGRATOR_MATERIAL. Where a ray escapes, all
//! four are 0.
//!
//! The ground-truth outputs (`object_id`, `instance_id`, `material_id`, `position`, `uv`,
//! `object_position`, `z`) are not averaged: they come from one sample through each pixel's
//! centre (`crate::render::ground_truth`), so that IDs are exact integers. So do the motion
//! vectors (`motion`: two layers, `crate::render::motion_vectors`). Cryptomatte
//! (`cryptomatte`, `crate::render::cryptomatte`) is ranked over jittered samples instead.

use std::sync::Arc;

use crate::camera::Camera;
use crate::error::Result;
use crate::render::ground_truth::{
    camera_forward, check_float_exact, render_first_hits, FirstHit, FirstHits, SceneIds,
};
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
    /// Ground truth (`crate::render::ground_truth`, exact, from the ray through the pixel
    /// centre): the glTF node hit, its index + 1 (0: nothing hit).
    #[cfg_attr(feature = "cli", value(name = "object_id"))]
    ObjectId,
    /// Ground truth: the mesh copy hit, its index in the scene's copies + 1.
    #[cfg_attr(feature = "cli", value(name = "instance_id"))]
    InstanceId,
    /// Ground truth: the material hit, its index + 1.
    #[cfg_attr(feature = "cli", value(name = "material_id"))]
    MaterialId,
    /// Ground truth: the hit's world-space point.
    Position,
    /// Ground truth: the hit's first UV set (u, v, 0).
    Uv,
    /// Ground truth: the hit in its object's own frame (before the node's world transform).
    #[cfg_attr(feature = "cli", value(name = "object_position"))]
    ObjectPosition,
    /// Ground truth: the hit's camera-space z, its distance along the optical axis (positive
    /// in front of the camera; `depth` is the distance along the ray).
    Z,
    /// Ground truth: motion vectors, where the hit point is seen one frame later and one
    /// earlier, in pixels (`crate::render::motion_vectors`): two layers, `motion_forward`
    /// and `motion_backward`, each (du, dv, defined).
    Motion,
    /// Cryptomatte (`crate::render::cryptomatte`): object and material ID mattes with
    /// coverage, ranked over the pixel's jittered samples, as the specification's layers
    /// `CryptoObject00`... and `CryptoMaterial00`... with its header metadata.
    Cryptomatte,
}

impl Aov {
    /// The EXR layer's name.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Material => "material",
            Aov::ObjectId => "object_id",
            Aov::InstanceId => "instance_id",
            Aov::MaterialId => "material_id",
            Aov::Position => "position",
            Aov::Uv => "uv",
            Aov::ObjectPosition => "object_position",
            Aov::Z => "z",
            Aov::Motion => "motion",
            Aov::Cryptomatte => "cryptomatte",
        }
    }

    /// Whether it is an integer ID (exact; refused in a PNG's place, Python returns integers).
    pub fn is_id(self) -> bool {
        matches!(self, Aov::ObjectId | Aov::InstanceId | Aov::MaterialId)
    }

    /// Whether it is ground truth from the pixel centre's first hit (`render_first_hits`),
    /// not an average over the pixel's samples.
    pub fn is_ground_truth(self) -> bool {
        self.integrator() == Integrator::Triangle && self != Aov::Cryptomatte
    }

    /// Whether its layers need an EXR (IDs, and Cryptomatte's hashes and header): refused
    /// where the only output is a PNG.
    pub fn needs_exr(self) -> bool {
        self.is_id() || self == Aov::Cryptomatte
    }

    /// Whether a shard writes it (the ground truth and Cryptomatte): its layers are the same
    /// whatever samples a render takes, so every shard holds them whole and `vkpath merge`
    /// keeps them bit for bit. The averaged ones (albedo, normal, depth, material) are not.
    pub fn goes_into_shards(self) -> bool {
        self.integrator() == Integrator::Triangle
    }

    /// Whether its EXR layer has one channel (`name.Z`).
    pub fn is_single_channel(self) -> bool {
        matches!(self, Aov::Depth | Aov::Z) || self.is_id()
    }

    /// The integrator that computes it.
    fn integrator(self) -> Integrator {
        match self {
            Aov::Albedo => Integrator::RayTracing,
            Aov::Normal => Integrator::Normal,
            Aov::Depth => Integrator::Depth,
            Aov::Material => Integrator::Material,
            Aov::ObjectId
            | Aov::InstanceId
            | Aov::MaterialId
            | Aov::Position
            | Aov::Uv
            | Aov::ObjectPosition
            | Aov::Z
            | Aov::Motion
            | Aov::Cryptomatte => Integrator::Triangle,
        }
    }
}

/// The pixels of a ground-truth `aov` (`Aov::is_ground_truth`) from each pixel's first hit,
/// rows top-down (one-channel layers in all three components); 0 where nothing was hit.
/// `Aov::Motion`'s two layers come from `motion_vectors::motion_pixels` (here: 0).
pub fn ground_truth_pixels(
    scene: &Scene,
    camera: &Camera,
    hits: &FirstHits,
    aov: Aov,
) -> Result<Vec<[f32; 3]>> {
    let ids = SceneIds::new(scene);
    let largest = match aov {
        Aov::ObjectId => ids.largest_object_id(),
        Aov::InstanceId => ids.largest_instance_id(),
        Aov::MaterialId => ids.largest_material_id(),
        _ => 0,
    };
    check_float_exact(aov.name(), largest)?;
    let forward = camera_forward(camera);
    let value = |hit: &FirstHit| -> [f32; 3] {
        let id = |id: u64| [id as f32; 3];
        match aov {
            Aov::ObjectId => id(ids.object_id(hit.triangle)),
            Aov::InstanceId => id(ids.instance_id(hit.triangle)),
            Aov::MaterialId => id(ids.material_id(hit.triangle)),
            Aov::Uv => ids.uv(hit).extend(0.0).to_array(),
            Aov::ObjectPosition => ids.object_position(hit).to_array(),
            Aov::Z => [(ids.position(hit) - camera.position).dot(forward); 3],
            Aov::Position => ids.position(hit).to_array(),
            Aov::Albedo
            | Aov::Normal
            | Aov::Depth
            | Aov::Material
            | Aov::Motion
            | Aov::Cryptomatte => [0.0; 3],
        }
    };
    Ok(hits
        .hits
        .iter()
        .map(|hit| hit.as_ref().map_or([0.0; 3], value))
        .collect())
}

/// Renders `aov` with `settings` (its integrator replaced) and returns each pixel's average,
/// rows top-down (depth in all three components); a ground-truth `aov` from the pixel
/// centre's first hit (`ground_truth_pixels`).
pub fn render_aov(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    aov: Aov,
) -> Result<Vec<[f32; 3]>> {
    if aov.is_ground_truth() {
        let hits = render_first_hits(context, scene, camera, settings)?;
        return ground_truth_pixels(scene, camera, &hits, aov);
    }
    if aov == Aov::Cryptomatte {
        return Err(crate::error::Error::InvalidSettings(
            "--aov cryptomatte has layers of its own (crate::render::cryptomatte), not one image"
                .into(),
        ));
    }
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
