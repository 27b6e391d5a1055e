//! `vkpath bench`: renders a fixed scene with each integrator at a fixed spp and compares
//! them fairly: samples/s and rays/s for speed, relative MSE against a high-spp reference for
//! quality, and efficiency 1 / (relMSE * seconds), with the time each needs to reach a relMSE
//! of 0.005. Pipeline creation (cold start) is timed apart from the steady-state frames.

pub mod startup;

use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use crate::camera::Camera;
use crate::error::Result;
use crate::guiding::training::GuideTraining;
use crate::image_io::data::RenderedImage;
use crate::render::gpu_scene::SceneMemory;
use crate::render::settings::{
    default_russian_roulette_start, Integrator, LightSelection, RenderSettings, SamplerKind,
};
use crate::render::Renderer;
use crate::scene::{Scene, SceneSource};
use crate::vk::Context;

/// The relMSE at which `seconds_to_target` is reported.
pub const TARGET_RELATIVE_MSE: f64 = 0.005;

/// One integrator's measurements.
#[derive(Clone, Debug, Serialize)]
pub struct BenchResult {
    /// Integrator name as `--integrator` spells it.
    pub integrator: String,
    /// How nee and mis chose their lights, as `--light-selection` spells it.
    pub light_selection: String,
    /// Seconds to create the renderer (pipeline compilation, uploads).
    pub cold_start_seconds: f64,
    /// Steady-state seconds for all samples (measured after the first frame, scaled).
    pub render_seconds: f64,
    /// Samples (paths) per second.
    pub samples_per_second: f64,
    /// Rays per second (camera, path and shadow rays).
    pub rays_per_second: f64,
    /// Mean over pixels and channels of (x - r)^2 / (r^2 + 0.01).
    pub relative_mse: f64,
    /// 1 / (relMSE * seconds): higher is better.
    pub efficiency: f64,
    /// Seconds to reach relMSE 0.005, assuming relMSE falls as 1 / time (unbiased MC).
    pub seconds_to_target: f64,
    /// Whether the render was guided (`--guiding`).
    pub guiding: bool,
    /// Seconds that training the guide took (0 unguided; part of `cold_start_seconds`,
    /// not of `render_seconds`).
    pub training_seconds: f64,
    /// The process's CPU time (user + system, every thread: lavapipe's too) for the whole
    /// render: creating the renderer, training, every frame.
    pub cpu_seconds: f64,
    /// 1 / (relMSE * cpu_seconds): what a render costs in all, start-up and training
    /// included (on a CPU device, the fairest measure).
    pub cpu_efficiency: f64,
    /// What the scene took on the device: the acceleration structure's bytes and every
    /// buffer's, in all and per triangle.
    pub scene_memory: SceneMemory,
}

/// The benchmark's setup and results.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    /// Device name and kind.
    pub device: String,
    /// Scene description.
    pub scene: String,
    /// Number of triangles.
    pub triangle_count: usize,
    /// How rays found their hits (`Traversal::name`).
    pub traversal: String,
    /// Random numbers of cosine, nee and mis: "pcg" or "sobol".
    pub sampler: String,
    /// How nee and mis sampled their lights: "area" or "solid-angle".
    pub light_sampling: String,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Samples per pixel of each measured render.
    pub spp: u32,
    /// Samples per pixel of the reference (rendered with MIS, or the most any pixel of a
    /// stored reference has).
    pub reference_spp: u32,
    /// Where the reference came from: "mis" (rendered by the bench) or a stored file's path.
    pub reference: String,
    /// The relMSE its own noise adds, in expectation, to every measured relMSE (from its
    /// moments; `None` for a stored reference without them). Small next to the measured
    /// figures, or the better estimators' ratios are understated.
    pub reference_noise_relative_mse: Option<f64>,
    /// Maximum path length of every render.
    pub max_path_length: u32,
    /// Per integrator.
    pub results: Vec<BenchResult>,
}

/// Relative MSE of an image against a reference (`vkpath compare` reports it too).
pub use crate::compare::{reference_noise_relative_mse, relative_mse};

