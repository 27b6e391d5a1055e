//! CPU tests of the BVH: node layout, the builder's invariants, and the traversal twins
//! against brute force (`cpu::integrator::ray_mesh_intersection`).

use std::mem::{offset_of, size_of};

use glam::{UVec2, Vec3};

use super::*;
use crate::cpu::integrator::{ray_mesh_intersection, MeshHit};
use crate::cpu::workshop::{get_random_numbers, sample_sphere};
use crate::scene::meshes::{displaced_grid, scale_test_scene, subdivided_sphere};
use crate::scene::Scene;

#[test]
fn node_matches_std430_bvh_node_t() {
    // struct bvh_node_t { vec4 lower; vec4 upper; }
    assert_eq!(size_of::<GpuBvhNode>(), 32);
    assert_eq!(offset_of!(GpuBvhNode, lower), 0);
    assert_eq!(offset_of!(GpuBvhNode, upper), 16);
    let bounds = Aabb {
        lower: Vec3::new(-1.0, -2.0, -3.0),
        upper: Vec3::new(1.0, 2.0, 3.0),
    };
    // Indices whose bits are denormals, infinity and NaN survive as bits.
    for index in [0u32, 1, 5, 0x7F80_0000, 0x7FC0_0001, u32::MAX] {
        let leaf = GpuBvhNode::leaf(&bounds, index, 3);
        assert_eq!((leaf.first_index(), leaf.triangle_count()), (index, 3));
        assert!(leaf.is_leaf());
        let copied: GpuBvhNode = bytemuck::pod_read_unaligned(bytemuck::bytes_of(&leaf));
        assert_eq!(copied.first_index(), index);
        let interior = GpuBvhNode::interior(&bounds, index);
        assert!(!interior.is_leaf());
        assert_eq!(interior.bounds(), bounds);
    }
}

#[test]
fn wide_node_matches_the_wide_node_texels() {
    // WIDE_BVH_NODE_TEXEL_COUNT texels: lower x, upper x, lower y, upper y, lower z, upper z
    // of the four children, then their references
    assert_eq!(
        size_of::<GpuWideBvhNode>(),
        16 * crate::contract::WIDE_BVH_NODE_TEXEL_COUNT as usize
    );
    let offsets = [
        offset_of!(GpuWideBvhNode, lower_x),
        offset_of!(GpuWideBvhNode, upper_x),
        offset_of!(GpuWideBvhNode, lower_y),
        offset_of!(GpuWideBvhNode, upper_y),
        offset_of!(GpuWideBvhNode, lower_z),
        offset_of!(GpuWideBvhNode, upper_z),
        offset_of!(GpuWideBvhNode, children),
    ];
    assert_eq!(offsets, [0, 16, 32, 48, 64, 80, 96]);
    // A leaf's reference: its count above WIDE_BVH_LEAF_COUNT_SHIFT, its first triangle below
    let reference = leaf_reference(0xAB_CDEF, 16);
    assert_eq!(
        (
            traversal::get_bvh_child_index(reference),
            traversal::get_bvh_leaf_triangle_count(reference)
        ),
        (0xAB_CDEF, 16)
    );
    assert_eq!(traversal::get_bvh_leaf_triangle_count(7), 0);
}

