//! The furnace test on the GPU: a camera inside a closed box whose walls all have albedo a
//! and emission Le sees Le (1 - a^n) / (1 - a) in every pixel for maximum path length n,
//! with every integrator, both traversals, both samplers, both light samplings, and with
//! path guiding (nee and mis, `--guiding`).

use crate::common;

use vkpath::guiding::training::GuideTraining;
use vkpath::scene::procedural::{furnace, furnace_radiance};
use vkpath::{Accel, Integrator, LightSampling, RenderSettings, Renderer, SamplerKind};

fn check_furnace(albedo: f32, emission: f32, max_path_length: u32) {
    for accel in [Accel::None, Accel::Bvh] {
        for integrator in [
            Integrator::PathTracing,
            Integrator::Cosine,
            Integrator::Nee,
            Integrator::Mis,
        ] {
            check_furnace_with(
                integrator,
                accel,
                SamplerKind::Pcg,
                LightSampling::SolidAngle,
                albedo,
                emission,
                max_path_length,
                None,
            );
        }
    }
    // Scrambled Sobol samples must stay unbiased too; one integrator that draws every kind of
    // random number (jitter, light samples, directions, roulette) keeps the runtime small.
    check_furnace_with(
        Integrator::Mis,
        Accel::None,
        SamplerKind::Sobol,
        LightSampling::SolidAngle,
        albedo,
        emission,
        max_path_length,
        None,
    );
    // The light sampling, uniform on the light's area, for both light-sampling
    // integrators.
    for integrator in [Integrator::Nee, Integrator::Mis] {
        check_furnace_with(
            integrator,
            Accel::None,
            SamplerKind::Pcg,
            LightSampling::Area,
            albedo,
            emission,
            max_path_length,
            None,
        );
    }
    // Path guiding: a guide trained on 16 spp (its cells taught, its mixture with the BSDF
    // in every direction sample and MIS weight) keeps both light-sampling integrators
    // unbiased.
    for integrator in [Integrator::Nee, Integrator::Mis] {
        check_furnace_with(
            integrator,
            Accel::None,
            SamplerKind::Pcg,
            LightSampling::SolidAngle,
            albedo,
            emission,
            max_path_length,
            Some(GuideTraining { samples: 16 }),
        );
    }
}

// One furnace, each of its settings a parameter: a struct would only name them again.
#[allow(clippy::too_many_arguments)]
fn check_furnace_with(
    integrator: Integrator,
    accel: Accel,
    sampler: SamplerKind,
    light_sampling: LightSampling,
    albedo: f32,
    emission: f32,
    max_path_length: u32,
    guiding: Option<GuideTraining>,
) {
    let context = common::validated_context();
    let scene = furnace(albedo, emission);
    let settings = RenderSettings {
        width: 32,
        height: 32,
        spp: 32,
        max_path_length,
        samples_per_frame: 8,
        integrator,
        accel,
        sampler,
        light_sampling,
        // Russian roulette on from the second vertex, so the tests see it at work.
        russian_roulette_start: 2,
        guiding,
        ..Default::default()
    };
    let mut renderer =
        Renderer::new(&context, &scene, &scene.camera.unwrap(), settings.clone()).unwrap();
    let image = renderer.render_all().unwrap();
    if guiding.is_some() {
        let guide = renderer
            .guide_report()
            .expect("a guided render trains its guide");
        assert!(
            guide.guided_cell_count > 0,
            "training taught no cell: {guide:?}"
        );
    }
    let expected = furnace_radiance(f64::from(albedo), f64::from(emission), max_path_length);
    // Every sample is independent (distinct per-pixel, per-sample seeds), so the image mean
    // is a mean of N = W*H*spp samples with standard error sqrt(var / N), where var is the
    // per-sample variance pooled over pixels from the stored second moments. Sobol samples
    // of one pixel are negatively correlated (stratified), which only lowers the true error
    // below this estimate, so the tolerance stays conservative; pixels are independent.
    let samples = f64::from(settings.width * settings.height * settings.spp);
    for channel in 0..3 {
        let mean = image.average()[channel];
        let variance = image
            .mean
            .iter()
            .zip(&image.second_moment)
            .map(|(m, m2)| f64::from(m2[channel]) - f64::from(m[channel]).powi(2))
            .sum::<f64>()
            / image.mean.len() as f64;
        let standard_error = (variance / samples).sqrt();
        // 5 standard errors: a false failure has probability ~6e-7 for a normal mean, while
        // a bias of a few percent (e.g. a lost or extra bounce) is many standard errors.
        let tolerance = 5.0 * standard_error;
        println!("{integrator:?} {accel:?} {sampler:?} {light_sampling:?} guiding {guiding:?} a={albedo} n={max_path_length}: mean {mean:.5}, expected {expected:.5}, SE {standard_error:.2e}");
        assert!(
            variance > 0.0,
            "the estimator should be noisy, got zero variance"
        );
        assert!(
            (mean - expected).abs() <= tolerance,
            "furnace {integrator:?} {accel:?} {sampler:?} {light_sampling:?} a={albedo} n={max_path_length} channel {channel}: mean {mean} vs {expected} (tolerance {tolerance})"
        );
    }
    drop(renderer);
    common::assert_validation_silent(&context);
}

#[test]
fn furnace_half_albedo_three_bounces() {
    check_furnace(0.5, 1.0, 3);
}

#[test]
fn furnace_high_albedo_six_bounces() {
    check_furnace(0.8, 0.5, 6);
}
