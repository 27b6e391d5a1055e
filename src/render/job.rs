//! A production render: a range of every pixel's sample sequence (all of it, or a shard), a
//! time limit, a cancel flag (signals), periodic checkpoints and resuming from one, bit for
//! bit, and a periodic tone-mapped preview. The command line only parses these and prints
//! what happened.

use std::ops::Range;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::image_io::output::{save_image, SaveOptions};
use crate::render::accumulation::Accumulation;
use crate::render::metadata::RenderMetadata;
use crate::render::renderer::{RenderControl, RenderOutcome, Renderer, StopReason};
use crate::render::sequence::SequenceCache;
use crate::render::settings::{Integrator, RenderSettings, SamplerKind};
use crate::render::state_exr::{read_state, write_state};
use crate::scene::Scene;
use crate::vk::Context;
use crate::RenderedImage;

/// The settings of a production render where nothing says otherwise, what `vkpath render`
/// starts from and what the Python package's `vkpath.render` takes for every setting a call
/// leaves out (so the two cannot drift apart): the library's defaults with the best estimator the scenes support, `mis`
/// (light and BRDF samples weighted by the power heuristic: it sees every kind of light,
/// punctual ones included, and measured 3.7x the workshop's efficiency on the Cornell box)
/// with Owen-scrambled Sobol points (8.7x; see the README's Benchmarks). The workshop's
/// integrator (`RenderSettings::default()`) stays what `exercise`, `check` and parity work
/// use.
pub fn production_settings() -> RenderSettings {
    RenderSettings {
        integrator: Integrator::Mis,
        sampler: SamplerKind::Sobol,
        ..RenderSettings::default()
    }
}

/// The default interval between checkpoints.
pub const DEFAULT_CHECKPOINT_INTERVAL: Duration = Duration::from_secs(60);

/// The default interval between previews.
pub const DEFAULT_PREVIEW_INTERVAL: Duration = Duration::from_secs(10);

/// A PNG of the image so far, rewritten (atomically, as every output) while a render runs.
#[derive(Clone, Debug)]
pub struct PreviewOptions {
    /// The preview image (.png; an .exr would be linear).
    pub path: PathBuf,
    /// Seconds between rewrites; the preview is also written when the render stops.
    pub interval: Duration,
    /// Exposure and tone map (the output PNG's).
    pub save: SaveOptions,
}

/// A live view of the image so far (`render --tev`): shown every `interval` while the render
/// runs (with the preview, if any, at the sooner of their intervals). It must return at once.
#[derive(Clone, Copy)]
pub struct LiveImage<'a> {
    /// Time between updates.
    pub interval: Duration,
    /// Shows an image.
    pub show: &'a (dyn Fn(&RenderedImage) + Sync),
}

impl std::fmt::Debug for LiveImage<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveImage")
            .field("interval", &self.interval)
            .finish_non_exhaustive()
    }
}

/// How a production render runs.
#[derive(Clone, Debug)]
pub struct JobOptions<'a> {
    /// The samples of every pixel's sequence to take (`0..spp` for a whole render).
    pub samples: Range<u32>,
    /// Stop after this long (after the current batch).
    pub time_limit: Option<Duration>,
    /// Stop after the current batch once set (signals).
    pub cancel: Option<&'a AtomicBool>,
    /// Write the render state here every `checkpoint_interval` and when the render stops.
    pub checkpoint: Option<PathBuf>,
    /// See `checkpoint`.
    pub checkpoint_interval: Duration,
    /// Continue from this checkpoint (it must be of the same scene and settings).
    pub resume: Option<PathBuf>,
    /// Rewrite a preview image every so often and when the render stops.
    pub preview: Option<PreviewOptions>,
    /// Set once the first batch of samples is done (after the renderer is built: kernels,
    /// scene upload, resumed state; and after the first batch, which on drivers that compile
    /// at the first dispatch, as lavapipe does, takes the kernels' compile, and with
    /// `--guiding` the guide's training): what a caller's signal handling needs to know,
    /// since a stop before then has nothing to save.
    pub started: Option<&'a AtomicBool>,
    /// Show the image so far every so often (a live view).
    pub live: Option<LiveImage<'a>>,
    /// Keep the render's whole state for its outcome (a shard, or a device's share of a
    /// render on several). Without it, and without a time limit, checkpoints, resuming,
    /// previews, a live view or a guide to train, a render in tiles finishes them one at a
    /// time (`Renderer::tile_by_tile`): the host holds the finished image, not the state.
    pub keep_state: bool,
}

