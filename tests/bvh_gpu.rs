//! The GPU's BVH traversal (`glsl/bvh.glsl`, run by `glsl/probe_bvh.comp`) against its Rust
//! twins `bvh_closest_hit` / `bvh_any_hit`, and against the GPU's own brute-force
//! `ray_mesh_intersection`, with the validation layer on and silent.

use crate::common;

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{UVec2, Vec3};
use vkpath::bvh::compressed_traversal::{cwbvh_any_hit, cwbvh_closest_hit};
use vkpath::bvh::{
    bvh_any_hit, bvh_closest_hit, bvh_inverse_direction, bvh_ray_box_intersection,
    get_bvh_child_box, packed_traversal_triangles, traversal_triangles, Bvh, CompressedBvh,
};
use vkpath::contract;
use vkpath::cpu::workshop::{get_random_numbers, sample_sphere};
use vkpath::kernels::{self, Bound, Resource};
use vkpath::probe::{Probe, ProbeScene};
use vkpath::scene::meshes::scale_test_scene;
use vkpath::scene::Triangle;
use vkpath::vk::{Buffer, Context, TexelBufferView};

/// `bvh_probe_ray_t`: xyz origin, w t_max of the any-hit query; xyz direction.
type ProbeRay = [[f32; 4]; 2];
/// `bvh_probe_result_t`: the BVH's (t bits, index, hit, any hit), brute force's (t bits,
/// index, hit, 0), the inverse direction and root entry t (float bits), the root box hit.
type ProbeResult = [[u32; 4]; 4];

/// Runs the probe kernel over `rays` with the reordered triangles (in full, and their
/// traversal-only positions) and the BVH's nodes.
/// Returns the results and the seconds the run took.
fn run_probe(
    context: &Arc<Context>,
    triangles: &[Triangle],
    bvh: &Bvh,
    rays: &[ProbeRay],
    brute_force: bool,
) -> (Vec<ProbeResult>, f64) {
    let positions = traversal_triangles(triangles);
    let layout = (
        bytemuck::cast_slice::<_, u8>(&bvh.wide_nodes),
        bytemuck::cast_slice::<_, u8>(&positions),
        contract::BVH_LAYOUT_WIDE,
    );
    run_probe_with(context, triangles, layout, rays, brute_force)
}

/// `run_probe` with the nodes' and traversal triangles' bytes in the given `SPEC_BVH_LAYOUT`.
fn run_probe_with(
    context: &Arc<Context>,
    triangles: &[Triangle],
    (node_bytes, traversal_bytes, layout): (&[u8], &[u8], u32),
    rays: &[ProbeRay],
    brute_force: bool,
) -> (Vec<ProbeResult>, f64) {
    let scene = ProbeScene::new(context, triangles).unwrap();
    let nodes = Buffer::with_data(
        context,
        "bvh nodes",
        node_bytes,
        vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
    )
    .unwrap();
    let node_texels = TexelBufferView::new(context, nodes, vk::Format::R32G32B32A32_UINT).unwrap();
    let positions = Buffer::with_data(
        context,
        "traversal triangles",
        traversal_bytes,
        vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
    )
    .unwrap();
    let position_texels =
        TexelBufferView::new(context, positions, vk::Format::R32G32B32A32_UINT).unwrap();
    let specialization = [
        (contract::BVH_PROBE_SPEC_BRUTE_FORCE, u32::from(brute_force)),
        (contract::SPEC_BVH_LAYOUT, layout),
    ];
    let probe = Probe::embedded(
        context,
        &kernels::PROBE_BVH,
        &specialization,
        "bvh_closest_hit",
    )
    .unwrap();
    let start = Instant::now();
    let results = probe
        .run(
            |resource| match resource {
                Resource::BvhNodes => Some(Bound::TexelBuffer(&node_texels)),
                Resource::TraversalTriangles => Some(Bound::TexelBuffer(&position_texels)),
                other => scene.resource(other),
            },
            rays,
        )
        .unwrap();
    (results, start.elapsed().as_secs_f64())
}

