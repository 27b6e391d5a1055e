//! The progressive GPU renderer: uploads a scene, runs frames of the path-tracing kernel that
//! add samples to an accumulation image, and reads the image back.

use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::bvh::Bvh;
use crate::camera::Camera;
use crate::contract;
use crate::error::{Error, Result};
use crate::gpu_types::{FramePushConstants, RenderUniforms};
use crate::image_data::RenderedImage;
use crate::lights::LightTable;
use crate::scene::{Scene, Triangle};
use crate::settings::{Accel, RenderSettings};
use crate::shaders;
use crate::vk::{
    full_compute_barrier, Buffer, CommandRunner, ComputePipeline, Context, DescriptorSet,
    StorageImage, TexelBufferView, VkError,
};

/// How long one submission of frames should take: long enough to hide submission overhead,
/// short enough for a responsive progress bar. Each frame is its own dispatch, so a GPU
/// watchdog sees short dispatches whatever this is.
const TARGET_BATCH_DURATION: Duration = Duration::from_millis(250);
/// Most frames recorded into one submission.
const MAX_FRAMES_PER_BATCH: u32 = 256;

/// Converts embedded SPIR-V bytes to words.
pub(crate) fn spirv_words(bytes: &[u8]) -> Result<Vec<u32>> {
    ash::util::read_spv(&mut std::io::Cursor::new(bytes))
        .map_err(|e| Error::Vulkan(VkError::InvalidSpirv(e.to_string())))
}

/// How the kernel finds the triangle a ray hits. The triangles' data are read from a texel
/// buffer (RGBA32_UINT, `TRIANGLE_TEXEL_COUNT` texels per triangle): on lavapipe a texel fetch
/// at a per-lane index is a vector gather, faster than uniform- or storage-buffer loads
/// (docs/performance.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Traversal {
    /// The workshop's loop over all triangles, compiled into the kernel: their positions are
    /// specialization constants (`glsl/constant_triangles.glsl`), so a ray reads no memory
    /// per triangle. For scenes of at most `CONSTANT_TRIANGLE_CAPACITY` triangles.
    ConstantTriangles,
    /// The workshop's loop over all triangles, read from the texel buffer
    /// (`glsl/path_tracer.comp`).
    Linear,
    /// A BVH, with the triangles in its leaf order (`path_tracer.comp` with `USE_BVH`).
    Bvh,
}

impl Traversal {
    /// What `accel` asks for, for a scene of `triangle_count` triangles: the loop over all
    /// triangles is compiled into the kernel whenever they fit.
    pub fn choose(triangle_count: usize, accel: Accel) -> Traversal {
        if accel.uses_bvh(triangle_count) {
            Traversal::Bvh
        } else if triangle_count <= contract::CONSTANT_TRIANGLE_CAPACITY as usize {
            Traversal::ConstantTriangles
        } else {
            Traversal::Linear
        }
    }

    /// A short name for reports: "constant triangles", "linear" or "BVH".
    pub fn name(self) -> &'static str {
        match self {
            Traversal::ConstantTriangles => "constant triangles",
            Traversal::Linear => "linear",
            Traversal::Bvh => "BVH",
        }
    }

    fn kernel(self) -> &'static [u8] {
        match self {
            Traversal::ConstantTriangles | Traversal::Linear => shaders::PATH_TRACER,
            Traversal::Bvh => shaders::PATH_TRACER_BVH,
        }
    }
}

/// Views `buffer` as RGBA32_UINT texels, after checking that the device allows that many.
fn texel_view(context: &Arc<Context>, buffer: Buffer, what: &str) -> Result<TexelBufferView> {
    let texels = buffer.size / 16;
    let limit = u64::from(context.limits.max_texel_buffer_elements);
    if texels > limit {
        return Err(Error::InvalidSettings(format!(
            "the scene's {what} need {texels} texels, more than this device's texel-buffer limit of {limit}"
        )));
    }
    Ok(TexelBufferView::new(
        context,
        buffer,
        vk::Format::R32G32B32A32_UINT,
    )?)
}

