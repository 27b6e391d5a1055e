//! Light beyond emissive triangles, rendered on the GPU against closed forms: a convex
//! diffuse object under a constant background, point, spot and directional lights over a
//! diffuse plane, and an environment map that every integrator sees alike.

use crate::common;

use glam::{Mat4, Vec3};
use vkpath::camera::Camera;
use vkpath::lights::{Environment, EnvironmentMap};
use vkpath::lights::{PunctualKind, PunctualLight};
use vkpath::scene::procedural::inward_cube;
use vkpath::scene::Triangle;
use vkpath::stats::ztest::{z_test_images, MeanImage};
use vkpath::{
    Integrator, PixelFilter, RenderSettings, RenderedImage, Renderer, SamplerKind, Scene,
};

fn render(scene: &Scene, settings: RenderSettings) -> RenderedImage {
    let context = common::validated_context();
    let mut renderer = Renderer::new(&context, scene, &scene.camera.unwrap(), settings).unwrap();
    let image = renderer.render_all().unwrap();
    drop(renderer);
    common::assert_validation_silent(&context);
    image
}

/// A unit cube of albedo `albedo` facing outwards (the inward cube turned inside out).
fn outward_cube(albedo: Vec3) -> Vec<Triangle> {
    inward_cube(albedo, Vec3::ZERO)
        .into_iter()
        .map(|t| {
            Triangle::new(
                [t.positions[0], t.positions[2], t.positions[1]],
                albedo,
                Vec3::ZERO,
                false,
            )
            .unwrap()
        })
        .collect()
}

fn scene(triangles: Vec<Triangle>, camera: Camera) -> Scene {
    Scene {
        triangles,
        camera: Some(camera),
        cameras: vec![camera],
        ..Default::default()
    }
}

#[test]
fn a_convex_diffuse_object_under_a_constant_sky_reflects_albedo_times_sky() {
    // Every point of a convex object sees only the sky over its whole hemisphere, so its
    // radiance is a L at any path length >= 2, and the sky itself reads L.
    let albedo = Vec3::new(0.5, 0.7, 0.3);
    let sky = Vec3::new(1.0, 0.5, 0.25);
    let camera = Camera::look_at(Vec3::new(1.5, 2.5, 2.0), Vec3::ZERO, Vec3::Z, 0.9);
    let mut cube = scene(outward_cube(albedo), camera);
    cube.environment = Some(Environment::constant(sky));
    for (integrator, spp) in [
        (Integrator::PathTracing, 256),
        (Integrator::Cosine, 256),
        (Integrator::Nee, 64),
        (Integrator::Mis, 64),
    ] {
        let image = render(
            &cube,
            RenderSettings {
                width: 24,
                height: 24,
                spp,
                max_path_length: 3,
                pixel_filter: PixelFilter::Center,
                integrator,
                ..Default::default()
            },
        );
        let variance = image.variance_of_mean();
        let (mut worst_z, mut object_pixels) = (0.0f64, 0);
        for (mean, variance) in image.mean.iter().zip(&variance) {
            let value = Vec3::new(mean[0], mean[1], mean[2]);
            // A pixel sees the sky (exactly L) or the cube (a L in expectation).
            let expected = if (value - sky).abs().max_element() < 1e-6 {
                sky
            } else {
                object_pixels += 1;
                albedo * sky
            };
            for c in 0..3 {
                let z = f64::from(value[c] - expected[c]) / f64::from(variance[c]).sqrt().max(1e-7);
                worst_z = worst_z.max(z.abs());
            }
        }
        println!("{integrator:?}: {object_pixels} cube pixels, worst |z| {worst_z:.2}");
        assert!(object_pixels > 100);
        // 576 pixels x 3 channels at 1%, Šidák: |z| < 4.3.
        assert!(worst_z < 4.3, "{integrator:?}: |z| = {worst_z}");
    }
}

/// A 40 m diffuse square at z = 0 seen from above, with one punctual light.
fn plane_with(light: PunctualLight, albedo: f32) -> Scene {
    let s = 20.0;
    let corners = [
        Vec3::new(-s, -s, 0.0),
        Vec3::new(s, -s, 0.0),
        Vec3::new(s, s, 0.0),
        Vec3::new(-s, s, 0.0),
    ];
    let triangles = vec![
        Triangle::new(
            [corners[0], corners[1], corners[2]],
            Vec3::splat(albedo),
            Vec3::ZERO,
            false,
        )
        .unwrap(),
        Triangle::new(
            [corners[0], corners[2], corners[3]],
            Vec3::splat(albedo),
            Vec3::ZERO,
            false,
        )
        .unwrap(),
    ];
    let camera = Camera::look_at(Vec3::new(0.0, -1.0, 4.0), Vec3::ZERO, Vec3::Y, 1.2);
    let mut plane = scene(triangles, camera);
    plane.punctual_lights = vec![light];
    plane
}

