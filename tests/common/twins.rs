//! GPU images against the CPU twins' images of the same paths: pixel by pixel to float
//! rounding, with a bound on the pixels whose paths diverged, and by 8x8 block means, so
//! that divergent paths cannot hide a bias (`tests/guided_twins.rs`,
//! `tests/light_tree_twins.rs`; `tests/image_parity.rs` adds a near-tie replay of its own).

use vkpath::cpu::{CpuImage, CpuRenderSettings};
use vkpath::stats::ztest::{z_test_images, MeanImage};
use vkpath::{RenderSettings, RenderedImage};

/// Absolute floor of the tolerance for near-zero means (radiance is O(1) or more).
const ABSOLUTE_TOLERANCE: f32 = 1e-6;

/// How a GPU image and a CPU image of the same paths agree.
#[derive(Debug)]
pub struct TwinAgreement {
    /// (x, y, GPU mean, CPU mean) of the pixels that differ by more than the tolerance.
    pub divergent: Vec<(u32, u32, [f32; 4], [f32; 4])>,
    /// The largest relative difference among the other pixels.
    pub worst_agreeing: f32,
    /// Whether the 8x8 block means pass a z-test at family-wise level 0.01.
    pub blocks_agree: bool,
}

/// Compares `gpu` with `cpu` (the same size), a pixel agreeing when its channels differ by
/// at most `relative_tolerance` of the larger value.
pub fn compare_twin_images(
    gpu: &RenderedImage,
    cpu: &CpuImage,
    relative_tolerance: f32,
) -> TwinAgreement {
    let cpu_mean = cpu.mean();
    let mut divergent = Vec::new();
    let mut worst_agreeing = 0.0f32;
    for (index, (g, c)) in gpu.mean.iter().zip(&cpu_mean).enumerate() {
        let relative = (0..3)
            .map(|i| {
                (g[i] - c[i]).abs()
                    / g[i]
                        .abs()
                        .max(c[i].abs())
                        .max(ABSOLUTE_TOLERANCE / relative_tolerance)
            })
            .fold(0.0f32, f32::max);
        if relative <= relative_tolerance {
            worst_agreeing = worst_agreeing.max(relative);
        } else {
            let width = gpu.width;
            divergent.push((index as u32 % width, index as u32 / width, *g, *c));
        }
    }
    let gpu_variance: Vec<[f64; 3]> = gpu
        .variance_of_mean()
        .iter()
        .map(|v| v.map(f64::from))
        .collect();
    let (width, height) = (gpu.width as usize, gpu.height as usize);
    let blocks = |mean: &[[f32; 4]], variance: &[[f64; 3]]| {
        MeanImage::from_rgb(width, height, mean, variance)
            .and_then(|image| image.block_average(8))
            .unwrap()
    };
    let report = z_test_images(
        &blocks(&gpu.mean, &gpu_variance),
        &blocks(&cpu_mean, &cpu.variance_of_mean()),
        0.01,
    )
    .unwrap();
    TwinAgreement {
        divergent,
        worst_agreeing,
        blocks_agree: report.passed,
    }
}

/// The CPU renderer's settings for the GPU's `settings`, with `light_selection`
/// (`LIGHT_SELECTION_*`: the GPU's choice, which depends on the scene's light count).
pub fn cpu_settings(settings: &RenderSettings, light_selection: u32) -> CpuRenderSettings {
    CpuRenderSettings {
        width: settings.width,
        height: settings.height,
        spp: settings.spp,
        max_path_length: settings.max_path_length,
        seed: settings.seed,
        pixel_filter: settings.pixel_filter.spec_constant(),
        integrator: settings.integrator.spec_constant(),
        russian_roulette_start: settings.russian_roulette_start,
        sampler: settings.sampler.spec_constant(),
        light_sampling: settings.light_sampling.spec_constant(),
        light_selection,
    }
}
