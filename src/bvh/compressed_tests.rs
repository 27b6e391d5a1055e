//! CPU tests of the compressed wide BVH: node layout, the tree's invariants, the packed
//! triangles, and the traversal twins against brute force.

use std::mem::{offset_of, size_of};

use glam::Vec3;

use super::compressed_traversal::{
    cwbvh_any_hit, cwbvh_closest_hit, cwbvh_octant_inverse, get_packed_traversal_triangle,
};
use super::tests::{
    assert_agrees, compare_traversal_with_brute_force, random_rays, room_box, Agreement,
};
use super::*;
use crate::contract::{CWBVH_NODE_TEXEL_COUNT, CWBVH_STACK_SIZE};
use crate::scene::meshes::{displaced_grid, scale_test_scene, subdivided_sphere};
use crate::scene::Scene;

/// A grey, one-sided triangle at the origin, for its other members.
fn plain() -> Triangle {
    Triangle {
        positions: [Vec3::ZERO; 3],
        normal: Vec3::Z,
        color: Vec3::splat(0.5),
        emission: Vec3::ZERO,
        double_sided: false,
    }
}

#[test]
fn compressed_node_matches_the_node_texels_and_obvhs() {
    // CWBVH_NODE_TEXEL_COUNT texels: origin + exponents/inner mask; child base, triangle
    // base, meta; lower x, upper x; lower y, upper y; lower z, upper z
    assert_eq!(
        size_of::<GpuCompressedBvhNode>(),
        16 * CWBVH_NODE_TEXEL_COUNT as usize
    );
    let offsets = [
        offset_of!(GpuCompressedBvhNode, origin),
        offset_of!(GpuCompressedBvhNode, exponents_inner_mask),
        offset_of!(GpuCompressedBvhNode, child_base),
        offset_of!(GpuCompressedBvhNode, triangle_base),
        offset_of!(GpuCompressedBvhNode, child_meta),
        offset_of!(GpuCompressedBvhNode, lower_x),
        offset_of!(GpuCompressedBvhNode, upper_x),
        offset_of!(GpuCompressedBvhNode, lower_y),
        offset_of!(GpuCompressedBvhNode, upper_y),
        offset_of!(GpuCompressedBvhNode, lower_z),
        offset_of!(GpuCompressedBvhNode, upper_z),
    ];
    assert_eq!(offsets, [0, 12, 16, 20, 24, 32, 40, 48, 56, 64, 72]);
    // The conversion keeps obvhs's bytes (its node is the same 80-byte layout)
    assert_eq!(size_of::<obvhs::cwbvh::node::CwBvhNode>(), 80);
}

#[test]
fn packed_triangles_round_trip_at_every_word_offset() {
    let triangles: Vec<Triangle> = (0..9)
        .map(|i| {
            let f = i as f32;
            Triangle {
                positions: [
                    Vec3::new(f, f + 0.1, f + 0.2),
                    Vec3::new(-f, f32::MIN_POSITIVE, 1e30),
                    Vec3::new(f * 3.0, -0.0, f + 0.5),
                ],
                ..plain()
            }
        })
        .collect();
    let packed = packed_traversal_triangles(&triangles);
    // 9 words each, padded to whole texels
    assert_eq!(packed.len(), (9 * 9usize).div_ceil(4));
    for (i, triangle) in triangles.iter().enumerate() {
        let read = get_packed_traversal_triangle(&packed, i as u32);
        for (a, b) in read.positions.iter().zip(&triangle.positions) {
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits)
            );
        }
    }
}

#[test]
fn octant_inverse_counts_negative_zero_as_positive() {
    assert_eq!(cwbvh_octant_inverse(Vec3::new(1.0, 1.0, 1.0)), 7);
    assert_eq!(cwbvh_octant_inverse(Vec3::new(-0.0, 0.0, -0.0)), 7);
    assert_eq!(cwbvh_octant_inverse(Vec3::new(-1.0, 1.0, 1.0)), 3);
    assert_eq!(cwbvh_octant_inverse(Vec3::new(1.0, -1.0, -1.0)), 4);
}

