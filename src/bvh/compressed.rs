//! The compressed wide BVH that `glsl/cwbvh.glsl` traverses (Ylitie, Karras and Laine 2017,
//! "Efficient incoherent ray traversal on GPUs through compressed wide BVHs", HPG): 8
//! children per node, their boxes quantised to one byte per plane on a grid anchored at the
//! node's lower corner, with a power-of-two cell size per axis, so a node of eight boxes
//! takes 80 bytes where the 4-wide tree takes 112 for four. Leaves hold 1 to 3 triangles,
//! referenced by offset from the node's first triangle, so a node stores no per-child index.
//!
//! The tree is the binned-SAH binary tree of `Bvh::build` (the 4-wide tree's), collapsed by
//! the `obvhs` crate (the paper's cost-optimal collapse into 8-wide nodes, children ordered by
//! octant): this module hands it the binary tree and converts its nodes into
//! `GpuCompressedBvhNode` and its primitive order into `triangle_order`. The traversal triangles are packed 36 bytes apiece
//! (`packed_traversal_triangles`).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::{Aabb, Bvh, GpuBvhNode};
use crate::contract::{CWBVH_MAX_NODE_COUNT, CWBVH_STACK_SIZE, PACKED_TRIANGLE_WORD_COUNT};
use crate::scene::Triangle;

/// One node of the compressed BVH as `glsl/cwbvh.glsl` reads it (`CWBVH_NODE_TEXEL_COUNT`
/// RGBA32 texels, 80 bytes; the layout of `obvhs::cwbvh::node::CwBvhNode`).
///
/// Child `c`'s box is `origin + scale * q` per axis, with `q` its quantised lower and upper
/// planes (bytes `c` of `lower_x` .. `upper_z`) and `scale = 2^(exponent - 127)` (the float
/// whose bits are `exponent << 23`). The quantised planes are rounded outwards, so the
/// child's box contains its exact box.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuCompressedBvhNode {
    /// The grid's origin, world space: the node's lower corner.
    pub origin: [f32; 3],
    /// Bytes 0-2: the biased exponents of the grid's cell size along x, y and z; byte 3:
    /// the inner mask, bit `c` set iff child `c` is an interior node.
    pub exponents_inner_mask: [u8; 4],
    /// The first interior child's node index; the others follow in slot order.
    pub child_base: u32,
    /// The first triangle of the leaf children, in the reordered triangle buffer.
    pub triangle_base: u32,
    /// Per child slot: 0 for an empty slot; `24 + slot` (binary 001 in the top bits) for an
    /// interior child; for a leaf, its triangle count in unary in bits 5-7 (1: `001`, 2:
    /// `011`, 3: `111`) and its first triangle's offset from `triangle_base` (0 to 23) in
    /// bits 0-4.
    pub child_meta: [u8; 8],
    /// The children's quantised lower x planes.
    pub lower_x: [u8; 8],
    /// Their upper x planes.
    pub upper_x: [u8; 8],
    /// Their lower y planes.
    pub lower_y: [u8; 8],
    /// Their upper y planes.
    pub upper_y: [u8; 8],
    /// Their lower z planes.
    pub lower_z: [u8; 8],
    /// Their upper z planes.
    pub upper_z: [u8; 8],
}

impl GpuCompressedBvhNode {
    /// The grid's cell size per axis: `2^(exponent - 127)`.
    pub fn scale(&self) -> Vec3 {
        let e = self.exponents_inner_mask;
        Vec3::new(
            f32::from_bits(u32::from(e[0]) << 23),
            f32::from_bits(u32::from(e[1]) << 23),
            f32::from_bits(u32::from(e[2]) << 23),
        )
    }

    /// Bit `c` set iff child `c` is an interior node.
    pub fn inner_mask(&self) -> u8 {
        self.exponents_inner_mask[3]
    }

    /// Child `slot`'s (dequantised, conservative) box, world space: lower and upper corner.
    pub fn child_box(&self, slot: usize) -> (Vec3, Vec3) {
        let origin = Vec3::from(self.origin);
        let scale = self.scale();
        let q = |x: &[u8; 8], y: &[u8; 8], z: &[u8; 8]| {
            Vec3::new(f32::from(x[slot]), f32::from(y[slot]), f32::from(z[slot]))
        };
        (
            origin + scale * q(&self.lower_x, &self.lower_y, &self.lower_z),
            origin + scale * q(&self.upper_x, &self.upper_y, &self.upper_z),
        )
    }

