//! Frames and batches: each frame dispatches its plan's stages over the pixels (the area, or
//! a tile of it) and adds up to `samples_per_dispatch` samples; a batch is one submission of
//! as many frames as take about 250 ms.

use std::time::{Duration, Instant};

use crate::error::{Error, Result};
use crate::kernels::KernelPipeline;
use crate::render::adaptive::NoiseThreshold;
use crate::render::gpu_types::FramePushConstants;
use crate::render::region::PixelRegion;
use crate::render::tiles::TileDevice;

use super::Renderer;

/// How long one submission of frames should take: long enough to hide submission overhead,
/// short enough for a responsive progress bar. Each frame is its own dispatch, so a GPU
/// watchdog sees short dispatches whatever this is.
const TARGET_BATCH_DURATION: Duration = Duration::from_millis(250);
/// Most frames recorded into one submission.
const MAX_FRAMES_PER_BATCH: u32 = 256;

/// The samples that `Renderer::run_frames` takes: the render's (`first_sample`,
/// `settings.spp`, its noise threshold) or a training iteration's.
pub(super) struct FrameSpan {
    /// The first sample of every pixel's sequence in the span.
    pub(super) first_sample: u32,
    /// Samples per pixel in the span (`samples_done` counts those taken).
    pub(super) spp: u32,
    /// Adaptive sampling, if on.
    pub(super) noise_threshold: Option<NoiseThreshold>,
    /// Whether the frames train the guide (with `Renderer::training_pipeline`).
    pub(super) training: bool,
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

impl Renderer {
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
    pub(super) fn render_batch_within(&mut self, budget: Option<Duration>) -> Result<u32> {
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
    pub(super) fn clear_state(&mut self) -> Result<()> {
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
    pub(super) fn run_frames(&mut self, frames: u32, span: &FrameSpan) -> Result<u32> {
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
}
