//! The progressive GPU renderer: uploads a scene, runs frames of the path-tracing kernel that
//! add samples to an accumulation image, and reads the image back.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::camera::Camera;
use crate::contract;
use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::render::gpu_scene::GpuScene;
use crate::render::gpu_types::FramePushConstants;
use crate::render::settings::RenderSettings;
use crate::render::traversal::Traversal;
use crate::scene::Scene;
use crate::vk::{
    spirv_words, Buffer, CommandRunner, ComputePipeline, Context, DescriptorSet, StorageImage,
};

/// How long one submission of frames should take: long enough to hide submission overhead,
/// short enough for a responsive progress bar. Each frame is its own dispatch, so a GPU
/// watchdog sees short dispatches whatever this is.
const TARGET_BATCH_DURATION: Duration = Duration::from_millis(250);
/// Most frames recorded into one submission.
const MAX_FRAMES_PER_BATCH: u32 = 256;

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
    _scene: GpuScene,
    samples_done: u32,
    frames_per_batch: u32,
    rays_traced: f64,
}

/// How a render that `Renderer::render_to_end` ran ended.
#[derive(Debug)]
pub struct RenderOutcome {
    /// The image with every sample taken.
    pub image: RenderedImage,
    /// Samples per pixel taken.
    pub samples: u32,
    /// Seconds the frames took (the read-back excluded).
    pub seconds: f64,
    /// Whether the cancel flag stopped it before all samples were taken.
    pub cancelled: bool,
    /// The error that stopped it after some samples were taken (they are in `image`).
    pub failure: Option<Error>,
}

impl RenderOutcome {
    /// The outcome, or the error that stopped the render early.
    pub fn finished(self) -> Result<RenderOutcome> {
        match self.failure {
            Some(error) => Err(error),
            None => Ok(self),
        }
    }
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
    /// chooses) and `with_kernel`.
    fn create(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        kernel: Option<(&[u32], Traversal)>,
    ) -> Result<Renderer> {
        validate(context, scene, &settings)?;
        let commands = CommandRunner::new(context)?;
        let traversal = match kernel {
            Some((_, traversal)) => traversal,
            None => Traversal::choose(scene.triangles.len(), settings.accel),
        };
        let gpu_scene = GpuScene::upload(context, &commands, scene, camera, &settings, traversal)?;
        let mut bindings = gpu_scene.bindings();
        bindings.push((
            contract::BINDING_ACCUMULATION,
            vk::DescriptorType::STORAGE_IMAGE,
        ));
        let mut specialization = settings.specialization();
        specialization.extend_from_slice(&gpu_scene.specialization);
        let spirv = match kernel {
            Some((spirv, _)) => spirv.to_vec(),
            None => spirv_words(traversal.kernel())?,
        };
        let pipeline = ComputePipeline::new(
            context,
            &spirv,
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
        gpu_scene.write(&descriptors);
        descriptors.write_storage_image(contract::BINDING_ACCUMULATION, &accumulation);
        commands.run(|recorder| recorder.clear_storage_image(&accumulation))?;
        Ok(Renderer {
            context: context.clone(),
            settings,
            commands,
            pipeline,
            descriptors,
            accumulation,
            readback,
            _scene: gpu_scene,
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
        let extent = [self.settings.width, self.settings.height, 1];
        let (pipeline, descriptors) = (&self.pipeline, &self.descriptors);
        self.commands.run(|recorder| {
            recorder.bind(pipeline, descriptors);
            for frame in 0..frames {
                let constants = FramePushConstants {
                    first_sample_index: first + frame * spf,
                    sample_end,
                };
                recorder.push_constants(pipeline, &constants);
                recorder.dispatch(pipeline, extent);
                // Each frame reads what the previous one wrote.
                recorder.compute_barrier();
            }
        })?;
        self.samples_done = (first + frames * spf).min(sample_end);
        Ok(self.samples_done)
    }

    /// Copies the accumulation image back and returns the per-pixel mean, second moment and
    /// sample count. Can be called at any time (e.g. to save a partial render).
    pub fn read_back(&mut self) -> Result<RenderedImage> {
        let (image, readback) = (&self.accumulation, &self.readback);
        self.commands
            .run(|recorder| recorder.copy_image_to_buffer(image, readback))?;
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

    /// Renders until every sample is taken or `cancel` is set, one batch at a time, calling
    /// `progress` with the samples per pixel taken after each batch, and reads the image
    /// back. An error after some samples were taken ends the render without losing them
    /// (`RenderOutcome::failure`); an error before any is returned.
    pub fn render_to_end(
        &mut self,
        mut progress: impl FnMut(u32),
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderOutcome> {
        let started = Instant::now();
        let mut failure = None;
        let cancelled = || cancel.is_some_and(|flag| flag.load(Ordering::SeqCst));
        while !self.is_complete() && !cancelled() {
            match self.render_batch() {
                Ok(done) => progress(done),
                Err(error) if self.samples_done == 0 => return Err(error),
                Err(error) => {
                    failure = Some(error);
                    break;
                }
            }
        }
        let seconds = started.elapsed().as_secs_f64();
        Ok(RenderOutcome {
            image: self.read_back()?,
            samples: self.samples_done,
            seconds,
            cancelled: !self.is_complete() && failure.is_none(),
            failure,
        })
    }

    /// Renders every remaining sample and reads the image back; any error is returned.
    pub fn render_all(&mut self) -> Result<RenderedImage> {
        Ok(self.render_to_end(|_| {}, None)?.finished()?.image)
    }
}

/// Checks what a render needs before anything is allocated: valid settings, an image
/// within the device's limits, a scene with triangles.
fn validate(context: &Context, scene: &Scene, settings: &RenderSettings) -> Result<()> {
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
    Ok(())
}
