//! One render session: a scene seen by a camera, rendered with settings on one device as a
//! job says (a range of every pixel's sample sequence, a time limit, a stop flag, periodic
//! checkpoints and resuming from one, a preview and a live view), reporting its progress
//! after each batch, then post-processed (AOVs, denoising). `vkpath render` (each frame of
//! `--frames`, each device of `--device all`) and Python's `vkpath.render` and
//! `render_frames` run their renders through it: the command line only parses options and
//! writes files and lines, Python only parses arguments and builds its dict.
//!
//! A session is a short function of its steps, as a frame is in kajiya's
//! `world_render_passes.rs`: make the renderer (or take a sequence's kept parts) and resume,
//! choose how the state is held, warm the kernels up, render with the hooks, write what a
//! stop keeps, and leave the sequence's parts for the next render.

use std::cell::Cell;
use std::ops::Range;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Instant;

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::image_io::output::{save_image, ImageLayer};
use crate::render::accumulation::Accumulation;
use crate::render::job::{stopped_before_first_sample, JobOptions, JobOutcome, JobProgress};
use crate::render::metadata::RenderMetadata;
use crate::render::post_process::PostProcess;
use crate::render::renderer::{RenderControl, Renderer};
use crate::render::sequence::SequenceCache;
use crate::render::settings::RenderSettings;
use crate::render::state_exr::{read_state, write_state};
use crate::scene::Scene;
use crate::vk::Context;
use crate::RenderedImage;

/// A render of one scene on one device, as its job says, and what happens to its image
/// after (`post_process`). Build it with `new` and set the fields that differ.
pub struct RenderSession<'a> {
    /// The device.
    pub context: &'a Arc<Context>,
    /// The scene as loaded (or posed, for a frame of a sequence).
    pub scene: &'a Scene,
    /// The camera.
    pub camera: &'a Camera,
    /// The render settings; `spp` is ignored: `job.samples` decides.
    pub settings: &'a RenderSettings,
    /// The samples to take and what controls the render (time limit, stop flag,
    /// checkpoints, resuming, preview, live view, whether to keep the state).
    pub job: JobOptions<'a>,
    /// What happens to the finished image (`--aov`, `--denoise`; Python's `aovs=`,
    /// `denoise=`).
    pub post: PostProcess,
    /// With a cache, one render of a sequence on this device (`Renderer::in_sequence`): it
    /// takes what the earlier ones left there and leaves its own for the next.
    pub sequence: Option<&'a mut SequenceCache>,
}

