//! The end of a render command: render with a progress bar (or quietly), stop on a signal or
//! a time limit, save the image with its metadata (into the temp directory when the output
//! cannot be written), print the summary line (or one JSON object), and fail when the
//! validation layer complained.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::bail;
use serde::Serialize;

use super::signals;
use super::summary::{summary_line, RenderProgress, SequencePosition, Summary};
use super::tev::TevView;
use crate::camera::Camera;
use crate::image_io::output::{
    save_image_with_attributes, save_image_with_layers, ImageLayer, SaveOptions,
};
use crate::render::accumulation::Accumulation;
use crate::render::aov::{render_aov, Aov};
use crate::render::gpu_scene::SceneMemory;
use crate::render::job::{run_job, JobOptions, LiveImage};
use crate::render::metadata::{
    sampler_name, RenderMetadata, RenderOutcome, AOV_FIELD, DENOISER_NAME, DENOISE_FIELD,
};
use crate::render::multi::run_on_devices;
use crate::render::renderer::GuideReport;
use crate::render::sequence::{ReuseCounts, SequenceCache};
use crate::render::settings::{RenderSettings, SamplerKind};
use crate::render::state_exr::write_state;
use crate::render::StopReason;
use crate::scene::Scene;
use crate::vk::{Context, DeviceInfo};
use crate::RenderedImage;

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

/// The version of `RenderReport`'s schema: it changes only when a key is removed or changes
/// meaning (added keys keep it).
pub const RENDER_REPORT_SCHEMA_VERSION: u32 = 1;

/// The JSON object `render --json` prints on stdout, the same whatever the devices (the
/// README documents every key).
#[derive(Serialize)]
pub struct RenderReport {
    /// `RENDER_REPORT_SCHEMA_VERSION`.
    pub schema_version: u32,
    /// The files written, in the order given by `-o`.
    pub outputs: Vec<String>,
    /// The scene: its file, `builtin:cornell-box` or `generated:N`.
    pub scene: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The command-line name of the integrator.
    pub integrator: &'static str,
    /// The sampler the integrator used (`pcg` for the workshop's, which has no other).
    pub sampler: &'static str,
    /// Samples per pixel asked for (the sample range's length).
    pub spp_requested: u32,
    /// Samples per pixel the outputs hold (resumed ones included).
    pub spp_taken: u32,
    /// The samples of every pixel's sequence the outputs hold, [start, end).
    pub sample_range: [u32; 2],
    /// Of `spp_taken`, those that came from `--resume`'s checkpoint.
    pub resumed_spp: u32,
    /// Seconds from the command's start to the first sample: loading the scene, opening the
    /// device(s), building the kernels, uploading.
    pub setup_seconds: f64,
    /// Seconds of rendering, from the first sample to the last.
    pub render_seconds: f64,
    /// Samples (pixels x spp) this run took per second of rendering: resumed samples do not
    /// count.
    pub samples_per_second: f64,
    /// Every device, with the samples per pixel it took in this run.
    pub devices: Vec<DeviceReport>,
    /// Why the render stopped: `done`, `time-limit`, `signal` or `failed`.
    pub stop: &'static str,
    /// The checkpoint written, if any.
    pub checkpoint: Option<String>,
    /// The preview written, if any.
    pub preview: Option<String>,
    /// The part of the image rendered, [x0, y0, x1, y1] (`--region`), or `null`: all of it.
    pub region: Option<[u32; 4]>,
    /// `--noise-threshold`, or `null`.
    pub noise_threshold: Option<f32>,
    /// The mean over the pixels of the samples each holds: `spp_taken` unless
    /// `--noise-threshold` stopped some pixels early.
    pub spp_mean: f64,
    /// How nee and mis chose their lights: `power` or `tree` (`--light-selection`, `auto`
    /// resolved for the scene).
    pub light_selection: &'static str,
    /// What training the guide did (`--guiding`), or `null`.
    pub guide: Option<GuideSummary>,
    /// What found the hits: `hardware` (the device's ray queries), `bvh` or `none` (the
    /// loop over all triangles); `null` when the render stopped before its renderer was made.
    pub accel: Option<&'static str>,
    /// What the scene takes on the device: the acceleration structure's bytes (BVH nodes and
    /// traversal triangles, or the device's structures) and every buffer's, in all and per
    /// triangle (`null` when the render stopped before its renderer was made).
    pub scene_memory: Option<SceneMemory>,
    /// The camera that saw the image (world space): `position` (the pinhole),
    /// `image_plane_middle`, `up` and `right_per_unit_aspect` (the image plane's edges), so
    /// that a script can tell that the frames of a sequence share one view.
    pub camera: CameraReport,
    /// The frame number (`--frames`); absent for a still, `null` with `--time`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frame: Option<Option<u32>>,
    /// The scene time in seconds (`--time`, or frame / `--fps`); absent without either.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// What a frame of `--frames` took from the frames before it instead of building it:
    /// `kernel` (the path tracer's pipeline), `accumulation` (the image and its buffers),
    /// `scene` (the upload, when the scene's data did not change), or where the scene moved
    /// the parts of its upload that did not: `materials` (material words and texture
    /// texels), `environment`, `punctual_lights`; absent without `--frames`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reused: Option<Vec<&'static str>>,
}

