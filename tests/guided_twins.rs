//! Path guiding in the path loop (`glsl/path_guiding.glsl`) against its Rust twins
//! (`vkpath::cpu::path_guiding` in `vkpath::cpu::path_loop`) on the Cornell box with `mis`:
//! the GPU trains a guide (`Renderer::train_guide`) and the CPU trains one from the same
//! training samples (`train_cpu_guide`: the same seeds, recording, fixed-point splats and
//! host build), and the two guides agree; then the GPU's guided render and the CPU's, with
//! the GPU's guide, agree pixel by pixel. Both trace the same paths from the same random
//! numbers, so only float rounding separates them (see `tests/image_parity.rs` for why a
//! path can diverge, and how rarely). The test asserts that the validation layer stayed
//! silent.

use crate::common;

use vkpath::cpu::guiding::GuideTexels;
use vkpath::cpu::{
    add_cpu_guided_samples, train_cpu_guide, CpuGuiding, CpuImage, CpuRenderSettings,
};
use vkpath::guiding::training::GuideTraining;
use vkpath::guiding::GuideGrid;
use vkpath::{Integrator, PixelFilter, RenderSettings, Renderer, Scene};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;
const SPP: u32 = 8;
/// Iterations of 1, 2 and 4 spp: the last two sample with a guide. The GPU and the CPU train
/// the same guide only while no training path diverges: with 16 spp (49 152 training paths)
/// a few did, their cells' guides then differed by up to 4e-2 and sampled differently in
/// the next iteration, and 58 of 1447 cells ended more than 1e-4 apart. With 7 spp
/// (21 504 paths) none diverged on lavapipe.
const TRAINING_SPP: u32 = 7;
const SEED: u32 = 7;
const MAX_PATH_LENGTH: u32 = 5;

/// Two cells' cumulative probabilities agree when they differ by at most this. For the same
/// paths the splats differ only by the rounding of throughputs and densities (1e-6
/// relative), and each iteration samples with the guide of the one before, which carries
/// those differences into slightly different guided directions. Measured on lavapipe: at
/// most 4.0e-5 over 947 guided cells (median 6.6e-7); 2e-4 leaves a margin of 5, while a
/// diverged path moves its cells by 1e-3 and more.
const CUMULATIVE_TOLERANCE: f32 = 2e-4;

/// The guided render's pixels agree when they differ by at most this, relative: the light
/// samples' tolerance of `tests/image_parity.rs` (Arvo's sampler amplifies the GPU's few-ulp
/// sines and cosines), which a guided direction, one lookup and a sine and cosine more, keeps.
const RELATIVE_TOLERANCE: f32 = 1e-3;
/// Pixels that may diverge. Measured on lavapipe: 1 of 3072 (2 with a 16 spp guide), as
/// `tests/image_parity.rs` finds for unguided mis (it allows nee and mis 6 without a
/// near-tie on the workshop's replay). A guided sample also crosses bin edges, where the
/// GPU's arctangent may put it in the neighbouring bin (tests/guiding.rs: 0 of 50 000 did),
/// so allow 0.5 % (15 pixels). A wrong formula on either side makes most pixels diverge.
const MAX_DIVERGENT_PIXELS: usize = 15;

fn settings() -> RenderSettings {
    RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        spp: SPP,
        max_path_length: MAX_PATH_LENGTH,
        seed: SEED,
        pixel_filter: PixelFilter::Box,
        integrator: Integrator::Mis,
        samples_per_frame: 4,
        guiding: Some(GuideTraining {
            samples: TRAINING_SPP,
        }),
        ..Default::default()
    }
}

fn cpu_settings(settings: &RenderSettings) -> CpuRenderSettings {
    // The box's two lights: `LightSelection::Auto` picks the power CDF.
    common::twins::cpu_settings(settings, vkpath::contract::LIGHT_SELECTION_POWER)
}

