//! The samplers, judged by what they must do and never by equality: 10^6 directions from
//! the user's `sample_sphere` or `sample_hemisphere` on the GPU, binned on the sphere and
//! tested against the uniform density with Pearson's χ² (`crate::stats::chi2`). A correct
//! sampler written differently (z = 1 - 2 u, another phi mapping, flipping instead of
//! mirroring) passes; a wrong density, directions that are not unit vectors, or directions
//! below the hemisphere fail.

use glam::{UVec2, Vec2, Vec3};

use crate::check::detect::WorkshopFunction;
use crate::check::report::FunctionReport;
use crate::check::Session;
use crate::error::{Error, Result};
use crate::probe::inputs;
use crate::probe::{DirectionOutput, ProbeKind};
use crate::stats::chi2::{chi2_direction_test, Chi2Config, Chi2Result};
use crate::stats::sphere_histogram::{SphereFrame, TargetDensity, UNIT_LENGTH_TOLERANCE};

/// 10^6 samples put about 200 into each of Mitsuba's 5050 bins (400 on a hemisphere): the
/// χ² approximation is excellent, and a density error of a few percent over some bins is far
/// beyond the noise. One dispatch on the GPU, about a tenth of a second of binning.
pub const SAMPLE_COUNT: usize = 1_000_000;

/// The normals around which `sample_hemisphere` is tested: +z, -x and an oblique one, so
/// that a sampler that only works for +z fails.
pub fn hemisphere_normals() -> [Vec3; 3] {
    [Vec3::Z, -Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()]
}

/// How many χ² tests `check_sampler` runs for `function` (for the Šidák correction).
pub fn test_count(function: WorkshopFunction) -> usize {
    match function {
        WorkshopFunction::SampleSphere => 1,
        WorkshopFunction::SampleHemisphere => hemisphere_normals().len(),
        _ => 0,
    }
}

/// χ² tests of the user's `sample_sphere` (uniform on the sphere) or `sample_hemisphere`
/// (uniform on the hemisphere around each of `hemisphere_normals`), each at the session's
/// per-test significance level.
pub fn check_sampler(session: &Session, function: WorkshopFunction) -> Result<FunctionReport> {
    let (kind, normals, target) = match function {
        WorkshopFunction::SampleSphere => (
            ProbeKind::SampleSphere,
            vec![Vec3::Z],
            TargetDensity::UniformSphere,
        ),
        WorkshopFunction::SampleHemisphere => (
            ProbeKind::SampleHemisphere,
            hemisphere_normals().to_vec(),
            TargetDensity::UniformHemisphere,
        ),
        _ => {
            return Err(Error::InvalidSettings(format!(
                "{} is not a sampler",
                function.name()
            )))
        }
    };
    let mut report =
        FunctionReport::new(
            function.name(),
            session.user.line_of(function),
            "chi-square",
            format!(
            "Pearson's χ² test of {SAMPLE_COUNT} directions against the uniform density on the {} \
             (50 x 101 equal-area bins), each test at significance {:.2e} (Šidák: {} family-wise \
             over all statistical tests of this check); every direction must be a unit vector \
             (length within {UNIT_LENGTH_TOLERANCE} of 1){}",
            if kind == ProbeKind::SampleSphere { "sphere" } else { "hemisphere around the normal" },
            session.test_alpha,
            session.options.alpha,
            if kind == ProbeKind::SampleHemisphere {
                " on the normal's side"
            } else {
                ""
            },
        ),
        );
    let pipeline = session.user_probe(kind)?;
    let config = Chi2Config {
        alpha: session.test_alpha,
        ..Chi2Config::default()
    };
    let mut min_p = 1.0f64;
    for (index, normal) in normals.into_iter().enumerate() {
        let numbers = inputs::pcg_random_numbers(UVec2::new(2024, index as u32), SAMPLE_COUNT);
        let probe_inputs = inputs::sampler_inputs(&numbers, normal);
        let outputs: Vec<DirectionOutput> = session.runner.run(&pipeline, &probe_inputs)?;
        let directions: Vec<Vec3> = outputs.iter().map(DirectionOutput::direction).collect();
        let frame = if kind == ProbeKind::SampleSphere {
            SphereFrame::WORLD
        } else {
            SphereFrame::from_normal(normal).map_err(|e| Error::InvalidSettings(e.to_string()))?
        };
        let result = chi2_direction_test(directions.iter().copied(), target, &frame, &config)
            .map_err(|e| Error::InvalidSettings(e.to_string()))?;
        let label = if kind == ProbeKind::SampleHemisphere {
            format!("normal_{index}_")
        } else {
            String::new()
        };
        report.measure(&format!("{label}chi2"), result.statistic);
        report.measure(
            &format!("{label}degrees_of_freedom"),
            result.degrees_of_freedom as f64,
        );
        report.measure(&format!("{label}p_value"), result.p_value);
        min_p = min_p.min(result.p_value);
        report.cases += 1;
        if !result.passed {
            report_failure(&mut report, &result, &numbers, &directions, kind, normal);
        }
    }
    report.passed = report.failures == 0;
    report.summary = if report.passed {
        format!(
            "uniform: {} χ² test(s) passed (smallest p = {min_p:.3})",
            report.cases
        )
    } else {
        format!(
            "not uniform: {} of {} χ² test(s) rejected (smallest p = {min_p:.3e})",
            report.failures, report.cases
        )
    };
    Ok(report)
}

/// Records a rejected test, with examples of invalid or impossible directions if there are
/// any (they say more than a statistic).
fn report_failure(
    report: &mut FunctionReport,
    result: &Chi2Result,
    numbers: &[Vec2],
    directions: &[Vec3],
    kind: ProbeKind,
    normal: Vec3,
) {
    let around = if kind == ProbeKind::SampleHemisphere {
        format!(
            " around normal = vec3({}, {}, {})",
            normal.x, normal.y, normal.z
        )
    } else {
        String::new()
    };
    report.add_mismatch(
        format!("{} samples{around}", directions.len()),
        "uniformly distributed unit vectors".into(),
        format!(
            "χ² = {:.1} with {} degrees of freedom, p = {:.3e}; {} directions not of unit \
             length, {} below the hemisphere",
            result.statistic,
            result.degrees_of_freedom,
            result.p_value,
            result.invalid_sample_count,
            result.impossible_sample_count
        ),
    );
    // A few examples of the first failing test say more than a statistic; later tests add
    // their summary only.
    let mut examples = if report.failures > 1 { 3 } else { 0 };
    for (&random, &direction) in numbers.iter().zip(directions) {
        if examples == 3 {
            break;
        }
        let length = f64::from(direction.length());
        let invalid = !direction.is_finite() || (length - 1.0).abs() > UNIT_LENGTH_TOLERANCE;
        // Below the hemisphere beyond rounding (the χ²'s equator bin absorbs the rest).
        let below = kind == ProbeKind::SampleHemisphere && normal.dot(direction) < -1e-6;
        if invalid || below {
            let problem = if invalid {
                format!("length {length}")
            } else {
                format!("dot(normal, direction) = {}", normal.dot(direction))
            };
            report.mismatches.push(crate::check::report::Mismatch {
                input: format!("random_numbers = vec2({}, {}){around}", random.x, random.y),
                expected: if invalid {
                    "a unit vector".into()
                } else {
                    "a direction with dot(normal, direction) >= 0".into()
                },
                actual: format!(
                    "vec3({}, {}, {}) ({problem})",
                    direction.x, direction.y, direction.z
                ),
            });
            examples += 1;
        }
    }
}
