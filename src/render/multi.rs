//! One image on several devices at once (`--device all`, `--device 0,1`): each device takes
//! an equal contiguous share of the sample range, in its own thread with its own renderer,
//! and the shares are merged as shards are (`Accumulation::merge`: within 4 ulps of one
//! render). A device listed twice is two renderers on it (that is how the tests run it on
//! lavapipe). Each device takes an equal share, so a faster device finishes first: balancing
//! by speed is left for later. In a sequence (`render --frames ... --device all`) each device
//! keeps its own `SequenceCache`: pipelines, images and scene uploads belong to one device,
//! so a frame takes from each device's cache what that device's renderer left there.

use std::ops::Range;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::render::accumulation::Accumulation;
use crate::render::gpu_scene::SceneMemory;
use crate::render::job::{run_job, shard_range, JobOptions, DEFAULT_CHECKPOINT_INTERVAL};
use crate::render::renderer::{GuideReport, StopReason};
use crate::render::sequence::SequenceCache;
use crate::render::settings::RenderSettings;
use crate::scene::Scene;
use crate::vk::Context;

/// What a render on several devices did.
pub struct MultiOutcome {
    /// The merged state of every device's share.
    pub state: Accumulation,
    /// Each device's name and the samples per pixel it took.
    pub shares: Vec<(String, u32)>,
    /// Seconds from start to the last device's end.
    pub seconds: f64,
    /// When the first device began rendering (the end of its set-up).
    pub rendering_started: Instant,
    /// Why it stopped: `Done` only when every device finished its share.
    pub stop: StopReason,
    /// What training the first device's guide did (`--guiding`; each device trains its
    /// own, the same on devices of one kind).
    pub guide: Option<GuideReport>,
    /// What the scene takes on the first device (the same on every device).
    pub scene_memory: Option<SceneMemory>,
}

/// Renders `samples` of `scene` on every context at once and merges the shares. A time
/// limit or the cancel flag stops every device; the merged state then holds what each took
/// (the shares' ranges then leave gaps, so the state is returned only when all finished or
/// the stop is reported with the samples each took). `rendering` is set when the first
/// device begins rendering (as `JobOptions::started`). `sequences` holds what a sequence's
/// earlier renders left on each device, one cache per context in their order (`run_job`'s
/// `sequence`); an empty slice (a still) keeps nothing, and a context past its end renders
/// without a cache.
#[allow(clippy::too_many_arguments)]
pub fn run_on_devices(
    contexts: &[Arc<Context>],
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    samples: Range<u32>,
    time_limit: Option<Duration>,
    cancel: Option<&AtomicBool>,
    rendering: Option<&AtomicBool>,
    sequences: &mut [SequenceCache],
) -> Result<MultiOutcome> {
    let count = contexts.len() as u32;
    if count == 0 {
        return Err(Error::InvalidSettings("no device to render on".into()));
    }
    let started = Instant::now();
    let (first, total) = (samples.start, samples.len() as u32);
    type DeviceResult = (
        Accumulation,
        StopReason,
        Option<Error>,
        Instant,
        Option<GuideReport>,
        SceneMemory,
    );
    // Each device's thread borrows its own cache, none where there are fewer.
    let mut caches: Vec<Option<&mut SequenceCache>> = sequences.iter_mut().map(Some).collect();
    caches.resize_with(contexts.len(), || None);
    let results: Vec<Result<DeviceResult>> = std::thread::scope(|scope| {
        let handles: Vec<_> = contexts
            .iter()
            .zip(caches)
            .enumerate()
            .map(|(index, (context, cache))| {
                scope.spawn(move || -> Result<DeviceResult> {
                    let share = shard_range(index as u32, count, total)?;
                    let job = JobOptions {
                        samples: first + share.start..first + share.end,
                        time_limit,
                        cancel,
                        checkpoint: None,
                        checkpoint_interval: DEFAULT_CHECKPOINT_INTERVAL,
                        resume: None,
                        preview: None,
                        started: rendering,
                        live: None,
                        keep_state: true,
                    };
                    let job = run_job(context, scene, camera, settings, &job, |_| (), cache)?;
                    let outcome = job.outcome;
                    let state = outcome.state.ok_or_else(|| {
                        Error::InvalidSettings("a device's share kept no state to merge".into())
                    })?;
                    Ok((
                        state,
                        outcome.stop,
                        outcome.failure,
                        job.rendering_started,
                        outcome.guide,
                        outcome.scene_memory,
                    ))
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|handle| {
                handle.join().unwrap_or_else(|_| {
                    Err(Error::InvalidSettings(
                        "a device's render thread panicked".into(),
                    ))
                })
            })
            .collect()
    });
    let mut states = Vec::new();
    let mut shares = Vec::new();
    let mut stop = StopReason::Done;
    let mut rendering_started = Instant::now();
    let mut guide = None;
    let mut scene_memory = None;
    for (context, result) in contexts.iter().zip(results) {
        let (state, device_stop, failure, device_started, device_guide, device_memory) = result?;
        guide = guide.or(device_guide);
        scene_memory = scene_memory.or(Some(device_memory));
        rendering_started = rendering_started.min(device_started);
        if let Some(error) = failure {
            return Err(Error::InvalidSettings(format!(
                "device '{}' failed after {} samples: {error}",
                context.info.name,
                state.samples.len()
            )));
        }
        if device_stop != StopReason::Done {
            stop = device_stop;
        }
        shares.push((context.info.name.clone(), state.samples.len() as u32));
        states.push(state);
    }
    let state = if stop == StopReason::Done {
        Accumulation::merge(&states).map_err(|e| Error::InvalidSettings(e.to_string()))?
    } else {
        // Stopped early: the shares end before their ranges do; their sum is still an
        // unbiased image of the samples taken (each pixel's count says how many).
        let parts: Vec<&Accumulation> = states.iter().collect();
        Accumulation::sum(
            &parts,
            first..first + shares.iter().map(|s| s.1).sum::<u32>(),
        )
    };
    Ok(MultiOutcome {
        state,
        shares,
        seconds: started.elapsed().as_secs_f64(),
        rendering_started,
        stop,
        guide,
        scene_memory,
    })
}
