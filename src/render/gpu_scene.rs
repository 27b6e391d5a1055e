//! The scene as the path-tracing kernel reads it: triangles (in BVH leaf order when a BVH
//! is used, with their positions also apart for the traversal's triangle tests), its lights
//! (`crate::lights::SceneLights`), the BVH nodes and the render uniforms, uploaded to the
//! device, with the specialization constants that go with them; the kernel's binding table
//! (`crate::kernels::bindings`) says where each is bound.

use std::sync::Arc;

use ash::vk;

use crate::bvh::{traversal_triangles, Bvh, BvhStats};
use crate::camera::Camera;
use crate::contract;
use crate::error::{Error, Result};
use crate::kernels::{Bound, Resource};
use crate::lights::SceneLights;
use crate::render::gpu_materials::{
    material_texel_words, scene_texture_slots, GpuMaterial, GpuTriangleShading,
};
use crate::render::gpu_textures::TextureAtlas;
use crate::render::gpu_types::{GpuTriangle, RenderUniforms};
use crate::render::settings::RenderSettings;
use crate::render::traversal::{constant_triangle_specialization, Traversal};
use crate::scene::Scene;
use crate::vk::{Buffer, CommandRunner, Context, TexelBufferView};

/// Whether a render of `scene` with `settings` can take the lean builds of the path tracer
/// (`crate::kernels::builds::WITHOUT_LIGHT_TREE`): no light tree, no path guiding, no
/// environment map to sample. `GpuScene::fits_lean_builds` says the same for an uploaded scene.
pub fn fits_lean_builds(scene: &Scene, settings: &RenderSettings) -> bool {
    let lights = SceneLights::new(scene, &scene.triangles);
    let uses_tree = settings
        .light_selection
        .uses_tree(lights.emissive.triangle_indices.len());
    render_fits_lean_builds(settings, uses_tree, &lights)
}

/// `fits_lean_builds` from the lights that the upload has already gathered.
fn render_fits_lean_builds(
    settings: &RenderSettings,
    uses_tree: bool,
    lights: &SceneLights,
) -> bool {
    settings.guiding.is_none() && !uses_tree && !lights.samples_environment()
}

/// The buffers of `glsl/materials.glsl`.
struct MaterialBuffers {
    shading: TexelBufferView,
    materials: TexelBufferView,
    texture_texels: TexelBufferView,
    environment: TexelBufferView,
    punctual_lights: TexelBufferView,
}

/// A scene uploaded for one traversal.
pub struct GpuScene {
    triangles: TexelBufferView,
    uniforms: Buffer,
    lights: TexelBufferView,
    bvh_nodes: Option<TexelBufferView>,
    /// The vertex positions alone, in leaf order, for the traversal (with a BVH only).
    traversal_triangles: Option<TexelBufferView>,
    /// Shading data, materials and texture texels (scenes with materials only).
    materials: Option<MaterialBuffers>,
    /// The specialization constants that the traversal needs (the constant triangles).
    pub specialization: Vec<(u32, u32)>,
    /// Emissive triangles, the count that the kernel's light search halves
    /// (`get_light_count()`).
    pub light_count: u64,
    /// With a light tree, the light searches' iterations per ray
    /// (`SceneLights::light_search_iterations`); `None`: the power CDF's.
    pub light_tree_iterations: Option<u64>,
    /// The BVH's shape, for bounding a traversal's loop iterations (`None` without a BVH).
    pub bvh_stats: Option<BvhStats>,
    /// Whether the render can take the lean builds (`fits_lean_builds`: no guiding, no light
    /// tree, no environment map to sample).
    pub fits_lean_builds: bool,
}

