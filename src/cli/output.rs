//! The end of a render command: render with a progress bar (or quietly), stop on a signal or
//! a time limit, save the image with its metadata (into the temp directory when the output
//! cannot be written), print the summary line (or one JSON object), and fail when the
//! validation layer complained.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use super::signals;
use super::summary::{RenderProgress, SequencePosition};
use super::tev::TevView;
use crate::camera::Camera;
use crate::error::Error;
use crate::image_io::output::SaveOptions;
use crate::render::accumulation::Accumulation;
use crate::render::gpu_scene::SceneMemory;
use crate::render::job::{JobOptions, LiveImage};
use crate::render::metadata::{RenderMetadata, RenderOutcome};
use crate::render::multi::run_on_devices;
use crate::render::renderer::GuideReport;
use crate::render::sequence::{ReuseCounts, SequenceCache};
use crate::render::session::RenderSession;
use crate::render::settings::RenderSettings;
use crate::render::StopReason;
use crate::scene::Scene;
use crate::vk::Context;
use crate::RenderedImage;
use files::{save_outputs, write_camera_data, written_outputs};
use lines::{
    end_after_report, print_summary, refuse_when_nothing_was_taken, warn_about_non_finite_pixels,
};
use report::{object_report, render_report, RunCounts, WrittenFiles};

mod files;
mod lines;
mod report;

pub use crate::render::post_process::PostProcess;
pub use files::{id_names_path, partial_path, save_or_rescue, DENOISED_LINE};
pub use lines::fail_on_validation_messages;
pub use report::{
    CameraReport, DeviceReport, GuideSummary, RenderFailure, RenderReport, ReportPrinted,
    RENDER_REPORT_SCHEMA_VERSION,
};

/// How a command reports.
#[derive(Clone, Copy, Debug, Default)]
pub struct Reporting {
    /// One JSON object on stdout at the end instead of the summary line.
    pub json: bool,
    /// No device line, progress bar, summary or `wrote` lines (warnings and errors still
    /// print).
    pub quiet: bool,
}

impl Reporting {
    /// Whether the human-readable lines (device, `wrote`, summary) are printed.
    pub fn talks(self) -> bool {
        !self.json && !self.quiet
    }
}

/// What a render command asks for, besides the device(s): the scene, how to render it, the
/// job's controls, where the image goes and how the command reports.
pub struct RenderRequest<'a> {
    /// The scene as loaded.
    pub scene: &'a Scene,
    /// How the command line named it (`SceneArgs::name`), for the JSON report.
    pub scene_name: String,
    /// The camera.
    pub camera: &'a Camera,
    /// The render settings (`spp` is the job's sample range's length).
    pub settings: &'a RenderSettings,
    /// Sample range, time limit, checkpoints, resuming, preview.
    pub job: JobOptions<'a>,
    /// The images to write, each in the format its extension names, all from one render.
    pub outputs: &'a [PathBuf],
    /// How they are written.
    pub save: SaveOptions,
    /// How the command reports.
    pub reporting: Reporting,
    /// Whether the outputs hold the render state (a shard, for `vkpath merge`).
    pub shard: bool,
    /// What happens to the finished image before it is saved.
    pub post: PostProcess,
    /// Whether to write the frame's camera (`crate::camera_data::CameraData`) beside each
    /// output as `NAME.json` (`--camera-data`).
    pub camera_data: bool,
    /// When the command began: set-up time (loading, device, kernels) counts from here.
    pub command_started: Instant,
    /// The frame and time rendered, when the command line gave `--time` or `--frames`.
    pub frame: Option<super::frames::FrameTime>,
    /// Where the frame stands in a sequence of several frames (the progress bar's and the
    /// summary's frame counter, the sequence's time left); `None` for one image.
    pub position: Option<SequencePosition>,
    /// Where a live view goes (`--tev HOST:PORT`) and how often, if anywhere.
    pub tev: Option<(String, std::time::Duration)>,
    /// What the frames of a sequence keep for the next: one cache per device, in the order
    /// of the devices (empty: a still, which keeps nothing).
    pub sequences: &'a mut [SequenceCache],
}

/// A finished render of one device or several, before it is saved.
struct Finished {
    /// The image.
    image: RenderedImage,
    /// The render state, kept for a shard only (its outputs hold it).
    state: Option<Accumulation>,
    /// Whether the render finished its tiles one at a time (it kept no state): stopped
    /// early, it holds no sample of the tiles it did not reach.
    tile_by_tile: bool,
    /// What the outputs hold.
    metadata: RenderMetadata,
    stop: StopReason,
    /// A failure after some samples were taken (they are saved all the same).
    failure: Option<String>,
    resumed_samples: u32,
    rendering_started: Instant,
    render_seconds: f64,
    devices: Vec<DeviceReport>,
    /// What training the guide did (`--guiding`; the first device's).
    guide: Option<GuideReport>,
    /// What the scene takes on the (first) device.
    scene_memory: Option<SceneMemory>,
    /// Why the final preview could not be written, if it could not.
    preview_failure: Option<String>,
    /// What the render took from the frames before it (a sequence on one device).
    reused: Option<Vec<&'static str>>,
}

