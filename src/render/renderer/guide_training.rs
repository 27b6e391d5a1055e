//! Training a guided render's guide (`--guiding`): the training pipeline, the iterations of
//! training frames over the render's area, and what the training did (`GuideReport`). A part
//! of `Renderer` kept apart from the progressive render it precedes.

use std::sync::Arc;
use std::time::Instant;

use crate::contract;
use crate::error::{Error, Result};
use crate::guiding::training::{GuideTrainer, GUIDE_TRAINING_FIRST_SAMPLE};
use crate::guiding::Guide;
use crate::kernels::{Build, PATH_TRACER};

use super::{FrameSpan, Renderer};

/// Frames recorded into one submission while training a guide.
const TRAINING_FRAMES_PER_SUBMISSION: u32 = 16;

/// The kernel a guided render's training pipeline is built from: the render's own, with
/// `SPEC_GUIDING` set to `GUIDING_TRAINING`.
pub(super) struct TrainingKernel {
    pub(super) build: Build,
    pub(super) spirv: Vec<u32>,
    pub(super) specialization: Vec<(u32, u32)>,
}

/// What training a render's guide did (`--guiding`).
#[derive(Clone, Debug, PartialEq)]
pub struct GuideReport {
    /// Positions of the guide's grid along x, y and z.
    pub grid_resolution: [u32; 3],
    /// Cells in all (one per grid position and orientation that a surface there can face).
    pub cell_count: u32,
    /// Cells that training taught (the others sample the BSDF alone).
    pub guided_cell_count: u32,
    /// Bytes the guide takes on the device (the training splats take about twice that).
    pub memory_bytes: usize,
    /// Samples per pixel of each training iteration.
    pub iterations: Vec<u32>,
    /// Where the training's seconds went (`seconds()` is their sum).
    pub times: TrainingTimes,
    /// Whether the guide came frozen in a resumed state (`Renderer::resume`) instead: no
    /// iterations, no seconds.
    pub from_checkpoint: bool,
}

impl GuideReport {
    /// The report of `guide`, trained in `iterations` (spp each) in `times`, or frozen in a
    /// resumed state.
    fn of(
        guide: &Guide,
        iterations: Vec<u32>,
        times: TrainingTimes,
        from_checkpoint: bool,
    ) -> GuideReport {
        let grid = guide.grid();
        GuideReport {
            grid_resolution: grid.resolution.to_array(),
            cell_count: grid.cell_count(),
            guided_cell_count: guide.guided_cell_count(),
            memory_bytes: guide.memory_bytes(),
            iterations,
            times,
            from_checkpoint,
        }
    }

    /// Seconds the training took (pipeline, frames, read-backs and builds; 0 for a guide
    /// from a checkpoint).
    pub fn seconds(&self) -> f64 {
        self.times.pipeline_seconds + self.times.frames_seconds + self.times.host_seconds
    }
}

/// Where a guide's training spent its seconds (`GuideReport::times`): what to make cheaper
/// differs between lavapipe, where the frames dominate, and a GPU, where they take
/// milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrainingTimes {
    /// Building the training kernel's pipeline (the driver's compile, or its cache's copy).
    pub pipeline_seconds: f64,
    /// The training frames: recording and submitting them and waiting for the device (on
    /// lavapipe this includes compiling the kernel at its first dispatch).
    pub frames_seconds: f64,
    /// The host's side between iterations: clearing the state and the splats, reading the
    /// splats back, building each iteration's guide and uploading it.
    pub host_seconds: f64,
}

impl Renderer {
    /// The trained guide: `None` before training, and without `--guiding`.
    pub fn guide(&self) -> Option<&Guide> {
        self.guide.as_deref()
    }

    /// What training the guide did: `None` before it has, and without `--guiding`.
    pub fn guide_report(&self) -> Option<&GuideReport> {
        self.guide_report.as_ref()
    }

