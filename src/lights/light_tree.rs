//! A light tree (`--light-selection tree`): a bounding-volume hierarchy over the emissive
//! triangles whose nodes bound the position, orientation and power of the lights below
//! them, so that the shader chooses a light with a probability that follows its importance
//! to the shading point (Conty Estevez and Kulla, "Importance Sampling of Many Lights with
//! Adaptive Tree Splitting", HPG 2018; as pbrt-v4's `BVHLightSampler` does). Built here, on
//! the host; traversed by `glsl/light_tree.glsl` (Rust twin: `crate::cpu::light_tree`).
//!
//! The build follows pbrt-v4: one light per leaf; each interior node split where the
//! surface area orientation heuristic (SAOH) over 12 buckets of the centroids along each axis
//! is least. Nodes are stored depth first: an interior node's first child follows it, its
//! second child's index is stored. Each light keeps its leaf's bit trail (bit d: the second
//! child was taken at depth d), with which the shader recomputes a light's selection
//! probability for MIS by walking from the root to it.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use super::emissive::{triangle_power, EmissiveTriangles};
use crate::contract::{LIGHT_TREE_FLAG_LEAF, LIGHT_TREE_FLAG_TWO_SIDED, LIGHT_TREE_MAX_DEPTH};
use crate::scene::motion::KeyTriangle;
use crate::scene::Triangle;

/// Buckets of the SAOH split along each axis (pbrt-v4's 12).
const SPLIT_BUCKETS: usize = 12;

/// How much a cone's cosine is lowered when it is stored (the bounds widened): the f32
/// rounding of a union of cones must never leave a light outside its node's cone, which would
/// make the tree call it unreachable where it is not. 1e-5 widens a cone by at most 0.26
/// degrees (at a cosine near 1), which costs nothing measurable in importance.
const CONE_COSINE_MARGIN: f64 = 1e-5;

/// Motion blur's keys of the triangles a light tree is built over (`LightTree::build_over_keys`).
#[derive(Clone, Copy, Debug)]
pub struct LightKeys<'a> {
    /// `keys[k][i]`: the scene's triangle i at key k (`SceneMotion::triangles`); empty for a
    /// still scene.
    pub keys: &'a [Vec<KeyTriangle>],
    /// `order[j]`: the scene's index of the triangle stored j-th, which the tree's triangles
    /// are in (the BVH's leaf order); `None`: the scene's order.
    pub order: Option<&'a [u32]>,
}

impl LightKeys<'_> {
    /// A still scene: no keys.
    pub const STILL: LightKeys<'static> = LightKeys {
        keys: &[],
        order: None,
    };

    /// The stored triangle `stored` at every key.
    fn of(&self, stored: u32) -> impl Iterator<Item = &KeyTriangle> + '_ {
        let index = self.order.map_or(stored, |order| order[stored as usize]) as usize;
        self.keys.iter().map(move |key| &key[index])
    }
}

/// The bounds of one or more lights (pbrt-v4's `LightBounds`), in f64 while building.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Corner of the box around the lights with the smallest coordinates, world space.
    pub min: DVec3,
    /// Corner with the largest coordinates.
    pub max: DVec3,
    /// Emitted power (`triangle_power`), summed over the lights.
    pub phi: f64,
    /// Unit axis of the cone that holds every light's emitting normal.
    pub direction: DVec3,
    /// Cosine of that cone's half angle theta_o (1: a single normal; -1: every direction).
    pub cos_theta_o: f64,
    /// Cosine of the angle theta_e beyond the normals' cone into which light is emitted
    /// (triangles: pi / 2, so 0).
    pub cos_theta_e: f64,
    /// Whether any light emits from both sides (the cone then holds the normals and their
    /// opposites).
    pub two_sided: bool,
}

impl LightBounds {
    /// The bounds of an emissive triangle; `None` for one with no power.
    pub fn of_triangle(triangle: &Triangle) -> Option<LightBounds> {
        let phi = f64::from(triangle_power(triangle));
        // (NaN, from a degenerate triangle, is no light either.)
        if phi.is_nan() || phi <= 0.0 {
            return None;
        }
        let p = triangle.positions.map(|p| p.as_dvec3());
        Some(LightBounds {
            min: p[0].min(p[1]).min(p[2]),
            max: p[0].max(p[1]).max(p[2]),
            phi,
            direction: triangle.normal.as_dvec3().normalize(),
            cos_theta_o: 1.0,
            cos_theta_e: 0.0,
            two_sided: triangle.double_sided,
        })
    }