/// Renders all samples with a progress bar, saves the image and prints the summary line
/// (neither with `reporting.quiet`). A signal stops it early and saves the samples taken so
/// far.
pub fn render_and_save(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: RenderSettings,
    output: &Path,
    save: &SaveOptions,
    reporting: Reporting,
) -> anyhow::Result<()> {
    let outputs = [output.to_path_buf()];
    render_job_and_save(
        context,
        RenderRequest {
            scene,
            scene_name: "builtin:cornell-box".into(),
            camera,
            settings: &settings,
            job: JobOptions {
                samples: 0..settings.spp,
                ..JobOptions::default()
            },
            outputs: &outputs,
            save: *save,
            reporting,
            shard: false,
            post: PostProcess::default(),
            camera_data: false,
            command_started: Instant::now(),
            frame: None,
            position: None,
            tev: None,
            sequences: &mut [],
        },
    )
}

/// Runs a production render (`request.job`) on one device and saves it; a shard writes the
/// render state into the EXRs too (for `vkpath merge`). A stop before the first sample
/// writes nothing. Exits with 128 + the signal's number when a signal stopped it, after
/// everything is written.
pub fn render_job_and_save(context: &Arc<Context>, request: RenderRequest) -> anyhow::Result<()> {
    install_signals(&request)?;
    let mut job = request.job.clone();
    job.cancel = Some(&signals::STOP_REQUESTED);
    job.started = Some(&signals::RENDERING);
    let total = job.samples.len() as u32;
    let tev = connect_tev(&request);
    let show = |image: &RenderedImage| {
        if let Some(view) = &tev {
            view.show(image);
        }
    };
    if let (Some(_), Some((_, interval))) = (&tev, &request.tev) {
        job.live = Some(LiveImage {
            interval: *interval,
            show: &show,
        });
    }
    let mut progress = request.reporting.talks().then(|| {
        RenderProgress::new(total, request.settings.noise_threshold.is_some())
            .in_sequence(request.position.clone())
    });
    let mut session = RenderSession {
        job,
        post: request.post.clone(),
        sequence: request.sequences.first_mut(),
        ..RenderSession::new(context, request.scene, request.camera, request.settings)
    };
    let outcome = session
        .run(|done| {
            if let Some(progress) = progress.as_mut() {
                progress.update(done.samples_done, done.deadline, done.converged_share);
            }
        })
        .map_err(say_nothing_was_kept)?;
    if let Some(progress) = progress {
        progress.finish();
    }
    let result = outcome.outcome;
    let new_samples = result.samples - outcome.resumed_samples;
    let finished = Finished {
        metadata: outcome.metadata,
        stop: result.stop,
        failure: result.failure.map(|e| e.to_string()),
        resumed_samples: outcome.resumed_samples,
        rendering_started: outcome.rendering_started,
        render_seconds: result.seconds,
        devices: vec![DeviceReport::new(context, new_samples)],
        preview_failure: outcome.preview_failure.map(|e| e.to_string()),
        guide: result.guide,
        scene_memory: Some(result.scene_memory),
        reused: outcome
            .reused
            .filter(|_| request.frame.is_some_and(|f| f.frame.is_some())),
        image: result.image,
        tile_by_tile: result.state.is_none(),
        state: result.state.filter(|_| request.shard),
    };
    drop(session);
    finish(&request, std::slice::from_ref(context), finished, tev)
}

/// Completes the error of a render whose device failed and could not give back what it held
/// (`Error::RenderLost`), where the session said nothing of what was kept (no checkpoint was
/// asked for, nor resumed from): nothing of it is.
fn say_nothing_was_kept(error: Error) -> Error {
    match error {
        Error::RenderLost {
            samples,
            error,
            kept,
        } if kept.is_empty() => Error::RenderLost {
            samples,
            error,
            kept: "; without --checkpoint nothing of it is kept".to_string(),
        },
        other => other,
    }
}

/// Connects the live view the request asks for (`--tev`), named after its first output; a
/// tev that cannot be reached is a warning, and the render goes on without it.
fn connect_tev(request: &RenderRequest) -> Option<TevView> {
    let (address, _) = request.tev.as_ref()?;
    let area = request.settings.area();
    let name = request
        .outputs
        .first()
        .map(|o| o.display().to_string())
        .unwrap_or_else(|| "vkpath".into());
    match TevView::connect(address, &name, area.width(), area.height()) {
        Ok(view) => Some(view),
        Err(warning) => {
            eprintln!("vkpath: warning: {warning}");
            None
        }
    }
}