/// A timed render's image and times.
struct TimedRender {
    image: RenderedImage,
    /// Creating the renderer plus its first frame (training a guide included).
    cold_start: f64,
    /// The steady-state frames, scaled to all `spp` samples.
    seconds: f64,
    rays: f64,
    /// Training the guide (part of `cold_start`).
    training: f64,
    /// The process's CPU time over all of it.
    cpu: f64,
    /// What the scene took on the device.
    scene_memory: SceneMemory,
}

/// The process's CPU time so far, user and system, in seconds (every thread's).
pub fn process_cpu_seconds() -> f64 {
    // SAFETY: getrusage writes the struct it is given; RUSAGE_SELF is always valid.
    let usage = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        usage
    };
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    seconds(usage.ru_utime) + seconds(usage.ru_stime)
}

/// A render with timings. The cold start is creating the renderer plus its first frame
/// (drivers may compile the pipeline lazily, at the first dispatch; a guided render trains
/// its guide there); the steady-state time is measured over the remaining frames and scaled
/// to the whole sample count.
fn timed_render(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: RenderSettings,
) -> Result<TimedRender> {
    let spp = settings.spp;
    let cpu_started = process_cpu_seconds();
    let started = Instant::now();
    let mut renderer = Renderer::new(context, scene, camera, settings)?;
    let first_frame_samples = renderer.render_frame()?;
    let cold_start = started.elapsed().as_secs_f64();
    let outcome = renderer.render_to_end(|_| {}, None)?.finished()?;
    let cpu = process_cpu_seconds() - cpu_started;
    let training = outcome
        .guide
        .as_ref()
        .map_or(0.0, crate::render::renderer::GuideReport::seconds);
    let (image, steady, outcome_memory) = (outcome.image, outcome.seconds, outcome.scene_memory);
    let steady_samples = spp - first_frame_samples;
    let seconds = if steady_samples > 0 {
        steady * f64::from(spp) / f64::from(steady_samples)
    } else {
        cold_start
    };
    Ok(TimedRender {
        image,
        cold_start,
        seconds,
        rays: renderer.rays_traced(),
        training,
        cpu,
        scene_memory: outcome_memory,
    })
}

/// What to benchmark.
#[derive(Clone, Debug)]
pub struct BenchSetup {
    /// Settings of the measured renders (integrator and seed are set per render).
    pub settings: RenderSettings,
    /// Samples per pixel of the MIS reference.
    pub reference_spp: u32,
    /// A stored reference (`--reference`) to measure against instead of rendering one, with
    /// the file's name; it must have the measured renders' size.
    pub stored_reference: Option<(RenderedImage, String)>,
    /// Integrators to measure.
    pub integrators: Vec<Integrator>,
    /// Light selections to measure each integrator with (`--light-selections`), against
    /// the same reference; empty: only `settings.light_selection`.
    pub light_selections: Vec<LightSelection>,
    /// Whether to measure nee and mis guided too (`--guiding`): each of them then once
    /// without and once with the guide of `guide_training`.
    pub compare_guiding: bool,
    /// The guided runs' training (`--guide-training-spp`, else
    /// `RenderSettings::default_guide_training`).
    pub guide_training: Option<GuideTraining>,
    /// `--russian-roulette-start` as given: every render, the reference's included, resolves
    /// it as `vkpath render` does, `default_russian_roulette_start(guided)` where none was
    /// given (`settings.russian_roulette_start` is not read).
    pub russian_roulette_start: Option<u32>,
    /// Scene description for the report.
    pub scene_name: String,
    /// Timed renders per integrator; the fastest counts (the image is the same each time,
    /// so only the timing varies, and the minimum is the least disturbed by other load).
    pub repeats: u32,
}

impl BenchSetup {
    /// The Russian roulette start of a guided or unguided render: the one given, else
    /// `default_russian_roulette_start(guided)`, the rule of `vkpath render`.
    pub fn russian_roulette_start(&self, guided: bool) -> u32 {
        self.russian_roulette_start
            .unwrap_or(default_russian_roulette_start(guided))
    }
}

