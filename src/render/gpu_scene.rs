//! The scene as the path-tracing kernel reads it: triangles (in BVH leaf order when a BVH
//! is used, with their positions also apart for the traversal's triangle tests), its lights
//! (`crate::lights::SceneLights`), the BVH nodes and the render uniforms, uploaded to the
//! device, with the summary the variant room reads (`crate::kernels::variant`); the kernel's binding table
//! (`crate::kernels::bindings`) says where each is bound.

use std::borrow::Cow;
use std::sync::Arc;

use ash::vk;

use crate::accel::SceneStructures;
use crate::bvh::{
    packed_traversal_triangles, reorder_by, traversal_triangles, Bvh, BvhStats, CompressedBvh,
    MotionBvh,
};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::kernels::variant::{
    self, path_tracer_variant, KernelSource, SceneSummary, Traversal, Variant, VariantSettings,
};
use crate::kernels::Build;
use crate::kernels::{Bound, Resource};
use crate::lights::{KeptLightBuffers, LightBuffers, LightKeys, SceneLights};
use crate::render::gpu_materials::{
    material_texel_words, scene_texture_slots, shading_texel_words, GpuMaterial,
};
use crate::render::gpu_motion::{motion_key_boxes, motion_texels};
use crate::render::gpu_textures::TextureAtlas;
use crate::render::gpu_types::{GpuTriangle, RenderUniforms};
use crate::render::settings::{Accel, RenderSettings};
use crate::scene::materials::SceneMaterials;
use crate::scene::{Scene, Triangle};
use crate::vk::{Buffer, CommandRunner, Context, TexelBufferView, VkResult};

mod upload_digest;
pub use upload_digest::{SameParts, UploadDigest};

/// Whether a render of `scene` with `settings` can take the lean builds of the path tracer
/// (`crate::kernels::variant::fits_lean_builds`).
pub fn fits_lean_builds(scene: &Scene, settings: &RenderSettings) -> bool {
    let lights = SceneLights::new(scene, &scene.triangles);
    let summary = scene_summary(scene, None, &lights, 0);
    variant::fits_lean_builds(&summary, &variant_settings(settings, &lights))
}

/// The build of the path tracer that `Renderer::new` takes for `scene` with `settings` and
/// `traversal` (the variant room's choice, which reads no texture slots).
pub fn embedded_build(
    scene: &Scene,
    settings: &RenderSettings,
    traversal: Traversal,
) -> Result<Build> {
    Ok(host_variant(scene, settings, traversal)?.build)
}

/// The variant of the path tracer (build and specialization) that `Renderer::new` takes for
/// `scene` with `settings` and `traversal`, decided on the host without a device: the
/// scenes whose materials use no textures get exactly the renderer's (the texture slots are
/// counted on the upload).
pub fn host_variant(
    scene: &Scene,
    settings: &RenderSettings,
    traversal: Traversal,
) -> Result<Variant> {
    let lights = SceneLights::new(scene, &scene.triangles);
    let materials = kernel_materials(scene);
    let summary = scene_summary(scene, materials.as_deref(), &lights, 0);
    let settings = variant_settings(settings, &lights);
    path_tracer_variant(&summary, &settings, traversal, KernelSource::Embedded)
}

/// The materials the kernels read: the scene's, or for a workshop scene that needs the
/// material kernels its plain ones (`Scene::needs_material_kernels`); `None` for the
/// workshop kernels.
fn kernel_materials(scene: &Scene) -> Option<Cow<'_, SceneMaterials>> {
    match &scene.materials {
        Some(materials) => Some(Cow::Borrowed(materials)),
        None if scene.needs_material_kernels() => {
            Some(Cow::Owned(SceneMaterials::from_plain(&scene.triangles)))
        }
        None => None,
    }
}

