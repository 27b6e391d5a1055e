//! The light tree in the path loop (`glsl/lights.glsl` with `LIGHT_SELECTION_TREE`) against
//! the CPU reference renderer with the tree (`vkpath::cpu::lights` over the twins of
//! `vkpath::cpu::light_tree`, on the words the GPU reads): nee and mis on
//! `scenes/many_lights.gltf` (1000 small lights of widely varying power, traced through its
//! BVH on the GPU) and on the Cornell box with the tree forced. Both trace the same paths
//! from the same random numbers, so only float rounding separates them (see
//! `tests/image_parity.rs`). The test asserts that the validation layer stayed silent.

use crate::common;

use vkpath::bvh::{Bvh, CompressedBvh};
use vkpath::contract::LIGHT_SELECTION_TREE;
use vkpath::cpu::{render_cpu, CpuRenderSettings};
use vkpath::render::settings::LightSelection;
use vkpath::render::traversal::Traversal;
use vkpath::{Integrator, PixelFilter, RenderSettings, Renderer, Scene};

/// Pixels agree when they differ by at most this, relative: the light samples' tolerance of
/// `tests/image_parity.rs` (Arvo's sampler amplifies the GPU's few-ulp sines and cosines;
/// measured there at most 2.7e-4). The tree's importance bounds add a few more
/// transcendental functions (`acos`-free cosines, but square roots and divisions) per level.
const RELATIVE_TOLERANCE: f32 = 1e-3;
/// Pixels whose paths may diverge, out of 768. Measured on lavapipe: 0 (nee) and 1 (mis) on
/// the many lights, 0 on the box. A walk that the GPU's rounding sends to the other child (a
/// probability within rounding of a random number) changes the light and so the pixel, as a
/// ray that grazes an edge changes the path; a wrong formula on either side changes most
/// pixels.
const MAX_DIVERGENT_PIXELS: usize = 8;

fn settings(integrator: Integrator) -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 24,
        spp: 8,
        seed: 11,
        pixel_filter: PixelFilter::Box,
        integrator,
        light_selection: LightSelection::Tree,
        ..Default::default()
    }
}

fn cpu_settings(settings: &RenderSettings) -> CpuRenderSettings {
    common::twins::cpu_settings(settings, LIGHT_SELECTION_TREE)
}

fn twins_agree(name: &str, scene: &Scene, tree_differs_from_power: bool) {
    assert!(
        !scene.needs_material_kernels(),
        "{name}: the CPU twins render the workshop's Lambertian triangles"
    );
    let camera = scene.camera.unwrap();
    let context = common::validated_context();
    for integrator in [Integrator::Nee, Integrator::Mis] {
        let settings = settings(integrator);
        let mut renderer = Renderer::new(&context, scene, &camera, settings.clone()).unwrap();
        let gpu = renderer.render_all().unwrap();
        drop(renderer);
        let plane = camera.image_plane(settings.aspect());
        // The CPU renders the triangles in the order the GPU holds them: a BVH's leaf order
        // where the GPU traverses one. The light list follows it, so the power CDF draws
        // another light for the same number in another order (767 of 768 pixels differed),
        // and the tree's probabilities too change slightly with the order its build sees
        // (mis: 6 pixels differed by 0.5-3 %, 1 in the same order).
        let traversal = Traversal::for_scene(scene, settings.accel);
        let ordered = match traversal {
            Traversal::Bvh => Bvh::build(&scene.triangles).reorder(&scene.triangles),
            Traversal::CompressedBvh => CompressedBvh::build(&scene.triangles)
                .unwrap()
                .reorder(&scene.triangles),
            _ => scene.triangles.clone(),
        };
        let cpu = render_cpu(&ordered, &plane, &cpu_settings(&settings));
        let agreement = common::twins::compare_twin_images(&gpu, &cpu, RELATIVE_TOLERANCE);
        let divergent = &agreement.divergent;
        println!(
            "{name} {integrator:?}: {} of {} pixels diverge; agreeing pixels differ by at most \
             {:.2e} relative",
            divergent.len(),
            gpu.mean.len(),
            agreement.worst_agreeing
        );
        assert!(
            divergent.len() <= MAX_DIVERGENT_PIXELS,
            "{name} {integrator:?}: {} pixels diverge (x, y, GPU, CPU): {:?}",
            divergent.len(),
            &divergent[..divergent.len().min(5)]
        );
        assert!(
            agreement.blocks_agree,
            "{name} {integrator:?}: block means differ: {agreement:?}"
        );
        // The tree chose the lights: the power CDF's image of the same paths differs. Not
        // on the Cornell box: its light is a quad's two triangles, of equal power and the
        // same bounding box, so the tree picks each with probability 1/2, as the CDF does.
        if !tree_differs_from_power {
            continue;
        }
        let power = render_cpu(
            &scene.triangles,
            &plane,
            &CpuRenderSettings {
                light_selection: vkpath::contract::LIGHT_SELECTION_POWER,
                ..cpu_settings(&settings)
            },
        );
        assert_ne!(power.mean(), cpu.mean(), "{name} {integrator:?}");
    }
    common::assert_validation_silent(&context);
}

#[test]
fn gpu_and_cpu_choose_the_same_lights_by_the_tree() {
    let many = Scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/many_lights.gltf"
    )))
    .unwrap();
    twins_agree("many lights", &many, true);
    twins_agree("Cornell box", &Scene::builtin_cornell_box().unwrap(), false);
}