#[test]
fn a_tree_whose_paths_would_overflow_the_wide_stack_stays_binary() {
    // A spine of 40 interior nodes, each with a small interior child that continues the
    // spine and a large sibling of three leaves under two levels: collapsed 4 wide, each
    // spine node pushes the sibling's three leaves (120 entries down the spine), more than
    // WIDE_BVH_STACK_SIZE, so the binary tree is kept, two children per node.
    let unit = |size: f32| Aabb {
        lower: Vec3::ZERO,
        upper: Vec3::splat(size),
    };
    let mut nodes = vec![GpuBvhNode::default()];
    let mut spine = 0usize;
    for level in 0..40 {
        let first = nodes.len();
        // children: the spine's next node (small) and the large sibling
        nodes.extend([GpuBvhNode::default(); 2]);
        nodes[spine] = GpuBvhNode::interior(&unit(10.0 - 0.1 * level as f32), first as u32);
        let sibling = first + 1;
        let grandchildren = nodes.len();
        nodes.extend([GpuBvhNode::default(); 2]);
        nodes[sibling] = GpuBvhNode::interior(&unit(50.0), grandchildren as u32);
        let leaves = nodes.len();
        nodes.extend([GpuBvhNode::leaf(&unit(1.0), level, 1); 2]);
        nodes[grandchildren] = GpuBvhNode::interior(&unit(40.0), leaves as u32);
        nodes[grandchildren + 1] = GpuBvhNode::leaf(&unit(30.0), 100 + level, 1);
        spine = first;
    }
    nodes[spine] = GpuBvhNode::leaf(&unit(0.5), 1000, 1);
    let four_wide = wide::widen_to(&nodes, 4);
    assert_eq!(most_pushes(&four_wide), 3 * 40);
    let wide = widen(&nodes);
    assert!(most_pushes(&wide) <= crate::contract::WIDE_BVH_STACK_SIZE as usize);
    assert!(wide.iter().all(|node| node.children[2] == 0));
    let interior = nodes.iter().filter(|node| !node.is_leaf()).count();
    assert_eq!(wide.len(), interior);
}

#[test]
fn traversal_triangle_matches_traversal_triangle_texels() {
    // TRAVERSAL_TRIANGLE_TEXEL_COUNT texels: v_0, v_1, v_2 in xyz, w unused
    assert_eq!(
        size_of::<GpuTraversalTriangle>(),
        16 * crate::contract::TRAVERSAL_TRIANGLE_TEXEL_COUNT as usize
    );
    assert_eq!(offset_of!(GpuTraversalTriangle, positions), 0);
    let triangle = Triangle {
        positions: [
            Vec3::new(1.0, -2.5, 3.0e-38),
            Vec3::new(f32::MIN_POSITIVE / 4.0, 5.0, -0.0),
            Vec3::new(0.1, 0.2, 0.3),
        ],
        normal: Vec3::Z,
        color: Vec3::ONE,
        emission: Vec3::splat(2.0),
        double_sided: true,
    };
    let packed = GpuTraversalTriangle::new(&triangle);
    let words: &[u32] = bytemuck::cast_slice(std::slice::from_ref(&packed));
    for (vertex, position) in triangle.positions.iter().enumerate() {
        for (axis, value) in position.to_array().iter().enumerate() {
            assert_eq!(words[4 * vertex + axis], value.to_bits());
        }
        assert_eq!(words[4 * vertex + 3], 0);
    }
    // The twin of get_traversal_triangle() gives the positions bit for bit, zeros elsewhere.
    let unpacked = get_traversal_triangle(&[packed], 0);
    for (a, b) in unpacked.positions.iter().zip(&triangle.positions) {
        assert_eq!(
            a.to_array().map(f32::to_bits),
            b.to_array().map(f32::to_bits)
        );
    }
    assert_eq!(
        (unpacked.normal, unpacked.color, unpacked.emission),
        (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO)
    );
}

