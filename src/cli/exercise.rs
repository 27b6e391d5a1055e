//! `vkpath exercise NAME`: the workshop's pictures as its ShaderToy framework shows them.

use std::path::PathBuf;

use anyhow::bail;
use glam::{UVec2, Vec3};

use super::options::{parse_spp, SaveArgs};
use super::output::{fail_on_validation_messages, render_and_save, Reporting};
use super::value_error::ValueError;
use super::{parse_pixel, parse_vec3, DeviceArgs};
use crate::exercise::{
    render_brdf_sample_display, render_guide_cell_display, render_sample_display,
    workshop_frame_settings, BrdfDisplaySetup, Exercise, ExerciseKind, ExerciseSampler,
    GuideCellSetup,
};
use crate::guiding::training::GuideTraining;
use crate::image_io::output::{check_writable, save_image, SaveOptions};
use crate::image_io::tonemap::ToneMap;
use crate::render::settings::MAX_SPP;
use crate::render::settings::{PixelFilter, RenderSettings};
use crate::scene::SceneSource;

/// Arguments of `vkpath exercise`. Its defaults are the workshop's
/// (`workshop_frame_settings()`), not `render`'s, and the frame's sample count is
/// `--sample-count` as the workshop calls it. Its PNGs are clamped, as the workshop shows
/// them, so `--tonemap`'s help names that default (`EXERCISE_TONEMAP_HELP`).
#[derive(Debug, Clone, clap::Args)]
#[command(mut_arg("tonemap", |arg| arg.help(EXERCISE_TONEMAP_HELP)))]
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
    #[arg(long, value_parser = parse_spp)]
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
    /// Print only notes, warnings and errors: no device line, progress bar, summary or
    /// `wrote` line.
    #[arg(long)]
    pub quiet: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
    /// The scene, point and training of `guide-cell`.
    #[command(flatten)]
    pub guide: GuideCellArgs,
    /// The material and view of `brdf-samples` (last: its help heading applies to what
    /// follows it, so the general options above stay under "Options").
    #[command(flatten)]
    pub brdf: BrdfArgs,
}

/// `exercise`'s help for `--tonemap` (in place of `SaveArgs`' own): its default is
/// `EXERCISE_TONE_MAP`.
pub const EXERCISE_TONEMAP_HELP: &str =
    "PNG only: how exposed radiance becomes display values [default: clamp, the workshop's display]";

/// The tone map of `exercise`'s PNGs when --tonemap is not given: the workshop's display,
/// exposure then clip (PNGs byte for byte as they always were).
pub const EXERCISE_TONE_MAP: ToneMap = ToneMap::Clamp;

/// What `vkpath exercise guide-cell` shows: the scene, the pixel whose camera ray finds the
/// point, and the guide's training.
#[derive(Debug, Clone, clap::Args)]
#[command(next_help_heading = "guide-cell")]
pub struct GuideCellArgs {
    /// The scene (.gltf, .glb, .obj) [default: the built-in Cornell box].
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// The pixel "X,Y" (from the top-left) of a 64 x 64 view through the scene's camera
    /// whose ray finds the point [default: the centre, 32,32].
    #[arg(long, value_parser = parse_pixel)]
    pub pixel: Option<UVec2>,
    /// Training samples per pixel of that 64 x 64 view (as `render --guiding` trains).
    #[arg(long, default_value_t = 64)]
    pub guide_training_spp: u32,
}

/// Side of the square view through which `guide-cell` trains and picks its point.
const GUIDE_CELL_VIEW_SIDE: u32 = 64;

/// The material (glTF's metallic-roughness parameters) and view angle whose `sample_brdf`
/// samples `vkpath exercise brdf-samples` draws; what is not given is
/// `BrdfDisplaySetup::default()`'s, a white dielectric with glTF's defaults seen from 45°.
#[derive(Debug, Clone, clap::Args)]
#[command(next_help_heading = "brdf-samples")]
pub struct BrdfArgs {
    /// Metallic factor in [0, 1] (0: dielectric, 1: metal) [default: 0].
    #[arg(long, value_parser = parse_fraction)]
    pub metallic: Option<f32>,
    /// Perceptual roughness in [0, 1] (GGX alpha = roughness^2) [default: 1].
    #[arg(long, value_parser = parse_fraction)]
    pub roughness: Option<f32>,
    /// Angle between the view direction and the normal in degrees, in [0, 90) [default: 45].
    #[arg(long, value_parser = parse_view_angle)]
    pub view_angle: Option<f32>,
    /// Base colour, linear RGB in [0, 1] [default: 1,1,1].
    #[arg(long, value_parser = parse_color)]
    pub base_color: Option<Vec3>,
    /// KHR_materials_specular's specularFactor in [0, 1] [default: 1].
    #[arg(long, value_parser = parse_fraction)]
    pub specular: Option<f32>,
}

impl BrdfArgs {
    /// Whether any of the options was given.
    pub fn any_given(&self) -> bool {
        self.metallic.is_some()
            || self.roughness.is_some()
            || self.view_angle.is_some()
            || self.base_color.is_some()
            || self.specular.is_some()
    }

