//! Tests of the layered BSDF's CPU twins: χ² of every sampler against its density (rough
//! dielectric at several roughnesses, IORs and angles, entering and leaving; thin walls;
//! clear coats over the base), the Fresnel reflectance by hand, the BTDF's generalised
//! reciprocity, and the energy a single-scattering microfacet dielectric keeps.

use glam::{UVec2, Vec2, Vec3};

use super::*;
use crate::contract::SHEEN_ALBEDO_SIZE;
use crate::cpu::brdf::get_luminance;
use crate::cpu::fresnel::get_schlick_fresnel;
use crate::cpu::workshop::get_random_numbers;
use crate::stats::chi2::{chi2_direction_test, Chi2Config};
use crate::stats::sphere_histogram::{SphereFrame, TargetDensity};

/// 10^6 samples per test: about 200 per bin of the 5050-bin grid (as the BRDF's tests).
const SAMPLE_COUNT: usize = 1_000_000;

/// A view direction `degrees` from the normal +Z, in the x-z plane.
fn view_at(degrees: f32) -> Vec3 {
    let theta = degrees.to_radians();
    Vec3::new(theta.sin(), 0.0, theta.cos())
}

/// Glass: white, transmission 1, a refracting volume.
fn glass(roughness: f32, ior: f32) -> MaterialSample {
    MaterialSample {
        transmission: 1.0,
        thickness: 1.0,
        ior,
        ..MaterialSample::gltf(Vec3::ONE, 0.0, roughness)
    }
}

/// `count` samples of `sample_layered_bsdf` in the shading frame (normal +Z) with a
/// sequential PCG2D stream: a pair for the direction, then a pair whose first number
/// chooses the lobe (as `sample_path_direction` draws them).
fn layered_samples(material: &MaterialSample, eta: f32, view: Vec3, count: usize) -> Vec<Vec3> {
    let mut seed = UVec2::new(23, 777);
    (0..count)
        .map(|_| {
            let random_numbers: Vec2 = get_random_numbers(&mut seed);
            let lobe_random = get_random_numbers(&mut seed)[0];
            sample_layered_bsdf(
                random_numbers,
                lobe_random,
                material,
                eta,
                Vec3::Z,
                Vec3::Z,
                view,
            )
            .0
        })
        .collect()
}

/// The χ² cases: (name, material, eta, view angle in degrees).
fn chi2_cases() -> Vec<(String, MaterialSample, f32, f32)> {
    let mut cases = Vec::new();
    // Entering (eta = ior) and leaving (eta = 1 / ior: total internal reflection beyond
    // the critical angle) at each IOR, roughness and angle.
    for (ior, roughness, degrees) in [
        (1.33, 0.7, 0.0),
        (1.33, 0.6, 70.0),
        (1.5, 0.3, 45.0),
        (1.5, 1.0, 20.0),
        (2.4, 0.5, 60.0),
        (2.4, 0.4, 35.0),
    ] {
        for (side, eta) in [("entering", ior), ("leaving", 1.0 / ior)] {
            cases.push((
                format!("glass ior {ior} roughness {roughness} {degrees} deg {side}"),
                glass(roughness, ior),
                eta,
                degrees,
            ));
        }
    }
    let mut tinted_thin = glass(0.4, 1.5);
    tinted_thin.thickness = 0.0;
    tinted_thin.base_color = Vec3::new(0.9, 0.4, 0.1);
    cases.push((
        "thin wall roughness 0.4, 50 deg".into(),
        tinted_thin,
        1.5,
        50.0,
    ));
    let mut half_glass = glass(0.5, 1.5);
    half_glass.transmission = 0.5;
    half_glass.metallic = 0.3;
    half_glass.base_color = Vec3::new(0.7, 0.8, 0.9);
    cases.push((
        "half transmissive, part metal, 30 deg".into(),
        half_glass,
        1.5,
        30.0,
    ));
    let mut coated = MaterialSample::gltf(Vec3::new(0.6, 0.1, 0.1), 0.0, 0.8);
    coated.clearcoat = 1.0;
    coated.clearcoat_roughness = 0.3;
    cases.push((
        "clear coat 1 over rough red, 60 deg".into(),
        coated,
        1.5,
        60.0,
    ));
    let mut coated_glass = glass(0.6, 1.5);
    coated_glass.clearcoat = 0.5;
    coated_glass.clearcoat_roughness = 0.4;
    cases.push((
        "clear coat 0.5 over rough glass, 10 deg".into(),
        coated_glass,
        1.5,
        10.0,
    ));
    let mut sheen = MaterialSample::gltf(Vec3::new(0.3, 0.3, 0.6), 0.0, 0.6);
    sheen.sheen_color = Vec3::new(1.0, 0.8, 0.6);
    sheen.sheen_roughness = 0.5;
    cases.push(("sheen 0.5 over blue, 40 deg".into(), sheen, 1.5, 40.0));
    let mut coated_sheen = sheen;
    coated_sheen.sheen_roughness = 0.2;
    coated_sheen.clearcoat = 0.7;
    coated_sheen.clearcoat_roughness = 0.4;
    cases.push((
        "clear coat over sheen 0.2, 70 deg".into(),
        coated_sheen,
        1.5,
        70.0,
    ));
    cases
}

