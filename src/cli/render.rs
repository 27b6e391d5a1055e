//! `vkpath render`: loads a scene, renders it progressively and writes the image.

use std::path::{Path, PathBuf};

use anyhow::bail;
use glam::Vec3;

use super::options::{JobArgs, RenderOptions, SaveArgs, SceneArgs};
use super::output::{render_job_and_save, render_on_devices_and_save};
use super::{parse_vec3, DeviceArgs};
use crate::camera::{Camera, DEFAULT_VERTICAL_FOV_DEGREES};
use crate::image_io::output::{check_writable, ImageFormat};
use crate::image_io::tonemap::RENDER_PNG_TONE_MAP;
use crate::render::settings::{Integrator, PixelFilter, RenderSettings};
use crate::scene::Scene;

/// Arguments of `vkpath render`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output image: .exr (linear radiance, 32-bit float) or .png (sRGB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = RenderSettings::default().width)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = RenderSettings::default().height)]
    pub height: u32,
    /// Samples per pixel in total.
    #[arg(long, default_value_t = RenderSettings::default().spp)]
    pub spp: u32,
    /// How paths are traced.
    #[command(flatten)]
    pub render: RenderOptions,
    /// Random seed; 0 seeds exactly as the workshop does.
    #[arg(long, default_value_t = RenderSettings::default().seed)]
    pub seed: u32,
    /// Sampling strategy: the workshop's uniform hemisphere sampling, cosine-weighted
    /// sampling, next event estimation, or multiple importance sampling.
    #[arg(long, value_enum, default_value_t = RenderSettings::default().integrator)]
    pub integrator: Integrator,
    /// Where samples look inside a pixel.
    #[arg(long, value_enum, default_value_t = RenderSettings::default().pixel_filter)]
    pub pixel_filter: PixelFilter,
    /// How the image is written.
    #[command(flatten)]
    pub save: SaveArgs,
    /// The camera, when not the scene's.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Time limit, checkpoints, shards and reporting.
    #[command(flatten)]
    pub job: JobArgs,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// A look-at camera in place of the scene's.
#[derive(Debug, Clone, clap::Args)]
pub struct CameraArgs {
    /// Camera position x,y,z (overrides the scene's camera; needed for OBJ).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub camera_position: Option<Vec3>,
    /// Point the camera looks at, x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub look_at: Option<Vec3>,
    /// Camera up direction x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,1,0")]
    pub up: Vec3,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = DEFAULT_VERTICAL_FOV_DEGREES)]
    pub fov: f32,
}

impl RenderArgs {
    /// The render settings these arguments describe.
    pub fn settings(&self) -> RenderSettings {
        self.render.apply(RenderSettings {
            width: self.width,
            height: self.height,
            spp: self.spp,
            seed: self.seed,
            pixel_filter: self.pixel_filter,
            integrator: self.integrator,
            ..RenderSettings::default()
        })
    }

    /// The camera from the command line, else the scene's.
    pub fn camera(&self, scene: &Scene) -> anyhow::Result<Camera> {
        let CameraArgs {
            camera_position,
            look_at,
            up,
            fov,
        } = self.camera;
        match (camera_position, look_at) {
            (Some(position), Some(target)) => {
                Ok(Camera::look_at_checked(position, target, up, fov)?)
            }
            (Some(_), None) | (None, Some(_)) => {
                bail!("--camera-position and --look-at must be given together")
            }
            (None, None) => match scene.camera {
                Some(camera) => Ok(camera),
                None => {
                    let name = self.scene.scene.as_deref().unwrap_or(Path::new(""));
                    bail!(
                        "scene '{}' has no camera: pass --camera-position X,Y,Z and \
                         --look-at X,Y,Z (and optionally --up, --fov)",
                        name.display()
                    )
                }
            },
        }
    }
}

/// Runs `vkpath render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let settings = args.settings();
    settings.validate()?;
    let save = args.save.options(RENDER_PNG_TONE_MAP);
    let job = args.job.options(settings.spp, save)?;
    check_writable(&args.output)?;
    let shard = args.job.is_shard();
    if shard
        && !args
            .output
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
    {
        bail!("a shard (--sample-range or --shard) is written as EXR, for `vkpath merge`: use an .exr output");
    }
    if let Some(checkpoint) = &job.checkpoint {
        check_writable(checkpoint)?;
    }
    if let Some(preview) = &job.preview {
        if check_writable(&preview.path)? != ImageFormat::Png {
            bail!(
                "the preview '{}' is a tone-mapped picture: use a .png",
                preview.path.display()
            );
        }
    }
    let scene = args.scene.load("vkpath render")?;
    if !scene.emits_light() {
        eprintln!("vkpath: warning: nothing in the scene emits light: the image will be black");
    }
    let camera = args.camera(&scene)?;
    if let Some(selectors) = args.device.several()? {
        if job.checkpoint.is_some() || job.resume.is_some() || job.preview.is_some() {
            bail!("--checkpoint, --resume and --preview work with one device; render on several with shards instead");
        }
        let contexts = args.device.create_contexts(&selectors)?;
        return render_on_devices_and_save(
            &contexts,
            &scene,
            &camera,
            &settings,
            job,
            &args.output,
            &save,
            args.job.reporting(),
            shard,
        );
    }
    let context = args.device.create_context()?;
    render_job_and_save(
        &context,
        &scene,
        &camera,
        &settings,
        job,
        &args.output,
        &save,
        args.job.reporting(),
        shard,
    )
}
