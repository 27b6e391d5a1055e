//! The GPU against the CPU twins, function by function: each probe kernel
//! (`glsl/probe_*.comp`) evaluates a workshop function on many inputs and the Rust twin of
//! `vkpath::cpu` evaluates it on the same inputs. Integer results must match bit for bit;
//! float results within bounds measured on lavapipe and justified below; decisions (hit or
//! miss, path branches) may differ only where an ulp can flip them, which is counted and
//! bounded. Every test prints its measured maximum errors and asserts that the validation
//! layer stayed silent.

use crate::common;

use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};
use vkpath::cpu::integrator::{
    compute_direct_illumination, get_ray_radiance, ray_mesh_intersection,
};
use vkpath::cpu::workshop::{
    get_primary_ray_direction, get_random_numbers, ray_triangle_intersection, sample_hemisphere,
    sample_sphere,
};
use vkpath::probe::compare::{
    max_ulps_of_one, ray_mesh_is_ambiguous, ray_triangle_geometry, relative_error,
    vector_relative_error,
};
use vkpath::probe::inputs::{self, InputRng};
use vkpath::probe::{
    DirectionOutput, IntersectionOutput, MeshIntersectionOutput, ProbeKind, ProbePipeline,
    ProbeRunner, RadianceOutput, RandomNumbersInput, RandomNumbersOutput,
};
use vkpath::scene::Triangle;
use vkpath::vk::Context;
use vkpath::Scene;

/// `MAX_PATH_LENGTH` for the `get_ray_radiance` probe: the renderer's default.
const MAX_PATH_LENGTH: u32 = vkpath::render::settings::DEFAULT_MAX_PATH_LENGTH;

/// Runs the reference probe `kind` on `inputs` with `triangles` as the scene.
fn run_reference<I: bytemuck::Pod, O: bytemuck::Pod>(
    context: &Arc<Context>,
    triangles: &[Triangle],
    kind: ProbeKind,
    inputs: &[I],
) -> Vec<O> {
    let runner = ProbeRunner::new(context, triangles).expect("probe runner");
    let pipeline =
        ProbePipeline::reference(context, kind, MAX_PATH_LENGTH).expect("probe pipeline");
    let outputs = runner.run(&pipeline, inputs).expect("probe run");
    assert_eq!(outputs.len(), inputs.len());
    outputs
}

fn cornell_triangles() -> Vec<Triangle> {
    Scene::builtin_cornell_box()
        .expect("built-in scene")
        .triangles
}

#[test]
fn pcg2d_is_bit_exact_over_a_million_seeds() {
    let context = common::validated_context();
    let seeds = inputs::random_seeds(&mut InputRng::new(1), 1_000_000);
    let probe_inputs: Vec<RandomNumbersInput> =
        seeds.iter().map(|&s| RandomNumbersInput::new(s)).collect();
    let outputs: Vec<RandomNumbersOutput> =
        run_reference(&context, &[], ProbeKind::GetRandomNumbers, &probe_inputs);
    let mut mismatches = 0;
    for (&seed, output) in seeds.iter().zip(&outputs) {
        let mut cpu_seed = seed;
        let cpu_numbers = get_random_numbers(&mut cpu_seed);
        let same = output.seed() == cpu_seed
            && output.numbers().x.to_bits() == cpu_numbers.x.to_bits()
            && output.numbers().y.to_bits() == cpu_numbers.y.to_bits();
        if !same {
            if mismatches < 5 {
                println!(
                    "seed {seed}: GPU {:?}, CPU {cpu_seed} {cpu_numbers}",
                    output
                );
            }
            mismatches += 1;
        }
    }
    println!("PCG2D: {} seeds, {mismatches} mismatches", seeds.len());
    assert_eq!(mismatches, 0, "PCG2D must be bit-exact");
    common::assert_validation_silent(&context);
}