/// A camera as `render --json` reports it: `Camera`'s vectors as `[x, y, z]`.
#[derive(Serialize)]
pub struct CameraReport {
    /// The pinhole.
    pub position: [f32; 3],
    /// The centre of the image plane.
    pub image_plane_middle: [f32; 3],
    /// The image plane's full-height edge vector, pointing up in the image.
    pub up: [f32; 3],
    /// The image plane's full-width edge vector for an aspect ratio of 1.
    pub right_per_unit_aspect: [f32; 3],
}

impl CameraReport {
    /// The report of `camera`.
    pub fn of(camera: &Camera) -> CameraReport {
        CameraReport {
            position: camera.position.to_array(),
            image_plane_middle: camera.image_plane_middle.to_array(),
            up: camera.up.to_array(),
            right_per_unit_aspect: camera.right_per_unit_aspect.to_array(),
        }
    }
}

/// The JSON object `render --json` prints on stdout when it fails before its report: the
/// schema version, `stop` as `failed` and the error line, so that a script reading stdout
/// always gets one object (the exit status is still non-zero).
#[derive(Serialize)]
pub struct RenderFailure {
    /// `RENDER_REPORT_SCHEMA_VERSION`.
    pub schema_version: u32,
    /// Always `failed`.
    pub stop: &'static str,
    /// The error, as the line on stderr says it (without `vkpath: error: `).
    pub error: String,
}

impl RenderFailure {
    /// The report of a render that failed with `error`.
    pub fn new(error: &anyhow::Error) -> RenderFailure {
        RenderFailure {
            schema_version: RENDER_REPORT_SCHEMA_VERSION,
            stop: crate::render::StopReason::Failed.name(),
            error: format!("{error:#}"),
        }
    }
}

/// An error after `render --json` printed its report (which says how the render stopped),
/// so that no second JSON object follows it. Displays as the error it wraps.
#[derive(Debug, thiserror::Error)]
#[error("{0:#}")]
pub struct ReportPrinted(pub anyhow::Error);

/// `--guiding`'s guide in a `RenderReport`.
#[derive(Serialize)]
pub struct GuideSummary {
    /// Positions of its grid along x, y and z.
    pub grid: [u32; 3],
    /// Cells in all: one per grid position and orientation that a surface there can face.
    pub cells: u32,
    /// Cells that training taught.
    pub guided_cells: u32,
    /// Bytes it takes on the device.
    pub memory_bytes: usize,
    /// Samples per pixel of each training iteration.
    pub training_iterations: Vec<u32>,
    /// Seconds training took (part of `render_seconds`).
    pub training_seconds: f64,
    /// Of those: building the training kernel's pipeline.
    pub training_pipeline_seconds: f64,
    /// Of those: the training frames (submitting them and waiting for the device).
    pub training_frames_seconds: f64,
    /// Of those: the host's side (read-backs, guide builds, uploads, clears).
    pub training_host_seconds: f64,
    /// Whether the guide came frozen in the resumed checkpoint (no training then).
    pub from_checkpoint: bool,
}

