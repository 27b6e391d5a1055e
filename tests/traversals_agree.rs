//! The loop over all triangles compiled into the kernel (`Traversal::ConstantTriangles`, the
//! default for small scenes) and the same loop over the texel buffer (`Traversal::Linear`)
//! trace the same rays with the same arithmetic: their renders must be bit-identical. So must
//! the material kernels' builds with and without the layered lobes on a scene that has none,
//! and a small material scene's constant triangles (the default) and its BVH.

use crate::common;

use vkpath::kernels::variant::{path_tracer_variant, KernelSource, SceneSummary, VariantSettings};
use vkpath::render::gpu_scene::fits_lean_builds;
use vkpath::render::settings::Accel;
use vkpath::render::Traversal;
use vkpath::scene::materials::AlphaMode;
use vkpath::{Integrator, RenderSettings, Renderer, Scene};

/// How many of the values differ in their bits.
fn differing_bits(a: &[f32], b: &[f32]) -> usize {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

/// The embedded linear kernel's SPIR-V words.
fn path_tracer_spirv() -> Vec<u32> {
    ash::util::read_spv(&mut std::io::Cursor::new(vkpath::shaders::PATH_TRACER)).unwrap()
}

/// Asserts that two renders are bit-identical and not black.
fn assert_same_bits(integrator: Integrator, a: &[f32], b: &[f32]) {
    assert!(a.iter().any(|&v| v > 0.0), "{integrator:?}: a black image");
    let differing = differing_bits(a, b);
    assert_eq!(
        differing,
        0,
        "{integrator:?}: {differing} of {} values differ",
        a.len()
    );
}

/// The box's small test render.
fn box_settings(integrator: Integrator) -> RenderSettings {
    RenderSettings {
        width: 24,
        height: 24,
        spp: 8,
        samples_per_frame: 4,
        integrator,
        ..Default::default()
    }
}

fn render(integrator: Integrator, traversal: Traversal) -> Vec<f32> {
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let settings = box_settings(integrator);
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
        assert_same_bits(integrator, &constant, &linear);
    }
}

#[test]
fn the_build_for_few_triangles_renders_exactly_as_the_full_one() {
    // The workshop's box (30 triangles) gets the build that unrolls 32 constant triangles
    // instead of 64 (FEW_CONSTANT_TRIANGLES), without the light tree and guiding: the same
    // tests, so the same bits.
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let settings = box_settings(Integrator::Mis);
    assert!(fits_lean_builds(&scene, &settings));
    let summary = SceneSummary {
        triangle_count: scene.triangles.len(),
        emissive_triangles: true,
        ..SceneSummary::default()
    };
    let picked = path_tracer_variant(
        &summary,
        &VariantSettings::default(),
        Traversal::for_scene(&scene, Accel::Auto),
        KernelSource::Embedded,
    )
    .unwrap()
    .build;
    // ... without the light tree and guiding, which it does not need (the lean build)
    assert_eq!(picked.name, "path_tracer_few_triangles_lean");
    for integrator in [Integrator::PathTracing, Integrator::Mis] {
        let settings = box_settings(integrator);
        let few = Renderer::new(&context, &scene, &scene.camera.unwrap(), settings)
            .unwrap()
            .render_all()
            .unwrap()
            .mean
            .concat();
        let full = render(integrator, Traversal::ConstantTriangles);
        assert_same_bits(integrator, &few, &full);
    }
    common::assert_validation_silent(&context);
}

#[test]
fn constant_triangles_refuse_a_scene_that_does_not_fit() {
    let scene = vkpath::scene::meshes::scale_test_scene(200).unwrap();
    let message = constant_triangles_refusal(&scene, &path_tracer_spirv());
    assert!(message.contains("at most 64 triangles"), "{message}");
}

/// The error of a renderer of `scene` with `spirv` built for constant triangles.
fn constant_triangles_refusal(scene: &Scene, spirv: &[u32]) -> String {
    let context = common::validated_context();
    let result = Renderer::with_kernel(
        &context,
        scene,
        &scene.camera.unwrap(),
        RenderSettings::default(),
        spirv,
        Traversal::ConstantTriangles,
    );
    result.err().expect("an error").to_string()
}

/// Renders `scene` with the kernel that `Renderer::new` picks and with the build that keeps
/// the layered lobes (`path_tracer_materials_bvh`) through the BVH.
fn render_both_material_builds(scene: &Scene, integrator: Integrator) -> (Vec<f32>, Vec<f32>) {
    let context = common::validated_context();
    let camera = scene.camera.unwrap();
    let settings = RenderSettings {
        width: 24,
        height: 18,
        spp: 8,
        integrator,
        ..Default::default()
    };
    let picked = Renderer::new(&context, scene, &camera, settings.clone())
        .unwrap()
        .render_all()
        .unwrap()
        .mean
        .concat();
    let layered = plain_build(Traversal::Bvh, true, true);
    assert_eq!(layered.name, "path_tracer_materials_bvh");
    let spirv = layered.embedded_spirv().unwrap();
    let full = Renderer::with_kernel(&context, scene, &camera, settings, &spirv, Traversal::Bvh)
        .unwrap()
        .render_all()
        .unwrap()
        .mean
        .concat();
    common::assert_validation_silent(&context);
    (picked, full)
}

