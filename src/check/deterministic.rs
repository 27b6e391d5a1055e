//! The deterministic functions, compared with the reference input by input on the GPU: the
//! user's probe kernel and the reference probe kernel run on the same inputs, and outputs
//! are compared bit for bit (`get_random_numbers`) or within a tolerance that any correct
//! algorithm meets (the others), skipping near-degenerate inputs where correct algorithms
//! may legitimately decide differently.

use glam::{Vec2, Vec3};

use crate::check::detect::WorkshopFunction;
use crate::check::report::FunctionReport;
use crate::check::Session;
use crate::error::Result;
use crate::probe::compare::{
    max_ulps_of_one, ray_mesh_is_ambiguous, ray_triangle_geometry, relative_error,
    T_TOLERANCE_UNITS,
};
use crate::probe::inputs::{self, InputRng};
use crate::probe::{
    DirectionOutput, IntersectionOutput, MeshIntersectionOutput, ProbeKind, RandomNumbersInput,
    RandomNumbersOutput,
};

/// Seeds tried for `get_random_numbers`: every pixel seed of a 64 x 64 image's first 4
/// samples and random ones. PCG2D is a hash: a wrong constant or step changes (nearly)
/// every output, so a few thousand would do; 2^18 cost a few milliseconds.
const RANDOM_NUMBERS_CASES: usize = 1 << 18;
/// Random ray-triangle pairs (about 1/6 hit; see `inputs::ray_triangle_cases`).
const RAY_TRIANGLE_CASES: usize = 1 << 16;
/// Random rays inside the Cornell box.
const RAY_MESH_CASES: usize = 1 << 15;
/// Random cameras and image points.
const PRIMARY_RAY_CASES: usize = 1 << 15;

/// get_primary_ray_direction: each component of the unit direction within this many ulps of
/// one (2^-23) of the reference, i.e. 7.6e-6. Writing the sum in another order (e.g.
/// (left_bottom - camera_position) + ...) changes the image-plane point by a few ulps of
/// coordinates up to ~10 in the generated cameras, which normalization scales by
/// |point| / |point - camera| (up to ~10): tens of ulps of one. A wrong formula (a missing
/// normalize, swapped axes, tex_coord not in [0, 1]) is off by far more.
pub const PRIMARY_RAY_TOLERANCE_ULPS: f64 = 64.0;

fn vec3_text(v: Vec3) -> String {
    format!("vec3({}, {}, {})", v.x, v.y, v.z)
}

fn vec2_text(v: Vec2) -> String {
    format!("vec2({}, {})", v.x, v.y)
}

/// PCG2D: the updated seed and both random numbers, bit for bit.
pub fn check_random_numbers(session: &Session) -> Result<FunctionReport> {
    let function = WorkshopFunction::GetRandomNumbers;
    let mut report = FunctionReport::new(
        function.name(),
        session.user.line_of(function),
        "bit-exact",
        "the updated seed and both random numbers must equal the reference (PCG2D) bit for bit \
         (0 ulp): any correct way of writing PCG2D gives the same bits"
            .into(),
    );
    let seeds = inputs::random_seeds(&mut InputRng::new(11), RANDOM_NUMBERS_CASES);
    let probe_inputs: Vec<RandomNumbersInput> =
        seeds.iter().map(|&s| RandomNumbersInput::new(s)).collect();
    let (expected, actual): (Vec<RandomNumbersOutput>, Vec<RandomNumbersOutput>) =
        session.run_both(ProbeKind::GetRandomNumbers, &probe_inputs)?;
    let describe = |output: &RandomNumbersOutput| {
        format!(
            "seed = uvec2({}u, {}u), returns {}",
            output.seed().x,
            output.seed().y,
            vec2_text(output.numbers())
        )
    };
    let mut kinds = RandomNumbersMistakes::default();
    for ((seed, expected), actual) in seeds.iter().zip(&expected).zip(&actual) {
        if expected != actual {
            kinds.add(*seed, expected, actual);
            report.add_mismatch(
                format!("seed = uvec2({}u, {}u)", seed.x, seed.y),
                describe(expected),
                describe(actual),
            );
        }
    }
    report.cases = seeds.len();
    report.passed = report.failures == 0;
    if !report.passed {
        report.hint = Some(kinds.hint());
    }
    report.summary = format!(
        "{} of {} seeds give different bits",
        report.failures, report.cases
    );
    Ok(report)
}

