//! Tests of the glTF BRDF's CPU twins: χ² of `sample_brdf` against `get_brdf_density`,
//! reciprocity, the density's integral, white-furnace albedo bounds, and Lambertian and
//! mirror limits by hand.

use glam::{DVec3, UVec2, Vec2, Vec3};

use super::*;
use crate::cpu::workshop::get_random_numbers;
use crate::stats::chi2::{chi2_direction_test, Chi2Config};
use crate::stats::sphere_histogram::{SphereFrame, TargetDensity};

/// 10^6 samples: about 200 per bin of Mitsuba's 5050 (the sampler tests' choice).
const SAMPLE_COUNT: usize = 1_000_000;

/// A view direction `degrees` from the normal +Z, in the x-z plane.
fn view_at(degrees: f32) -> Vec3 {
    let theta = degrees.to_radians();
    Vec3::new(theta.sin(), 0.0, theta.cos())
}

/// The configurations the χ² tests cover: (name, material, view angle in degrees).
fn mixed_cases() -> Vec<(&'static str, MaterialSample, f32)> {
    let mut tinted = MaterialSample::gltf(Vec3::new(0.8, 0.3, 0.1), 0.0, 0.4);
    tinted.specular_color = Vec3::new(1.0, 0.5, 2.0);
    tinted.ior = 2.2;
    vec![
        (
            "rough dielectric, normal view",
            MaterialSample::gltf(Vec3::splat(0.5), 0.0, 1.0),
            0.0,
        ),
        (
            "dielectric, roughness 0.3, 60 degrees",
            MaterialSample::gltf(Vec3::new(0.2, 0.6, 0.9), 0.0, 0.3),
            60.0,
        ),
        (
            "half metal, roughness 0.5, 30 degrees",
            MaterialSample::gltf(Vec3::new(0.9, 0.7, 0.2), 0.5, 0.5),
            30.0,
        ),
        (
            "metal, roughness 0.7, 80 degrees",
            MaterialSample::gltf(Vec3::ONE, 1.0, 0.7),
            80.0,
        ),
        ("tinted specular, ior 2.2, 45 degrees", tinted, 45.0),
    ]
}

/// `count` samples of `sample_brdf` with a sequential PCG2D stream.
fn brdf_samples(material: &MaterialSample, view: Vec3, count: usize) -> Vec<Vec3> {
    let mut seed = UVec2::new(17, 4242);
    (0..count)
        .map(|_| sample_brdf(get_random_numbers(&mut seed), material, Vec3::Z, view))
        .collect()
}

#[test]
fn sample_brdf_follows_get_brdf_density() {
    let cases = mixed_cases();
    let config = Chi2Config {
        test_count: cases.len(),
        ..Chi2Config::default()
    };
    for (name, material, degrees) in cases {
        let view = view_at(degrees);
        let density = |light: Vec3| f64::from(get_brdf_density(&material, Vec3::Z, view, light));
        let result = chi2_direction_test(
            brdf_samples(&material, view, SAMPLE_COUNT),
            TargetDensity::SolidAngle(&density),
            &SphereFrame::WORLD,
            &config,
        )
        .unwrap();
        println!(
            "{name}: p = {:.4}, chi2 = {:.1}, dof {}",
            result.p_value, result.statistic, result.degrees_of_freedom
        );
        assert!(result.passed, "{name}: {result:?}");
    }
}

/// The light direction of a direction `stretched` in GGX's configuration stretched to alpha 1:
/// the half vector is normalize(alpha x, alpha y, z), the light its reflection of the view.
fn light_of_stretched(alpha: f64, view: DVec3, stretched: DVec3) -> (DVec3, DVec3, f64) {
    let scaled = DVec3::new(alpha * stretched.x, alpha * stretched.y, stretched.z);
    let half = scaled.normalize();
    let light = 2.0 * view.dot(half) * half - view;
    (light, half, scaled.length())
}