/// The largest difference of a cumulative probability over all cells and bins, and the
/// cells guided by one guide but not the other.
fn guide_difference(gpu: GuideTexels, cpu: GuideTexels, cell_count: u32) -> (f32, Vec<u32>) {
    use vkpath::cpu::guiding::{get_guide_cumulative, is_guided_cell};
    let mut worst = 0.0f32;
    let mut disagreeing = Vec::new();
    for cell in 0..cell_count {
        if is_guided_cell(gpu, cell) != is_guided_cell(cpu, cell) {
            disagreeing.push(cell);
            continue;
        }
        for bin in 0..vkpath::contract::GUIDE_BIN_COUNT {
            let difference =
                (get_guide_cumulative(gpu, cell, bin) - get_guide_cumulative(cpu, cell, bin)).abs();
            worst = worst.max(difference);
        }
    }
    (worst, disagreeing)
}

#[test]
fn gpu_and_cpu_train_the_same_guide_and_render_the_same_guided_image() {
    let scene = Scene::builtin_cornell_box().unwrap();
    let camera = scene.camera.unwrap();
    let settings = settings();
    let context = common::validated_context();
    let mut renderer = Renderer::new(&context, &scene, &camera, settings.clone()).unwrap();
    let gpu_image = renderer.render_all().unwrap();
    let gpu_guide = renderer
        .guide()
        .expect("a guided render has a guide")
        .clone();
    drop(renderer);
    common::assert_validation_silent(&context);

    // The guide.
    let grid = GuideGrid::around_triangles(scene.triangles.iter().map(|t| t.positions));
    assert_eq!(gpu_guide.grid(), &grid);
    let plane = camera.image_plane(settings.aspect());
    let cpu_settings = cpu_settings(&settings);
    let cpu_guide = train_cpu_guide(
        &scene.triangles,
        &plane,
        &cpu_settings,
        grid.clone(),
        settings.guiding.unwrap(),
    )
    .unwrap();
    let guided = gpu_guide.guided_cell_count();
    println!(
        "guide: {} cells, {guided} guided on the GPU, {} on the CPU",
        grid.cell_count(),
        cpu_guide.guided_cell_count()
    );
    // The box's walls, floor and blocks span many cells: a guide that learned only a few
    // would test little.
    assert!(guided >= 100, "only {guided} cells learned");
    let (worst, disagreeing) =
        guide_difference(gpu_guide.texels(), cpu_guide.texels(), grid.cell_count());
    println!("guide: cumulative probabilities differ by at most {worst:.2e}");
    assert!(
        disagreeing.is_empty(),
        "cells guided by one guide only: {disagreeing:?}"
    );
    assert!(
        worst <= CUMULATIVE_TOLERANCE,
        "the guides' cumulative probabilities differ by {worst:.2e}"
    );

    // The guided render, both with the GPU's guide.
    let mut cpu_image = CpuImage::new(WIDTH, HEIGHT);
    add_cpu_guided_samples(
        &scene.triangles,
        &plane,
        &cpu_settings,
        CpuGuiding {
            guide: Some(gpu_guide.texels()),
            splats: None,
        },
        0..SPP,
        &mut cpu_image,
    );
    let agreement = common::twins::compare_twin_images(&gpu_image, &cpu_image, RELATIVE_TOLERANCE);
    let divergent = &agreement.divergent;
    println!(
        "image: {} of {} pixels diverge; agreeing pixels differ by at most {:.2e} relative",
        divergent.len(),
        gpu_image.mean.len(),
        agreement.worst_agreeing
    );
    assert!(
        divergent.len() <= MAX_DIVERGENT_PIXELS,
        "{} pixels diverge (x, y, GPU, CPU): {:?}",
        divergent.len(),
        &divergent[..divergent.len().min(5)]
    );
    // Block means, so that the divergent paths cannot hide a bias.
    assert!(agreement.blocks_agree, "block means differ: {agreement:?}");
    let cpu_mean = cpu_image.mean();

    // Guiding changed the paths: the CPU's unguided image differs in most pixels, so the
    // agreement above is the guided loop's and not the plain one's.
    let mut plain = CpuImage::new(WIDTH, HEIGHT);
    add_cpu_guided_samples(
        &scene.triangles,
        &plane,
        &cpu_settings,
        CpuGuiding::default(),
        0..SPP,
        &mut plain,
    );
    let same = plain
        .mean()
        .iter()
        .zip(&cpu_mean)
        .filter(|(a, b)| a == b)
        .count();
    assert!(
        same < cpu_mean.len() / 2,
        "{same} of {} pixels are the same guided and unguided",
        cpu_mean.len()
    );
}
