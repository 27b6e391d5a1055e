//! `render --json`'s report: the one JSON object a render prints on stdout (`RenderReport`,
//! with its devices, guide and camera), the object of a render that failed before it
//! (`RenderFailure`), and what a run took as the summary line and the report count it.

use std::path::PathBuf;

use serde::Serialize;

use super::{Finished, RenderRequest};
use crate::camera::Camera;
use crate::camera_data::CameraData;
use crate::image_io::output::ImageLayer;
use crate::render::aov::Aov;
use crate::render::gpu_scene::SceneMemory;
use crate::render::ground_truth::{object_summaries, IdNames, ObjectSummary};
use crate::render::metadata::sampler_name;
use crate::render::renderer::GuideReport;
use crate::render::settings::SamplerKind;
use crate::vk::Context;
use crate::RenderedImage;

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
    /// The same camera as datasets take it (`crate::camera_data::CameraData`): `k` (pixels,
    /// OpenCV), `camera_to_world_opencv`, `camera_to_world_opengl`, `near`, `far`,
    /// `fov_x_degrees`, `fov_y_degrees`, the sensor and the lens.
    pub camera_data: CameraData,
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
    /// With `--aov object_id`: each visible object (`id`, `name`, `pixels`, `bbox` [x0, y0,
    /// x1, y1) and `visible_fraction`), by ID; absent without the layer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub objects: Option<Vec<ObjectSummary>>,
    /// With `--aov object_id`: the fraction of pixels whose centre ray hits an object.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub visible_fraction: Option<f64>,
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
    pub(super) fn new(report: &GuideReport) -> GuideSummary {
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
    pub(super) fn line(&self) -> String {
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
    pub(super) fn new(context: &Context, spp: u32) -> DeviceReport {
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

/// The files a finished render wrote, for its report.
pub(super) struct WrittenFiles<'a> {
    /// The images (the outputs, or after Ctrl-C their `.partial` siblings).
    pub(super) outputs: &'a [PathBuf],
    /// The checkpoint, if one was asked for.
    pub(super) checkpoint: Option<&'a PathBuf>,
    /// The preview, if one was asked for and written.
    pub(super) preview: Option<&'a PathBuf>,
}

/// What this run of a render took, as the summary and the report count it.
pub(super) struct RunCounts {
    /// From the command's start to the first batch (loading, device, kernels).
    pub(super) setup_seconds: f64,
    /// Samples this run took: all those held but the resumed ones (`resumed_spp` per pixel,
    /// exact unless an adaptive checkpoint had stopped some pixels before).
    pub(super) new_samples: f64,
    /// Mean over the pixels of the samples each holds.
    pub(super) spp_mean: f64,
}

impl RunCounts {
    pub(super) fn of(
        request: &RenderRequest,
        finished: &Finished,
        image: &RenderedImage,
    ) -> RunCounts {
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

/// The object `render --json` prints (the devices' reports are moved out of `finished`).
pub(super) fn render_report(
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
        camera_data: CameraData::of(request.camera, settings.width, settings.height),
        frame: request.frame.map(|f| f.frame),
        time: request.frame.map(|f| f.time),
        reused: finished.reused.take(),
        objects: None,
        visible_fraction: None,
    }
}

/// `objects` and `visible_fraction` of a report, from the post-processed `layers` of an
/// image `width` pixels wide (`None` without an `object_id` layer); boxes in the full
/// image's pixels (a region's offset added).
pub(super) fn object_report(
    request: &RenderRequest,
    width: u32,
    layers: &[ImageLayer],
) -> Option<(Vec<ObjectSummary>, f64)> {
    let layer = layers.iter().find(|l| l.name == Aov::ObjectId.name())?;
    let mut objects = object_summaries(&layer.pixels, width, &IdNames::of(request.scene));
    if let Some(region) = request.settings.region {
        for object in &mut objects {
            let [x0, y0, x1, y1] = object.bbox;
            object.bbox = [
                x0 + region.x0,
                y0 + region.y0,
                x1 + region.x0,
                y1 + region.y0,
            ];
        }
    }
    let visible = objects.iter().map(|o| o.visible_fraction).sum();
    Some((objects, visible))
}
