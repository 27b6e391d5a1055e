//! Rust twins of `glsl/bvh.glsl`: the inverse direction, the slab test and the two
//! traversals, operation for operation and in the same order, so that they visit the same
//! nodes and test the same triangles as the shader. Where the shader reads the global
//! `g_bvh_node_texels` and `g_traversal_triangle_texels`, the twins take them as their first
//! parameters (the traversal-only triangles of the triangles reordered by `Bvh::reorder`).
//! Change both together.

use glam::Vec3;

use super::{GpuBvhNode, GpuTraversalTriangle};
use crate::contract::{BVH_MIN_DIRECTION, BVH_SLAB_PADDING, BVH_STACK_SIZE, NO_HIT_T};
use crate::cpu::integrator::MeshHit;
use crate::cpu::workshop::ray_triangle_intersection;
use crate::scene::Triangle;

const STACK_SIZE: usize = BVH_STACK_SIZE as usize;

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

/// Node `index`'s box test, as the shader writes it inline.
fn node_box_test(
    nodes: &[GpuBvhNode],
    index: u32,
    ray_origin: Vec3,
    inverse_direction: Vec3,
    t_max: f32,
) -> Option<f32> {
    let bounds = nodes[index as usize].bounds();
    bvh_ray_box_intersection(
        ray_origin,
        inverse_direction,
        bounds.lower,
        bounds.upper,
        t_max,
    )
}

/// Twin of GLSL `bvh_enters_root`: whether the ray enters the root's box before `t_max` (an
/// empty tree is entered by nothing).
pub fn bvh_enters_root(
    nodes: &[GpuBvhNode],
    ray_origin: Vec3,
    inverse_direction: Vec3,
    t_max: f32,
) -> bool {
    !nodes.is_empty() && node_box_test(nodes, 0, ray_origin, inverse_direction, t_max).is_some()
}

/// The children of an interior node that a ray enters, nearer first (`bvh_enter_children`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnteredChildren {
    /// How many of the two boxes the ray enters before `t_max`: 0, 1 or 2.
    pub count: u32,
    /// The child to visit next (the nearer one when both are entered).
    pub near: u32,
    /// The child to push when both are entered.
    pub far: u32,
    /// Where the ray enters `far` (meaningful when both are entered).
    pub far_entry: f32,
}

/// Twin of GLSL `bvh_enter_children`: the children `first_index` and `first_index + 1` whose
/// boxes the ray enters before `t_max`, nearer first.
pub fn bvh_enter_children(
    nodes: &[GpuBvhNode],
    first_index: u32,
    ray_origin: Vec3,
    inverse_direction: Vec3,
    t_max: f32,
) -> EnteredChildren {
    let t_left = node_box_test(nodes, first_index, ray_origin, inverse_direction, t_max);
    let t_right = node_box_test(nodes, first_index + 1, ray_origin, inverse_direction, t_max);
    let left_first = match (t_left, t_right) {
        (_, None) => true,
        (Some(left), Some(right)) => left <= right,
        (None, Some(_)) => false,
    };
    let (near, far, far_entry) = if left_first {
        (first_index, first_index + 1, t_right)
    } else {
        (first_index + 1, first_index, t_left)
    };
    EnteredChildren {
        count: u32::from(t_left.is_some()) + u32::from(t_right.is_some()),
        near,
        far,
        far_entry: far_entry.unwrap_or(0.0),
    }
}

/// Finds the closest triangle that a ray hits by traversing the BVH, twin of GLSL
/// `bvh_closest_hit`: brute force's triangle tests, nearer child first, subtrees skipped
/// once they start beyond the closest hit so far.
/// \param nodes The BVH's nodes (the shader's `g_bvh_nodes`)
/// \param scene_triangles The traversal-only triangles in leaf order (the shader's
///        `g_traversal_triangle_texels`)
/// \param ray_origin, ray_direction The ray, world space
/// \return The closest hit (t, index into `scene_triangles`), `None` iff no triangle is hit
///         at t < `NO_HIT_T` (1e38)
///
/// # Panics
/// If the nodes index past `nodes` or `scene_triangles` (a BVH built for other triangles).
pub fn bvh_closest_hit(
    nodes: &[GpuBvhNode],
    scene_triangles: &[GpuTraversalTriangle],
    ray_origin: Vec3,
    ray_direction: Vec3,
) -> Option<MeshHit> {
    let mut out_t = NO_HIT_T;
    let mut out_triangle_index = 0u32;
    let mut hit = false;
    let node_count = nodes.len();
    let inverse_direction = bvh_inverse_direction(ray_direction);
    if !bvh_enters_root(nodes, ray_origin, inverse_direction, out_t) {
        return None;
    }
    let mut stack_nodes = [0u32; STACK_SIZE];
    let mut stack_entries = [0f32; STACK_SIZE];
    let mut stack_size = 0usize;
    let mut node_index = 0u32;
    // Each iteration visits one node and no node is visited twice.
    for _ in 0..node_count {
        let node = nodes[node_index as usize];
        let first_index = node.first_index();
        let triangle_count = node.triangle_count();
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
            let children =
                bvh_enter_children(nodes, first_index, ray_origin, inverse_direction, out_t);
            if children.count == 2 && stack_size < STACK_SIZE {
                stack_nodes[stack_size] = children.far;
                stack_entries[stack_size] = children.far_entry;
                stack_size += 1;
            }
            if children.count != 0 {
                node_index = children.near;
                descend = true;
            }
        }
        while !descend && stack_size != 0 {
            stack_size -= 1;
            if stack_entries[stack_size] <= out_t {
                node_index = stack_nodes[stack_size];
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
/// \param nodes The BVH's nodes (the shader's `g_bvh_nodes`)
/// \param scene_triangles The traversal-only triangles in leaf order (the shader's
///        `g_traversal_triangle_texels`)
/// \param ray_origin, ray_direction The ray, world space
/// \param t_max Hits at or beyond this ray parameter do not count
///
/// # Panics
/// If the nodes index past `nodes` or `scene_triangles` (a BVH built for other triangles).
pub fn bvh_any_hit(
    nodes: &[GpuBvhNode],
    scene_triangles: &[GpuTraversalTriangle],
    ray_origin: Vec3,
    ray_direction: Vec3,
    t_max: f32,
) -> bool {
    let node_count = nodes.len();
    let inverse_direction = bvh_inverse_direction(ray_direction);
    if !bvh_enters_root(nodes, ray_origin, inverse_direction, t_max) {
        return false;
    }
    let mut stack_nodes = [0u32; STACK_SIZE];
    let mut stack_size = 0usize;
    let mut node_index = 0u32;
    for _ in 0..node_count {
        let node = nodes[node_index as usize];
        let first_index = node.first_index();
        let triangle_count = node.triangle_count();
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
            // Nearer first: an occluder near the origin ends the search sooner
            let children =
                bvh_enter_children(nodes, first_index, ray_origin, inverse_direction, t_max);
            if children.count == 2 && stack_size < STACK_SIZE {
                stack_nodes[stack_size] = children.far;
                stack_size += 1;
            }
            if children.count != 0 {
                node_index = children.near;
                continue;
            }
        }
        if stack_size == 0 {
            break;
        }
        stack_size -= 1;
        node_index = stack_nodes[stack_size];
    }
    false
}