    /// The bounds of an emissive triangle over motion blur's `keys` (the same triangle at
    /// each key across the shutter): its box holds it at every time of the shutter (rays see
    /// its vertices lerped between two keys, inside the keys' boxes), its normals' cone holds
    /// its normal at every key (between two keys the lerped triangle's normal lies close to
    /// the arc between theirs, the closer the more `--motion-steps`). So the tree does not call
    /// it unreachable where it shines during the shutter. Its power is the frame's. `None` for
    /// one with no power.
    pub fn over_keys<'k>(
        triangle: &Triangle,
        keys: impl IntoIterator<Item = &'k KeyTriangle>,
    ) -> Option<LightBounds> {
        let frame = LightBounds::of_triangle(triangle)?;
        Some(keys.into_iter().fold(frame, |bounds, key| {
            let p = key.positions.map(|p| p.as_dvec3());
            let (direction, cos_theta_o) = union_cones(
                (bounds.direction, bounds.cos_theta_o),
                (key.normal.as_dvec3().normalize(), 1.0),
            );
            LightBounds {
                min: bounds.min.min(p[0]).min(p[1]).min(p[2]),
                max: bounds.max.max(p[0]).max(p[1]).max(p[2]),
                direction,
                cos_theta_o,
                ..bounds
            }
        }))
    }

    /// The centre of the box.
    pub fn centroid(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// The bounds of the lights of both (pbrt-v4's `Union`).
    pub fn union(&self, other: &LightBounds) -> LightBounds {
        let (direction, cos_theta_o) = union_cones(
            (self.direction, self.cos_theta_o),
            (other.direction, other.cos_theta_o),
        );
        LightBounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
            phi: self.phi + other.phi,
            direction,
            cos_theta_o,
            cos_theta_e: self.cos_theta_e.min(other.cos_theta_e),
            two_sided: self.two_sided || other.two_sided,
        }
    }

    /// pbrt-v4's `EvaluateCost`: phi times the orientation measure M_Omega times the box's
    /// surface area, times the box's aspect along `axis` (which favours splitting it across
    /// its longest side).
    fn split_cost(&self, centroid_extent: DVec3, axis: usize) -> f64 {
        use std::f64::consts::PI;
        let theta_o = self.cos_theta_o.clamp(-1.0, 1.0).acos();
        let theta_e = self.cos_theta_e.clamp(-1.0, 1.0).acos();
        let theta_w = (theta_o + theta_e).min(PI);
        let sin_theta_o = (1.0 - self.cos_theta_o * self.cos_theta_o).max(0.0).sqrt();
        let m_omega = 2.0 * PI * (1.0 - self.cos_theta_o)
            + PI / 2.0
                * (2.0 * theta_w * sin_theta_o
                    - (theta_o - 2.0 * theta_w).cos()
                    - 2.0 * theta_o * sin_theta_o
                    + self.cos_theta_o);
        let extent = centroid_extent[axis];
        let aspect = if extent > 0.0 {
            centroid_extent.max_element() / extent
        } else {
            1.0
        };
        let d = self.max - self.min;
        let area = 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
        self.phi * m_omega * aspect * area
    }
}

/// The smallest cone (pbrt-v4's `DirectionCone` `Union`) that holds two cones, each an axis
/// and the cosine of its half angle.
fn union_cones(a: (DVec3, f64), b: (DVec3, f64)) -> (DVec3, f64) {
    use std::f64::consts::PI;
    let theta_a = a.1.clamp(-1.0, 1.0).acos();
    let theta_b = b.1.clamp(-1.0, 1.0).acos();
    let theta_d = a.0.dot(b.0).clamp(-1.0, 1.0).acos();
    if (theta_d + theta_b).min(PI) <= theta_a {
        return a;
    }
    if (theta_d + theta_a).min(PI) <= theta_b {
        return b;
    }
    let theta_o = 0.5 * (theta_a + theta_d + theta_b);
    if theta_o >= PI {
        return (a.0, -1.0);
    }
    // Rotate a's axis towards b's by theta_o - theta_a.
    let axis = a.0.cross(b.0);
    if axis.length_squared() < 1e-24 {
        return (a.0, -1.0);
    }
    let rotation = glam::DQuat::from_axis_angle(axis.normalize(), theta_o - theta_a);
    ((rotation * a.0).normalize(), theta_o.cos())
}

