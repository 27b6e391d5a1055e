//! `vkpath render`: loads a scene, renders it progressively and writes the image.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::bail;
use glam::Vec3;

use super::summary::{summary_line, RenderProgress};
use super::{parse_vec3, DeviceArgs, PixelFilterArg};
use crate::camera::Camera;
use crate::image_io::output::{check_writable, save_image, SaveOptions};
use crate::render::settings::{Accel, Integrator, LightSampling, RenderSettings, SamplerKind};
use crate::render::Renderer;
use crate::scene::Scene;

/// Arguments of `vkpath render`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// Scene file (.gltf, .glb or .obj); the workshop's Cornell box when omitted.
    pub scene: Option<PathBuf>,
    /// Instead of a scene file: the generated scale-test scene (the Cornell box with an
    /// icosphere and a displaced grid) of about this many triangles, e.g. 1000000.
    #[arg(long, conflicts_with = "scene")]
    pub generated: Option<usize>,
    /// Output image: .exr (linear radiance, 32-bit float) or .png (sRGB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 512)]
    pub height: u32,
    /// Samples per pixel in total.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Maximum number of surface hits per path (the workshop's MAX_PATH_LENGTH).
    #[arg(long, default_value_t = 5)]
    pub max_path_length: u32,
    /// Samples per pixel per frame (the workshop's SAMPLE_COUNT); the image does not depend
    /// on it. Fewer keep each dispatch short on a GPU; more amortise the per-frame cost.
    #[arg(long, default_value_t = 4)]
    pub samples_per_frame: u32,
    /// Random seed; 0 seeds exactly as the workshop does.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Sampling strategy: the workshop's uniform hemisphere sampling, cosine-weighted
    /// sampling, next event estimation, or multiple importance sampling.
    #[arg(long, value_enum, default_value_t = IntegratorArg::Workshop)]
    pub integrator: IntegratorArg,
    /// Path vertex after which Russian roulette may end a path (cosine, nee, mis); 0 turns
    /// it off. --max-path-length stays a hard limit.
    #[arg(long, default_value_t = 3)]
    pub russian_roulette_start: u32,
    /// Ray traversal: a BVH for scenes above 64 triangles (auto), the workshop's loop over
    /// all triangles (none), or always a BVH (bvh).
    #[arg(long, value_enum, default_value_t = AccelArg::Auto)]
    pub accel: AccelArg,
    /// Random numbers of cosine, nee and mis: the workshop's PCG2D (pcg) or Owen-scrambled
    /// Sobol points (sobol). The workshop integrator always uses PCG2D.
    #[arg(long, value_enum, default_value_t = SamplerArg::Pcg)]
    pub sampler: SamplerArg,
    /// How nee and mis sample a point on the chosen light: uniformly in the solid angle it
    /// subtends (solid-angle) or uniformly on its area (area).
    #[arg(long, value_enum, default_value_t = LightSamplingArg::SolidAngle)]
    pub light_sampling: LightSamplingArg,
    /// Where samples look inside a pixel.
    #[arg(long, value_enum, default_value_t = PixelFilterArg::Box)]
    pub pixel_filter: PixelFilterArg,
    /// PNG only: multiply radiance by 2^EXPOSURE before clamping to [0, 1] and sRGB encoding.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// EXR only: also store each pixel's second moment and sample count (for `vkpath compare`).
    #[arg(long)]
    pub moments: bool,
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
    #[arg(long, default_value_t = 45.0)]
    pub fov: f32,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

impl RenderArgs {
    /// The render settings these arguments describe.
    pub fn settings(&self) -> RenderSettings {
        let integrator = match self.integrator {
            IntegratorArg::Workshop => Integrator::PathTracing,
            IntegratorArg::Cosine => Integrator::Cosine,
            IntegratorArg::Nee => Integrator::Nee,
            IntegratorArg::Mis => Integrator::Mis,
        };
        RenderSettings {
            width: self.width,
            height: self.height,
            spp: self.spp,
            max_path_length: self.max_path_length,
            seed: self.seed,
            pixel_filter: self.pixel_filter.into(),
            integrator,
            samples_per_frame: self.samples_per_frame,
            russian_roulette_start: self.russian_roulette_start,
            accel: match self.accel {
                AccelArg::Auto => Accel::Auto,
                AccelArg::None => Accel::None,
                AccelArg::Bvh => Accel::Bvh,
            },
            sampler: self.sampler.into(),
            light_sampling: self.light_sampling.into(),
        }
    }
}

/// `--sampler` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SamplerArg {
    /// The workshop's PCG2D: independent random numbers.
    Pcg,
    /// Owen-scrambled Sobol points (Burley 2020): lower error at the same spp.
    Sobol,
}

impl From<SamplerArg> for SamplerKind {
    fn from(sampler: SamplerArg) -> Self {
        match sampler {
            SamplerArg::Pcg => SamplerKind::Pcg,
            SamplerArg::Sobol => SamplerKind::Sobol,
        }
    }
}

/// `--light-sampling` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LightSamplingArg {
    /// A direction uniform in the light's solid angle (Arvo 1995): less noise near lights.
    SolidAngle,
    /// A point uniform on the light's area.
    Area,
}

impl From<LightSamplingArg> for LightSampling {
    fn from(light_sampling: LightSamplingArg) -> Self {
        match light_sampling {
            LightSamplingArg::SolidAngle => LightSampling::SolidAngle,
            LightSamplingArg::Area => LightSampling::Area,
        }
    }
}

