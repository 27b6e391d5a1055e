//! Rust twins of `glsl/bvh.glsl`: the inverse direction, the slab test and the two
//! traversals, operation for operation and in the same order, so that they visit the same
//! nodes and test the same triangles as the shader. Where the shader reads the global
//! `g_bvh_node_texels` and `g_traversal_triangle_texels`, the twins take them as their first
//! parameters (the traversal-only triangles of the triangles reordered by `Bvh::reorder`).
//! Change both together.

use glam::Vec3;

use super::{Aabb, GpuTraversalTriangle, GpuWideBvhNode};
use crate::contract::{
    BVH_MIN_DIRECTION, BVH_SLAB_PADDING, NO_HIT_T, WIDE_BVH_EMPTY_CHILD, WIDE_BVH_INDEX_MASK,
    WIDE_BVH_LEAF_COUNT_SHIFT, WIDE_BVH_STACK_SIZE, WIDE_BVH_WIDTH,
};
use crate::cpu::integrator::MeshHit;
use crate::cpu::workshop::ray_triangle_intersection;
use crate::scene::Triangle;

const STACK_SIZE: usize = WIDE_BVH_STACK_SIZE as usize;

/// Triangle `index` as the traversal's triangle test sees it, twin of GLSL
/// `get_traversal_triangle`: its vertex positions, and zeros for the members that
/// `ray_triangle_intersection` does not read.
///
/// # Panics
/// If `index` is out of range.
pub fn get_traversal_triangle(triangles: &[GpuTraversalTriangle], index: u32) -> Triangle {
    let packed = &triangles[index as usize];
    Triangle {
        positions: packed.positions.map(|p| Vec3::new(p[0], p[1], p[2])),
        normal: Vec3::ZERO,
        color: Vec3::ZERO,
        emission: Vec3::ZERO,
        double_sided: false,
    }
}

/// The per-component inverse of a ray direction for slab tests, twin of GLSL
/// `bvh_inverse_direction`.
/// \param ray_direction The ray direction, world space (need not be normalized)
/// \return sign(d_i) / max(|d_i|, BVH_MIN_DIRECTION), +0 counting as positive
pub fn bvh_inverse_direction(ray_direction: Vec3) -> Vec3 {
    let magnitude = ray_direction.abs().max(Vec3::splat(BVH_MIN_DIRECTION));
    let direction_sign = Vec3::select(
        ray_direction.cmpge(Vec3::ZERO),
        Vec3::splat(1.0),
        Vec3::splat(-1.0),
    );
    direction_sign / magnitude
}

/// The slab test (Kay and Kajiya 1986), twin of GLSL `bvh_ray_box_intersection`: whether a
/// ray enters an axis-aligned box before `t_max`.
/// \param ray_origin The ray origin, world space
/// \param inverse_direction `bvh_inverse_direction(ray_direction)`
/// \param box_lower, box_upper The box's corners, world space
/// \param t_max Entries past this do not count
/// \return The parameter where the ray enters the box (0 if the origin is inside) iff the
///         segment [0, t_max] meets the (slightly padded) box. The GLSL twin writes it to
///         `out_t_entry` even on a miss; here a miss is `None`.
pub fn bvh_ray_box_intersection(
    ray_origin: Vec3,
    inverse_direction: Vec3,
    box_lower: Vec3,
    box_upper: Vec3,
    t_max: f32,
) -> Option<f32> {
    let t_lower = (box_lower - ray_origin) * inverse_direction;
    let t_upper = (box_upper - ray_origin) * inverse_direction;
    let t_near = t_lower.min(t_upper);
    let t_far = t_lower.max(t_upper);
    let t_entry = t_near.x.max(t_near.y).max(t_near.z.max(0.0));
    let t_exit = t_far.x.min(t_far.y).min(t_far.z) * BVH_SLAB_PADDING;
    (t_entry <= t_exit.min(t_max)).then_some(t_entry)
}

/// Twin of GLSL `get_bvh_child_box`: the box of child `slot` of node `node_index`, world
/// space.
pub fn get_bvh_child_box(nodes: &[GpuWideBvhNode], node_index: u32, slot: usize) -> Aabb {
    nodes[node_index as usize].child_bounds(slot)
}

/// Twin of GLSL `get_bvh_leaf_triangle_count`: a child reference's triangle count, at least 1
/// for a leaf, 0 for an interior node.
pub fn get_bvh_leaf_triangle_count(child: u32) -> u32 {
    child >> WIDE_BVH_LEAF_COUNT_SHIFT
}

/// Twin of GLSL `get_bvh_child_index`: a child reference's node index (interior) or first
/// triangle (leaf).
pub fn get_bvh_child_index(child: u32) -> u32 {
    child & WIDE_BVH_INDEX_MASK
}