    /// The setup these options describe, defaults filled in.
    pub fn setup(&self) -> BrdfDisplaySetup {
        let default = BrdfDisplaySetup::default();
        let mut material = default.material;
        material.metallic = self.metallic.unwrap_or(material.metallic);
        material.roughness = self.roughness.unwrap_or(material.roughness);
        material.base_color = self.base_color.unwrap_or(material.base_color);
        material.specular = self.specular.unwrap_or(material.specular);
        match self.view_angle {
            Some(angle) => BrdfDisplaySetup::new(material, angle),
            None => BrdfDisplaySetup {
                material,
                ..default
            },
        }
    }
}

/// Parses a number in [0, 1].
fn parse_fraction(text: &str) -> Result<f32, ValueError> {
    let value: f32 = text
        .trim()
        .parse()
        .map_err(|_| ValueError::NotNumber { text: text.into() })?;
    if !(0.0..=1.0).contains(&value) {
        return Err(ValueError::OutsideUnitInterval { value });
    }
    Ok(value)
}

/// Parses a view angle in degrees in [0, 90): `sample_brdf` needs the view above the surface.
fn parse_view_angle(text: &str) -> Result<f32, ValueError> {
    let value: f32 = text
        .trim()
        .parse()
        .map_err(|_| ValueError::NotNumber { text: text.into() })?;
    if !(0.0..90.0).contains(&value) {
        return Err(ValueError::ViewBelowSurface { value });
    }
    Ok(value)
}

/// Parses "r,g,b" with every component in [0, 1].
fn parse_color(text: &str) -> Result<Vec3, ValueError> {
    let color = parse_vec3(text)?;
    if color.cmplt(Vec3::ZERO).any() || color.cmpgt(Vec3::ONE).any() {
        return Err(ValueError::ColorOutsideUnitInterval { color });
    }
    Ok(color)
}

/// Runs `vkpath exercise`.
pub fn run(args: &ExerciseArgs) -> anyhow::Result<()> {
    let save = args.save.options(EXERCISE_TONE_MAP);
    let talk = !args.quiet;
    let reporting = Reporting {
        json: false,
        quiet: args.quiet,
    };
    args.save
        .warn_unused(std::slice::from_ref(&args.output), false);
    match args.name.kind() {
        ExerciseKind::Render(integrator) => {
            if args.brdf.any_given() {
                eprintln!("vkpath: note: the material options only apply to brdf-samples");
            }
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
            let context = args.device.create_context_reporting(talk)?;
            render_and_save(
                &context,
                &scene,
                &camera,
                settings,
                &args.output,
                &save,
                reporting,
            )
        }
        ExerciseKind::GuideCell => run_guide_cell(args, &save, talk),
        ExerciseKind::Samples(sampler) => {
            if sampler != ExerciseSampler::Brdf && args.brdf.any_given() {
                eprintln!("vkpath: note: the material options only apply to brdf-samples");
            }
            if args.spp.is_some()
                || args.sample_count != workshop_frame_settings().samples_per_frame
            {
                eprintln!(
                    "vkpath: note: --spp and --sample-count do not apply to the sample displays"
                );
            }
            check_writable(&args.output)?;
            let context = args.device.create_context_reporting(talk)?;
            let image = match sampler {
                ExerciseSampler::Brdf => render_brdf_sample_display(
                    &context,
                    &args.brdf.setup(),
                    args.width,
                    args.height,
                    args.seed,
                )?,
                _ => render_sample_display(&context, sampler, args.width, args.height, args.seed)?,
            };
            save_image(&args.output, &image, &save)?;
            if talk {
                eprintln!("vkpath: wrote {}", args.output.display());
            }
            fail_on_validation_messages(&context)
        }
    }
}

/// `vkpath exercise guide-cell`: a trained guide's cell at the point a camera pixel sees,
/// beside the BSDF's samples there.
fn run_guide_cell(args: &ExerciseArgs, save: &SaveOptions, talk: bool) -> anyhow::Result<()> {
    check_writable(&args.output)?;
    let source = SceneSource::new(args.guide.scene.as_deref(), None);
    let scene = source.load()?;
    let Some(camera) = scene.camera else {
        bail!("the scene has no camera; guide-cell looks through the scene's own camera");
    };
    let setup = GuideCellSetup {
        width: GUIDE_CELL_VIEW_SIDE,
        height: GUIDE_CELL_VIEW_SIDE,
        training: GuideTraining {
            samples: args.guide.guide_training_spp,
        },
        pixel: args
            .guide
            .pixel
            .unwrap_or(UVec2::splat(GUIDE_CELL_VIEW_SIDE / 2)),
        seed: args.seed,
    };
    if !(1..=MAX_SPP).contains(&setup.training.samples) {
        bail!(
            "--guide-training-spp {} is outside 1..={MAX_SPP}",
            setup.training.samples
        );
    }
    if setup.pixel.x >= setup.width || setup.pixel.y >= setup.height {
        bail!(
            "--pixel {},{} is outside the {}x{} view",
            setup.pixel.x,
            setup.pixel.y,
            setup.width,
            setup.height
        );
    }
    let context = args.device.create_context_reporting(talk)?;
    let view =
        render_guide_cell_display(&context, &scene, &camera, &setup, args.width, args.height)?;
    save_image(&args.output, &view.image, save)?;
    if talk {
        eprintln!(
            "vkpath: wrote {} (cell {} at {}, normal {}: guide left, BSDF right)",
            args.output.display(),
            view.cell,
            view.point,
            view.normal
        );
    }
    fail_on_validation_messages(&context)
}