impl GpuScene {
    /// Uploads `scene` as `traversal` reads it, with the camera's image plane for the
    /// settings' aspect ratio and their seed in the render uniforms.
    pub fn upload(
        context: &Arc<Context>,
        commands: &CommandRunner,
        scene: &Scene,
        camera: &Camera,
        settings: &RenderSettings,
        traversal: Traversal,
    ) -> Result<GpuScene> {
        // With a BVH, triangles are stored in the order its leaves reference them; light
        // indices then refer to that order too.
        let bvh = (traversal == Traversal::Bvh).then(|| Bvh::build(&scene.triangles));
        let ordered_triangles = match &bvh {
            Some(bvh) => bvh.reorder(&scene.triangles),
            None => scene.triangles.clone(),
        };
        let mut gpu_triangles: Vec<GpuTriangle> =
            ordered_triangles.iter().map(GpuTriangle::new).collect();
        let mut scene_lights = SceneLights::new(scene, &ordered_triangles);
        let uses_tree = settings
            .light_selection
            .uses_tree(scene_lights.emissive.triangle_indices.len());
        if uses_tree {
            scene_lights = scene_lights.with_light_tree(&ordered_triangles);
        }
        scene_lights.annotate(&mut gpu_triangles);
        let texels = |name: &str, bytes: &[u8]| -> Result<TexelBufferView> {
            let buffer = Buffer::device_local_with_data(
                context,
                commands,
                name,
                bytes,
                vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            )?;
            Ok(TexelBufferView::rgba32_uint(
                context,
                buffer,
                &format!("scene's {name}"),
            )?)
        };
        let triangles = texels("triangles", bytemuck::cast_slice(&gpu_triangles))?;
        let uniforms = Buffer::with_data(
            context,
            "render uniforms",
            &[RenderUniforms::new(
                &camera.image_plane(settings.aspect()),
                settings.width,
                settings.height,
                scene.triangles.len() as u32,
                settings.seed,
            )],
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        let bvh_nodes = match &bvh {
            Some(bvh) => Some(texels("BVH nodes", bytemuck::cast_slice(&bvh.wide_nodes))?),
            None => None,
        };
        let traversal_triangles = match &bvh {
            Some(_) => Some(texels(
                "traversal triangles",
                bytemuck::cast_slice(&traversal_triangles(&ordered_triangles)),
            )?),
            None => None,
        };
        let lights = texels("lights", &scene_lights.emissive_bytes())?;
        let plain_materials;
        let scene_materials = match &scene.materials {
            Some(materials) => Some(materials),
            None if scene.needs_material_kernels() => {
                plain_materials =
                    crate::scene::materials::SceneMaterials::from_plain(&scene.triangles);
                Some(&plain_materials)
            }
            None => None,
        };
        // SCENE_TEXTURE_SLOTS, set with the materials' words
        let mut texture_slots = 0;
        let materials = match scene_materials {
            None => None,
            Some(scene_materials) => {
                let shading: Vec<GpuTriangleShading> = match &bvh {
                    Some(bvh) => bvh.reorder(&scene_materials.triangles),
                    None => scene_materials.triangles.clone(),
                }
                .iter()
                .map(GpuTriangleShading::new)
                .collect();
                let limit = u64::from(context.limits.max_texel_buffer_elements);
                let atlas = TextureAtlas::new(&scene_materials.textures, limit).map_err(|e| {
                    Error::MissingInput(format!("the scene's textures do not fit this device: {e}"))
                })?;
                let texture_bytes = atlas.texels.len() as u64 * 4;
                let memory = context.device_memory_bytes();
                if texture_bytes > memory / 2 {
                    return Err(Error::MissingInput(format!(
                        "the scene's textures need {} MiB, more than half of this device's {} MiB of memory",
                        texture_bytes >> 20,
                        memory >> 20
                    )));
                }
                let gpu_materials: Vec<GpuMaterial> = scene_materials
                    .materials
                    .iter()
                    .map(|m| GpuMaterial::new(m, scene_materials, &atlas))
                    .collect();
                texture_slots = scene_texture_slots(&gpu_materials);
                let texture_buffer = Buffer::device_local_with_data(
                    context,
                    commands,
                    "texture texels",
                    bytemuck::cast_slice(&atlas.texels),
                    vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
                )?;
                Some(MaterialBuffers {
                    shading: texels("shading data", bytemuck::cast_slice(&shading))?,
                    materials: texels(
                        "materials",
                        bytemuck::cast_slice(&material_texel_words(&gpu_materials)),
                    )?,
                    texture_texels: TexelBufferView::rgba8_uint(
                        context,
                        texture_buffer,
                        "scene's texture texels",
                    )?,
                    environment: texels(
                        "environment",
                        bytemuck::cast_slice(&scene_lights.environment_words()),
                    )?,
                    punctual_lights: texels(
                        "punctual lights",
                        bytemuck::cast_slice(&scene_lights.punctual_words()),
                    )?,
                })
            }
        };
        let mut specialization = constant_triangle_specialization(traversal, &ordered_triangles);
        specialization.push((
            contract::SPEC_LIGHT_SELECTION,
            if uses_tree {
                contract::LIGHT_SELECTION_TREE
            } else {
                contract::LIGHT_SELECTION_POWER
            },
        ));
        if let Some(scene_materials) = scene_materials {
            // What the material kernels compile out where the scene lacks it
            let flag = u32::from;
            specialization.extend([
                (
                    contract::SPEC_SCENE_HAS_ALPHA,
                    flag(scene_materials.uses_alpha()),
                ),
                (contract::SPEC_SCENE_TEXTURE_SLOTS, texture_slots),
                (
                    contract::SPEC_SCENE_HAS_LAYERS,
                    flag(scene_materials.uses_layers()),
                ),
                (
                    contract::SPEC_SCENE_HAS_ENVIRONMENT,
                    flag(scene_lights.has_environment()),
                ),
                (
                    contract::SPEC_SCENE_HAS_PUNCTUAL_LIGHTS,
                    flag(!scene_lights.punctual.is_empty()),
                ),
                (
                    contract::SPEC_SCENE_SAMPLES_ENVIRONMENT,
                    flag(scene_lights.samples_environment()),
                ),
                (
                    contract::SPEC_SCENE_HAS_SPECULAR,
                    flag(scene_materials.uses_specular()),
                ),
                (
                    contract::SPEC_SCENE_HAS_EMISSIVE_TRIANGLES,
                    flag(!scene_lights.emissive.triangle_indices.is_empty()),
                ),
            ]);
        }
        Ok(GpuScene {
            triangles,
            uniforms,
            lights,
            bvh_nodes,
            traversal_triangles,
            materials,
            specialization,
            light_count: scene_lights.emissive.triangle_indices.len() as u64,
            light_tree_iterations: scene_lights
                .tree
                .as_ref()
                .map(|_| scene_lights.light_search_iterations()),
            bvh_stats: bvh.as_ref().map(Bvh::stats),
            fits_lean_builds: render_fits_lean_builds(settings, uses_tree, &scene_lights),
        })
    }

    /// The scene's resource for a binding of the path tracer's table
    /// (`crate::kernels::bindings::PATH_TRACER`); `None` for one it does not hold (the
    /// accumulation image, the BVH without a BVH, materials without materials).
    pub fn resource(&self, resource: Resource) -> Option<Bound<'_>> {
        let materials = self.materials.as_ref();
        let texel = match resource {
            Resource::Triangles => &self.triangles,
            Resource::RenderUniforms => return Some(Bound::Buffer(&self.uniforms)),
            Resource::Lights => &self.lights,
            Resource::BvhNodes => self.bvh_nodes.as_ref()?,
            Resource::TraversalTriangles => self.traversal_triangles.as_ref()?,
            Resource::Shading => &materials?.shading,
            Resource::Materials => &materials?.materials,
            Resource::TextureTexels => &materials?.texture_texels,
            Resource::Environment => &materials?.environment,
            Resource::PunctualLights => &materials?.punctual_lights,
            _ => return None,
        };
        Some(Bound::TexelBuffer(texel))
    }
}