impl Default for JobOptions<'_> {
    /// A whole render of 0 samples with nothing else: set `samples`.
    fn default() -> Self {
        JobOptions {
            samples: 0..0,
            time_limit: None,
            cancel: None,
            checkpoint: None,
            checkpoint_interval: DEFAULT_CHECKPOINT_INTERVAL,
            resume: None,
            preview: None,
            started: None,
            live: None,
            keep_state: false,
        }
    }
}

/// What a production render did.
pub struct JobOutcome {
    /// The render's outcome (image, state, stop reason, ...); its state is `None` when the
    /// render went tile by tile (`JobOptions::keep_state`).
    pub outcome: RenderOutcome,
    /// The metadata of what it holds (for the output file's header).
    pub metadata: RenderMetadata,
    /// The samples that came from the resumed checkpoint.
    pub resumed_samples: u32,
    /// When the renderer was ready and the first batch began (the end of set-up).
    pub rendering_started: Instant,
    /// Why the preview could not be written when the render stopped, if it could not. A
    /// preview that fails never stops the render; failures on the way are logged.
    pub preview_failure: Option<Error>,
}

/// The samples of shard `index` (from 0) of `count` of a render of `spp` samples per pixel:
/// contiguous ranges whose sizes differ by at most one, in order.
pub fn shard_range(index: u32, count: u32, spp: u32) -> Result<Range<u32>> {
    if count == 0 || index >= count {
        return Err(Error::InvalidSettings(format!(
            "shard {index}/{count}: the index must be below the count (from 0)"
        )));
    }
    let boundary = |i: u32| (u64::from(spp) * u64::from(i) / u64::from(count)) as u32;
    Ok(boundary(index)..boundary(index + 1))
}

/// Where a running job stands, after each batch (`run_job`'s progress).
#[derive(Clone, Copy, Debug)]
pub struct JobProgress {
    /// Samples per pixel done so far (of the job's range, resumed ones included).
    pub samples_done: u32,
    /// When the time limit stops the render, if one was set (counted from the end of
    /// set-up, as `JobOptions::time_limit` is).
    pub deadline: Option<Instant>,
    /// Under `--noise-threshold`, the share of the pixels converged so far (0 to 1): they
    /// take no more samples.
    pub converged_share: Option<f64>,
}

