//! The 4-wide BVH that `glsl/bvh.glsl` traverses: the builder's binary tree collapsed so that
//! each node holds up to `WIDE_BVH_WIDTH` children, whose boxes a ray tests together. A
//! traversal then takes about half the steps of the binary tree's, and reads a node's four
//! boxes from 7 contiguous texels instead of two boxes from 4 texels in two places.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::traversal::get_bvh_leaf_triangle_count;
use super::{Aabb, GpuBvhNode};
use crate::contract::{
    WIDE_BVH_EMPTY_CHILD, WIDE_BVH_INDEX_MASK, WIDE_BVH_LEAF_COUNT_SHIFT, WIDE_BVH_STACK_SIZE,
    WIDE_BVH_WIDTH,
};

const WIDTH: usize = WIDE_BVH_WIDTH as usize;

/// One node of the wide BVH as `glsl/bvh.glsl` reads it (`WIDE_BVH_NODE_TEXEL_COUNT` RGBA32
/// texels, 112 bytes): its children's boxes, one coordinate of all four per texel, then their
/// references (`child`). An unused slot has the reference `WIDE_BVH_EMPTY_CHILD` (0, the
/// root's index, which is no node's child) and a box of zeros.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuWideBvhNode {
    /// The children's lower x, world space.
    pub lower_x: [f32; 4],
    /// Their upper x.
    pub upper_x: [f32; 4],
    /// Their lower y.
    pub lower_y: [f32; 4],
    /// Their upper y.
    pub upper_y: [f32; 4],
    /// Their lower z.
    pub lower_z: [f32; 4],
    /// Their upper z.
    pub upper_z: [f32; 4],
    /// Their references: a node index (interior child), a leaf's first triangle |
    /// its triangle count << `WIDE_BVH_LEAF_COUNT_SHIFT`, or `WIDE_BVH_EMPTY_CHILD`.
    pub children: [u32; 4],
}

impl GpuWideBvhNode {
    /// Child `slot`'s box, world space.
    pub fn child_bounds(&self, slot: usize) -> Aabb {
        Aabb {
            lower: Vec3::new(self.lower_x[slot], self.lower_y[slot], self.lower_z[slot]),
            upper: Vec3::new(self.upper_x[slot], self.upper_y[slot], self.upper_z[slot]),
        }
    }

    /// Sets child `slot`: its box (world space) and its reference.
    pub(super) fn set_child(&mut self, slot: usize, bounds: &Aabb, child: u32) {
        self.lower_x[slot] = bounds.lower.x;
        self.lower_y[slot] = bounds.lower.y;
        self.lower_z[slot] = bounds.lower.z;
        self.upper_x[slot] = bounds.upper.x;
        self.upper_y[slot] = bounds.upper.y;
        self.upper_z[slot] = bounds.upper.z;
        self.children[slot] = child;
    }
}

/// The reference to a leaf over triangles `first..first + count` (`count` from 1 to
/// `MAX_LEAF_SIZE`).
pub fn leaf_reference(first: u32, count: u32) -> u32 {
    debug_assert!(first <= WIDE_BVH_INDEX_MASK && (1..256).contains(&count));
    first | count << WIDE_BVH_LEAF_COUNT_SHIFT
}

/// The wide BVH of a binary one (`Bvh::nodes`, root first): each node takes its binary
/// node's two children and opens the interior child of largest surface area until it has
/// `WIDE_BVH_WIDTH` children or only leaves. Where some path of that tree would push more
/// than `WIDE_BVH_STACK_SIZE` entries (never seen; each node pushes up to width - 1), the
/// binary tree itself is returned in the wide layout (two children per node), whose paths
/// push at most its depth. Empty for an empty tree.
pub fn widen(nodes: &[GpuBvhNode]) -> Vec<GpuWideBvhNode> {
    widen_with_sources(nodes).0
}

/// Which binary node each child of a wide node is (`sources[w][slot]`, an index into the
/// binary nodes; 0 for an unused slot): motion blur's tree gives each wide child the boxes
/// its binary node has at each key (`super::motion`).
pub(super) type WideSources = Vec<[u32; WIDTH]>;