/// Rays of a path tracer in the Cornell box: half from the workshop camera's pinhole towards
/// the box, a quarter from random points inside the room in uniform directions, a quarter
/// from such points along the axes (zero direction components: the slab test's
/// `BVH_MIN_DIRECTION` path). `t_max` of the any-hit query is the closest hit's t (Rust twin)
/// times a factor in [0.5, 1.5), or 1e30.
fn test_rays(count: usize, triangles: &[Triangle], bvh: &Bvh) -> Vec<ProbeRay> {
    let traversal = traversal_triangles(triangles);
    let mut seed = UVec2::new(2024, 7);
    let camera = Vec3::new(0.278, 0.8, 0.2744);
    (0..count)
        .map(|i| {
            let a = get_random_numbers(&mut seed);
            let b = get_random_numbers(&mut seed);
            let (origin, direction) = if i % 2 == 0 {
                let target = Vec3::new(0.556 * a.x, -0.56, 0.549 * a.y);
                (camera, (target - camera).normalize())
            } else {
                let origin = Vec3::new(0.556 * a.x, -0.56 * a.y, 0.549 * b.x);
                let random = get_random_numbers(&mut seed);
                let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
                if i % 4 == 1 {
                    (origin, axes[(random.x * 6.0) as usize % 6])
                } else {
                    (origin, sample_sphere(random))
                }
            };
            let hit = bvh_closest_hit(&bvh.wide_nodes, &traversal, origin, direction);
            let t_max = hit.map_or(1e30, |h| h.t * (0.5 + b.y));
            [
                origin.extend(t_max).to_array(),
                direction.extend(0.0).to_array(),
            ]
        })
        .collect()
}

/// How the GPU's answers compared.
#[derive(Debug, Default)]
struct Tally {
    hits: usize,
    /// Same triangle, t within 1e-6 relative (8 ulps: lavapipe may fuse multiply-adds).
    same: usize,
    /// A different triangle or hit/miss answer at a near-degenerate configuration: t within
    /// 1e-5 relative (a tie between triangles sharing an edge, a grazing ray).
    near_degenerate: usize,
    /// Anything else.
    different: usize,
}

impl Tally {
    fn add(&mut self, expected: Option<(u32, f32)>, actual: Option<(u32, f32)>) {
        let close = |a: f32, b: f32, tolerance: f32| (a - b).abs() <= tolerance * a.abs().max(1e-3);
        match (expected, actual) {
            (None, None) => self.same += 1,
            (Some((ei, et)), Some((ai, at))) => {
                self.hits += 1;
                if ei == ai && close(et, at, 1e-6) {
                    self.same += 1;
                } else if close(et, at, 1e-5) {
                    self.near_degenerate += 1;
                } else {
                    self.different += 1;
                }
            }
            _ => self.different += 1,
        }
    }

    /// No gross difference, and near-degenerate ones below 0.5% of the rays: random rays
    /// meet an edge within 1e-5 relative with a probability of order 1e-4 each.
    fn assert_agrees(&self, what: &str, rays: usize) {
        println!("{what}: {self:?}");
        assert_eq!(self.different, 0, "{what}: {self:?}");
        assert!(self.near_degenerate * 200 <= rays, "{what}: {self:?}");
    }
}

fn hit(result: [u32; 4]) -> Option<(u32, f32)> {
    (result[2] != 0).then(|| (result[1], f32::from_bits(result[0])))
}