/// Near-mirror metals: the lobe is ~alpha rad wide, far narrower than any bin of a sphere
/// grid, so the samples are tested after mapping each light direction back to its half
/// vector and un-stretching it (h -> normalize(h_x / alpha, h_y / alpha, h_z)), where the
/// lobe spans the hemisphere. The target density there is the light direction's density
/// times the Jacobians of both maps: |d omega_l / d omega_h| = 4 |v.h| and
/// |d omega_h / d omega_s| = alpha^2 / |M s|^3 for M = diag(alpha, alpha, 1).
#[test]
fn sample_brdf_follows_its_density_down_to_roughness_0_01() {
    let cases = [(0.01_f32, 45.0_f32), (0.01, 85.0), (0.1, 20.0), (0.2, 70.0)];
    let config = Chi2Config {
        test_count: cases.len(),
        ..Chi2Config::default()
    };
    for (roughness, degrees) in cases {
        let material = MaterialSample::gltf(Vec3::new(0.95, 0.64, 0.54), 1.0, roughness);
        assert_eq!(get_specular_probability(&material, view_at(degrees).z), 1.0);
        let view = view_at(degrees);
        let alpha = f64::from(get_ggx_alpha(roughness));
        let view64 = view.as_dvec3();
        let stretched: Vec<Vec3> = brdf_samples(&material, view, SAMPLE_COUNT)
            .into_iter()
            .map(|light| {
                let half = (view64 + light.as_dvec3()).normalize();
                DVec3::new(half.x / alpha, half.y / alpha, half.z)
                    .normalize()
                    .as_vec3()
            })
            .collect();
        // Below the stretched horizon the half vector would be flipped, which reflects the
        // view to the same light direction: those directions are not in the map's range.
        let density = |s: Vec3| {
            if s.z <= 0.0 {
                return 0.0;
            }
            let (light, half, length) = light_of_stretched(alpha, view64, s.as_dvec3());
            let p = f64::from(get_brdf_density(
                &material,
                Vec3::Z,
                view,
                light.normalize().as_vec3(),
            ));
            p * 4.0 * view64.dot(half).abs() * alpha * alpha / length.powi(3)
        };
        let result = chi2_direction_test(
            stretched,
            TargetDensity::SolidAngle(&density),
            &SphereFrame::WORLD,
            &config,
        )
        .unwrap();
        println!(
            "metal roughness {roughness} at {degrees} degrees: p = {:.4}, chi2 = {:.1}",
            result.p_value, result.statistic
        );
        assert!(
            result.passed,
            "roughness {roughness}, {degrees} degrees: {result:?}"
        );
    }
}

/// Midpoint quadrature over the sphere in (phi, cos theta): sum of f over `n` x 2`n` cells.
fn integrate_sphere(n: usize, f: impl Fn(Vec3) -> f64) -> f64 {
    let mut sum = 0.0;
    for i in 0..n {
        let cos_theta = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
        let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
        for j in 0..2 * n {
            let phi = std::f64::consts::PI * (j as f64 + 0.5) / n as f64;
            let direction = DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
            sum += f(direction.as_vec3());
        }
    }
    sum * 4.0 * std::f64::consts::PI / (2 * n * n) as f64
}

#[test]
fn brdf_density_integrates_to_one() {
    // Roughness >= 0.3 keeps the lobe many cells wide at 2000 x 4000 cells (the quadrature
    // error is then ~1e-4); narrower lobes are covered by the χ² tests above.
    for (name, material, degrees) in mixed_cases() {
        let view = view_at(degrees);
        let integral = integrate_sphere(1000, |light| {
            f64::from(get_brdf_density(&material, Vec3::Z, view, light))
        });
        println!("{name}: density integral {integral:.5}");
        assert!((integral - 1.0).abs() < 2e-3, "{name}: {integral}");
    }
    let below = view_at(120.0);
    let material = MaterialSample::gltf(Vec3::ONE, 0.0, 0.5);
    assert_eq!(get_brdf_density(&material, Vec3::Z, below, Vec3::Z), 0.0);
}

#[test]
fn brdf_is_reciprocal() {
    let mut seed = UVec2::new(3, 9);
    let mut next = || get_random_numbers(&mut seed);
    let mut worst = 0.0_f32;
    for _ in 0..20_000 {
        let [a, b] = next().to_array();
        let [c, d] = next().to_array();
        let material = get_base_material(
            Vec3::new(a, b, c),
            d,
            next().x.max(0.05),
            next().x,
            Vec3::new(next().x, next().y, 1.0),
            1.0 + 2.0 * next().x,
        );
        let view = crate::cpu::workshop::sample_hemisphere(next(), Vec3::Z);
        let light = crate::cpu::workshop::sample_hemisphere(next(), Vec3::Z);
        let forward = get_brdf(&material, Vec3::Z, view, light);
        let backward = get_brdf(&material, Vec3::Z, light, view);
        let error = ((forward - backward).abs() / forward.max(Vec3::splat(1e-6))).max_element();
        worst = worst.max(error);
    }
    println!("largest relative difference f(v, l) vs f(l, v): {worst:e}");
    // Float rounding of the half vector and of the two sums in V: a few ulps.
    assert!(worst < 1e-4, "{worst}");
}

/// Directional albedo: integral of f(v, l) (n.l) over the hemisphere.
fn directional_albedo(material: &MaterialSample, view: Vec3) -> f64 {
    integrate_sphere(1000, |light| {
        f64::from(get_brdf(material, Vec3::Z, view, light).x) * f64::from(light.z.max(0.0))
    })
}

#[test]
fn white_furnace_albedo_never_exceeds_one() {
    // A white metal has F = 1: its albedo is the GGX lobe's energy kept by single
    // scattering, below 1 and near 1 for smooth surfaces at moderate angles.
    for roughness in [0.3_f32, 0.6, 1.0] {
        for degrees in [0.0_f32, 30.0, 60.0, 80.0] {
            let albedo = directional_albedo(
                &MaterialSample::gltf(Vec3::ONE, 1.0, roughness),
                view_at(degrees),
            );
            println!("white metal roughness {roughness}, {degrees} degrees: albedo {albedo:.4}");
            // Roughness 1 at normal view loses most: f = 0.5 / (pi (n.l + n.v)), albedo 1 - ln 2.
            assert!(albedo <= 1.0 + 1e-3 && albedo > 0.3, "{albedo}");
        }
    }
    // A white Lambertian (specular 0) reflects everything.
    let mut lambertian = MaterialSample::gltf(Vec3::ONE, 0.0, 1.0);
    lambertian.specular = 0.0;
    let albedo = directional_albedo(&lambertian, view_at(40.0));
    assert!((albedo - 1.0).abs() < 1e-3, "{albedo}");
}