impl GuideSummary {
    /// The summary of a render's guide report.
    fn new(report: &GuideReport) -> GuideSummary {
        GuideSummary {
            grid: report.grid_resolution,
            cells: report.cell_count,
            guided_cells: report.guided_cell_count,
            memory_bytes: report.memory_bytes,
            training_iterations: report.iterations.clone(),
            training_seconds: report.seconds(),
            training_pipeline_seconds: report.times.pipeline_seconds,
            training_frames_seconds: report.times.frames_seconds,
            training_host_seconds: report.times.host_seconds,
            from_checkpoint: report.from_checkpoint,
        }
    }

    /// "guide: XxYxZ grid, C cells, G taught, M MB; trained on N spp (1+2+...) in S s
    /// (pipeline P s, frames F s, host H s)" (or "from the checkpoint").
    fn line(&self) -> String {
        let [x, y, z] = self.grid;
        if self.from_checkpoint {
            return format!(
                "guide: {x}x{y}x{z} grid, {} cells, {} taught, {:.2} MB; from the checkpoint",
                self.cells,
                self.guided_cells,
                self.memory_bytes as f64 / 1e6
            );
        }
        let total: u32 = self.training_iterations.iter().sum();
        let parts: Vec<String> = self
            .training_iterations
            .iter()
            .map(u32::to_string)
            .collect();
        format!(
            "guide: {x}x{y}x{z} grid, {} cells, {} taught, {:.2} MB; trained on {total} spp ({}) \
             in {:.2} s (pipeline {:.2} s, frames {:.2} s, host {:.2} s)",
            self.cells,
            self.guided_cells,
            self.memory_bytes as f64 / 1e6,
            parts.join("+"),
            self.training_seconds,
            self.training_pipeline_seconds,
            self.training_frames_seconds,
            self.training_host_seconds
        )
    }
}

/// One device of a `RenderReport`.
#[derive(Serialize)]
pub struct DeviceReport {
    /// Its index, as `vkpath devices` lists it.
    pub index: usize,
    /// The driver's name for it.
    pub name: String,
    /// `discrete-gpu`, `integrated-gpu`, `virtual-gpu`, `cpu` or `other`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// Its UUID, `GPU-xxxxxxxx-...` (`vkpath devices`).
    pub uuid: String,
    /// Why it was chosen (`--device 1`, `CUDA_VISIBLE_DEVICES=GPU-...`, `default: ...`).
    pub chosen_because: String,
    /// Samples per pixel it took in this run.
    pub spp: u32,
}

impl DeviceReport {
    /// The report of `context`'s device, which took `spp` samples per pixel.
    fn new(context: &Context, spp: u32) -> DeviceReport {
        let device = &context.info;
        DeviceReport {
            uuid: crate::vk::format_uuid(&device.uuid),
            chosen_because: context.chosen_because.clone(),
            index: device.index,
            name: device.name.clone(),
            kind: device.kind.report_name(),
            spp,
        }
    }
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
            command_started: Instant::now(),
            frame: None,
            position: None,
            tev: None,
            sequences: &mut [],
        },
    )
}

/// What `render --denoise` says it did (after "vkpath: ", unless quiet): the filter
/// `PostProcess::apply` runs and where the original went.
pub const DENOISED_LINE: &str = "denoised with Intel Open Image Denoise's RT filter (HDR, \
     guided by the albedo and normal); an EXR keeps the noisy image in its `noisy` layer";

