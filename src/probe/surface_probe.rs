//! The surface functions' probe (`glsl/probe_surface.comp`): runs `is_opaque_hit`,
//! `get_surface` and `get_bsdf` of `glsl/surface.glsl` (glTF model) on a buffer of inputs
//! against a scene with materials, packed as the renderer packs it (`SurfaceWords`), so that
//! tests can compare them with their Rust twins (`crate::cpu::gltf_surface`) reading the same
//! words.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{UVec2, Vec2, Vec3};

use crate::contract::{SPEC_SCENE_HAS_LAYERS, SPEC_SCENE_TEXTURE_SLOTS};
use crate::cpu::gltf_surface::SurfaceTexels;
use crate::error::{Error, Result};
use crate::kernels::{self, Bound, Resource};
use crate::probe::runner::Probe;
use crate::render::gpu_materials::{
    material_texel_words, scene_texture_slots, GpuMaterial, GpuTriangleShading,
};
use crate::render::gpu_textures::TextureAtlas;
use crate::render::gpu_types::{GpuTriangle, RenderUniforms};
use crate::scene::Scene;
use crate::vk::{Buffer, Context, TexelBufferView};

/// `probe_input_t` of `glsl/probe_surface.comp` (80 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SurfaceProbeInput {
    /// xyz: the ray's origin, world space; w: the hit's ray parameter t.
    pub ray_origin: [f32; 4],
    /// xyz: the ray's unit direction; w: 0.
    pub ray_direction: [f32; 4],
    /// xyz: the unit light direction of `get_bsdf`; w: 0.
    pub light: [f32; 4],
    /// x: the hit triangle; yz: `g_alpha_seed`; w: `g_ray_count`.
    pub triangle_seed: [u32; 4],
    /// xy: `sample_bsdf`'s random numbers; z: its lobe random number; w: 0.
    pub randoms: [f32; 4],
}

impl SurfaceProbeInput {
    /// The input for a hit at `origin + t direction` on triangle `triangle_index`, lit from
    /// `light`, with the globals `g_alpha_seed` and `g_ray_count` of the call.
    pub fn new(
        triangle_index: u32,
        origin: Vec3,
        direction: Vec3,
        t: f32,
        light: Vec3,
        alpha_seed: UVec2,
        ray_count: u32,
    ) -> SurfaceProbeInput {
        SurfaceProbeInput {
            ray_origin: origin.extend(t).to_array(),
            ray_direction: direction.extend(0.0).to_array(),
            light: light.extend(0.0).to_array(),
            triangle_seed: [triangle_index, alpha_seed.x, alpha_seed.y, ray_count],
            randoms: [0.0; 4],
        }
    }

    /// The same input with `sample_bsdf`'s random numbers.
    pub fn with_randoms(mut self, random_numbers: Vec2, lobe_random: f32) -> SurfaceProbeInput {
        self.randoms = [random_numbers.x, random_numbers.y, lobe_random, 0.0];
        self
    }
}

/// `probe_output_t` of `glsl/probe_surface.comp` (192 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SurfaceProbeOutput {
    /// xyz: `surface.geometric_normal`; w: `is_opaque_hit()` as 0 or 1.
    pub geometric_normal: [f32; 4],
    /// xyz: `surface.shading_normal`; w: 0.
    pub shading_normal: [f32; 4],
    /// rgb: the material's base colour; a: its metallic.
    pub base_color: [f32; 4],
    /// The material's roughness, specular, ior; w: `has_delta_lobe` as 0 or 1.
    pub factors: [f32; 4],
    /// rgb: the material's specular colour; a: 0.
    pub specular_color: [f32; 4],
    /// rgb: `surface.emission`; a: 0.
    pub emission: [f32; 4],
    /// rgb: `get_bsdf(surface, -direction, light)`; a: `get_bsdf_density` there.
    pub reflection: [f32; 4],
    /// The material's transmission, thickness, clearcoat and clearcoat roughness.
    pub layers: [f32; 4],
    /// xyz: `surface.clearcoat_normal`; w: `surface.eta`.
    pub clearcoat_normal: [f32; 4],
    /// xyz: `sample_bsdf`'s direction; w: its density.
    pub sampled: [f32; 4],
    /// rgb: `sample_bsdf`'s weight; a: its lobes as a float.
    pub sample_weight: [f32; 4],
    /// rgb: `surface.unlit_color`; a: the sample's eta.
    pub extras: [f32; 4],
}

/// A scene's triangles, shading data, materials and texture atlas, packed as
/// `crate::render::gpu_scene` packs them (without a BVH: in the scene's order), in the
/// words both the probe and the CPU twins read.
pub struct SurfaceWords {
    /// The packed triangles (`GpuTriangle`).
    pub triangles: Vec<u32>,
    /// The shading data (`GpuTriangleShading`).
    pub shading: Vec<u32>,
    /// The materials (`GpuMaterial`).
    pub materials: Vec<u32>,
    /// The texture atlas.
    pub atlas: TextureAtlas,
    /// The texture slots in which some material has a texture (`SCENE_TEXTURE_SLOTS`).
    pub texture_slots: u32,
    /// Whether it needs the layers (`SCENE_HAS_LAYERS`).
    pub has_layers: bool,
}