/// The specialization constants that pass the triangles' positions into the kernel for
/// `Traversal::ConstantTriangles` (`glsl/constant_triangles.glsl`); none for the others.
fn constant_triangle_specialization(
    traversal: Traversal,
    triangles: &[Triangle],
) -> Vec<(u32, u32)> {
    if traversal != Traversal::ConstantTriangles {
        return Vec::new();
    }
    let mut constants = vec![(
        contract::SPEC_CONSTANT_TRIANGLE_COUNT,
        triangles.len() as u32,
    )];
    let coordinates = triangles
        .iter()
        .flat_map(|triangle| triangle.positions)
        .flat_map(|position| position.to_array());
    for (k, coordinate) in coordinates.enumerate() {
        constants.push((
            contract::SPEC_CONSTANT_TRIANGLES + k as u32,
            coordinate.to_bits(),
        ));
    }
    constants
}

/// A progressive render of one scene on one device.
pub struct Renderer {
    context: Arc<Context>,
    settings: RenderSettings,
    commands: CommandRunner,
    pipeline: ComputePipeline,
    descriptors: DescriptorSet,
    accumulation: StorageImage,
    readback: Buffer,
    // Bound through the descriptor set; kept alive as long as it.
    _triangles: TexelBufferView,
    _uniforms: Buffer,
    _lights: TexelBufferView,
    _bvh_nodes: Option<TexelBufferView>,
    samples_done: u32,
    frames_per_batch: u32,
    rays_traced: f64,
}

impl Renderer {
    /// Prepares a render: validates the settings, uploads the scene's triangles and the
    /// camera, creates the pipeline and clears the accumulation image.
    pub fn new(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
    ) -> Result<Renderer> {
        Renderer::create(context, scene, camera, settings, None)
    }

    /// Prepares a render like `new`, with the kernel's SPIR-V given instead of the embedded
    /// one: `glsl/path_tracer.comp` compiled at run time, e.g. with a user's functions by
    /// `vkpath check`. `traversal` says how it was compiled (`Bvh` with `USE_BVH` defined,
    /// the others without) and, for `ConstantTriangles`, that the scene must fit
    /// `CONSTANT_TRIANGLE_CAPACITY`.
    pub fn with_kernel(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        spirv: &[u32],
        traversal: Traversal,
    ) -> Result<Renderer> {
        let capacity = contract::CONSTANT_TRIANGLE_CAPACITY as usize;
        if traversal == Traversal::ConstantTriangles && scene.triangles.len() > capacity {
            return Err(Error::InvalidSettings(format!(
                "a kernel with constant triangles holds at most {capacity} triangles, the scene has {}",
                scene.triangles.len()
            )));
        }
        Renderer::create(context, scene, camera, settings, Some((spirv, traversal)))
    }