    fn from_obvhs(node: &obvhs::cwbvh::node::CwBvhNode) -> GpuCompressedBvhNode {
        GpuCompressedBvhNode {
            origin: [node.p.x, node.p.y, node.p.z],
            exponents_inner_mask: [node.e[0], node.e[1], node.e[2], node.imask],
            child_base: node.child_base_idx,
            triangle_base: node.primitive_base_idx,
            child_meta: node.child_meta,
            lower_x: node.child_min_x,
            upper_x: node.child_max_x,
            lower_y: node.child_min_y,
            upper_y: node.child_max_y,
            lower_z: node.child_min_z,
            upper_z: node.child_max_z,
        }
    }
}

/// Why a list of triangles has no compressed BVH, in one line (the renderer refuses the
/// render with it under `--accel compressed-bvh`, and under `--accel auto` warns with it and
/// takes the 4-wide tree).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CompressedBvhError {
    /// More triangles than the packed triangles' 32-bit word indices address.
    #[error("{0} triangles are too many for the compressed BVH")]
    TooManyTriangles(usize),
    /// The scene's extent (1e15 or more, or not finite) would overflow the collapse's costs.
    #[error(
        "the scene spans {0}, too far for the compressed BVH's quantised boxes; use --accel bvh"
    )]
    TooFar(Vec3),
    /// Interior nodes deeper than the traversal's stack (`CWBVH_STACK_SIZE`) can follow.
    #[error(
        "the compressed BVH of these {triangle_count} triangles is {levels} levels deep, more \
         than its traversal's stack of {} allows; use --accel bvh",
        CWBVH_STACK_SIZE
    )]
    TooDeep {
        /// Triangles in the tree.
        triangle_count: usize,
        /// Levels of interior nodes (the deepest's depth + 1).
        levels: u32,
    },
    /// More nodes than a traversal's stack entry addresses (`CWBVH_MAX_NODE_COUNT`).
    #[error(
        "the compressed BVH of these {triangle_count} triangles has {nodes} nodes, more than \
         its traversal's stack entries address ({}); use --accel bvh",
        CWBVH_MAX_NODE_COUNT
    )]
    TooManyNodes {
        /// Triangles in the tree.
        triangle_count: usize,
        /// Nodes in the tree.
        nodes: usize,
    },
}

/// A compressed wide BVH over a list of triangles, ready for the GPU.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CompressedBvh {
    /// The nodes, root first; empty iff there are no triangles (the shader then reports no
    /// hits). Upload them at `BINDING_BVH_NODES`.
    pub nodes: Vec<GpuCompressedBvhNode>,
    /// Triangle `i` of the reordered buffer that the leaves index is triangle
    /// `triangle_order[i]` of the list the tree was built from: a permutation.
    pub triangle_order: Vec<u32>,
    /// The deepest interior node's depth (the root's is 0), which bounds the traversal's
    /// stack entries.
    pub max_interior_depth: u32,
}

impl CompressedBvh {
    /// Builds the tree: the binned-SAH binary tree of `Bvh::build`, each leaf split into
    /// single triangles, collapsed by `obvhs` (Ylitie et al.'s cost-optimal collapse into
    /// 8-wide nodes, leaves of 1 to 3 triangles, children ordered by octant) and quantised.
    /// The collapse never deepens a path, so interior nodes lie no deeper than the binary
    /// tree's `MAX_DEPTH` plus the 4 levels that split a leaf of `MAX_LEAF_SIZE`.
    ///
    /// An error (one line) when they lie deeper than the traversal's stack
    /// (`CWBVH_STACK_SIZE`) can follow, which takes a chain of leaves at the depth limit
    /// (never seen), when the scene spans 1e15 or more (obvhs's collapse costs would
    /// overflow), or when there are more triangles than the packed triangles address.
    pub fn build(triangles: &[Triangle]) -> Result<CompressedBvh, CompressedBvhError> {
        CompressedBvh::from_binary(&Bvh::build(triangles), triangles)
    }

