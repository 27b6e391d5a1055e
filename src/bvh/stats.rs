//! Statistics of a flattened BVH: its size, depth and surface-area-heuristic cost.

use std::fmt;

use super::build::{INTERSECTION_COST, TRAVERSAL_COST};
use super::GpuBvhNode;

/// What a BVH looks like.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStats {
    /// All nodes, interior and leaves.
    pub node_count: usize,
    /// Leaves.
    pub leaf_count: usize,
    /// Depth of the deepest leaf (the root has depth 0); at most `MAX_DEPTH`.
    pub max_depth: u32,
    /// Triangles in the largest leaf.
    pub max_leaf_size: u32,
    /// Triangles referenced by the leaves.
    pub triangle_count: usize,
    /// The tree's SAH cost relative to the root's box: the expected cost of a ray that hits
    /// the root box, sum over interior nodes of `TRAVERSAL_COST * A(node) / A(root)` plus
    /// sum over leaves of `INTERSECTION_COST * triangles * A(leaf) / A(root)`. Brute force
    /// costs `INTERSECTION_COST * triangle_count`.
    pub sah_cost: f32,
}

impl BvhStats {
    /// Walks the nodes from the root. Nodes that point outside the array are skipped, so
    /// that malformed input gives odd numbers rather than a panic.
    pub fn of(nodes: &[GpuBvhNode]) -> BvhStats {
        let mut stats = BvhStats::default();
        let Some(root) = nodes.first() else {
            return stats;
        };
        let root_area = root.bounds().surface_area();
        // Relative areas of a flat or point-like root are meaningless; count every node fully.
        let relative = |node: &GpuBvhNode| {
            if root_area > 0.0 {
                node.bounds().surface_area() / root_area
            } else {
                1.0
            }
        };
        let mut sah = 0.0f64;
        let mut stack = vec![(0usize, 0u32)];
        while let Some((index, depth)) = stack.pop() {
            let Some(node) = nodes.get(index) else {
                continue;
            };
            stats.node_count += 1;
            if node.is_leaf() {
                let count = node.triangle_count();
                stats.leaf_count += 1;
                stats.max_depth = stats.max_depth.max(depth);
                stats.max_leaf_size = stats.max_leaf_size.max(count);
                stats.triangle_count += count as usize;
                sah += f64::from(INTERSECTION_COST * count as f32 * relative(node));
            } else {
                sah += f64::from(TRAVERSAL_COST * relative(node));
                let first = node.first_index() as usize;
                stack.push((first + 1, depth + 1));
                stack.push((first, depth + 1));
            }
        }
        stats.sah_cost = sah as f32;
        stats
    }

    /// Mean triangles per leaf.
    pub fn mean_leaf_size(&self) -> f32 {
        self.triangle_count as f32 / self.leaf_count.max(1) as f32
    }
}

impl fmt::Display for BvhStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} nodes, {} leaves ({:.2} triangles on average, at most {}), depth {}, SAH cost {:.2} (brute force {})",
            self.node_count,
            self.leaf_count,
            self.mean_leaf_size(),
            self.max_leaf_size,
            self.max_depth,
            self.sah_cost,
            self.triangle_count
        )
    }
}
