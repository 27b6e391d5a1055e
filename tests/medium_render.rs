//! The global medium (`RenderSettings::medium`, `render --medium`) rendered on lavapipe
//! against closed forms and between integrators, with `SamplerKind::Pcg` (independent
//! samples, so that per-pixel moments give honest standard errors):
//! - Beer-Lambert: a pure chromatic absorber between the camera and a wall that emits 1
//!   transmits exp(-sigma_a d) per channel (cosine, nee, mis);
//! - a furnace: a closed box whose walls emit 1 and reflect nothing, filled with a chromatic
//!   medium of albedo 1 per channel and g = 0.6, shows 1 in every pixel (cosine, nee, mis),
//!   which holds only if the distance sampler's weights, the phase function's sampling, the
//!   light samples at medium vertices with their transmittance and MIS all agree;
//! - nee, mis and cosine agree with each other on the Cornell box in fog (block z-tests).

use crate::common;

use glam::Vec3;
use vkpath::medium::Medium;
use vkpath::scene::procedural::furnace;
use vkpath::stats::ztest::{z_test_images, MeanImage};
use vkpath::{Camera, Integrator, RenderSettings, RenderedImage, SamplerKind, Scene};

/// The integrators that render media.
const INTEGRATORS: [Integrator; 3] = [Integrator::Cosine, Integrator::Nee, Integrator::Mis];

/// Small settings for the statistics: `integrator` with PCG samples and `medium`.
fn settings(integrator: Integrator, medium: Medium, spp: u32) -> RenderSettings {
    RenderSettings {
        width: 16,
        height: 16,
        spp,
        samples_per_frame: 16,
        integrator,
        sampler: SamplerKind::Pcg,
        // Paths of up to 64 vertices: in the furnace a path ends at a wall after a few
        // scattering events (the chance of more than 64 is below 1e-4 in its densest
        // channel), so the truncation's bias is far below the tolerance
        max_path_length: 64,
        russian_roulette_start: 2,
        medium: Some(medium),
        ..Default::default()
    }
}

/// The furnace box ([-1, 1]^3, walls of albedo 0 emitting 1) seen from `position` along +x
/// through a narrow field of view (0.01 rad: every ray meets the wall x = 1 within 1.3e-5 of
/// the axis's distance).
fn emitting_box(position: Vec3) -> Scene {
    Scene {
        camera: Some(Camera::look_at(position, position + Vec3::X, Vec3::Z, 0.01)),
        ..furnace(0.0, 1.0)
    }
}

#[test]
fn a_pure_absorber_transmits_beer_lambert() {
    let absorption = Vec3::new(0.2, 0.7, 1.5);
    let medium = Medium {
        absorption,
        scattering: Vec3::ZERO,
        anisotropy: 0.0,
    };
    // The wall lies 1.5 away
    let scene = emitting_box(Vec3::new(-0.5, 0.1, -0.2));
    let expected = (-absorption * 1.5).exp();
    for integrator in INTEGRATORS {
        let spp = 64;
        let image = common::render_scene(&scene, settings(integrator, medium, spp));
        common::assert_mean(
            &image,
            spp,
            expected,
            &format!("Beer-Lambert {integrator:?}"),
        );
    }
}

#[test]
fn a_scattering_furnace_shows_one_everywhere() {
    // Albedo 1 in every channel, a different extinction in each (chromatic weights at work)
    let medium = Medium {
        absorption: Vec3::ZERO,
        scattering: Vec3::new(0.5, 1.0, 2.0),
        anisotropy: 0.6,
    };
    let scene = Scene {
        camera: Some(Camera::look_at(
            Vec3::new(0.1, -0.2, 0.05),
            Vec3::new(1.0, 0.3, 0.2),
            Vec3::Z,
            1.2,
        )),
        ..furnace(0.0, 1.0)
    };
    for integrator in INTEGRATORS {
        let spp = 32;
        let image = common::render_scene(&scene, settings(integrator, medium, spp));
        common::assert_mean(
            &image,
            spp,
            Vec3::ONE,
            &format!("medium furnace {integrator:?}"),
        );
    }
}

/// Block means (4x4 blocks of the 16x16 image) with their variances, for z_test_images.
fn block_means(image: &RenderedImage) -> MeanImage {
    let variance: Vec<[f64; 3]> = image
        .variance_of_mean()
        .iter()
        .map(|v| v.map(f64::from))
        .collect();
    MeanImage::from_rgb(
        image.width as usize,
        image.height as usize,
        &image.mean,
        &variance,
    )
    .unwrap()
    .block_average(4)
    .unwrap()
}

#[test]
fn nee_mis_and_cosine_agree_in_fog() {
    let scene = Scene::builtin_cornell_box().unwrap();
    // The box is 0.56 across: an optical depth of about 0.9, a quarter of it absorbed
    let medium = Medium {
        absorption: Vec3::new(0.2, 0.4, 0.6),
        scattering: Vec3::new(1.4, 1.2, 1.0),
        anisotropy: 0.5,
    };
    let render = |integrator, seed| {
        let settings = RenderSettings {
            max_path_length: 8,
            seed,
            ..settings(integrator, medium, 256)
        };
        block_means(&common::render_scene(&scene, settings))
    };
    let mis = render(Integrator::Mis, 1);
    for (integrator, seed) in [(Integrator::Nee, 2), (Integrator::Cosine, 3)] {
        // 1% significance, Šidák-corrected over all blocks and channels inside z_test_images
        let report = z_test_images(&render(integrator, seed), &mis, 0.01).unwrap();
        println!("{integrator:?} vs mis in fog: {report:?}");
        assert!(
            report.passed,
            "{integrator:?} disagrees with mis in fog: {report:?}"
        );
    }
}