/// What the variant room reads of `scene`, of the materials the kernels read (`None`: the
/// workshop kernels), of its lights (`SceneLights::summary`) and of the texture slots its
/// materials use.
fn scene_summary(
    scene: &Scene,
    materials: Option<&SceneMaterials>,
    lights: &SceneLights,
    texture_slots: u32,
) -> SceneSummary {
    SceneSummary {
        triangle_count: scene.triangles.len(),
        materials: materials.is_some(),
        layers: materials.is_some_and(|m| m.uses_layers()),
        volume_scatter: materials.is_some_and(|m| m.uses_volume_scatter()),
        alpha: materials.is_some_and(|m| m.uses_alpha()),
        specular: materials.is_some_and(|m| m.uses_specular()),
        vertex_attributes: materials.map_or(0, |m| m.vertex_attributes()),
        texture_slots,
        ..lights.summary()
    }
}

/// The words of the triangles' binding: the triangles (in the traversal's order) and, for
/// motion blur, the keys after them (`motion_texels`, at the image's `aspect`).
fn triangle_texels<'a>(
    gpu_triangles: &'a [GpuTriangle],
    scene: &Scene,
    triangle_order: Option<&[u32]>,
    aspect: f32,
) -> Cow<'a, [u8]> {
    let triangles: &[u8] = bytemuck::cast_slice(gpu_triangles);
    match &scene.motion {
        Some(motion) => {
            let mut bytes = triangles.to_vec();
            let keys = motion_texels(motion, triangle_order, aspect);
            bytes.extend_from_slice(bytemuck::cast_slice(&keys));
            Cow::Owned(bytes)
        }
        None => Cow::Borrowed(triangles),
    }
}

/// What the variant room reads of `settings`, for a scene with `lights`
/// (`SceneLights::variant_settings` reads the light selection).
fn variant_settings(settings: &RenderSettings, lights: &SceneLights) -> VariantSettings {
    VariantSettings {
        guiding: settings.guiding.is_some(),
        ..lights.variant_settings(settings.light_selection)
    }
}

/// The lights of `scene` as `settings` select among them, its triangles uploaded as
/// `ordered` (the scene's in `order`, the BVH's leaf order, where there is one); under
/// motion blur the light tree bounds each light over the keys.
fn lights_of<'a>(
    scene: &'a Scene,
    ordered: &[Triangle],
    order: Option<&[u32]>,
    settings: &RenderSettings,
) -> SceneLights<'a> {
    let keys = LightKeys {
        keys: scene
            .motion
            .as_ref()
            .map_or(&[], |motion| &motion.triangles[..]),
        order,
    };
    SceneLights::new(scene, ordered).with_selection(settings.light_selection, ordered, keys)
}

/// The render uniforms of `scene` seen by `camera`, at `settings`' aspect, size and seed.
fn render_uniforms(scene: &Scene, camera: &Camera, settings: &RenderSettings) -> RenderUniforms {
    RenderUniforms::new(
        &camera.image_plane(settings.aspect()),
        settings.width,
        settings.height,
        scene.triangles.len() as u32,
        settings.seed,
    )
}

/// The trees a traversal reads: the binary tree it is built from (its shape bounds the
/// loops) and the compressed tree collapsed from it, as `traversal` asks.
struct SceneTrees {
    /// The traversal they serve: `Bvh` where `auto`'s compressed tree made way for the
    /// 4-wide one.
    traversal: Traversal,
    bvh: Option<Bvh>,
    compressed: Option<CompressedBvh>,
    /// Motion blur: the nodes of `MotionBvh` (a box per key), whose shape and order `bvh`
    /// holds, as the kernels read them instead of `bvh.wide_nodes`.
    motion_nodes: Option<Vec<[u32; 4]>>,
}

