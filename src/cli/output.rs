//! The end of a render command: render with a progress bar (or quietly), stop on a signal or
//! a time limit, save the image with its metadata (into the temp directory when the output
//! cannot be written), print the summary line (or one JSON object), and fail when the
//! validation layer complained.

use std::path::Path;
use std::sync::Arc;

use anyhow::bail;
use serde::Serialize;

use super::signals;
use super::summary::{summary_line, RenderProgress};
use crate::camera::Camera;
use crate::image_io::output::{
    save_image_with_attributes, save_image_with_layers, ImageLayer, SaveOptions,
};
use crate::image_io::state_exr::write_state;
use crate::render::aov::{render_aov, Aov};
use crate::render::job::{run_job, JobOptions, DEFAULT_CHECKPOINT_INTERVAL};
use crate::render::metadata::RenderMetadata;
use crate::render::multi::run_on_devices;
use crate::render::settings::RenderSettings;
use crate::render::StopReason;
use crate::scene::Scene;
use crate::vk::Context;
use crate::RenderedImage;

/// How a command reports.
#[derive(Clone, Copy, Debug, Default)]
pub struct Reporting {
    /// One JSON object on stdout at the end instead of the summary line.
    pub json: bool,
    /// No progress bar, summary or `wrote` lines (warnings and errors still print).
    pub quiet: bool,
}

/// The JSON object `render --json` prints.
#[derive(Serialize)]
struct RenderReport<'a> {
    output: String,
    spp: u32,
    sample_range: [u32; 2],
    seconds: f64,
    /// Seconds before the first frame (building the kernels, the BVH, uploads).
    setup_seconds: f64,
    samples_per_second: f64,
    devices: Vec<String>,
    stop: &'a str,
    checkpoint: Option<String>,
}

/// Renders all samples with a progress bar, saves the image and prints the summary line.
/// A signal stops it early and saves the samples taken so far.
pub fn render_and_save(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: RenderSettings,
    output: &Path,
    save: &SaveOptions,
) -> anyhow::Result<()> {
    let job = JobOptions {
        samples: 0..settings.spp,
        time_limit: None,
        cancel: None,
        checkpoint: None,
        checkpoint_interval: DEFAULT_CHECKPOINT_INTERVAL,
        resume: None,
        preview: None,
    };
    render_job_and_save(
        context,
        scene,
        camera,
        &settings,
        job,
        output,
        save,
        Reporting::default(),
        false,
        &PostProcess::default(),
    )
}

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

/// Runs a production render (`job`) and saves it; `shard` writes the render state into the
/// EXR too (for `vkpath merge`). Exits with 128 + the signal's number when a signal stopped
/// it, after everything is written.
#[allow(clippy::too_many_arguments)]
pub fn render_job_and_save(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    mut job: JobOptions,
    output: &Path,
    save: &SaveOptions,
    reporting: Reporting,
    shard: bool,
    post: &PostProcess,
) -> anyhow::Result<()> {
    signals::install()?;
    job.cancel = Some(&signals::STOP_REQUESTED);
    let total = job.samples.len() as u32;
    let mut progress = (!reporting.quiet && !reporting.json).then(|| RenderProgress::new(total));
    let outcome = run_job(context, scene, camera, settings, &job, |done| {
        if let Some(progress) = progress.as_mut() {
            progress.update(done);
        }
    })?;
    if let Some(progress) = progress {
        progress.finish();
    }
    let metadata = &outcome.metadata;
    let result = &outcome.outcome;
    let done = result.samples;
    let non_finite = result
        .image
        .mean
        .iter()
        .filter(|p| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()))
        .count();
    if non_finite > 0 {
        eprintln!(
            "vkpath: warning: {non_finite} pixels are not finite (NaN or infinite); the scene's values overflow 32-bit floats"
        );
    }
    if shard {
        write_state(output, &result.state, metadata)?;
    } else if post.is_empty() {
        save_or_rescue(output, &result.image, save, metadata, &[])?;
    } else if result.stop != StopReason::Done {
        eprintln!("vkpath: warning: the render stopped early: saved without --aov/--denoise");
        save_or_rescue(output, &result.image, save, metadata, &[])?;
    } else {
        // Saved as rendered first, so that nothing is lost if post-processing fails.
        save_or_rescue(output, &result.image, save, metadata, &[])?;
        let (image, layers) = post.apply(context, scene, camera, settings, &result.image)?;
        save_or_rescue(output, &image, save, metadata, &layers)?;
    }
    if let Some(error) = &outcome.preview_failure {
        eprintln!("vkpath: warning: {error} (the preview)");
    }
    let quiet = reporting.quiet || reporting.json;
    if !quiet {
        eprintln!("vkpath: wrote {}", output.display());
        if let Some(checkpoint) = &job.checkpoint {
            eprintln!("vkpath: wrote {} (checkpoint)", checkpoint.display());
        }
        if let (Some(preview), None) = (&job.preview, &outcome.preview_failure) {
            eprintln!("vkpath: wrote {} (preview)", preview.path.display());
        }
        let seconds = result.seconds;
        eprintln!(
            "{}",
            summary_line(
                &context.info,
                settings.width,
                settings.height,
                done,
                result.setup_seconds,
                seconds
            )
        );
    }
    let stop = result.stop.name();
    if reporting.json {
        let pixels = f64::from(settings.width) * f64::from(settings.height);
        let new_samples = f64::from(done - outcome.resumed_samples) * pixels;
        let report = RenderReport {
            output: output.display().to_string(),
            spp: done,
            sample_range: [result.state.samples.start, result.state.samples.end],
            seconds: result.seconds,
            setup_seconds: result.setup_seconds,
            samples_per_second: new_samples / result.seconds.max(1e-9),
            devices: vec![context.info.name.clone()],
            stop,
            checkpoint: job.checkpoint.as_ref().map(|p| p.display().to_string()),
        };
        println!("{}", serde_json::to_string(&report)?);
    }
    if let Some(error) = &result.failure {
        bail!("rendering stopped after {done} of {total} spp: {error}");
    }
    match result.stop {
        StopReason::Cancelled => {
            let (name, status) = signals::received().unwrap_or(("a signal", 130));
            eprintln!(
                "vkpath: stopped by {name} after {done} of {total} spp; saved to '{}'{}",
                output.display(),
                job.checkpoint
                    .as_ref()
                    .map(|c| format!(" and '{}'", c.display()))
                    .unwrap_or_default()
            );
            std::process::exit(status);
        }
        StopReason::TimeLimit if !quiet => {
            eprintln!("vkpath: time limit reached after {done} of {total} spp");
        }
        _ => {}
    }
    fail_on_validation_messages(context)
}