/// Inputs for the samplers: a PCG2D stream, plus the corners of [0, 1]^2 and the largest
/// float below 1, where cos, sin and sqrt meet their edge cases.
fn sampler_random_numbers() -> Vec<Vec2> {
    let below_one = 1.0 - f32::EPSILON / 2.0;
    let mut numbers = vec![
        Vec2::ZERO,
        Vec2::new(below_one, 0.0),
        Vec2::new(0.0, below_one),
        Vec2::splat(below_one),
        Vec2::new(0.25, 0.5),
        Vec2::new(0.5, 0.5),
        Vec2::new(0.75, 1.0),
    ];
    numbers.extend(inputs::pcg_random_numbers(UVec2::new(17, 4), 1 << 18));
    numbers
}

/// sample_sphere and sample_hemisphere: each component within this many ulps of one
/// (2^-23 absolute) of the CPU twin. The twins perform the same operations; they differ in
/// the GPU's cos and sin (lavapipe evaluates its own polynomial approximations), its sqrt,
/// and fused multiply-adds (e.g. 1 - z * z). Measured on lavapipe (Mesa 22.3, 2^18 + 7
/// inputs): 0.5 for sample_sphere, 2 for sample_hemisphere around an oblique normal (the
/// mirror step adds its own rounding); 8 leaves a margin of 4x. Vulkan itself only promises
/// sin and cos to 2^-11 absolute, so another driver may need a larger bound: that would be a
/// finding about the driver, not a bug in the twin.
const SAMPLER_ULPS_OF_ONE: f64 = 8.0;

#[test]
fn sample_sphere_matches_its_twin_within_ulps() {
    let context = common::validated_context();
    let numbers = sampler_random_numbers();
    let probe_inputs = inputs::sampler_inputs(&numbers, Vec3::ZERO);
    let outputs: Vec<DirectionOutput> =
        run_reference(&context, &[], ProbeKind::SampleSphere, &probe_inputs);
    let mut worst = (0.0, Vec2::ZERO);
    for (&random, output) in numbers.iter().zip(&outputs) {
        let error = max_ulps_of_one(output.direction(), sample_sphere(random));
        if error > worst.0 {
            worst = (error, random);
        }
    }
    println!(
        "sample_sphere: {} inputs, max error {} ulps of one (at u = {})",
        numbers.len(),
        worst.0,
        worst.1
    );
    assert!(worst.0 <= SAMPLER_ULPS_OF_ONE, "{worst:?}");
    common::assert_validation_silent(&context);
}

#[test]
fn sample_hemisphere_matches_its_twin_within_ulps() {
    let context = common::validated_context();
    let numbers = sampler_random_numbers();
    let normals = [Vec3::Z, -Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize()];
    for normal in normals {
        let probe_inputs = inputs::sampler_inputs(&numbers, normal);
        let outputs: Vec<DirectionOutput> =
            run_reference(&context, &[], ProbeKind::SampleHemisphere, &probe_inputs);
        let mut worst = (0.0, Vec2::ZERO);
        for (&random, output) in numbers.iter().zip(&outputs) {
            // Where n . omega is within rounding of 0 the GPU and the CPU may disagree on
            // mirroring, but the mirror then moves omega by 2 |n . omega| only: no special
            // case is needed.
            let error = max_ulps_of_one(output.direction(), sample_hemisphere(random, normal));
            if error > worst.0 {
                worst = (error, random);
            }
        }
        println!(
            "sample_hemisphere around {normal}: max error {} ulps of one (at u = {})",
            worst.0, worst.1
        );
        assert!(worst.0 <= SAMPLER_ULPS_OF_ONE, "{normal}: {worst:?}");
    }
    common::assert_validation_silent(&context);
}

/// Near-degenerate inputs may be decided differently (see `vkpath::probe::compare`); they
/// must stay rare: at most this fraction of the cases. Measured: 0.12% of the random
/// ray-triangle cases, 0.68% of the rays in the Cornell box (shared edges of its quads and
/// the blocks' edges on the floor).
const MAX_DEGENERATE_FRACTION: f64 = 0.01;

