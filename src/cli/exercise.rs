//! `vkpath exercise NAME`: the workshop's pictures as its ShaderToy framework shows them.

use std::path::PathBuf;

use anyhow::bail;

use super::options::SaveArgs;
use super::output::{fail_on_validation_messages, render_and_save};
use super::DeviceArgs;
use crate::exercise::{render_sample_display, workshop_frame_settings, Exercise, ExerciseKind};
use crate::image_io::output::{check_writable, save_image};
use crate::render::settings::{PixelFilter, RenderSettings};
use crate::scene::SceneSource;

/// Arguments of `vkpath exercise`. Its defaults are the workshop's
/// (`workshop_frame_settings()`), not `render`'s, and the frame's sample count is
/// `--sample-count` as the workshop calls it.
#[derive(Debug, Clone, clap::Args)]
pub struct ExerciseArgs {
    /// Which picture.
    #[arg(value_enum)]
    pub name: Exercise,
    /// Output image: .png (sRGB) or .exr (linear).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image width in pixels (256 keeps a CPU device such as lavapipe quick).
    #[arg(long, default_value_t = workshop_frame_settings().width)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = workshop_frame_settings().height)]
    pub height: u32,
    /// The workshop's SAMPLE_COUNT: samples per pixel in one frame (the slides show 1 and 8).
    #[arg(long, default_value_t = workshop_frame_settings().samples_per_frame)]
    pub sample_count: u32,
    /// Samples per pixel in total, rendered progressively in frames of --sample-count;
    /// default: one frame, as the slides' pictures.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Maximum number of surface hits per path (MAX_PATH_LENGTH, path-tracing).
    #[arg(long, default_value_t = workshop_frame_settings().max_path_length)]
    pub max_path_length: u32,
    /// Random seed; 0 seeds exactly as the workshop does. For the sample displays, the
    /// seed of the 512 samples.
    #[arg(long, default_value_t = workshop_frame_settings().seed)]
    pub seed: u32,
    /// Where samples look inside a pixel; the workshop uses the centre.
    #[arg(long, value_enum, default_value_t = workshop_frame_settings().pixel_filter)]
    pub pixel_filter: PixelFilter,
    /// How the image is written.
    #[command(flatten)]
    pub save: SaveArgs,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// Runs `vkpath exercise`.
pub fn run(args: &ExerciseArgs) -> anyhow::Result<()> {
    let save = args.save.options();
    match args.name.kind() {
        ExerciseKind::Render(integrator) => {
            let settings = RenderSettings {
                width: args.width,
                height: args.height,
                spp: args.spp.unwrap_or(args.sample_count),
                max_path_length: args.max_path_length,
                seed: args.seed,
                pixel_filter: args.pixel_filter,
                integrator,
                samples_per_frame: args.sample_count,
                ..workshop_frame_settings()
            };
            settings.validate()?;
            check_writable(&args.output)?;
            let scene = SceneSource::CornellBox.load()?;
            let Some(camera) = scene.camera else {
                bail!("the built-in Cornell box has no camera");
            };
            let context = args.device.create_context()?;
            render_and_save(&context, &scene, &camera, settings, &args.output, &save)
        }
        ExerciseKind::Samples(sampler) => {
            if args.spp.is_some()
                || args.sample_count != workshop_frame_settings().samples_per_frame
            {
                eprintln!(
                    "vkpath: note: --spp and --sample-count do not apply to the sample displays"
                );
            }
            check_writable(&args.output)?;
            let context = args.device.create_context()?;
            let image =
                render_sample_display(&context, sampler, args.width, args.height, args.seed)?;
            save_image(&args.output, &image, &save)?;
            fail_on_validation_messages(&context)
        }
    }
}