#[test]
fn slab_test_handles_axis_parallel_rays_and_flat_boxes() {
    let lower = Vec3::new(0.0, 0.0, 0.0);
    let upper = Vec3::new(1.0, 1.0, 0.0); // flat, like a Cornell box wall's triangle
    let down = Vec3::new(0.0, 0.0, -1.0);
    let inverse = bvh_inverse_direction(down);
    assert!(inverse.is_finite());
    let origin = Vec3::new(0.5, 0.5, 2.0);
    assert_eq!(
        bvh_ray_box_intersection(origin, inverse, lower, upper, 1e38),
        Some(2.0)
    );
    // Too short a segment, a box behind the origin, a ray beside the box
    assert_eq!(
        bvh_ray_box_intersection(origin, inverse, lower, upper, 1.5),
        None
    );
    assert_eq!(
        bvh_ray_box_intersection(origin, -inverse, lower, upper, 1e38),
        None
    );
    let beside = Vec3::new(1.5, 0.5, 2.0);
    assert_eq!(
        bvh_ray_box_intersection(beside, inverse, lower, upper, 1e38),
        None
    );
    // A ray in the plane of a face (origin on the face x = 0 of a cube, direction +y): the
    // slab x gives 0 * 1e30 = 0 and 1 * 1e30, no NaN
    let along = bvh_inverse_direction(Vec3::Y);
    let on_face = Vec3::new(0.0, -1.0, 0.5);
    let cube = Vec3::ONE;
    assert_eq!(
        bvh_ray_box_intersection(on_face, along, lower, cube, 1e38),
        Some(1.0)
    );
    // Inside: enters at 0
    let inside = Vec3::new(0.5, 0.5, 0.5);
    assert_eq!(
        bvh_ray_box_intersection(inside, along, lower, cube, 1e38),
        Some(0.0)
    );
    // A ray in the plane of a flat box misses it; so does it every triangle inside, to which
    // it is parallel (ray_triangle_intersection's determinant is 0)
    let in_plane = Vec3::new(0.5, -1.0, 0.0);
    assert_eq!(
        bvh_ray_box_intersection(in_plane, along, lower, upper, 1e38),
        None
    );
    // -0.0 counts as positive, as in GLSL's greaterThanEqual
    assert_eq!(bvh_inverse_direction(Vec3::new(-0.0, 1.0, -2.0)).x, 1e30);
}

#[test]
fn empty_input_gives_an_empty_bvh_that_misses() {
    let bvh = Bvh::build(&[]);
    assert!(bvh.nodes.is_empty() && bvh.triangle_order.is_empty());
    assert_eq!(
        bvh_closest_hit(&bvh.wide_nodes, &[], Vec3::ZERO, Vec3::X),
        None
    );
    assert!(!bvh_any_hit(
        &bvh.wide_nodes,
        &[],
        Vec3::ZERO,
        Vec3::X,
        1e30
    ));
    assert_eq!(bvh.stats(), BvhStats::default());
}

/// Checks what the traversal relies on: every triangle in exactly one leaf, leaves holding
/// contiguous ranges of the reordered triangles, every box inside its parent's, no leaf
/// deeper than `MAX_DEPTH`.
fn check_structure(bvh: &Bvh, triangles: &[Triangle]) {
    let n = triangles.len();
    let mut order = bvh.triangle_order.clone();
    order.sort_unstable();
    assert!(
        order.iter().copied().eq(0..n as u32),
        "triangle_order is a permutation"
    );
    let reordered = bvh.reorder(triangles);
    let mut referenced = vec![0u32; n];
    let mut stack = vec![(0usize, 0u32, None::<Aabb>)];
    while let Some((index, depth, parent)) = stack.pop() {
        let node = &bvh.nodes[index];
        let bounds = node.bounds();
        if let Some(parent) = parent {
            assert!(
                parent.contains(&bounds),
                "child box {index} inside its parent's"
            );
        }
        if node.is_leaf() {
            assert!(depth <= MAX_DEPTH);
            let first = node.first_index() as usize;
            for (i, triangle) in reordered[first..first + node.triangle_count() as usize]
                .iter()
                .enumerate()
            {
                referenced[first + i] += 1;
                assert!(bounds.contains(&Aabb::of_triangle(&triangle.positions)));
            }
        } else {
            let first = node.first_index() as usize;
            assert!(first > index && first + 1 < bvh.nodes.len());
            stack.push((first, depth + 1, Some(bounds)));
            stack.push((first + 1, depth + 1, Some(bounds)));
        }
    }
    assert!(
        referenced.iter().all(|&c| c == 1),
        "each triangle in exactly one leaf"
    );
    let stats = bvh.stats();
    assert_eq!(
        stats.node_count,
        bvh.nodes.len(),
        "every node reachable once"
    );
    assert_eq!(stats.triangle_count, n);
    assert_eq!(stats.node_count, 2 * stats.leaf_count - 1);
    check_wide_structure(bvh);
}

