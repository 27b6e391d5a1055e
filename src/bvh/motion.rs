//! Motion blur's BVH (Embree's linear motion blur, Cycles' motion steps): one tree over the
//! moving triangles whose nodes hold their children's boxes at each key of the shutter, so
//! that `glsl/bvh.glsl` (`bvh_enter_moving_children`) tests a ray against the boxes lerped at
//! the ray's time, each about as tight as a still tree's at that time. (A tree over each
//! triangle's box across the whole shutter, the first motion blur's, was 2.7 times slower
//! than a still frame on a sliding grid: a leaf's box spanned its triangles' whole travel.)
//!
//! Why the lerped boxes hold the triangles: between keys k and k + 1 the kernels place a
//! vertex at `(1 - f) v_k + f v_(k+1)` (`get_moving_packed_triangle`, `glsl/scene.glsl`). A
//! child's box at key k holds its triangles' vertices at key k, and the lerp of two boxes'
//! corners with the same weight holds the lerp of any two points they hold (both are linear
//! and monotone in each corner), so the lerped box holds every vertex at every time between
//! the keys, hence the triangle. A node's box at key k is the union of its children's at key
//! k, so the same holds all the way up.
//!
//! The topology is built once, by the SAH over each triangle's mean box over the keys (its
//! time-averaged box for linear motion between evenly spread keys: the middle key's box for a
//! translation), then every binary node gets its box at each key (`key_boxes`) and every wide
//! child its binary node's.

use glam::Vec3;
use rayon::prelude::*;

use super::traversal::{bvh_enter_boxes, EnteredChildren};
use super::wide::{widen_with_sources, WideSources};
use super::{build, Aabb, Bvh, GpuBvhNode, GpuWideBvhNode, MAX_DEPTH};
use crate::contract::{MOTION_BVH_KEY_TEXEL_COUNT, WIDE_BVH_EMPTY_CHILD};

/// Motion blur's 4-wide BVH: the tree, and its nodes' boxes at each key.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MotionBvh {
    /// The tree's shape, built over each triangle's mean box over the keys: its
    /// `triangle_order` (the leaves' order of the triangles and of their keys), its binary
    /// nodes (whose shape bounds a traversal's iterations) and its wide nodes (whose child
    /// references the kernels read; their boxes are the mean boxes', unused by the kernels).
    pub bvh: Bvh,
    /// `key_nodes[k][w]`: wide node `w` of `bvh.wide_nodes` with its children's boxes at key
    /// k (world space), the references the same.
    key_nodes: Vec<Vec<GpuWideBvhNode>>,
}

/// Texels (RGBA32) of one node of motion blur's tree with `steps` keys, twin of GLSL
/// `get_motion_bvh_node_texel_count`: `MOTION_BVH_KEY_TEXEL_COUNT` per key, then one of child
/// references.
pub fn get_motion_bvh_node_texel_count(steps: u32) -> u32 {
    MOTION_BVH_KEY_TEXEL_COUNT * steps + 1
}

impl MotionBvh {
    /// Builds the tree over triangles given by their boxes at each key: `key_boxes[k][i]` is
    /// triangle i's box at key k (world space). Every key lists the same triangles; at least
    /// two keys (`Shutter::steps`).
    ///
    /// # Panics
    /// If the keys list different numbers of triangles.
    pub fn build(key_boxes: &[Vec<Aabb>]) -> MotionBvh {
        let count = key_boxes.first().map_or(0, Vec::len);
        assert!(key_boxes.iter().all(|key| key.len() == count));
        let weight = 1.0 / key_boxes.len().max(1) as f32;
        let mean_boxes: Vec<Aabb> = (0..count)
            .into_par_iter()
            .map(|i| {
                let (lower, upper) = key_boxes.iter().fold(Default::default(), |(l, u), key| {
                    (l + key[i].lower * weight, u + key[i].upper * weight)
                });
                Aabb { lower, upper }
            })
            .collect();
        let Some((root, triangle_order)) = build::build_tree_of_boxes(&mean_boxes, MAX_DEPTH)
        else {
            return MotionBvh::default();
        };
        let nodes = build::flatten(&root);
        let (wide_nodes, sources) = widen_with_sources(&nodes);
        let key_nodes = key_boxes
            .par_iter()
            .map(|boxes| {
                let binary = key_boxes_of_nodes(&nodes, &triangle_order, boxes);
                wide_nodes_at_key(&wide_nodes, &sources, &binary)
            })
            .collect();
        MotionBvh {
            bvh: Bvh {
                nodes,
                triangle_order,
                wide_nodes,
            },
            key_nodes,
        }
    }

    /// How many keys the nodes hold boxes at (0 for an empty tree).
    pub fn steps(&self) -> u32 {
        if self.bvh.wide_nodes.is_empty() {
            0
        } else {
            self.key_nodes.len() as u32
        }
    }

