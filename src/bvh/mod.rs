//! A bounding volume hierarchy over the scene's triangles, so that a ray tests O(log n)
//! triangles instead of all of them: a binned-SAH builder on the CPU (`build`) of a binary
//! tree (`GpuBvhNode`), collapsed into the 4-wide tree that `glsl/bvh.glsl` traverses
//! (`wide`, `GpuWideBvhNode`), and the Rust twins of the shader's traversal (`traversal`).
//!
//! Usage: `let bvh = Bvh::build(&scene.triangles);` then upload
//! `bvh.reorder(&scene.triangles)` as the triangle buffer (leaves reference contiguous
//! ranges of the reordered triangles), `traversal_triangles` of the reordered triangles at
//! `BINDING_TRAVERSAL_TRIANGLES` and `bvh.wide_nodes` at `BINDING_BVH_NODES`. Triangle
//! indices that the traversal reports refer to the reordered triangles;
//! `bvh.triangle_order[i]` is the original index of triangle i.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

mod aabb;
mod build;
mod compressed;
pub mod compressed_traversal;
pub mod motion;
mod stats;
pub mod traversal;
mod wide;

#[cfg(test)]
mod compressed_tests;
#[cfg(test)]
mod motion_tests;
#[cfg(test)]
mod tests;

pub use aabb::Aabb;
pub use build::{
    BIN_COUNT, INTERSECTION_COST, LEAF_SIZE, MAX_DEPTH, MAX_LEAF_SIZE, TRAVERSAL_COST,
};
pub use compressed::{
    compressed_child_node, packed_traversal_triangles, CompressedBvh, CompressedBvhError,
    GpuCompressedBvhNode,
};
pub use motion::MotionBvh;
pub use stats::BvhStats;
pub use traversal::{
    bvh_any_hit, bvh_closest_hit, bvh_enter_boxes, bvh_enter_children, bvh_inverse_direction,
    bvh_ray_box_intersection, get_bvh_child_box, get_traversal_triangle, EnteredChildren,
};
pub use wide::{leaf_reference, most_pushes, widen, GpuWideBvhNode};

use crate::scene::Triangle;

/// `bvh_node_t` of `glsl/bvh.glsl` (std430, 32 bytes): one node of the flattened tree.
///
/// An interior node's children are nodes `first_index()` and `first_index() + 1` (stored
/// side by side, so one index suffices); a leaf holds triangles `first_index()..` `+
/// triangle_count()` of the reordered triangle buffer. The root is node 0. Integers live in
/// the w components as the bits of a float (`f32::from_bits`, GLSL `floatBitsToUint`), which
/// loads and stores keep exactly; no arithmetic ever touches them.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBvhNode {
    /// xyz: the box's lower corner, world space; w: the bits of the first child's index
    /// (interior) or of the first triangle's index (leaf).
    pub lower: [f32; 4],
    /// xyz: the box's upper corner, world space; w: the bits of the triangle count, 0 for
    /// an interior node (a leaf has at least one triangle).
    pub upper: [f32; 4],
}

impl GpuBvhNode {
    /// An interior node whose children are nodes `first_child` and `first_child + 1`.
    pub fn interior(bounds: &Aabb, first_child: u32) -> GpuBvhNode {
        GpuBvhNode::new(bounds, first_child, 0)
    }

    /// A leaf over the reordered triangles `first_triangle..first_triangle + triangle_count`;
    /// `triangle_count` must be at least 1 (0 marks interior nodes).
    pub fn leaf(bounds: &Aabb, first_triangle: u32, triangle_count: u32) -> GpuBvhNode {
        GpuBvhNode::new(bounds, first_triangle, triangle_count)
    }

    fn new(bounds: &Aabb, first_index: u32, triangle_count: u32) -> GpuBvhNode {
        let l = bounds.lower;
        let u = bounds.upper;
        GpuBvhNode {
            lower: [l.x, l.y, l.z, f32::from_bits(first_index)],
            upper: [u.x, u.y, u.z, f32::from_bits(triangle_count)],
        }
    }

    /// The first child (interior node) or first triangle (leaf).
    pub fn first_index(&self) -> u32 {
        self.lower[3].to_bits()
    }

    /// The number of triangles of a leaf; 0 for an interior node.
    pub fn triangle_count(&self) -> u32 {
        self.upper[3].to_bits()
    }

    /// Whether the node is a leaf.
    pub fn is_leaf(&self) -> bool {
        self.triangle_count() != 0
    }

    /// The node's box, world space.
    pub fn bounds(&self) -> Aabb {
        Aabb {
            lower: Vec3::new(self.lower[0], self.lower[1], self.lower[2]),
            upper: Vec3::new(self.upper[0], self.upper[1], self.upper[2]),
        }
    }
}

