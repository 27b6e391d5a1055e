//! The binned surface-area-heuristic builder (Wald, "On fast Construction of SAH-based
//! Bounding Volume Hierarchies", IEEE RT 2007) and the flattening of its tree into the GPU
//! layout of `GpuBvhNode`.
//!
//! Each node bins its triangles' centroids into `BIN_COUNT` equal bins along the longest axis
//! of the centroids' box, evaluates the SAH at the `BIN_COUNT - 1` bin boundaries and
//! partitions the triangle indices in place. The children's boxes come out of the binning, so
//! each node costs two passes over its triangles. Subtrees are built in parallel (rayon) above
//! a size where a task pays, and the binning of the top nodes is parallel too.

use glam::Vec3;
use rayon::prelude::*;

use super::aabb::Aabb;
use super::GpuBvhNode;
use crate::contract::BVH_STACK_SIZE;
use crate::scene::Triangle;

/// Centroid bins per node. Wald (2007) found 16 bins within a few percent of the full SAH
/// sweep at a fraction of its cost.
pub const BIN_COUNT: usize = 16;

/// SAH cost of visiting an interior node: loading its two children's boxes (2 x 32 bytes)
/// and two slab tests, about 20 flops each.
pub const TRAVERSAL_COST: f32 = 1.0;

/// SAH cost of one ray-triangle test: loading three vertices (48 bytes) and Cramer's rule
/// (two cross and four dot products, ~40 flops), about the work and memory traffic of the
/// two slab tests above, hence the same cost.
pub const INTERSECTION_COST: f32 = 1.0;

/// Nodes with at most this many triangles are leaves without asking the SAH: below it the
/// split's traversal cost (a stack push/pop and divergence among SIMD lanes, which the SAH
/// does not see) outweighs the saved triangle tests.
pub const LEAF_SIZE: usize = 4;

/// Nodes with more triangles than this are split even when the SAH says splitting does not
/// pay (heavily overlapping triangles), so that the leaf loops of the shader stay short.
/// Only the depth limit and coincident centroids make larger leaves.
pub const MAX_LEAF_SIZE: usize = 16;

/// No leaf is deeper than this (the root has depth 0): a traversal of the binary tree pushes
/// at most one node per interior ancestor, so a stack of `BVH_STACK_SIZE` entries never
/// overflows (the wide tree bounds its own pushes, `wide::most_pushes`). Nodes at this depth
/// become leaves whatever their size; a binned SAH tree over 10^6 triangles is about 25 deep,
/// so this only matters for pathological inputs.
pub const MAX_DEPTH: u32 = BVH_STACK_SIZE;

/// Subtrees with more triangles than this are built in a rayon task of their own; smaller
/// ones (~10 us of work) would spend a noticeable share on task overhead.
const PARALLEL_RECURSION_THRESHOLD: usize = 4096;

/// Nodes with more triangles than this are binned in parallel, in chunks of
/// `BINNING_CHUNK` (64 KiB of indices: large enough that merging 16 bins per chunk is free).
const PARALLEL_BINNING_THRESHOLD: usize = 65536;
const BINNING_CHUNK: usize = 16384;

/// What the builder needs of a triangle.
#[derive(Clone, Copy, Debug)]
struct Primitive {
    bounds: Aabb,
    centroid: Vec3,
}

/// The triangles of a node: the box of their boxes and the box of their centroids.
#[derive(Clone, Copy, Debug)]
struct NodeBounds {
    bounds: Aabb,
    centroid_bounds: Aabb,
    count: usize,
}

impl NodeBounds {
    const EMPTY: NodeBounds = NodeBounds {
        bounds: Aabb::EMPTY,
        centroid_bounds: Aabb::EMPTY,
        count: 0,
    };

    fn add(mut self, primitive: &Primitive) -> NodeBounds {
        self.bounds = self.bounds.union(primitive.bounds);
        self.centroid_bounds = self.centroid_bounds.grow(primitive.centroid);
        self.count += 1;
        self
    }

    fn merge(self, other: NodeBounds) -> NodeBounds {
        NodeBounds {
            bounds: self.bounds.union(other.bounds),
            centroid_bounds: self.centroid_bounds.union(other.centroid_bounds),
            count: self.count + other.count,
        }
    }

    fn of(primitives: &[Primitive], indices: &[u32]) -> NodeBounds {
        indices
            .iter()
            .fold(NodeBounds::EMPTY, |b, &i| b.add(&primitives[i as usize]))
    }
}

/// The tree as the builder makes it, before flattening.
#[derive(Debug)]
pub(super) enum BuildNode {
    /// Triangles `first..first + count` of the reordered triangles.
    Leaf {
        bounds: Aabb,
        first: usize,
        count: usize,
    },
    /// Two subtrees.
    Interior {
        bounds: Aabb,
        children: Box<[BuildNode; 2]>,
    },
}

