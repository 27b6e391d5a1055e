//! The share of converged pixels that the progress bar shows under `--noise-threshold`:
//! the kernel's count (`BINDING_CONVERGED_PIXELS`) equals, after every batch, the pixels that
//! the kernel's twins judge converged in the state read back, untiled and in tiles, and a
//! resumed render starts from the count of the state it resumes.

use crate::common;

use vkpath::render::adaptive::NoiseThreshold;
use vkpath::render::converged_pixels::converged_pixel_count;
use vkpath::render::renderer::Renderer;
use vkpath::render::settings::RenderSettings;
use vkpath::scene::Scene;

use std::sync::atomic::Ordering;

/// 0.2 at 8 samples: on the box at 24×24 some pixels (the dark walls' flat parts, the
/// light) converge within the first checks and others (edges, the shadowed corners) never
/// do within 128 spp, so the count passes through values strictly between 0 and all.
fn noise() -> NoiseThreshold {
    NoiseThreshold {
        threshold: 0.2,
        min_spp: 8,
    }
}

fn settings(tile_size: Option<u32>) -> RenderSettings {
    RenderSettings {
        width: 24,
        height: 24,
        spp: 128,
        samples_per_frame: 4,
        noise_threshold: Some(noise()),
        tile_size,
        ..RenderSettings::default()
    }
}

#[test]
fn the_kernels_count_is_the_converged_pixels_of_the_state_after_every_batch() {
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let camera = scene.camera.unwrap();
    let pixels = 24 * 24;
    for tile_size in [None, Some(10)] {
        let mut renderer = Renderer::new(&context, &scene, &camera, settings(tile_size)).unwrap();
        let count = renderer.converged_pixels();
        let mut seen = Vec::new();
        let mut halfway = None;
        while !renderer.is_complete() {
            renderer.render_batch().unwrap();
            let state = renderer.accumulation().unwrap();
            let counted = count.load(Ordering::SeqCst);
            assert_eq!(
                counted,
                converged_pixel_count(&state, &noise()),
                "{tile_size:?} at {} spp",
                renderer.samples_done()
            );
            if halfway.is_none() && counted > 0 {
                halfway = Some(state);
            }
            seen.push(counted);
        }
        assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
        assert!(
            seen.iter().any(|&c| c > 0 && c < pixels),
            "{tile_size:?}: {seen:?}"
        );
        // A render resumed from a state with converged pixels starts from their count.
        let state = halfway.expect("some pixels converged");
        let mut resumed = Renderer::new(&context, &scene, &camera, settings(tile_size)).unwrap();
        resumed.resume(&state).unwrap();
        assert_eq!(
            resumed.converged_pixels().load(Ordering::SeqCst),
            converged_pixel_count(&state, &noise())
        );
    }
    common::assert_validation_silent(&context);
}
