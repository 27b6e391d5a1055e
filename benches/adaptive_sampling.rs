//! What `--noise-threshold` saves: samples at equal error. For a scene (the built-in box,
//! or a file given as the first argument), renders a high-spp reference (another seed),
//! uniform renders at 8..=512 spp and adaptive ones at several thresholds (cap 512,
//! minimum 16), and prints each adaptive render's mean spp beside the spp a uniform render
//! needs for the same error (interpolated log-log between the uniform renders around it),
//! for two errors: the image's relMSE (the mean over pixels, as `vkpath bench`) and the 99th
//! percentile of the pixels' own relMSE (the noisiest 1%, what a threshold bounds).
//! Counts samples, not seconds: a pixel that stopped still costs its SIMD lanes' idle time.
//!
//! `cargo bench --profile dev --bench adaptive_sampling -- [SCENE] [--size 48] [--reference-spp 8192] [--pcg]`
//!
//! Run without `--bench` (as `cargo test --all-targets` runs every bench target), it is a
//! smoke test at 8 x 8 pixels, a 64-spp reference, two uniform renders and one threshold,
//! so the suite checks it still runs without paying for the table.

use std::path::Path;

use vkpath::bench::relative_mse;
use vkpath::render::adaptive::NoiseThreshold;
use vkpath::render::job::production_settings;
use vkpath::vk::{Context, ContextOptions};
use vkpath::{RenderSettings, RenderedImage, Renderer, Scene};

/// Uniform spp of the error curve.
const UNIFORM_SPP: [u32; 7] = [8, 16, 32, 64, 128, 256, 512];
/// Thresholds tried.
const THRESHOLDS: [f32; 4] = [0.2, 0.1, 0.05, 0.03];
/// The adaptive renders' cap and minimum.
const CAP: u32 = 512;
const MIN_SPP: u32 = 16;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let benchmarking = std::env::args().any(|a| a == "--bench");
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let value_of = |name: &str, default: u32| -> u32 {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let (size, reference_spp) = match benchmarking {
        true => (value_of("--size", 48), value_of("--reference-spp", 8192)),
        false => (8, 64),
    };
    let (uniform_spp, thresholds) = match benchmarking {
        true => (&UNIFORM_SPP[..], &THRESHOLDS[..]),
        false => (&UNIFORM_SPP[..2], &THRESHOLDS[..1]),
    };
    let scene_path = args
        .iter()
        .enumerate()
        .find(|(i, a)| !a.starts_with("--") && (*i == 0 || !args[i - 1].starts_with("--")))
        .map(|(_, a)| a.clone());
    let scene = match &scene_path {
        Some(path) => Scene::load(Path::new(path))?,
        None => Scene::builtin_cornell_box()?,
    };
    let camera = scene.camera.ok_or("the scene has no camera")?;
    let context = Context::new(&ContextOptions::default())?;
    // --pcg: independent random numbers instead of Sobol points.
    let sampler = if args.iter().any(|a| a == "--pcg") {
        vkpath::SamplerKind::Pcg
    } else {
        production_settings().sampler
    };
    let base = RenderSettings {
        width: size,
        height: size,
        sampler,
        ..production_settings()
    };
    let render = |settings: RenderSettings| -> Result<RenderedImage, vkpath::Error> {
        Renderer::new(&context, &scene, &camera, settings)?.render_all()
    };
    println!(
        "scene {}, {size}x{size}, {} ({}), reference {reference_spp} spp (seed 7)",
        scene_path.as_deref().unwrap_or("builtin:cornell-box"),
        base.integrator.name(),
        vkpath::render::metadata::sampler_name(base.sampler),
    );
    let reference = render(RenderSettings {
        spp: reference_spp,
        seed: 7,
        ..base.clone()
    })?;
    let (mut curve, mut tail_curve) = (Vec::new(), Vec::new());
    for &spp in uniform_spp {
        let image = render(RenderSettings {
            spp,
            ..base.clone()
        })?;
        let error = relative_mse(&image, &reference);
        let tail = tail_relative_mse(&image, &reference);
        println!("uniform   {spp:>5} spp: relMSE {error:.4e}, p99 pixel relMSE {tail:.4e}");
        curve.push((f64::from(spp), error));
        tail_curve.push((f64::from(spp), tail));
    }
    println!("threshold  mean spp  relMSE      uniform spp at it (saved)  p99 pixel relMSE  uniform spp at it (saved)");
    for &threshold in thresholds {
        let image = render(RenderSettings {
            spp: CAP,
            noise_threshold: Some(NoiseThreshold {
                threshold,
                min_spp: MIN_SPP,
            }),
            ..base.clone()
        })?;
        let error = relative_mse(&image, &reference);
        let mean_spp = image
            .sample_count
            .iter()
            .map(|&n| f64::from(n))
            .sum::<f64>()
            / image.sample_count.len() as f64;
        let tail = tail_relative_mse(&image, &reference);
        let at = |curve: &[(f64, f64)], error: f64| match equal_error_spp(curve, error) {
            Some(uniform) => format!(
                "{uniform:>7.1} ({:>5.1}%)",
                100.0 * (1.0 - mean_spp / uniform)
            ),
            None => "outside the uniform curve".to_string(),
        };
        println!(
            "{threshold:<9}  {mean_spp:>8.1}  {error:.4e}  {:>25}  {tail:.4e}        {:>25}",
            at(&curve, error),
            at(&tail_curve, tail)
        );
    }
    Ok(())
}

/// The 99th percentile over pixels of each pixel's relMSE (its mean over RGB of
/// (x - r)^2 / (r^2 + 0.01), the terms of `relative_mse`).
fn tail_relative_mse(image: &RenderedImage, reference: &RenderedImage) -> f64 {
    let mut errors: Vec<f64> = image
        .mean
        .iter()
        .zip(&reference.mean)
        .map(|(x, r)| {
            (0..3)
                .map(|c| {
                    let (x, r) = (f64::from(x[c]), f64::from(r[c]));
                    (x - r).powi(2) / (r * r + 0.01)
                })
                .sum::<f64>()
                / 3.0
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    errors[(errors.len() * 99 / 100).min(errors.len() - 1)]
}

/// The spp at which the uniform renders' relMSE (`curve`: (spp, relMSE), spp rising) is
/// `error`, interpolated log-log between the two renders around it; `None` outside.
fn equal_error_spp(curve: &[(f64, f64)], error: f64) -> Option<f64> {
    curve.windows(2).find_map(|pair| {
        let ((n0, e0), (n1, e1)) = (pair[0], pair[1]);
        if !(e1 <= error && error <= e0) || e0 == e1 {
            return None;
        }
        let t = (error.ln() - e0.ln()) / (e1.ln() - e0.ln());
        Some((n0.ln() + t * (n1.ln() - n0.ln())).exp())
    })
}
