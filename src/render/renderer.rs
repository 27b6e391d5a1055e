//! The progressive GPU renderer: uploads a scene, runs frames of the path-tracing kernel that
//! add samples to an accumulation image, and reads the image back. Each room beside it has
//! one job: making a renderer (`create`), frames and batches (`frames`), the render loop
//! (`render_loop`), the state on the host (`state`), what a render reports and what may
//! stop it (`outcome`), training a guided render's guide (`guide_training`) and the lavapipe
//! loop budget that sizes each dispatch (`loop_budget`).

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::guiding::training::GUIDE_TRAINING_FIRST_SAMPLE;
use crate::guiding::Guide;
use crate::kernels::variant::Traversal;
use crate::kernels::KernelPipeline;
use crate::render::converged_pixels::ConvergedPixels;
use crate::render::gpu_scene::{GpuScene, SceneMemory};
use crate::render::guide_buffers::GuideBuffers;
use crate::render::region::PixelRegion;
use crate::render::settings::RenderSettings;
use crate::render::tiles::Tiles;
use crate::vk::{Buffer, CommandRunner, Context, DescriptorSet, StorageImage};

mod create;
mod frames;
mod guide_training;
mod loop_budget;
mod outcome;
mod render_loop;
mod state;

use frames::FrameSpan;
use guide_training::TrainingKernel;
pub use guide_training::{GuideReport, TrainingTimes};
pub use outcome::{RenderControl, RenderOutcome, StateCallback, StopReason};

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

impl Renderer {
    /// What the scene takes on the device (`render --json`'s `scene_memory`).
    pub fn scene_memory(&self) -> SceneMemory {
        self.scene.memory
    }

    /// Which scene triangle each of the kernels' triangle indices is
    /// (`GpuScene::triangle_order`; `None`: the scene's own order).
    pub fn triangle_order(&self) -> Option<&[u32]> {
        self.scene.triangle_order.as_deref()
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
}