impl Default for BenchSetup {
    /// `vkpath bench`'s defaults: the four path tracers on a 64 x 64 image at 64 spp against
    /// a 4096 spp reference, the fastest of 3 timed renders; the workshop's Cornell box.
    fn default() -> Self {
        BenchSetup {
            settings: RenderSettings {
                width: 64,
                height: 64,
                spp: 64,
                ..RenderSettings::default()
            },
            reference_spp: 4096,
            stored_reference: None,
            integrators: vec![
                Integrator::PathTracing,
                Integrator::Cosine,
                Integrator::Nee,
                Integrator::Mis,
            ],
            light_selections: Vec::new(),
            compare_guiding: false,
            guide_training: None,
            russian_roulette_start: None,
            scene_name: SceneSource::CornellBox.description(),
            repeats: 3,
        }
    }
}

/// Renders the reference, then each integrator, and reports. `progress` is told what runs.
pub fn run_bench(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    setup: &BenchSetup,
    mut progress: impl FnMut(&str),
) -> Result<BenchReport> {
    let rendered_reference;
    let (reference, reference_name, reference_spp) = match &setup.stored_reference {
        Some((image, name)) => {
            let (width, height) = (setup.settings.width, setup.settings.height);
            if (image.width, image.height) != (width, height) {
                return Err(crate::error::Error::InvalidSettings(format!(
                    "the reference {name} is {}x{}, the renders {width}x{height}",
                    image.width, image.height
                )));
            }
            let spp = image.sample_count.iter().fold(0.0f32, |a, &b| a.max(b));
            (image, name.clone(), spp as u32)
        }
        None => {
            progress(&format!("reference: mis, {} spp", setup.reference_spp));
            let reference_settings = RenderSettings {
                spp: setup.reference_spp,
                integrator: Integrator::Mis,
                // A seed no measured render uses, so the reference's noise is independent.
                seed: 0x5eed,
                guiding: None,
                russian_roulette_start: setup.russian_roulette_start(false),
                ..setup.settings.clone()
            };
            rendered_reference = timed_render(context, scene, camera, reference_settings)?.image;
            (&rendered_reference, "mis".to_string(), setup.reference_spp)
        }
    };
    let mut results = Vec::new();
    let selections = if setup.light_selections.is_empty() {
        vec![setup.settings.light_selection]
    } else {
        setup.light_selections.clone()
    };
    let guidings: &[bool] = if setup.compare_guiding {
        &[false, true]
    } else {
        &[false]
    };
    let runs = setup.integrators.iter().flat_map(|&i| {
        selections.iter().flat_map(move |&s| {
            guidings
                .iter()
                .filter(move |&&g| !g || i.takes_light_samples())
                .map(move |&g| (i, s, g))
        })
    });
    for (integrator, light_selection, guided) in runs {
        let name = integrator.name();
        let mut what = name.to_string();
        if selections.len() > 1 {
            what += &format!(", --light-selection {}", light_selection.name());
        }
        if guided {
            what += ", --guiding";
        }
        progress(&what);
        let guiding = guided.then(|| {
            setup
                .guide_training
                .unwrap_or(setup.settings.default_guide_training())
        });
        let settings = RenderSettings {
            integrator,
            light_selection,
            seed: 1,
            guiding,
            russian_roulette_start: setup.russian_roulette_start(guided),
            ..setup.settings.clone()
        };
        let samples =
            f64::from(settings.width) * f64::from(settings.height) * f64::from(settings.spp);
        let timed = timed_render(context, scene, camera, settings)?;
        let relative_mse = relative_mse(&timed.image, reference);
        let seconds = timed.seconds.max(1e-9);
        results.push(BenchResult {
            integrator: name.to_string(),
            light_selection: light_selection.name().to_string(),
            cold_start_seconds: timed.cold_start,
            render_seconds: timed.seconds,
            samples_per_second: samples / seconds,
            rays_per_second: timed.rays / seconds,
            relative_mse,
            efficiency: 1.0 / (relative_mse * seconds),
            seconds_to_target: seconds * relative_mse / TARGET_RELATIVE_MSE,
            guiding: guided,
            training_seconds: timed.training,
            cpu_seconds: timed.cpu,
            cpu_efficiency: 1.0 / (relative_mse * timed.cpu.max(1e-9)),
            scene_memory: timed.scene_memory,
        });
    }
    Ok(BenchReport {
        device: format!("{} [{}]", context.info.name, context.info.kind),
        scene: setup.scene_name.clone(),
        triangle_count: scene.triangles.len(),
        // As the renders chose it, on this device (its ray queries, where it has them)
        traversal: crate::accel::choose_traversal(context, scene, setup.settings.accel, false)?
            .traversal
            .name()
            .to_string(),
        sampler: match setup.settings.sampler {
            SamplerKind::Pcg => "pcg",
            SamplerKind::Sobol => "sobol",
        }
        .to_string(),
        light_sampling: setup.settings.light_sampling.name().to_string(),
        width: setup.settings.width,
        height: setup.settings.height,
        spp: setup.settings.spp,
        reference_spp,
        reference: reference_name,
        reference_noise_relative_mse: reference_noise_relative_mse(reference),
        max_path_length: setup.settings.max_path_length,
        results,
    })
}