/// The wide tree holds the binary tree's leaves, each once, with their boxes, under nodes of
/// 2 to 4 children (1 for a leaf root), and no path pushes more than the stack holds.
fn check_wide_structure(bvh: &Bvh) {
    use crate::contract::{WIDE_BVH_EMPTY_CHILD, WIDE_BVH_STACK_SIZE};
    let binary_leaves: std::collections::HashMap<u32, Aabb> = bvh
        .nodes
        .iter()
        .filter(|node| node.is_leaf())
        .map(|node| {
            (
                leaf_reference(node.first_index(), node.triangle_count()),
                node.bounds(),
            )
        })
        .collect();
    let mut leaves_seen = std::collections::HashSet::new();
    let mut nodes_seen = vec![0u32; bvh.wide_nodes.len()];
    nodes_seen[0] = 1;
    for node in &bvh.wide_nodes {
        let used = node
            .children
            .iter()
            .take_while(|&&c| c != WIDE_BVH_EMPTY_CHILD)
            .count();
        assert!(node.children[used..]
            .iter()
            .all(|&c| c == WIDE_BVH_EMPTY_CHILD));
        assert!(used >= 2 || bvh.wide_nodes.len() == 1 && used == 1);
        for (slot, &child) in node.children[..used].iter().enumerate() {
            if traversal::get_bvh_leaf_triangle_count(child) != 0 {
                assert_eq!(
                    binary_leaves[&child],
                    node.child_bounds(slot),
                    "a leaf's box"
                );
                assert!(leaves_seen.insert(child), "each leaf once");
            } else {
                nodes_seen[child as usize] += 1;
            }
        }
    }
    assert_eq!(leaves_seen.len(), binary_leaves.len(), "every leaf");
    assert!(nodes_seen.iter().all(|&c| c == 1), "every wide node once");
    let interior = bvh.nodes.len() - binary_leaves.len();
    assert!(bvh.wide_nodes.len() <= interior.max(1));
    assert!(most_pushes(&bvh.wide_nodes) <= WIDE_BVH_STACK_SIZE as usize);
}

/// Random rays: origins in `origin_box` (grown by 10% so some start outside the mesh),
/// directions uniform on the sphere, from a fixed PCG2D seed.
pub(super) fn random_rays(count: usize, origin_box: Aabb, seed: u32) -> Vec<(Vec3, Vec3)> {
    let mut state = UVec2::new(seed, 0x9E37_79B9);
    let centre = origin_box.centre();
    let half = 0.55 * origin_box.extent();
    (0..count)
        .map(|_| {
            let a = get_random_numbers(&mut state);
            let b = get_random_numbers(&mut state);
            let u = Vec3::new(a.x, a.y, b.x) * 2.0 - 1.0;
            let origin = centre + u * half;
            let direction = sample_sphere(get_random_numbers(&mut state));
            (origin, direction)
        })
        .collect()
}

/// How the BVH's answers compared with brute force.
#[derive(Debug, Default)]
pub(super) struct Agreement {
    pub(super) rays: usize,
    pub(super) hits: usize,
    /// Different triangles at t equal within 1e-6 relative (ties and near-ties that rounding
    /// in different triangles' Cramer's rule decides).
    pub(super) near_ties: usize,
    /// Anything else: a hit missed or found, a different t, a wrong any-hit answer.
    pub(super) mismatches: usize,
}

fn compare_with_brute_force(triangles: &[Triangle], rays: &[(Vec3, Vec3)]) -> Agreement {
    let bvh = Bvh::build(triangles);
    check_structure(&bvh, triangles);
    let reordered = traversal_triangles(&bvh.reorder(triangles));
    compare_traversal_with_brute_force(
        triangles,
        rays,
        &bvh.triangle_order,
        |origin, direction| bvh_closest_hit(&bvh.wide_nodes, &reordered, origin, direction),
        |origin, direction, t_max| {
            bvh_any_hit(&bvh.wide_nodes, &reordered, origin, direction, t_max)
        },
    )
}