/// How the user's PCG2D outputs differ from the reference's, counted over the seeds where
/// they differ: the hint follows what the evidence shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct RandomNumbersMistakes {
    /// The numbers are the reference's, and the seed comes back as it went in.
    seed_not_written_back: usize,
    /// The numbers are the reference's, the seed written back is another.
    other_seed: usize,
    /// The seed is the reference's updated seed, the numbers are not.
    other_numbers: usize,
    /// Both differ.
    both: usize,
}

impl RandomNumbersMistakes {
    fn add(
        &mut self,
        seed: glam::UVec2,
        expected: &RandomNumbersOutput,
        actual: &RandomNumbersOutput,
    ) {
        let numbers_agree = expected.seed_and_numbers[2..] == actual.seed_and_numbers[2..];
        let seed_agrees = expected.seed() == actual.seed();
        match (numbers_agree, seed_agrees) {
            (true, false) if actual.seed() == seed => self.seed_not_written_back += 1,
            (true, false) => self.other_seed += 1,
            (false, true) => self.other_numbers += 1,
            _ => self.both += 1,
        }
    }

    /// The likely mistake, from the largest count.
    fn hint(&self) -> String {
        let largest = self
            .seed_not_written_back
            .max(self.other_seed)
            .max(self.other_numbers)
            .max(self.both);
        if largest == self.seed_not_written_back {
            format!(
                "your function returns the right numbers but leaves seed as it was ({} seeds): \
                 write the updated seed back to the inout parameter (seed = ...), or every call \
                 with that seed returns the same numbers",
                self.seed_not_written_back
            )
        } else if largest == self.other_seed {
            format!(
                "your function returns the right numbers but writes back another seed than the \
                 updated one ({} seeds): the seed after the call must be PCG2D's updated state, \
                 from which the numbers are taken",
                self.other_seed
            )
        } else if largest == self.other_numbers {
            format!(
                "your seed is updated right, but the numbers returned from it are not ({} \
                 seeds): return vec2(seed) * 2.32830643654e-10 (2^-32) of the updated seed",
                self.other_numbers
            )
        } else {
            "this is not PCG2D as on the slides: compare the constants (1664525u, \
             1013904223u), the order of the updates of seed.x and seed.y, the two shifts by 16 \
             and the final scale 2^-32 (2.32830643654e-10)"
                .into()
        }
    }
}

/// Ray-triangle intersection: the same hit or miss and t within `T_TOLERANCE_UNITS` error
/// units, except near edges, grazing rays and t near 0.
pub fn check_ray_triangle(session: &Session) -> Result<FunctionReport> {
    let function = WorkshopFunction::RayTriangleIntersection;
    let mut report = FunctionReport::new(
        function.name(),
        session.user.line_of(function),
        "tolerance",
        format!(
            "the same hit/miss as the reference, and on hits |t - t_ref| <= {T_TOLERANCE_UNITS} \
             * 2^-23 (|t| + |o - v_0| / |d|) / |cos| (a few 1e-5 relative for rays that are not \
             grazing; met by Cramer's rule, Möller-Trumbore and inverse(mat3)); rays within \
             1e-5 / |cos| (barycentric) of an edge, grazing (|cos| < 1e-3) or with t near 0 are \
             not judged"
        ),
    );
    let cases = inputs::ray_triangle_cases(&mut InputRng::new(12), RAY_TRIANGLE_CASES);
    let (expected, actual): (Vec<IntersectionOutput>, Vec<IntersectionOutput>) =
        session.run_both(ProbeKind::RayTriangleIntersection, &cases)?;
    let (mut max_units, mut max_relative) = (0.0f64, 0.0f64);
    let (mut behind, mut missed, mut wrong_t) = (0usize, 0usize, 0usize);
    let outcome = |t: Option<f32>| match t {
        Some(t) => format!("true, out_t = {t}"),
        None => "false".to_string(),
    };
    for ((case, expected), actual) in cases.iter().zip(&expected).zip(&actual) {
        let geometry =
            ray_triangle_geometry(case.ray_origin(), case.ray_direction(), case.positions());
        let Some(geometry) = geometry.filter(|g| g.degeneracy().is_none()) else {
            report.skipped += 1;
            continue;
        };
        let (expected_t, actual_t) = (expected.hit_t(), actual.hit_t());
        let failed = match (expected_t, actual_t) {
            (Some(e), Some(a)) => {
                let units = geometry.t_error_units(e, a);
                max_units = max_units.max(units);
                max_relative = max_relative.max(relative_error(e, a));
                let failed = units.is_nan() || units > T_TOLERANCE_UNITS;
                wrong_t += usize::from(failed);
                failed
            }
            (None, None) => false,
            (None, Some(a)) => {
                behind += usize::from(a < 0.0);
                true
            }
            (Some(_), None) => {
                missed += 1;
                true
            }
        };
        if failed {
            let [v0, v1, v2] = case.positions();
            report.add_mismatch(
                format!(
                    "ray_origin = {}, ray_direction = {}, triangle.positions = {{{}, {}, {}}} \
                     (exact t = {:.7})",
                    vec3_text(case.ray_origin()),
                    vec3_text(case.ray_direction()),
                    vec3_text(v0),
                    vec3_text(v1),
                    vec3_text(v2),
                    geometry.t
                ),
                outcome(expected_t),
                outcome(actual_t),
            );
        }
    }
    report.cases = cases.len() - report.skipped;
    report.measure("max_t_error_units", max_units);
    report.measure("max_relative_t_error", max_relative);
    report.passed = report.failures == 0;
    report.summary = format!(
        "{} of {} rays disagree ({} near-degenerate rays not judged)",
        report.failures, report.cases, report.skipped
    );
    report.hint = ray_triangle_mistake(behind, missed, wrong_t);
    Ok(report)
}