/// What happens to a finished render before it is saved: outputs beside the colour
/// (`--aov`) and denoising (`--denoise`, which renders the albedo and normal it needs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PostProcess {
    /// The outputs to add as EXR layers.
    pub aovs: Vec<Aov>,
    /// Whether to denoise the colour with Open Image Denoise (the EXR keeps the original in a
    /// `noisy` layer).
    pub denoise: bool,
}

impl PostProcess {
    /// Whether there is anything to do.
    pub fn is_empty(&self) -> bool {
        self.aovs.is_empty() && !self.denoise
    }

    /// Records in `metadata` what this does to an image (`denoise`, `aov`), as the files
    /// it post-processed say.
    pub fn record(&self, metadata: &mut RenderMetadata) {
        if self.denoise {
            metadata.set_image_field(DENOISE_FIELD, DENOISER_NAME.to_string());
        }
        if !self.aovs.is_empty() {
            let names: Vec<&str> = self.aovs.iter().map(|aov| aov.name()).collect();
            metadata.set_image_field(AOV_FIELD, names.join(","));
        }
    }

    /// The image to save and its extra layers.
    fn apply(
        &self,
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: &RenderSettings,
        image: &RenderedImage,
    ) -> anyhow::Result<(RenderedImage, Vec<ImageLayer>)> {
        let mut wanted = self.aovs.clone();
        if self.denoise {
            for aov in [Aov::Albedo, Aov::Normal] {
                if !wanted.contains(&aov) {
                    wanted.push(aov);
                }
            }
        }
        let mut rendered = Vec::new();
        for aov in wanted {
            rendered.push((aov, render_aov(context, scene, camera, settings, aov)?));
        }
        let layer_of = |aov: Aov| rendered.iter().find(|(a, _)| *a == aov).map(|(_, p)| p);
        let mut layers: Vec<ImageLayer> = self
            .aovs
            .iter()
            .filter_map(|&aov| {
                layer_of(aov).map(|pixels| ImageLayer {
                    name: aov.name().to_owned(),
                    pixels: pixels.clone(),
                    single_channel: aov == Aov::Depth,
                })
            })
            .collect();
        let mut result = image.clone();
        if self.denoise {
            let noisy: Vec<[f32; 3]> = image.mean.iter().map(|p| [p[0], p[1], p[2]]).collect();
            let denoised = crate::denoise::denoise(
                &noisy,
                layer_of(Aov::Albedo).map(Vec::as_slice),
                layer_of(Aov::Normal).map(Vec::as_slice),
                image.width,
                image.height,
            )?;
            for (pixel, value) in result.mean.iter_mut().zip(&denoised) {
                pixel[..3].copy_from_slice(value);
            }
            layers.push(ImageLayer {
                name: "noisy".to_owned(),
                pixels: noisy,
                single_channel: false,
            });
        }
        Ok((result, layers))
    }
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
    let before = request.sequences.first().map(|s| s.reused);
    let outcome = run_job(
        context,
        request.scene,
        request.camera,
        request.settings,
        &job,
        |done| {
            if let Some(progress) = progress.as_mut() {
                progress.update(done.samples_done, done.deadline, done.converged_share);
            }
        },
        request.sequences.first_mut(),
    )?;
    let reused = request
        .sequences
        .first()
        .zip(before)
        .map(|(sequence, before)| sequence.reused.since(before));
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
        reused: reused.filter(|_| request.frame.is_some_and(|f| f.frame.is_some())),
        image: result.image,
        tile_by_tile: result.state.is_none(),
        state: result.state.filter(|_| request.shard),
    };
    drop(job);
    finish(&request, std::slice::from_ref(context), finished, tev)
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
    )?;
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

