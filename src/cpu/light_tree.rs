//! Rust twins of `glsl/light_tree.glsl`: choosing an emissive triangle by the light tree's
//! importance to a shading point, and the probability of a given light, read from the same
//! words of the lights' texel buffer that the GPU reads
//! (`crate::lights::gpu_emissive::gpu_light_bytes_with_tree`), with the same maths.

use glam::Vec3;

use crate::contract::{
    LIGHT_TREE_FLAG_LEAF, LIGHT_TREE_FLAG_TWO_SIDED, LIGHT_TREE_MAX_DEPTH, ONE_MINUS_EPSILON,
};
use crate::cpu::texels::{fetch_float_texel, fetch_texel};

/// Twin of `NO_LIGHT`: what `sample_light_tree` returns where no light can reach the point
/// (also the selection word of a triangle that is no light, which the host writes).
pub use crate::lights::gpu_emissive::NO_LIGHT;

/// The words of `g_light_texels` (header, lights, tree nodes) as the twins read them.
#[derive(Clone, Copy, Debug)]
pub struct LightTexels<'a> {
    /// RGBA32_UINT texels, four words each.
    pub words: &'a [u32],
}

/// Twin of `light_tree_node_t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightTreeNodeT {
    /// Corner of the box with the smallest coordinates, world space.
    pub bounds_min: Vec3,
    /// Corner with the largest coordinates.
    pub bounds_max: Vec3,
    /// Emitted power below the node.
    pub phi: f32,
    /// Interior: the second child's node index; leaf: the light's index.
    pub index: u32,
    /// Unit axis of the normals' cone.
    pub direction: Vec3,
    /// Cosine of its half angle.
    pub cos_theta_o: f32,
    /// Cosine of the emission angle beyond the normals.
    pub cos_theta_e: f32,
    /// A single light.
    pub is_leaf: bool,
    /// Some light below emits from both sides.
    pub two_sided: bool,
}

/// Twin of `get_light_tree_first_texel`.
pub fn get_light_tree_first_texel(texels: LightTexels) -> u32 {
    fetch_texel(texels.words, 0).y
}

/// Twin of `get_light_tree_depth`.
pub fn get_light_tree_depth(texels: LightTexels) -> u32 {
    fetch_texel(texels.words, 0).z
}

/// Twin of `get_light_bit_trail`.
pub fn get_light_bit_trail(texels: LightTexels, light_index: u32) -> u32 {
    fetch_texel(texels.words, light_index as usize + 1).z
}

/// Twin of `get_light_tree_node`.
pub fn get_light_tree_node(texels: LightTexels, node_index: u32) -> LightTreeNodeT {
    let first = (get_light_tree_first_texel(texels) + 4 * node_index) as usize;
    let t0 = fetch_float_texel(texels.words, first);
    let t1 = fetch_texel(texels.words, first + 1);
    let t2 = fetch_float_texel(texels.words, first + 2);
    let t3 = fetch_texel(texels.words, first + 3);
    LightTreeNodeT {
        bounds_min: t0.truncate(),
        phi: t0.w,
        bounds_max: fetch_float_texel(texels.words, first + 1).truncate(),
        index: t1.w,
        direction: t2.truncate(),
        cos_theta_o: t2.w,
        cos_theta_e: f32::from_bits(t3.x),
        is_leaf: t3.y & LIGHT_TREE_FLAG_LEAF != 0,
        two_sided: t3.y & LIGHT_TREE_FLAG_TWO_SIDED != 0,
    }
}

/// Twin of `cos_sub_clamped`.
pub fn cos_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        return 1.0;
    }
    cos_a * cos_b + sin_a * sin_b
}

/// Twin of `sin_sub_clamped`.
pub fn sin_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        return 0.0;
    }
    sin_a * cos_b - cos_a * sin_b
}

