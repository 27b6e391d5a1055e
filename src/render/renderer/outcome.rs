//! What a render reports and what may stop it: why it stopped (`StopReason`), its controls
//! (`RenderControl`: a cancel flag, a deadline, periodic checkpoints and previews) and its
//! outcome (`RenderOutcome`).

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::render::accumulation::Accumulation;
use crate::render::gpu_scene::SceneMemory;

use super::GuideReport;

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