impl SceneTrees {
    /// Builds the trees `traversal` reads. Under `--accel auto`, a scene the compressed tree
    /// refuses (deeper than its stack, or beyond its quantisation's range) takes the 4-wide
    /// tree, with a warning; under `--accel compressed-bvh` it is refused.
    fn build(scene: &Scene, accel: Accel, traversal: Traversal) -> Result<SceneTrees> {
        // Motion blur: a tree whose nodes hold a box per key, lerped at the ray's time
        let (bvh, motion_nodes) = match (traversal.uses_bvh(), &scene.motion) {
            (false, _) => (None, None),
            (true, None) => (Some(Bvh::build(&scene.triangles)), None),
            (true, Some(motion)) => {
                let motion_bvh = MotionBvh::build(&motion_key_boxes(motion));
                let nodes = motion_bvh.texels();
                (Some(motion_bvh.bvh), Some(nodes))
            }
        };
        let mut trees = SceneTrees {
            traversal,
            bvh: None,
            compressed: None,
            motion_nodes,
        };
        if let (Some(bvh), Traversal::CompressedBvh) = (&bvh, traversal) {
            match CompressedBvh::from_binary(bvh, &scene.triangles) {
                Ok(compressed) => trees.compressed = Some(compressed),
                Err(reason) if accel == Accel::Auto => {
                    log::warn!("the 4-wide BVH instead of the compressed one: {reason}");
                    trees.traversal = Traversal::Bvh;
                }
                Err(reason) => return Err(Error::InvalidSettings(reason.to_string())),
            }
        }
        trees.bvh = bvh;
        Ok(trees)
    }

    /// The order of the triangles that the tree's leaves reference (the triangles, their
    /// shading data and the light indices are stored in it); `None` without a tree.
    fn triangle_order(&self) -> Option<&[u32]> {
        match (&self.compressed, &self.bvh) {
            (Some(compressed), _) => Some(&compressed.triangle_order),
            (None, Some(bvh)) => Some(&bvh.triangle_order),
            (None, None) => None,
        }
    }

    /// Uploads the traversal's bindings with `upload` (name, bytes): the nodes and the
    /// triangles (`ordered_triangles`, in `triangle_order`) of the compressed tree (packed
    /// triangles, 36 bytes) or of the 4-wide tree (48-byte triangles), at the same bindings
    /// (`SPEC_BVH_LAYOUT` tells which); `None` without a tree.
    fn upload_traversal(
        &self,
        ordered_triangles: &[Triangle],
        upload: impl Fn(&str, &[u8]) -> VkResult<TexelBufferView>,
    ) -> Result<Option<(TexelBufferView, TexelBufferView)>> {
        let views = match (&self.compressed, &self.bvh) {
            (Some(compressed), _) => Some((
                upload("BVH nodes", bytemuck::cast_slice(&compressed.nodes))?,
                upload(
                    "traversal triangles",
                    bytemuck::cast_slice(&packed_traversal_triangles(ordered_triangles)),
                )?,
            )),
            (None, Some(bvh)) => Some((
                match &self.motion_nodes {
                    Some(nodes) => upload("motion BVH nodes", bytemuck::cast_slice(nodes))?,
                    None => upload("BVH nodes", bytemuck::cast_slice(&bvh.wide_nodes))?,
                },
                upload(
                    "traversal triangles",
                    bytemuck::cast_slice(&traversal_triangles(ordered_triangles)),
                )?,
            )),
            (None, None) => None,
        };
        Ok(views)
    }

    /// The binary tree's shape, which bounds a traversal's iterations
    /// (`bvh_iterations_per_ray_at_most`: 2 nodes + triangles); the compressed tree's count a
    /// visit and a pop per node and a test per triangle, so its node count, if larger (never
    /// in practice: a node collapses several binary ones), takes the place.
    fn stats(&self) -> Option<BvhStats> {
        self.bvh.as_ref().map(|bvh| {
            let mut stats = bvh.stats();
            if let Some(compressed) = &self.compressed {
                stats.node_count = stats.node_count.max(compressed.nodes.len() + 1);
            }
            stats
        })
    }
}

/// The device buffers of a scene, for `SceneMemory::of`.
struct SceneBuffers<'a> {
    triangles: &'a TexelBufferView,
    uniforms: &'a Buffer,
    bvh_nodes: Option<&'a TexelBufferView>,
    traversal_triangles: Option<&'a TexelBufferView>,
    structures: Option<&'a SceneStructures>,
    shading: Option<&'a TexelBufferView>,
    materials: Option<&'a MaterialBuffers>,
    lights: &'a LightBuffers,
}