/// The typical mistake that the kinds of disagreement point to, if any.
fn ray_triangle_mistake(behind: usize, missed: usize, wrong_t: usize) -> Option<String> {
    let largest = behind.max(missed).max(wrong_t);
    if largest == 0 {
        None
    } else if behind == largest {
        Some(format!(
            "{behind} hits behind the ray's origin (t < 0) are accepted: a hit needs t >= 0"
        ))
    } else if missed == largest {
        Some(format!(
            "{missed} hits are missed: check the barycentric bounds (b1 >= 0, b2 >= 0, \
             b1 + b2 <= 1) and which edges the system's columns use (v1 - v0, v2 - v0)"
        ))
    } else {
        Some(format!(
            "{wrong_t} hits have the wrong t: t is the first component of the solution of \
             mat3(-direction, v1 - v0, v2 - v0) * (t, b1, b2) = origin - v0"
        ))
    }
}

/// Closest hit in the Cornell box: the same triangle (or none) and t within the tolerance,
/// except for ambiguous rays.
pub fn check_ray_mesh(session: &Session) -> Result<FunctionReport> {
    let function = WorkshopFunction::RayMeshIntersection;
    let mut report = FunctionReport::new(
        function.name(),
        session.user.line_of(function),
        "tolerance",
        format!(
            "on rays from inside the Cornell box: the same hit triangle (or none) as the \
             reference, t within {T_TOLERANCE_UNITS} error units as for \
             ray_triangle_intersection; rays whose closest hit is ambiguous (an edge, a tie, a \
             grazing triangle) are not judged"
        ),
    );
    let triangles = &session.scene.triangles;
    let positions: Vec<[Vec3; 3]> = triangles.iter().map(|t| t.positions).collect();
    let rays = inputs::rays_inside(&mut InputRng::new(13), triangles, RAY_MESH_CASES);
    let (expected, actual): (Vec<MeshIntersectionOutput>, Vec<MeshIntersectionOutput>) =
        session.run_both(ProbeKind::RayMeshIntersection, &rays)?;
    let mut max_units = 0.0f64;
    let outcome = |output: &MeshIntersectionOutput| match output.hit_t() {
        Some(t) => match output.triangle_index(triangles) {
            Some(index) => format!("true, out_t = {t}, triangle {index}"),
            None => format!(
                "true, out_t = {t}, a triangle that is not in the scene (positions {:?})",
                output.triangle.positions
            ),
        },
        None => "false".to_string(),
    };
    for ((ray, expected), actual) in rays.iter().zip(&expected).zip(&actual) {
        let (origin, direction) = (ray.ray_origin(), ray.ray_direction());
        if ray_mesh_is_ambiguous(origin, direction, positions.iter().copied()) {
            report.skipped += 1;
            continue;
        }
        let expected_hit = expected.hit_t().zip(expected.triangle_index(triangles));
        let actual_hit = actual
            .hit_t()
            .map(|t| (t, actual.triangle_index(triangles)));
        let failed = match (expected_hit, actual_hit) {
            (Some((e, index)), Some((a, Some(actual_index)))) if index == actual_index => {
                let units = ray_triangle_geometry(origin, direction, positions[index])
                    .map_or(f64::INFINITY, |g| g.t_error_units(e, a));
                max_units = max_units.max(units);
                units.is_nan() || units > T_TOLERANCE_UNITS
            }
            (None, None) => false,
            _ => true,
        };
        if failed {
            report.add_mismatch(
                format!(
                    "ray_origin = {}, ray_direction = {}",
                    vec3_text(origin),
                    vec3_text(direction)
                ),
                outcome(expected),
                outcome(actual),
            );
        }
    }
    report.cases = rays.len() - report.skipped;
    report.measure("max_t_error_units", max_units);
    report.passed = report.failures == 0;
    report.summary = format!(
        "{} of {} rays disagree ({} ambiguous rays not judged)",
        report.failures, report.cases, report.skipped
    );
    Ok(report)
}