/// Maps a centroid to its bin along one axis.
struct Binning {
    axis: usize,
    origin: f32,
    scale: f32,
}

impl Binning {
    /// The bin of a centroid. `as usize` saturates (negative and NaN give 0), and the last
    /// bin takes the centroids on the box's upper face.
    fn bin_index(&self, centroid: Vec3) -> usize {
        let bin = ((centroid[self.axis] - self.origin) * self.scale) as usize;
        bin.min(BIN_COUNT - 1)
    }

    fn bin(&self, primitives: &[Primitive], indices: &[u32]) -> [NodeBounds; BIN_COUNT] {
        let mut bins = [NodeBounds::EMPTY; BIN_COUNT];
        for &index in indices {
            let primitive = &primitives[index as usize];
            let bin = self.bin_index(primitive.centroid);
            bins[bin] = bins[bin].add(primitive);
        }
        bins
    }
}

/// The best split of a node: bins `..bin` go left.
struct Split {
    bin: usize,
    /// SAH cost times the node's surface area (comparable with the leaf's).
    scaled_cost: f32,
    left: NodeBounds,
    right: NodeBounds,
}

/// Builds the tree over all triangles; `None` when there are none. The second value lists
/// the triangles in leaf order (see `Bvh::triangle_order`).
/// `max_depth` is `MAX_DEPTH` but for tests, which lower it to see the limit at work.
pub(super) fn build_tree(triangles: &[Triangle], max_depth: u32) -> Option<(BuildNode, Vec<u32>)> {
    let primitives: Vec<Primitive> = triangles
        .par_iter()
        .map(|triangle| Primitive::of(Aabb::of_triangle(&triangle.positions)))
        .collect();
    build_tree_of_primitives(primitives, max_depth)
}

/// `build_tree` over primitives given by their boxes (`Bvh::build_over_boxes`; motion blur's
/// mean box of each triangle over the keys, `MotionBvh::build`).
pub(super) fn build_tree_of_boxes(boxes: &[Aabb], max_depth: u32) -> Option<(BuildNode, Vec<u32>)> {
    build_tree_of_primitives(boxes.iter().map(|&b| Primitive::of(b)).collect(), max_depth)
}

impl Primitive {
    /// A primitive of box `bounds`, split by the box's centre.
    fn of(bounds: Aabb) -> Primitive {
        Primitive {
            bounds,
            centroid: bounds.centre(),
        }
    }
}

/// `build_tree` over `primitives`; `None` when there are none.
fn build_tree_of_primitives(
    primitives: Vec<Primitive>,
    max_depth: u32,
) -> Option<(BuildNode, Vec<u32>)> {
    if primitives.is_empty() {
        return None;
    }
    let mut order: Vec<u32> = (0..primitives.len() as u32).collect();
    let root_bounds = primitives
        .par_chunks(BINNING_CHUNK)
        .map(|chunk| chunk.iter().fold(NodeBounds::EMPTY, NodeBounds::add))
        .reduce(|| NodeBounds::EMPTY, NodeBounds::merge);
    let limits = Limits { max_depth };
    let root = build_node(&primitives, &mut order, 0, 0, root_bounds, &limits);
    Some((root, order))
}

/// What the recursion passes down unchanged.
struct Limits {
    /// Nodes at this depth become leaves.
    max_depth: u32,
}

/// Builds the subtree over `indices`, which are triangles `first..` of the final order.
fn build_node(
    primitives: &[Primitive],
    indices: &mut [u32],
    first: usize,
    depth: u32,
    node: NodeBounds,
    limits: &Limits,
) -> BuildNode {
    let count = indices.len();
    let leaf = BuildNode::Leaf {
        bounds: node.bounds,
        first,
        count,
    };
    if count <= LEAF_SIZE || depth >= limits.max_depth {
        return leaf;
    }
    // The SAH: a leaf costs C_i * N; a split costs C_t + C_i (A_L N_L + A_R N_R) / A. Both
    // are compared multiplied by A, which also works for flat boxes.
    let leaf_scaled_cost = INTERSECTION_COST * count as f32 * node.bounds.surface_area();
    let split = find_split(primitives, indices, &node);
    let (middle, left, right) = match split {
        Some((binning, split)) if split.scaled_cost < leaf_scaled_cost || count > MAX_LEAF_SIZE => {
            let middle = partition(indices, |index| {
                binning.bin_index(primitives[index as usize].centroid) < split.bin
            });
            (middle, split.left, split.right)
        }
        // All centroids coincide: no plane separates them and any halving is as good.
        None if count > MAX_LEAF_SIZE => {
            let middle = count / 2;
            (
                middle,
                NodeBounds::of(primitives, &indices[..middle]),
                NodeBounds::of(primitives, &indices[middle..]),
            )
        }
        _ => return leaf,
    };
    // The partition uses the binning's own bin_index, so both sides hold what the bins
    // counted, never nothing; this guard keeps an empty leaf (which the GPU layout would read
    // as an interior node, count 0) impossible even so.
    if middle == 0 || middle == count {
        return leaf;
    }
    let (left_indices, right_indices) = indices.split_at_mut(middle);
    let (left_node, right_node) = if count > PARALLEL_RECURSION_THRESHOLD {
        rayon::join(
            || build_node(primitives, left_indices, first, depth + 1, left, limits),
            || {
                build_node(
                    primitives,
                    right_indices,
                    first + middle,
                    depth + 1,
                    right,
                    limits,
                )
            },
        )
    } else {
        (
            build_node(primitives, left_indices, first, depth + 1, left, limits),
            build_node(
                primitives,
                right_indices,
                first + middle,
                depth + 1,
                right,
                limits,
            ),
        )
    };
    BuildNode::Interior {
        bounds: node.bounds,
        children: Box::new([left_node, right_node]),
    }
}