/// The files a render writes its image to: its outputs, or after Ctrl-C (SIGINT) or a
/// device failure their partial siblings (`out.png` -> `out.partial.png`), so that an
/// interrupted or failed render never replaces a finished image, as Mitsuba, pbrt and
/// Blender leave theirs. A time limit and SIGTERM or SIGHUP (a scheduler's stop, which
/// expects the outputs and checkpoint there) write the outputs themselves.
fn written_outputs(outputs: &[PathBuf], stop: StopReason) -> Vec<PathBuf> {
    let interrupted =
        (stop == StopReason::Cancelled && signals::interrupted()) || stop == StopReason::Failed;
    outputs
        .iter()
        .map(|output| match interrupted {
            true => partial_path(output),
            false => output.clone(),
        })
        .collect()
}

/// Where an interrupted render writes what it rendered for `output`: `.partial` before its
/// extension (`out.png` -> `out.partial.png`; `out` -> `out.partial`).
pub fn partial_path(output: &Path) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = match output.extension() {
        Some(extension) => format!("{stem}.partial.{}", extension.to_string_lossy()),
        None => format!("{stem}.partial"),
    };
    output.with_file_name(name)
}

/// Installs the signal handlers, naming the request's outputs for a stop before the first
/// sample.
fn install_signals(request: &RenderRequest) -> anyhow::Result<()> {
    let mut files: Vec<&Path> = request.outputs.iter().map(PathBuf::as_path).collect();
    files.extend(request.job.checkpoint.as_deref());
    files.extend(request.job.preview.as_ref().map(|p| p.path.as_path()));
    signals::install(&files)
}

/// What the line of a render that failed after some samples says it kept, and how to go
/// on: the partial images (the outputs left as they were) and, with a checkpoint, the
/// `--resume` that continues from it; without one, that the next render starts over.
fn what_a_failure_kept(
    request: &RenderRequest,
    outputs: &[PathBuf],
    checkpoint: Option<&PathBuf>,
) -> String {
    let images = format!(
        "the samples taken are in {}{}",
        quoted_paths(outputs),
        left_as_they_were(request, outputs)
    );
    match checkpoint {
        Some(checkpoint) => format!(
            "{images}; add --resume '{}' to go on from its last checkpoint",
            checkpoint.display()
        ),
        None => format!(
            "{images}; without --checkpoint a render cannot resume, so a new one starts over"
        ),
    }
}

/// Paths as the lines name them: `'a.png', 'b.exr'`.
fn quoted_paths(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| format!("'{}'", p.display())).collect();
    names.join(", ")
}

/// What a line adds where a stopped render wrote beside its outputs (`written`, their
/// `.partial` siblings): ` ('out.png' left as it was)` for the outputs that exist, `'out.exr'
/// not written` for those that do not; nothing where it wrote the outputs.
fn left_as_they_were(request: &RenderRequest, written: &[PathBuf]) -> String {
    if written == request.outputs {
        return String::new();
    }
    let (kept, absent): (Vec<PathBuf>, Vec<PathBuf>) =
        request.outputs.iter().cloned().partition(|o| o.exists());
    let mut parts = Vec::new();
    if !kept.is_empty() {
        parts.push(format!("{} left as it was", quoted_paths(&kept)));
    }
    if !absent.is_empty() {
        parts.push(format!("{} not written", quoted_paths(&absent)));
    }
    format!(" ({})", parts.join("; "))
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
        let report = render_report(request, &mut finished, &files, &counts);
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

/// Ends the command, writing nothing, when a render stopped before this run's first sample:
/// a failure or a time limit as an error, a signal as the signal asks.
fn refuse_when_nothing_was_taken(finished: &Finished) -> anyhow::Result<()> {
    let new_samples = finished.metadata.samples.len() as u32 - finished.resumed_samples;
    if finished.stop == StopReason::Done || new_samples > 0 {
        return Ok(());
    }
    if let (true, None, StopReason::Cancelled) =
        (finished.tile_by_tile, &finished.failure, finished.stop)
    {
        let (name, status) = signals::received().unwrap_or(("a signal", 130));
        eprintln!(
            "vkpath: stopped by {name} before the last tile: a render finishing its tiles one \
             at a time has no sample of those it did not reach, so nothing was written \
             (--checkpoint keeps what a stopped render took){}",
            signals::frames_left()
        );
        std::process::exit(status);
    }
    match (&finished.failure, finished.stop) {
        (Some(error), _) => {
            bail!("rendering failed before its first sample, so nothing was written: {error}")
        }
        (None, StopReason::Cancelled) => signals::exit_with_nothing_written(),
        _ => bail!(
            "the render stopped ({}) before its first sample: nothing was written",
            finished.stop.name()
        ),
    }
}

/// Warns once when pixels are NaN or infinite.
fn warn_about_non_finite_pixels(image: &RenderedImage) {
    let non_finite = image
        .mean
        .iter()
        .filter(|p| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()))
        .count();
    if non_finite > 0 {
        eprintln!(
            "vkpath: warning: {non_finite} pixels are not finite (NaN or infinite); the scene's values overflow 32-bit floats"
        );
    }
}