    /// `new` (`kernel` = `None`: the embedded kernel for the traversal that `settings.accel`
    /// chooses) and
    /// `with_kernel`.
    fn create(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        kernel: Option<(&[u32], Traversal)>,
    ) -> Result<Renderer> {
        settings.validate()?;
        let device_limit = context.limits.max_image_dimension2_d;
        if settings.width > device_limit || settings.height > device_limit {
            return Err(Error::InvalidSettings(format!(
                "image size {}x{} exceeds the device's limit of {device_limit} pixels per side",
                settings.width, settings.height
            )));
        }
        if scene.triangles.is_empty() {
            return Err(Error::MissingInput("the scene has no triangles".into()));
        }
        let commands = CommandRunner::new(context)?;
        let traversal = match kernel {
            Some((_, traversal)) => traversal,
            None => Traversal::choose(scene.triangles.len(), settings.accel),
        };
        // With a BVH, triangles are stored in the order its leaves reference them; light
        // indices then refer to that order too.
        let bvh = (traversal == Traversal::Bvh).then(|| Bvh::build(&scene.triangles));
        let ordered_triangles = match &bvh {
            Some(bvh) => bvh.reorder(&scene.triangles),
            None => scene.triangles.clone(),
        };
        let mut gpu_triangles: Vec<_> = ordered_triangles.iter().map(|t| t.to_gpu()).collect();
        let lights = LightTable::new(&ordered_triangles);
        lights.annotate(&mut gpu_triangles);
        let triangle_bytes = upload_device_local(
            context,
            &commands,
            "triangles",
            bytemuck::cast_slice(&gpu_triangles),
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
        )?;
        let triangles = texel_view(context, triangle_bytes, "triangles")?;
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
            Some(bvh) => {
                let bytes = upload_device_local(
                    context,
                    &commands,
                    "bvh nodes",
                    bytemuck::cast_slice(&bvh.nodes),
                    vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
                )?;
                Some(texel_view(context, bytes, "BVH nodes")?)
            }
            None => None,
        };
        let light_bytes = upload_device_local(
            context,
            &commands,
            "lights",
            &lights.gpu_bytes(),
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
        )?;
        let light_buffer = texel_view(context, light_bytes, "lights")?;
        let mut bindings = vec![
            (
                contract::BINDING_TRIANGLES,
                vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
            ),
            (
                contract::BINDING_RENDER_UNIFORMS,
                vk::DescriptorType::UNIFORM_BUFFER,
            ),
            (
                contract::BINDING_ACCUMULATION,
                vk::DescriptorType::STORAGE_IMAGE,
            ),
            (
                contract::BINDING_LIGHTS,
                vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
            ),
        ];
        if bvh_nodes.is_some() {
            bindings.push((
                contract::BINDING_BVH_NODES,
                vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
            ));
        }
        let mut specialization = vec![
            (contract::SPEC_SAMPLE_COUNT, settings.samples_per_frame),
            (contract::SPEC_MAX_PATH_LENGTH, settings.max_path_length),
            (
                contract::SPEC_PIXEL_FILTER,
                settings.pixel_filter.spec_constant(),
            ),
            (
                contract::SPEC_INTEGRATOR,
                settings.integrator.spec_constant(),
            ),
            (
                contract::SPEC_RUSSIAN_ROULETTE_START,
                settings.russian_roulette_start,
            ),
            (contract::SPEC_SAMPLER, settings.sampler.spec_constant()),
            (
                contract::SPEC_LIGHT_SAMPLING,
                settings.light_sampling.spec_constant(),
            ),
        ];
        specialization.extend(constant_triangle_specialization(
            traversal,
            &ordered_triangles,
        ));
        let pipeline = ComputePipeline::new(
            context,
            &match kernel {
                Some((spirv, _)) => spirv.to_vec(),
                None => spirv_words(traversal.kernel())?,
            },
            &bindings,
            std::mem::size_of::<FramePushConstants>() as u32,
            &specialization,
        )?;
        let accumulation = StorageImage::new(
            context,
            "accumulation",
            settings.width,
            settings.height,
            contract::ACCUMULATION_LAYER_COUNT,
        )?;
        let readback = Buffer::new(
            context,
            "readback",
            accumulation.byte_size(),
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let descriptors = pipeline.allocate_descriptor_set()?;
        descriptors.write_texel_buffer(contract::BINDING_TRIANGLES, &triangles);
        descriptors.write_buffer(
            contract::BINDING_RENDER_UNIFORMS,
            vk::DescriptorType::UNIFORM_BUFFER,
            &uniforms,
        );
        descriptors.write_storage_image(contract::BINDING_ACCUMULATION, &accumulation);
        if let Some(nodes) = &bvh_nodes {
            descriptors.write_texel_buffer(contract::BINDING_BVH_NODES, nodes);
        }
        descriptors.write_texel_buffer(contract::BINDING_LIGHTS, &light_buffer);
        commands.run(|device, command_buffer| {
            clear_to_general(device, command_buffer, &accumulation)
        })?;
        Ok(Renderer {
            context: context.clone(),
            settings,
            commands,
            pipeline,
            descriptors,
            accumulation,
            readback,
            _triangles: triangles,
            _uniforms: uniforms,
            _lights: light_buffer,
            _bvh_nodes: bvh_nodes,
            samples_done: 0,
            frames_per_batch: 1,
            rays_traced: 0.0,
        })
    }