    /// `build` from a binary BVH already built over `triangles`.
    pub fn from_binary(
        binary: &Bvh,
        triangles: &[Triangle],
    ) -> Result<CompressedBvh, CompressedBvhError> {
        // 9 words per packed triangle must index a u32 (`get_packed_traversal_triangle`)
        if triangles.len() >= (u32::MAX / PACKED_TRIANGLE_WORD_COUNT) as usize {
            return Err(CompressedBvhError::TooManyTriangles(triangles.len()));
        }
        // obvhs's collapse sums surface areas times costs over subtrees in f32: areas of
        // 1e30 (extents of 1e15) leave 1e8 of headroom below f32::MAX; beyond, infinite
        // costs trip its assertions
        if let Some(root) = binary.nodes.first() {
            let extent = root.bounds().extent();
            if !(extent.is_finite() && extent.max_element() < 1e15) {
                return Err(CompressedBvhError::TooFar(extent));
            }
        }
        let ordered = binary.reorder(triangles);
        let nodes = match binary.nodes.as_slice() {
            [] => Vec::new(),
            // obvhs collapses from an interior root
            [leaf] if leaf.triangle_count() == 1 => vec![single_leaf_root(&leaf.bounds())],
            nodes => {
                let tree = obvhs::bvh2::Bvh2 {
                    nodes: single_triangle_leaves(nodes, &ordered),
                    primitive_indices: (0..ordered.len() as u32).collect(),
                    ..Default::default()
                };
                let wide = obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh(&tree, 3, true, false);
                // Its primitives index the binary tree's order: compose below
                let order: Vec<u32> = wide.primitive_indices;
                return CompressedBvh::checked(
                    wide.nodes
                        .iter()
                        .map(GpuCompressedBvhNode::from_obvhs)
                        .collect(),
                    order
                        .iter()
                        .map(|&i| binary.triangle_order[i as usize])
                        .collect(),
                    triangles.len(),
                );
            }
        };
        CompressedBvh::checked(nodes, binary.triangle_order.clone(), triangles.len())
    }

    /// The tree of these nodes and order, or the error of a tree deeper than the stack.
    pub(super) fn checked(
        nodes: Vec<GpuCompressedBvhNode>,
        triangle_order: Vec<u32>,
        triangle_count: usize,
    ) -> Result<CompressedBvh, CompressedBvhError> {
        // A traversal's stack entry keeps a node's index in 24 bits (`cwbvh_stack_entry`)
        if nodes.len() > CWBVH_MAX_NODE_COUNT as usize {
            return Err(CompressedBvhError::TooManyNodes {
                triangle_count,
                nodes: nodes.len(),
            });
        }
        let max_interior_depth = max_interior_depth(&nodes);
        if max_interior_depth >= CWBVH_STACK_SIZE {
            return Err(CompressedBvhError::TooDeep {
                triangle_count,
                levels: max_interior_depth + 1,
            });
        }
        Ok(CompressedBvh {
            nodes,
            triangle_order,
            max_interior_depth,
        })
    }

    /// Reorders a per-triangle list into the order the leaves reference:
    /// `result[i] = items[triangle_order[i]]`.
    ///
    /// # Panics
    /// If `items` is shorter than the list the tree was built from.
    pub fn reorder<T: Clone>(&self, items: &[T]) -> Vec<T> {
        self.triangle_order
            .iter()
            .map(|&index| items[index as usize].clone())
            .collect()
    }

    /// Bytes of the node buffer.
    pub fn node_bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice())
    }
}

/// obvhs's binary node with this box, triangle count (0: interior) and first index.
fn obvhs_node(bounds: &Aabb, count: u32, first_index: u32) -> obvhs::bvh2::node::Bvh2Node {
    let vector = |v: Vec3| obvhs_glam::Vec3A::new(v.x, v.y, v.z);
    obvhs::bvh2::node::Bvh2Node {
        aabb: obvhs::aabb::Aabb::new(vector(bounds.lower), vector(bounds.upper)),
        prim_count: count,
        first_index,
        meta1: 0,
        meta2: 0,
    }
}