#[test]
fn specular_zero_dielectric_is_lambertian_and_samples_the_cosine() {
    let mut material = MaterialSample::gltf(Vec3::new(0.2, 0.5, 0.8), 0.0, 0.5);
    material.specular = 0.0;
    let view = view_at(33.0);
    assert_eq!(get_specular_probability(&material, view.z), 0.0);
    let light = Vec3::new(0.3, -0.4, 0.866).normalize();
    let f = get_brdf(&material, Vec3::Z, view, light);
    assert!(
        (f - material.base_color / M_PI).abs().max_element() < 1e-7,
        "{f}"
    );
    let density = get_brdf_density(&material, Vec3::Z, view, light);
    assert!((density - light.z / M_PI).abs() < 1e-7);
}

#[test]
fn the_lambert_special_case_has_the_general_functions_bits() {
    // Kernels whose scene has no specular lobe (SCENE_HAS_SPECULAR false) call the Lambert
    // functions instead of get_brdf, sample_brdf and get_brdf_density: their images keep
    // every bit only if these agree exactly, for any roughness and any directions, the view
    // above the normal (the surface seam guarantees it) and the light anywhere. A black base
    // colour is the one exception (its specular probability is 1/2); it reflects nothing.
    let mut seed = UVec2::new(5, 77);
    let mut uniform = || get_random_numbers(&mut seed);
    let sphere = |u: Vec2| {
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * M_PI * u.y;
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    for _ in 0..20_000 {
        let colour = uniform();
        let roughness = uniform();
        let mut material = MaterialSample::gltf(
            Vec3::new(colour.x, colour.y, 0.01 + roughness.y),
            0.0,
            roughness.x,
        );
        material.specular = 0.0;
        let normal = sphere(uniform());
        let mut view = sphere(uniform());
        if normal.dot(view) < 0.0 {
            view = -view;
        }
        let light = sphere(uniform());
        let randoms = uniform();
        let general = get_brdf(&material, normal, view, light);
        let lambert = get_lambert_brdf(&material, normal, view, light);
        assert_eq!(
            general.to_array().map(f32::to_bits),
            lambert.to_array().map(f32::to_bits)
        );
        assert_eq!(
            get_brdf_density(&material, normal, view, light).to_bits(),
            get_lambert_brdf_density(normal, view, light).to_bits()
        );
        let sampled = sample_brdf(randoms, &material, normal, view);
        assert_eq!(
            sampled.to_array().map(f32::to_bits),
            sample_lambert_brdf(randoms, normal)
                .to_array()
                .map(f32::to_bits)
        );
    }
}

#[test]
fn roughness_zero_gives_finite_values_and_a_mirror_direction() {
    let material = MaterialSample::gltf(Vec3::ONE, 1.0, 0.0);
    let view = view_at(50.0);
    let mirror = Vec3::new(-view.x, -view.y, view.z);
    let mut seed = UVec2::new(1, 2);
    for _ in 0..1000 {
        let light = sample_brdf(get_random_numbers(&mut seed), &material, Vec3::Z, view);
        assert!(light.is_finite() && (light.length() - 1.0).abs() < 1e-5);
        // The lobe is ~alpha = 1e-4 rad wide.
        // GGX's tail holds a fraction ~(alpha / angle)^2 beyond an angle: 4e-6 beyond 0.05 rad.
        assert!(light.dot(mirror) > (0.05_f32).cos(), "{light} vs {mirror}");
        let f = get_brdf(&material, Vec3::Z, view, light);
        let density = get_brdf_density(&material, Vec3::Z, view, light);
        assert!(f.is_finite() && density.is_finite() && density > 0.0);
        // A white mirror's sample weight f (n.l) / p is G_2 / G_1, at most 1.
        let weight = f.x * light.z / density;
        assert!(weight > 0.99 && weight <= 1.0 + 1e-3, "{weight}");
    }
    let off = get_brdf(&material, Vec3::Z, view, Vec3::Z);
    assert!(off.is_finite());
}

#[test]
fn fresnel_and_f0_by_hand() {
    let material = MaterialSample::gltf(Vec3::ONE, 0.0, 1.0);
    let f0 = get_dielectric_f0(&material);
    assert!((f0 - Vec3::splat(0.04)).abs().max_element() < 1e-7);
    assert_eq!(get_schlick_fresnel(f0, Vec3::ONE, 1.0), f0);
    assert_eq!(get_schlick_fresnel(f0, Vec3::ONE, 0.0), Vec3::ONE);
    let half_way = get_schlick_fresnel(Vec3::ZERO, Vec3::ONE, 0.5);
    assert!((half_way.x - 1.0 / 32.0).abs() < 1e-7);
    assert!(Vec2::ZERO.is_finite());
}