/// `--accel` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum AccelArg {
    /// A BVH above 64 triangles, else the linear loop.
    Auto,
    /// The workshop's linear loop over all triangles.
    None,
    /// Always a BVH.
    Bvh,
}

/// `--integrator` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum IntegratorArg {
    /// Uniform hemisphere sampling, exactly as the workshop's slides.
    Workshop,
    /// Cosine-weighted hemisphere sampling.
    Cosine,
    /// Next event estimation (light sampling).
    Nee,
    /// Light and cosine sampling combined with the power heuristic.
    Mis,
}

/// Loads the scene the user named, or the built-in one.
/// Most triangles `--generated` accepts (about 2 GB of scene data on the host).
pub const MAX_GENERATED_TRIANGLES: usize = 20_000_000;

/// The scene a command names: the generated scale-test scene of about `generated`
/// triangles, else `load_scene(path)`. `command` prefixes the progress line.
pub fn load_scene_source(
    path: Option<&Path>,
    generated: Option<usize>,
    command: &str,
) -> anyhow::Result<Scene> {
    let Some(triangles) = generated else {
        return load_scene(path);
    };
    if triangles > MAX_GENERATED_TRIANGLES {
        bail!("--generated {triangles}: at most {MAX_GENERATED_TRIANGLES} triangles");
    }
    let started = Instant::now();
    let scene = crate::scene::meshes::scale_test_scene(triangles)?;
    eprintln!(
        "{command}: generated {} triangles in {:.2} s",
        scene.triangles.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(scene)
}

/// A scene file, or the built-in Cornell box; prints the loader's warnings.
pub fn load_scene(path: Option<&Path>) -> anyhow::Result<Scene> {
    let scene = match path {
        Some(path) => Scene::load(path)?,
        None => Scene::builtin_cornell_box()?,
    };
    for warning in &scene.warnings {
        eprintln!("vkpath: warning: {warning}");
    }
    Ok(scene)
}

/// The camera from the command line, else the scene's.
pub fn choose_camera(args: &RenderArgs, scene: &Scene) -> anyhow::Result<Camera> {
    match (args.camera_position, args.look_at) {
        (Some(position), Some(target)) => {
            if !(args.fov > 0.0 && args.fov < 180.0) {
                bail!("--fov {} is outside (0, 180) degrees", args.fov);
            }
            let forward = target - position;
            if forward.length() == 0.0 || forward.cross(args.up).length() < 1e-6 * forward.length() * args.up.length() {
                bail!("--camera-position, --look-at and --up do not define a view (the view direction is zero or parallel to --up)");
            }
            Ok(Camera::look_at(position, target, args.up, args.fov.to_radians()))
        }
        (Some(_), None) | (None, Some(_)) => {
            bail!("--camera-position and --look-at must be given together")
        }
        (None, None) => scene.camera.ok_or_else(|| {
            let name = args.scene.as_deref().map(|p| p.display().to_string()).unwrap_or_default();
            anyhow::anyhow!("scene '{name}' has no camera: pass --camera-position X,Y,Z and --look-at X,Y,Z (and optionally --up, --fov)")
        }),
    }
}

/// Set by Ctrl-C: stop after the current batch and save what was rendered.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Runs `vkpath render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let settings = args.settings();
    settings.validate()?;
    check_writable(&args.output)?;
    let scene = load_scene_source(args.scene.as_deref(), args.generated, "vkpath render")?;
    let camera = choose_camera(args, &scene)?;
    let context = args.device.create_context()?;
    render_and_save(
        &context,
        &scene,
        &camera,
        settings,
        &args.output,
        &SaveOptions {
            exposure: args.exposure,
            moments: args.moments,
        },
    )
}

/// Renders with a progress bar, saves the image and prints the summary line. Ctrl-C stops
/// early and saves the samples taken so far.
pub fn render_and_save(
    context: &Arc<crate::vk::Context>,
    scene: &Scene,
    camera: &Camera,
    settings: RenderSettings,
    output: &Path,
    save: &SaveOptions,
) -> anyhow::Result<()> {
    // A second handler cannot be installed (e.g. in tests calling this twice); the render
    // then simply is not interruptible, which is harmless.
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
    let mut renderer = Renderer::new(context, scene, camera, settings.clone())?;
    let mut progress = RenderProgress::new(settings.spp);
    let outcome = renderer.render_to_end(|done| progress.update(done), Some(&INTERRUPTED))?;
    progress.finish();
    let (seconds, done, image) = (outcome.seconds, outcome.samples, outcome.image);
    if let Some(error) = outcome.failure {
        eprintln!("vkpath: error after {done} spp: {error}; saving what was rendered");
    }
    if let Err(error) = save_image(output, &image, save) {
        // Nothing already rendered is lost: keep it in the temp directory.
        let rescue = std::env::temp_dir().join(format!("vkpath-rescue-{}.exr", std::process::id()));
        let rescued = save_image(
            &rescue,
            &image,
            &SaveOptions {
                moments: true,
                ..*save
            },
        );
        match rescued {
            Ok(()) => bail!(
                "{error}; the render was saved to '{}' instead",
                rescue.display()
            ),
            Err(_) => bail!("{error}"),
        }
    }
    eprintln!(
        "{}",
        summary_line(
            &context.info,
            settings.width,
            settings.height,
            done,
            seconds
        )
    );
    if INTERRUPTED.load(Ordering::SeqCst) && done < settings.spp {
        bail!(
            "interrupted after {done} of {} spp; the partial render was saved to '{}'",
            settings.spp,
            output.display()
        );
    }
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