/// The files a finished render wrote, for its report.
struct WrittenFiles<'a> {
    /// The images (the outputs, or after Ctrl-C their `.partial` siblings).
    outputs: &'a [PathBuf],
    /// The checkpoint, if one was asked for.
    checkpoint: Option<&'a PathBuf>,
    /// The preview, if one was asked for and written.
    preview: Option<&'a PathBuf>,
}

/// What this run of a render took, as the summary and the report count it.
struct RunCounts {
    /// From the command's start to the first batch (loading, device, kernels).
    setup_seconds: f64,
    /// Samples this run took: all those held but the resumed ones (`resumed_spp` per pixel,
    /// exact unless an adaptive checkpoint had stopped some pixels before).
    new_samples: f64,
    /// Mean over the pixels of the samples each holds.
    spp_mean: f64,
}

impl RunCounts {
    fn of(request: &RenderRequest, finished: &Finished, image: &RenderedImage) -> RunCounts {
        let area = request.settings.area();
        let pixels = f64::from(area.width()) * f64::from(area.height());
        let samples_held: f64 = image.sample_count.iter().map(|&n| f64::from(n)).sum();
        RunCounts {
            setup_seconds: finished
                .rendering_started
                .saturating_duration_since(request.command_started)
                .as_secs_f64(),
            new_samples: (samples_held - f64::from(finished.resumed_samples) * pixels).max(0.0),
            spp_mean: samples_held / pixels.max(1.0),
        }
    }
}

/// The lines on stderr after a render: resumed from where, the files written, the summary
/// line and the guide's.
fn print_summary(
    request: &RenderRequest,
    contexts: &[Arc<Context>],
    finished: &Finished,
    files: &WrittenFiles,
    counts: &RunCounts,
) {
    let total = request.job.samples.len() as u32;
    let done = finished.metadata.samples.len() as u32;
    if let Some(resumed) = &request.job.resume {
        eprintln!(
            "vkpath: resumed from '{}' at {} of {total} spp; this run took {} more",
            resumed.display(),
            finished.resumed_samples,
            done - finished.resumed_samples
        );
    }
    for output in files.outputs {
        eprintln!("vkpath: wrote {}", output.display());
    }
    if let Some(checkpoint) = files.checkpoint {
        eprintln!("vkpath: wrote {} (checkpoint)", checkpoint.display());
    }
    if let Some(preview) = files.preview {
        eprintln!("vkpath: wrote {} (preview)", preview.display());
    }
    let devices: Vec<(DeviceInfo, u32)> = contexts
        .iter()
        .zip(&finished.devices)
        .map(|(context, report)| (context.info.clone(), report.spp))
        .collect();
    let area = request.settings.area();
    let counter = request
        .position
        .as_ref()
        .map(|p| format!("{}: ", p.counter()))
        .unwrap_or_default();
    eprintln!(
        "{counter}{}",
        summary_line(&Summary {
            devices: &devices,
            width: area.width(),
            height: area.height(),
            spp: done,
            spp_mean: request.settings.noise_threshold.map(|_| counts.spp_mean),
            new_samples: counts.new_samples,
            setup_seconds: counts.setup_seconds,
            seconds: finished.render_seconds,
            traversal: finished.scene_memory.map(|memory| memory.traversal),
        })
    );
    if let Some(guide) = &finished.guide {
        eprintln!("{}", GuideSummary::new(guide).line());
    }
}