    /// Trains the guide of a guided render (`--guiding`), if it has not yet: the iterations
    /// of `GuideTraining::iterations` over the render's whole area, each taking training
    /// samples (from `GUIDE_TRAINING_FIRST_SAMPLE` on, which no render takes) with the
    /// guide built so far and adding its splats to those before; then the render's state
    /// is cleared. The first frame (and `resume`) call it; deterministic, so every shard and
    /// resumed render of an image trains the same guide.
    pub fn train_guide(&mut self) -> Result<()> {
        self.train_guide_until(&|| false).map(|_| ())
    }

    /// `train_guide`, asking `stop` before each submission of training frames: once it
    /// says so, training is abandoned (the next call starts it afresh, so the guide is the
    /// same) and this returns `false`; `true` once the guide is trained (or none is
    /// needed).
    pub fn train_guide_until(&mut self, stop: &dyn Fn() -> bool) -> Result<bool> {
        let (Some(training), Some(grid)) = (self.settings.guiding, self.guide_buffers.grid())
        else {
            return Ok(true);
        };
        if self.guide_report.is_some() {
            return Ok(true);
        }
        let started = Instant::now();
        let mut times = TrainingTimes::default();
        if let Some(kernel) = &self.training_kernel {
            self.training_pipeline = Some(PATH_TRACER.pipeline(
                &self.context,
                &kernel.build,
                &kernel.spirv,
                &kernel.specialization,
            )?);
            self.training_kernel = None;
        }
        times.pipeline_seconds = started.elapsed().as_secs_f64();
        let iterations = training.iterations();
        let mut trainer = GuideTrainer::new(grid.clone());
        let mut taken = 0u32;
        let result = (|| -> Result<bool> {
            // The first iteration samples with no guided cell, whatever an abandoned
            // training left bound.
            self.guide_buffers
                .set_guide(&self.context, trainer.guide())?;
            self.descriptors
                .write_texel_buffer(contract::BINDING_GUIDE, &self.guide_buffers.guide);
            for &samples in &iterations {
                self.clear_state()?;
                self.guide_buffers.clear_splats(&self.commands)?;
                // Adaptive sampling stays off: every pixel trains alike.
                let span = FrameSpan {
                    first_sample: GUIDE_TRAINING_FIRST_SAMPLE + taken,
                    spp: samples,
                    noise_threshold: None,
                    training: true,
                };
                let frames_started = Instant::now();
                while self.samples_done < samples {
                    if stop() {
                        return Ok(false);
                    }
                    self.run_frames(TRAINING_FRAMES_PER_SUBMISSION, &span)?;
                }
                times.frames_seconds += frames_started.elapsed().as_secs_f64();
                if let Some(splats) = self.guide_buffers.read_splats(&self.commands)? {
                    trainer.add_iteration(&splats);
                }
                self.guide_buffers
                    .set_guide(&self.context, trainer.guide())?;
                self.descriptors
                    .write_texel_buffer(contract::BINDING_GUIDE, &self.guide_buffers.guide);
                taken += samples;
            }
            Ok(true)
        })();
        self.clear_state()?;
        if !result? {
            return Ok(false);
        }
        let guide = trainer.into_guide();
        let seconds = started.elapsed().as_secs_f64();
        times.host_seconds = (seconds - times.pipeline_seconds - times.frames_seconds).max(0.0);
        self.guide_report = Some(GuideReport::of(&guide, iterations, times, false));
        self.guide = Some(Arc::new(guide));
        Ok(true)
    }

    /// Samples with `guide` (a guided render's, frozen into a saved state) instead of
    /// training one: it must cover this render's grid, i.e. come from this scene.
    pub(super) fn use_frozen_guide(&mut self, guide: Arc<Guide>) -> Result<()> {
        let grid = self.guide_buffers.grid();
        if grid != Some(guide.grid()) {
            return Err(Error::InvalidSettings(match grid {
                None => "the saved state holds a guide, but this render is not guided".into(),
                Some(_) => "the saved state's guide covers another grid than this scene's".into(),
            }));
        }
        self.guide_buffers.set_guide(&self.context, &guide)?;
        self.descriptors
            .write_texel_buffer(contract::BINDING_GUIDE, &self.guide_buffers.guide);
        self.guide_report = Some(GuideReport::of(
            &guide,
            Vec::new(),
            TrainingTimes::default(),
            true,
        ));
        self.guide = Some(guide);
        Ok(())
    }
}
