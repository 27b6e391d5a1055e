//! `vkpath exercise guide-cell`: what path guiding learned at one point of a scene, drawn as
//! the workshop's sample displays draw samples. The guide is trained as `render --guiding`
//! trains it (mis, the scene's camera); the point is where the camera's ray through a pixel
//! first hits the scene. The left half of the picture shows 512 samples of the point's cell
//! (`sample_guide_direction`), the right half 512 cosine-weighted samples around the
//! surface's normal (Lambert's BSDF sampling), both in world space on the same sphere: where
//! the two differ, guiding sends paths where BSDF sampling would not.

use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};

use super::display::render_direction_display;
use super::view::get_sample_display_seed;
use crate::camera::Camera;
use crate::contract::EXERCISE_SAMPLE_COUNT;
use crate::cpu::guiding::{get_guide_cell_index, is_guided_cell, sample_guide_direction};
use crate::cpu::importance_sampling::sample_hemisphere_cosine;
use crate::cpu::integrator::ray_mesh_intersection;
use crate::cpu::workshop::{get_primary_ray_direction, get_random_numbers};
use crate::error::{Error, Result};
use crate::guiding::training::GuideTraining;
use crate::image_io::data::RenderedImage;
use crate::render::settings::{Integrator, RenderSettings};
use crate::render::Renderer;
use crate::scene::Scene;
use crate::vk::Context;

/// What `guide-cell` shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuideCellSetup {
    /// The training's image size (the camera's view of the scene).
    pub width: u32,
    /// The training's image size.
    pub height: u32,
    /// Training samples per pixel.
    pub training: GuideTraining,
    /// The pixel (from the top-left) whose camera ray finds the point.
    pub pixel: UVec2,
    /// Seed of the displayed samples.
    pub seed: u32,
}

/// The picture and what it shows.
#[derive(Clone, Debug)]
pub struct GuideCellView {
    /// Guide samples left, BSDF samples right (twice the display's width).
    pub image: RenderedImage,
    /// The point, world space.
    pub point: Vec3,
    /// The surface's normal there, facing the camera.
    pub normal: Vec3,
    /// The guide's cell that holds the point.
    pub cell: u32,
    /// The guide's samples (left half).
    pub guide_directions: Vec<Vec3>,
    /// The BSDF's samples (right half).
    pub bsdf_directions: Vec<Vec3>,
}

/// Trains the guide of `scene` seen by `camera`, finds the point `setup.pixel` shows and
/// draws its cell's samples next to the BSDF's, each `width` x `height`.
pub fn render_guide_cell_display(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    setup: &GuideCellSetup,
    width: u32,
    height: u32,
) -> Result<GuideCellView> {
    if setup.pixel.x >= setup.width || setup.pixel.y >= setup.height {
        return Err(Error::InvalidSettings(format!(
            "pixel {},{} is outside the {}x{} view",
            setup.pixel.x, setup.pixel.y, setup.width, setup.height
        )));
    }
    let settings = RenderSettings {
        width: setup.width,
        height: setup.height,
        spp: 1,
        integrator: Integrator::Mis,
        guiding: Some(setup.training),
        ..RenderSettings::default()
    };
    // The point: the camera ray through the pixel's centre (rows from the top, the image
    // plane's y from the bottom).
    let plane = camera.image_plane(settings.aspect());
    let x = (setup.pixel.x as f32 + 0.5) / setup.width as f32;
    let y = 1.0 - (setup.pixel.y as f32 + 0.5) / setup.height as f32;
    let direction = get_primary_ray_direction(
        x,
        y,
        plane.camera_position,
        plane.left_bottom,
        plane.right,
        plane.up,
    );
    let hit = ray_mesh_intersection(&scene.triangles, plane.camera_position, direction)
        .ok_or_else(|| {
            Error::InvalidSettings(format!(
                "the camera's ray through pixel {},{} hits nothing",
                setup.pixel.x, setup.pixel.y
            ))
        })?;
    let point = plane.camera_position + hit.t * direction;
    let triangle_normal = scene.triangles[hit.triangle_index].normal;
    let normal = if triangle_normal.dot(direction) > 0.0 {
        -triangle_normal
    } else {
        triangle_normal
    };
    let mut renderer = Renderer::new(context, scene, camera, settings)?;
    renderer.train_guide()?;
    let guide = renderer
        .guide()
        .ok_or_else(|| Error::InvalidSettings("the render trained no guide".into()))?;
    let texels = guide.texels();
    let cell = get_guide_cell_index(texels, point, normal);
    if !is_guided_cell(texels, cell) {
        return Err(Error::InvalidSettings(format!(
            "the guide's cell at {point} learned nothing (too few training paths reached it): \
             use more --guide-training-spp or another --pixel"
        )));
    }
    let mut seed = get_sample_display_seed(setup.seed);
    let count = EXERCISE_SAMPLE_COUNT as usize;
    let mut draw = || -> Vec2 { get_random_numbers(&mut seed) };
    let guide_directions: Vec<Vec3> = (0..count)
        .map(|_| sample_guide_direction(texels, cell, draw()).direction)
        .collect();
    let bsdf_directions: Vec<Vec3> = (0..count)
        .map(|_| sample_hemisphere_cosine(draw(), normal))
        .collect();
    let left = render_direction_display(context, &guide_directions, width, height)?;
    let right = render_direction_display(context, &bsdf_directions, width, height)?;
    Ok(GuideCellView {
        image: side_by_side(&left, &right),
        point,
        normal,
        cell,
        guide_directions,
        bsdf_directions,
    })
}

/// Two images of one height, `left` then `right`.
fn side_by_side(left: &RenderedImage, right: &RenderedImage) -> RenderedImage {
    let width = left.width + right.width;
    let rows = |image: &RenderedImage, row: usize| {
        let w = image.width as usize;
        (row * w)..((row + 1) * w)
    };
    let mut image = RenderedImage {
        width,
        height: left.height,
        mean: Vec::new(),
        second_moment: Vec::new(),
        sample_count: Vec::new(),
    };
    for row in 0..left.height as usize {
        for part in [left, right] {
            let range = rows(part, row);
            image.mean.extend_from_slice(&part.mean[range.clone()]);
            image
                .second_moment
                .extend_from_slice(&part.second_moment[range.clone()]);
            image
                .sample_count
                .extend_from_slice(&part.sample_count[range]);
        }
    }
    image
}
