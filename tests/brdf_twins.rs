//! The glTF BRDF of `glsl/brdf.glsl` on the GPU (`glsl/probe_brdf.comp`) against its Rust
//! twins (`vkpath::cpu::brdf`) on the same inputs: random materials (metallic 0, 1 or
//! between; roughness 0, 0.01, random or 1; specular 0, 1 or between; tinted specular
//! colours; ior in [1, 3]), random shading normals (both signs of normal.z, and the poles),
//! views and lights on both sides of the surface, at grazing angles, near the mirror
//! direction and opposite the view. Zero/non-zero decisions must agree except within
//! rounding of a boundary, values within tolerances measured and justified below, sampled
//! directions within a measured angle except near the lobe choice's boundary. Then χ² tests
//! of the GPU's `sample_brdf` against the CPU's `get_brdf_density`. Every test prints its
//! measured maximum errors and asserts that the validation layer stayed silent.

use crate::common;

use glam::{UVec2, Vec2, Vec3};
use vkpath::cpu::brdf::{
    get_base_material, get_brdf_density, get_ggx_alpha, get_ggx_distribution, get_smith_visibility,
    MaterialSample,
};
use vkpath::cpu::shading_basis::get_shading_basis;
use vkpath::probe::brdf_probe::{BrdfProbeInput, BrdfProbeOutput, BrdfProbeRunner};
use vkpath::probe::inputs::{self, InputRng};
use vkpath::stats::chi2::{chi2_direction_test, Chi2Config};
use vkpath::stats::sphere_histogram::{SphereFrame, TargetDensity};

/// Random cases of the twin test.
const CASE_COUNT: usize = 100_000;

/// A random material: each parameter from its corner values or at random.
fn random_material(rng: &mut InputRng) -> MaterialSample {
    let mut pick = |values: &[f32]| {
        let index = (rng.next_u32() as usize) % (values.len() + 1);
        values.get(index).copied()
    };
    let metallic = pick(&[0.0, 1.0]);
    let roughness = pick(&[0.0, 0.01, 1.0]);
    let specular = pick(&[0.0, 1.0]);
    // Black one time in ten: the lobe choice's other corner (no diffuse energy).
    let black = rng.uniform() < 0.1;
    // Arguments in the order the fields were drawn in before, so that the cases stay the same.
    get_base_material(
        if black {
            Vec3::ZERO
        } else {
            rng.in_box(Vec3::ZERO, Vec3::ONE)
        },
        metallic.unwrap_or_else(|| rng.uniform()),
        roughness.unwrap_or_else(|| rng.uniform()),
        specular.unwrap_or_else(|| rng.uniform()),
        rng.in_box(Vec3::ZERO, Vec3::splat(2.0)),
        rng.range(1.0, 3.0),
    )
}

/// A random unit normal: mostly uniform on the sphere, sometimes a pole or next to one
/// (the shading basis branches on the sign of z and divides by 1 + |z|).
fn random_normal(rng: &mut InputRng) -> Vec3 {
    match rng.next_u32() % 10 {
        0 => Vec3::Z,
        1 => -Vec3::Z,
        2 => Vec3::new(rng.range(-1e-3, 1e-3), rng.range(-1e-3, 1e-3), -1.0).normalize(),
        3 => Vec3::new(rng.range(-1e-3, 1e-3), rng.range(-1e-3, 1e-3), 1.0).normalize(),
        _ => rng.unit_vector(),
    }
}

/// A direction relative to `normal`: above it three times in four, at a grazing angle
/// (within 1e-3 of the horizon, on either side) one time in ten.
fn random_direction(rng: &mut InputRng, normal: Vec3) -> Vec3 {
    let direction = rng.unit_vector();
    let choice = rng.uniform();
    if choice < 0.1 {
        let tangent = (direction - direction.dot(normal) * normal)
            .normalize_or(normal.any_orthonormal_vector());
        (tangent + rng.range(-1e-3, 1e-3) * normal).normalize()
    } else if choice < 0.75 {
        direction * direction.dot(normal).signum()
    } else {
        -direction * direction.dot(normal).signum()
    }
}