/// `render_job_and_save` on several devices at once (each an equal share; no checkpoints,
/// previews or post-processing). The summary gives each device's share.
pub fn render_on_devices_and_save(
    contexts: &[Arc<Context>],
    request: RenderRequest,
) -> anyhow::Result<()> {
    install_signals(&request)?;
    let before: Vec<ReuseCounts> = request.sequences.iter().map(|s| s.reused).collect();
    let outcome = run_on_devices(
        contexts,
        request.scene,
        request.camera,
        request.settings,
        request.job.samples.clone(),
        request.job.time_limit,
        Some(&signals::STOP_REQUESTED),
        Some(&signals::RENDERING),
        &mut *request.sequences,
    )
    .map_err(say_nothing_was_kept)?;
    let job = &request.job;
    // What every device took from the frames before it.
    let reused = (!before.is_empty()).then(|| {
        let each: Vec<Vec<&'static str>> = request
            .sequences
            .iter()
            .zip(&before)
            .map(|(sequence, before)| sequence.reused.since(*before))
            .collect();
        each[0]
            .iter()
            .copied()
            .filter(|part| each.iter().all(|parts| parts.contains(part)))
            .collect::<Vec<_>>()
    });
    let render_seconds = outcome.rendering_started.elapsed().as_secs_f64();
    let spp_settings = RenderSettings {
        spp: job.samples.len() as u32,
        ..request.settings.clone()
    };
    let metadata = RenderMetadata::new(
        &spp_settings,
        request.scene,
        request.camera,
        outcome.state.samples.clone(),
    );
    let devices = contexts
        .iter()
        .zip(&outcome.shares)
        .map(|(context, (_, spp))| DeviceReport::new(context, *spp))
        .collect();
    let finished = Finished {
        image: outcome.state.image(),
        state: request.shard.then_some(outcome.state),
        tile_by_tile: false,
        metadata,
        stop: outcome.stop,
        failure: None,
        resumed_samples: 0,
        rendering_started: outcome.rendering_started,
        render_seconds,
        devices,
        guide: outcome.guide,
        scene_memory: outcome.scene_memory,
        preview_failure: None,
        reused: reused.filter(|_| request.frame.is_some_and(|f| f.frame.is_some())),
    };
    finish(&request, contexts, finished, None)
}

/// Installs the signal handlers, naming the request's outputs for a stop before the first
/// sample.
fn install_signals(request: &RenderRequest) -> anyhow::Result<()> {
    let mut files: Vec<&Path> = request.outputs.iter().map(PathBuf::as_path).collect();
    files.extend(request.job.checkpoint.as_deref());
    files.extend(request.job.preview.as_ref().map(|p| p.path.as_path()));
    signals::install(&files)
}

/// Saves a finished render to every output, reports it and ends the command as its stop
/// says.
fn finish(
    request: &RenderRequest,
    contexts: &[Arc<Context>],
    mut finished: Finished,
    tev: Option<TevView>,
) -> anyhow::Result<()> {
    refuse_when_nothing_was_taken(&finished)?;
    finished.metadata.outcome = Some(RenderOutcome {
        spp_requested: request.job.samples.len() as u32,
        stop: finished.stop.name().to_string(),
    });
    if let Some(frame) = request.frame {
        finished.metadata.set_frame(frame.frame, frame.time);
    }
    let outputs = written_outputs(request.outputs, finished.stop);
    let image = std::mem::replace(&mut finished.image, RenderedImage::empty(0, 0));
    warn_about_non_finite_pixels(&image);
    let processed = save_outputs(request, &outputs, contexts, &finished, &image)?;
    if request.camera_data {
        write_camera_data(request, &outputs)?;
    }
    if let Some(view) = tev {
        let (shown, layers) = match &processed {
            Some((processed, layers)) => (processed, layers.as_slice()),
            None => (&image, &[][..]),
        };
        if let Some(warning) = view.finish(shown, layers) {
            eprintln!("vkpath: warning: {warning}");
        }
    }
    if let Some(error) = &finished.preview_failure {
        eprintln!("vkpath: warning: {error} (the preview)");
    }
    let files = WrittenFiles {
        outputs: &outputs,
        checkpoint: request.job.checkpoint.as_ref(),
        preview: request
            .job
            .preview
            .as_ref()
            .filter(|_| finished.preview_failure.is_none())
            .map(|p| &p.path),
    };
    let counts = RunCounts::of(request, &finished, &image);
    if request.reporting.talks() {
        print_summary(request, contexts, &finished, &files, &counts);
    }
    if request.reporting.json {
        let mut report = render_report(request, &mut finished, &files, &counts);
        if let Some((objects, visible)) = processed
            .as_ref()
            .and_then(|(image, layers)| object_report(request, image.width, layers))
        {
            report.objects = Some(objects);
            report.visible_fraction = Some(visible);
        }
        println!("{}", serde_json::to_string(&report)?);
    }
    end_after_report(request, &outputs, contexts, &finished, files.checkpoint).map_err(|error| {
        if request.reporting.json {
            ReportPrinted(error).into()
        } else {
            error
        }
    })
}
