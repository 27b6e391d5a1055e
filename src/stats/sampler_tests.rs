//! χ² tests of the workshop's direction samplers (the CPU twins, driven by the twin of
//! PCG2D), and of the test itself: samplers that are known to be wrong must fail.

use glam::{UVec2, Vec2, Vec3};

use crate::cpu::camera::get_sample_seed;
use crate::cpu::workshop::{
    get_random_numbers, sample_hemisphere, sample_sphere, sample_sphere_spherical_coordinates,
};
use crate::stats::chi2::{chi2_direction_test, Chi2Config, Chi2Result};
use crate::stats::sphere_histogram::{SphereFrame, TargetDensity};

/// 10^6 samples put about 200 into each of Mitsuba's 5050 bins (400 on a hemisphere): the
/// χ² approximation is excellent, and a density error of a few percent over a region of
/// some bins is far beyond the noise. Cheap at opt-level 2.
const SAMPLE_COUNT: usize = 1_000_000;

/// `count` directions from `sampler` with a sequential PCG2D stream from `seed`.
fn sample_stream(
    seed: UVec2,
    count: usize,
    sampler: impl Fn(Vec2) -> Vec3,
) -> impl Iterator<Item = Vec3> {
    let mut state = seed;
    (0..count).map(move |_| sampler(get_random_numbers(&mut state)))
}

fn report(label: &str, result: &Chi2Result) {
    println!(
        "{label}: chi2 = {:.1}, dof = {}, p = {:.4e}, significance = {:.4e}, pooled bins = {}, impossible = {}, invalid = {}, passed = {}",
        result.statistic,
        result.degrees_of_freedom,
        result.p_value,
        result.significance,
        result.pooled_bin_count,
        result.impossible_sample_count,
        result.invalid_sample_count,
        result.passed
    );
}

#[test]
fn sample_sphere_passes() {
    let config = Chi2Config::default();
    let samples = sample_stream(
        UVec2::new(0x1234_5678, 0x9abc_def0),
        SAMPLE_COUNT,
        sample_sphere,
    );
    let result = chi2_direction_test(
        samples,
        TargetDensity::UniformSphere,
        &SphereFrame::WORLD,
        &config,
    )
    .unwrap();
    report("sample_sphere, sequential PCG2D", &result);
    assert!(result.passed, "{result:?}");
}

#[test]
fn sample_sphere_passes_with_per_pixel_seeds() {
    // As the renderer uses PCG2D: the first pair of random numbers of each of 1000 x 1000
    // pixels, seeded by get_sample_seed, i.e. PCG2D as a hash of neighbouring seeds.
    let config = Chi2Config::default();
    let samples = (0..1000u32).flat_map(|y| {
        (0..1000u32).map(move |x| {
            let mut seed = get_sample_seed(UVec2::new(x, y), 0, 0);
            sample_sphere(get_random_numbers(&mut seed))
        })
    });
    let result = chi2_direction_test(
        samples,
        TargetDensity::UniformSphere,
        &SphereFrame::WORLD,
        &config,
    )
    .unwrap();
    report("sample_sphere, per-pixel seeds", &result);
    assert!(result.passed, "{result:?}");
}

/// +Z, -X and an oblique unit vector.
fn test_normals() -> [Vec3; 3] {
    [Vec3::Z, -Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()]
}

#[test]
fn sample_hemisphere_passes_for_several_normals() {
    let normals = test_normals();
    // Šidák over the normals: 1% for the family of three tests.
    let config = Chi2Config {
        test_count: normals.len(),
        ..Chi2Config::default()
    };
    for (index, normal) in normals.into_iter().enumerate() {
        let frame = SphereFrame::from_normal(normal).unwrap();
        let samples = sample_stream(UVec2::new(42, index as u32), SAMPLE_COUNT, |random| {
            sample_hemisphere(random, normal)
        });
        let result =
            chi2_direction_test(samples, TargetDensity::UniformHemisphere, &frame, &config)
                .unwrap();
        report(&format!("sample_hemisphere around {normal}"), &result);
        assert!(result.passed, "{normal}: {result:?}");
    }
}

