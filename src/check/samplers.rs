//! The samplers, judged by what they must do and never by equality: 10^6 directions from
//! the user's `sample_sphere` or `sample_hemisphere` on the GPU, binned on the sphere and
//! tested against the uniform density with Pearson's χ² (`crate::stats::chi2`). A correct
//! sampler written differently (z = 1 - 2 u, another phi mapping, flipping instead of
//! mirroring) passes; a wrong density, directions that are not unit vectors, or directions
//! below the hemisphere fail. A failing sampler's directions are also tested against the
//! densities of the typical mistakes (cosine-weighted, no mirror, θ = π u, the upper half
//! only), to name the mistake, and its 512 samples are drawn next to the reference's the
//! way `vkpath exercise sample-sphere` draws them.

use glam::{UVec2, Vec2, Vec3};

use crate::check::compile::compile_kernel;
use crate::check::detect::WorkshopFunction;
use crate::check::report::FunctionReport;
use crate::check::Session;
use crate::error::{Error, Result};
use crate::exercise::{render_sample_display, render_sample_display_with, ExerciseSampler};
use crate::image_io::data::RenderedImage;
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
            if report.hint.is_none() {
                report.hint = typical_mistake(function, &directions, normal, &config);
            }
        }
    }
    report.passed = report.failures == 0;
    if !report.passed {
        report.images = draw_samples(session, function)?;
    }
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

/// A typical mistake whose density the directions follow: each candidate density is tested
/// with the same χ² statistic, and the first whose statistic per degree of freedom is below
/// 2 is named (a correct match gives about 1 with 10^6 samples, the uniform density that
/// failed gives tens or hundreds).
fn typical_mistake(
    function: WorkshopFunction,
    directions: &[Vec3],
    normal: Vec3,
    config: &Chi2Config,
) -> Option<String> {
    use std::f64::consts::PI;
    let n = normal.as_dvec3();
    let cosine = move |d: Vec3| (d.as_dvec3().dot(n)).max(0.0) / PI;
    let upper_half = |d: Vec3| if d.z >= 0.0 { 1.0 / (2.0 * PI) } else { 0.0 };
    type Candidate<'a> = (TargetDensity<'a>, SphereFrame, &'static str);
    let frame = SphereFrame::from_normal(normal).ok()?;
    let candidates: Vec<Candidate> =
        match function {
            WorkshopFunction::SampleHemisphere => vec![
            (
                TargetDensity::SolidAngle(&cosine),
                frame,
                "your directions are cosine-weighted (density cos θ / π): a valid sampler, but \
                 not the exercise's uniform one; the workshop's weight a · 2 · dot(n, ω) assumes \
                 the uniform density 1 / (2π)",
            ),
            (
                TargetDensity::UniformSphere,
                frame,
                "your directions are uniform on the whole sphere: half of them point below the \
                 surface; mirror those into the hemisphere, ω' = ω - 2 dot(n, ω) n when \
                 dot(n, ω) < 0",
            ),
            (
                TargetDensity::UniformTheta { theta_max: PI / 2.0 },
                frame,
                "your directions crowd around the normal like spherical coordinates with \
                 θ = (π/2) u: cos θ must be uniform instead (z = u, or a mirrored uniform \
                 sphere sample)",
            ),
        ],
            WorkshopFunction::SampleSphere => vec![
                (
                    TargetDensity::UniformTheta { theta_max: PI },
                    SphereFrame::WORLD,
                    "your directions crowd at the poles like spherical coordinates with θ = π u \
                 (the slides' \"too many samples at the top\"): z = cos θ must be uniform, \
                 z = 2 u - 1",
                ),
                (
                    TargetDensity::SolidAngle(&upper_half),
                    SphereFrame::WORLD,
                    "your directions cover only the upper half of the sphere (z >= 0): z must run \
                 over [-1, 1], z = 2 u - 1",
                ),
            ],
            _ => Vec::new(),
        };
    candidates.into_iter().find_map(|(target, frame, words)| {
        let result =
            chi2_direction_test(directions.iter().copied(), target, &frame, config).ok()?;
        let per_degree = result.statistic / result.degrees_of_freedom.max(1) as f64;
        (result.invalid_sample_count == 0
            && result.impossible_sample_count == 0
            && per_degree < 2.0)
            .then(|| words.to_string())
    })
}

/// Side of each half of the sample picture, in pixels.
const SAMPLE_PICTURE_SIZE: u32 = 256;

/// Draws the reference's 512 samples (left) and the user's (right) as `vkpath exercise`
/// does, into `<function>-samples.png`.
fn draw_samples(session: &Session, function: WorkshopFunction) -> Result<Vec<String>> {
    let sampler = match function {
        WorkshopFunction::SampleSphere => ExerciseSampler::Sphere,
        _ => ExerciseSampler::Hemisphere,
    };
    let size = SAMPLE_PICTURE_SIZE;
    let reference = render_sample_display(&session.context, sampler, size, size, 0)?;
    let compiled = compile_kernel(
        "exercise_samples.comp",
        Some(&session.user.code(&[function])),
        &[],
    )
    .map_err(|error| Error::ShaderCompilation(error.to_string()))?;
    let yours =
        render_sample_display_with(&session.context, &compiled.spirv, sampler, size, size, 0)?;
    session.save_pngs(&[(
        format!("{}-samples", function.name()),
        side_by_side(&reference, &yours),
    )])
}

/// Two images of the same height next to each other, with a grey column between them.
fn side_by_side(left: &RenderedImage, right: &RenderedImage) -> RenderedImage {
    let width = left.width + 1 + right.width;
    let mut mean = Vec::with_capacity((width * left.height) as usize);
    for y in 0..left.height {
        mean.extend((0..left.width).map(|x| left.pixel(x, y)));
        mean.push([0.5, 0.5, 0.5, 1.0]);
        mean.extend((0..right.width).map(|x| right.pixel(x, y)));
    }
    let count = mean.len();
    RenderedImage {
        width,
        height: left.height,
        mean,
        second_moment: vec![[0.0; 3]; count],
        sample_count: vec![1.0; count],
    }
}
