//! The loop over all triangles compiled into the kernel (`Traversal::ConstantTriangles`, the
//! default for small scenes) and the same loop over the texel buffer (`Traversal::Linear`)
//! trace the same rays with the same arithmetic: their renders must be bit-identical.

mod common;

use vkpath::render::Traversal;
use vkpath::{Integrator, RenderSettings, Renderer, Scene};

/// The embedded linear kernel's SPIR-V words.
fn path_tracer_spirv() -> Vec<u32> {
    ash::util::read_spv(&mut std::io::Cursor::new(vkpath::shaders::PATH_TRACER)).unwrap()
}

fn render(integrator: Integrator, traversal: Traversal) -> Vec<f32> {
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let settings = RenderSettings {
        width: 24,
        height: 24,
        spp: 8,
        samples_per_frame: 4,
        integrator,
        ..Default::default()
    };
    let spirv = path_tracer_spirv();
    let camera = scene.camera.unwrap();
    let mut renderer =
        Renderer::with_kernel(&context, &scene, &camera, settings, &spirv, traversal).unwrap();
    renderer.render_all().unwrap().mean.concat()
}

#[test]
fn constant_triangles_render_exactly_as_the_texel_loop() {
    for integrator in [Integrator::PathTracing, Integrator::Mis] {
        let constant = render(integrator, Traversal::ConstantTriangles);
        let linear = render(integrator, Traversal::Linear);
        assert!(
            constant.iter().any(|&v| v > 0.0),
            "{integrator:?}: a black image"
        );
        let differing = constant
            .iter()
            .zip(&linear)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(
            differing,
            0,
            "{integrator:?}: {differing} of {} values differ",
            constant.len()
        );
    }
}

#[test]
fn constant_triangles_refuse_a_scene_that_does_not_fit() {
    let context = common::validated_context();
    let scene = vkpath::scene::meshes::scale_test_scene(200).unwrap();
    let spirv = path_tracer_spirv();
    let result = Renderer::with_kernel(
        &context,
        &scene,
        &scene.camera.unwrap(),
        RenderSettings::default(),
        &spirv,
        Traversal::ConstantTriangles,
    );
    let message = result.err().expect("an error").to_string();
    assert!(message.contains("at most 64 triangles"), "{message}");
}