/// `widen`, and where its children come from.
pub(super) fn widen_with_sources(nodes: &[GpuBvhNode]) -> (Vec<GpuWideBvhNode>, WideSources) {
    if nodes.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let wide = widen_to_with_sources(nodes, WIDTH);
    if most_pushes(&wide.0) <= WIDE_BVH_STACK_SIZE as usize {
        wide
    } else {
        widen_to_with_sources(nodes, 2)
    }
}

/// `widen` with nodes of up to `width` children and no fallback (for the tests).
#[cfg(test)]
pub(super) fn widen_to(nodes: &[GpuBvhNode], width: usize) -> Vec<GpuWideBvhNode> {
    widen_to_with_sources(nodes, width).0
}

/// `widen_to`, and where its children come from.
fn widen_to_with_sources(nodes: &[GpuBvhNode], width: usize) -> (Vec<GpuWideBvhNode>, WideSources) {
    let mut wide = vec![GpuWideBvhNode::default()];
    let mut sources = vec![[0; WIDTH]];
    fill(nodes, 0, 0, width, &mut wide, &mut sources);
    (wide, sources)
}

/// The binary nodes that become the children of binary node `index`'s wide node (just
/// `index` for a leaf root).
fn collapsed_children(nodes: &[GpuBvhNode], index: usize, width: usize) -> Vec<usize> {
    let node = &nodes[index];
    if node.is_leaf() {
        return vec![index];
    }
    let first = node.first_index() as usize;
    let mut children = vec![first, first + 1];
    while children.len() < width {
        let largest = children
            .iter()
            .enumerate()
            .filter(|(_, &child)| !nodes[child].is_leaf())
            .max_by(|(_, &a), (_, &b)| {
                let area = |i: usize| nodes[i].bounds().surface_area();
                area(a).total_cmp(&area(b))
            })
            .map(|(position, _)| position);
        let Some(position) = largest else {
            break;
        };
        let opened = nodes[children[position]].first_index() as usize;
        children.splice(position..=position, [opened, opened + 1]);
    }
    children
}

fn fill(
    nodes: &[GpuBvhNode],
    index: usize,
    slot: usize,
    width: usize,
    wide: &mut Vec<GpuWideBvhNode>,
    sources: &mut WideSources,
) {
    let mut node = GpuWideBvhNode::default();
    let mut node_sources = [0; WIDTH];
    for (k, &child) in collapsed_children(nodes, index, width).iter().enumerate() {
        let binary = &nodes[child];
        let reference = if binary.is_leaf() {
            leaf_reference(binary.first_index(), binary.triangle_count())
        } else {
            let child_slot = wide.len();
            debug_assert!(child_slot as u32 <= WIDE_BVH_INDEX_MASK);
            wide.push(GpuWideBvhNode::default());
            sources.push([0; WIDTH]);
            fill(nodes, child, child_slot, width, wide, sources);
            child_slot as u32
        };
        node.set_child(k, &binary.bounds(), reference);
        node_sources[k] = child as u32;
    }
    wide[slot] = node;
    sources[slot] = node_sources;
}

/// The most stack entries that a traversal of `wide` can hold: over all paths from the root,
/// the sum of each node's children but one.
pub fn most_pushes(wide: &[GpuWideBvhNode]) -> usize {
    let mut most = 0;
    let mut stack = vec![(0usize, 0usize)];
    while let Some((index, pending)) = stack.pop() {
        let Some(node) = wide.get(index) else {
            continue;
        };
        let used = node
            .children
            .iter()
            .filter(|&&c| c != WIDE_BVH_EMPTY_CHILD)
            .count();
        let pushes = pending + used.saturating_sub(1);
        most = most.max(pushes);
        for &child in &node.children {
            if child != WIDE_BVH_EMPTY_CHILD && get_bvh_leaf_triangle_count(child) == 0 {
                stack.push((child as usize, pushes));
            }
        }
    }
    most
}
