//! A production render's options and outcome: a range of every pixel's sample sequence (all
//! of it, or a shard), a time limit, a cancel flag (signals), periodic checkpoints and
//! resuming from one, bit for bit, and a periodic tone-mapped preview. `RenderSession`
//! (`session.rs`) runs them; the command line only parses these and prints what happened.

use std::ops::Range;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::image_io::output::SaveOptions;
use crate::render::metadata::RenderMetadata;
use crate::render::post_process::PostProcess;
use crate::render::renderer::{RenderOutcome, StopReason};
use crate::render::sequence::SequenceCache;
use crate::render::session::RenderSession;
use crate::render::settings::{Integrator, RenderSettings, SamplerKind};
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
    /// What the render took from the renders before it in its sequence instead of building
    /// it (`ReuseCounts::since`: `kernel`, `accumulation`, `scene`, ...); `None` outside a
    /// sequence.
    pub reused: Option<Vec<&'static str>>,
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

/// Runs a render as `options` say: a `RenderSession` of `options` (a shorthand kept for
/// callers that need no post-processing). `settings.spp` is ignored: the sample range
/// decides. With `sequence`, one render of a sequence (`Renderer::in_sequence`): it takes
/// what the earlier ones left there and leaves its own for the next.
pub fn run_job(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    options: &JobOptions,
    progress: impl FnMut(JobProgress),
    sequence: Option<&mut SequenceCache>,
) -> Result<JobOutcome> {
    RenderSession {
        context,
        scene,
        camera,
        settings,
        job: options.clone(),
        post: PostProcess::default(),
        sequence,
    }
    .run(progress)
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