#[test]
fn sample_layered_bsdf_follows_get_layered_density() {
    let cases = chi2_cases();
    let config = Chi2Config {
        test_count: cases.len(),
        ..Chi2Config::default()
    };
    let mut failed = Vec::new();
    for (name, material, eta, degrees) in cases {
        let view = view_at(degrees);
        let density = |light: Vec3| {
            f64::from(get_layered_density(
                &material,
                eta,
                Vec3::Z,
                Vec3::Z,
                view,
                light,
            ))
        };
        let result = chi2_direction_test(
            layered_samples(&material, eta, view, SAMPLE_COUNT),
            TargetDensity::SolidAngle(&density),
            &SphereFrame::WORLD,
            &config,
        )
        .unwrap();
        println!(
            "{name}: p = {:.4}, chi2 = {:.1}, dof {}",
            result.p_value, result.statistic, result.degrees_of_freedom
        );
        if !result.passed {
            failed.push(format!("{name}: {result:?}"));
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}

#[test]
fn btdf_is_reciprocal_with_the_eta_squared_factor() {
    // Generalised reciprocity of a BTDF for radiance: f(v -> l; eta) eta_l^2 ... with our
    // eta = eta_far / eta_view, swapping the directions (and so the sides, eta -> 1 / eta)
    // gives f(l, v; 1 / eta) = eta^2 f(v, l; eta).
    let mut seed = UVec2::new(5, 11);
    let mut worst = 0.0f32;
    let mut compared = 0;
    for _ in 0..20_000 {
        let u: Vec2 = get_random_numbers(&mut seed);
        let w: Vec2 = get_random_numbers(&mut seed);
        let roughness = 0.05 + 0.95 * u.x;
        let eta = [1.33f32, 1.5, 2.4, 1.0 / 1.33, 1.0 / 1.5, 1.0 / 2.4][(u.y * 6.0) as usize % 6];
        let view = crate::cpu::workshop::sample_hemisphere(w, Vec3::Z);
        let light =
            -crate::cpu::workshop::sample_hemisphere(get_random_numbers(&mut seed), Vec3::Z);
        let alpha = get_ggx_alpha(roughness);
        let forward = get_rough_dielectric_bsdf(alpha, eta, view, light).y;
        // Seen from the light's side: both directions mirrored so that the light is above.
        let backward = get_rough_dielectric_bsdf(
            alpha,
            1.0 / eta,
            mirror_through_surface(light),
            mirror_through_surface(view),
        )
        .y;
        if forward > 1e-3 {
            compared += 1;
            let error = (backward - eta * eta * forward).abs() / (eta * eta * forward);
            worst = worst.max(error);
        } else {
            assert!(backward < 1e-2 * eta * eta + 1e-6, "{forward} {backward}");
        }
    }
    println!("reciprocity: {compared} pairs, largest relative error {worst:e}");
    assert!(compared > 2_000, "{compared}");
    // Float rounding: 1 - F loses digits near grazing refraction, where F nears 1
    // (measured: 2.9e-3 at most over these pairs).
    assert!(worst < 1e-2, "{worst}");
}

/// The energy a path keeps at one scattering: the mean sample weight f |cos| / p, with
/// refractions' 1 / eta^2 radiance scale divided out (what a furnace sees after leaving
/// the medium again), and its standard error.
fn kept_energy(material: &MaterialSample, eta: f32, view: Vec3, count: usize) -> (f64, f64) {
    let (mut sum, mut sum_of_squares) = (0.0f64, 0.0f64);
    let mut seed = UVec2::new(77, 1);
    for _ in 0..count {
        let random_numbers: Vec2 = get_random_numbers(&mut seed);
        let lobe_random = get_random_numbers(&mut seed)[0];
        let (light, delta_weight) = sample_layered_bsdf(
            random_numbers,
            lobe_random,
            material,
            eta,
            Vec3::Z,
            Vec3::Z,
            view,
        );
        let density = get_layered_density(material, eta, Vec3::Z, Vec3::Z, view, light);
        let mut weight = 0.0;
        if let Some(delta_weight) = delta_weight {
            // A delta pick (roughness 0): its own f / p
            weight = f64::from(delta_weight.x);
        } else if density > 0.0 {
            let bsdf = get_layered_bsdf(material, eta, Vec3::Z, Vec3::Z, Vec3::Z, view, light);
            weight = f64::from(bsdf.x / density);
        }
        if light.z < 0.0 && is_refracting(material) {
            weight *= f64::from(eta * eta);
        }
        sum += weight;
        sum_of_squares += weight * weight;
    }
    let mean = sum / count as f64;
    let variance = (sum_of_squares / count as f64 - mean * mean).max(0.0);
    (mean, (variance / count as f64).sqrt())
}

#[test]
fn a_dielectric_keeps_at_most_all_energy_and_smooth_glass_all_of_it() {
    for (roughness, lower) in [(0.0f32, 0.999), (0.3, 0.85), (0.5, 0.7), (0.7, 0.55)] {
        for eta in [1.5f32, 1.0 / 1.5] {
            for degrees in [0.0f32, 40.0, 75.0] {
                let (kept, error) =
                    kept_energy(&glass(roughness, 1.5), eta, view_at(degrees), 200_000);
                println!(
                    "glass roughness {roughness}, eta {eta:.3}, {degrees} deg: keeps {kept:.4} +- {error:.4}"
                );
                // Energy is conserved (within 4 standard errors) and, for smooth glass,
                // entirely kept; rough glass loses what single scattering loses.
                assert!(kept <= 1.0 + 4.0 * error + 1e-4, "{kept}");
                assert!(kept >= lower, "{roughness} {eta} {degrees}: {kept}");
            }
        }
    }
}

#[test]
fn smooth_lobes_have_no_value_and_no_density_for_any_direction() {
    // Roughness 0 is a delta lobe: get_ggx_alpha() 0, and every GGX lobe's value and density
    // are exactly 0 whatever the direction (light samples find nothing), the directions
    // closest to the peaks included; a rough lobe (roughness 0.01, alpha 1e-4) has them.
    assert_eq!(get_ggx_alpha(0.0), 0.0);
    assert_eq!(get_ggx_alpha(0.001), crate::contract::MIN_GGX_ALPHA);
    let mut thin = glass(0.0, 1.5);
    thin.thickness = 0.0;
    let mut coated = MaterialSample::gltf(Vec3::new(0.5, 0.2, 0.1), 1.0, 0.0);
    coated.clearcoat = 1.0;
    let view = view_at(30.0);
    let mirror = Vec3::new(-view.x, -view.y, view.z);
    let refracted = refract(-view, Vec3::Z, 1.0 / 1.5);
    let tilted = |direction: Vec3| (direction + Vec3::new(1e-4, 0.0, 0.0)).normalize();
    for (name, material) in [
        ("glass", glass(0.0, 1.5)),
        ("thin wall", thin),
        ("coated metal", coated),
    ] {
        for light in [
            mirror,
            -view,
            refracted,
            tilted(mirror),
            tilted(-view),
            Vec3::Z,
            -Vec3::Z,
        ] {
            let bsdf = get_layered_bsdf(&material, 1.5, Vec3::Z, Vec3::Z, Vec3::Z, view, light);
            let density = get_layered_density(&material, 1.5, Vec3::Z, Vec3::Z, view, light);
            assert_eq!((bsdf, density), (Vec3::ZERO, 0.0), "{name} towards {light}");
        }
    }
    let mut rough_thin = thin;
    rough_thin.roughness = 0.01;
    assert!(get_layered_density(&rough_thin, 1.5, Vec3::Z, Vec3::Z, view, -view) > 1e3);
}

#[test]
fn a_smooth_thin_pane_passes_straight_through_with_weight_one_minus_f_over_its_pick() {
    // Tinted base colour c, ior 1.5, thickness 0: every pick is one of two peaks, the mirror
    // direction (weight F / P_r) or -v itself (weight (1 - F) c / (1 - P_r)), with F
    // Schlick's at n.v and P_r = lum(F) / (lum(F) + lum((1 - F) c)). Head-on F = F0 = 0.04,
    // so the transmitted light, the mean of the transmitted picks' weights, is 0.96 c.
    let tint = Vec3::new(0.9, 0.6, 0.3);
    let mut pane = glass(0.0, 1.5);
    pane.thickness = 0.0;
    pane.base_color = tint;
    for degrees in [0.0f32, 50.0] {
        let view = view_at(degrees);
        let fresnel = get_schlick_fresnel(Vec3::splat(0.04), Vec3::ONE, view.z);
        let reflected = get_luminance(fresnel);
        let probability = reflected / (reflected + get_luminance((1.0 - fresnel) * tint));
        let mut seed = UVec2::new(1, 2);
        let (mut transmitted, count) = (Vec3::ZERO, 40_000);
        for _ in 0..count {
            let random_numbers: Vec2 = get_random_numbers(&mut seed);
            let lobe_random = get_random_numbers(&mut seed)[0];
            let (light, delta_weight) = sample_layered_bsdf(
                random_numbers,
                lobe_random,
                &pane,
                1.5,
                Vec3::Z,
                Vec3::Z,
                view,
            );
            let weight = delta_weight.expect("every pick of a smooth thin wall is a delta");
            if light.z < 0.0 {
                assert!((light + view).length() < 1e-6, "{degrees}: {light} not -v");
                let expected = (1.0 - fresnel) * tint / (1.0 - probability);
                assert!(
                    (weight - expected).abs().max_element() < 1e-6,
                    "{weight} vs {expected}"
                );
                transmitted += weight;
            } else {
                assert!((light - Vec3::new(-view.x, -view.y, view.z)).length() < 1e-6);
                assert!((weight - fresnel / probability).abs().max_element() < 1e-6);
            }
        }
        let mean = transmitted / count as f32;
        let closed_form = (1.0 - fresnel) * tint;
        // A transmitted pick is Bernoulli(1 - P_r) times its fixed weight: 4 standard
        // errors of that (at most 0.9 sqrt(0.05 / 40000) = 1e-3).
        let error = (closed_form / (1.0 - probability))
            * ((1.0 - probability) * probability / count as f32).sqrt();
        println!("smooth thin pane {degrees} deg: transmits {mean} (closed form {closed_form})");
        assert!(
            ((mean - closed_form).abs() - 4.0 * error).max_element() < 1e-6,
            "{mean}"
        );
    }
}

#[test]
fn a_smooth_dielectric_refracts_and_reflects_with_exact_fresnel_weights() {
    // Refracting glass (transmission 1, ior 1.5), entering and leaving: a reflection pick
    // has weight F / F = 1, a refraction's (1 - F) / eta^2 / (1 - F) = 1 / eta^2 and lies
    // along Snell's direction; past the critical angle (leaving at 50 degrees) every pick
    // reflects.
    let material = glass(0.0, 1.5);
    for (eta, degrees) in [
        (1.5f32, 0.0f32),
        (1.5, 60.0),
        (1.0 / 1.5, 30.0),
        (1.0 / 1.5, 50.0),
    ] {
        let view = view_at(degrees);
        let fresnel = get_dielectric_fresnel(view.z, eta);
        let mut seed = UVec2::new(3, 4);
        let mut refracted_count = 0;
        for _ in 0..4_000 {
            let random_numbers: Vec2 = get_random_numbers(&mut seed);
            let lobe_random = get_random_numbers(&mut seed)[0];
            let (light, delta_weight) = sample_layered_bsdf(
                random_numbers,
                lobe_random,
                &material,
                eta,
                Vec3::Z,
                Vec3::Z,
                view,
            );
            let weight = delta_weight.expect("smooth glass picks only peaks");
            if light.z < 0.0 {
                refracted_count += 1;
                let snell = refract(-view, Vec3::Z, 1.0 / eta);
                assert!((light - snell).length() < 1e-5, "{light} vs {snell}");
                assert!(
                    (weight - Vec3::splat(1.0 / (eta * eta)))
                        .abs()
                        .max_element()
                        < 1e-5
                );
            } else {
                assert!((weight - Vec3::ONE).abs().max_element() < 1e-5, "{weight}");
            }
        }
        println!("smooth glass eta {eta:.3} {degrees} deg: F {fresnel:.4}, {refracted_count} of 4000 refracted");
        if fresnel == 1.0 {
            assert_eq!(refracted_count, 0);
        } else {
            // Binomial(4000, 1 - F): within 5 standard deviations.
            let mean = 4000.0 * (1.0 - fresnel);
            let sd = (4000.0 * fresnel * (1.0 - fresnel)).sqrt();
            assert!(
                (refracted_count as f32 - mean).abs() < 5.0 * sd + 1.0,
                "{refracted_count} vs {mean}"
            );
        }
    }
}

#[test]
fn clear_coat_zero_is_the_base_and_the_coat_weight_follows_n_c_dot_v() {
    let base = MaterialSample::gltf(Vec3::new(0.5, 0.2, 0.1), 0.0, 0.5);
    assert_eq!(get_clearcoat_weight(&base, 0.3), 0.0);
    let mut coated = base;
    coated.clearcoat = 1.0;
    // Schlick at normal view: F0 = 0.04; at grazing: 1.
    assert!((get_clearcoat_weight(&coated, 1.0) - 0.04).abs() < 1e-7);
    assert!((get_clearcoat_weight(&coated, 0.0) - 1.0).abs() < 1e-7);
    // The coat's weight reads the coat normal, not the half vector: a tilted coat normal
    // changes it while the base stays.
    let view = view_at(30.0);
    let light = view_at(-50.0);
    let tilted = Vec3::new(0.3, 0.0, 1.0).normalize();
    let straight = get_layered_bsdf(&coated, 1.5, Vec3::Z, Vec3::Z, Vec3::Z, view, light);
    let bent = get_layered_bsdf(&coated, 1.5, Vec3::Z, Vec3::Z, tilted, view, light);
    assert_ne!(straight, bent);
}

#[test]
fn the_sheen_albedo_table_is_the_lobes_integral() {
    // Recompute table nodes (n.v = i / 31, roughness j / 31) by the midpoint rule over the
    // hemisphere with the twins' own lobe, and compare: the table's generator
    // (scripts/make_sheen_albedo.py, double precision, 512 x 1024 cells) and this f32
    // quadrature (256 x 512 cells) agree to the quadrature's error, a few 1e-4 where the
    // lobe is smooth; a stale or mis-indexed table is off by far more.
    let mut worst = 0.0f32;
    for (i, j) in [
        (31u32, 31u32),
        (31, 8),
        (20, 16),
        (10, 25),
        (5, 12),
        (16, 31),
        (25, 4),
    ] {
        let mu = (i as f32 / 31.0).max(1e-4);
        let roughness = j as f32 / 31.0;
        let material = MaterialSample {
            sheen_color: Vec3::ONE,
            sheen_roughness: roughness,
            ..MaterialSample::gltf(Vec3::ZERO, 0.0, 1.0)
        };
        let view = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        let n = 256;
        let mut sum = 0.0f64;
        for a in 0..n {
            let cos_theta = (a as f32 + 0.5) / n as f32;
            let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
            for b in 0..2 * n {
                let phi = std::f32::consts::PI * (b as f32 + 0.5) / n as f32;
                let light = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
                sum += f64::from(get_sheen_brdf(&material, Vec3::Z, view, light).x * cos_theta);
            }
        }
        let integral = (sum * std::f64::consts::PI / (n * n) as f64) as f32;
        let table = get_sheen_albedo_entry((i * SHEEN_ALBEDO_SIZE + j) as usize);
        println!(
            "E(n.v {mu:.3}, roughness {roughness:.3}): table {table:.5}, quadrature {integral:.5}"
        );
        worst = worst.max((table - integral).abs());
        // Bilinear lookup at a node returns the node.
        assert!((get_sheen_albedo(i as f32 / 31.0, roughness) - table).abs() < 1e-6);
    }
    assert!(worst < 2e-3, "{worst}");
}