/// Renders `scene` with NEE at path length 2 and the centre filter (a single punctual light
/// makes each pixel deterministic) and returns the largest relative error against
/// `expected(point on the plane)`.
fn punctual_error(scene: &Scene, expected: impl Fn(Vec3) -> f32) -> f32 {
    let (width, height) = (16, 16);
    let image = render(
        scene,
        RenderSettings {
            width,
            height,
            spp: 1,
            max_path_length: 2,
            pixel_filter: PixelFilter::Center,
            integrator: Integrator::Nee,
            ..Default::default()
        },
    );
    let camera = scene.camera.unwrap();
    let plane = camera.image_plane(1.0);
    let mut worst = 0.0f32;
    for y in 0..height {
        for x in 0..width {
            let u = (x as f32 + 0.5) / width as f32;
            let v = ((height - 1 - y) as f32 + 0.5) / height as f32;
            let direction = (plane.left_bottom + u * plane.right + v * plane.up
                - plane.camera_position)
                .normalize();
            let point =
                plane.camera_position + (-plane.camera_position.z / direction.z) * direction;
            let want = expected(point);
            let got = image.mean[(y * width + x) as usize][0];
            worst = worst.max((got - want).abs() / want.max(1e-3));
        }
    }
    worst
}

#[test]
fn point_spot_and_directional_lights_match_their_closed_forms() {
    let albedo = 0.6;
    let lambert = albedo / std::f32::consts::PI;
    let above = Mat4::from_translation(Vec3::new(0.5, 0.3, 2.0));
    // Point: intensity I a/pi cos theta / d^2.
    let point = PunctualLight::new(PunctualKind::Point, Vec3::ONE, 10.0, above).unwrap();
    let error = punctual_error(&plane_with(point, albedo), |p| {
        let to_light = point.position - p;
        10.0 * lambert * to_light.normalize().z / to_light.length_squared()
    });
    println!("point light: largest relative error {error:e}");
    assert!(error < 1e-4, "{error}");
    // Spot, pointing straight down: times the extension's falloff (clamp(cos s + o)^2).
    let spot = PunctualLight::new(
        PunctualKind::Spot {
            inner_cone_angle: 0.3,
            outer_cone_angle: 0.6,
        },
        Vec3::ONE,
        10.0,
        above,
    )
    .unwrap();
    let (scale, offset) = spot.cone_scale_offset();
    let error = punctual_error(&plane_with(spot, albedo), |p| {
        let to_light = spot.position - p;
        let falloff = (spot.direction.dot(-to_light.normalize()) * scale + offset).clamp(0.0, 1.0);
        10.0 * lambert * to_light.normalize().z / to_light.length_squared() * falloff * falloff
    });
    println!("spot light: largest relative error {error:e}");
    // The falloff multiplies the rounding of the cosine (~1e-7) by its scale (1 / (cos 0.3 -
    // cos 0.6) = 7.4) and squares it, and is relative to a falloff that goes to 0 at the
    // cone's edge: 1e-3 there is still a few ulps of the cosine.
    assert!(error < 2e-3, "{error}");
    // Directional, 30 degrees from the normal: E a/pi cos theta everywhere.
    let tilt = Mat4::from_rotation_x(30f32.to_radians());
    let sun = PunctualLight::new(PunctualKind::Directional, Vec3::ONE, 3.0, tilt).unwrap();
    let cosine = (-sun.direction).z;
    let error = punctual_error(&plane_with(sun, albedo), |_| 3.0 * lambert * cosine);
    println!("directional light: largest relative error {error:e}");
    assert!(error < 1e-4, "{error}");
}

