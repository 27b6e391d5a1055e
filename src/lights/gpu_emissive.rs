//! The emissive triangles as `glsl/emissive_lights.glsl` reads them: the lights' texel
//! buffer (`g_light_texels`, RGBA32_UINT: a header, then one entry per emissive triangle
//! with its cumulative probability) and every scene triangle's selection word
//! (`g_light_selection_words`, R32_UINT: its selection probability's float bits, for MIS,
//! `get_light_selection_probability`). With a light tree (`--light-selection tree`,
//! `glsl/light_tree.glsl`), the header also says where the tree's nodes start (they follow
//! the lights) and how deep it is, each light's entry holds its leaf's bit trail, and the
//! selection word holds the triangle's index in the light list (`NO_LIGHT` for
//! non-emitters) instead of a probability.

use bytemuck::{Pod, Zeroable};

use super::emissive::EmissiveTriangles;
use super::light_tree::LightTree;

/// The selection word of a triangle that is no light, with a light tree (GLSL `NO_LIGHT` of
/// `glsl/light_tree.glsl`, which `sample_light_tree` also returns where no light reaches).
pub const NO_LIGHT: u32 = u32::MAX;

/// Texel 0 of the lights' texel buffer (`g_light_texels` of `glsl/emissive_lights.glsl`,
/// RGBA32_UINT, 16 bytes): the number of lights and where the light tree is. `GpuLight`s
/// follow it, then the tree's nodes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuLightHeader {
    /// Number of lights, the `GpuLight`s after the header (GLSL `get_light_count`).
    pub light_count: u32,
    /// Texel of the light tree's first node; 0: no tree (GLSL
    /// `get_light_tree_first_texel`).
    pub tree_first_texel: u32,
    /// Depth of the tree's deepest leaf (GLSL `get_light_tree_depth`).
    pub tree_depth: u32,
    padding: u32,
}

/// Texel 1 + i of the lights' texel buffer (16 bytes): light i.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// Index of the emissive triangle in the scene's (uploaded) triangles (GLSL
    /// `get_light_triangle_index`).
    pub triangle_index: u32,
    /// Probability of choosing this light or an earlier one, power-proportional; the last
    /// light's is exactly 1 (GLSL `get_light_cumulative_probability`, which reads the bits).
    pub cdf: f32,
    /// With a light tree, the bit trail of the light's leaf (GLSL `get_light_bit_trail`);
    /// else 0.
    pub bit_trail: u32,
    padding: u32,
}

impl GpuLightHeader {
    /// The header of a buffer of `light_count` lights.
    pub fn new(light_count: u32) -> GpuLightHeader {
        GpuLightHeader {
            light_count,
            tree_first_texel: 0,
            tree_depth: 0,
            padding: 0,
        }
    }
}

impl GpuLight {
    /// Light entry for scene triangle `triangle_index` with cumulative probability `cdf`.
    pub fn new(triangle_index: u32, cdf: f32) -> GpuLight {
        GpuLight {
            triangle_index,
            cdf,
            bit_trail: 0,
            padding: 0,
        }
    }
}

/// The bytes of the lights' texel buffer (`g_light_texels`): a `GpuLightHeader`, then one
/// `GpuLight` per light of the table, in the table's order.
pub fn gpu_light_bytes(lights: &EmissiveTriangles) -> Vec<u8> {
    let header = GpuLightHeader::new(lights.triangle_indices.len() as u32);
    let entries: Vec<GpuLight> = lights
        .triangle_indices
        .iter()
        .zip(&lights.cdf)
        .map(|(&index, &cdf)| GpuLight::new(index, cdf))
        .collect();
    let mut bytes = bytemuck::bytes_of(&header).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(&entries));
    bytes
}

/// The bytes of the lights' texel buffer with `tree` (built over `lights`): the header with
/// the tree's place and depth, the `GpuLight`s with their bit trails, then the tree's nodes.
/// Without lights, the same bytes as `gpu_light_bytes`.
pub fn gpu_light_bytes_with_tree(lights: &EmissiveTriangles, tree: &LightTree) -> Vec<u8> {
    let mut bytes = gpu_light_bytes(lights);
    if tree.nodes.is_empty() {
        return bytes;
    }
    let header = GpuLightHeader {
        tree_first_texel: 1 + lights.triangle_indices.len() as u32,
        tree_depth: tree.depth,
        ..GpuLightHeader::new(lights.triangle_indices.len() as u32)
    };
    bytes[..16].copy_from_slice(bytemuck::bytes_of(&header));
    for (light, &trail) in tree.bit_trails.iter().enumerate() {
        let at = 16 * (1 + light) + 8;
        bytes[at..at + 4].copy_from_slice(&trail.to_le_bytes());
    }
    bytes.extend_from_slice(bytemuck::cast_slice(&tree.nodes));
    bytes
}

