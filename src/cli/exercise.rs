//! `vkpath exercise NAME`: the workshop's pictures as its ShaderToy framework shows them.

use std::path::PathBuf;

use anyhow::bail;

use super::render::render_and_save;
use super::{DeviceArgs, PixelFilterArg};
use crate::exercise::{render_sample_display, Exercise, ExerciseKind};
use crate::image_io::output::{check_writable, save_image, SaveOptions};
use crate::render::settings::RenderSettings;
use crate::scene::Scene;

/// `vkpath exercise` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ExerciseArg {
    /// Part 1: unshaded ray tracing of the Cornell box (the albedo of the first hit).
    RayTracing,
    /// Exercise 4: 512 samples of sample_sphere() drawn on the sphere.
    SampleSphere,
    /// Exercise 5: 512 samples of sample_hemisphere() (normal +z) drawn on the sphere.
    SampleHemisphere,
    /// The naive spherical-coordinates sampler: too many samples at the top.
    SphericalCoords,
    /// Exercise 6: direct illumination (one frame of --sample-count samples by default).
    DirectIllumination,
    /// Exercise 7: path tracing (one frame of --sample-count samples by default).
    PathTracing,
}

impl From<ExerciseArg> for Exercise {
    fn from(arg: ExerciseArg) -> Exercise {
        match arg {
            ExerciseArg::RayTracing => Exercise::RayTracing,
            ExerciseArg::SampleSphere => Exercise::SampleSphere,
            ExerciseArg::SampleHemisphere => Exercise::SampleHemisphere,
            ExerciseArg::SphericalCoords => Exercise::SphericalCoords,
            ExerciseArg::DirectIllumination => Exercise::DirectIllumination,
            ExerciseArg::PathTracing => Exercise::PathTracing,
        }
    }
}

/// Arguments of `vkpath exercise`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExerciseArgs {
    /// Which picture.
    #[arg(value_enum)]
    pub name: ExerciseArg,
    /// Output image: .png (sRGB) or .exr (linear).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image width in pixels (256 keeps a CPU device such as lavapipe quick).
    #[arg(long, default_value_t = 256)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 256)]
    pub height: u32,
    /// The workshop's SAMPLE_COUNT: samples per pixel in one frame (the slides show 1 and 8).
    #[arg(long, default_value_t = 1)]
    pub sample_count: u32,
    /// Samples per pixel in total, rendered progressively in frames of --sample-count;
    /// default: one frame, as the slides' pictures.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Maximum number of surface hits per path (MAX_PATH_LENGTH, path-tracing).
    #[arg(long, default_value_t = 5)]
    pub max_path_length: u32,
    /// Random seed; 0 seeds exactly as the workshop does. For the sample displays, the
    /// seed of the 512 samples.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Where samples look inside a pixel; the workshop uses the centre.
    #[arg(long, value_enum, default_value_t = PixelFilterArg::Center)]
    pub pixel_filter: PixelFilterArg,
    /// PNG only: multiply radiance by 2^EXPOSURE before clamping and sRGB encoding.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// EXR only: also store each pixel's second moment and sample count.
    #[arg(long)]
    pub moments: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// Runs `vkpath exercise`.
pub fn run(args: &ExerciseArgs) -> anyhow::Result<()> {
    let save = SaveOptions {
        exposure: args.exposure,
        moments: args.moments,
    };
    match Exercise::from(args.name).kind() {
        ExerciseKind::Render(integrator) => {
            let settings = RenderSettings {
                width: args.width,
                height: args.height,
                spp: args.spp.unwrap_or(args.sample_count),
                max_path_length: args.max_path_length,
                seed: args.seed,
                pixel_filter: args.pixel_filter.into(),
                integrator,
                samples_per_frame: args.sample_count,
                ..RenderSettings::default()
            };
            settings.validate()?;
            check_writable(&args.output)?;
            let scene = Scene::builtin_cornell_box()?;
            let Some(camera) = scene.camera else {
                bail!("the built-in Cornell box has no camera");
            };
            let context = args.device.create_context()?;
            render_and_save(&context, &scene, &camera, settings, &args.output, &save)
        }
        ExerciseKind::Samples(sampler) => {
            if args.spp.is_some() || args.sample_count != 1 {
                eprintln!(
                    "vkpath: note: --spp and --sample-count do not apply to the sample displays"
                );
            }
            check_writable(&args.output)?;
            let context = args.device.create_context()?;
            let image =
                render_sample_display(&context, sampler, args.width, args.height, args.seed)?;
            save_image(&args.output, &image, &save)?;
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
    }
}
