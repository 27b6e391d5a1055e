//! The material kernels compile out what a scene's materials do not use, told by
//! specialization constants; each cut must keep every bit of the image:
//! - no specular lobe (`SCENE_HAS_SPECULAR` false): Lambertian surfaces skip the GGX maths;
//! - one texture slot: its lookup runs without the loop over the slots.
//!
//! Each test renders a scene and the same scene with one more material that no triangle
//! uses, which turns the cut off, and compares the bits.

use crate::common;

use vkpath::scene::materials::{PbrMaterial, TextureBinding};
use vkpath::scene::textures::TextureTransform;
use vkpath::{Integrator, RenderSettings, Scene};

use glam::Vec3;

/// A small render of `scene` with `integrator`.
fn render(scene: &Scene, integrator: Integrator) -> vkpath::RenderedImage {
    common::render_scene(
        scene,
        RenderSettings {
            width: 24,
            height: 18,
            spp: 8,
            integrator,
            ..Default::default()
        },
    )
}

/// Renders `plain` and `extended` (the same triangles, one more unused material) with the
/// integrators that sample the BSDF, evaluate it for light samples and weigh both by MIS,
/// and fails unless they agree bit for bit.
fn assert_renders_the_same(plain: &Scene, extended: &Scene) {
    for integrator in [Integrator::PathTracing, Integrator::Nee, Integrator::Mis] {
        let a = render(plain, integrator);
        let b = render(extended, integrator);
        assert!(
            a.mean.iter().any(|p| p[0] > 0.0),
            "{integrator:?}: a black image"
        );
        assert_eq!(
            common::worst_ulps_apart(&a, &b),
            0,
            "{integrator:?}: the images differ"
        );
    }
}

/// `scene` with `material` appended to its materials, used by no triangle.
fn with_unused_material(scene: &Scene, material: PbrMaterial) -> Scene {
    let mut extended = scene.clone();
    extended
        .materials
        .as_mut()
        .unwrap()
        .materials
        .push(material);
    extended
}

#[test]
fn lambertian_scenes_render_exactly_as_with_the_specular_lobe() {
    let plain = common::scenes::textured_lambertian_box();
    assert!(!plain.materials.as_ref().unwrap().uses_specular());
    let mut shiny = PbrMaterial::lambertian(Vec3::splat(0.5), Vec3::ZERO, false);
    shiny.specular = 1.0;
    let extended = with_unused_material(&plain, shiny);
    assert!(extended.materials.as_ref().unwrap().uses_specular());
    assert_renders_the_same(&plain, &extended);
}

#[test]
fn one_texture_slot_renders_exactly_as_the_loop_over_slots() {
    // The box's floor has a base colour texture only; the extra material's emissive
    // texture makes it two slots, which the kernel then loops over.
    let plain = common::scenes::textured_lambertian_box();
    let mut glowing = PbrMaterial::lambertian(Vec3::splat(0.5), Vec3::ONE, false);
    glowing.emissive_texture = Some(TextureBinding::new(0, TextureTransform::identity()));
    let extended = with_unused_material(&plain, glowing);
    assert_renders_the_same(&plain, &extended);
}