#[test]
fn every_integrator_sees_an_environment_map_alike() {
    // An 8x4 map, dim blue with one bright texel above the horizon, around a diffuse cube on
    // a floor: block means agree between all four integrators.
    let mut texels = vec![Vec3::new(0.05, 0.1, 0.2); 32];
    texels[8 + 5] = Vec3::new(20.0, 16.0, 10.0);
    let map = EnvironmentMap {
        width: 8,
        height: 4,
        texels,
    };
    let mut triangles = outward_cube(Vec3::splat(0.7));
    let s = 6.0;
    let floor = [
        Vec3::new(-s, -s, -0.5),
        Vec3::new(s, -s, -0.5),
        Vec3::new(s, s, -0.5),
        Vec3::new(-s, s, -0.5),
    ];
    triangles.push(
        Triangle::new(
            [floor[0], floor[1], floor[2]],
            Vec3::splat(0.5),
            Vec3::ZERO,
            false,
        )
        .unwrap(),
    );
    triangles.push(
        Triangle::new(
            [floor[0], floor[2], floor[3]],
            Vec3::splat(0.5),
            Vec3::ZERO,
            false,
        )
        .unwrap(),
    );
    let camera = Camera::look_at(Vec3::new(2.0, 2.5, 1.5), Vec3::ZERO, Vec3::Z, 1.0);
    let mut lit = scene(triangles, camera);
    lit.environment = Some(Environment {
        map: Some(map),
        background: Vec3::ZERO,
        strength: 1.5,
        rotation_degrees: 30.0,
    });
    let means = |integrator, seed| {
        let image = render(
            &lit,
            RenderSettings {
                width: 32,
                height: 32,
                spp: 256,
                max_path_length: 3,
                integrator,
                seed,
                ..Default::default()
            },
        );
        let variance: Vec<[f64; 3]> = image
            .variance_of_mean()
            .iter()
            .map(|v| v.map(f64::from))
            .collect();
        MeanImage::from_rgb(32, 32, &image.mean, &variance)
            .unwrap()
            .block_average(8)
            .unwrap()
    };
    let reference = means(Integrator::Mis, 1);
    for integrator in [Integrator::PathTracing, Integrator::Cosine, Integrator::Nee] {
        let report = z_test_images(&means(integrator, 2), &reference, 0.01).unwrap();
        println!("{integrator:?} vs mis: {report:?}");
        assert!(report.passed, "{integrator:?}: {report:?}");
    }
}

/// A `width` x `height` equirectangular sky of radiance (0.2, 0.3, 0.5) with a Gaussian sun
/// of standard deviation 1.5 degrees, 40 degrees above the horizon, whose peak is about a
/// thousand times the sky's luminance: a large map with a sharp peak. Black below the
/// horizon, where a plane facing up would waste light samples.
fn sun_sky(width: u32, height: u32) -> EnvironmentMap {
    let sun = glam::DVec3::new(0.3, 0.64, -0.7).normalize();
    let sigma = 1.5f64.to_radians();
    let sky = Vec3::new(0.2, 0.3, 0.5);
    let mut texels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        let theta = std::f64::consts::PI * (f64::from(y) + 0.5) / f64::from(height);
        for x in 0..width {
            let phi = ((f64::from(x) + 0.5) / f64::from(width) - 0.5) * std::f64::consts::TAU;
            let direction = glam::DVec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                -theta.sin() * phi.cos(),
            );
            let angle = direction.dot(sun).clamp(-1.0, 1.0).acos();
            let falloff = (-0.5 * (angle / sigma).powi(2)).exp() as f32;
            let radiance = sky + Vec3::new(1.0, 0.9, 0.7) * 300.0 * falloff;
            texels.push(if 2 * y < height { radiance } else { Vec3::ZERO });
        }
    }
    EnvironmentMap {
        width,
        height,
        texels,
    }
}

/// The radiance a horizontal diffuse plane (normal +Y) of albedo `albedo` reflects under a
/// piecewise-constant map: albedo / pi times the irradiance, which over texel rows
/// [theta_0, theta_1] of the upper hemisphere is L delta_phi (sin^2 theta_1 - sin^2 theta_0) / 2
/// exactly (the integral of cos theta sin theta).
fn plane_radiance_under(map: &EnvironmentMap, albedo: f64) -> [f64; 3] {
    let mut irradiance = [0.0f64; 3];
    let delta_phi = std::f64::consts::TAU / f64::from(map.width);
    for y in 0..map.height / 2 {
        let theta = |row: u32| std::f64::consts::PI * f64::from(row) / f64::from(map.height);
        let band = 0.5 * delta_phi * (theta(y + 1).sin().powi(2) - theta(y).sin().powi(2));
        for x in 0..map.width {
            let radiance = map.texels[(y * map.width + x) as usize];
            for (c, e) in irradiance.iter_mut().enumerate() {
                *e += f64::from(radiance[c]) * band;
            }
        }
    }
    irradiance.map(|e| albedo / std::f64::consts::PI * e)
}

