//! A homogeneous medium (`glsl/medium.glsl`) and its phase function
//! (`glsl/phase_function.glsl`) on the GPU (`glsl/probe_medium.comp`) against their Rust
//! twins (`vkpath::cpu::medium`, `vkpath::cpu::phase_function`) on the same inputs: random
//! chromatic media (channels that neither absorb nor scatter among them), g at both ends,
//! 0, the isotropic branch's bound and at random, distances from 0 to NO_HIT_T, directions
//! at random, straight on and straight back. Every value within the relative tolerance
//! justified below, the sampled directions within a measured angle; then a χ² test of the
//! GPU's phase function samples against the CPU's density. The test prints its measured
//! maximum errors and asserts that the validation layer stayed silent.

use crate::common;

use glam::{Vec2, Vec3};
use vkpath::contract::NO_HIT_T;
use vkpath::cpu::phase_function::get_phase_function_density;
use vkpath::medium::Medium;
use vkpath::probe::inputs::InputRng;
use vkpath::probe::medium_probe::{MediumProbeInput, MediumProbeOutput, MediumProbeRunner};
use vkpath::stats::chi2::{chi2_direction_test, Chi2Config};
use vkpath::stats::sphere_histogram::{SphereFrame, TargetDensity};

/// Random cases of the twin test.
const CASE_COUNT: usize = 20_000;

/// Largest relative error of any value: 1e-4. Each is a few exp/log/sqrt/pow and divisions of
/// float arguments: exp(x) in Vulkan's bound of (3 + 2|x|) ulp, with |x| = sigma_t d <= 20
/// here (4 per unit, 5 units), is 43 ulp = 5e-6; the phase function divides by
/// (1 + g^2 - 2 g cos)^(3/2), which magnifies the cosine's error of a few ulp by up to
/// 3 g / (1 - g)^2 = 270 at g = 0.9 (3e-5). 1e-4 leaves a margin of 3 over the worst.
const RELATIVE_TOLERANCE: f64 = 1e-4;

/// Values below this are compared absolutely (exp's results near 0, a density of 0).
const ABSOLUTE_FLOOR: f64 = 1e-6;

/// Largest angle between the GPU's and the CPU's sampled directions: 1e-3 rad. Vulkan allows
/// sin and cos an absolute error of 2^-11 (5e-4) for arguments in [-pi, pi]; lavapipe's are far
/// better, which the printed maximum shows.
const ANGLE_TOLERANCE: f64 = 1e-3;

/// Vulkan's absolute error bound of log(x) for x in [0.5, 2]: 2^-21. The sampled distance
/// -log(1 - u_1) / sigma_t,c takes the log of a number near 1 for small u_1, whose relative
/// error is then unbounded (measured: 5e-4 at u_1 = 4e-5), so the distance is allowed 4 times
/// this bound divided by sigma_t,c besides the relative tolerance.
const LOG_ABSOLUTE_ERROR: f64 = 1.0 / (1u64 << 21) as f64;

/// The index of the sampled distance among `MediumProbeOutput::values`.
const DISTANCE_VALUE: usize = 3;

/// A random medium: each channel's coefficient 0 one time in five, else in [0, 2].
fn random_medium(rng: &mut InputRng) -> Medium {
    let mut coefficients = || {
        Vec3::from_array(std::array::from_fn(|_| {
            if rng.uniform() < 0.2 {
                0.0
            } else {
                rng.range(0.0, 2.0)
            }
        }))
    };
    let (absorption, scattering) = (coefficients(), coefficients());
    let anisotropy = match rng.next_u32() % 6 {
        0 => -0.9,
        1 => 0.0,
        2 => 0.0005,
        3 => 0.9,
        _ => rng.range(-0.95, 0.95),
    };
    Medium {
        absorption,
        scattering,
        anisotropy,
    }
}