/// How a tree's traversal (`closest_hit` and `any_hit` over its triangles in leaf order,
/// `triangle_order[leaf index]` being the scene's index) agrees with the brute-force
/// `ray_mesh_intersection` over `triangles` on `rays`; shared by the 4-wide and the
/// compressed tree's tests.
pub(super) fn compare_traversal_with_brute_force(
    triangles: &[Triangle],
    rays: &[(Vec3, Vec3)],
    triangle_order: &[u32],
    closest_hit: impl Fn(Vec3, Vec3) -> Option<MeshHit>,
    any_hit: impl Fn(Vec3, Vec3, f32) -> bool,
) -> Agreement {
    let mut agreement = Agreement::default();
    let mut state = UVec2::new(7, 11);
    for &(origin, direction) in rays {
        agreement.rays += 1;
        let expected = ray_mesh_intersection(triangles, origin, direction);
        let actual = closest_hit(origin, direction);
        match (expected, actual) {
            (None, None) => {}
            (Some(e), Some(a)) => {
                agreement.hits += 1;
                let original = triangle_order[a.triangle_index] as usize;
                if original != e.triangle_index {
                    // Rounding in the two triangles' tests decides a tie: 1e-6 relative is
                    // ~8 ulps, the error bound of Cramer's rule at these sizes.
                    if (a.t - e.t).abs() <= 1e-6 * e.t.max(1e-3) {
                        agreement.near_ties += 1;
                    } else {
                        agreement.mismatches += 1;
                    }
                } else if a.t != e.t {
                    agreement.mismatches += 1; // same function, same triangle: same bits
                }
            }
            _ => agreement.mismatches += 1,
        }
        // Any-hit with t_max on either side of the closest hit (or far for misses).
        let factor = 0.5 + get_random_numbers(&mut state).x;
        let t_max = expected.map_or(1e30, |e| e.t * factor);
        let expected_any = expected.is_some_and(|e| e.t < t_max);
        if any_hit(origin, direction, t_max) != expected_any {
            agreement.mismatches += 1;
        }
    }
    agreement
}

pub(super) fn assert_agrees(name: &str, agreement: &Agreement) {
    println!("{name}: {agreement:?}");
    assert_eq!(agreement.mismatches, 0, "{name}: {agreement:?}");
    // Random rays tie only where they hit an edge or vertex exactly: rare.
    assert!(
        agreement.near_ties * 100 <= agreement.rays,
        "{name}: {agreement:?}"
    );
    // The rays should exercise hits (origins inside closed meshes always hit something).
    assert!(agreement.hits * 5 >= agreement.rays, "{name}: too few hits");
}

pub(super) fn room_box() -> Aabb {
    Aabb {
        lower: Vec3::new(0.0, -0.56, 0.0),
        upper: Vec3::new(0.556, 0.0, 0.549),
    }
}

#[test]
fn closest_and_any_hit_match_brute_force_in_the_cornell_box() {
    let scene = Scene::builtin_cornell_box().unwrap();
    let rays = random_rays(20_000, room_box(), 1);
    assert_agrees(
        "Cornell box",
        &compare_with_brute_force(&scene.triangles, &rays),
    );
}

#[test]
fn closest_and_any_hit_match_brute_force_on_generated_meshes() {
    let sphere = subdivided_sphere(4, Vec3::new(0.1, 0.2, 0.3), 1.0, Vec3::ONE, Vec3::ZERO);
    let around_sphere = Aabb {
        lower: Vec3::splat(-1.0),
        upper: Vec3::splat(1.0),
    };
    let rays = random_rays(4_000, around_sphere, 2);
    assert_agrees("icosphere", &compare_with_brute_force(&sphere, &rays));

    let grid = displaced_grid(60, Vec3::ZERO, Vec3::X, Vec3::Y, 0.1, Vec3::ONE);
    let above_grid = Aabb {
        lower: Vec3::new(0.0, 0.0, -0.3),
        upper: Vec3::new(1.0, 1.0, 0.3),
    };
    let rays = random_rays(4_000, above_grid, 3);
    assert_agrees("displaced grid", &compare_with_brute_force(&grid, &rays));

    let scene = scale_test_scene(20_000).unwrap();
    let rays = random_rays(2_000, room_box(), 4);
    assert_agrees(
        "scale test scene",
        &compare_with_brute_force(&scene.triangles, &rays),
    );
}