/// Compares the probe's results with the Rust twins (and brute force on the GPU, if run).
fn check(
    name: &str,
    triangles: &[Triangle],
    bvh: &Bvh,
    rays: &[ProbeRay],
    results: &[ProbeResult],
    brute_force: bool,
) {
    let traversal = traversal_triangles(triangles);
    let mut twin = Tally::default();
    let mut gpu_brute_force = Tally::default();
    let mut any_hit_disagreements = 0;
    let mut box_test_disagreements = 0;
    let root = get_bvh_child_box(&bvh.wide_nodes, 0, 0);
    for (ray, result) in rays.iter().zip(results) {
        let origin = Vec3::from_slice(&ray[0][..3]);
        let direction = Vec3::from_slice(&ray[1][..3]);
        // bvh_inverse_direction and bvh_ray_box_intersection with the root's first child's box: within
        // 1e-6 relative (8 ulps; lavapipe divides exactly, other GPUs to 2.5 ulps).
        let inverse = bvh_inverse_direction(direction);
        let gpu = result[2].map(f32::from_bits);
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * a.abs();
        assert!(
            (0..3).all(|i| close(inverse[i], gpu[i])),
            "{inverse} vs {gpu:?}"
        );
        let entry = bvh_ray_box_intersection(origin, inverse, root.lower, root.upper, ray[0][3]);
        let gpu_entry = (result[3][0] != 0).then_some(gpu[3]);
        let agrees = match (entry, gpu_entry) {
            (Some(e), Some(g)) => (e - g).abs() <= 1e-6 * e.max(1e-3),
            (e, g) => e == g,
        };
        box_test_disagreements += usize::from(!agrees);
        let expected = bvh_closest_hit(&bvh.wide_nodes, &traversal, origin, direction)
            .map(|h| (h.triangle_index as u32, h.t));
        twin.add(expected, hit(result[0]));
        if brute_force {
            gpu_brute_force.add(hit(result[1]), hit(result[0]));
        }
        let expected_any = bvh_any_hit(&bvh.wide_nodes, &traversal, origin, direction, ray[0][3]);
        any_hit_disagreements += usize::from(expected_any != (result[0][3] != 0));
    }
    twin.assert_agrees(
        &format!("{name}: GPU bvh_closest_hit vs Rust twin"),
        rays.len(),
    );
    assert!(twin.hits * 2 >= rays.len(), "most rays hit: {twin:?}");
    if brute_force {
        gpu_brute_force.assert_agrees(
            &format!("{name}: GPU bvh_closest_hit vs GPU brute force"),
            rays.len(),
        );
    }
    // t_max lies at least 0.5x away from the closest hit, so any-hit has no ties.
    assert_eq!(any_hit_disagreements, 0, "{name}: bvh_any_hit");
    assert_eq!(
        box_test_disagreements, 0,
        "{name}: bvh_ray_box_intersection"
    );
}

#[test]
fn gpu_traversal_matches_the_rust_twins_and_gpu_brute_force() {
    let context = common::validated_context();
    let scene = scale_test_scene(10_000).unwrap();
    let bvh = Bvh::build(&scene.triangles);
    let triangles = bvh.reorder(&scene.triangles);
    let rays = test_rays(2048, &triangles, &bvh);
    let (results, bvh_seconds) = run_probe(&context, &triangles, &bvh, &rays, false);
    check("10^4 triangles", &triangles, &bvh, &rays, &results, false);
    // Brute force tests every triangle per ray (lavapipe: ~7.5 M tests/s on 2 cores), so it
    // gets a quarter of the rays: 512 x 10^4 tests, under a second.
    let rays = &rays[..512];
    let (results, brute_force_seconds) = run_probe(&context, &triangles, &bvh, rays, true);
    check(
        "10^4 triangles with brute force",
        &triangles,
        &bvh,
        rays,
        &results,
        true,
    );
    println!(
        "{} triangles: 2048 rays, BVH closest + any hit: {:.1} ms; 512 rays, BVH and brute force: {:.1} ms",
        triangles.len(),
        bvh_seconds * 1e3,
        brute_force_seconds * 1e3
    );
    common::assert_validation_silent(&context);
}

#[test]
fn gpu_traversal_in_the_cornell_box_matches_gpu_brute_force() {
    // Axis-aligned walls make flat boxes; rays along the axes meet them head-on.
    let context = common::validated_context();
    let scene = vkpath::Scene::builtin_cornell_box().unwrap();
    let bvh = Bvh::build(&scene.triangles);
    let triangles = bvh.reorder(&scene.triangles);
    let rays = test_rays(4096, &triangles, &bvh);
    let (results, bvh_seconds) = run_probe(&context, &triangles, &bvh, &rays, false);
    check("Cornell box", &triangles, &bvh, &rays, &results, false);
    let (results, both_seconds) = run_probe(&context, &triangles, &bvh, &rays, true);
    check(
        "Cornell box with brute force",
        &triangles,
        &bvh,
        &rays,
        &results,
        true,
    );
    println!(
        "Cornell box, 4096 rays: BVH closest + any hit {:.1} ms; with brute force too {:.1} ms",
        bvh_seconds * 1e3,
        both_seconds * 1e3
    );
    common::assert_validation_silent(&context);
}