/// One node of the light tree as the shader reads it: four RGBA32_UINT texels of the lights'
/// texel buffer (`light_tree_node_t` of `glsl/light_tree.glsl`, read by
/// `get_light_tree_node`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLightTreeNode {
    /// xyz: the box's smallest corner, world space; w: the power phi below the node.
    pub bounds_min_phi: [f32; 4],
    /// xyz: the box's largest corner; w: the bits of the second child's node index (an
    /// interior node) or of the light's index in the light list (a leaf).
    pub bounds_max_index: [f32; 4],
    /// xyz: the unit axis of the normals' cone; w: cos theta_o.
    pub direction_cos_theta_o: [f32; 4],
    /// x: cos theta_e; y: the bits of the flags (`LIGHT_TREE_FLAG_*`); zw: 0.
    pub cos_theta_e_flags: [f32; 4],
}

impl GpuLightTreeNode {
    /// The node of `bounds`; `index`: the second child's node (interior) or the light (leaf).
    fn new(bounds: &LightBounds, index: u32, leaf: bool) -> GpuLightTreeNode {
        let mut flags = 0;
        if leaf {
            flags |= LIGHT_TREE_FLAG_LEAF;
        }
        if bounds.two_sided {
            flags |= LIGHT_TREE_FLAG_TWO_SIDED;
        }
        let widened = |cosine: f64| (cosine - CONE_COSINE_MARGIN).max(-1.0) as f32;
        let v = |p: DVec3| p.as_vec3();
        let (min, max, w) = (v(bounds.min), v(bounds.max), v(bounds.direction));
        GpuLightTreeNode {
            bounds_min_phi: [min.x, min.y, min.z, bounds.phi as f32],
            bounds_max_index: [max.x, max.y, max.z, f32::from_bits(index)],
            direction_cos_theta_o: [w.x, w.y, w.z, widened(bounds.cos_theta_o)],
            cos_theta_e_flags: [widened(bounds.cos_theta_e), f32::from_bits(flags), 0.0, 0.0],
        }
    }
}

/// The light tree over a scene's emissive triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct LightTree {
    /// The nodes, depth first (the root first); empty without lights.
    pub nodes: Vec<GpuLightTreeNode>,
    /// For each light of the table (`EmissiveTriangles::triangle_indices` order), the bit
    /// trail of its leaf: bit d is 1 where the walk from the root takes the second child at
    /// depth d.
    pub bit_trails: Vec<u32>,
    /// The depth of the deepest leaf (0: the root is a leaf), at most `LIGHT_TREE_MAX_DEPTH`.
    pub depth: u32,
}

/// A light while building: its index in the table and its bounds.
#[derive(Clone, Copy)]
struct BuildLight {
    index: u32,
    bounds: LightBounds,
}

impl LightTree {
    /// Builds the tree over the lights of `lights`, whose triangles are `triangles` (the
    /// ones the table was made from, in the same order).
    pub fn build(triangles: &[Triangle], lights: &EmissiveTriangles) -> LightTree {
        LightTree::build_over_keys(triangles, lights, LightKeys::STILL)
    }

    /// `build`, each light bounded over motion blur's `keys` (`LightBounds::over_keys`), so
    /// that a light that moves during the shutter is reachable wherever it shines at some
    /// time of it: next-event estimation with the tree stays unbiased.
    pub fn build_over_keys(
        triangles: &[Triangle],
        lights: &EmissiveTriangles,
        keys: LightKeys,
    ) -> LightTree {
        let mut build: Vec<BuildLight> = lights
            .triangle_indices
            .iter()
            .enumerate()
            .filter_map(|(index, &triangle)| {
                let at_keys = keys.of(triangle);
                LightBounds::over_keys(&triangles[triangle as usize], at_keys).map(|bounds| {
                    BuildLight {
                        index: index as u32,
                        bounds,
                    }
                })
            })
            .collect();
        let mut tree = LightTree {
            nodes: Vec::new(),
            bit_trails: vec![0; lights.triangle_indices.len()],
            depth: 0,
        };
        if !build.is_empty() {
            tree.build_node(&mut build, 0, 0);
        }
        tree
    }

