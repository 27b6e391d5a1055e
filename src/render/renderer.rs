//! The progressive GPU renderer: uploads a scene, runs frames of the path-tracing kernel that
//! add samples to an accumulation image, and reads the image back. Training a guided
//! render's guide (`guide_training`) and the lavapipe loop budget that sizes each dispatch
//! (`loop_budget`) are rooms of their own beside it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::accel::choose_traversal;
use crate::camera::Camera;
use crate::contract;
use crate::error::{Error, Result};
use crate::guiding::training::GUIDE_TRAINING_FIRST_SAMPLE;
use crate::guiding::{Guide, GuideGrid};
use crate::image_io::data::RenderedImage;
use crate::kernels::specialization::{path_tracer_specialization, SpecializationParts};
use crate::kernels::variant::{path_tracer_variant, KernelSource, Traversal};
use crate::kernels::{Bound, KernelPipeline, Resource, PATH_TRACER};
use crate::render::accumulation::Accumulation;
use crate::render::adaptive::NoiseThreshold;
use crate::render::converged_pixels::{converged_pixel_count, ConvergedPixels};
use crate::render::gpu_scene::{GpuScene, KeptParts, SceneMemory};
use crate::render::gpu_types::FramePushConstants;
use crate::render::guide_buffers::GuideBuffers;
use crate::render::region::{PixelRegion, ACCUMULATION_BYTES_PER_PIXEL, ACCUMULATION_COPIES};
use crate::render::sequence::{AccumulationImages, KeptUpload, SequenceCache, UploadKey};
use crate::render::settings::RenderSettings;
use crate::render::tiles::{
    area_texel_count, scene_bytes, tile_layout, TileDevice, Tiles, TilesEnd,
};
use crate::scene::Scene;
use crate::vk::{Buffer, CommandRunner, Context, DescriptorSet, StorageImage};

mod guide_training;
mod loop_budget;

use guide_training::TrainingKernel;
pub use guide_training::{GuideReport, TrainingTimes};
use loop_budget::{loop_limit_advice, LoopBudget};

/// How long one submission of frames should take: long enough to hide submission overhead,
/// short enough for a responsive progress bar. Each frame is its own dispatch, so a GPU
/// watchdog sees short dispatches whatever this is.
const TARGET_BATCH_DURATION: Duration = Duration::from_millis(250);
/// Most frames recorded into one submission.
const MAX_FRAMES_PER_BATCH: u32 = 256;

/// The samples that `Renderer::run_frames` takes: the render's (`first_sample`,
/// `settings.spp`, its noise threshold) or a training iteration's.
struct FrameSpan {
    /// The first sample of every pixel's sequence in the span.
    first_sample: u32,
    /// Samples per pixel in the span (`samples_done` counts those taken).
    spp: u32,
    /// Adaptive sampling, if on.
    noise_threshold: Option<NoiseThreshold>,
    /// Whether the frames train the guide (with `Renderer::training_pipeline`).
    training: bool,
}

/// What one frame dispatches: each stage's pipeline over the frame's pixels, in order, with
/// a barrier after each (the stages share the descriptor set and the frame's push
/// constants). Today's plans have one stage, the path tracer's megakernel (its render or
/// its guide-training build); a staged (wavefront) integrator or another integrator's
/// kernels are another plan, not another branch of the frame loop.
struct FramePlan<'a> {
    stages: Vec<&'a KernelPipeline>,
}

impl<'a> FramePlan<'a> {
    /// The plan of a render's frames: its `render` pipeline, or with `training` the guide's
    /// training build (which only `train_guide_until` runs, once it has built it).
    fn of(
        render: &'a KernelPipeline,
        training_pipeline: Option<&'a KernelPipeline>,
        training: bool,
    ) -> Result<FramePlan<'a>> {
        let stage = match (training, training_pipeline) {
            (false, _) => render,
            (true, Some(pipeline)) => pipeline,
            (true, None) => {
                return Err(Error::InvalidSettings(
                    "training frames without a training pipeline (an unguided render)".into(),
                ))
            }
        };
        Ok(FramePlan {
            stages: vec![stage],
        })
    }
}