/// The report as a table for people, efficiencies also as ratios to the first integrator.
pub fn format_table(report: &BenchReport) -> String {
    let mut text = format!(
        "{} | {} ({} triangles, {}) | sampler {} | light sampling {} | {}x{} | {} spp | reference {} spp ({}, own noise adds relMSE {}) | max path length {}\n",
        report.device,
        report.scene,
        report.triangle_count,
        report.traversal,
        report.sampler,
        report.light_sampling,
        report.width,
        report.height,
        report.spp,
        report.reference_spp,
        report.reference,
        report
            .reference_noise_relative_mse
            .map_or("unknown".to_string(), |n| format!("{n:.5}")),
        report.max_path_length
    );
    text += &format!(
        "{:<16} {:>9} {:>9} {:>11} {:>11} {:>10} {:>11} {:>9} {:>12} {:>8} {:>8} {:>9}\n",
        "integrator",
        "cold s",
        "render s",
        "Msamples/s",
        "Mrays/s",
        "relMSE",
        "efficiency",
        "vs first",
        "s to 0.005",
        "train s",
        "cpu s",
        "cpu vs 1st"
    );
    let baseline = report.results.first().map(|r| r.efficiency).unwrap_or(1.0);
    let cpu_baseline = report
        .results
        .first()
        .map(|r| r.cpu_efficiency)
        .unwrap_or(1.0);
    // With several light selections (`--light-selections`), each row names its own.
    let several = report
        .results
        .iter()
        .any(|r| r.light_selection != report.results[0].light_selection);
    for r in &report.results {
        let mut name = if several {
            format!("{}/{}", r.integrator, r.light_selection)
        } else {
            r.integrator.clone()
        };
        if r.guiding {
            name += "+guiding";
        }
        text += &format!(
            "{:<16} {:>9.3} {:>9.3} {:>11.3} {:>11.3} {:>10.5} {:>11.2} {:>8.2}x {:>12.2} {:>8.2} {:>8.2} {:>8.2}x\n",
            name,
            r.cold_start_seconds,
            r.render_seconds,
            r.samples_per_second / 1e6,
            r.rays_per_second / 1e6,
            r.relative_mse,
            r.efficiency,
            r.efficiency / baseline,
            r.seconds_to_target,
            r.training_seconds,
            r.cpu_seconds,
            r.cpu_efficiency / cpu_baseline
        );
    }
    if let Some(first) = report.results.first() {
        text += &first.scene_memory.line();
        text += "\n";
    }
    if let Some(note) = reference_noise_note(report) {
        text += &note;
        text += "\n";
    }
    text
}

/// Share of the smallest measured relMSE beyond which the reference's own noise is worth a
/// note: every relMSE includes it, so it understates the best render's efficiency against
/// the others by about this share.
const REFERENCE_NOISE_NOTE_SHARE: f64 = 0.05;

