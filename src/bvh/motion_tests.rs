//! CPU tests of motion blur's BVH (`motion`): its boxes lerped at any time hold the triangles
//! at that time, its closest hits are brute force's, its texels are the kernel's layout, and
//! on a sliding grid a ray at one time does about the work of a still tree's ray (the 1.5x
//! goal of issue 55), where a tree over the triangles' boxes across the shutter does far more.

use glam::{Quat, UVec2, Vec3};

use super::motion::{
    bvh_enter_moving_children, get_motion_bvh_node_texel_count, get_motion_segment, mix,
};
use super::traversal::{bvh_enter_children, bvh_inverse_direction, EnteredChildren};
use super::*;
use crate::contract::{NO_HIT_T, WIDE_BVH_EMPTY_CHILD, WIDE_BVH_INDEX_MASK};
use crate::cpu::workshop::{get_random_numbers, ray_triangle_intersection};

/// Vertices of moving triangles: `[k][i]` is triangle i at key k.
type Keys = Vec<Vec<[Vec3; 3]>>;

fn key_boxes(keys: &Keys) -> Vec<Vec<Aabb>> {
    keys.iter()
        .map(|key| key.iter().map(Aabb::of_triangle).collect())
        .collect()
}

/// Triangle i at `time` as the kernel places it: each vertex lerped between the two keys
/// around the time (`get_moving_packed_triangle`).
fn triangle_at(keys: &Keys, i: usize, time: f32) -> Triangle {
    let (key, fraction) = get_motion_segment(time, keys.len() as u32);
    let (a, b) = (keys[key as usize][i], keys[key as usize + 1][i]);
    let positions: [Vec3; 3] = std::array::from_fn(|v| {
        Vec3::new(
            mix(a[v].x, b[v].x, fraction),
            mix(a[v].y, b[v].y, fraction),
            mix(a[v].z, b[v].z, fraction),
        )
    });
    Triangle {
        positions,
        normal: Vec3::Z,
        color: Vec3::ONE,
        emission: Vec3::ZERO,
        double_sided: false,
    }
}

/// `count` small triangles scattered in a unit cube, each translated, rotated about its own
/// centre and scaled across `steps` keys by its own random amounts (curved paths between the
/// keys' poses, linear between two keys as the kernel moves them).
fn tumbling_triangles(count: usize, steps: usize, seed: u32) -> Keys {
    let mut state = UVec2::new(seed, 0x5eed);
    let shapes: Vec<([Vec3; 3], Vec3, Vec3, Quat)> = (0..count)
        .map(|_| {
            let centre = get_random_numbers(&mut state).extend(get_random_numbers(&mut state).x);
            let corners = std::array::from_fn(|_| {
                (get_random_numbers(&mut state).extend(get_random_numbers(&mut state).y)
                    - Vec3::splat(0.5))
                    * 0.1
            });
            let travel = (get_random_numbers(&mut state).extend(0.5) - Vec3::splat(0.5)) * 0.3;
            let axis = (get_random_numbers(&mut state).extend(1.0) - Vec3::splat(0.5)).normalize();
            let turn = Quat::from_axis_angle(axis, 3.0 * get_random_numbers(&mut state).x);
            (corners, centre, travel, turn)
        })
        .collect();
    (0..steps)
        .map(|k| {
            let s = k as f32 / (steps - 1) as f32;
            shapes
                .iter()
                .map(|(corners, centre, travel, turn)| {
                    let rotation = Quat::IDENTITY.slerp(*turn, s);
                    corners.map(|c| *centre + travel * s + rotation * c * (1.0 + 0.5 * s))
                })
                .collect()
        })
        .collect()
}