/// Twin of GLSL `order_bvh_children`: a compare-exchange of (entry, child) pairs that swaps
/// only when the second enters strictly earlier.
pub fn order_bvh_children(entries: &mut [f32; 4], children: &mut [u32; 4], a: usize, b: usize) {
    if entries[b] < entries[a] {
        entries.swap(a, b);
        children.swap(a, b);
    }
}

/// The children of a wide node that a ray enters (`bvh_enter_children`), nearest first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnteredChildren {
    /// How many of the boxes the ray enters before `t_max`: 0 to `WIDE_BVH_WIDTH`.
    pub count: u32,
    /// The references, those entered first, nearest first.
    pub children: [u32; 4],
    /// Where the ray enters them (`NO_HIT_T` for those not entered).
    pub entries: [f32; 4],
}

/// Twin of GLSL `bvh_enter_children`: the children of interior node `node_index` whose boxes
/// the ray enters before `t_max` (`bvh_enter_boxes`), nearest first.
pub fn bvh_enter_children(
    nodes: &[GpuWideBvhNode],
    node_index: u32,
    ray_origin: Vec3,
    inverse_direction: Vec3,
    t_max: f32,
) -> EnteredChildren {
    bvh_enter_boxes(
        &nodes[node_index as usize],
        ray_origin,
        inverse_direction,
        t_max,
    )
}

/// Twin of GLSL `bvh_enter_boxes`: the children of a wide node (its four boxes and references,
/// which the GLSL twin takes as seven vectors) whose boxes the ray enters before `t_max`
/// (`bvh_ray_box_intersection`'s slab test, four boxes at once), nearest first by a sorting
/// network.
pub fn bvh_enter_boxes(
    node: &GpuWideBvhNode,
    ray_origin: Vec3,
    inverse_direction: Vec3,
    t_max: f32,
) -> EnteredChildren {
    let slab = |values: [f32; 4], origin: f32, inverse: f32| values.map(|v| (v - origin) * inverse);
    let t_lower_x = slab(node.lower_x, ray_origin.x, inverse_direction.x);
    let t_upper_x = slab(node.upper_x, ray_origin.x, inverse_direction.x);
    let t_lower_y = slab(node.lower_y, ray_origin.y, inverse_direction.y);
    let t_upper_y = slab(node.upper_y, ray_origin.y, inverse_direction.y);
    let t_lower_z = slab(node.lower_z, ray_origin.z, inverse_direction.z);
    let t_upper_z = slab(node.upper_z, ray_origin.z, inverse_direction.z);
    let mut entries = [0.0f32; 4];
    let mut count = 0;
    for k in 0..4 {
        let t_entry = t_lower_x[k]
            .min(t_upper_x[k])
            .max(t_lower_y[k].min(t_upper_y[k]))
            .max(t_lower_z[k].min(t_upper_z[k]).max(0.0));
        let t_exit = t_lower_x[k]
            .max(t_upper_x[k])
            .min(t_lower_y[k].max(t_upper_y[k]))
            .min(t_lower_z[k].max(t_upper_z[k]))
            * BVH_SLAB_PADDING;
        let entered = t_entry <= t_exit.min(t_max) && node.children[k] != WIDE_BVH_EMPTY_CHILD;
        // Boxes not entered sort last
        entries[k] = if entered { t_entry } else { NO_HIT_T };
        count += u32::from(entered);
    }
    let mut children = node.children;
    for (a, b) in [(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)] {
        order_bvh_children(&mut entries, &mut children, a, b);
    }
    EnteredChildren {
        count,
        children,
        entries,
    }
}

/// `PUSH_BVH_CHILDREN` of `glsl/bvh.glsl`: the entered children but the nearest, farthest
/// first.
fn push_children(
    entered: &EnteredChildren,
    stack_nodes: &mut [u32; STACK_SIZE],
    stack_entries: &mut [f32; STACK_SIZE],
    stack_size: &mut usize,
) {
    for k in (1..entered.count as usize).rev() {
        if *stack_size < STACK_SIZE {
            stack_nodes[*stack_size] = entered.children[k];
            stack_entries[*stack_size] = entered.entries[k];
            *stack_size += 1;
        }
    }
}