/// A progressive render of one scene on one device.
pub struct Renderer {
    context: Arc<Context>,
    settings: RenderSettings,
    commands: CommandRunner,
    /// Shared with the sequence it belongs to, if any (`in_sequence`).
    pipeline: Arc<KernelPipeline>,
    /// A guided render's training frames' pipeline (`GUIDING_TRAINING`; `pipeline` holds
    /// none of the training's code), built when training first needs it from
    /// `training_kernel`, which it then replaces; `descriptors` serve both.
    training_pipeline: Option<KernelPipeline>,
    /// What the training pipeline is built from (`--guiding` only, until it is built: a
    /// render resumed with a frozen guide never builds it).
    training_kernel: Option<TrainingKernel>,
    descriptors: DescriptorSet,
    /// The part of the image rendered (`settings.area()`): the accumulation's pixels.
    area: PixelRegion,
    /// The tiles of `area` the device holds one at a time, or `None` when the accumulation
    /// image holds all of `area`.
    tiles: Option<Tiles>,
    accumulation: StorageImage,
    readback: Buffer,
    /// Under `--noise-threshold`, the pixels converged so far (the kernel counts them).
    converged_pixels: ConvergedPixels,
    /// Bound through the descriptor set; kept alive as long as it.
    scene: GpuScene,
    /// Index of the first sample of every pixel's sequence that this render takes.
    first_sample: u32,
    samples_done: u32,
    frames_per_batch: u32,
    /// Samples each dispatch adds at most: `samples_per_frame`, less when one frame would
    /// take much longer than a batch should (the result is the same however samples are
    /// split into dispatches).
    samples_per_dispatch: u32,
    /// How long the last batch's frames took each.
    seconds_per_frame: Option<f64>,
    rays_traced: f64,
    /// Seconds that creating the renderer took (BVH, uploads, building the kernel).
    setup_seconds: f64,
    /// How the kernel traverses the scene (for advice when the loop limit stops a render).
    traversal: Traversal,
    /// Path guiding's guide and training splats (bound, unread, when not guiding).
    guide_buffers: GuideBuffers,
    /// What training the guide did, once it has (`--guiding` only).
    guide_report: Option<GuideReport>,
    /// The trained guide (`--guiding` only, once trained).
    guide: Option<Arc<Guide>>,
}

/// Why a render stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum StopReason {
    /// Every sample was taken.
    Done,
    /// The time limit was reached.
    TimeLimit,
    /// The cancel flag was set (a signal).
    Cancelled,
    /// An error stopped it after some samples (`RenderOutcome::failure`).
    Failed,
}

impl StopReason {
    /// How reports (`render --json`) name it: done, time-limit, signal or failed.
    pub fn name(self) -> &'static str {
        match self {
            StopReason::Done => "done",
            StopReason::TimeLimit => "time-limit",
            StopReason::Cancelled => "signal",
            StopReason::Failed => "failed",
        }
    }

    /// Whether the render ended as it was asked to: every sample taken, or its time limit
    /// reached (a time-limited render is a finished one, which `--denoise` and `--aov` still
    /// post-process); not stopped by a signal or a failure.
    pub fn is_finished(self) -> bool {
        matches!(self, StopReason::Done | StopReason::TimeLimit)
    }
}

