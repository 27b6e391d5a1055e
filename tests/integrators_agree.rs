//! Every integrator estimates the same image: on the workshop's Cornell box, the block means
//! of the cosine, NEE and MIS integrators agree with the workshop's uniform-sampling render
//! within statistical bounds. NEE with area light sampling (`LightSampling::Area`) is left out
//! on purpose: next to the light's edge (the tops of the walls) that estimator is unbiased but
//! heavy-tailed (1/d^2), so a few hundred samples read low and their sample variance
//! understates the truth (measured with the CPU twin at a wall point 9 mm below the ceiling:
//! 1.7% low after 4e5 samples, 0.3% after 2e7). Solid-angle sampling, the default, has no
//! such tail. Area-sampled NEE is checked against the furnace's closed form (tests/furnace.rs).

use crate::common;

use vkpath::render::settings::DEFAULT_MAX_PATH_LENGTH;
use vkpath::stats::ztest::{z_test_images, MeanImage};
use vkpath::{Integrator, RenderSettings, RenderedImage, Renderer, Scene};

fn render(integrator: Integrator, seed: u32) -> RenderedImage {
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let settings = RenderSettings {
        width: 32,
        height: 32,
        spp: 256,
        samples_per_frame: 16,
        integrator,
        seed,
        ..Default::default()
    };
    let mut renderer = Renderer::new(&context, &scene, &scene.camera.unwrap(), settings).unwrap();
    let image = renderer.render_all().unwrap();
    drop(renderer);
    common::assert_validation_silent(&context);
    image
}

fn block_means(image: &RenderedImage) -> MeanImage {
    let variance: Vec<[f64; 3]> = image
        .variance_of_mean()
        .iter()
        .map(|v| v.map(f64::from))
        .collect();
    let pixels = MeanImage::from_rgb(
        image.width as usize,
        image.height as usize,
        &image.mean,
        &variance,
    )
    .unwrap();
    // 8x8 blocks: per-pixel variances from 256 samples of a heavy-tailed estimator are
    // themselves noisy; a block mean of 64 pixels is close to normal with a reliable variance.
    pixels.block_average(8).unwrap()
}

#[test]
fn importance_sampled_integrators_match_the_workshop_render() {
    let workshop = block_means(&render(Integrator::PathTracing, 1));
    for integrator in [Integrator::Cosine, Integrator::Nee, Integrator::Mis] {
        let other = block_means(&render(integrator, 2));
        // 1% significance, Šidák-corrected over all blocks and channels inside z_test_images.
        let report = z_test_images(&other, &workshop, 0.01).unwrap();
        println!("{integrator:?} vs workshop: {report:?}");
        assert!(
            report.passed,
            "{integrator:?} disagrees with the workshop render: {report:?}"
        );
    }
}

#[test]
fn a_biased_render_is_detected() {
    // The same comparison must reject a render with a shorter maximum path length: it misses
    // the fifth bounce's light, a bias of a few percent.
    let workshop = block_means(&render(Integrator::PathTracing, 1));
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let settings = RenderSettings {
        width: 32,
        height: 32,
        spp: 256,
        samples_per_frame: 16,
        integrator: Integrator::Mis,
        max_path_length: 3,
        seed: 3,
        ..Default::default()
    };
    let mut renderer = Renderer::new(&context, &scene, &scene.camera.unwrap(), settings).unwrap();
    let biased = block_means(&renderer.render_all().unwrap());
    let report = z_test_images(&biased, &workshop, 0.01).unwrap();
    println!("path length 3 vs {DEFAULT_MAX_PATH_LENGTH} (the default): {report:?}");
    assert!(
        !report.passed,
        "a path-length-3 render passed as unbiased: {report:?}"
    );
}
