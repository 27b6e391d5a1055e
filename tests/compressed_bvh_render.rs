//! The compressed wide BVH (`--accel compressed-bvh`) renders what the 4-wide one does: both
//! find the same closest hits (up to ties at equal t between triangles, which random rays
//! meet with probability ~0) and the same shadow-ray answers. `workshop` (path tracing without
//! light samples) draws the same random numbers for the same hits, so its images agree bit for
//! bit but for the rare pixel whose path met a tie. `mis` samples lights from the emissive
//! triangles in leaf order, which differs between the trees, so the same random numbers pick
//! other lights: its images agree in their mean. Also through alpha-tested materials, whose
//! test both traversals run on candidate hits.

use crate::common;

use vkpath::render::settings::Accel;
use vkpath::render::Traversal;
use vkpath::scene::materials::AlphaMode;
use vkpath::{Integrator, RenderSettings, Renderer, Scene};

/// The render of `scene` by `accel`: the mean image's values.
fn render(scene: &Scene, accel: Accel, integrator: Integrator, spp: u32) -> Vec<f32> {
    let context = common::validated_context();
    let settings = RenderSettings {
        width: 32,
        height: 24,
        spp,
        samples_per_frame: 4,
        integrator,
        accel,
        ..Default::default()
    };
    let image = Renderer::new(&context, scene, &scene.camera.unwrap(), settings)
        .unwrap()
        .render_all()
        .unwrap()
        .mean
        .concat();
    common::assert_validation_silent(&context);
    image
}

/// Asserts that the two trees' renders of `scene` agree: not black; with `workshop`, at
/// most 1 % of the values differ in their bits (a tie decided the other way changes one
/// path's pixel; a wrong traversal changes most pixels); with `mis`, the images' means
/// within 3 % (each mean averages 24 576 paths of 32 spp; measured 0.35 % apart on the
/// generated scene, identical on the glossy box, whose one light sees no reordering).
/// Returns the compressed tree's `workshop` image.
fn assert_trees_agree(name: &str, scene: &Scene) -> Vec<f32> {
    assert_eq!(
        Traversal::for_scene(scene, Accel::CompressedBvh),
        Traversal::CompressedBvh
    );
    let wide = render(scene, Accel::Bvh, Integrator::PathTracing, 8);
    let compressed = render(scene, Accel::CompressedBvh, Integrator::PathTracing, 8);
    assert!(wide.iter().any(|&v| v > 0.0), "{name}: a black image");
    let differing = wide
        .iter()
        .zip(&compressed)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    println!(
        "{name}, workshop: {differing} of {} values differ",
        wide.len()
    );
    assert!(
        differing * 100 <= wide.len(),
        "{name}, workshop: {differing} of {} values differ",
        wide.len()
    );
    let mean =
        |image: &[f32]| image.iter().map(|&v| f64::from(v)).sum::<f64>() / image.len() as f64;
    let wide_mis = mean(&render(scene, Accel::Bvh, Integrator::Mis, 32));
    let compressed_mis = mean(&render(scene, Accel::CompressedBvh, Integrator::Mis, 32));
    let relative = (compressed_mis / wide_mis - 1.0).abs();
    println!("{name}, mis: means {wide_mis:.5} and {compressed_mis:.5}, {relative:.4} apart");
    assert!(
        relative <= 0.03,
        "{name}, mis: means {wide_mis} and {compressed_mis}"
    );
    compressed
}

#[test]
fn the_compressed_bvh_renders_as_the_four_wide_one() {
    let generated = vkpath::scene::meshes::scale_test_scene(20_000).unwrap();
    assert_trees_agree("generated 2 10^4", &generated);
    let opaque = common::scenes::glossy_box(0.3);
    let opaque_image = assert_trees_agree("glossy box", &opaque);
    // One material made transparent by its alpha mask: both traversals skip its triangles
    let mut masked = common::scenes::glossy_box(0.3);
    let materials = masked.materials.as_mut().unwrap();
    materials.materials[1].alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
    materials.materials[1].base_color.w = 0.25;
    assert!(masked.uses_alpha());
    let masked_image = assert_trees_agree("glossy box, a masked material", &masked);
    assert_ne!(opaque_image, masked_image, "the mask changes the image");
}