/// The cheapest of the `BIN_COUNT - 1` binned splits along the centroids' longest axis;
/// `None` when the centroids coincide.
fn find_split(
    primitives: &[Primitive],
    indices: &[u32],
    node: &NodeBounds,
) -> Option<(Binning, Split)> {
    let extent = node.centroid_bounds.extent();
    let axis = extent.max_position();
    // Zero (coincident centroids) or NaN (non-finite input): no plane to bin along.
    if extent[axis].is_nan() || extent[axis] <= 0.0 {
        return None;
    }
    let binning = Binning {
        axis,
        origin: node.centroid_bounds.lower[axis],
        scale: BIN_COUNT as f32 / extent[axis],
    };
    let bins = if indices.len() > PARALLEL_BINNING_THRESHOLD {
        indices
            .par_chunks(BINNING_CHUNK)
            .map(|chunk| binning.bin(primitives, chunk))
            .reduce(
                || [NodeBounds::EMPTY; BIN_COUNT],
                |a, b| std::array::from_fn(|i| a[i].merge(b[i])),
            )
    } else {
        binning.bin(primitives, indices)
    };
    // Suffix unions: right[k] holds bins k.. .
    let mut right = [NodeBounds::EMPTY; BIN_COUNT];
    let mut accumulated = NodeBounds::EMPTY;
    for k in (1..BIN_COUNT).rev() {
        accumulated = accumulated.merge(bins[k]);
        right[k] = accumulated;
    }
    let node_area = node.bounds.surface_area();
    let mut left = NodeBounds::EMPTY;
    let mut best: Option<Split> = None;
    for k in 1..BIN_COUNT {
        left = left.merge(bins[k - 1]);
        if left.count == 0 || right[k].count == 0 {
            continue;
        }
        let scaled_cost = TRAVERSAL_COST * node_area
            + INTERSECTION_COST
                * (left.bounds.surface_area() * left.count as f32
                    + right[k].bounds.surface_area() * right[k].count as f32);
        if best.as_ref().is_none_or(|b| scaled_cost < b.scaled_cost) {
            best = Some(Split {
                bin: k,
                scaled_cost,
                left,
                right: right[k],
            });
        }
    }
    best.map(|split| (binning, split))
}

/// Moves the indices for which `goes_left` holds to the front; returns how many there are.
fn partition(indices: &mut [u32], goes_left: impl Fn(u32) -> bool) -> usize {
    let mut middle = 0;
    for i in 0..indices.len() {
        if goes_left(indices[i]) {
            indices.swap(i, middle);
            middle += 1;
        }
    }
    middle
}

/// Flattens the tree depth first, the two children of an interior node side by side.
pub(super) fn flatten(root: &BuildNode) -> Vec<GpuBvhNode> {
    let mut nodes = vec![GpuBvhNode::default()];
    flatten_into(root, 0, &mut nodes);
    nodes
}

fn flatten_into(node: &BuildNode, slot: usize, nodes: &mut Vec<GpuBvhNode>) {
    match node {
        BuildNode::Leaf {
            bounds,
            first,
            count,
        } => nodes[slot] = GpuBvhNode::leaf(bounds, *first as u32, *count as u32),
        BuildNode::Interior { bounds, children } => {
            let first_child = nodes.len();
            nodes.extend([GpuBvhNode::default(); 2]);
            nodes[slot] = GpuBvhNode::interior(bounds, first_child as u32);
            flatten_into(&children[0], first_child, nodes);
            flatten_into(&children[1], first_child + 1, nodes);
        }
    }
}