/// The object `render --json` prints (the devices' reports are moved out of `finished`).
fn render_report(
    request: &RenderRequest,
    finished: &mut Finished,
    files: &WrittenFiles,
    counts: &RunCounts,
) -> RenderReport {
    let settings = request.settings;
    let effective_sampler = if settings.integrator.is_importance_sampled() {
        settings.sampler
    } else {
        SamplerKind::Pcg
    };
    RenderReport {
        schema_version: RENDER_REPORT_SCHEMA_VERSION,
        outputs: files
            .outputs
            .iter()
            .map(|p| p.display().to_string())
            .collect(),
        scene: request.scene_name.clone(),
        width: settings.width,
        height: settings.height,
        region: settings.region.map(|r| [r.x0, r.y0, r.x1, r.y1]),
        noise_threshold: settings.noise_threshold.map(|n| n.threshold),
        spp_mean: counts.spp_mean,
        integrator: settings.integrator.name(),
        sampler: sampler_name(effective_sampler),
        spp_requested: request.job.samples.len() as u32,
        spp_taken: finished.metadata.samples.len() as u32,
        sample_range: [
            finished.metadata.samples.start,
            finished.metadata.samples.end,
        ],
        resumed_spp: finished.resumed_samples,
        setup_seconds: counts.setup_seconds,
        render_seconds: finished.render_seconds,
        samples_per_second: counts.new_samples / finished.render_seconds.max(1e-9),
        devices: std::mem::take(&mut finished.devices),
        stop: finished.stop.name(),
        checkpoint: files.checkpoint.map(|p| p.display().to_string()),
        preview: files.preview.map(|p| p.display().to_string()),
        light_selection: match finished.metadata.setting("light_selection") {
            Some("tree") => "tree",
            _ => "power",
        },
        guide: finished.guide.as_ref().map(GuideSummary::new),
        accel: finished.scene_memory.map(|memory| memory.accel),
        scene_memory: finished.scene_memory,
        camera: CameraReport::of(request.camera),
        frame: request.frame.map(|f| f.frame),
        time: request.frame.map(|f| f.time),
        reused: finished.reused.take(),
    }
}

/// What `finish` does after the report: fails as the render did, exits as a signal asks,
/// says that the time limit was reached, and fails when the validation layer complained.
fn end_after_report(
    request: &RenderRequest,
    outputs: &[PathBuf],
    contexts: &[Arc<Context>],
    finished: &Finished,
    checkpoint: Option<&PathBuf>,
) -> anyhow::Result<()> {
    let total = request.job.samples.len() as u32;
    let done = finished.metadata.samples.len() as u32;
    if let Some(error) = &finished.failure {
        bail!(
            "rendering stopped after {done} of {total} spp: {error}; {}",
            what_a_failure_kept(request, outputs, checkpoint)
        );
    }
    match finished.stop {
        StopReason::Cancelled => {
            let (name, status) = signals::received().unwrap_or(("a signal", 130));
            let mut saved: Vec<String> = outputs
                .iter()
                .chain(checkpoint)
                .map(|p| format!("'{}'", p.display()))
                .collect();
            let last = saved.pop().unwrap_or_default();
            let saved = match saved.is_empty() {
                true => last,
                false => format!("{} and {last}", saved.join(", ")),
            };
            let kept = left_as_they_were(request, outputs);
            let frames_left = signals::frames_left();
            eprintln!(
                "vkpath: stopped by {name} after {done} of {total} spp; saved to {saved}{kept}{frames_left}"
            );
            std::process::exit(status);
        }
        StopReason::TimeLimit if !request.reporting.quiet && !request.reporting.json => {
            eprintln!("vkpath: time limit reached after {done} of {total} spp");
        }
        _ => {}
    }
    for context in contexts {
        fail_on_validation_messages(context)?;
    }
    Ok(())
}