impl<'a> RenderSession<'a> {
    /// A session of every sample `settings.spp` asks for, with nothing else: no time limit,
    /// stop flag, checkpoint, preview or post-processing, and no sequence.
    pub fn new(
        context: &'a Arc<Context>,
        scene: &'a Scene,
        camera: &'a Camera,
        settings: &'a RenderSettings,
    ) -> RenderSession<'a> {
        RenderSession {
            context,
            scene,
            camera,
            settings,
            job: JobOptions {
                samples: 0..settings.spp,
                ..JobOptions::default()
            },
            post: PostProcess::default(),
            sequence: None,
        }
    }

    /// Renders as the job says, calling `progress` after each batch. The settings' `spp` is
    /// the sample range's length. An error after some samples were taken ends the render
    /// without losing them (`RenderOutcome::failure`); when the device could not give them
    /// back either (`Error::RenderLost`), the error says what the job's checkpoint or
    /// resumed checkpoint kept.
    pub fn run(&mut self, progress: impl FnMut(JobProgress)) -> Result<JobOutcome> {
        let settings = RenderSettings {
            spp: self.job.samples.len() as u32,
            ..self.settings.clone()
        };
        let before = self.sequence.as_deref().map(|s| s.reused);
        let (mut renderer, resumed_samples) = self.start(&settings)?;
        let checkpointed = Cell::new(None);
        let (outcome, rendering_started) = self.render(
            &mut renderer,
            &settings,
            progress,
            &checkpointed,
            resumed_samples,
        )?;
        // A stop before this run's first sample has nothing new: it writes nothing, so that an
        // existing checkpoint or preview stays as it was.
        let took_samples = !stopped_before_first_sample(&outcome, resumed_samples);
        let job = &self.job;
        let preview_failure = job
            .preview
            .as_ref()
            .filter(|_| took_samples)
            .and_then(|preview| save_image(&preview.path, &outcome.image, &preview.save).err())
            .map(Error::from);
        // Every other stop writes the checkpoint, so that nothing rendered is lost.
        if let (Some(path), true, Some(state)) = (&job.checkpoint, took_samples, &outcome.state) {
            write_state(
                path,
                state,
                &self.metadata(&settings, state.samples.clone()),
            )?;
        }
        let reused = match self.sequence.as_deref_mut() {
            Some(sequence) => {
                renderer.keep_for_next(sequence);
                before.map(|before| sequence.reused.since(before))
            }
            None => None,
        };
        let taken = job.samples.start..job.samples.start + outcome.samples;
        Ok(JobOutcome {
            metadata: self.metadata(&settings, taken),
            outcome,
            resumed_samples,
            rendering_started,
            preview_failure,
            reused,
        })
    }

    /// The image after `post` and its extra layers, for a render that finished (every
    /// sample taken, or the time limit reached) and took `outcome`'s samples; `None` when
    /// there is nothing to do or the render stopped early (a signal, a failure), which is
    /// saved or returned as it is.
    pub fn post_process(
        &self,
        outcome: &JobOutcome,
    ) -> Result<Option<(RenderedImage, Vec<ImageLayer>)>> {
        let finished = outcome.outcome.stop.is_finished() && outcome.outcome.failure.is_none();
        if self.post.is_empty() || !finished {
            return Ok(None);
        }
        // The layers take the samples the colour took: all of them, or those before the time
        // limit (not the million asked, which would take far longer than the render did).
        let taken = RenderSettings {
            spp: outcome.metadata.samples.len() as u32,
            ..self.settings.clone()
        };
        let image = &outcome.outcome.image;
        let processed = self
            .post
            .apply(self.context, self.scene, self.camera, &taken, image)?;
        Ok(Some(processed))
    }

    /// The metadata of a render of `settings` that holds `taken` (for an output's header).
    fn metadata(&self, settings: &RenderSettings, taken: Range<u32>) -> RenderMetadata {
        RenderMetadata::new(settings, self.scene, self.camera, taken)
    }

    /// The renderer (from the sequence's kept parts, if any), started at the job's first
    /// sample and resumed from its checkpoint, with the samples that came from it.
    fn start(&mut self, settings: &RenderSettings) -> Result<(Renderer, u32)> {
        let (context, scene, camera) = (self.context, self.scene, self.camera);
        let samples = self.job.samples.clone();
        let mut renderer = match self.sequence.as_deref_mut() {
            Some(sequence) => {
                Renderer::in_sequence(context, scene, camera, settings.clone(), sequence)?
            }
            None => Renderer::new(context, scene, camera, settings.clone())?,
        };
        renderer.start_at_sample(samples.start)?;
        let Some(path) = &self.job.resume else {
            return Ok((renderer, 0));
        };
        let (state, saved) = read_state(path)?;
        let refuse = |why: String| {
            Error::InvalidSettings(format!("cannot resume from '{}': {why}", path.display()))
        };
        if let Some(difference) = saved.first_difference(&self.metadata(settings, samples.clone()))
        {
            return Err(refuse(format!(
                "it was rendered with another {} (checkpoint vs now)",
                difference
            )));
        }
        if state.samples.start != samples.start || state.samples.end > samples.end {
            return Err(refuse(format!(
                "it holds samples {}..{}, this render takes {}..{}",
                state.samples.start, state.samples.end, samples.start, samples.end
            )));
        }
        renderer.resume(&state)?;
        Ok((renderer, state.samples.len() as u32))
    }

    /// Renders with the job's hooks (checkpoints, preview, live view) and stop conditions,
    /// after warming the kernels up; returns the outcome and when the first batch began.
    /// `checkpointed` gets the samples per pixel of each checkpoint written.
    fn render(
        &self,
        renderer: &mut Renderer,
        settings: &RenderSettings,
        progress: impl FnMut(JobProgress),
        checkpointed: &Cell<Option<usize>>,
        resumed_samples: u32,
    ) -> Result<(crate::render::RenderOutcome, Instant)> {
        let job = &self.job;
        // What needs the whole state as the render goes, or at its end.
        let whole_state = job.keep_state
            || job.time_limit.is_some()
            || job.checkpoint.is_some()
            || job.resume.is_some()
            || job.preview.is_some()
            || job.live.is_some();
        if !whole_state {
            renderer.tile_by_tile()?;
        }
        let mut write_checkpoint = |state: &Accumulation| -> Result<()> {
            if let Some(path) = &job.checkpoint {
                write_state(path, state, &self.metadata(settings, state.samples.clone()))?;
                checkpointed.set(Some(state.samples.len()));
            }
            Ok(())
        };
        let mut write_preview = self.image_hook();
        // The preview and the live view share the periodic hook, at the sooner interval.
        let image_interval = [
            job.preview.as_ref().map(|p| p.interval),
            job.live.as_ref().map(|l| l.interval),
        ]
        .into_iter()
        .flatten()
        .min();
        // The driver's first-dispatch compile belongs to set-up, not to the first batch (nor to
        // the time limit, counted from the end of set-up).
        renderer.warm_up()?;
        let deadline = job.time_limit.map(|limit| Instant::now() + limit);
        let control = RenderControl {
            cancel: job.cancel,
            deadline,
            checkpoint: job.checkpoint.as_ref().map(|_| {
                (
                    job.checkpoint_interval,
                    &mut write_checkpoint as &mut dyn FnMut(&_) -> Result<()>,
                )
            }),
            preview: image_interval.map(|interval| {
                (
                    interval,
                    &mut write_preview as &mut dyn FnMut(&_) -> Result<()>,
                )
            }),
        };
        let progress = self.progress_of(renderer, settings, deadline, progress);
        let rendering_started = Instant::now();
        let outcome = renderer.render_with(progress, control).map_err(|error| {
            say_what_a_lost_render_kept(error, job, checkpointed.get(), resumed_samples)
        })?;
        Ok((outcome, rendering_started))
    }

    /// The periodic image hook: writes the preview (a failed write is logged once and the
    /// render goes on: a preview is a convenience) and shows the live view.
    fn image_hook(&self) -> impl FnMut(&Accumulation) -> Result<()> + '_ {
        let job = &self.job;
        let mut preview_warned = false;
        move |state: &Accumulation| {
            let image = state.image();
            if let Some(preview) = &job.preview {
                if let Err(error) = save_image(&preview.path, &image, &preview.save) {
                    if !std::mem::replace(&mut preview_warned, true) {
                        log::warn!("{error} (the preview; the render goes on)");
                    }
                }
            }
            if let Some(live) = &job.live {
                (live.show)(&image);
            }
            Ok(())
        }
    }

    /// What the renderer calls after each batch: marks the job started and calls
    /// `progress` with the samples done, the deadline and, under `--noise-threshold`, the
    /// share of the pixels converged.
    fn progress_of<'p>(
        &'p self,
        renderer: &Renderer,
        settings: &RenderSettings,
        deadline: Option<Instant>,
        mut progress: impl FnMut(JobProgress) + 'p,
    ) -> impl FnMut(u32) + 'p {
        let converged = renderer.converged_pixels();
        let pixels = f64::from(settings.area().width()) * f64::from(settings.area().height());
        let adaptive = settings.noise_threshold.is_some();
        let started = self.job.started;
        move |samples: u32| {
            if let Some(started) = started {
                started.store(true, Ordering::SeqCst);
            }
            progress(JobProgress {
                samples_done: samples,
                deadline,
                converged_share: adaptive
                    .then(|| converged.load(Ordering::SeqCst) as f64 / pixels.max(1.0)),
            });
        }
    }
}

/// Completes the error of a render whose device failed and could not give back what it
/// held (`Error::RenderLost`) with what is left of it: the last checkpoint this run wrote
/// (and the `--resume` that goes on from it), the resumed checkpoint, or that none had been
/// written yet. A job without a checkpoint or resume leaves the error as it is (the
/// command line says that without `--checkpoint` nothing is kept).
fn say_what_a_lost_render_kept(
    error: Error,
    options: &JobOptions,
    checkpointed: Option<usize>,
    resumed_samples: u32,
) -> Error {
    let Error::RenderLost { samples, error, .. } = error else {
        return error;
    };
    let written = options.checkpoint.as_ref().zip(checkpointed);
    let kept = match (written, &options.resume, &options.checkpoint) {
        (Some((path, spp)), _, _) => format!(
            "; '{}' holds the first {spp} spp: add --resume '{}' to go on from it",
            path.display(),
            path.display()
        ),
        (None, Some(resumed), _) => format!(
            "; '{}' still holds the {resumed_samples} spp this run resumed from",
            resumed.display()
        ),
        (None, None, Some(_)) => "; no checkpoint had been written yet".to_string(),
        (None, None, None) => String::new(),
    };
    Error::RenderLost {
        samples,
        error,
        kept,
    }
}