/// What may stop a render early, and what to do on the way.
#[derive(Default)]
pub struct RenderControl<'a> {
    /// Stop after the current batch once this is set (e.g. by a signal handler).
    pub cancel: Option<&'a AtomicBool>,
    /// Stop once this instant has passed (batches are shortened so as not to overshoot it
    /// by more than a batch of about 250 ms).
    pub deadline: Option<Instant>,
    /// Called with the state every `checkpoint_interval` (not at the end: the caller has the
    /// final state in the outcome).
    pub checkpoint: Option<(Duration, StateCallback<'a>)>,
    /// Called with the state every interval, like `checkpoint` (e.g. to write a preview
    /// image); when both are due, the state is read back once for both.
    pub preview: Option<(Duration, StateCallback<'a>)>,
}

/// What a render calls with its read-back state (`RenderControl`'s checkpoint and preview).
pub type StateCallback<'a> = &'a mut dyn FnMut(&Accumulation) -> Result<()>;

/// How a render that `Renderer::render_to_end` ran ended.
#[derive(Debug)]
pub struct RenderOutcome {
    /// The image with every sample taken.
    pub image: RenderedImage,
    /// Samples per pixel taken.
    pub samples: u32,
    /// Seconds the frames took (the read-back excluded).
    pub seconds: f64,
    /// Seconds that creating the renderer took before the first frame (BVH, uploads,
    /// building the kernel; a driver that compiles lazily does part of it in the first
    /// frame, which `seconds` counts).
    pub setup_seconds: f64,
    /// The raw state (for a checkpoint or a shard); `None` for a render finished tile by
    /// tile (`Renderer::tile_by_tile`), which holds no state of the whole image.
    pub state: Option<Accumulation>,
    /// Why it stopped.
    pub stop: StopReason,
    /// The error that stopped it after some samples were taken (they are in `image`).
    pub failure: Option<Error>,
    /// What training the guide did (`--guiding` only).
    pub guide: Option<GuideReport>,
    /// What the scene takes on the device.
    pub scene_memory: SceneMemory,
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
        Renderer::create(context, scene, camera, settings, None, None)
    }

    /// Prepares a render like `new`, one of a sequence on the same device: it takes from
    /// `sequence` what an earlier render left there (`SequenceCache`: the pipeline of the
    /// same variant, the accumulation image of the same size, the scene upload when the
    /// scene's data are the same bit for bit), building only the rest. The image is bit
    /// for bit `new`'s. Give the renderer back with `keep_for_next` when it is done.
    pub fn in_sequence(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        sequence: &mut SequenceCache,
    ) -> Result<Renderer> {
        Renderer::create(context, scene, camera, settings, None, Some(sequence))
    }

    /// Leaves the pipeline, the accumulation image and the scene upload in `sequence` for
    /// the next render (`in_sequence`).
    pub fn keep_for_next(self, sequence: &mut SequenceCache) {
        let images = AccumulationImages {
            accumulation: self.accumulation,
            readback: self.readback,
            tile_upload: self.tiles.and_then(Tiles::into_upload),
        };
        sequence.keep(images, self.scene);
    }

    /// Prepares a render like `new`, with the kernel's SPIR-V given instead of the embedded
    /// one: `glsl/path_tracer.comp` compiled at run time, e.g. with a user's functions by
    /// `vkpath check`. `traversal` says how it was compiled (`Bvh` with `USE_BVH` defined,
    /// the others without) and, for `ConstantTriangles`, that the constant triangles must be
    /// able to trace the scene (`Traversal::constant_triangles_can_trace`).
    pub fn with_kernel(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        spirv: &[u32],
        traversal: Traversal,
    ) -> Result<Renderer> {
        if traversal == Traversal::ConstantTriangles {
            let materials = scene.needs_material_kernels();
            let capacity = Traversal::constant_triangle_capacity(materials);
            if scene.triangles.len() > capacity {
                return Err(Error::InvalidSettings(format!(
                    "a kernel with constant triangles holds at most {capacity} triangles, the scene has {}",
                    scene.triangles.len()
                )));
            }
            if scene.uses_alpha() {
                return Err(Error::InvalidSettings(
                    "a kernel with constant triangles runs no alpha test, and the scene has alpha-tested materials: use the BVH or the linear loop".into(),
                ));
            }
        }
        Renderer::create(
            context,
            scene,
            camera,
            settings,
            Some((spirv, traversal)),
            None,
        )
    }

    /// `new` (`kernel` = `None`: the embedded kernel for the traversal that `settings.accel`
    /// chooses), `with_kernel` and `in_sequence` (with `sequence`; a given kernel is never
    /// kept in one).
    fn create(
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: RenderSettings,
        kernel: Option<(&[u32], Traversal)>,
        sequence: Option<&mut SequenceCache>,
    ) -> Result<Renderer> {
        let mut sequence = sequence.filter(|_| kernel.is_none());
        let started = Instant::now();
        settings.validate()?;
        let area = settings.area();
        let tile_list = tile_layout(context, scene, &settings, area);
        let (image_width, image_height) = tile_list
            .first()
            .map_or((area.width(), area.height()), |t| (t.width(), t.height()));
        validate(context, scene, &settings, image_width, image_height)?;
        let commands = CommandRunner::new(context)?;
        // The device decides too: its ray queries under --accel auto and hardware
        // (`crate::accel::choose_traversal`, which refuses or warns where it cannot).
        let traversal = match kernel {
            Some((_, traversal)) => traversal,
            None => {
                let moving = sequence.as_ref().is_some_and(|s| s.moving_geometry);
                let choice = choose_traversal(context, scene, settings.accel, moving)?;
                if let Some(warning) = &choice.warning {
                    log::warn!("{warning}");
                }
                choice.traversal
            }
        };
        // A sequence's earlier upload of the same data needs only the camera written again;
        // of a scene that moved, the parts that did not are kept.
        let kept = match sequence.as_deref_mut() {
            Some(sequence) => sequence.take_scene(scene, UploadKey::new(&settings, traversal)),
            None => KeptUpload::Parts(KeptParts::default()),
        };
        let gpu_scene = match kept {
            KeptUpload::Whole(mut gpu_scene) => {
                gpu_scene.aim(scene, camera, &settings);
                gpu_scene
            }
            KeptUpload::Parts(parts) => GpuScene::upload(
                context, &commands, scene, camera, &settings, traversal, parts,
            )?,
        };
        // (`auto`'s compressed tree may have made way for the 4-wide one)
        let traversal = gpu_scene.traversal;
        // A given kernel was compiled as the variant room says of one (the plain macros)
        let source = match kernel {
            Some(_) => KernelSource::Given,
            None => KernelSource::Embedded,
        };
        let variant = path_tracer_variant(
            &gpu_scene.summary,
            &gpu_scene.variant_settings,
            traversal,
            source,
        )?;
        let build = variant.build;
        let guiding = settings.guiding.is_some();
        let budget = LoopBudget::of(context, &settings, scene, &gpu_scene, traversal)?;
        let settings_specialization = settings.specialization();
        let (loop_limit, loops) = budget.limit_and_loops();
        let parts = SpecializationParts {
            settings: &settings_specialization,
            traversal,
            triangles: &scene.triangles,
            variant: &variant,
            loop_limit,
            loops,
        };
        let specialization_with = |guiding_value| path_tracer_specialization(&parts, guiding_value);
        let guide_buffers = if guiding {
            GuideBuffers::guided(
                context,
                GuideGrid::around_triangles(scene.triangles.iter().map(|t| t.positions)),
            )?
        } else {
            GuideBuffers::unguided(context)?
        };
        let spirv = match kernel {
            Some((spirv, _)) => spirv.to_vec(),
            None => build.embedded_spirv()?,
        };
        let render_specialization = specialization_with(if guiding {
            contract::GUIDING_ON
        } else {
            contract::GUIDING_OFF
        });
        let build_pipeline =
            || PATH_TRACER.pipeline(context, &build, &spirv, &render_specialization);
        let pipeline = match sequence.as_deref_mut() {
            Some(sequence) => sequence.pipeline(&build, &render_specialization, build_pipeline)?,
            None => Arc::new(build_pipeline()?),
        };
        let training_kernel = guiding.then(|| TrainingKernel {
            build,
            specialization: specialization_with(contract::GUIDING_TRAINING),
            spirv,
        });
        let tiled = !tile_list.is_empty();
        let kept = sequence.and_then(|s| s.take_images(image_width, image_height, tiled));
        let AccumulationImages {
            accumulation,
            readback,
            tile_upload,
        } = match kept {
            Some(images) => images,
            None => accumulation_images(context, image_width, image_height, tiled)?,
        };
        let converged_pixels = ConvergedPixels::new(context)?;
        let descriptors = pipeline.descriptor_set(|resource| match resource {
            Resource::Accumulation => Some(Bound::StorageImage(&accumulation)),
            Resource::ConvergedPixels => Some(Bound::Buffer(&converged_pixels.buffer)),
            Resource::Guide => Some(Bound::TexelBuffer(&guide_buffers.guide)),
            Resource::GuideSplats => Some(Bound::Buffer(&guide_buffers.splats)),
            other => gpu_scene.resource(other),
        })?;
        commands.run(|recorder| recorder.clear_storage_image(&accumulation))?;
        let tiles = tile_upload.map(|upload| Tiles::every_frame(tile_list, upload));
        Ok(Renderer {
            context: context.clone(),
            settings,
            commands,
            pipeline,
            training_pipeline: None,
            training_kernel,
            descriptors,
            area,
            tiles,
            accumulation,
            readback,
            scene: gpu_scene,
            first_sample: 0,
            samples_done: 0,
            frames_per_batch: 1,
            samples_per_dispatch: budget.samples_per_dispatch,
            seconds_per_frame: None,
            rays_traced: 0.0,
            setup_seconds: started.elapsed().as_secs_f64(),
            traversal,
            guide_buffers,
            converged_pixels,
            guide_report: None,
            guide: None,
        })
    }

    /// What the scene takes on the device (`render --json`'s `scene_memory`).
    pub fn scene_memory(&self) -> SceneMemory {
        self.scene.memory
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

    /// Makes the render take samples `first..first + spp` of every pixel's sequence instead
    /// of `0..spp` (a shard of a larger render: the same samples that render would take).
    /// Only before the first frame.
    pub fn start_at_sample(&mut self, first: u32) -> Result<()> {
        if self.samples_done > 0 {
            return Err(Error::InvalidSettings(
                "the first sample can only be chosen before rendering".into(),
            ));
        }
        let end = first.checked_add(self.settings.spp).ok_or_else(|| {
            Error::InvalidSettings(format!("samples {first}.. past 2^32 do not exist"))
        })?;
        if self.settings.guiding.is_some() && end > GUIDE_TRAINING_FIRST_SAMPLE {
            return Err(Error::InvalidSettings(format!(
                "a guided render's samples end below 2^31 (the guide's training samples), \
                 not at {end}"
            )));
        }
        self.first_sample = first;
        Ok(())
    }

    /// The samples of every pixel's sequence taken so far.
    pub fn samples_taken(&self) -> std::ops::Range<u32> {
        self.first_sample..self.first_sample + self.samples_done
    }

    /// Makes a render in tiles finish each tile before the next begins, so that the host
    /// holds the finished image and one tile's state instead of the whole area's state
    /// (the image is bit for bit the same); returns whether it did. Without tiles, with a
    /// guide to train (`--guiding`: its training frames visit every tile) or once a sample
    /// was taken it changes nothing. A render going tile by tile has no state of the whole
    /// image: `accumulation`, `read_back`, `resume` and periodic checkpoints or previews
    /// fail, its outcome's `state` is `None`, and until its last tile is done no sample is
    /// held by every pixel (`samples_done` is 0; `render_batch` reports the samples taken
    /// spread over the image).
    pub fn tile_by_tile(&mut self) -> Result<bool> {
        let Some(tiles) = self.tiles.as_mut() else {
            return Ok(false);
        };
        if self.settings.guiding.is_some() || self.samples_done > 0 {
            return Ok(false);
        }
        tiles.go_tile_by_tile(&self.settings, self.area)?;
        Ok(true)
    }

    /// Reads the raw accumulation state back (for a checkpoint or a shard), and updates
    /// `rays_traced`.
    pub fn accumulation(&mut self) -> Result<Accumulation> {
        let texels = match self.tiles.as_mut() {
            Some(tiles) => tiles
                .whole_state(&self.settings, self.area, "read back")?
                .clone(),
            None => self.read_texels()?,
        };
        let pixels = self.area.width() as usize * self.area.height() as usize;
        let squares = contract::LAYER_SUM_OF_SQUARES as usize * pixels;
        let flagged = texels[squares..squares + pixels]
            .iter()
            .filter(|texel| texel[3] != 0.0)
            .count();
        if flagged > 0 {
            return Err(self.loop_limit_error(flagged));
        }
        let state = Accumulation {
            width: self.area.width(),
            height: self.area.height(),
            texels,
            samples: self.samples_taken(),
            guide: self.guide.clone(),
        };
        self.rays_traced = state.rays_traced();
        Ok(state)
    }

    /// Continues a render from its saved state: uploads it and goes on with the next
    /// sample, so that the result is bit for bit what an uninterrupted render gives. The
    /// state must be of this render's size and start where this render starts. A guided
    /// render samples with the state's frozen guide where it has one (the same guide the
    /// saved samples were taken with, whatever device resumes), else trains its own.
    pub fn resume(&mut self, state: &Accumulation) -> Result<()> {
        match &state.guide {
            Some(guide) => self.use_frozen_guide(guide.clone())?,
            None => self.train_guide()?,
        }
        let (width, height) = (self.area.width(), self.area.height());
        if (state.width, state.height) != (width, height)
            || state.texels.len() != area_texel_count(self.area)
        {
            return Err(Error::InvalidSettings(format!(
                "the saved state is {}x{}, the render {width}x{height}",
                state.width, state.height
            )));
        }
        if state.samples.start != self.first_sample
            || state.samples.len() as u32 > self.settings.spp
        {
            return Err(Error::InvalidSettings(format!(
                "the saved state holds samples {}..{}, the render takes {}..{}",
                state.samples.start,
                state.samples.end,
                self.first_sample,
                self.first_sample + self.settings.spp
            )));
        }
        if let Some(tiles) = self.tiles.as_mut() {
            tiles
                .whole_state(&self.settings, self.area, "resume into")?
                .copy_from_slice(&state.texels);
        } else {
            let upload = Buffer::with_data(
                &self.context,
                "saved state",
                &state.texels,
                vk::BufferUsageFlags::TRANSFER_SRC,
            )?;
            let image = &self.accumulation;
            self.commands
                .run(|recorder| recorder.copy_buffer_to_image(&upload, image))?;
        }
        self.samples_done = state.samples.len() as u32;
        if let Some(noise) = &self.settings.noise_threshold {
            self.converged_pixels
                .set(converged_pixel_count(state, noise));
        }
        Ok(())
    }

    /// Under `--noise-threshold`, the pixels converged so far (they take no more samples),
    /// updated after every batch; read it while the render goes on, e.g. for progress.
    pub fn converged_pixels(&self) -> Arc<std::sync::atomic::AtomicU64> {
        self.converged_pixels.handle()
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
        self.render_frames(1)?;
        Ok(self.samples_done)
    }

    /// Runs one submission of as many frames as keep it near 250 ms (measured on the
    /// previous submission), and returns the samples per pixel accumulated so far. Call it
    /// until `is_complete()`; report progress between calls.
    pub fn render_batch(&mut self) -> Result<u32> {
        self.render_batch_within(None)
    }

    /// `render_batch`, with fewer frames than usual when `budget` would not cover them.
    fn render_batch_within(&mut self, budget: Option<Duration>) -> Result<u32> {
        let started = Instant::now();
        let mut frames = self.frames_per_batch;
        if let (Some(budget), Some(per_frame)) = (budget, self.seconds_per_frame) {
            frames = frames.min(((budget.as_secs_f64() / per_frame) as u32).max(1));
        }
        let frames = self.render_frames(frames)?;
        if frames == 0 {
            return Ok(self.progress_samples());
        }
        let per_frame = started.elapsed().as_secs_f64() / f64::from(frames);
        self.seconds_per_frame = Some(per_frame);
        let target = TARGET_BATCH_DURATION.as_secs_f64();
        let wanted = (target / per_frame.max(1e-6)) as u32;
        // Grow at most 4x at a time so one fast outlier cannot make a batch take seconds.
        self.frames_per_batch = wanted.clamp(1, (frames * 4).min(MAX_FRAMES_PER_BATCH));
        // A single frame much longer than a batch should be takes fewer samples next time,
        // so that stopping (a signal, a time limit) waits for at most about a batch.
        if per_frame > 2.0 * target && self.samples_per_dispatch > 1 {
            let old_step = self.samples_per_dispatch;
            let scaled = f64::from(old_step) * target / per_frame;
            self.samples_per_dispatch = (scaled as u32).clamp(1, old_step - 1);
            self.seconds_per_frame =
                Some(per_frame * f64::from(self.samples_per_dispatch) / f64::from(old_step));
        }
        Ok(self.progress_samples())
    }

    /// Samples per pixel taken so far, for progress: `samples_done`, or for a render going
    /// tile by tile its samples spread over the image (rounded down).
    fn progress_samples(&self) -> u32 {
        match &self.tiles {
            Some(tiles) => tiles.progress(self.samples_done, self.settings.spp),
            None => self.samples_done,
        }
    }

    /// Dispatches the render pipeline once over no pixels (an extent of 0 × 0: every
    /// invocation returns before reading or writing anything), so that a driver that compiles
    /// kernels at their first dispatch, as lavapipe does, compiles it now: set-up, not the
    /// first batch, pays for it (the summary's set-up and render seconds, the first batch's
    /// timing that sizes the next). The image is as it was.
    pub fn warm_up(&mut self) -> Result<()> {
        let constants = FramePushConstants {
            first_sample_index: 0,
            sample_end: 0,
            pixel_offset: [0, 0],
            pixel_extent: [0, 0],
            noise_threshold: 0.0,
            noise_min_samples: 0,
        };
        let (pipeline, descriptors) = (&self.pipeline.pipeline, &self.descriptors);
        self.commands.run(|recorder| {
            recorder.bind(pipeline, descriptors);
            recorder.push_constants(pipeline, &constants);
            recorder.dispatch(pipeline, [1, 1, 1]);
        })?;
        Ok(())
    }

    /// Zeroes the accumulation state: no samples taken.
    fn clear_state(&mut self) -> Result<()> {
        let image = &self.accumulation;
        self.commands
            .run(|recorder| recorder.clear_storage_image(image))?;
        if let Some(tiles) = self.tiles.as_mut() {
            tiles.clear(&self.settings, self.area)?;
        }
        self.samples_done = 0;
        self.converged_pixels.set(0);
        Ok(())
    }

    /// Records up to `frames` frames into one submission and waits for them (after training
    /// the guide of a guided render that has not yet); returns how many were recorded.
    fn render_frames(&mut self, frames: u32) -> Result<u32> {
        self.train_guide()?;
        let span = FrameSpan {
            first_sample: self.first_sample,
            spp: self.settings.spp,
            noise_threshold: self.settings.noise_threshold,
            training: false,
        };
        self.run_frames(frames, &span)
    }

    /// `render_frames` without training first; `training` marks them training frames.
    fn run_frames(&mut self, frames: u32, span: &FrameSpan) -> Result<u32> {
        let step = self.samples_per_dispatch;
        // Samples the pixels these frames visit hold: every pixel's, or with tiles finished
        // one at a time the current tile's (the batch ends with it).
        let done = self.tiles.as_ref().map_or(self.samples_done, |tiles| {
            tiles.samples_of_current_pixels(self.samples_done)
        });
        let remaining_frames = (span.spp - done).div_ceil(step);
        let frames = frames.min(remaining_frames);
        if frames == 0 {
            return Ok(0);
        }
        let first = span.first_sample + done;
        let end = span.first_sample + span.spp;
        let (noise_threshold, noise_min_samples) = span
            .noise_threshold
            .map_or((0.0, 0), |noise| (noise.threshold, noise.min_spp));
        let plan = FramePlan::of(
            &self.pipeline,
            self.training_pipeline.as_ref(),
            span.training,
        )?;
        let descriptors = &self.descriptors;
        // The frames over one rectangle (the area, or a tile of it): each frame dispatches
        // the plan's stages in order.
        let record_frames = |recorder: &mut crate::vk::Recorder, part: PixelRegion| {
            let mut bound: Option<&KernelPipeline> = None;
            for frame in 0..frames {
                let frame_first = first + frame * step;
                let constants = FramePushConstants {
                    first_sample_index: frame_first,
                    sample_end: (frame_first + step).min(end),
                    pixel_offset: [part.x0, part.y0],
                    pixel_extent: [part.width(), part.height()],
                    noise_threshold,
                    noise_min_samples,
                };
                for &stage in &plan.stages {
                    let pipeline = &stage.pipeline;
                    if !bound.is_some_and(|b| std::ptr::eq(b, stage)) {
                        recorder.bind(pipeline, descriptors);
                        bound = Some(stage);
                    }
                    recorder.push_constants(pipeline, &constants);
                    recorder.dispatch(pipeline, [part.width(), part.height(), 1]);
                    // Each stage, and each frame, reads what the one before wrote.
                    recorder.compute_barrier();
                }
            }
            // The converged pixels' count, read by the host after the submission.
            recorder.host_read_barrier();
        };
        let after = (first + frames * step).min(end) - span.first_sample;
        self.converged_pixels.begin_batch();
        self.samples_done = match self.tiles.as_mut() {
            None => {
                self.commands
                    .run(|recorder| record_frames(recorder, self.area))?;
                after
            }
            Some(tiles) => {
                let device = TileDevice {
                    commands: &self.commands,
                    image: &self.accumulation,
                    readback: &self.readback,
                    area: self.area,
                    settings: &self.settings,
                };
                tiles.run_batch(&device, &record_frames, after, span.spp)?
            }
        };
        // Training frames' samples are the guide's, not the image's.
        if !span.training {
            self.converged_pixels.end_batch();
        }
        Ok(frames)
    }

    /// Copies the accumulation image back and returns the per-pixel mean, second moment and
    /// sample count. Can be called at any time (e.g. to save a partial render).
    pub fn read_back(&mut self) -> Result<RenderedImage> {
        Ok(self.accumulation()?.image())
    }

    /// Renders until every sample is taken or `cancel` is set, one batch at a time, calling
    /// `progress` with the samples per pixel taken after each batch, and reads the image
    /// back. An error after some samples were taken ends the render without losing them
    /// (`RenderOutcome::failure`); an error before any is returned.
    pub fn render_to_end(
        &mut self,
        progress: impl FnMut(u32),
        cancel: Option<&AtomicBool>,
    ) -> Result<RenderOutcome> {
        self.render_with(
            progress,
            RenderControl {
                cancel,
                ..RenderControl::default()
            },
        )
    }

    /// `render_to_end` with every control: a cancel flag, a deadline, periodic
    /// checkpoints.
    pub fn render_with(
        &mut self,
        mut progress: impl FnMut(u32),
        mut control: RenderControl,
    ) -> Result<RenderOutcome> {
        let started = Instant::now();
        let mut last_checkpoint = Instant::now();
        let mut last_preview = Instant::now();
        let mut failure = None;
        // A guided render trains its guide first; a signal or the time limit stops that too
        // (with no sample taken).
        let cancelled = || {
            control
                .cancel
                .is_some_and(|flag| flag.load(Ordering::SeqCst))
        };
        let late = || control.deadline.is_some_and(|d| Instant::now() >= d);
        let trained = self.train_guide_until(&|| cancelled() || late())?;
        let stop = loop {
            if !trained {
                break if cancelled() {
                    StopReason::Cancelled
                } else {
                    StopReason::TimeLimit
                };
            }
            if self.is_complete() {
                break StopReason::Done;
            }
            if control
                .cancel
                .is_some_and(|flag| flag.load(Ordering::SeqCst))
            {
                break StopReason::Cancelled;
            }
            let budget = control
                .deadline
                .map(|d| d.saturating_duration_since(Instant::now()));
            if budget == Some(Duration::ZERO) {
                break StopReason::TimeLimit;
            }
            match self.render_batch_within(budget) {
                Ok(done) => progress(done),
                Err(error) if self.samples_done == 0 => return Err(error),
                Err(error) => {
                    failure = Some(error);
                    break StopReason::Failed;
                }
            }
            // Periodic hooks read the accumulation back only when one is due (and not after
            // the last batch: the caller has the final state in the outcome).
            let due = |hook: &Option<(Duration, _)>, last: Instant| {
                hook.as_ref()
                    .is_some_and(|(interval, _)| last.elapsed() >= *interval)
            };
            let checkpoint_due = due(&control.checkpoint, last_checkpoint);
            let preview_due = due(&control.preview, last_preview);
            if (checkpoint_due || preview_due) && !self.is_complete() {
                let state = match self.accumulation() {
                    Ok(state) => state,
                    Err(error) => {
                        failure = Some(error);
                        break StopReason::Failed;
                    }
                };
                if let (true, Some((_, checkpoint))) = (checkpoint_due, control.checkpoint.as_mut())
                {
                    checkpoint(&state)?;
                    last_checkpoint = Instant::now();
                }
                if let (true, Some((_, preview))) = (preview_due, control.preview.as_mut()) {
                    preview(&state)?;
                    last_preview = Instant::now();
                }
            }
        };
        let seconds = started.elapsed().as_secs_f64();
        let (image, state) = match (self.final_image(), failure) {
            (Ok(image_and_state), failure_so_far) => {
                failure = failure_so_far;
                image_and_state
            }
            (Err(error), _) if self.samples_done == 0 => return Err(error),
            // A device that failed (lost) cannot give back what it holds either; any other
            // error of the read-back (a loop limit's flagged pixels) is the render's own.
            (Err(read_back), None) if !matches!(read_back, Error::Vulkan(_)) => {
                return Err(read_back)
            }
            (Err(read_back), failure) => {
                return Err(Error::RenderLost {
                    samples: self.samples_done,
                    error: Box::new(failure.unwrap_or(read_back)),
                    kept: String::new(),
                })
            }
        };
        Ok(RenderOutcome {
            image,
            samples: self.samples_done,
            seconds,
            setup_seconds: self.setup_seconds,
            stop,
            state,
            failure,
            guide: self.guide_report.clone(),
            scene_memory: self.scene.memory,
        })
    }

    /// Renders every remaining sample and reads the image back; any error is returned.
    pub fn render_all(&mut self) -> Result<RenderedImage> {
        Ok(self.render_to_end(|_| {}, None)?.finished()?.image)
    }
}

impl Renderer {
    /// The image at the end of a render and, unless it went tile by tile, its state (a
    /// render going tile by tile hands its image out: it holds none after).
    fn final_image(&mut self) -> Result<(RenderedImage, Option<Accumulation>)> {
        match self.tiles.as_mut().map(Tiles::end).transpose()? {
            Some(TilesEnd::Image { image, rays }) => {
                self.rays_traced = rays;
                Ok((image, None))
            }
            Some(TilesEnd::CutPaths(flagged)) => Err(self.loop_limit_error(flagged)),
            Some(TilesEnd::WholeState) | None => {
                let state = self.accumulation()?;
                Ok((state.image(), Some(state)))
            }
        }
    }

    /// The error of a render whose paths the loop limit may have cut short in `flagged`
    /// pixels.
    fn loop_limit_error(&self, flagged: usize) -> Error {
        Error::LoopLimit(format!(
            "the loop limit (llvmpipe's {} loop iterations, after which it ends loops \
             silently, or the limit of a checked function's loops) may have cut paths short \
             in {flagged} pixels, so the image would be wrong: {}",
            contract::LLVMPIPE_LOOP_LIMIT,
            loop_limit_advice(self.traversal, true)
        ))
    }

    /// Copies the accumulation image back: every layer, texel by texel.
    fn read_texels(&mut self) -> Result<Vec<[f32; 4]>> {
        let (image, readback) = (&self.accumulation, &self.readback);
        self.commands
            .run(|recorder| recorder.copy_image_to_buffer(image, readback))?;
        Ok(self.readback.read())
    }
}

/// A new accumulation image of `width` x `height` texels with its read-back buffer and,
/// when `tiled`, its upload buffer.
fn accumulation_images(
    context: &Arc<Context>,
    width: u32,
    height: u32,
    tiled: bool,
) -> Result<AccumulationImages> {
    let accumulation = StorageImage::new(
        context,
        "accumulation",
        width,
        height,
        contract::ACCUMULATION_LAYER_COUNT,
    )?;
    let buffer = |name: &str, usage, location| {
        Buffer::new(context, name, accumulation.byte_size(), usage, location)
    };
    let readback = buffer(
        "readback",
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let tile_upload = match tiled {
        true => Some(buffer(
            "tile upload",
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?),
        false => None,
    };
    Ok(AccumulationImages {
        accumulation,
        readback,
        tile_upload,
    })
}

/// Checks what a render needs before anything is allocated: valid settings, an image
/// within the device's limits, a scene with triangles.
fn validate(
    context: &Context,
    scene: &Scene,
    settings: &RenderSettings,
    image_width: u32,
    image_height: u32,
) -> Result<()> {
    let device_limit = context.limits.max_image_dimension2_d;
    if image_width > device_limit || image_height > device_limit {
        return Err(Error::InvalidSettings(format!(
            "a tile of {image_width}x{image_height} pixels exceeds the device's limit of \
             {device_limit} pixels per side: use a smaller --tile-size"
        )));
    }
    if scene.triangles.is_empty() {
        return Err(Error::MissingInput("the scene has no triangles".into()));
    }
    // What the render allocates on the device: the triangles (96 bytes each), with a BVH
    // their positions for the traversal (48 bytes each) and at most 1 wide node per triangle
    // (112 bytes each), the lights (16 bytes each and a header, and a selection word of 4 bytes
    // per triangle), the accumulation image (of the area or of a tile) and its read-back and upload buffers (48 bytes per pixel each).
    let triangles = scene.triangles.len() as u64;
    let scene_bytes = scene_bytes(scene);
    let image_bytes = u64::from(image_width)
        * u64::from(image_height)
        * ACCUMULATION_COPIES
        * ACCUMULATION_BYTES_PER_PIXEL;
    let available = context.device_memory_bytes();
    if available > 0 && scene_bytes + image_bytes > available {
        return Err(Error::InvalidSettings(format!(
            "the render needs about {} MB on '{}' ({} MB for {triangles} triangles, {} MB for \
             {image_width}x{image_height} pixels of the {}x{} image at once), more than its {} MB: \
             use a smaller --tile-size or scene",
            (scene_bytes + image_bytes) >> 20,
            context.info.name,
            scene_bytes >> 20,
            image_bytes >> 20,
            settings.width,
            settings.height,
            available >> 20
        )));
    }
    Ok(())
}