/// Twin of `get_light_bounds_importance`.
pub fn get_light_bounds_importance(node: &LightTreeNodeT, position: Vec3, normal: Vec3) -> f32 {
    let center = 0.5 * (node.bounds_min + node.bounds_max);
    let to_point = position - center;
    let center_distance_squared = to_point.dot(to_point);
    let diagonal = node.bounds_max - node.bounds_min;
    let d2 = center_distance_squared.max(0.5 * diagonal.length());
    let wi = if center_distance_squared > 0.0 {
        to_point / center_distance_squared.sqrt()
    } else {
        Vec3::ZERO
    };
    let mut cos_theta_w = node.direction.dot(wi);
    if node.two_sided {
        cos_theta_w = cos_theta_w.abs();
    }
    let sin_theta_w = (1.0 - cos_theta_w * cos_theta_w).max(0.0).sqrt();
    let radius_squared = 0.25 * diagonal.dot(diagonal);
    let mut cos_theta_b = -1.0;
    if center_distance_squared > radius_squared {
        cos_theta_b = (1.0 - radius_squared / center_distance_squared)
            .max(0.0)
            .sqrt();
    }
    let sin_theta_b = (1.0f32 - cos_theta_b * cos_theta_b).max(0.0).sqrt();
    let sin_theta_o = (1.0 - node.cos_theta_o * node.cos_theta_o).max(0.0).sqrt();
    let cos_theta_x = cos_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, node.cos_theta_o);
    let sin_theta_x = sin_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, node.cos_theta_o);
    let cos_theta_p = cos_sub_clamped(sin_theta_x, cos_theta_x, sin_theta_b, cos_theta_b);
    if cos_theta_p <= node.cos_theta_e {
        return 0.0;
    }
    let mut importance = node.phi * cos_theta_p / d2;
    if normal != Vec3::ZERO {
        if normal.dot(center - position) + normal.abs().dot(0.5 * diagonal) <= 0.0 {
            return 0.0;
        }
        let cos_theta_i = -wi.dot(normal);
        let sin_theta_i = (1.0 - cos_theta_i * cos_theta_i).max(0.0).sqrt();
        importance *= cos_sub_clamped(sin_theta_i, cos_theta_i, sin_theta_b, cos_theta_b);
    }
    importance.max(0.0)
}

/// Twin of `get_light_tree_first_child_probability`.
// `!(a > 0.0)` as the GLSL has it: true for NaN too.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn get_light_tree_first_child_probability(
    texels: LightTexels,
    node: &LightTreeNodeT,
    node_index: u32,
    position: Vec3,
    normal: Vec3,
) -> f32 {
    let first = get_light_bounds_importance(
        &get_light_tree_node(texels, node_index + 1),
        position,
        normal,
    );
    let second =
        get_light_bounds_importance(&get_light_tree_node(texels, node.index), position, normal);
    if !(first + second > 0.0) {
        return -1.0;
    }
    first / (first + second)
}

/// Twin of `sample_light_tree`: (the light's index or `NO_LIGHT`, its probability).
pub fn sample_light_tree(
    texels: LightTexels,
    random_number: f32,
    position: Vec3,
    normal: Vec3,
) -> (u32, f32) {
    if get_light_tree_first_texel(texels) == 0 {
        return (NO_LIGHT, 0.0);
    }
    let mut u = random_number;
    let mut probability = 1.0f32;
    let mut node_index = 0u32;
    for _depth in 0..=LIGHT_TREE_MAX_DEPTH {
        let node = get_light_tree_node(texels, node_index);
        if node.is_leaf {
            if node_index > 0 || get_light_bounds_importance(&node, position, normal) > 0.0 {
                return (node.index, probability);
            }
            return (NO_LIGHT, 0.0);
        }
        let first =
            get_light_tree_first_child_probability(texels, &node, node_index, position, normal);
        if first < 0.0 {
            return (NO_LIGHT, 0.0);
        }
        if u < first {
            u = (u / first).min(ONE_MINUS_EPSILON);
            probability *= first;
            node_index += 1;
        } else {
            u = ((u - first) / (1.0 - first)).min(ONE_MINUS_EPSILON);
            probability *= 1.0 - first;
            node_index = node.index;
        }
    }
    (NO_LIGHT, 0.0)
}

