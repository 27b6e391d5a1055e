//! Tests of the glTF BRDF's CPU twins: χ² of `sample_brdf` against `get_brdf_density`,
//! reciprocity, the density's integral, white-furnace albedo bounds, and Lambertian and
//! mirror limits by hand.

use glam::{DVec3, UVec2, Vec2, Vec3};

use super::*;
use crate::cpu::fresnel::get_schlick_fresnel;
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
fn roughness_zero_is_a_mirror_whose_pick_weighs_its_reflectance() {
    // A smooth metal of colour c: a delta lobe. sample_brdf() returns the mirror direction
    // (to rounding), get_brdf() and get_brdf_density() are 0 there and everywhere else, and
    // the mirror pick (probability 1: a metal has no diffuse lobe) weighs Schlick's
    // F(c, 1, n.v): c itself head-on, a mirror in a uniform environment of radiance L shows
    // c L exactly.
    let color = Vec3::new(0.9, 0.5, 0.2);
    let metal = MaterialSample::gltf(color, 1.0, 0.0);
    for degrees in [0.0f32, 50.0, 85.0] {
        let view = view_at(degrees);
        let mirror = Vec3::new(-view.x, -view.y, view.z);
        assert_eq!(get_brdf_mirror_probability(&metal, Vec3::Z, view), 1.0);
        let weight = get_brdf_mirror_weight(&metal, Vec3::Z, view);
        let schlick = get_schlick_fresnel(color, Vec3::ONE, view.z);
        assert!(
            (weight - schlick).abs().max_element() < 1e-6,
            "{weight} vs {schlick}"
        );
        if degrees == 0.0 {
            assert!((weight - color).abs().max_element() < 1e-6, "{weight}");
        }
        let mut seed = UVec2::new(1, 2);
        for _ in 0..1000 {
            let light = sample_brdf(get_random_numbers(&mut seed), &metal, Vec3::Z, view);
            assert!((light - mirror).length() < 1e-6, "{light} vs {mirror}");
            assert_eq!(get_brdf(&metal, Vec3::Z, view, light), Vec3::ZERO);
            assert_eq!(get_brdf_density(&metal, Vec3::Z, view, light), 0.0);
        }
    }
    // A smooth dielectric keeps its diffuse lobe, with the mixture density without the
    // delta part: (1 - p_s) (n.l) / pi.
    let plastic = MaterialSample::gltf(color, 0.0, 0.0);
    let view = view_at(40.0);
    let light = view_at(-20.0);
    let specular_probability = get_specular_probability(&plastic, view.z);
    assert_eq!(
        get_brdf_mirror_probability(&plastic, Vec3::Z, view),
        specular_probability
    );
    let density = get_brdf_density(&plastic, Vec3::Z, view, light);
    let expected = (1.0 - specular_probability) * light.z / M_PI;
    assert!(
        (density - expected).abs() < 1e-6 * expected,
        "{density} vs {expected}"
    );
    // The mirror pick's weight: F_d(n.v) / p_s; a diffuse pick's is the continuous f / p.
    let weight = get_brdf_mirror_weight(&plastic, Vec3::Z, view);
    let fresnel = get_schlick_fresnel(Vec3::splat(0.04), Vec3::ONE, view.z);
    assert!(
        (weight - fresnel / specular_probability)
            .abs()
            .max_element()
            < 1e-6
    );
    // Roughness just above 0 is still a continuous lobe (alpha MIN_GGX_ALPHA).
    let nearly = MaterialSample::gltf(color, 1.0, 1e-3);
    assert_eq!(get_brdf_mirror_probability(&nearly, Vec3::Z, view), 0.0);
    let mirror = Vec3::new(-view.x, -view.y, view.z);
    assert!(get_brdf_density(&nearly, Vec3::Z, view, mirror) > 1e6);
}

#[test]
fn a_smooth_plastic_samples_its_mirror_and_diffuse_lobes_without_bias() {
    // sample_brdf() at roughness 0 with the path loop's weights: a mirror pick (u_0 below
    // get_brdf_mirror_probability()) weighs get_brdf_mirror_weight(), a diffuse pick
    // get_brdf() (n.l) / get_brdf_density(). Their mean is the directional albedo: the
    // mirror's F_d(n.v) plus the diffuse lobe's integral (midpoint rule, 400 x 800 cells).
    let color = Vec3::new(0.9, 0.5, 0.2);
    let plastic = MaterialSample::gltf(color, 0.0, 0.0);
    for degrees in [10.0f32, 56.7, 75.0] {
        let view = view_at(degrees);
        let n = 400;
        let mut albedo = DVec3::ZERO;
        for i in 0..n {
            let cos_theta = (i as f64 + 0.5) / n as f64;
            let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
            for j in 0..2 * n {
                let phi = std::f64::consts::PI * (j as f64 + 0.5) / n as f64;
                let light = DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
                albedo += get_brdf(&plastic, Vec3::Z, view, light.as_vec3()).as_dvec3() * cos_theta;
            }
        }
        albedo = albedo * std::f64::consts::PI / (n * n) as f64
            + get_mirror_reflectance(&plastic, view.z).as_dvec3();
        let mut seed = UVec2::new(9, 9);
        let count = 200_000;
        let (mut sum, mut sum_of_squares, mut mirrors) = (DVec3::ZERO, DVec3::ZERO, 0);
        let mirror_probability = get_brdf_mirror_probability(&plastic, Vec3::Z, view);
        for _ in 0..count {
            let random_numbers: Vec2 = get_random_numbers(&mut seed);
            let light = sample_brdf(random_numbers, &plastic, Vec3::Z, view);
            let weight = if random_numbers[0] < mirror_probability {
                mirrors += 1;
                get_brdf_mirror_weight(&plastic, Vec3::Z, view)
            } else {
                let density = get_brdf_density(&plastic, Vec3::Z, view, light);
                get_brdf(&plastic, Vec3::Z, view, light) * light.z.max(0.0) / density
            }
            .as_dvec3();
            sum += weight;
            sum_of_squares += weight * weight;
        }
        let mean = sum / f64::from(count);
        let error = ((sum_of_squares / f64::from(count) - mean * mean) / f64::from(count))
            .max(DVec3::ZERO)
            .to_array()
            .map(f64::sqrt);
        println!("smooth plastic at {degrees} deg: mean {mean}, albedo {albedo}, +- {error:?}, mirror picks {mirrors} (p = {mirror_probability})");
        for channel in 0..3 {
            // 9 tests at 1 %: |z| < 3.3
            assert!(
                (mean[channel] - albedo[channel]).abs() < 3.3 * error[channel] + 1e-5,
                "{degrees} deg channel {channel}: {} vs {}",
                mean[channel],
                albedo[channel]
            );
        }
    }
}