#[test]
fn the_depth_limit_makes_leaves_and_traversal_still_matches() {
    // Parallel triangles at x = 2^k 1e-6, of size x / 10: an unbalanced tree (depth ~20)
    // that a limit of 5 cuts into large leaves.
    let triangles: Vec<Triangle> = (0..50)
        .map(|k| {
            let x = 2.0f32.powi(k) * 1e-6;
            let s = 0.1 * x;
            let p = [
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x, s, 0.0),
                Vec3::new(x, 0.0, s),
            ];
            Triangle::new(p, Vec3::ONE, Vec3::ZERO, false).unwrap()
        })
        .collect();
    let unlimited = Bvh::build(&triangles).stats();
    let bvh = Bvh::build_with_max_depth(&triangles, 5);
    let stats = bvh.stats();
    assert!(unlimited.max_depth > 5, "{unlimited}");
    assert_eq!(stats.max_depth, 5, "{stats}");
    assert!(stats.max_leaf_size as usize > MAX_LEAF_SIZE, "{stats}");
    check_structure(&bvh, &triangles);
    let reordered = traversal_triangles(&bvh.reorder(&triangles));
    // Rays along the x axis cross all but the smallest triangles, and random rays.
    let near_axis = |i: usize| Vec3::new(0.0, 1e-9 * (1 + i) as f32, 1e-9);
    let mut rays: Vec<(Vec3, Vec3)> = (0..200)
        .map(|i| (near_axis(i) - Vec3::X, Vec3::X))
        .collect();
    rays.extend((0..200).map(|i| (near_axis(i) + 1e30 * Vec3::X, -Vec3::X)));
    let span = Aabb {
        lower: Vec3::ZERO,
        upper: Vec3::splat(1.0),
    };
    rays.extend(random_rays(1_000, span, 5));
    let mut hits = 0;
    for (origin, direction) in rays {
        let expected = ray_mesh_intersection(&triangles, origin, direction);
        let actual = bvh_closest_hit(&bvh.wide_nodes, &reordered, origin, direction);
        let actual = actual.map(|a| (bvh.triangle_order[a.triangle_index] as usize, a.t));
        assert_eq!(actual, expected.map(|e| (e.triangle_index, e.t)));
        hits += usize::from(actual.is_some());
    }
    assert!(hits >= 400);
    println!("depth limit 5: {stats} (unlimited: {unlimited})");
}

#[test]
fn coincident_triangles_are_halved_into_small_leaves() {
    // Copies of one triangle: all centroids coincide, no plane separates them.
    let triangle = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], Vec3::ONE, Vec3::ZERO, false);
    let triangles = vec![triangle.unwrap(); 200];
    let bvh = Bvh::build(&triangles);
    let stats = bvh.stats();
    assert!(stats.max_leaf_size as usize <= MAX_LEAF_SIZE, "{stats}");
    let span = Aabb {
        lower: Vec3::splat(-0.5),
        upper: Vec3::splat(1.5),
    };
    let agreement = compare_with_brute_force(&triangles, &random_rays(1_000, span, 6));
    println!("copies: {agreement:?}, {stats}");
    // Every hit is a tie among 200 copies; the BVH reports one of them at the same t.
    assert_eq!(agreement.mismatches, 0);
}

#[test]
fn build_time_per_million_triangles() {
    let scene = scale_test_scene(1_000_000).unwrap();
    let n = scene.triangles.len();
    let start = std::time::Instant::now();
    let bvh = Bvh::build(&scene.triangles);
    let seconds = start.elapsed().as_secs_f64();
    let stats = bvh.stats();
    let node_bytes_per_triangle = bvh.node_bytes() as f64 / n as f64;
    println!(
        "BVH over {n} triangles: {:.3} s ({:.3} s per million triangles, {} rayon threads); {stats}; \
         GPU bytes per triangle: 96 (triangle) + 48 (traversal positions) + {node_bytes_per_triangle:.1} (nodes)",
        seconds,
        seconds * 1e6 / n as f64,
        rayon::current_num_threads()
    );
    assert!(stats.max_depth <= MAX_DEPTH);
    assert_eq!(stats.triangle_count, n);
    // A well-built SAH tree costs tens of triangle tests per ray here, not n (brute force);
    // 200 leaves a wide margin while catching a broken builder (e.g. one without splits).
    assert!(stats.sah_cost < 200.0, "{stats}");
}