#[test]
fn gpu_traversal_of_a_large_scene_matches_the_rust_twins() {
    let context = common::validated_context();
    let scene = scale_test_scene(200_000).unwrap();
    let bvh = Bvh::build(&scene.triangles);
    let triangles = bvh.reorder(&scene.triangles);
    let rays = test_rays(4096, &triangles, &bvh);
    let (results, seconds) = run_probe(&context, &triangles, &bvh, &rays, false);
    check("2 10^5 triangles", &triangles, &bvh, &rays, &results, false);
    println!(
        "{} rays, {} triangles: BVH closest + any hit {:.1} ms ({})",
        rays.len(),
        triangles.len(),
        seconds * 1e3,
        bvh.stats()
    );
    common::assert_validation_silent(&context);
}

/// The compressed tree's probe (`SPEC_BVH_LAYOUT` = `BVH_LAYOUT_COMPRESSED`) against its Rust
/// twins `cwbvh_closest_hit` / `cwbvh_any_hit` and the GPU's brute force, with the same
/// tallies as the 4-wide tree's (`check`).
fn check_compressed(
    name: &str,
    scene_triangles: &[Triangle],
    ray_count: usize,
    brute_force: usize,
) {
    let context = common::validated_context();
    let bvh = CompressedBvh::build(scene_triangles).unwrap();
    let triangles = bvh.reorder(scene_triangles);
    let packed = packed_traversal_triangles(&triangles);
    // The 4-wide tree over the same (reordered) triangles only makes the rays
    let wide = Bvh::build(&triangles);
    let rays = test_rays(ray_count, &wide.reorder(&triangles), &wide);
    let layout = (
        bytemuck::cast_slice::<_, u8>(&bvh.nodes),
        bytemuck::cast_slice::<_, u8>(&packed),
        contract::BVH_LAYOUT_COMPRESSED,
    );
    let (results, seconds) = run_probe_with(&context, &triangles, layout, &rays, false);
    let (brute_results, _) =
        run_probe_with(&context, &triangles, layout, &rays[..brute_force], true);
    let mut twin = Tally::default();
    let mut gpu_brute_force = Tally::default();
    let mut any_hit_disagreements = 0;
    for (k, (ray, result)) in rays.iter().zip(&results).enumerate() {
        let origin = Vec3::from_slice(&ray[0][..3]);
        let direction = Vec3::from_slice(&ray[1][..3]);
        let expected = cwbvh_closest_hit(&bvh.nodes, &packed, origin, direction)
            .map(|h| (h.triangle_index as u32, h.t));
        twin.add(expected, hit(result[0]));
        let expected_any = cwbvh_any_hit(&bvh.nodes, &packed, origin, direction, ray[0][3]);
        any_hit_disagreements += usize::from(expected_any != (result[0][3] != 0));
        if let Some(brute) = brute_results.get(k) {
            assert_eq!(
                brute[0], result[0],
                "{name}: the same probe with brute force beside"
            );
            gpu_brute_force.add(hit(brute[1]), hit(brute[0]));
        }
    }
    twin.assert_agrees(
        &format!("{name}: GPU cwbvh_closest_hit vs Rust twin"),
        rays.len(),
    );
    assert!(twin.hits * 2 >= rays.len(), "most rays hit: {twin:?}");
    gpu_brute_force.assert_agrees(
        &format!("{name}: GPU cwbvh_closest_hit vs GPU brute force"),
        brute_force,
    );
    // t_max lies at least 0.5x away from the 4-wide tree's closest hit, the same up to ties
    assert_eq!(any_hit_disagreements, 0, "{name}: cwbvh_any_hit");
    println!(
        "{name}: {} rays, {} triangles, {} compressed nodes: closest + any hit {:.1} ms",
        rays.len(),
        triangles.len(),
        bvh.nodes.len(),
        seconds * 1e3
    );
    common::assert_validation_silent(&context);
}

#[test]
fn gpu_compressed_traversal_matches_the_rust_twins_and_gpu_brute_force() {
    let scene = vkpath::Scene::builtin_cornell_box().unwrap();
    check_compressed("Cornell box, compressed", &scene.triangles, 4096, 4096);
    let scene = scale_test_scene(10_000).unwrap();
    check_compressed("10^4 triangles, compressed", &scene.triangles, 2048, 512);
}