impl SceneMemory {
    /// What `buffers` of a scene of `triangle_count` triangles, traced by `traversal`, take
    /// on the device.
    fn of(triangle_count: usize, traversal: Traversal, buffers: SceneBuffers) -> SceneMemory {
        let bytes = |view: Option<&TexelBufferView>| view.map_or(0, TexelBufferView::byte_size);
        let bvh_node_bytes = bytes(buffers.bvh_nodes);
        let traversal_triangle_bytes = bytes(buffers.traversal_triangles);
        let structures = buffers.structures;
        let hardware_structure_bytes = structures.map_or(0, SceneStructures::bytes);
        let material_bytes = bytes(buffers.shading)
            + buffers.materials.map_or(0, |m| {
                m.materials.byte_size() + m.texture_texels.byte_size()
            });
        let scene_bytes = buffers.triangles.byte_size()
            + buffers.uniforms.size
            + bvh_node_bytes
            + traversal_triangle_bytes
            + hardware_structure_bytes
            + material_bytes
            + buffers.lights.byte_size();
        let per_triangle = |bytes: u64| bytes as f64 / triangle_count.max(1) as f64;
        SceneMemory {
            traversal: traversal.name(),
            accel: traversal.accel_name(),
            triangle_count: triangle_count as u64,
            bvh_node_bytes,
            traversal_triangle_bytes,
            hardware_structure_bytes,
            hardware_bottom_levels: structures.map_or(0, |s| s.bottom_level_count() as u64),
            hardware_instances: structures.map_or(0, |s| s.instance_count() as u64),
            acceleration_bytes_per_triangle: per_triangle(
                bvh_node_bytes + traversal_triangle_bytes + hardware_structure_bytes,
            ),
            scene_bytes,
            scene_bytes_per_triangle: per_triangle(scene_bytes),
        }
    }
}

/// The materials of `scene_materials` as the kernels read them, their textures' texels in
/// `atlas`.
fn gpu_materials(scene_materials: &SceneMaterials, atlas: &TextureAtlas) -> Vec<GpuMaterial> {
    scene_materials
        .materials
        .iter()
        .map(|m| GpuMaterial::new(m, scene_materials, atlas))
        .collect()
}

/// The buffers of `glsl/materials.glsl` that do not depend on the triangles: the materials'
/// words and their textures' texels (the per-triangle shading words are the geometry's).
struct MaterialBuffers {
    materials: TexelBufferView,
    texture_texels: TexelBufferView,
    /// `SCENE_TEXTURE_SLOTS`, set with the materials' words.
    texture_slots: u32,
}

impl MaterialBuffers {
    /// Uploads the materials of `scene_materials` and their textures; an error when the
    /// textures do not fit the device.
    fn upload(
        context: &Arc<Context>,
        commands: &CommandRunner,
        scene_materials: &SceneMaterials,
    ) -> Result<MaterialBuffers> {
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
        let gpu_materials = gpu_materials(scene_materials, &atlas);
        let texture_buffer = Buffer::device_local_with_data(
            context,
            commands,
            "texture texels",
            bytemuck::cast_slice(&atlas.texels),
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
        )?;
        Ok(MaterialBuffers {
            materials: TexelBufferView::upload_rgba32_uint(
                context,
                commands,
                "materials",
                bytemuck::cast_slice(&material_texel_words(&gpu_materials)),
            )?,
            texture_texels: TexelBufferView::rgba8_uint(
                context,
                texture_buffer,
                "scene's texture texels",
            )?,
            texture_slots: scene_texture_slots(&gpu_materials),
        })
    }
}

/// The per-triangle shading words of `scene_materials` in the order of the BVH's leaves
/// (`triangle_order`) where there is one (gathered as they are made: a reordered copy of
/// the shading data first took 112 MB and ~0.1 s more at 10^6 triangles).
fn shading_words(scene_materials: &SceneMaterials, triangle_order: Option<&[u32]>) -> Vec<u32> {
    match triangle_order {
        Some(order) => {
            shading_texel_words(scene_materials, order.iter().map(|&index| index as usize))
        }
        None => shading_texel_words(scene_materials, 0..scene_materials.triangles.len()),
    }
}