/// The tree's invariants: `triangle_order` a permutation, every triangle in exactly one
/// leaf, every leaf's triangles inside its (dequantised) box, every interior child's node
/// inside its box, depth within the stack.
fn check_compressed_structure(bvh: &CompressedBvh, triangles: &[Triangle]) {
    let mut sorted = bvh.triangle_order.clone();
    sorted.sort_unstable();
    assert!(sorted.iter().copied().eq(0..triangles.len() as u32));
    assert!(bvh.max_interior_depth < CWBVH_STACK_SIZE);
    let ordered = bvh.reorder(triangles);
    let mut referenced = vec![0u32; triangles.len()];
    let mut visited = vec![false; bvh.nodes.len()];
    // Nodes to check, with their ancestors' boxes of them (which must hold their triangles)
    let mut stack: Vec<(u32, Vec<(Vec3, Vec3)>)> = vec![(0, Vec::new())];
    // A box holds a point with a relative slack of 1e-6 (quantisation rounds outwards, but
    // the dequantised planes are rounded floats)
    let inside = |(lower, upper): (Vec3, Vec3), p: Vec3| {
        let slack = 1e-6 * (upper - lower).abs().max(p.abs()) + 1e-30;
        p.cmpge(lower - slack).all() && p.cmple(upper + slack).all()
    };
    while let Some((index, ancestors)) = stack.pop() {
        assert!(!visited[index as usize], "node {index} visited twice");
        visited[index as usize] = true;
        let node = &bvh.nodes[index as usize];
        let mut leaf_triangles = 0;
        for slot in 0..8u32 {
            let meta = node.child_meta[slot as usize];
            if meta == 0 {
                continue;
            }
            let mut boxes = ancestors.clone();
            boxes.push(node.child_box(slot as usize));
            if node.inner_mask() & (1 << slot) != 0 {
                assert_eq!(meta, 0b0010_0000 | (24 + slot as u8), "interior meta");
                stack.push((compressed_child_node(node, slot), boxes));
            } else {
                let count = u32::from(meta >> 5).count_ones();
                assert!((1..=3).contains(&count), "meta {meta:#010b}");
                assert_eq!(u32::from(meta >> 5), (1 << count) - 1, "unary count");
                let first = node.triangle_base + u32::from(meta & 31);
                leaf_triangles += count;
                for i in first..first + count {
                    referenced[i as usize] += 1;
                    for p in ordered[i as usize].positions {
                        assert!(
                            boxes.iter().all(|&b| inside(b, p)),
                            "triangle {i} outside a box above it"
                        );
                    }
                }
            }
        }
        assert!(leaf_triangles <= 24);
    }
    assert!(
        referenced.iter().all(|&n| n == 1),
        "a triangle in 0 or 2 leaves"
    );
    assert!(visited.iter().all(|&v| v), "an unreachable node");
}

fn compare_compressed_with_brute_force(triangles: &[Triangle], rays: &[(Vec3, Vec3)]) -> Agreement {
    let bvh = CompressedBvh::build(triangles).unwrap();
    check_compressed_structure(&bvh, triangles);
    let packed = packed_traversal_triangles(&bvh.reorder(triangles));
    compare_traversal_with_brute_force(
        triangles,
        rays,
        &bvh.triangle_order,
        |origin, direction| cwbvh_closest_hit(&bvh.nodes, &packed, origin, direction),
        |origin, direction, t_max| cwbvh_any_hit(&bvh.nodes, &packed, origin, direction, t_max),
    )
}

#[test]
fn compressed_closest_and_any_hit_match_brute_force_in_the_cornell_box() {
    let scene = Scene::builtin_cornell_box().unwrap();
    let rays = random_rays(20_000, room_box(), 1);
    assert_agrees(
        "Cornell box, compressed",
        &compare_compressed_with_brute_force(&scene.triangles, &rays),
    );
}

#[test]
fn compressed_closest_and_any_hit_match_brute_force_on_generated_meshes() {
    let sphere = subdivided_sphere(4, Vec3::new(0.1, 0.2, 0.3), 1.0, Vec3::ONE, Vec3::ZERO);
    let around_sphere = Aabb {
        lower: Vec3::splat(-1.0),
        upper: Vec3::splat(1.0),
    };
    let rays = random_rays(4_000, around_sphere, 2);
    assert_agrees(
        "icosphere, compressed",
        &compare_compressed_with_brute_force(&sphere, &rays),
    );

    let grid = displaced_grid(60, Vec3::ZERO, Vec3::X, Vec3::Y, 0.1, Vec3::ONE);
    let above_grid = Aabb {
        lower: Vec3::new(0.0, 0.0, -0.3),
        upper: Vec3::new(1.0, 1.0, 0.3),
    };
    let rays = random_rays(4_000, above_grid, 3);
    assert_agrees(
        "displaced grid, compressed",
        &compare_compressed_with_brute_force(&grid, &rays),
    );

    let scene = scale_test_scene(20_000).unwrap();
    let rays = random_rays(2_000, room_box(), 4);
    assert_agrees(
        "scale test scene, compressed",
        &compare_compressed_with_brute_force(&scene.triangles, &rays),
    );
}