#[test]
fn light_sampling_resolves_a_sharp_sun_in_a_large_map_to_a_tenth_of_a_percent() {
    // The defect of issue 18: nee and mis were 0.2-0.3 % dark under a 512x256 sky with a
    // small sun, which an 8x4 map at low spp cannot see. A diffuse plane facing +Y that
    // nothing else shadows, seen from above at path length 2 (one bounce: the light sample
    // and, for mis, the BRDF sample that escapes), reflects albedo / pi times the map's
    // exact irradiance at every pixel (plane_radiance_under()).
    let map = sun_sky(512, 256);
    let albedo = 0.5;
    let expected = plane_radiance_under(&map, albedo);
    let s = 20.0;
    let corners = [
        Vec3::new(-s, 0.0, s),
        Vec3::new(s, 0.0, s),
        Vec3::new(s, 0.0, -s),
        Vec3::new(-s, 0.0, -s),
    ];
    let triangles = [[0, 1, 2], [0, 2, 3]]
        .map(|[a, b, c]| {
            Triangle::new(
                [corners[a], corners[b], corners[c]],
                Vec3::splat(albedo as f32),
                Vec3::ZERO,
                false,
            )
            .unwrap()
        })
        .to_vec();
    let camera = Camera::look_at(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, Vec3::NEG_Z, 0.3);
    let mut lit = scene(triangles, camera);
    lit.environment = Some(Environment {
        map: Some(map),
        background: Vec3::ZERO,
        strength: 1.0,
        rotation_degrees: 0.0,
    });
    // 16x16 pixels (4 workgroups, so both cores work) x 16384 spp = 4.2M samples per
    // integrator. Light sampling's L / p is nearly constant, so a sample's relative standard
    // deviation is about 0.5 (the cosine and the colour) and the image mean's 0.021-0.031 %
    // (measured): the bias of issue 18 (0.27 % in red for nee with PCG, measured with this
    // test before the fix: z = -5.5 at 8x8 x 65536 spp with the lower half of the sky lit)
    // is about 9 sigma here, and a 0.1 % bias about 3.5 (the test asserts the precision it
    // reached). PCG only: the same GLSL with Sobol points is checked by the CPU twins at
    // 2^22 samples (src/cpu/environment.rs), and another 8M samples would double the test.
    // cosine sampling is left out: it finds the sun with probability ~1e-3 per sample, and
    // at 4.2M samples its mean is good to only 0.66 % (measured: -0.16 %, z -0.24 against
    // the closed form).
    let (width, height, spp) = (16u32, 16u32, 1u32 << 14);
    let sampler = SamplerKind::Pcg;
    for integrator in [Integrator::Nee, Integrator::Mis] {
        let image = render(
            &lit,
            RenderSettings {
                width,
                height,
                spp,
                max_path_length: 2,
                integrator,
                sampler,
                samples_per_frame: 64,
                seed: 11,
                ..Default::default()
            },
        );
        let variance: Vec<[f64; 3]> = image
            .variance_of_mean()
            .iter()
            .map(|v| v.map(f64::from))
            .collect();
        let pixels = (width * height) as f64;
        let mean = image.average();
        for c in 0..3 {
            // The image mean: pixels are independent, so its variance is the sum of the
            // pixels' variances of the mean over the pixel count squared.
            let sigma = (variance.iter().map(|v| v[c]).sum::<f64>()).sqrt() / pixels;
            let relative = mean[c] / expected[c] - 1.0;
            let z = (mean[c] - expected[c]) / sigma;
            println!(
                    "{sampler:?} {integrator:?} channel {c}: mean {:.6} expected {:.6} ({:+.4} %, z {z:+.2}, sigma {:.4} %)",
                    mean[c],
                    expected[c],
                    100.0 * relative,
                    100.0 * sigma / expected[c]
                );
            // |z| < 4: a false alarm in 6e-5 of the tests (6 per run).
            assert!(
                z.abs() < 4.0,
                "{sampler:?} {integrator:?} channel {c}: z = {z}"
            );
            assert!(
                sigma / expected[c] < 3.5e-4,
                "the test no longer resolves 0.1 %: sigma {sigma}"
            );
        }
        // Blocks of 2x2 pixels against the closed form: where in the image it fails.
        let exact: Vec<f64> = (0..width * height).flat_map(|_| expected).collect();
        let reference = MeanImage::exact(width as usize, height as usize, 3, exact)
            .unwrap()
            .block_average(2)
            .unwrap();
        let blocks = MeanImage::from_rgb(width as usize, height as usize, &image.mean, &variance)
            .unwrap()
            .block_average(2)
            .unwrap();
        let report = z_test_images(&blocks, &reference, 0.01).unwrap();
        assert!(report.passed, "{sampler:?} {integrator:?}: {report:?}");
    }
}
