//! The emissive triangles as the shaders read them: the lights' texel buffer
//! (`g_light_texels` of `glsl/importance_sampling.glsl`, RGBA32_UINT: a header, then one
//! entry per emissive triangle with its cumulative probability) and each packed triangle's
//! selection probability in normal.w (`get_light_selection_probability`, for MIS).

use bytemuck::{Pod, Zeroable};

use super::emissive::EmissiveTriangles;
use crate::render::gpu_types::GpuTriangle;

/// Texel 0 of the lights' texel buffer (`g_light_texels` of `glsl/importance_sampling.glsl`,
/// RGBA32_UINT, 16 bytes): the number of lights. `GpuLight`s follow it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuLightHeader {
    /// Number of lights, the `GpuLight`s after the header (GLSL `get_light_count`).
    pub light_count: u32,
    padding: [u32; 3],
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
    padding: [u32; 2],
}

impl GpuLightHeader {
    /// The header of a buffer of `light_count` lights.
    pub fn new(light_count: u32) -> GpuLightHeader {
        GpuLightHeader {
            light_count,
            padding: [0; 3],
        }
    }
}

impl GpuLight {
    /// Light entry for scene triangle `triangle_index` with cumulative probability `cdf`.
    pub fn new(triangle_index: u32, cdf: f32) -> GpuLight {
        GpuLight {
            triangle_index,
            cdf,
            padding: [0; 2],
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

/// Writes each triangle's light-selection probability into its packed normal.w, where MIS
/// reads it (`get_light_selection_probability`). `triangles` must be the packed triangles
/// the table was built from, in the same order.
pub fn annotate_selection_probabilities(lights: &EmissiveTriangles, triangles: &mut [GpuTriangle]) {
    for (triangle, &probability) in triangles.iter_mut().zip(&lights.selection_probability) {
        triangle.normal[3] = probability;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Triangle;
    use std::mem::{offset_of, size_of};

    #[test]
    fn lights_match_the_light_texels() {
        // Texel 0: uvec4(count, 0, 0, 0); texel 1 + i: uvec4(triangle index, cdf bits, 0, 0).
        assert_eq!(size_of::<GpuLightHeader>(), 16);
        assert_eq!(offset_of!(GpuLightHeader, light_count), 0);
        assert_eq!(offset_of!(GpuLightHeader, padding), 4);
        assert_eq!(size_of::<GpuLight>(), 16);
        assert_eq!(offset_of!(GpuLight, triangle_index), 0);
        assert_eq!(offset_of!(GpuLight, cdf), 4);
        assert_eq!(offset_of!(GpuLight, padding), 8);
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

        let mut packed: Vec<GpuTriangle> = triangles.iter().map(GpuTriangle::new).collect();
        annotate_selection_probabilities(&table, &mut packed);
        let read: Vec<f32> = packed.iter().map(|t| t.normal[3]).collect();
        assert_eq!(read, table.selection_probability);
        assert_eq!(read[1], 0.0);
    }
}