/// The binary tree as obvhs's collapse wants it: the same nodes at the same indices, each
/// leaf of k > 1 triangles (of `ordered`, the leaf order) made the root of a balanced
/// subtree of single-triangle leaves, appended pair by pair.
fn single_triangle_leaves(
    nodes: &[GpuBvhNode],
    ordered: &[Triangle],
) -> Vec<obvhs::bvh2::node::Bvh2Node> {
    let bounds_of = |first: u32, count: u32| {
        let of = |i: u32| Aabb::of_triangle(&ordered[i as usize].positions);
        (first + 1..first + count).fold(of(first), |bounds, i| bounds.union(of(i)))
    };
    let mut out: Vec<_> = nodes
        .iter()
        .map(|n| obvhs_node(&n.bounds(), n.triangle_count(), n.first_index()))
        .collect();
    let mut split: Vec<(usize, u32, u32)> = nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| n.triangle_count() > 1)
        .map(|(index, n)| (index, n.first_index(), n.triangle_count()))
        .collect();
    while let Some((index, first, count)) = split.pop() {
        let half = count / 2;
        let pair = out.len();
        out.push(obvhs_node(&bounds_of(first, half), 1, first));
        out.push(obvhs_node(
            &bounds_of(first + half, count - half),
            1,
            first + half,
        ));
        out[index].prim_count = 0;
        out[index].first_index = pair as u32;
        for (child, first, count) in [(pair, first, half), (pair + 1, first + half, count - half)] {
            if count > 1 {
                split.push((child, first, count));
            }
        }
    }
    out
}

/// The root of a one-triangle tree: one leaf child, its box the whole grid.
fn single_leaf_root(bounds: &Aabb) -> GpuCompressedBvhNode {
    // The smallest power-of-two cell with 255 cells spanning the box (as obvhs chooses)
    let exponent = |extent: f32| {
        let cell = (extent.max(1e-20) / 255.0).log2().ceil().exp2();
        (cell.to_bits() >> 23) as u8
    };
    let extent = bounds.extent();
    let mut node = GpuCompressedBvhNode {
        origin: bounds.lower.to_array(),
        exponents_inner_mask: [
            exponent(extent.x),
            exponent(extent.y),
            exponent(extent.z),
            0,
        ],
        ..GpuCompressedBvhNode::default()
    };
    node.child_meta[0] = 0b0010_0000;
    node.upper_x[0] = 255;
    node.upper_y[0] = 255;
    node.upper_z[0] = 255;
    node
}

/// The node index of interior child `slot` of `node`: `child_base` plus the interior
/// children in the slots before it.
pub fn compressed_child_node(node: &GpuCompressedBvhNode, slot: u32) -> u32 {
    let below = u32::from(node.inner_mask()) & ((1u32 << slot) - 1);
    node.child_base + below.count_ones()
}

/// The deepest interior node's depth, walking from the root (nodes out of range skipped).
fn max_interior_depth(nodes: &[GpuCompressedBvhNode]) -> u32 {
    let mut deepest = 0;
    let mut stack = vec![(0u32, 0u32)];
    while let Some((index, depth)) = stack.pop() {
        let Some(node) = nodes.get(index as usize) else {
            continue;
        };
        deepest = deepest.max(depth);
        for slot in 0..8 {
            if node.inner_mask() & (1 << slot) != 0 {
                stack.push((compressed_child_node(node, slot), depth + 1));
            }
        }
    }
    deepest
}

/// The traversal triangles of the compressed tree (`g_traversal_triangle_texels` of
/// `glsl/cwbvh.glsl`, read by `get_packed_traversal_triangle`): the vertex positions of
/// `triangles` (reordered by `CompressedBvh::reorder`), `PACKED_TRIANGLE_WORD_COUNT` floats
/// each, back to back, bit for bit, in RGBA32 texels (the last one padded with zeros).
pub fn packed_traversal_triangles(triangles: &[Triangle]) -> Vec<[f32; 4]> {
    let mut words: Vec<f32> = triangles
        .iter()
        .flat_map(|t| t.positions.iter().flat_map(|p| p.to_array()))
        .collect();
    words.resize(words.len().div_ceil(4) * 4, 0.0);
    words
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect()
}