/// `render_job_and_save` on several devices at once (each an equal share; no checkpoints).
/// The summary gives each device's share.
#[allow(clippy::too_many_arguments)]
pub fn render_on_devices_and_save(
    contexts: &[Arc<Context>],
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    job: JobOptions,
    output: &Path,
    save: &SaveOptions,
    reporting: Reporting,
    shard: bool,
) -> anyhow::Result<()> {
    signals::install()?;
    let outcome = run_on_devices(
        contexts,
        scene,
        camera,
        settings,
        job.samples.clone(),
        job.time_limit,
        Some(&signals::STOP_REQUESTED),
    )?;
    let spp_settings = RenderSettings {
        spp: job.samples.len() as u32,
        ..settings.clone()
    };
    let metadata = RenderMetadata::new(&spp_settings, scene, camera, outcome.state.samples.clone());
    if shard {
        write_state(output, &outcome.state, &metadata)?;
    } else {
        save_or_rescue(output, &outcome.state.image(), save, &metadata, &[])?;
    }
    let done = outcome.state.samples.len() as u32;
    let shares: Vec<String> = outcome
        .shares
        .iter()
        .map(|(name, spp)| format!("{name}: {spp} spp"))
        .collect();
    if reporting.json {
        let pixels = f64::from(settings.width) * f64::from(settings.height);
        let report = serde_json::json!({
            "output": output.display().to_string(),
            "spp": done,
            "sample_range": [outcome.state.samples.start, outcome.state.samples.end],
            "seconds": outcome.seconds,
            "samples_per_second": f64::from(done) * pixels / outcome.seconds.max(1e-9),
            "devices": outcome.shares.iter().map(|(name, spp)| serde_json::json!({"name": name, "spp": spp})).collect::<Vec<_>>(),
            "stop": outcome.stop.name(),
        });
        println!("{report}");
    } else if !reporting.quiet {
        eprintln!("vkpath: wrote {}", output.display());
        eprintln!(
            "{} devices, {}x{}, {done} spp, {:.2} s ({})",
            contexts.len(),
            settings.width,
            settings.height,
            outcome.seconds,
            shares.join(", ")
        );
    }
    if outcome.stop == StopReason::Cancelled {
        let (name, status) = signals::received().unwrap_or(("a signal", 130));
        eprintln!(
            "vkpath: stopped by {name} after {done} spp; saved to '{}'",
            output.display()
        );
        std::process::exit(status);
    }
    for context in contexts {
        fail_on_validation_messages(context)?;
    }
    Ok(())
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
    let attributes = metadata.attributes();
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