/// The twin test's inputs. The light is random, or near the view's mirror direction
/// (where narrow GGX lobes peak), or exactly the view or its opposite; the random numbers
/// are uniform, sometimes 0.
fn twin_cases(rng: &mut InputRng, count: usize) -> Vec<BrdfProbeInput> {
    (0..count)
        .map(|_| {
            let material = random_material(rng);
            let normal = random_normal(rng);
            let view = random_direction(rng, normal);
            let light = match rng.next_u32() % 16 {
                0..=3 => {
                    let mirror = 2.0 * view.dot(normal) * normal - view;
                    let spread = [1e-4, 1e-3, 1e-2, 1e-1][(rng.next_u32() % 4) as usize];
                    (mirror + spread * rng.unit_vector()).normalize()
                }
                4 => view,
                5 => -view,
                _ => random_direction(rng, normal),
            };
            let mut random_numbers = Vec2::new(rng.uniform(), rng.uniform());
            if rng.next_u32().is_multiple_of(32) {
                random_numbers.x = 0.0;
            }
            if rng.next_u32().is_multiple_of(32) {
                random_numbers.y = 0.0;
            }
            BrdfProbeInput::new(&material, random_numbers, normal, view, light)
        })
        .collect()
}

/// The largest error seen so far and the case it came from.
#[derive(Default, Debug)]
struct Worst {
    error: f64,
    case: usize,
}

impl Worst {
    fn add(&mut self, error: f64, case: usize) {
        if error > self.error || error.is_nan() {
            *self = Worst { error, case };
        }
    }
}

/// The angle between two directions, in radians (f64, accurate also for tiny angles).
fn angle(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.as_dvec3().normalize(), b.as_dvec3().normalize());
    2.0 * ((a - b).length() / 2.0).min(1.0).asin()
}

/// 2^-23, the ulp of 1.
const ULP: f64 = f32::EPSILON as f64;

/// How rounding errors of the inputs of `get_brdf` and `get_brdf_density` grow for the
/// direction pair (view, light): the half vector normalize(v + l) carries an angle error of
/// about ULP / |v + l|, and GGX's D(h) changes by a relative 4 |h_xy| dh / (alpha^2 s)
/// (s = |h_xy|^2 / alpha^2 + h_z^2), at most 2 dh / alpha. So the relative error of the
/// specular terms is about ULP (1 + 2 / (alpha |v + l|)): for alpha = 1e-4 near the mirror
/// direction a rounding of h alone moves D by 1e-3 relative, and at grazing angles, where
/// |v + l| is small, by more; no f32 implementation can do better there.
fn condition(input: &BrdfProbeInput, light: Vec3) -> f64 {
    let alpha = f64::from(get_ggx_alpha(input.material().roughness));
    // Roughness 0: a delta lobe, no GGX term at all (D is exactly 0)
    if alpha == 0.0 {
        return 1.0;
    }
    let sum = (input.view().as_dvec3() + light.as_dvec3()).length();
    1.0 + 2.0 / (alpha * sum)
}

/// The absolute size of the BRDF's terms before Fresnel and the metallic mix weigh them:
/// D V + max(base colour) / pi. Schlick's weight 1 - |v.h| has an absolute error of an ulp
/// (it even goes to -1e-7 where rounding makes |v.h| > 1), and mix() may be computed as
/// x + (y - x) a, whose error is an ulp of the larger lobe: both are absolute errors of
/// about ULP times this.
fn brdf_term_scale(input: &BrdfProbeInput) -> f64 {
    let material = input.material();
    let (normal, view, light) = (input.normal(), input.view(), input.light());
    let (normal_dot_view, normal_dot_light) = (normal.dot(view), normal.dot(light));
    if normal_dot_view <= 0.0 || normal_dot_light <= 0.0 {
        return 0.0;
    }
    let basis = get_shading_basis(normal);
    let local_half = (basis.transpose() * (view + light)).normalize();
    let alpha = get_ggx_alpha(material.roughness);
    let specular = get_ggx_distribution(alpha, local_half)
        * get_smith_visibility(alpha, normal_dot_view, normal_dot_light);
    f64::from(specular) + f64::from(material.base_color.max_element()) / std::f64::consts::PI
}

/// An error in units of ULP times (|cpu| times the condition) plus an absolute scale.
fn error_units(gpu: f32, cpu: f32, condition: f64, absolute_scale: f64) -> f64 {
    let difference = (f64::from(gpu) - f64::from(cpu)).abs();
    if difference == 0.0 {
        return 0.0;
    }
    difference / (ULP * (f64::from(cpu).abs() * condition + absolute_scale))
}