#[test]
fn ray_triangle_intersection_matches_its_twin() {
    let context = common::validated_context();
    let cases = inputs::ray_triangle_cases(&mut InputRng::new(3), 1 << 18);
    let outputs: Vec<IntersectionOutput> =
        run_reference(&context, &[], ProbeKind::RayTriangleIntersection, &cases);
    let (mut degenerate, mut degenerate_disagreements, mut hits) = (0, 0, 0);
    let mut max_t_units: f64 = 0.0;
    let mut max_t_relative: f64 = 0.0;
    for (case, output) in cases.iter().zip(&outputs) {
        let positions = case.positions();
        let triangle = Triangle::new(positions, Vec3::splat(0.5), Vec3::ZERO, false)
            .expect("generated triangles are not degenerate");
        let cpu = ray_triangle_intersection(case.ray_origin(), case.ray_direction(), &triangle);
        let gpu = output.hit_t();
        let geometry = ray_triangle_geometry(case.ray_origin(), case.ray_direction(), positions);
        if geometry.is_none_or(|g| g.degeneracy().is_some()) {
            degenerate += 1;
            degenerate_disagreements += usize::from(cpu.is_some() != gpu.is_some());
            continue;
        }
        let geometry = geometry.expect("checked above");
        assert_eq!(
            cpu.is_some(),
            gpu.is_some(),
            "hit/miss differs away from degeneracies: {case:?}, CPU {cpu:?}, GPU {gpu:?}"
        );
        if let (Some(cpu_t), Some(gpu_t)) = (cpu, gpu) {
            hits += 1;
            max_t_units = max_t_units.max(geometry.t_error_units(cpu_t, gpu_t));
            max_t_relative = max_t_relative.max(relative_error(cpu_t, gpu_t));
        }
    }
    println!(
        "ray_triangle_intersection: {} cases, {hits} clear hits, {degenerate} near-degenerate \
         ({degenerate_disagreements} of them decided differently); max t error {max_t_units:.3} \
         error units, max relative t error {max_t_relative:.3e}",
        cases.len()
    );
    // The twins perform the same operations: t differs by the GPU's fused multiply-adds
    // only, far below the tolerance that different algorithms get (T_TOLERANCE_UNITS).
    assert!(max_t_units <= T_TWIN_UNITS, "{max_t_units}");
    assert!((degenerate as f64) < MAX_DEGENERATE_FRACTION * cases.len() as f64);
    common::assert_validation_silent(&context);
}

/// How far the GPU's t may be from the CPU twin's, in `RayTriangleGeometry::t_error_unit`s
/// (2^-23 (|t| + |o - v_0| / |d|) / |cos|). Measured on lavapipe: 0 (bit-identical: the
/// same operations without fused multiply-adds); 8 units leave room for a driver that
/// contracts a * b + c into an fma (an error of about one unit per fused dot product), and
/// stay well below `vkpath::probe::compare::T_TOLERANCE_UNITS` (64) for other algorithms.
const T_TWIN_UNITS: f64 = 8.0;

#[test]
fn ray_mesh_intersection_matches_its_twin_in_the_cornell_box() {
    let context = common::validated_context();
    let triangles = cornell_triangles();
    let rays = inputs::rays_inside(&mut InputRng::new(4), &triangles, 1 << 16);
    let outputs: Vec<MeshIntersectionOutput> =
        run_reference(&context, &triangles, ProbeKind::RayMeshIntersection, &rays);
    let positions: Vec<[Vec3; 3]> = triangles.iter().map(|t| t.positions).collect();
    let (mut ambiguous, mut ambiguous_disagreements) = (0, 0);
    let mut max_t_relative: f64 = 0.0;
    for (ray, output) in rays.iter().zip(&outputs) {
        let cpu = ray_mesh_intersection(&triangles, ray.ray_origin(), ray.ray_direction());
        let gpu = output.hit_t().map(|t| (t, output.hit[1] as usize));
        // The reference sets g_hit_triangle_index and returns the same triangle.
        if let Some((_, index)) = gpu {
            assert_eq!(output.triangle_index(&triangles), Some(index));
        }
        let cpu = cpu.map(|hit| (hit.t, hit.triangle_index));
        if ray_mesh_is_ambiguous(
            ray.ray_origin(),
            ray.ray_direction(),
            positions.iter().copied(),
        ) {
            ambiguous += 1;
            ambiguous_disagreements += usize::from(cpu.map(|c| c.1) != gpu.map(|g| g.1));
            continue;
        }
        match (cpu, gpu) {
            (Some((cpu_t, cpu_index)), Some((gpu_t, gpu_index))) => {
                assert_eq!(cpu_index, gpu_index, "{ray:?}");
                max_t_relative = max_t_relative.max(relative_error(cpu_t, gpu_t));
            }
            (None, None) => {}
            _ => panic!("hit/miss differs: {ray:?}: CPU {cpu:?}, GPU {gpu:?}"),
        }
    }
    println!(
        "ray_mesh_intersection: {} rays in the Cornell box, {ambiguous} ambiguous \
         ({ambiguous_disagreements} decided differently), max relative t error {max_t_relative:.3e}",
        rays.len()
    );
    assert!(
        max_t_relative <= MESH_T_RELATIVE_TOLERANCE,
        "{max_t_relative}"
    );
    assert!((ambiguous as f64) < MAX_DEGENERATE_FRACTION * rays.len() as f64);
    common::assert_validation_silent(&context);
}