    /// The settings this render was made with.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// The device this render runs on.
    pub fn context(&self) -> &Arc<Context> {
        &self.context
    }

    /// Samples per pixel accumulated so far.
    pub fn samples_done(&self) -> u32 {
        self.samples_done
    }

    /// Rays traced so far (camera, path and shadow rays), as of the last `read_back()`.
    pub fn rays_traced(&self) -> f64 {
        self.rays_traced
    }

    /// Whether all `spp` samples have been taken.
    pub fn is_complete(&self) -> bool {
        self.samples_done >= self.settings.spp
    }

    /// Runs one frame: adds up to `samples_per_frame` samples to every pixel. Returns the
    /// samples per pixel accumulated so far.
    pub fn render_frame(&mut self) -> Result<u32> {
        self.render_frames(1)
    }

    /// Runs one submission of as many frames as keep it near 250 ms (measured on the
    /// previous submission), and returns the samples per pixel accumulated so far. Call it
    /// until `is_complete()`; report progress between calls.
    pub fn render_batch(&mut self) -> Result<u32> {
        let started = Instant::now();
        let frames = self.frames_per_batch;
        self.render_frames(frames)?;
        let per_frame = started.elapsed().as_secs_f64() / f64::from(frames);
        let wanted = (TARGET_BATCH_DURATION.as_secs_f64() / per_frame.max(1e-6)) as u32;
        // Grow at most 4x at a time so one fast outlier cannot make a batch take seconds.
        self.frames_per_batch = wanted.clamp(1, (frames * 4).min(MAX_FRAMES_PER_BATCH));
        Ok(self.samples_done)
    }

    /// Records `frames` frames into one submission and waits for them.
    fn render_frames(&mut self, frames: u32) -> Result<u32> {
        let spf = self.settings.samples_per_frame;
        let remaining_frames = (self.settings.spp - self.samples_done).div_ceil(spf);
        let frames = frames.min(remaining_frames);
        if frames == 0 {
            return Ok(self.samples_done);
        }
        let first = self.samples_done;
        let sample_end = self.settings.spp;
        let groups_x = self.settings.width.div_ceil(contract::WORKGROUP_SIZE_X);
        let groups_y = self.settings.height.div_ceil(contract::WORKGROUP_SIZE_Y);
        let pipeline = &self.pipeline;
        let set = self.descriptors.set;
        self.commands.run(|device, command_buffer| unsafe {
            // SAFETY: all bound resources live as long as self; the image is in GENERAL.
            pipeline.record_bind(device, command_buffer, set);
            for frame in 0..frames {
                let constants = FramePushConstants {
                    first_sample_index: first + frame * spf,
                    sample_end,
                };
                device.cmd_push_constants(
                    command_buffer,
                    pipeline.layout,
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    bytemuck::bytes_of(&constants),
                );
                device.cmd_dispatch(command_buffer, groups_x, groups_y, 1);
                // Each frame reads what the previous one wrote.
                full_compute_barrier(device, command_buffer);
            }
        })?;
        self.samples_done = (first + frames * spf).min(sample_end);
        Ok(self.samples_done)
    }