#[test]
fn compressed_tree_handles_empty_single_and_degenerate_input() {
    let empty = CompressedBvh::build(&[]).unwrap();
    assert!(empty.nodes.is_empty() && empty.triangle_order.is_empty());
    assert!(cwbvh_closest_hit(&[], &[], Vec3::ZERO, Vec3::X).is_none());
    assert!(!cwbvh_any_hit(&[], &[], Vec3::ZERO, Vec3::X, 1e30));

    let one = vec![Triangle {
        positions: [
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(1.0, 1.0, -1.0),
            Vec3::new(1.0, 0.0, 1.0),
        ],
        ..plain()
    }];
    let rays = [
        (Vec3::ZERO, Vec3::X),
        (Vec3::ZERO, -Vec3::X),
        (Vec3::new(0.0, 0.1, 0.1), Vec3::X),
    ];
    let agreement = compare_compressed_with_brute_force(&one, &rays);
    assert_eq!(
        (agreement.mismatches, agreement.hits),
        (0, 2),
        "{agreement:?}"
    );

    // Points, segments and coincident triangles still get leaves
    let mut degenerate = Vec::new();
    for i in 0..50 {
        let p = Vec3::new(0.5, i as f32 * 0.01, 0.0);
        degenerate.push(Triangle {
            positions: [p, p, p],
            ..plain()
        });
        degenerate.push(Triangle {
            positions: [p, p + Vec3::Y * 0.01, p + Vec3::Y * 0.02],
            ..plain()
        });
        degenerate.push(one[0]);
    }
    let rays = random_rays(500, room_box(), 9);
    let agreement = compare_compressed_with_brute_force(&degenerate, &rays);
    assert_eq!(agreement.mismatches, 0, "{agreement:?}");
}

#[test]
fn a_tree_deeper_than_the_stack_is_refused_with_one_line() {
    // A chain of nodes, each with one interior child (slot 0) and one leaf (slot 1): interior
    // depth 39, deeper than the CWBVH_STACK_SIZE groups the traversal can hold
    let chain: Vec<GpuCompressedBvhNode> = (0..40u32)
        .map(|i| {
            let mut node = GpuCompressedBvhNode {
                child_base: i + 1,
                triangle_base: i,
                ..GpuCompressedBvhNode::default()
            };
            if i < 39 {
                node.exponents_inner_mask[3] = 1;
                node.child_meta[0] = 0b0010_0000 | 24;
            }
            node.child_meta[1] = 0b0010_0000;
            node
        })
        .collect();
    let message = CompressedBvh::checked(chain.clone(), (0..40).collect(), 40)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("40 levels deep") && !message.contains('\n'),
        "{message}"
    );
    // 32 nodes deep (the deepest at depth 31): within the stack, accepted
    let mut shallow = chain[8..].to_vec();
    for (i, node) in shallow.iter_mut().enumerate() {
        node.child_base = i as u32 + 1;
    }
    let bvh = CompressedBvh::checked(shallow, (0..32).collect(), 32).unwrap();
    assert_eq!(bvh.max_interior_depth, 31);
}

#[test]
fn a_scene_too_large_to_quantise_is_refused_with_one_line() {
    let far = Triangle {
        positions: [
            Vec3::ZERO,
            Vec3::new(3e38, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        ..plain()
    };
    let message = CompressedBvh::build(&[far, plain()])
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("too far") && !message.contains('\n'),
        "{message}"
    );
    let too_far = subdivided_sphere(2, Vec3::ZERO, 1e15, Vec3::ONE, Vec3::ZERO);
    assert!(CompressedBvh::build(&too_far).is_err());
    // Large and small but within range: they still match brute force (at 1e-15 neither tree
    // does: the triangle test's own tolerances, not the trees, decide there)
    for radius in [1e14, 1e-4] {
        let sphere = subdivided_sphere(2, Vec3::ZERO, radius, Vec3::ONE, Vec3::ZERO);
        let around = Aabb {
            lower: Vec3::splat(-radius),
            upper: Vec3::splat(radius),
        };
        let rays = random_rays(500, around, 5);
        let agreement = compare_compressed_with_brute_force(&sphere, &rays);
        assert_eq!(agreement.mismatches, 0, "radius {radius}: {agreement:?}");
    }
}