/// Relative t tolerance inside the Cornell box, where origins are well inside and no ray
/// grazes (those are ambiguous): the box is 5.5 units wide, so t and |o - v_0| are alike and
/// the t error unit is a few 2^-23 relative. Measured on lavapipe: 0 (bit-identical); 1e-5
/// (about 80 ulps) leaves room for fused multiply-adds on other drivers.
const MESH_T_RELATIVE_TOLERANCE: f64 = 1e-5;

#[test]
fn primary_ray_direction_matches_its_twin() {
    let context = common::validated_context();
    let cases = inputs::primary_ray_cases(&mut InputRng::new(5), 1 << 16);
    let outputs: Vec<DirectionOutput> =
        run_reference(&context, &[], ProbeKind::GetPrimaryRayDirection, &cases);
    let mut worst: f64 = 0.0;
    for (case, output) in cases.iter().zip(&outputs) {
        let [position, left_bottom, right, up] = case.camera();
        let point = case.tex_coord();
        let cpu = get_primary_ray_direction(point.x, point.y, position, left_bottom, right, up);
        worst = worst.max(max_ulps_of_one(cpu, output.direction()));
    }
    println!(
        "get_primary_ray_direction: {} cases, max error {worst} ulps of one",
        cases.len()
    );
    assert!(worst <= PRIMARY_RAY_ULPS_OF_ONE, "{worst}");
    common::assert_validation_silent(&context);
}

/// get_primary_ray_direction: within this many ulps of one of the twin. The image-plane
/// point sums three products of magnitude up to ~10 (fused on the GPU), and the
/// subtraction of the camera position then normalization scale its rounding by up to
/// |point| / |point - camera|; glam normalizes with 1 / sqrt, the GPU may use inversesqrt.
/// Measured on lavapipe: 0.5 (2^16 random cameras and points); 8 leaves room for fused
/// multiply-adds and an inversesqrt of a few ulps.
const PRIMARY_RAY_ULPS_OF_ONE: f64 = 8.0;

/// The estimators may follow different paths when a branch (hit or miss, which triangle,
/// mirror or not) flips through an ulp; an output counts as diverged when its random state
/// after the call differs (a different number of bounces) or its radiance differs by more
/// than `DIVERGED_RELATIVE` of the larger (a different light or triangle was found: O(1)
/// changes). Divergences must be rare; all other outputs must agree within
/// `ESTIMATOR_RELATIVE_TOLERANCE`, and nothing may fall between the two thresholds, which
/// shows that the differences are either rounding or a flipped branch, nothing else.
const DIVERGED_RELATIVE: f64 = 5e-2;
/// See `DIVERGED_RELATIVE`. Non-diverged paths chain a few ray hits, sampler calls and
/// products of throughput; the factor n . omega of each bounce amplifies the sampler's
/// absolute error of ~2^-24 to a relative one of 2^-24 / (n . omega), large near grazing
/// directions. Measured on lavapipe (2^16 seeds each): 3.7e-5 for
/// compute_direct_illumination, 1.1e-5 for get_ray_radiance; 1e-3 leaves a margin of 27x.
const ESTIMATOR_RELATIVE_TOLERANCE: f64 = 1e-3;
/// At most this fraction of the outputs may diverge. Measured on lavapipe: none of 2^16.
const MAX_DIVERGED_FRACTION: f64 = 0.01;