impl SurfaceWords {
    /// Packs `scene`, which must have materials.
    pub fn new(scene: &Scene) -> Result<SurfaceWords> {
        let Some(materials) = &scene.materials else {
            return Err(Error::InvalidSettings(
                "the surface probe needs a scene with materials".into(),
            ));
        };
        let atlas = TextureAtlas::new(&materials.textures, u64::from(u32::MAX))
            .map_err(|e| Error::MissingInput(format!("the scene's textures: {e}")))?;
        let triangles: Vec<GpuTriangle> = scene.triangles.iter().map(GpuTriangle::new).collect();
        let shading: Vec<GpuTriangleShading> = materials
            .triangles
            .iter()
            .map(GpuTriangleShading::new)
            .collect();
        let packed: Vec<GpuMaterial> = materials
            .materials
            .iter()
            .map(|m| GpuMaterial::new(m, materials, &atlas))
            .collect();
        Ok(SurfaceWords {
            triangles: bytemuck::cast_slice(&triangles).to_vec(),
            shading: bytemuck::cast_slice(&shading).to_vec(),
            materials: material_texel_words(&packed),
            atlas,
            texture_slots: scene_texture_slots(&packed),
            has_layers: materials.uses_layers(),
        })
    }

    /// The words as the CPU twins read them.
    pub fn texels(&self) -> SurfaceTexels<'_> {
        SurfaceTexels {
            triangles: &self.triangles,
            shading: &self.shading,
            materials: &self.materials,
            texture_texels: &self.atlas.texels,
            scene_texture_slots: self.texture_slots,
            scene_has_layers: self.has_layers,
            // The probe's kernel is not specialized for vertex attributes
            scene_vertex_attributes: 0,
        }
    }
}

/// Runs the surface probe against one packed scene.
pub struct SurfaceProbeRunner {
    probe: Probe,
    triangles: TexelBufferView,
    uniforms: Buffer,
    texture_texels: TexelBufferView,
    shading: TexelBufferView,
    materials: TexelBufferView,
}

impl SurfaceProbeRunner {
    /// Uploads `words` as the path tracer's texel buffers.
    pub fn new(context: &Arc<Context>, words: &SurfaceWords) -> Result<SurfaceProbeRunner> {
        let usage = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let texels = |name: &str, words: &[u32]| -> Result<TexelBufferView> {
            let buffer = Buffer::with_data(context, name, words, usage)?;
            Ok(TexelBufferView::rgba32_uint(context, buffer, name)?)
        };
        let mut uniforms: RenderUniforms = Zeroable::zeroed();
        let triangle_count =
            (4 * words.triangles.len() / std::mem::size_of::<GpuTriangle>()) as u32;
        uniforms.resolution_triangle_count_seed = [1, 1, triangle_count, 0];
        let atlas = Buffer::with_data(context, "probe texture texels", &words.atlas.texels, usage)?;
        Ok(SurfaceProbeRunner {
            probe: Probe::embedded(
                context,
                &kernels::PROBE_SURFACE,
                &[
                    (SPEC_SCENE_TEXTURE_SLOTS, words.texture_slots),
                    (SPEC_SCENE_HAS_LAYERS, u32::from(words.has_layers)),
                ],
                "the surface functions",
            )?,
            triangles: texels("probe triangles", &words.triangles)?,
            uniforms: Buffer::with_data(
                context,
                "probe uniforms",
                &[uniforms],
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            )?,
            texture_texels: TexelBufferView::rgba8_uint(context, atlas, "probe textures")?,
            shading: texels("probe shading data", &words.shading)?,
            materials: texels("probe materials", &words.materials)?,
        })
    }

    /// Evaluates the surface functions on every input and returns the outputs in order;
    /// each input's triangle must be one of the scene's.
    pub fn run(&self, inputs: &[SurfaceProbeInput]) -> Result<Vec<SurfaceProbeOutput>> {
        let bound = [
            (Resource::Triangles, Bound::TexelBuffer(&self.triangles)),
            (Resource::RenderUniforms, Bound::Buffer(&self.uniforms)),
            (
                Resource::TextureTexels,
                Bound::TexelBuffer(&self.texture_texels),
            ),
            (Resource::Shading, Bound::TexelBuffer(&self.shading)),
            (Resource::Materials, Bound::TexelBuffer(&self.materials)),
        ];
        self.probe.run_with(&bound, inputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // vec4 ray_origin, ray_direction, light; uvec4 triangle_seed; vec4 randoms
        assert_eq!(size_of::<SurfaceProbeInput>(), 80);
        assert_eq!(offset_of!(SurfaceProbeInput, randoms), 64);
        assert_eq!(offset_of!(SurfaceProbeInput, ray_direction), 16);
        assert_eq!(offset_of!(SurfaceProbeInput, light), 32);
        assert_eq!(offset_of!(SurfaceProbeInput, triangle_seed), 48);
        // twelve vec4s
        assert_eq!(size_of::<SurfaceProbeOutput>(), 192);
        assert_eq!(offset_of!(SurfaceProbeOutput, layers), 112);
        assert_eq!(offset_of!(SurfaceProbeOutput, clearcoat_normal), 128);
        assert_eq!(offset_of!(SurfaceProbeOutput, sampled), 144);
        assert_eq!(offset_of!(SurfaceProbeOutput, sample_weight), 160);
        assert_eq!(offset_of!(SurfaceProbeOutput, extras), 176);
        assert_eq!(offset_of!(SurfaceProbeOutput, shading_normal), 16);
        assert_eq!(offset_of!(SurfaceProbeOutput, base_color), 32);
        assert_eq!(offset_of!(SurfaceProbeOutput, factors), 48);
        assert_eq!(offset_of!(SurfaceProbeOutput, specular_color), 64);
        assert_eq!(offset_of!(SurfaceProbeOutput, emission), 80);
        assert_eq!(offset_of!(SurfaceProbeOutput, reflection), 96);
    }
}