/// The selection words (`g_light_selection_words`, `BINDING_LIGHT_SELECTION`), one per
/// triangle that the table was built from, in the same order: each triangle's
/// light-selection probability as float bits (0 for non-emitters), where MIS reads it
/// (`get_light_selection_probability`).
pub fn gpu_light_selection_words(lights: &EmissiveTriangles) -> Vec<u32> {
    lights
        .selection_probability
        .iter()
        .map(|probability| probability.to_bits())
        .collect()
}

/// The selection words with a light tree: each triangle's index in the light list,
/// `NO_LIGHT` for non-emitters, where MIS finds the light's bit trail
/// (`get_emissive_triangle_density`). Exact for any count of lights.
pub fn gpu_light_index_words(lights: &EmissiveTriangles) -> Vec<u32> {
    let mut words = vec![NO_LIGHT; lights.selection_probability.len()];
    for (light, &index) in lights.triangle_indices.iter().enumerate() {
        words[index as usize] = light as u32;
    }
    words
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Triangle;
    use std::mem::{offset_of, size_of};

    #[test]
    fn lights_match_the_light_texels() {
        // Texel 0: uvec4(count, tree's first texel, tree depth, 0); texel 1 + i:
        // uvec4(triangle index, cdf bits, bit trail, 0).
        assert_eq!(size_of::<GpuLightHeader>(), 16);
        assert_eq!(offset_of!(GpuLightHeader, light_count), 0);
        assert_eq!(offset_of!(GpuLightHeader, tree_first_texel), 4);
        assert_eq!(offset_of!(GpuLightHeader, tree_depth), 8);
        assert_eq!(offset_of!(GpuLightHeader, padding), 12);
        assert_eq!(size_of::<GpuLight>(), 16);
        assert_eq!(offset_of!(GpuLight, triangle_index), 0);
        assert_eq!(offset_of!(GpuLight, cdf), 4);
        assert_eq!(offset_of!(GpuLight, bit_trail), 8);
        assert_eq!(offset_of!(GpuLight, padding), 12);
    }

    #[test]
    fn light_bytes_are_the_texels_word_for_word() {
        let emitter = |emission: f32, scale: f32| {
            Triangle::new(
                [
                    glam::Vec3::ZERO,
                    glam::Vec3::X * scale,
                    glam::Vec3::Y * scale,
                ],
                glam::Vec3::ONE,
                glam::Vec3::splat(emission),
                false,
            )
            .unwrap()
        };
        let triangles = [emitter(1.0, 1.0), emitter(0.0, 1.0), emitter(3.0, 2.0)];
        let table = EmissiveTriangles::new(&triangles);
        // The layout spelled out as u32 words, as the shader reads them.
        let mut words: Vec<u32> = vec![2, 0, 0, 0];
        for (&index, &cdf) in table.triangle_indices.iter().zip(&table.cdf) {
            words.extend_from_slice(&[index, cdf.to_bits(), 0, 0]);
        }
        assert_eq!(
            gpu_light_bytes(&table),
            bytemuck::cast_slice::<u32, u8>(&words)
        );
        let empty = EmissiveTriangles::new(&triangles[1..2]);
        assert_eq!(gpu_light_bytes(&empty), vec![0u8; 16]);

        let words = gpu_light_selection_words(&table);
        let read: Vec<f32> = words.iter().copied().map(f32::from_bits).collect();
        assert_eq!(read, table.selection_probability);
        assert_eq!(read[1], 0.0);

        // With a tree: the header points past the lights, the trails in z, the nodes after.
        let tree = LightTree::build(&triangles, &table);
        let mut words: Vec<u32> = vec![2, 3, tree.depth, 0];
        for ((&index, &cdf), &trail) in table
            .triangle_indices
            .iter()
            .zip(&table.cdf)
            .zip(&tree.bit_trails)
        {
            words.extend_from_slice(&[index, cdf.to_bits(), trail, 0]);
        }
        words.extend_from_slice(bytemuck::cast_slice(&tree.nodes));
        assert_eq!(tree.bit_trails, vec![0, 1]);
        assert_eq!(
            gpu_light_bytes_with_tree(&table, &tree),
            bytemuck::cast_slice::<u32, u8>(&words)
        );
        assert_eq!(gpu_light_index_words(&table), vec![0, NO_LIGHT, 1]);
    }
}