    /// Builds the subtree of `lights` at `depth` whose leaves' trails start with
    /// `bit_trail`; returns its bounds.
    fn build_node(&mut self, lights: &mut [BuildLight], depth: u32, bit_trail: u32) -> LightBounds {
        let node_index = self.nodes.len();
        if lights.len() == 1 {
            let light = lights[0];
            self.nodes
                .push(GpuLightTreeNode::new(&light.bounds, light.index, true));
            self.bit_trails[light.index as usize] = bit_trail;
            self.depth = self.depth.max(depth);
            return light.bounds;
        }
        let middle = split(lights, depth);
        // Placeholder, rewritten once the second child's index is known.
        self.nodes.push(GpuLightTreeNode::zeroed());
        let (below, above) = lights.split_at_mut(middle);
        let first = self.build_node(below, depth + 1, bit_trail);
        let second_index = self.nodes.len() as u32;
        let second = self.build_node(above, depth + 1, bit_trail | (1 << depth));
        let bounds = first.union(&second);
        self.nodes[node_index] = GpuLightTreeNode::new(&bounds, second_index, false);
        bounds
    }
}

/// Partitions `lights` (two or more) into two non-empty halves, the first `returned` of
/// them and the rest: by the least SAOH cost over the buckets of each axis; by their order
/// along the longest axis at the median where no bucket split exists or where the depth
/// left would not suffice for anything but a balanced tree (which keeps every leaf within
/// `LIGHT_TREE_MAX_DEPTH`).
fn split(lights: &mut [BuildLight], depth: u32) -> usize {
    let count = lights.len();
    let (mut low, mut high) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for light in lights.iter() {
        low = low.min(light.bounds.centroid());
        high = high.max(light.bounds.centroid());
    }
    let extent = high - low;
    // A balanced split from here needs ceil(log2(count)) more levels.
    let levels_needed = usize::BITS - (count - 1).leading_zeros();
    let balanced_only = depth + levels_needed + 2 > LIGHT_TREE_MAX_DEPTH;
    let mut best: Option<(f64, usize, usize)> = None;
    if !balanced_only {
        for axis in 0..3 {
            if extent[axis] <= 0.0 {
                continue;
            }
            let bucket_of = |light: &BuildLight| {
                let t = (light.bounds.centroid()[axis] - low[axis]) / extent[axis];
                ((t * SPLIT_BUCKETS as f64) as usize).min(SPLIT_BUCKETS - 1)
            };
            let mut buckets: [Option<LightBounds>; SPLIT_BUCKETS] = [None; SPLIT_BUCKETS];
            for light in lights.iter() {
                let b = &mut buckets[bucket_of(light)];
                *b = Some(b.map_or(light.bounds, |b| b.union(&light.bounds)));
            }
            for split_after in 0..SPLIT_BUCKETS - 1 {
                let union_of = |range: &[Option<LightBounds>]| {
                    range
                        .iter()
                        .flatten()
                        .fold(None, |acc: Option<LightBounds>, b| {
                            Some(acc.map_or(*b, |a| a.union(b)))
                        })
                };
                let (Some(below), Some(above)) = (
                    union_of(&buckets[..=split_after]),
                    union_of(&buckets[split_after + 1..]),
                ) else {
                    continue;
                };
                let cost = below.split_cost(extent, axis) + above.split_cost(extent, axis);
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, split_after));
                }
            }
        }
    }
    if let Some((_, axis, split_after)) = best {
        let bucket_of = |light: &BuildLight| {
            let t = (light.bounds.centroid()[axis] - low[axis]) / extent[axis];
            ((t * SPLIT_BUCKETS as f64) as usize).min(SPLIT_BUCKETS - 1)
        };
        // A stable partition, so that the build does not depend on the sort's whims.
        let (mut below, above): (Vec<BuildLight>, Vec<BuildLight>) =
            lights.iter().partition(|l| bucket_of(l) <= split_after);
        let middle = below.len();
        if middle > 0 && middle < count {
            below.extend(above);
            lights.copy_from_slice(&below);
            return middle;
        }
    }
    let axis = extent.max_position();
    lights.sort_by(|a, b| {
        a.bounds.centroid()[axis]
            .total_cmp(&b.bounds.centroid()[axis])
            .then(a.index.cmp(&b.index))
    });
    count / 2
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use std::mem::{offset_of, size_of};

    fn emitter(a: Vec3, b: Vec3, c: Vec3, emission: f32, double_sided: bool) -> Triangle {
        Triangle::new([a, b, c], Vec3::ONE, Vec3::splat(emission), double_sided).unwrap()
    }

    #[test]
    fn node_matches_light_tree_node_t() {
        // Four texels: (min, phi), (max, index bits), (direction, cos theta_o),
        // (cos theta_e, flag bits, 0, 0).
        assert_eq!(size_of::<GpuLightTreeNode>(), 64);
        assert_eq!(offset_of!(GpuLightTreeNode, bounds_min_phi), 0);
        assert_eq!(offset_of!(GpuLightTreeNode, bounds_max_index), 16);
        assert_eq!(offset_of!(GpuLightTreeNode, direction_cos_theta_o), 32);
        assert_eq!(offset_of!(GpuLightTreeNode, cos_theta_e_flags), 48);
        assert_eq!(std::mem::align_of::<GpuLightTreeNode>(), 4);
    }

    #[test]
    fn cone_union_holds_both_cones() {
        let a = (DVec3::Z, 1.0);
        let b = (DVec3::X, 1.0);
        let (w, cos) = union_cones(a, b);
        // Two normals 90 degrees apart: a cone of 45 degrees around their bisector.
        assert!((w - DVec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-12);
        assert!((cos - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
        assert_eq!(union_cones(a, (DVec3::Z, 0.5)), (DVec3::Z, 0.5));
        assert_eq!(union_cones(a, (-DVec3::Z, 1.0)).1, -1.0);
    }

    #[test]
    fn every_light_has_one_leaf_reached_by_its_trail() {
        let mut triangles = Vec::new();
        for i in 0..37 {
            let x = (i % 7) as f32;
            let z = (i / 7) as f32 * 1.5;
            triangles.push(emitter(
                Vec3::new(x, 0.0, z),
                Vec3::new(x + 0.3, 0.0, z),
                Vec3::new(x, 0.3, z + 0.1 * i as f32),
                1.0 + i as f32,
                i % 3 == 0,
            ));
        }
        // A non-emitter in between, which is no light.
        triangles.insert(5, emitter(Vec3::ZERO, Vec3::X, Vec3::Y, 0.0, false));
        let table = EmissiveTriangles::new(&triangles);
        let tree = LightTree::build(&triangles, &table);
        assert_eq!(tree.nodes.len(), 2 * 37 - 1);
        let leaf =
            |n: &GpuLightTreeNode| n.cos_theta_e_flags[1].to_bits() & LIGHT_TREE_FLAG_LEAF != 0;
        let mut seen = [false; 37];
        for (light, &trail) in tree.bit_trails.iter().enumerate() {
            let mut node = 0usize;
            let mut bits = trail;
            for _ in 0..=LIGHT_TREE_MAX_DEPTH {
                if leaf(&tree.nodes[node]) {
                    break;
                }
                node = if bits & 1 == 0 {
                    node + 1
                } else {
                    tree.nodes[node].bounds_max_index[3].to_bits() as usize
                };
                bits >>= 1;
            }
            assert!(leaf(&tree.nodes[node]));
            assert_eq!(
                tree.nodes[node].bounds_max_index[3].to_bits() as usize,
                light
            );
            seen[light] = true;
        }
        assert!(seen.iter().all(|&s| s));
        // The root holds all the power, and every light's box and normal.
        let root = &tree.nodes[0];
        let total: f32 = triangles.iter().map(triangle_power).sum();
        assert!((root.bounds_min_phi[3] - total).abs() < 1e-3 * total);
        let w = Vec3::from_slice(&root.direction_cos_theta_o[..3]);
        for t in triangles.iter().filter(|t| triangle_power(t) > 0.0) {
            assert!(t.normal.normalize().dot(w) >= root.direction_cos_theta_o[3] - 1e-6);
        }
        assert!(tree.depth <= LIGHT_TREE_MAX_DEPTH);
    }

    #[test]
    fn identical_lights_build_a_balanced_tree_within_the_depth_limit() {
        let t = emitter(Vec3::ZERO, Vec3::X, Vec3::Y, 1.0, false);
        let triangles = vec![t; 1000];
        let table = EmissiveTriangles::new(&triangles);
        let tree = LightTree::build(&triangles, &table);
        assert_eq!(tree.nodes.len(), 1999);
        assert_eq!(tree.depth, 10);
        let single = LightTree::build(&triangles[..1], &EmissiveTriangles::new(&triangles[..1]));
        assert_eq!(
            (single.nodes.len(), single.depth, single.bit_trails.clone()),
            (1, 0, vec![0])
        );
    }
}