/// Buffers of an earlier upload that `GpuScene::upload` takes instead of uploading them
/// again: each where that part of the new upload writes the same words
/// (`UploadDigest::same_parts`), e.g. the materials and textures of a scene that moved.
/// `Default`: none.
#[derive(Default)]
pub struct KeptParts {
    /// The materials' words and texture texels.
    materials: Option<MaterialBuffers>,
    /// The lights' buffers that did not change (`crate::lights::LightBuffers::into_kept`).
    lights: KeptLightBuffers,
}

impl KeptParts {
    /// Whether the materials' words and texture texels are kept.
    pub fn materials(&self) -> bool {
        self.materials.is_some()
    }

    /// The lights' kept buffers.
    pub fn lights(&self) -> &KeptLightBuffers {
        &self.lights
    }
}

/// What an uploaded scene takes on the device, in bytes: what the traversal reads (the
/// BVH's nodes and the vertex positions apart for its triangle tests) and every buffer in
/// all (`render --json` and `bench --json` report it as `scene_memory`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SceneMemory {
    /// How rays find hits (`Traversal::name`): `BVH` (the 4-wide BVH), `compressed BVH`
    /// (8-wide, quantised), `ray queries`, `linear` or `constant triangles`.
    pub traversal: &'static str,
    /// What found the hits as `--accel` names it (`Traversal::accel_name`): `hardware` (the
    /// device's ray queries), `bvh` or `none`.
    pub accel: &'static str,
    /// Triangles in the scene.
    pub triangle_count: u64,
    /// The BVH's nodes (0 without a BVH).
    pub bvh_node_bytes: u64,
    /// The vertex positions that the BVH traversal's triangle tests read (0 without a BVH).
    pub traversal_triangle_bytes: u64,
    /// The device's acceleration structures, top and bottom level (0 without ray queries).
    pub hardware_structure_bytes: u64,
    /// Bottom-level structures of the device's (a mesh that nodes draw, or a run of
    /// world-space triangles each; 0 without ray queries).
    pub hardware_bottom_levels: u64,
    /// Instances in the device's top-level structure (0 without ray queries).
    pub hardware_instances: u64,
    /// `bvh_node_bytes + traversal_triangle_bytes + hardware_structure_bytes` per triangle:
    /// what the traversal reads.
    pub acceleration_bytes_per_triangle: f64,
    /// Every buffer of the scene: triangles, BVH, lights, shading data, materials, textures
    /// and the render uniforms.
    pub scene_bytes: u64,
    /// `scene_bytes` per triangle.
    pub scene_bytes_per_triangle: f64,
}

impl SceneMemory {
    /// The memory in words: "scene memory (BVH): nodes 1.2 MiB + traversal triangles 0.5
    /// MiB = 160.0 bytes/triangle; all buffers 3.0 MiB = 300.0 bytes/triangle".
    pub fn line(&self) -> String {
        let mib = |bytes: u64| bytes as f64 / f64::from(1u32 << 20);
        let traversal = if self.bvh_node_bytes > 0 {
            format!(
                "nodes {:.2} MiB + traversal triangles {:.2} MiB = {:.1} bytes/triangle; ",
                mib(self.bvh_node_bytes),
                mib(self.traversal_triangle_bytes),
                self.acceleration_bytes_per_triangle
            )
        } else if self.hardware_structure_bytes > 0 {
            format!(
                "acceleration structures {:.2} MiB = {:.1} bytes/triangle; ",
                mib(self.hardware_structure_bytes),
                self.acceleration_bytes_per_triangle
            )
        } else {
            String::new()
        };
        format!(
            "scene memory ({}, {} triangles): {traversal}all buffers {:.2} MiB = {:.1} bytes/triangle",
            self.traversal,
            self.triangle_count,
            mib(self.scene_bytes),
            self.scene_bytes_per_triangle
        )
    }
}