#[test]
fn the_material_build_without_layers_renders_exactly_as_the_one_with_them() {
    // A glTF scene whose materials have no transmission, coat or sheen gets the build
    // without the layered lobes (WITHOUT_LAYERS: a constant false where the other build has
    // SCENE_HAS_LAYERS specialized to false), which must change no bit. The box is small
    // enough for the constant triangles, which run the BVH's triangle tests: the picked
    // kernel (the lean build: no light tree, guiding or map either) traces it with its
    // triangles compiled in, the other through the BVH.
    let scene = common::scenes::glossy_box(0.3);
    assert!(scene.needs_material_kernels() && !scene.needs_layered_kernels());
    assert_eq!(
        Traversal::for_scene(&scene, Accel::Auto),
        Traversal::ConstantTriangles
    );
    for integrator in [Integrator::PathTracing, Integrator::Mis] {
        let (picked, full) = render_both_material_builds(&scene, integrator);
        assert_same_bits(integrator, &picked, &full);
    }
}

/// Renders `scene` with the build `Renderer::new` picks and with `full` (a build with the
/// light tree, guiding and environment maps) on `traversal`, and fails unless every bit
/// agrees.
fn assert_lean_build_renders_as(scene: &Scene, full: &str, traversal: Traversal) {
    let context = common::validated_context();
    let camera = scene.camera.unwrap();
    let spirv = vkpath::kernels::PATH_TRACER
        .builds()
        .into_iter()
        .find(|build| build.name == full)
        .unwrap()
        .embedded_spirv()
        .unwrap();
    for integrator in [Integrator::PathTracing, Integrator::Mis] {
        let settings = box_settings(integrator);
        assert!(fits_lean_builds(scene, &settings));
        let render = |renderer: vkpath::Result<Renderer>| {
            renderer.unwrap().render_all().unwrap().mean.concat()
        };
        let lean = render(Renderer::new(&context, scene, &camera, settings.clone()));
        let full = render(Renderer::with_kernel(
            &context, scene, &camera, settings, &spirv, traversal,
        ));
        assert_same_bits(integrator, &lean, &full);
    }
    common::assert_validation_silent(&context);
}

#[test]
fn the_lean_builds_render_exactly_as_the_full_ones() {
    // Renders that need no light tree, guiding or environment map take the lean builds
    // (WITHOUT_LIGHT_TREE, WITHOUT_GUIDING, WITHOUT_ENVIRONMENT_MAP: constants where the
    // full builds have specialization constants, so that the code they turn off is not in
    // the SPIR-V). A plain scene through the BVH, and a material scene under a constant
    // environment, which the lean material builds keep. (Both through auto's BVH, the
    // compressed tree: the same builds, specialized with SPEC_BVH_LAYOUT.)
    let generated = vkpath::scene::meshes::scale_test_scene(200).unwrap();
    assert_eq!(
        Traversal::for_scene(&generated, Accel::Auto),
        Traversal::CompressedBvh
    );
    assert_lean_build_renders_as(&generated, "path_tracer_bvh", Traversal::CompressedBvh);
    let white = vkpath::lights::EnvironmentSource::Background(glam::Vec3::splat(0.5));
    let sky = common::scenes::glossy_box(0.3)
        .with_environment(Some(&white))
        .unwrap();
    assert_lean_build_renders_as(
        &sky,
        "path_tracer_materials_bvh_without_layers",
        Traversal::CompressedBvh,
    );
}

#[test]
fn constant_triangles_refuse_a_scene_with_alpha() {
    // Their unrolled tests run no alpha test, so a scene with alpha-tested materials gets the
    // BVH or the texel loop, and a kernel forced onto it is refused with a one-line error.
    let mut scene = common::scenes::glossy_box(0.3);
    let materials = scene.materials.as_mut().unwrap();
    materials.materials[1].alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
    assert!(scene.uses_alpha());
    assert_eq!(
        Traversal::for_scene(&scene, Accel::Auto),
        Traversal::CompressedBvh
    );
    assert_eq!(Traversal::for_scene(&scene, Accel::None), Traversal::Linear);
    let build = plain_build(Traversal::ConstantTriangles, true, false);
    let message = constant_triangles_refusal(&scene, &build.embedded_spirv().unwrap());
    assert!(message.contains("no alpha test"), "{message}");
}

/// The build that a kernel given to `Renderer::with_kernel` is compiled as, for a scene with
/// glTF `materials` (and their `layers`) or without.
fn plain_build(traversal: Traversal, materials: bool, layers: bool) -> vkpath::kernels::Build {
    let summary = SceneSummary {
        materials,
        layers,
        ..SceneSummary::default()
    };
    path_tracer_variant(
        &summary,
        &VariantSettings::default(),
        traversal,
        KernelSource::Given,
    )
    .unwrap()
    .build
}