/// The condition of `get_dielectric_fresnel(cos_theta_i, eta)`: 1 + 1 / cos_t, with cos_t the
/// refracted direction's cosine (in f64; 1e-6 at and beyond the critical angle, where the
/// reflectance is 1 and its rounding near the angle is the square root's).
fn fresnel_condition(cos_theta_i: f32, eta: f32) -> f64 {
    let (mut cos_i, mut eta) = (f64::from(cos_theta_i).clamp(-1.0, 1.0), f64::from(eta));
    if cos_i < 0.0 {
        cos_i = -cos_i;
        eta = 1.0 / eta;
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    1.0 + 1.0 / (1.0 - sin2_t).max(1e-12).sqrt()
}

/// Beyond this first-order relative error (ULP times the condition), a comparison of
/// values says nothing: the half vector's rounding alone moves it across a narrow lobe. Such
/// cases (alpha = 1e-4 with |v + l| < 0.24, i.e. roughness 0 and 0.01 away from normal
/// incidence; 9.3% of the random cases) are counted and only their decisions compared.
const ILL_CONDITIONED: f64 = 0.01;

/// Largest error of `get_brdf`, `get_brdf_density` and `get_specular_probability` in the
/// units of `error_units` (ULP (|cpu| condition + absolute scale)). Each is a few dozen
/// roundings of which a handful matter to first order; the GPU's sqrt, division and
/// normalize() may be off by up to 3 ulps each (Vulkan's precision table), and mix()'s
/// form is free. Measured on lavapipe: 1.58 (brdf), 1.22 (density), 2.74 (specular
/// probability), 1.72 (density at the sample); 8 leaves room for a driver with coarser sqrt or division.
const VALUE_UNITS: f64 = 8.0;

/// Largest angle (rad) between the GPU's and the CPU's directions of
/// `sample_ggx_visible_normal` for any random numbers. At u_1 = 0 the spherical cap's
/// z = (1 - u_1) (1 + v_z) - v_z rounds to within 2 ulps of 1 instead of exactly 1, and
/// sin_theta = sqrt(1 - z^2) turns that into up to sqrt(2 * 2^-22) = 6.9e-4 rad; un-stretching
/// by alpha <= 1 only shrinks it. Measured on lavapipe: 4.2e-4 (at u_1 = 0).
const VISIBLE_NORMAL_ANGLE: f64 = 6.9e-4;
/// The same for `sample_brdf`'s light directions: the reflection doubles the half vector's
/// angle error (the diffuse lobe's errors are ulps). Measured on lavapipe: 7.1e-4.
const SAMPLED_ANGLE: f64 = 1.4e-3;
/// Both angles for u_1 in (1e-3, 0.999), away from the cap's pole (above) and from its
/// rim, where the stretched half vector cap + v can get short. Measured on lavapipe: 5.4e-6
/// (visible normal), 1.1e-5 (sampled light); about 100 ulps.
const INTERIOR_ANGLE: f64 = 5.0e-5;

/// Cases whose u_0 is within this of the specular probability may choose the other lobe
/// on the GPU (the probabilities differ by ulps); they are counted and skipped. The
/// diffuse lobe's u = (u_0 - p) / (1 - p) is also ill-conditioned right above p.
const LOBE_BOUNDARY: f32 = 1e-5;
/// At most this fraction of the cases may be skipped as near the lobe boundary (mostly
/// u_0 = 0 with p = 0). Measured: 241 of 100 000.
const MAX_LOBE_BOUNDARY_FRACTION: f64 = 0.01;

/// Directions within this (cosine) of a horizon may be decided differently (zero or not).
const HORIZON: f32 = 1e-6;
/// At most this many of those flips. Measured: 0.
const MAX_FLIPS: usize = 100;

#[test]
fn brdf_matches_its_twins_on_random_cases() {
    let context = common::validated_context();
    let cases = twin_cases(&mut InputRng::new(0xb4df), CASE_COUNT);
    let runner = BrdfProbeRunner::new(&context).expect("BRDF probe runner");
    let gpu = runner.run(&cases).expect("BRDF probe run");
    assert_eq!(gpu.len(), cases.len());
    let mut brdf = Worst::default();
    let mut density = Worst::default();
    let mut probability = Worst::default();
    let mut sampled = Worst::default();
    let mut sampled_interior = Worst::default();
    let mut sampled_density = Worst::default();
    let mut visible_normal = Worst::default();
    let mut visible_normal_interior = Worst::default();
    let mut mirror_probability = Worst::default();
    let mut mirror_weight = Worst::default();
    let mut fresnel = Worst::default();
    let mut smooth_cases = 0usize;
    let mut flips = [0usize; 3];
    let (mut near_lobe_boundary, mut ill_conditioned) = (0, 0);
    for (index, (input, gpu)) in cases.iter().zip(&gpu).enumerate() {
        let cpu = BrdfProbeOutput::cpu(input);
        let (normal, view, light) = (input.normal(), input.view(), input.light());
        let kappa = condition(input, light);
        let well_conditioned = ULP * kappa <= ILL_CONDITIONED;
        ill_conditioned += usize::from(!well_conditioned);
        let horizon = normal.dot(view).abs().min(normal.dot(light).abs());

        // get_brdf and get_brdf_density at the input's light.
        let flipped = (gpu.brdf() == Vec3::ZERO) != (cpu.brdf() == Vec3::ZERO);
        if flipped && horizon < HORIZON {
            flips[0] += 1;
        } else if flipped || well_conditioned {
            let scale = brdf_term_scale(input);
            let error = (0..3)
                .map(|i| error_units(gpu.brdf()[i], cpu.brdf()[i], kappa, scale))
                .fold(0.0, f64::max);
            brdf.add(error, index);
        }
        let flipped = (gpu.density() == 0.0) != (cpu.density() == 0.0);
        if flipped && horizon < HORIZON {
            flips[1] += 1;
        } else if flipped || well_conditioned {
            let diffuse_scale = 1.0 / std::f64::consts::PI;
            density.add(
                error_units(gpu.density(), cpu.density(), kappa, diffuse_scale),
                index,
            );
        }
        let (gpu_p, cpu_p) = (gpu.specular_probability(), cpu.specular_probability());
        probability.add(error_units(gpu_p, cpu_p, 1.0, 0.0), index);
        // The Fresnel room at n.v (either side): Schlick's terms are well conditioned; the
        // exact dielectric's moves by about ULP / cos_t near the critical angle (cos_t is the
        // square root of 1 - sin^2), hence its condition 1 + 1 / cos_t.
        let (gpu_f, cpu_f) = (gpu.fresnel_terms(), cpu.fresnel_terms());
        let exact_condition = fresnel_condition(normal.dot(view), input.material().ior);
        let error = (0..7)
            .map(|i| {
                let condition = if i == 6 { exact_condition } else { 1.0 };
                error_units(gpu_f[i], cpu_f[i], condition, 1.0)
            })
            .fold(0.0, f64::max);
        fresnel.add(error, index);
        // get_brdf_mirror_probability and get_brdf_mirror_weight: a mirror pick exactly where
        // the roughness is 0 (views above the normal: their contract)
        if normal.dot(view) > 0.0 {
            let smooth = input.material().roughness == 0.0;
            assert_eq!(
                (
                    gpu.mirror_probability() > 0.0,
                    cpu.mirror_probability() > 0.0
                ),
                (smooth && cpu_p > 0.0, smooth && cpu_p > 0.0),
                "case {index}: {input:?}"
            );
            mirror_probability.add(
                error_units(gpu.mirror_probability(), cpu.mirror_probability(), 1.0, 0.0),
                index,
            );
            // F / p: Schlick's and the probability's few ulps each, relative to the weight
            let error = (0..3)
                .map(|i| {
                    let scale = f64::from(cpu.mirror_weight()[i].abs());
                    error_units(gpu.mirror_weight()[i], cpu.mirror_weight()[i], 1.0, scale)
                })
                .fold(0.0, f64::max);
            mirror_weight.add(error, index);
            smooth_cases += usize::from(smooth);
        }

        // sample_ggx_visible_normal (any view: the kernel mirrors it above the surface).
        let random_numbers = input.random_numbers();
        let interior = random_numbers.y > 1e-3 && random_numbers.y < 0.999;
        let half_angle = angle(gpu.visible_normal(), cpu.visible_normal());
        visible_normal.add(half_angle, index);
        if interior {
            visible_normal_interior.add(half_angle, index);
        }

        // sample_brdf and the density there, for views above the surface (its contract).
        if normal.dot(view) <= 0.0 {
            continue;
        }
        if (random_numbers.x - cpu_p).abs() < LOBE_BOUNDARY {
            near_lobe_boundary += 1;
            continue;
        }
        let light_angle = angle(gpu.sampled(), cpu.sampled());
        sampled.add(light_angle, index);
        if interior {
            sampled_interior.add(light_angle, index);
        }
        let (gpu_density, cpu_density) = (gpu.sampled_density(), cpu.sampled_density());
        let cosine = f64::from(normal.dot(cpu.sampled()).abs());
        let flipped = (gpu_density == 0.0) != (cpu_density == 0.0);
        let kappa = condition(input, cpu.sampled());
        if flipped && cosine < f64::from(HORIZON) {
            flips[2] += 1;
        } else if flipped || ULP * kappa <= ILL_CONDITIONED {
            // The GPU evaluates the density at its own direction: to first order the
            // density moves by the angle times the condition (GGX) or 1 / cos (diffuse).
            let cpu_density = f64::from(cpu_density);
            let moved = light_angle * (kappa + 1.0 / cosine) * cpu_density;
            let allowed = ULP * (kappa * cpu_density + 1.0 / std::f64::consts::PI) + moved;
            let difference = (f64::from(gpu_density) - cpu_density).abs();
            sampled_density.add(difference / allowed, index);
        }
    }
    let report = |name: &str, worst: &Worst| {
        println!("{name}: max {:.3e} (case {})", worst.error, worst.case);
        if worst.error > 0.0 {
            println!(
                "    input {:?}\n    GPU {:?}\n    CPU {:?}",
                cases[worst.case],
                gpu[worst.case],
                BrdfProbeOutput::cpu(&cases[worst.case])
            );
        }
    };
    report("get_brdf, error units", &brdf);
    report("get_brdf_density, error units", &density);
    report("get_specular_probability, error units", &probability);
    report(
        "get_brdf_mirror_probability, error units",
        &mirror_probability,
    );
    report("get_brdf_mirror_weight, error units", &mirror_weight);
    report(
        "the Fresnel room (glsl/fresnel.glsl) at n.v, error units",
        &fresnel,
    );
    println!("{smooth_cases} cases of roughness 0 above the normal");
    assert!(smooth_cases > CASE_COUNT / 20, "{smooth_cases}");
    report("sample_ggx_visible_normal, angle (rad)", &visible_normal);
    report(
        "sample_ggx_visible_normal for u_1 in (1e-3, 0.999), angle (rad)",
        &visible_normal_interior,
    );
    report("sample_brdf, angle (rad)", &sampled);
    report(
        "sample_brdf for u_1 in (1e-3, 0.999), angle (rad)",
        &sampled_interior,
    );
    report(
        "get_brdf_density at the sample, error / first-order bound",
        &sampled_density,
    );
    println!(
        "{} cases: {ill_conditioned} ill-conditioned (decisions only), {near_lobe_boundary} \
         near the lobe boundary (skipped), horizon flips (brdf, density, sampled density) {flips:?}",
        cases.len()
    );
    for (name, worst) in [
        ("brdf", &brdf),
        ("density", &density),
        ("specular probability", &probability),
        ("mirror probability", &mirror_probability),
        ("mirror weight", &mirror_weight),
        ("Fresnel room", &fresnel),
        ("sampled density", &sampled_density),
    ] {
        assert!(
            worst.error <= VALUE_UNITS,
            "{name}: {worst:?}: {:?}",
            cases[worst.case]
        );
    }
    assert!(
        visible_normal.error <= VISIBLE_NORMAL_ANGLE,
        "{visible_normal:?}"
    );
    assert!(sampled.error <= SAMPLED_ANGLE, "{sampled:?}");
    assert!(
        visible_normal_interior.error <= INTERIOR_ANGLE,
        "{visible_normal_interior:?}"
    );
    assert!(
        sampled_interior.error <= INTERIOR_ANGLE,
        "{sampled_interior:?}"
    );
    assert!((near_lobe_boundary as f64) <= MAX_LOBE_BOUNDARY_FRACTION * cases.len() as f64);
    assert!(flips.iter().sum::<usize>() <= MAX_FLIPS, "{flips:?}");
    common::assert_validation_silent(&context);
}

/// 10^6 samples: about 200 per bin of Mitsuba's 5050 (the sampler tests' choice).
const SAMPLE_COUNT: usize = 1_000_000;

/// The GPU's `sample_brdf` follows the CPU's `get_brdf_density` (χ², Šidák-corrected over the
/// three materials): a dielectric of roughness 0.3, a metal of roughness 0.5, and a half
/// metal with a tinted specular layer on a tilted normal (the shading basis's other branch).
/// Measured on lavapipe: p = 0.71, 0.98, 0.96 (significance 3.3e-3 each).
#[test]
fn gpu_sample_brdf_follows_get_brdf_density() {
    let context = common::validated_context();
    let runner = BrdfProbeRunner::new(&context).expect("BRDF probe runner");
    let mut mixed = MaterialSample::gltf(Vec3::new(0.8, 0.3, 0.1), 0.5, 0.4);
    mixed.specular = 0.7;
    mixed.specular_color = Vec3::new(1.0, 0.5, 2.0);
    mixed.ior = 2.2;
    let tilted = Vec3::new(0.3, -0.5, -0.8).normalize();
    let cases = [
        (
            "dielectric, roughness 0.3, 60 degrees",
            MaterialSample::gltf(Vec3::new(0.2, 0.6, 0.9), 0.0, 0.3),
            Vec3::Z,
            60.0_f32,
        ),
        (
            "metal, roughness 0.5, 30 degrees",
            MaterialSample::gltf(Vec3::new(0.95, 0.64, 0.54), 1.0, 0.5),
            Vec3::Z,
            30.0,
        ),
        (
            "half metal, tinted specular, tilted normal, 45 degrees",
            mixed,
            tilted,
            45.0,
        ),
    ];
    let config = Chi2Config {
        test_count: cases.len(),
        ..Chi2Config::default()
    };
    for (index, (name, material, normal, degrees)) in cases.into_iter().enumerate() {
        // The view `degrees` from the normal, in the plane of the normal and a tangent.
        let tangent = normal.any_orthonormal_vector();
        let theta = degrees.to_radians();
        let view = theta.cos() * normal + theta.sin() * tangent;
        let numbers = inputs::pcg_random_numbers(UVec2::new(0xb4d5, index as u32), SAMPLE_COUNT);
        let probe_inputs: Vec<BrdfProbeInput> = numbers
            .iter()
            .map(|&u| BrdfProbeInput::new(&material, u, normal, view, view))
            .collect();
        let directions: Vec<Vec3> = runner
            .run(&probe_inputs)
            .expect("BRDF probe run")
            .iter()
            .map(BrdfProbeOutput::sampled)
            .collect();
        let density = |light: Vec3| f64::from(get_brdf_density(&material, normal, view, light));
        let result = chi2_direction_test(
            directions,
            TargetDensity::SolidAngle(&density),
            &SphereFrame::WORLD,
            &config,
        )
        .expect("χ² test");
        println!(
            "GPU sample_brdf, {name}: chi2 = {:.1}, dof = {}, p = {:.4}, significance = {:.4e}, \
             pooled bins = {}, impossible = {}, invalid = {}",
            result.statistic,
            result.degrees_of_freedom,
            result.p_value,
            result.significance,
            result.pooled_bin_count,
            result.impossible_sample_count,
            result.invalid_sample_count
        );
        assert!(result.passed, "{name}: {result:?}");
    }
    common::assert_validation_silent(&context);
}

/// The χ² test above has teeth on GPU output: the metal's samples at roughness 0.5 fail
/// against the density of roughness 0.45 (a lobe 10% narrower in perceptual roughness).
#[test]
fn gpu_sample_brdf_fails_against_a_slightly_different_roughness() {
    let context = common::validated_context();
    let runner = BrdfProbeRunner::new(&context).expect("BRDF probe runner");
    let material = MaterialSample::gltf(Vec3::new(0.95, 0.64, 0.54), 1.0, 0.5);
    let wrong = MaterialSample {
        roughness: 0.45,
        ..material
    };
    let view = Vec3::new(0.5, 0.0, 0.75_f32.sqrt());
    let numbers = inputs::pcg_random_numbers(UVec2::new(0xb4d5, 99), SAMPLE_COUNT);
    let probe_inputs: Vec<BrdfProbeInput> = numbers
        .iter()
        .map(|&u| BrdfProbeInput::new(&material, u, Vec3::Z, view, view))
        .collect();
    let directions: Vec<Vec3> = runner
        .run(&probe_inputs)
        .expect("BRDF probe run")
        .iter()
        .map(BrdfProbeOutput::sampled)
        .collect();
    let density = |light: Vec3| f64::from(get_brdf_density(&wrong, Vec3::Z, view, light));
    let result = chi2_direction_test(
        directions,
        TargetDensity::SolidAngle(&density),
        &SphereFrame::WORLD,
        &Chi2Config::default(),
    )
    .expect("χ² test");
    println!(
        "GPU sample_brdf at roughness 0.5 against the density of 0.45: chi2 = {:.1}, dof = {}, p = {:.3e}",
        result.statistic, result.degrees_of_freedom, result.p_value
    );
    assert!(
        !result.passed,
        "a 10% roughness error must fail: {result:?}"
    );
    common::assert_validation_silent(&context);
}