/// A scene uploaded for one traversal.
pub struct GpuScene {
    triangles: TexelBufferView,
    uniforms: Buffer,
    /// The lights, one buffer per kind (`crate::lights::LightBuffers`).
    lights: LightBuffers,
    bvh_nodes: Option<TexelBufferView>,
    /// The vertex positions alone, in leaf order, for the traversal (with a BVH only).
    traversal_triangles: Option<TexelBufferView>,
    /// The device's acceleration structures (`Traversal::RayQuery` only).
    structures: Option<SceneStructures>,
    /// Per-triangle shading data, in leaf order (scenes with materials only).
    shading: Option<TexelBufferView>,
    /// Materials and texture texels (scenes with materials only).
    materials: Option<MaterialBuffers>,
    /// What the variant room (`crate::kernels::variant`) reads of the scene.
    pub summary: SceneSummary,
    /// What the variant room reads of the settings.
    pub variant_settings: VariantSettings,
    /// Iterations of one light search (`SceneLights::light_search_iterations`), for the
    /// loop budget.
    pub light_search_iterations: u64,
    /// Light samples a path vertex draws at most (`SceneLights::light_samples_per_vertex`),
    /// for the loop budget.
    pub light_samples_per_vertex: u64,
    /// The BVH's shape, for bounding a traversal's loop iterations (`None` without a BVH).
    pub bvh_stats: Option<BvhStats>,
    /// What the scene takes on the device.
    pub memory: SceneMemory,
    /// How rays find hits in it: the traversal asked for, or the 4-wide BVH where `auto`'s
    /// compressed tree could not hold the scene (`upload`).
    pub traversal: Traversal,
    /// Which triangle of the scene each uploaded triangle is (the tree's leaf order, the
    /// kernels' triangle indices); `None`: the scene's own order. The ground-truth AOVs
    /// (`crate::render::ground_truth`) map the kernels' indices back through it.
    pub triangle_order: Option<Vec<u32>>,
}

impl GpuScene {
    /// Uploads `scene` as `traversal` reads it, with the camera's image plane for the
    /// settings' aspect ratio and their seed in the render uniforms, taking the buffers in
    /// `kept` instead of uploading those parts again.
    pub fn upload(
        context: &Arc<Context>,
        commands: &CommandRunner,
        scene: &Scene,
        camera: &Camera,
        settings: &RenderSettings,
        traversal: Traversal,
        kept: KeptParts,
    ) -> Result<GpuScene> {
        let started = std::time::Instant::now();
        // With a BVH, triangles are stored in the order its leaves reference them; light
        // indices then refer to that order too.
        // The compressed tree collapses the binary one (`CompressedBvh::from_binary`).
        // Under `--accel auto`, a scene the compressed tree refuses (deeper than its stack,
        // or beyond its quantisation's range) takes the 4-wide tree, with a warning.
        let trees = SceneTrees::build(scene, settings.accel, traversal)?;
        let traversal = trees.traversal;
        let triangle_order = trees.triangle_order();
        log::debug!(
            "scene upload: trees built in {:.3} s",
            started.elapsed().as_secs_f64()
        );
        let ordered_triangles = match triangle_order {
            Some(order) => Cow::Owned(reorder_by(order, &scene.triangles)),
            None => Cow::Borrowed(&scene.triangles[..]),
        };
        let gpu_triangles: Vec<GpuTriangle> =
            ordered_triangles.iter().map(GpuTriangle::new).collect();
        let scene_lights = lights_of(scene, &ordered_triangles, triangle_order, settings);
        let variant_settings = variant_settings(settings, &scene_lights);
        let upload = |name: &str, bytes: &[u8]| {
            TexelBufferView::upload_rgba32_uint(context, commands, name, bytes)
        };
        let triangles = upload(
            "triangles",
            &triangle_texels(&gpu_triangles, scene, triangle_order, settings.aspect()),
        )?;
        let uniforms = Buffer::with_data(
            context,
            "render uniforms",
            &[render_uniforms(scene, camera, settings)],
            vk::BufferUsageFlags::UNIFORM_BUFFER,
        )?;
        let (bvh_nodes, traversal_triangles) =
            trees.upload_traversal(&ordered_triangles, upload)?.unzip();
        let structures = match traversal {
            // The triangles stay in the scene's order (no BVH reorders them)
            Traversal::RayQuery => Some(SceneStructures::build(context, commands, scene)?),
            _ => None,
        };
        let scene_materials = kernel_materials(scene);
        let scene_materials = scene_materials.as_deref();
        let lights = LightBuffers::upload(
            context,
            commands,
            &scene_lights,
            scene_materials.is_some(),
            kept.lights,
        )?;
        let shading = match scene_materials {
            Some(scene_materials) => Some(upload(
                "shading data",
                bytemuck::cast_slice(&shading_words(scene_materials, triangle_order)),
            )?),
            None => None,
        };
        let materials = match (scene_materials, kept.materials) {
            (Some(_), Some(kept)) => Some(kept),
            (Some(scene_materials), None) => {
                Some(MaterialBuffers::upload(context, commands, scene_materials)?)
            }
            (None, _) => None,
        };
        let texture_slots = materials.as_ref().map_or(0, |m| m.texture_slots);
        let summary = scene_summary(scene, scene_materials, &scene_lights, texture_slots);
        let memory = SceneMemory::of(
            scene.triangles.len(),
            traversal,
            SceneBuffers {
                triangles: &triangles,
                uniforms: &uniforms,
                bvh_nodes: bvh_nodes.as_ref(),
                traversal_triangles: traversal_triangles.as_ref(),
                structures: structures.as_ref(),
                shading: shading.as_ref(),
                materials: materials.as_ref(),
                lights: &lights,
            },
        );
        let bvh_stats = trees.stats();
        log::debug!(
            "scene upload: {} triangles uploaded in {:.3} s",
            scene.triangles.len(),
            started.elapsed().as_secs_f64()
        );
        Ok(GpuScene {
            triangles,
            uniforms,
            lights,
            bvh_nodes,
            traversal_triangles,
            structures,
            shading,
            materials,
            summary,
            variant_settings,
            light_search_iterations: scene_lights.light_search_iterations(),
            light_samples_per_vertex: scene_lights.light_samples_per_vertex(),
            bvh_stats,
            memory,
            traversal,
            triangle_order: triangle_order.map(<[u32]>::to_vec),
        })
    }