/// One texel-buffer record of `g_traversal_triangle_texels` (`glsl/bvh.glsl`, read by
/// `get_traversal_triangle`; 48 bytes, `TRAVERSAL_TRIANGLE_TEXEL_COUNT` RGBA32 texels): one
/// triangle's vertex positions alone, all that the traversal's triangle tests read. Uploaded at `BINDING_TRAVERSAL_TRIANGLES` in the same leaf order as the full
/// triangles (`traversal_triangles(&bvh.reorder(&triangles))`), so a leaf's triangles are
/// contiguous 48-byte records.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTraversalTriangle {
    /// xyz: v_0, v_1, v_2 (world space), bit for bit; w: unused (0).
    pub positions: [[f32; 4]; 3],
}

impl GpuTraversalTriangle {
    /// The positions of `triangle`, exactly.
    pub fn new(triangle: &Triangle) -> GpuTraversalTriangle {
        GpuTraversalTriangle {
            positions: triangle.positions.map(|p| p.extend(0.0).to_array()),
        }
    }
}

/// The traversal-only triangles (`GpuTraversalTriangle`) of `triangles`, in their order (pass
/// the triangles reordered by `Bvh::reorder`).
pub fn traversal_triangles(triangles: &[Triangle]) -> Vec<GpuTraversalTriangle> {
    triangles.iter().map(GpuTraversalTriangle::new).collect()
}

/// Reorders a per-triangle list by a tree's `triangle_order` (`Bvh::triangle_order`,
/// `CompressedBvh::triangle_order`): `result[i] = items[order[i]]`.
///
/// # Panics
/// If `order` indexes past `items`.
pub fn reorder_by<T: Clone>(order: &[u32], items: &[T]) -> Vec<T> {
    order
        .iter()
        .map(|&index| items[index as usize].clone())
        .collect()
}

/// A BVH over a list of triangles, ready for the GPU.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    /// The flattened tree, root first; empty iff there are no triangles (the shader then
    /// reports no hits; bind a buffer of at least one byte anyway, Vulkan wants one).
    pub nodes: Vec<GpuBvhNode>,
    /// Triangle `i` of the reordered buffer that the leaves index is triangle
    /// `triangle_order[i]` of the list the BVH was built from: a permutation.
    pub triangle_order: Vec<u32>,
    /// The same tree 4 wide (`widen(&nodes)`), as the kernels traverse it and the twins of
    /// `traversal` do: upload it at `BINDING_BVH_NODES`.
    pub wide_nodes: Vec<GpuWideBvhNode>,
}

impl Bvh {
    /// Builds the BVH with the binned SAH (`BIN_COUNT` bins, costs `TRAVERSAL_COST` and
    /// `INTERSECTION_COST`, leaves of up to `LEAF_SIZE` triangles or where splitting does not
    /// pay, no leaf deeper than `MAX_DEPTH`). Parallel on rayon's pool. Degenerate triangles
    /// are fine (they still get a leaf); up to 2^31 triangles, far beyond any GPU buffer.
    pub fn build(triangles: &[Triangle]) -> Bvh {
        Bvh::build_with_max_depth(triangles, MAX_DEPTH)
    }

    /// `build` over primitives given by their boxes alone. Leaf `i` references primitive
    /// `triangle_order[i]`. (Motion blur's tree is `MotionBvh`, whose nodes hold a box per
    /// key.)
    pub fn build_over_boxes(boxes: &[Aabb]) -> Bvh {
        Bvh::from_tree(build::build_tree_of_boxes(boxes, MAX_DEPTH))
    }

    /// `build` with a lower depth limit, for tests of the limit.
    pub(crate) fn build_with_max_depth(triangles: &[Triangle], max_depth: u32) -> Bvh {
        Bvh::from_tree(build::build_tree(triangles, max_depth.min(MAX_DEPTH)))
    }

    /// The flattened and widened tree of a built one.
    fn from_tree(tree: Option<(build::BuildNode, Vec<u32>)>) -> Bvh {
        match tree {
            Some((root, triangle_order)) => {
                let nodes = build::flatten(&root);
                Bvh {
                    wide_nodes: widen(&nodes),
                    nodes,
                    triangle_order,
                }
            }
            None => Bvh::default(),
        }
    }

    /// Reorders a per-triangle list (the triangles themselves, or anything indexed like
    /// them) into the order the leaves reference: `result[i] = items[triangle_order[i]]`.
    ///
    /// # Panics
    /// If `items` is shorter than the list the BVH was built from.
    pub fn reorder<T: Clone>(&self, items: &[T]) -> Vec<T> {
        self.triangle_order
            .iter()
            .map(|&index| items[index as usize].clone())
            .collect()
    }

    /// Size statistics and the tree's SAH cost.
    pub fn stats(&self) -> BvhStats {
        BvhStats::of(&self.nodes)
    }

    /// Bytes of the node buffer that the kernels read (the wide nodes).
    pub fn node_bytes(&self) -> usize {
        std::mem::size_of_val(self.wide_nodes.as_slice())
    }
}
