//! Light beyond emissive triangles, rendered on the GPU against closed forms: a convex
//! diffuse object under a constant background, point, spot and directional lights over a
//! diffuse plane, and an environment map that every integrator sees alike.

mod common;

use glam::{Mat4, Vec3};
use vkpath::camera::Camera;
use vkpath::scene::environment::{Environment, EnvironmentMap};
use vkpath::scene::procedural::inward_cube;
use vkpath::scene::punctual::{PunctualKind, PunctualLight};
use vkpath::scene::Triangle;
use vkpath::stats::ztest::{z_test_images, MeanImage};
use vkpath::{Integrator, PixelFilter, RenderSettings, RenderedImage, Renderer, Scene};

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