/// Twin of `get_light_tree_probability`.
pub fn get_light_tree_probability(
    texels: LightTexels,
    light_index: u32,
    position: Vec3,
    normal: Vec3,
) -> f32 {
    if get_light_tree_first_texel(texels) == 0 {
        return 0.0;
    }
    let mut trail = get_light_bit_trail(texels, light_index);
    let mut probability = 1.0f32;
    let mut node_index = 0u32;
    for _depth in 0..=LIGHT_TREE_MAX_DEPTH {
        let node = get_light_tree_node(texels, node_index);
        if node.is_leaf {
            if node_index > 0 || get_light_bounds_importance(&node, position, normal) > 0.0 {
                return probability;
            }
            return 0.0;
        }
        let first =
            get_light_tree_first_child_probability(texels, &node, node_index, position, normal);
        if first < 0.0 {
            return 0.0;
        }
        if trail & 1 == 0 {
            probability *= first;
            node_index += 1;
        } else {
            probability *= 1.0 - first;
            node_index = node.index;
        }
        trail >>= 1;
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::emissive::EmissiveTriangles;
    use crate::lights::gpu_emissive::gpu_light_bytes_with_tree;
    use crate::lights::light_tree::{LightKeys, LightTree};
    use crate::probe::inputs::InputRng;
    use crate::scene::motion::KeyTriangle;
    use crate::scene::Triangle;

    /// A cluster of `count` small emitters of widely varying power around `center`, facing
    /// +y, every third two-sided.
    fn cluster(count: usize, center: Vec3, rng: &mut InputRng) -> Vec<Triangle> {
        (0..count)
            .map(|i| {
                let p = center + Vec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0));
                let size = rng.range(0.02, 0.1);
                let emission = 10f32.powf(rng.range(-2.0, 2.0));
                Triangle::new(
                    [
                        p,
                        p + Vec3::new(0.0, 0.0, size),
                        p + Vec3::new(size, 0.0, 0.0),
                    ],
                    Vec3::ONE,
                    Vec3::splat(emission),
                    i % 3 == 0,
                )
                .unwrap()
            })
            .collect()
    }

    fn words(triangles: &[Triangle]) -> (EmissiveTriangles, Vec<u32>) {
        let table = EmissiveTriangles::new(triangles);
        let tree = LightTree::build(triangles, &table);
        let bytes = gpu_light_bytes_with_tree(&table, &tree);
        (table, bytemuck::pod_collect_to_vec(&bytes))
    }

    #[test]
    fn a_light_that_turns_towards_a_point_during_the_shutter_is_reachable_from_it() {
        // Issue 55: light b faces down (-y) at the frame's time and up at the shutter's last
        // key; a point above it sees it only during the shutter. A tree of the frame's bounds
        // gives b probability 0 there (next-event estimation with the tree would miss its
        // light: bias); one bounded over the keys reaches it, and the probabilities over the
        // lights still sum to 1.
        let light = |x: f32, up: bool| {
            let (a, b, c) = (
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x, 0.0, 0.2),
                Vec3::new(x + 0.2, 0.0, 0.0),
            );
            let positions = if up { [a, b, c] } else { [a, c, b] };
            Triangle::new(positions, Vec3::ONE, Vec3::splat(5.0), false).unwrap()
        };
        let frame = [light(0.0, true), light(2.0, false)];
        assert!(frame[0].normal.y > 0.0 && frame[1].normal.y < 0.0);
        let key = |t: &Triangle| KeyTriangle {
            positions: t.positions,
            normal: t.normal,
        };
        let keys = vec![
            frame.iter().map(key).collect::<Vec<_>>(),
            [light(0.0, true), light(2.0, true)]
                .iter()
                .map(key)
                .collect(),
        ];
        let table = EmissiveTriangles::new(&frame);
        let probability_of_b = |tree: &LightTree| {
            let words: Vec<u32> =
                bytemuck::pod_collect_to_vec(&gpu_light_bytes_with_tree(&table, tree));
            let texels = LightTexels { words: &words };
            let above_b = Vec3::new(2.1, 1.0, 0.05);
            let sum: f32 = (0..2)
                .map(|i| get_light_tree_probability(texels, i, above_b, Vec3::ZERO))
                .sum();
            let b = table.triangle_indices.iter().position(|&t| t == 1).unwrap() as u32;
            (
                get_light_tree_probability(texels, b, above_b, Vec3::ZERO),
                sum,
            )
        };
        let (still, _) = probability_of_b(&LightTree::build(&frame, &table));
        assert_eq!(
            still, 0.0,
            "the frame's tree reaches b: the test has no teeth"
        );
        let keyed = LightKeys {
            keys: &keys,
            order: None,
        };
        let (moving, sum) = probability_of_b(&LightTree::build_over_keys(&frame, &table, keyed));
        assert!(moving > 0.0, "the tree over the keys does not reach b");
        assert!((sum - 1.0).abs() < 1e-5, "probabilities sum to {sum}");
        // Stored in another order (a BVH's), the keys follow the order
        let reversed = [frame[1], frame[0]];
        let order = [1u32, 0];
        let table_reversed = EmissiveTriangles::new(&reversed);
        let tree = LightTree::build_over_keys(
            &reversed,
            &table_reversed,
            LightKeys {
                keys: &keys,
                order: Some(&order),
            },
        );
        assert_eq!(tree, {
            let reordered: Vec<Vec<KeyTriangle>> = keys.iter().map(|k| vec![k[1], k[0]]).collect();
            LightTree::build_over_keys(
                &reversed,
                &table_reversed,
                LightKeys {
                    keys: &reordered,
                    order: None,
                },
            )
        });
    }

    #[test]
    fn sampled_probability_is_the_walks_and_sums_to_one() {
        // Points above a cluster of lights facing up (every third two-sided), without a
        // normal or with one facing the lights: every node's bound admits them (no dead
        // ends, see tests/light_tree.rs), so the lights' probabilities sum to 1.
        let mut rng = InputRng::new(22);
        let triangles = cluster(64, Vec3::ZERO, &mut rng);
        let (table, words) = words(&triangles);
        let texels = LightTexels { words: &words };
        for i in 0..200 {
            let position = rng.in_box(Vec3::new(-3.0, 0.2, -3.0), Vec3::new(3.0, 3.0, 3.0));
            let normal = if i % 2 == 0 { Vec3::ZERO } else { -Vec3::Y };
            let total: f64 = (0..table.triangle_indices.len() as u32)
                .map(|i| f64::from(get_light_tree_probability(texels, i, position, normal)))
                .sum();
            assert!((total - 1.0).abs() < 1e-5, "sum {total}");
            let (light, p) = sample_light_tree(texels, rng.uniform(), position, normal);
            assert_ne!(light, NO_LIGHT);
            let walked = get_light_tree_probability(texels, light, position, normal);
            assert!((p - walked).abs() <= 1e-4 * walked, "{p} vs {walked}");
        }
    }

    #[test]
    fn lights_behind_the_surface_are_never_chosen() {
        let mut rng = InputRng::new(7);
        // One-sided lights below y = 0 facing up, a cluster above y = 2 facing up: at y = 1
        // with the normal pointing down, only the ones below can contribute.
        let mut triangles = cluster(16, Vec3::new(0.0, -1.0, 0.0), &mut rng);
        let mut above = cluster(16, Vec3::new(0.0, 3.0, 0.0), &mut rng);
        for t in triangles.iter_mut().chain(above.iter_mut()) {
            t.double_sided = false;
        }
        let below_count = triangles.len() as u32;
        triangles.extend(above);
        let (_, words) = words(&triangles);
        let texels = LightTexels { words: &words };
        for _ in 0..500 {
            let position = Vec3::new(rng.range(-0.5, 0.5), 1.0, rng.range(-0.5, 0.5));
            let (light, p) = sample_light_tree(texels, rng.uniform(), position, -Vec3::Y);
            // No light (a dead end) is allowed; one of the lights above never.
            assert!(
                light == NO_LIGHT || (light < below_count && p > 0.0),
                "light {light}"
            );
            for i in below_count..2 * below_count {
                assert_eq!(
                    get_light_tree_probability(texels, i, position, -Vec3::Y),
                    0.0
                );
            }
        }
    }
}