/// The pinhole camera: directions within `PRIMARY_RAY_TOLERANCE_ULPS` ulps of one.
pub fn check_primary_ray(session: &Session) -> Result<FunctionReport> {
    let function = WorkshopFunction::GetPrimaryRayDirection;
    let mut report = FunctionReport::new(
        function.name(),
        session.user.line_of(function),
        "tolerance",
        format!(
            "every component within {PRIMARY_RAY_TOLERANCE_ULPS} * 2^-23 of the reference's \
             normalized direction"
        ),
    );
    let cases = inputs::primary_ray_cases(&mut InputRng::new(14), PRIMARY_RAY_CASES);
    let (expected, actual): (Vec<DirectionOutput>, Vec<DirectionOutput>) =
        session.run_both(ProbeKind::GetPrimaryRayDirection, &cases)?;
    let mut max_ulps = 0.0f64;
    for ((case, expected), actual) in cases.iter().zip(&expected).zip(&actual) {
        let error = max_ulps_of_one(expected.direction(), actual.direction());
        let error = if error.is_nan() { f64::INFINITY } else { error };
        max_ulps = max_ulps.max(error);
        if error > PRIMARY_RAY_TOLERANCE_ULPS {
            let [position, left_bottom, right, up] = case.camera();
            report.add_mismatch(
                format!(
                    "x = {}, y = {}, camera_position = {}, left_bottom = {}, right = {}, up = {}",
                    case.tex_coord().x,
                    case.tex_coord().y,
                    vec3_text(position),
                    vec3_text(left_bottom),
                    vec3_text(right),
                    vec3_text(up)
                ),
                vec3_text(expected.direction()),
                vec3_text(actual.direction()),
            );
        }
    }
    report.cases = cases.len();
    report.measure("max_error_ulps_of_one", max_ulps);
    report.passed = report.failures == 0;
    if !report.passed {
        let unnormalized = cases.iter().zip(&expected).zip(&actual).all(|((_, e), a)| {
            let length = a.direction().length();
            length.is_finite()
                && length > 0.0
                && max_ulps_of_one(e.direction(), a.direction() / length)
                    <= PRIMARY_RAY_TOLERANCE_ULPS
        });
        report.hint = Some(if unnormalized {
            "the directions point the right way but are not normalized: return \
             normalize(left_bottom + x * right + y * up - camera_position)"
                .into()
        } else {
            "the image-plane point is left_bottom + x * right + y * up, with x and y in [0, 1] \
             (pixel_coord / iResolution), and the direction points from camera_position to it"
                .into()
        });
    }
    report.summary = format!(
        "{} of {} directions differ beyond the tolerance",
        report.failures, report.cases
    );
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn output(seed: [u32; 2], numbers: [u32; 2]) -> RandomNumbersOutput {
        RandomNumbersOutput {
            seed_and_numbers: [seed[0], seed[1], numbers[0], numbers[1]],
        }
    }

    #[test]
    fn a_pcg2d_hint_follows_what_differs() {
        let input = glam::UVec2::new(3, 4);
        let expected = output([10, 20], [1, 2]);
        // The right numbers, the seed as it went in: not written back (not the constants).
        let mut kinds = RandomNumbersMistakes::default();
        kinds.add(input, &expected, &output([3, 4], [1, 2]));
        let hint = kinds.hint();
        assert!(hint.contains("leaves seed as it was"), "{hint}");
        assert!(!hint.contains("constants"), "{hint}");
        // The right seed, other numbers: the scale.
        let mut kinds = RandomNumbersMistakes::default();
        kinds.add(input, &expected, &output([10, 20], [5, 2]));
        assert!(kinds.hint().contains("2^-32"), "{}", kinds.hint());
        // Both differ: not PCG2D.
        let mut kinds = RandomNumbersMistakes::default();
        kinds.add(input, &expected, &output([11, 20], [5, 2]));
        assert!(kinds.hint().contains("compare the constants"));
    }
}