    /// The parts of this upload that `same` says a new one writes alike, for that upload
    /// (`upload`'s `kept`); the rest (the geometry among them) is freed.
    pub fn into_kept(self, same: SameParts) -> KeptParts {
        KeptParts {
            materials: self.materials.filter(|_| same.materials),
            lights: self.lights.into_kept(same.lights),
        }
    }

    /// Writes the render uniforms again for `camera` and `settings`' image size and seed:
    /// for a render of the same scene data (`crate::render::sequence`), no device work
    /// pending.
    pub fn aim(&mut self, scene: &Scene, camera: &Camera, settings: &RenderSettings) {
        self.uniforms.write(bytemuck::bytes_of(&render_uniforms(
            scene, camera, settings,
        )));
    }

    /// The scene's resource for a binding of the path tracer's table
    /// (`crate::kernels::bindings::PATH_TRACER`); `None` for one it does not hold (the
    /// accumulation image, the BVH without a BVH, materials without materials). The lights'
    /// bindings are `LightBuffers::resource`'s.
    pub fn resource(&self, resource: Resource) -> Option<Bound<'_>> {
        let materials = self.materials.as_ref();
        let texel = match resource {
            Resource::Triangles => &self.triangles,
            Resource::RenderUniforms => return Some(Bound::Buffer(&self.uniforms)),
            Resource::AccelerationStructure => {
                return Some(Bound::AccelerationStructure(&self.structures.as_ref()?.top))
            }
            Resource::BvhNodes => self.bvh_nodes.as_ref()?,
            Resource::TraversalTriangles => self.traversal_triangles.as_ref()?,
            Resource::Shading => self.shading.as_ref()?,
            Resource::Materials => &materials?.materials,
            Resource::TextureTexels => &materials?.texture_texels,
            // The lights' own buffers, one per kind, and the emissive kind's selection words
            other => return self.lights.resource(other).map(Bound::TexelBuffer),
        };
        Some(Bound::TexelBuffer(texel))
    }
}