/// Every child box of every node, lerped at `time`, holds what lies below it at that time:
/// a leaf child's triangles, an interior child's own children's boxes.
fn check_boxes_hold_their_subtrees(motion: &MotionBvh, keys: &Keys, time: f32) {
    let order = &motion.bvh.triangle_order;
    for index in 0..motion.bvh.wide_nodes.len() as u32 {
        let node = motion.node_at_time(index, time);
        for slot in 0..4 {
            let child = node.children[slot];
            if child == WIDE_BVH_EMPTY_CHILD {
                continue;
            }
            let bounds = node.child_bounds(slot);
            let first = child & WIDE_BVH_INDEX_MASK;
            let count = traversal::get_bvh_leaf_triangle_count(child);
            if count == 0 {
                let below = motion.node_at_time(first, time);
                for inner in 0..4 {
                    if below.children[inner] != WIDE_BVH_EMPTY_CHILD {
                        let inner_box = below.child_bounds(inner);
                        assert!(
                            bounds.contains(&inner_box),
                            "node {index} slot {slot} at {time}: {bounds:?} misses {inner_box:?}"
                        );
                    }
                }
            } else {
                for stored in first..first + count {
                    let triangle = triangle_at(keys, order[stored as usize] as usize, time);
                    for p in triangle.positions {
                        assert!(
                            p.cmpge(bounds.lower).all() && p.cmple(bounds.upper).all(),
                            "leaf at node {index} slot {slot}, time {time}: {p} outside {bounds:?}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn lerped_boxes_hold_the_moving_triangles_at_every_time() {
    for steps in [2, 3, 5] {
        let keys = tumbling_triangles(600, steps, steps as u32);
        let motion = MotionBvh::build(&key_boxes(&keys));
        assert_eq!(motion.steps(), steps as u32);
        assert!(motion.bvh.wide_nodes.len() > 20);
        // The keys themselves, the middle of each segment, and odd times between
        for time in [0.0, 1.0, 0.5, 0.25, 0.37, 0.999, 0.123_456] {
            check_boxes_hold_their_subtrees(&motion, &keys, time);
        }
    }
}

/// The closest hit over `leaf_triangles` (in the tree's leaf order) found by a traversal that
/// enters children with `enter(node, t_max)`, the kernel's loop in short (nearest child first,
/// subtrees beyond the closest hit skipped); also how many boxes and triangles it tested.
fn closest_hit(
    leaf_triangles: &[Triangle],
    origin: Vec3,
    direction: Vec3,
    enter: impl Fn(u32, f32) -> EnteredChildren,
) -> (Option<f32>, u32) {
    let mut best = NO_HIT_T;
    let mut work = 0;
    let mut stack = vec![(0u32, 0.0f32)];
    while let Some((node, entry)) = stack.pop() {
        if entry > best {
            continue;
        }
        work += 4;
        let entered = enter(node, best);
        for k in (0..entered.count as usize).rev() {
            let child = entered.children[k];
            let count = traversal::get_bvh_leaf_triangle_count(child);
            if count == 0 {
                stack.push((child & WIDE_BVH_INDEX_MASK, entered.entries[k]));
                continue;
            }
            let first = child & WIDE_BVH_INDEX_MASK;
            for i in first..first + count {
                work += 1;
                let hit = ray_triangle_intersection(origin, direction, &leaf_triangles[i as usize]);
                if let Some(t) = hit.filter(|&t| t < best) {
                    best = t;
                }
            }
        }
    }
    ((best < NO_HIT_T).then_some(best), work)
}

/// The brute-force closest hit over `triangles`.
fn brute_force(triangles: &[Triangle], origin: Vec3, direction: Vec3) -> Option<f32> {
    triangles
        .iter()
        .filter_map(|t| ray_triangle_intersection(origin, direction, t))
        .min_by(f32::total_cmp)
}

#[test]
fn closest_hits_at_a_time_are_brute_forces_at_that_time() {
    let keys = tumbling_triangles(400, 3, 7);
    let motion = MotionBvh::build(&key_boxes(&keys));
    let mut state = UVec2::new(3, 4);
    let mut hits = 0;
    for ray in 0..400 {
        let time = get_random_numbers(&mut state).x;
        let triangles: Vec<Triangle> = (0..keys[0].len())
            .map(|i| triangle_at(&keys, i, time))
            .collect();
        let leaf_triangles = motion.bvh.reorder(&triangles);
        let target = get_random_numbers(&mut state).extend(get_random_numbers(&mut state).x);
        let origin = Vec3::new(0.5, 0.5, -2.0) + Vec3::new(ray as f32 % 3.0, 0.0, 0.0);
        let direction = target - origin;
        let inverse = bvh_inverse_direction(direction);
        let (found, _) = closest_hit(&leaf_triangles, origin, direction, |node, t_max| {
            bvh_enter_moving_children(&motion, node, time, origin, inverse, t_max)
        });
        let expected = brute_force(&triangles, origin, direction);
        assert_eq!(found, expected, "ray {ray} at time {time}");
        hits += usize::from(expected.is_some());
    }
    assert!(hits > 100, "the rays hit {hits} times");
}

#[test]
fn texels_hold_each_keys_boxes_then_the_references() {
    let keys = tumbling_triangles(50, 3, 11);
    let motion = MotionBvh::build(&key_boxes(&keys));
    let texels = motion.texels();
    let per_node = get_motion_bvh_node_texel_count(3) as usize;
    assert_eq!(per_node, 19);
    assert_eq!(texels.len(), per_node * motion.bvh.wide_nodes.len());
    for (index, node) in motion.bvh.wide_nodes.iter().enumerate() {
        let record = &texels[per_node * index..per_node * (index + 1)];
        assert_eq!(record[per_node - 1], node.children);
        for key in 0..3 {
            // Key k's boxes are the node's at time k / 2 (the keys themselves: fraction 0 or 1)
            let at_key = motion.node_at_time(index as u32, key as f32 / 2.0);
            let boxes = &record[6 * key..6 * key + 6];
            assert_eq!(boxes[0], at_key.lower_x.map(f32::to_bits));
            assert_eq!(boxes[3], at_key.upper_y.map(f32::to_bits));
            assert_eq!(boxes[5], at_key.upper_z.map(f32::to_bits));
        }
    }
}

/// `side` x `side` square cells of the unit square in the plane y = 0, two triangles each,
/// sliding `travel` along x from the first key to the last (2 keys: linear).
fn sliding_grid(side: usize, travel: f32, steps: usize) -> Keys {
    let cell = 1.0 / side as f32;
    (0..steps)
        .map(|k| {
            let shift = Vec3::X * travel * k as f32 / (steps - 1) as f32;
            (0..side * side)
                .flat_map(|c| {
                    let corner = Vec3::new((c % side) as f32, 0.0, (c / side) as f32) * cell;
                    let [a, b, d, e] = [
                        corner,
                        corner + Vec3::X * cell,
                        corner + Vec3::new(cell, 0.0, cell),
                        corner + Vec3::Z * cell,
                    ]
                    .map(|p| p + shift);
                    [[a, b, d], [a, d, e]]
                })
                .collect()
        })
        .collect()
}

#[test]
fn a_sliding_grid_costs_a_ray_about_what_a_still_grid_does() {
    // bench's moving grid in small: it slides 7.5 cells' width during the shutter
    let side = 96;
    let travel = 7.5 / side as f32;
    let mut work = [0u32; 3];
    let mut state = UVec2::new(1, 2);
    for steps in [2, 4] {
        let keys = sliding_grid(side, travel, steps);
        let boxes = key_boxes(&keys);
        let motion = MotionBvh::build(&boxes);
        // The first motion blur's tree: each triangle's box across the whole shutter
        let spans: Vec<Aabb> = (0..keys[0].len())
            .map(|i| boxes.iter().fold(Aabb::EMPTY, |b, key| b.union(key[i])))
            .collect();
        let spanning = Bvh::build_over_boxes(&spans);
        let (mut time, mut triangles, mut still) = (0.0, Vec::new(), Bvh::default());
        // Rays at 6 times, 50 at each (a still tree per time)
        for ray in 0..300 {
            if ray % 50 == 0 {
                time = get_random_numbers(&mut state).x;
                triangles = (0..keys[0].len())
                    .map(|i| triangle_at(&keys, i, time))
                    .collect();
                still = Bvh::build(&triangles);
            }
            let point = get_random_numbers(&mut state);
            let origin = Vec3::new(point.x, 1.0, point.y);
            let direction = Vec3::new(0.2, -1.0, 0.1);
            let inverse = bvh_inverse_direction(direction);
            let expected = brute_force(&triangles, origin, direction);
            let still_ray = closest_hit(&still.reorder(&triangles), origin, direction, |n, t| {
                bvh_enter_children(&still.wide_nodes, n, origin, inverse, t)
            });
            let motion_ray = closest_hit(
                &motion.bvh.reorder(&triangles),
                origin,
                direction,
                |n, t| bvh_enter_moving_children(&motion, n, time, origin, inverse, t),
            );
            let spanning_ray =
                closest_hit(&spanning.reorder(&triangles), origin, direction, |n, t| {
                    bvh_enter_children(&spanning.wide_nodes, n, origin, inverse, t)
                });
            for (found, _) in [still_ray, motion_ray, spanning_ray] {
                assert_eq!(found, expected);
            }
            work[0] += still_ray.1;
            work[1] += motion_ray.1;
            work[2] += spanning_ray.1;
        }
    }
    let [still, moving, spanning] = work.map(|w| w as f32);
    // The goal: blur at most 1.5x a still frame's cost; boxes tested and triangles tested are
    // what a ray's cost is made of
    assert!(
        moving < 1.5 * still,
        "motion tree {moving}, still tree {still}"
    );
    // The test has teeth: boxes that span the shutter make a ray work far more (2.25x here;
    // the motion tree 1.00x)
    assert!(
        spanning > 1.8 * still,
        "spanning boxes {spanning}, still tree {still}"
    );
}