fn cases(rng: &mut InputRng) -> Vec<MediumProbeInput> {
    (0..CASE_COUNT)
        .map(|_| {
            let medium = random_medium(rng);
            let distance = match rng.next_u32() % 8 {
                0 => 0.0,
                1 => NO_HIT_T,
                _ => rng.range(0.0, 5.0),
            };
            let view = rng.unit_vector();
            let direction = match rng.next_u32() % 6 {
                0 => -view,
                1 => view,
                _ => rng.unit_vector(),
            };
            let mut randoms = || Vec2::new(rng.uniform(), rng.uniform());
            let (distance_randoms, phase_randoms) = (randoms(), randoms());
            MediumProbeInput::new(
                &medium,
                distance,
                view,
                direction,
                distance_randoms,
                phase_randoms,
            )
        })
        .collect()
}

#[test]
fn the_medium_functions_match_their_twins() {
    let context = common::validated_context();
    let runner = MediumProbeRunner::new(&context).expect("medium probe");
    let inputs = cases(&mut InputRng::new(57));
    let outputs = runner.run(&inputs).expect("probe run");
    let mut worst = [0.0f64; 20];
    let mut worst_angle = 0.0f64;
    for (case, (input, gpu)) in inputs.iter().zip(&outputs).enumerate() {
        let cpu = MediumProbeOutput::cpu(input);
        for (k, (g, c)) in gpu.values().iter().zip(cpu.values()).enumerate() {
            // The sampled direction's components are compared as an angle below
            if (4..7).contains(&k) {
                continue;
            }
            let (g, c) = (f64::from(*g), f64::from(c));
            assert!(g.is_finite(), "case {case}, value {k}: GPU {g} ({input:?})");
            let mut error = (g - c).abs() / c.abs().max(ABSOLUTE_FLOOR);
            if k == DISTANCE_VALUE {
                let channel = ((input.random_numbers[0] * 3.0) as usize).min(2);
                let medium = input.medium();
                let sigma = f64::from((medium.absorption + medium.scattering)[channel]);
                let log_error = 4.0 * LOG_ABSOLUTE_ERROR / sigma.max(f64::MIN_POSITIVE);
                error = (error - log_error / c.abs().max(ABSOLUTE_FLOOR)).max(0.0);
            }
            worst[k] = worst[k].max(error);
            assert!(
                error <= RELATIVE_TOLERANCE,
                "case {case}, value {k}: GPU {g}, CPU {c} ({input:?})"
            );
        }
        let angle = f64::from(gpu.sampled().dot(cpu.sampled()).clamp(-1.0, 1.0)).acos();
        worst_angle = worst_angle.max(angle);
        assert!(
            angle <= ANGLE_TOLERANCE,
            "case {case}: sampled directions {angle} rad apart"
        );
    }
    println!("worst relative errors per value: {worst:?}; worst angle {worst_angle:.2e} rad");
    common::assert_validation_silent(&context);
}

/// The GPU's phase function samples (g = 0.7, a view off the axes, PCG2D numbers of a fixed
/// seed) against the CPU's density: χ² on Mitsuba's grid, 200 000 samples (40 per average
/// bin; sparse bins pooled below 5), alpha 1 %.
#[test]
fn gpu_phase_function_samples_follow_the_cpu_density() {
    let context = common::validated_context();
    let runner = MediumProbeRunner::new(&context).expect("medium probe");
    let medium = Medium {
        absorption: Vec3::ZERO,
        scattering: Vec3::ONE,
        anisotropy: 0.7,
    };
    let view = Vec3::new(-0.2, 0.6, 0.3).normalize();
    let mut rng = InputRng::new(611);
    let inputs: Vec<MediumProbeInput> = (0..200_000)
        .map(|_| {
            let phase = Vec2::new(rng.uniform(), rng.uniform());
            MediumProbeInput::new(&medium, 1.0, view, view, Vec2::ZERO, phase)
        })
        .collect();
    let outputs = runner.run(&inputs).expect("probe run");
    let density = |direction: Vec3| f64::from(get_phase_function_density(view, direction, 0.7));
    let result = chi2_direction_test(
        outputs.iter().map(MediumProbeOutput::sampled),
        TargetDensity::SolidAngle(&density),
        &SphereFrame::WORLD,
        &Chi2Config::default(),
    )
    .expect("chi2");
    println!("p = {:.4}, chi2 = {:.1}", result.p_value, result.statistic);
    assert!(result.passed, "{result:?}");
    common::assert_validation_silent(&context);
}