/// A note when the reference's own noise is more than `REFERENCE_NOISE_NOTE_SHARE` of the
/// smallest relMSE measured: the ratios to the best render are then understated.
pub fn reference_noise_note(report: &BenchReport) -> Option<String> {
    let noise = report.reference_noise_relative_mse?;
    let smallest = report
        .results
        .iter()
        .map(|r| r.relative_mse)
        .fold(f64::INFINITY, f64::min);
    let share = noise / smallest;
    (share > REFERENCE_NOISE_NOTE_SHARE).then(|| {
        format!(
            "note: the reference's own noise adds {noise:.5} to every relMSE, {:.0} % of the smallest ({smallest:.5}): the better renders' efficiencies are understated; raise --reference-spp or pass --reference",
            share * 100.0
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[f32]) -> RenderedImage {
        RenderedImage {
            width: values.len() as u32,
            height: 1,
            mean: values.iter().map(|&v| [v, v, v, 1.0]).collect(),
            second_moment: vec![[0.0; 3]; values.len()],
            sample_count: vec![1.0; values.len()],
        }
    }

    /// A report of renders with these relMSEs against a reference whose noise adds `noise`.
    fn report(noise: Option<f64>, relative_mses: &[f64]) -> BenchReport {
        let result = |relative_mse: f64| BenchResult {
            integrator: "mis".into(),
            light_selection: "power".into(),
            cold_start_seconds: 0.1,
            render_seconds: 1.0,
            samples_per_second: 1e6,
            rays_per_second: 4e6,
            relative_mse,
            efficiency: 1.0 / relative_mse,
            seconds_to_target: relative_mse / TARGET_RELATIVE_MSE,
            guiding: false,
            training_seconds: 0.0,
            cpu_seconds: 1.0,
            cpu_efficiency: 1.0 / relative_mse,
            scene_memory: SceneMemory {
                accel: "bvh",
                traversal: "BVH",
                triangle_count: 30,
                bvh_node_bytes: 1120,
                traversal_triangle_bytes: 1440,
                hardware_structure_bytes: 0,
                hardware_bottom_levels: 0,
                hardware_instances: 0,
                acceleration_bytes_per_triangle: 2560.0 / 30.0,
                scene_bytes: 6000,
                scene_bytes_per_triangle: 200.0,
            },
        };
        BenchReport {
            device: "device".into(),
            scene: "scene".into(),
            triangle_count: 30,
            traversal: "BVH".into(),
            sampler: "pcg".into(),
            light_sampling: "area".into(),
            width: 4,
            height: 4,
            spp: 4,
            reference_spp: 64,
            reference: "mis".into(),
            reference_noise_relative_mse: noise,
            max_path_length: 5,
            results: relative_mses.iter().map(|&m| result(m)).collect(),
        }
    }

    #[test]
    fn a_noisy_reference_is_noted_against_the_smallest_relative_mse() {
        // 0.00014 is 17.5 % of 0.0008 (the smallest), 3 % of 0.0047: noted, with the share.
        let noisy = report(Some(0.00014), &[0.0047, 0.0008]);
        let note = reference_noise_note(&noisy).unwrap();
        assert!(
            note.contains("0.00014") && note.contains("18 %") && note.contains("0.00080"),
            "{note}"
        );
        assert!(format_table(&noisy).ends_with(&format!("{note}\n")));
        // 0.00002 is 2.5 % of it; unknown noise says nothing.
        assert_eq!(
            reference_noise_note(&report(Some(0.00002), &[0.0047, 0.0008])),
            None
        );
        assert_eq!(reference_noise_note(&report(None, &[0.0047, 0.0008])), None);
        assert!(!format_table(&report(None, &[0.0047])).contains("note"));
    }

    #[test]
    fn each_render_resolves_the_roulette_start_as_vkpath_render_does() {
        // None given: guided renders none, unguided from vertex 3; a given start for both.
        let setup = BenchSetup::default();
        assert_eq!(setup.russian_roulette_start(false), 3);
        assert_eq!(setup.russian_roulette_start(true), 0);
        let given = BenchSetup {
            russian_roulette_start: Some(4),
            ..BenchSetup::default()
        };
        assert_eq!(given.russian_roulette_start(false), 4);
        assert_eq!(given.russian_roulette_start(true), 4);
    }

    #[test]
    fn relative_mse_follows_its_definition() {
        let reference = image(&[1.0, 0.0]);
        let test = image(&[1.1, 0.1]);
        // ((0.1^2 / 1.01) + (0.1^2 / 0.01)) / 2
        let expected = (0.01 / 1.01 + 1.0) / 2.0;
        assert!((relative_mse(&test, &reference) - expected).abs() < 1e-6);
        assert_eq!(relative_mse(&reference, &reference), 0.0);
    }
}