/// Writes the finished render to every output: the render state for a shard; otherwise the
/// image as rendered, then (for a finished render: every sample taken, or the time limit
/// reached) again after `request.post`, so that nothing is lost if post-processing fails.
fn save_outputs(
    request: &RenderRequest,
    outputs: &[PathBuf],
    contexts: &[Arc<Context>],
    finished: &Finished,
    image: &RenderedImage,
) -> anyhow::Result<Option<(RenderedImage, Vec<ImageLayer>)>> {
    let metadata = &finished.metadata;
    if request.shard {
        let Some(state) = &finished.state else {
            bail!("the shard's render kept no state to write");
        };
        for output in outputs {
            write_state(output, state, metadata)?;
        }
        return Ok(None);
    }
    for output in outputs {
        save_or_rescue(output, image, &request.save, metadata, &[])?;
    }
    if request.post.is_empty() {
        return Ok(None);
    }
    if !finished.stop.is_finished() {
        eprintln!(
            "vkpath: warning: the render stopped early ({}): saved without --aov/--denoise",
            finished.stop.name()
        );
        return Ok(None);
    }
    let Some(context) = contexts.first() else {
        return Ok(None);
    };
    // The layers take the samples the colour took: all of them, or those before the time
    // limit (not the million asked, which would take far longer than the render did).
    let taken = RenderSettings {
        spp: metadata.samples.len() as u32,
        ..request.settings.clone()
    };
    let (processed, layers) =
        request
            .post
            .apply(context, request.scene, request.camera, &taken, image)?;
    let mut metadata = metadata.clone();
    request.post.record(&mut metadata);
    for output in outputs {
        save_or_rescue(output, &processed, &request.save, &metadata, &layers)?;
    }
    if request.post.denoise && request.reporting.talks() {
        eprintln!("vkpath: {}", DENOISED_LINE);
    }
    Ok(Some((processed, layers)))
}

/// Saves `image` to `output` with the render's metadata in its header; when that fails,
/// nothing already rendered is lost: the image (with its moments) goes to the temp directory
/// and the error says where.
pub fn save_or_rescue(
    output: &Path,
    image: &RenderedImage,
    save: &SaveOptions,
    metadata: &RenderMetadata,
    layers: &[ImageLayer],
) -> anyhow::Result<()> {
    let attributes = metadata.attributes_with_counts(&image.sample_count);
    // A region's EXR is placed in the full image; an adaptive render's keeps every pixel's
    // sample count (and the second moments beside it, for `compare`).
    let save = &SaveOptions {
        window: metadata.window(),
        moments: save.moments || metadata.setting("noise_threshold").is_some(),
        ..*save
    };
    let Err(error) = save_image_with_layers(output, image, save, &attributes, layers) else {
        return Ok(());
    };
    let rescue = std::env::temp_dir().join(format!("vkpath-rescue-{}.exr", std::process::id()));
    let rescued = save_image_with_attributes(
        &rescue,
        image,
        &SaveOptions {
            moments: true,
            ..*save
        },
        &attributes,
    );
    match rescued {
        Ok(()) => bail!(
            "{error}; the render was saved to '{}' instead",
            rescue.display()
        ),
        Err(_) => bail!("{error}"),
    }
}

/// Fails, after a command has done its work, when the validation layer (`--validate`)
/// reported any error or warning; they were logged as they came.
pub fn fail_on_validation_messages(context: &Context) -> anyhow::Result<()> {
    if let Some(messages) = context.validation_messages() {
        if messages.total() > 0 {
            bail!(
                "the validation layer reported {} errors and {} warnings (see the log above)",
                messages.errors(),
                messages.warnings()
            );
        }
    }
    Ok(())
}