/// Compares estimator outputs: returns (diverged count, max relative error of the others,
/// count in the gap between the two thresholds).
fn compare_estimates(
    pairs: impl Iterator<Item = ((Vec3, UVec2), (Vec3, UVec2))>,
) -> (usize, f64, usize) {
    let (mut diverged, mut worst, mut in_gap) = (0, 0.0f64, 0);
    for ((cpu_radiance, cpu_seed), (gpu_radiance, gpu_seed)) in pairs {
        let error = vector_relative_error(cpu_radiance, gpu_radiance);
        if cpu_seed != gpu_seed || error > DIVERGED_RELATIVE {
            diverged += 1;
        } else if error > ESTIMATOR_RELATIVE_TOLERANCE {
            in_gap += 1;
            worst = worst.max(error);
        } else {
            worst = worst.max(error);
        }
    }
    (diverged, worst, in_gap)
}

#[test]
fn compute_direct_illumination_matches_its_twin_per_seed() {
    let context = common::validated_context();
    let triangles = cornell_triangles();
    let cases = inputs::direct_illumination_cases(&mut InputRng::new(6), &triangles, 1 << 16);
    let outputs: Vec<RadianceOutput> = run_reference(
        &context,
        &triangles,
        ProbeKind::ComputeDirectIllumination,
        &cases,
    );
    let pairs = cases.iter().zip(&outputs).map(|(case, output)| {
        let mut seed = case.seed();
        let triangle = triangles[case.triangle_index()];
        let radiance =
            compute_direct_illumination(&triangles, case.shading_position(), &triangle, &mut seed);
        ((radiance, seed), (output.radiance(), output.seed()))
    });
    let (diverged, worst, in_gap) = compare_estimates(pairs);
    let nonzero = outputs
        .iter()
        .filter(|o| o.radiance().max_element() > 0.0)
        .count();
    println!(
        "compute_direct_illumination: {} seeds ({nonzero} lit), {diverged} diverged, max relative \
         error of the others {worst:.3e}, {in_gap} between the thresholds",
        cases.len()
    );
    assert!(
        nonzero > cases.len() / 100,
        "too few estimates see the light to test anything"
    );
    assert!((diverged as f64) < MAX_DIVERGED_FRACTION * cases.len() as f64);
    assert_eq!(in_gap, 0, "max {worst}");
    common::assert_validation_silent(&context);
}

#[test]
fn get_ray_radiance_matches_its_twin_per_seed() {
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().expect("built-in scene");
    let plane = scene
        .camera
        .expect("the Cornell box has a camera")
        .image_plane(1.0);
    let cases = inputs::camera_path_cases(&mut InputRng::new(7), &plane, 1 << 16);
    let outputs: Vec<RadianceOutput> = run_reference(
        &context,
        &scene.triangles,
        ProbeKind::GetRayRadiance,
        &cases,
    );
    let pairs = cases.iter().zip(&outputs).map(|(case, output)| {
        let mut seed = case.seed();
        let radiance = get_ray_radiance(
            &scene.triangles,
            case.ray_origin(),
            case.ray_direction(),
            &mut seed,
            MAX_PATH_LENGTH,
        );
        ((radiance, seed), (output.radiance(), output.seed()))
    });
    let (diverged, worst, in_gap) = compare_estimates(pairs);
    let nonzero = outputs
        .iter()
        .filter(|o| o.radiance().max_element() > 0.0)
        .count();
    println!(
        "get_ray_radiance: {} paths ({nonzero} lit), {diverged} diverged, max relative error of \
         the others {worst:.3e}, {in_gap} between the thresholds",
        cases.len()
    );
    assert!(
        nonzero > cases.len() / 100,
        "too few paths see the light to test anything"
    );
    assert!((diverged as f64) < MAX_DIVERGED_FRACTION * cases.len() as f64);
    assert_eq!(in_gap, 0, "max {worst}");
    common::assert_validation_silent(&context);
}