/// Finds the closest triangle that a ray hits by traversing the wide BVH, twin of GLSL
/// `bvh_closest_hit`: brute force's triangle tests, nearest child first, subtrees skipped
/// once they start beyond the closest hit so far.
/// \param nodes The wide BVH's nodes (the shader's `g_bvh_node_texels`)
/// \param scene_triangles The traversal-only triangles in leaf order (the shader's
///        `g_traversal_triangle_texels`)
/// \param ray_origin, ray_direction The ray, world space
/// \return The closest hit (t, index into `scene_triangles`), `None` iff no triangle is hit
///         at t < `NO_HIT_T` (1e38)
///
/// # Panics
/// If the nodes index past `nodes` or `scene_triangles` (a BVH built for other triangles).
pub fn bvh_closest_hit(
    nodes: &[GpuWideBvhNode],
    scene_triangles: &[GpuTraversalTriangle],
    ray_origin: Vec3,
    ray_direction: Vec3,
) -> Option<MeshHit> {
    let mut out_t = NO_HIT_T;
    let mut out_triangle_index = 0u32;
    let mut hit = false;
    let inverse_direction = bvh_inverse_direction(ray_direction);
    if nodes.is_empty() {
        return None;
    }
    let mut stack_nodes = [0u32; STACK_SIZE];
    let mut stack_entries = [0f32; STACK_SIZE];
    let mut stack_size = 0usize;
    let mut child = 0u32;
    // Each iteration visits one child reference and none is visited twice.
    for _ in 0..WIDE_BVH_WIDTH as usize * nodes.len() + 1 {
        let first_index = get_bvh_child_index(child);
        let triangle_count = get_bvh_leaf_triangle_count(child);
        let mut descend = false;
        if triangle_count != 0 {
            for i in first_index..first_index + triangle_count {
                let triangle = get_traversal_triangle(scene_triangles, i);
                if let Some(t) = ray_triangle_intersection(ray_origin, ray_direction, &triangle) {
                    if t < out_t {
                        out_t = t;
                        out_triangle_index = i;
                        hit = true;
                    }
                }
            }
        } else {
            let entered =
                bvh_enter_children(nodes, first_index, ray_origin, inverse_direction, out_t);
            push_children(
                &entered,
                &mut stack_nodes,
                &mut stack_entries,
                &mut stack_size,
            );
            child = entered.children[0];
            descend = entered.count != 0;
        }
        while !descend && stack_size != 0 {
            stack_size -= 1;
            if stack_entries[stack_size] <= out_t {
                child = stack_nodes[stack_size];
                descend = true;
            }
        }
        if !descend {
            break;
        }
    }
    hit.then_some(MeshHit {
        t: out_t,
        triangle_index: out_triangle_index as usize,
    })
}

/// Whether a ray hits any triangle at t < `t_max` (shadow rays), twin of GLSL `bvh_any_hit`:
/// the traversal of `bvh_closest_hit` with a fixed `t_max`, ending at the first hit found.
/// \param nodes The wide BVH's nodes (the shader's `g_bvh_node_texels`)
/// \param scene_triangles The traversal-only triangles in leaf order (the shader's
///        `g_traversal_triangle_texels`)
/// \param ray_origin, ray_direction The ray, world space
/// \param t_max Hits at or beyond this ray parameter do not count
///
/// # Panics
/// If the nodes index past `nodes` or `scene_triangles` (a BVH built for other triangles).
pub fn bvh_any_hit(
    nodes: &[GpuWideBvhNode],
    scene_triangles: &[GpuTraversalTriangle],
    ray_origin: Vec3,
    ray_direction: Vec3,
    t_max: f32,
) -> bool {
    let inverse_direction = bvh_inverse_direction(ray_direction);
    if nodes.is_empty() {
        return false;
    }
    let mut stack_nodes = [0u32; STACK_SIZE];
    let mut stack_entries = [0f32; STACK_SIZE];
    let mut stack_size = 0usize;
    let mut child = 0u32;
    for _ in 0..WIDE_BVH_WIDTH as usize * nodes.len() + 1 {
        let first_index = get_bvh_child_index(child);
        let triangle_count = get_bvh_leaf_triangle_count(child);
        if triangle_count != 0 {
            for i in first_index..first_index + triangle_count {
                let triangle = get_traversal_triangle(scene_triangles, i);
                if let Some(t) = ray_triangle_intersection(ray_origin, ray_direction, &triangle) {
                    if t < t_max {
                        return true;
                    }
                }
            }
        } else {
            // Nearest first: an occluder near the origin ends the search sooner
            let entered =
                bvh_enter_children(nodes, first_index, ray_origin, inverse_direction, t_max);
            push_children(
                &entered,
                &mut stack_nodes,
                &mut stack_entries,
                &mut stack_size,
            );
            if entered.count != 0 {
                child = entered.children[0];
                continue;
            }
        }
        if stack_size == 0 {
            break;
        }
        stack_size -= 1;
        child = stack_nodes[stack_size];
    }
    false
}