    /// Copies the accumulation image back and returns the per-pixel mean, second moment and
    /// sample count. Can be called at any time (e.g. to save a partial render).
    pub fn read_back(&mut self) -> Result<RenderedImage> {
        let image = &self.accumulation;
        let readback = &self.readback;
        self.commands.run(|device, command_buffer| unsafe {
            // SAFETY: the image is in GENERAL; the buffer is large enough for all layers.
            // The copy reads the image in TRANSFER_SRC_OPTIMAL, then it returns to GENERAL.
            set_layout(
                device,
                command_buffer,
                image,
                (
                    vk::ImageLayout::GENERAL,
                    vk::AccessFlags::SHADER_WRITE,
                    vk::PipelineStageFlags::COMPUTE_SHADER,
                ),
                (
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::AccessFlags::TRANSFER_READ,
                    vk::PipelineStageFlags::TRANSFER,
                ),
            );
            let region = vk::BufferImageCopy::default()
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::COLOR)
                        .layer_count(image.layers),
                )
                .image_extent(vk::Extent3D {
                    width: image.width,
                    height: image.height,
                    depth: 1,
                });
            device.cmd_copy_image_to_buffer(
                command_buffer,
                image.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.handle,
                &[region],
            );
            set_layout(
                device,
                command_buffer,
                image,
                (
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::AccessFlags::TRANSFER_READ,
                    vk::PipelineStageFlags::TRANSFER,
                ),
                (
                    vk::ImageLayout::GENERAL,
                    vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE,
                    vk::PipelineStageFlags::COMPUTE_SHADER,
                ),
            );
            crate::vk::host_read_barrier(
                device,
                command_buffer,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            );
        })?;
        let texels: Vec<[f32; 4]> = self.readback.read();
        let pixels = (self.settings.width * self.settings.height) as usize;
        let compensation_layer = contract::LAYER_COMPENSATION as usize * pixels;
        self.rays_traced = texels[compensation_layer..compensation_layer + pixels]
            .iter()
            .map(|texel| f64::from(texel[3]))
            .sum();
        Ok(RenderedImage::from_accumulation(
            self.settings.width,
            self.settings.height,
            &texels,
        ))
    }
}

/// A layout, the accesses to wait for or to make wait, and their pipeline stage.
type LayoutUse = (vk::ImageLayout, vk::AccessFlags, vk::PipelineStageFlags);

/// Records a barrier that moves all layers of `image` from one use to another.
fn set_layout(
    device: &ash::Device,
    command_buffer: vk::CommandBuffer,
    image: &StorageImage,
    from: LayoutUse,
    to: LayoutUse,
) {
    let barrier = vk::ImageMemoryBarrier::default()
        .src_access_mask(from.1)
        .dst_access_mask(to.1)
        .old_layout(from.0)
        .new_layout(to.0)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image.handle)
        .subresource_range(StorageImage::all_layers(image.layers));
    // SAFETY: recording into a command buffer in the recording state; the image is alive.
    unsafe {
        device.cmd_pipeline_barrier(
            command_buffer,
            from.2,
            to.2,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &[barrier],
        );
    }
}

/// Moves the image from UNDEFINED to GENERAL and clears every layer to zero.
fn clear_to_general(device: &ash::Device, command_buffer: vk::CommandBuffer, image: &StorageImage) {
    let range = StorageImage::all_layers(image.layers);
    set_layout(
        device,
        command_buffer,
        image,
        (
            vk::ImageLayout::UNDEFINED,
            vk::AccessFlags::empty(),
            vk::PipelineStageFlags::TOP_OF_PIPE,
        ),
        (
            vk::ImageLayout::GENERAL,
            vk::AccessFlags::TRANSFER_WRITE,
            vk::PipelineStageFlags::TRANSFER,
        ),
    );
    // SAFETY: recording into a command buffer in the recording state; the image is alive.
    unsafe {
        device.cmd_clear_color_image(
            command_buffer,
            image.handle,
            vk::ImageLayout::GENERAL,
            &vk::ClearColorValue { float32: [0.0; 4] },
            &[range],
        );
    }
    full_compute_barrier(device, command_buffer);
}

/// A device-local buffer filled with `bytes` through a staging buffer.
fn upload_device_local(
    context: &Arc<Context>,
    commands: &CommandRunner,
    name: &str,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
) -> Result<Buffer> {
    let staging = Buffer::with_data(
        context,
        "staging",
        bytes,
        vk::BufferUsageFlags::TRANSFER_SRC,
    )?;
    let buffer = Buffer::new(
        context,
        name,
        bytes.len() as u64,
        usage | vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )?;
    commands.run(|device, command_buffer| unsafe {
        // SAFETY: both buffers are alive and large enough.
        device.cmd_copy_buffer(
            command_buffer,
            staging.handle,
            buffer.handle,
            &[vk::BufferCopy {
                src_offset: 0,
                dst_offset: 0,
                size: bytes.len().max(1) as u64,
            }],
        );
        full_compute_barrier(device, command_buffer);
    })?;
    Ok(buffer)
}