#[test]
fn naive_spherical_coordinates_fail() {
    // theta = pi u_1 crowds the poles: density 1 / (2 pi^2 sin theta) instead of 1 / (4 pi).
    let config = Chi2Config::default();
    let samples = sample_stream(
        UVec2::new(7, 7),
        SAMPLE_COUNT,
        sample_sphere_spherical_coordinates,
    );
    let result = chi2_direction_test(
        samples,
        TargetDensity::UniformSphere,
        &SphereFrame::WORLD,
        &config,
    )
    .unwrap();
    report("sample_sphere_spherical_coordinates (must fail)", &result);
    assert!(!result.passed);
    // Not a near miss: the p-value underflows to (almost) nothing.
    assert!(result.p_value < 1e-100, "{result:?}");
    // It does follow its own density, theta uniform in [0, pi] (how `vkpath check` names
    // the mistake).
    let samples = sample_stream(
        UVec2::new(7, 7),
        SAMPLE_COUNT,
        sample_sphere_spherical_coordinates,
    );
    let result = chi2_direction_test(
        samples,
        TargetDensity::UniformTheta {
            theta_max: std::f64::consts::PI,
        },
        &SphereFrame::WORLD,
        &config,
    )
    .unwrap();
    report(
        "sample_sphere_spherical_coordinates against its own density",
        &result,
    );
    assert!(result.passed, "{result:?}");
}

#[test]
fn hemisphere_without_mirroring_fails() {
    // Plain sphere samples judged as hemisphere samples: half of them land below.
    let config = Chi2Config::default();
    let frame = SphereFrame::from_normal(Vec3::Z).unwrap();
    let samples = sample_stream(UVec2::new(3, 4), SAMPLE_COUNT, sample_sphere);
    let result =
        chi2_direction_test(samples, TargetDensity::UniformHemisphere, &frame, &config).unwrap();
    report("sample_sphere judged as hemisphere (must fail)", &result);
    assert!(!result.passed && result.p_value == 0.0);
    // Bins below the equator bin expect nothing, so about half the samples are impossible.
    assert!(result.impossible_sample_count > 450_000, "{result:?}");
}

/// A cosine-weighted hemisphere sampler around +z (Malley's method: uniform disk, projected
/// up), density cos(theta) / pi w.r.t. solid angle. Not in the workshop; it exercises the
/// generic density path with a non-constant density.
fn sample_cosine_hemisphere(random_numbers: Vec2) -> Vec3 {
    let radius = random_numbers.x.sqrt();
    let phi = std::f32::consts::TAU * random_numbers.y;
    let x = radius * phi.cos();
    let y = radius * phi.sin();
    Vec3::new(x, y, (1.0 - x * x - y * y).max(0.0).sqrt())
}

#[test]
fn generic_density_path_accepts_cosine_and_rejects_uniform() {
    let config = Chi2Config::default();
    let cosine_density = |direction: Vec3| (direction.z as f64).max(0.0) / std::f64::consts::PI;
    let samples = sample_stream(UVec2::new(11, 13), SAMPLE_COUNT, sample_cosine_hemisphere);
    let result = chi2_direction_test(
        samples,
        TargetDensity::SolidAngle(&cosine_density),
        &SphereFrame::WORLD,
        &config,
    )
    .unwrap();
    report(
        "cosine-weighted sampler vs cos / pi (generic quadrature)",
        &result,
    );
    assert!(result.passed, "{result:?}");
    // The uniform hemisphere sampler is not cosine-weighted.
    let samples = sample_stream(UVec2::new(11, 13), SAMPLE_COUNT, |random| {
        sample_hemisphere(random, Vec3::Z)
    });
    let result = chi2_direction_test(
        samples,
        TargetDensity::SolidAngle(&cosine_density),
        &SphereFrame::WORLD,
        &config,
    )
    .unwrap();
    report("uniform hemisphere vs cos / pi (must fail)", &result);
    assert!(!result.passed);
}