    /// Wide node `node_index` with its children's boxes at `time` within the shutter (0: the
    /// first key, 1: the last), lerped between the two keys around it as the kernel lerps
    /// them (`bvh_enter_moving_children`).
    ///
    /// # Panics
    /// If `node_index` is out of range.
    pub fn node_at_time(&self, node_index: u32, time: f32) -> GpuWideBvhNode {
        let (key, fraction) = get_motion_segment(time, self.key_nodes.len() as u32);
        let before = &self.key_nodes[key as usize][node_index as usize];
        let after = &self.key_nodes[key as usize + 1][node_index as usize];
        let lerp =
            |a: [f32; 4], b: [f32; 4]| std::array::from_fn(|slot| mix(a[slot], b[slot], fraction));
        GpuWideBvhNode {
            lower_x: lerp(before.lower_x, after.lower_x),
            upper_x: lerp(before.upper_x, after.upper_x),
            lower_y: lerp(before.lower_y, after.lower_y),
            upper_y: lerp(before.upper_y, after.upper_y),
            lower_z: lerp(before.lower_z, after.lower_z),
            upper_z: lerp(before.upper_z, after.upper_z),
            children: before.children,
        }
    }

    /// The nodes as `glsl/bvh.glsl` reads them at `BINDING_BVH_NODES` with motion blur
    /// (`glsl/shared.h`): `get_motion_bvh_node_texel_count(steps)` RGBA32 texels per node,
    /// each key's six box texels (lower x, upper x, lower y, upper y, lower z, upper z of the
    /// four children, as float bits) in key order, then the child references.
    pub fn texels(&self) -> Vec<[u32; 4]> {
        let per_node = get_motion_bvh_node_texel_count(self.steps()) as usize;
        let mut texels = Vec::with_capacity(per_node * self.bvh.wide_nodes.len());
        for (index, node) in self.bvh.wide_nodes.iter().enumerate() {
            for key in &self.key_nodes {
                let at_key = &key[index];
                texels.extend(
                    [
                        at_key.lower_x,
                        at_key.upper_x,
                        at_key.lower_y,
                        at_key.upper_y,
                        at_key.lower_z,
                        at_key.upper_z,
                    ]
                    .map(|values| values.map(f32::to_bits)),
                );
            }
            texels.push(node.children);
        }
        texels
    }
}

/// The two keys around `time` (in [0, 1]) of `steps` evenly spread keys and the fraction of
/// the way between them, twin of GLSL `get_motion_segment` (`glsl/scene.glsl`, where `steps`
/// is `MOTION_STEPS`).
/// \return (the key at or before the time, 0 .. steps - 2; the fraction, in [0, 1])
pub fn get_motion_segment(time: f32, steps: u32) -> (u32, f32) {
    let scaled = time.clamp(0.0, 1.0) * (steps - 1) as f32;
    let key = (scaled as u32).min(steps - 2);
    (key, scaled - key as f32)
}

/// GLSL's `mix(x, y, a)` as the specification defines it: x (1 - a) + y a.
pub fn mix(x: f32, y: f32, a: f32) -> f32 {
    x * (1.0 - a) + y * a
}

/// Each binary node's box at one key: a leaf's the union of its triangles' `boxes` (indexed
/// by the scene's triangle, `triangle_order` maps the leaves' ranges to them), an interior
/// node's the union of its children's (stored after it, so one pass from the back).
fn key_boxes_of_nodes(nodes: &[GpuBvhNode], triangle_order: &[u32], boxes: &[Aabb]) -> Vec<Aabb> {
    let mut node_boxes = vec![Aabb::EMPTY; nodes.len()];
    for (index, node) in nodes.iter().enumerate().rev() {
        let first = node.first_index() as usize;
        node_boxes[index] = if node.is_leaf() {
            triangle_order[first..first + node.triangle_count() as usize]
                .iter()
                .fold(Aabb::EMPTY, |bounds, &triangle| {
                    bounds.union(boxes[triangle as usize])
                })
        } else {
            debug_assert!(first > index);
            node_boxes[first].union(node_boxes[first + 1])
        };
    }
    node_boxes
}

/// The wide nodes with each child's box that of its binary node (`sources`) at one key.
fn wide_nodes_at_key(
    wide_nodes: &[GpuWideBvhNode],
    sources: &WideSources,
    binary_boxes: &[Aabb],
) -> Vec<GpuWideBvhNode> {
    wide_nodes
        .iter()
        .zip(sources)
        .map(|(node, sources)| {
            let mut at_key = GpuWideBvhNode::default();
            for (slot, (&child, &source)) in node.children.iter().zip(sources).enumerate() {
                if child != WIDE_BVH_EMPTY_CHILD {
                    at_key.set_child(slot, &binary_boxes[source as usize], child);
                }
            }
            at_key
        })
        .collect()
}

/// Twin of GLSL `bvh_enter_moving_children`: the children of interior node `node_index` of
/// motion blur's tree whose boxes at `time` (the kernel's `g_motion_time`) the ray enters
/// before `t_max`, nearest first (`bvh_enter_boxes` of `MotionBvh::node_at_time`).
pub fn bvh_enter_moving_children(
    motion: &MotionBvh,
    node_index: u32,
    time: f32,
    ray_origin: Vec3,
    inverse_direction: Vec3,
    t_max: f32,
) -> EnteredChildren {
    bvh_enter_boxes(
        &motion.node_at_time(node_index, time),
        ray_origin,
        inverse_direction,
        t_max,
    )
}