/// Runs a render as `options` say. `settings.spp` is ignored: the sample range decides.
/// With `sequence`, one render of a sequence (`Renderer::in_sequence`): it takes what the
/// earlier ones left there and leaves its own for the next.
pub fn run_job(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    options: &JobOptions,
    progress: impl FnMut(JobProgress),
    sequence: Option<&mut SequenceCache>,
) -> Result<JobOutcome> {
    let samples = options.samples.clone();
    let settings = RenderSettings {
        spp: samples.len() as u32,
        ..settings.clone()
    };
    let metadata_of = |taken: Range<u32>| RenderMetadata::new(&settings, scene, camera, taken);
    let mut sequence = sequence;
    let mut renderer = match sequence.as_deref_mut() {
        Some(sequence) => {
            Renderer::in_sequence(context, scene, camera, settings.clone(), sequence)?
        }
        None => Renderer::new(context, scene, camera, settings.clone())?,
    };
    renderer.start_at_sample(samples.start)?;
    let mut resumed_samples = 0;
    if let Some(path) = &options.resume {
        let (state, saved) = read_state(path)?;
        let refuse = |why: String| {
            Error::InvalidSettings(format!("cannot resume from '{}': {why}", path.display()))
        };
        if let Some(difference) = saved.first_difference(&metadata_of(samples.clone())) {
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
        resumed_samples = state.samples.len() as u32;
    }
    // What needs the whole state as the render goes, or at its end.
    let whole_state = options.keep_state
        || options.time_limit.is_some()
        || options.checkpoint.is_some()
        || options.resume.is_some()
        || options.preview.is_some()
        || options.live.is_some();
    if !whole_state {
        renderer.tile_by_tile()?;
    }
    // The samples per pixel of the last checkpoint this run wrote (for a failure's line).
    let checkpointed = std::cell::Cell::new(None);
    let mut write_checkpoint = |state: &Accumulation| -> Result<()> {
        match &options.checkpoint {
            Some(path) => {
                write_state(path, state, &metadata_of(state.samples.clone()))?;
                checkpointed.set(Some(state.samples.len()));
                Ok(())
            }
            None => Ok(()),
        }
    };
    // A preview is a convenience: a failed write is logged (once) and the render goes on.
    let mut preview_warned = false;
    let mut write_preview = |state: &Accumulation| -> Result<()> {
        let image = state.image();
        if let Some(preview) = &options.preview {
            if let Err(error) = save_image(&preview.path, &image, &preview.save) {
                if !std::mem::replace(&mut preview_warned, true) {
                    log::warn!("{error} (the preview; the render goes on)");
                }
            }
        }
        if let Some(live) = &options.live {
            (live.show)(&image);
        }
        Ok(())
    };
    // The preview and the live view share the periodic hook, at the sooner interval.
    let image_interval = [
        options.preview.as_ref().map(|p| p.interval),
        options.live.as_ref().map(|l| l.interval),
    ]
    .into_iter()
    .flatten()
    .min();
    // The driver's first-dispatch compile belongs to set-up, not to the first batch (nor to
    // the time limit, counted from the end of set-up).
    renderer.warm_up()?;
    let deadline = options.time_limit.map(|limit| Instant::now() + limit);
    let control = RenderControl {
        cancel: options.cancel,
        deadline,
        checkpoint: options.checkpoint.as_ref().map(|_| {
            (
                options.checkpoint_interval,
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
    let mut progress = progress;
    let converged = renderer.converged_pixels();
    let pixels = f64::from(settings.area().width()) * f64::from(settings.area().height());
    let adaptive = settings.noise_threshold.is_some();
    let progress = |samples: u32| {
        if let Some(started) = options.started {
            started.store(true, Ordering::SeqCst);
        }
        progress(JobProgress {
            samples_done: samples,
            deadline,
            converged_share: adaptive
                .then(|| converged.load(Ordering::SeqCst) as f64 / pixels.max(1.0)),
        });
    };
    let rendering_started = Instant::now();
    let outcome = renderer.render_with(progress, control).map_err(|error| {
        say_what_a_lost_render_kept(error, options, checkpointed.get(), resumed_samples)
    })?;
    // A stop before this run's first sample has nothing new: it writes nothing, so that an
    // existing checkpoint or preview stays as it was.
    let took_samples = !stopped_before_first_sample(&outcome, resumed_samples);
    let preview_failure = options
        .preview
        .as_ref()
        .filter(|_| took_samples)
        .and_then(|preview| save_image(&preview.path, &outcome.image, &preview.save).err())
        .map(Error::from);
    // Every other stop writes the checkpoint, so that nothing rendered is lost.
    if let (Some(path), true, Some(state)) = (&options.checkpoint, took_samples, &outcome.state) {
        write_state(path, state, &metadata_of(state.samples.clone()))?;
    }
    if let Some(sequence) = sequence {
        renderer.keep_for_next(sequence);
    }
    let taken = samples.start..samples.start + outcome.samples;
    Ok(JobOutcome {
        metadata: metadata_of(taken),
        outcome,
        resumed_samples,
        rendering_started,
        preview_failure,
    })
}

/// Completes the error of a render whose device failed and could not give back what it
/// held (`Error::RenderLost`) with what is left of it: the last checkpoint this run wrote
/// (and the `--resume` that goes on from it), the resumed checkpoint, or nothing.
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
        (None, None, None) => "; without --checkpoint nothing of it is kept".to_string(),
    };
    Error::RenderLost {
        samples,
        error,
        kept,
    }
}

/// Whether a render stopped (by a signal, a time limit or a failure) before taking any
/// sample beyond the `resumed` ones: then it has nothing to write. A resumed render that was
/// already complete is done, not stopped.
pub fn stopped_before_first_sample(outcome: &RenderOutcome, resumed: u32) -> bool {
    outcome.stop != StopReason::Done && outcome.samples <= resumed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_tile_the_samples() {
        let ranges: Vec<Range<u32>> = (0..4).map(|i| shard_range(i, 4, 10).unwrap()).collect();
        assert_eq!(ranges, [0..2, 2..5, 5..7, 7..10]);
        assert_eq!(shard_range(0, 1, 64).unwrap(), 0..64);
        assert!(shard_range(4, 4, 10).is_err());
        assert!(shard_range(0, 0, 10).is_err());
        assert_eq!(shard_range(2, 3, u32::MAX).unwrap().end, u32::MAX);
    }
}
