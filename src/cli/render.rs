//! `vkpath render`: loads a scene, renders it progressively and writes the image.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::bail;
use glam::Vec3;

use super::frame_files::{check_frame_outputs, remove_stale_partials};
use super::frames::{frame_path, FrameArgs, FrameTime, UsageError};
use super::options::{parse_spp, JobArgs, RenderOptions, SaveArgs, SceneArgs};
use super::output::{
    render_job_and_save, render_on_devices_and_save, PostProcess, RenderFailure, RenderRequest,
    ReportPrinted, Reporting,
};
use super::shutter::{pose_keys, KeyTimes};
use super::summary::SequencePosition;
use super::{parse_vec3, signals, DeviceArgs};
use crate::camera::{Camera, DEFAULT_VERTICAL_FOV_DEGREES};
use crate::image_io::exr_input::check_exr_file;
use crate::image_io::output::{check_writable, ImageFormat};
use crate::image_io::tonemap::RENDER_PNG_TONE_MAP;
use crate::lights::environment_source::{EnvironmentSource, COMMAND_LINE_NAMES};
use crate::render::adaptive::{NoiseThreshold, DEFAULT_MIN_SPP};
use crate::render::aov::Aov;
use crate::render::job::{production_settings, JobOptions, DEFAULT_CHECKPOINT_INTERVAL};
use crate::render::metadata::{sampler_name, RenderMetadata};
use crate::render::motion_vectors::{FrameNeighbours, NeighbourPose};
use crate::render::region::PixelRegion;
use crate::render::sequence::SequenceCache;
use crate::render::settings::{Integrator, PixelFilter, RenderSettings};
use crate::scene::files::LoadOptions;
use crate::scene::gltf_file::{is_gltf_path, GltfFile};
use crate::scene::{framing_camera_of, Scene};

/// What `--resume` reads, for the error about a file that is not one.
pub const RESUME_READS: &str =
    "--resume reads the OpenEXR checkpoint that `vkpath render --checkpoint` writes";

/// Arguments of `vkpath render`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// The scene.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output image: .exr (linear radiance, 32-bit float) or .png (sRGB); give it more than
    /// once (-o a.exr -o a.png) to write several files from one render.
    #[arg(short, long = "output", required = true)]
    pub outputs: Vec<PathBuf>,
    /// Image width in pixels.
    #[arg(long, default_value_t = RenderSettings::default().width)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = RenderSettings::default().height)]
    pub height: u32,
    /// Samples per pixel in total.
    #[arg(long, default_value_t = RenderSettings::default().spp, value_parser = parse_spp)]
    pub spp: u32,
    /// How paths are traced.
    #[command(flatten)]
    pub render: RenderOptions,
    /// Random seed; 0 seeds exactly as the workshop does.
    #[arg(long, default_value_t = RenderSettings::default().seed)]
    pub seed: u32,
    /// Sampling strategy: the workshop's uniform hemisphere sampling, cosine-weighted
    /// sampling, next event estimation, or multiple importance sampling (the default: it
    /// sees every light and has the least noise).
    #[arg(long, value_enum, default_value_t = production_settings().integrator)]
    pub integrator: Integrator,
    /// Where samples look inside a pixel.
    #[arg(long, value_enum, default_value_t = RenderSettings::default().pixel_filter)]
    pub pixel_filter: PixelFilter,
    /// Render only these pixels of the --width x --height image: columns X0..X1 and rows
    /// Y0..Y1 (X1 and Y1 excluded), counted from the top-left. Each gets exactly the value
    /// the full render gives it. An EXR holds the region as its data window, inside a
    /// display window of the full image's size; a PNG holds the region's pixels.
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = PixelRegion::parse)]
    pub region: Option<PixelRegion>,
    /// Put the image on the device in square tiles of this many pixels a side, one at a
    /// time, and stitch them (the image is the same bit for bit). Without it, tiles are used
    /// only when the image would not fit the device's memory or image size. A render in
    /// tiles finishes each tile before the next, holding the finished image (32 bytes a
    /// pixel) but not the whole image's state, and writes nothing if stopped early; with
    /// --checkpoint, --resume, --time-limit, --preview, --tev, --guiding or a shard, every
    /// frame visits every tile instead and the host holds the state (about 5x as much).
    #[arg(long, value_name = "PIXELS")]
    pub tile_size: Option<u32>,
    /// Adaptive sampling: a pixel takes no more samples once the relative standard error of
    /// its mean (each channel's, estimated from its samples, against the brightest channel's
    /// mean) is at most T, e.g. 0.05, judged every --noise-min-spp samples; --spp is the cap. The
    /// EXR keeps each pixel's sample count (with --moments' channels). Slightly biased, as
    /// adaptive sampling is: a pixel whose first samples agree by chance stops early.
    #[arg(long, value_name = "T")]
    pub noise_threshold: Option<f32>,
    /// With --noise-threshold: samples every pixel takes before it may stop, and how often
    /// (in samples) it is judged after that (at least 2).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MIN_SPP)]
    pub noise_min_spp: u32,
    /// How the image is written.
    #[command(flatten)]
    pub save: SaveArgs,
    /// The camera, when not the scene's.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Depth of field.
    #[command(flatten)]
    pub lens: crate::cli::lens::LensArgs,
    /// Light from beyond the scene.
    #[command(flatten)]
    pub lights: LightArgs,
    /// Outputs beside the colour, as EXR layers: albedo (the first hit's base colour),
    /// normal (its shading normal, world space), depth (its distance from the camera),
    /// material (its metallic and roughness after textures, in R and G), each averaged over
    /// the pixel's samples; and ground truth from one ray through each pixel's centre,
    /// exact: object_id (the glTF node's index + 1), instance_id (the mesh copy's + 1),
    /// material_id (the material's + 1), 0 where nothing is hit, as float-exact integers
    /// (with a sidecar NAME.ids.json naming them); position (world space), uv (the first UV
    /// set), object_position (the object's own frame), z (camera-space depth); motion
    /// (layers motion_forward and motion_backward: where the hit point is seen one frame,
    /// 1 / --fps, later and earlier, minus where it is now, in pixels, x right, y down);
    /// cryptomatte (the Cryptomatte specification's CryptoObject00... and
    /// CryptoMaterial00... layers and header manifest: coverage ranked over up to 32
    /// jittered samples per pixel).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub aov: Vec<crate::render::aov::Aov>,
    /// With --aov cryptomatte: the ranks (ID, coverage) kept per pixel, 1 to 16, in
    /// ceil(N / 2) RGBA layers per kind.
    #[arg(long, value_name = "N", default_value_t = crate::render::cryptomatte::DEFAULT_CRYPTOMATTE_LEVELS)]
    pub cryptomatte_levels: u32,
    /// Denoise the image with Intel Open Image Denoise (the RT filter, HDR, guided by the
    /// albedo and normal): the EXR's colour is denoised and a `noisy` layer keeps the
    /// original; a PNG gets the denoised image.
    #[arg(long)]
    pub denoise: bool,
    /// Write each frame's camera beside each output as NAME.json: the intrinsics K (pixels)
    /// and the camera-to-world matrix in OpenCV's convention (x right, y down, z forward)
    /// and OpenGL's (x right, y up, z backward), near/far, fields of view and sensor (as
    /// `--json`'s `camera_data`).
    #[arg(long)]
    pub camera_data: bool,
    /// Time limit, checkpoints, shards and reporting.
    #[command(flatten)]
    pub job: JobArgs,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
    /// The time or frames rendered.
    #[command(flatten)]
    pub frames: FrameArgs,
    /// Motion blur.
    #[command(flatten)]
    pub shutter: crate::cli::shutter::ShutterArgs,
}

/// An environment map or a constant background around the scene.
#[derive(Debug, Clone, clap::Args)]
pub struct LightArgs {
    /// An equirectangular environment map (.exr or .hdr) that lights the scene: +Y is up and
    /// the image's centre is the direction -Z.
    #[arg(long)]
    pub environment: Option<PathBuf>,
    /// Factor on the environment map's radiance.
    #[arg(long, default_value_t = 1.0)]
    pub environment_strength: f32,
    /// Turns the environment map about +Y by this many degrees (90: what was seen looking
    /// down -Z is seen looking down -X).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub environment_rotation: f32,
    /// A constant environment of this radiance, R,G,B (default: black, nothing).
    #[arg(long, value_parser = parse_vec3, conflicts_with = "environment")]
    pub background: Option<Vec3>,
}

impl LightArgs {
    /// The environment these options ask for, if any, checked
    /// (`EnvironmentSource::from_options`).
    pub fn source(&self) -> anyhow::Result<Option<EnvironmentSource>> {
        EnvironmentSource::from_options(
            self.environment.as_deref(),
            self.environment_strength,
            self.environment_rotation,
            self.background,
            &COMMAND_LINE_NAMES,
        )
        .map_err(anyhow::Error::msg)
    }
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
    /// The file's N-th perspective camera (0: the first, the default).
    #[arg(long = "camera", conflicts_with_all = ["camera_position", "look_at"])]
    pub camera_index: Option<usize>,
}

impl RenderArgs {
    /// The render settings these arguments describe: `production_settings()` where they say
    /// nothing. The workshop's integrator has only PCG2D: it gets `pcg` (a --sampler given with
    /// it is warned about, `warn_unused_options`).
    pub fn settings(&self) -> RenderSettings {
        let settings = self.render.apply(RenderSettings {
            width: self.width,
            height: self.height,
            spp: self.spp,
            seed: self.seed,
            pixel_filter: self.pixel_filter,
            integrator: self.integrator,
            region: self.region,
            tile_size: self.tile_size,
            noise_threshold: self.noise_threshold.map(|threshold| NoiseThreshold {
                threshold,
                min_spp: self.noise_min_spp,
            }),
            ..production_settings()
        });
        settings.with_effective_sampler()
    }

    /// Warns about every option given that has no effect with the others (one line each).
    pub fn warn_unused_options(&self) {
        let warn = |line: String| eprintln!("vkpath: warning: {line}");
        self.save
            .warn_unused(&self.outputs, self.job.preview.is_some());
        let exr = self
            .outputs
            .iter()
            .any(|p| ImageFormat::from_path(p).ok() == Some(ImageFormat::Exr));
        if !self.aov.is_empty() && !exr && !self.aov.iter().any(|aov| aov.needs_exr()) {
            warn(
                "--aov has no effect: its layers go into EXR files, and no output is an EXR".into(),
            );
        }
        let integrator = self.integrator.name();
        let defaults = RenderSettings::default();
        if !self.integrator.is_importance_sampled() {
            if let Some(sampler) = self.render.sampler {
                warn(format!(
                    "--sampler {} has no effect with --integrator {integrator}: it always uses the workshop's PCG2D",
                    sampler_name(sampler)
                ));
            }
            if self.render.russian_roulette_start.is_some() {
                warn(format!(
                    "--russian-roulette-start has no effect with --integrator {integrator}: it has no Russian roulette"
                ));
            }
        }
        if !matches!(self.integrator, Integrator::Nee | Integrator::Mis)
            && self.render.light_sampling != defaults.light_sampling
        {
            warn(format!(
                "--light-sampling has no effect with --integrator {integrator}: only nee and mis sample lights"
            ));
        }
        if !matches!(self.integrator, Integrator::Nee | Integrator::Mis)
            && self.render.light_selection != defaults.light_selection
        {
            warn(format!(
                "--light-selection has no effect with --integrator {integrator}: only nee and mis sample lights"
            ));
        }
        if self.lights.environment.is_none() {
            if self.lights.environment_strength != 1.0 {
                warn("--environment-strength has no effect without --environment".into());
            }
            if self.lights.environment_rotation != 0.0 {
                warn("--environment-rotation has no effect without --environment".into());
            }
        }
        for option in self.lens.unused_without_aperture() {
            warn(format!(
                "{option} has no effect without --aperture-radius or --f-stop"
            ));
        }
        if self.camera.camera_position.is_none() {
            if self.camera.fov != DEFAULT_VERTICAL_FOV_DEGREES {
                warn("--fov has no effect without --camera-position and --look-at".into());
            }
            if self.camera.up != Vec3::Y {
                warn("--up has no effect without --camera-position and --look-at".into());
            }
        }
        if self.job.sample_range.is_some() && self.spp != defaults.spp {
            warn("--spp has no effect with --sample-range: the range decides the samples".into());
        }
        if self.frames.frames.is_none()
            && self.shutter.shutter.is_none()
            && !self.aov.contains(&Aov::Motion)
            && self.frames.fps != super::frames::DEFAULT_FPS
        {
            warn("--fps has no effect without --frames, --shutter or --aov motion".into());
        }
        for warning in self.shutter.warnings() {
            warn(warning);
        }
        if self.job.checkpoint.is_none()
            && self.job.checkpoint_interval != DEFAULT_CHECKPOINT_INTERVAL.as_secs_f64()
        {
            warn("--checkpoint-interval has no effect without --checkpoint".into());
        }
        match self.noise_threshold {
            None if self.noise_min_spp != DEFAULT_MIN_SPP => {
                warn("--noise-min-spp has no effect without --noise-threshold".into());
            }
            Some(_) if self.noise_min_spp >= self.spp && self.job.sample_range.is_none() => {
                warn(format!(
                    "--noise-threshold has no effect: --noise-min-spp {} is not below --spp {}",
                    self.noise_min_spp, self.spp
                ));
            }
            _ => {}
        }
    }

    /// Checks every file the render would write before anything is rendered: each output
    /// (`check_writable`: a known format, a regular file or a new name, never a device,
    /// FIFO, socket or directory), no output named twice, an EXR checkpoint and a PNG
    /// preview, EXR outputs for a shard; and that the checkpoint to resume is an EXR.
    fn check_files(&self, job: &JobOptions) -> anyhow::Result<()> {
        if let Some(resume) = &job.resume {
            check_exr_file(resume, Some(RESUME_READS))?;
        }
        for (index, output) in self.outputs.iter().enumerate() {
            check_writable(output)?;
            if self.outputs[..index].contains(output) {
                bail!("-o '{}' is given twice", output.display());
            }
        }
        if self.job.is_shard()
            && self
                .outputs
                .iter()
                .any(|p| ImageFormat::from_path(p).ok() != Some(ImageFormat::Exr))
        {
            bail!("a shard (--sample-range or --shard) is written as EXR, for `vkpath merge`: use .exr outputs");
        }
        if let Some(checkpoint) = &job.checkpoint {
            if ImageFormat::from_path(checkpoint).ok() != Some(ImageFormat::Exr) {
                bail!(
                    "--checkpoint '{}': a checkpoint is an EXR of the render state: use a .exr name",
                    checkpoint.display()
                );
            }
            check_writable(checkpoint)?;
            if self.outputs.contains(checkpoint) {
                bail!(
                    "--checkpoint '{}' is also an output: give it a name of its own",
                    checkpoint.display()
                );
            }
        }
        if let Some(preview) = &job.preview {
            if check_writable(&preview.path)? != ImageFormat::Png {
                bail!(
                    "the preview '{}' is a tone-mapped picture: use a .png",
                    preview.path.display()
                );
            }
            if self.outputs.contains(&preview.path) {
                bail!(
                    "--preview '{}' is also an output: give it a name of its own",
                    preview.path.display()
                );
            }
        }
        Ok(())
    }

    /// The camera from the command line, else the scene's, else one that frames the scene
    /// (which one line says when `talk` is set): `animation`'s box where a sequence gives
    /// one (`GltfFile::animation_bounds`: every frame takes the same camera), else the
    /// scene's own bounds; with the lens of the depth-of-field options (`LensArgs::apply`;
    /// `talk` says the focus distance autofocus found).
    pub fn camera(
        &self,
        scene: &Scene,
        talk: bool,
        animation: Option<(Vec3, Vec3)>,
    ) -> anyhow::Result<Camera> {
        let pinhole = self.pinhole_camera(scene, talk, animation)?;
        let (camera, autofocus) = self.lens.apply(pinhole, scene, self.width, self.height)?;
        if let (Some(distance), true) = (autofocus, talk) {
            eprintln!("vkpath: autofocus: focus distance {distance:.4}");
        }
        Ok(camera)
    }

    /// `camera` without the lens.
    fn pinhole_camera(
        &self,
        scene: &Scene,
        talk: bool,
        animation: Option<(Vec3, Vec3)>,
    ) -> anyhow::Result<Camera> {
        let CameraArgs {
            camera_position,
            look_at,
            up,
            fov,
            camera_index,
        } = self.camera;
        if let Some(index) = camera_index {
            return scene.cameras.get(index).copied().ok_or_else(|| {
                anyhow::anyhow!(
                    "--camera {index}: the scene has {} perspective camera(s), numbered from 0",
                    scene.cameras.len()
                )
            });
        }
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
                    let aspect = self.width as f32 / self.height as f32;
                    let framed = match animation {
                        Some((low, high)) => Some(framing_camera_of(low, high, aspect)),
                        None => scene.framing_camera(aspect),
                    };
                    let Some((camera, centre, radius)) = framed else {
                        bail!("the scene has no camera and nothing to frame");
                    };
                    if talk {
                        let sphere = match animation {
                            Some(_) => {
                                "the bounding sphere of its whole animation, for every frame"
                            }
                            None => "its bounding sphere",
                        };
                        eprintln!(
                        "vkpath: the scene has no camera: framing {sphere} (centre {:.3},{:.3},{:.3}, radius {radius:.3}) from +Z, 20 degrees above, vertical field of view {DEFAULT_VERTICAL_FOV_DEGREES} degrees",
                        centre.x, centre.y, centre.z
                    );
                    }
                    Ok(camera)
                }
            },
        }
    }

    /// Whether the camera comes from the command line (`--camera`, `--camera-position`).
    fn camera_given(&self) -> bool {
        self.camera.camera_index.is_some()
            || self.camera.camera_position.is_some()
            || self.camera.look_at.is_some()
    }
}

/// Runs `vkpath render`. With `--json`, a failure before the report is printed still
/// prints one JSON object on stdout (`RenderFailure`), and the error goes to `main` as
/// usual (one line on stderr, exit status 1).
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let result = render(args);
    if let Err(error) = &result {
        if args.job.json && !error.is::<ReportPrinted>() {
            let failure = RenderFailure::new(error);
            println!("{}", serde_json::to_string(&failure)?);
        }
    }
    result
}

/// `run` without the JSON report of a failure: every frame asked for, on devices opened
/// once.
fn render(args: &RenderArgs) -> anyhow::Result<()> {
    let command_started = Instant::now();
    let reporting = args.job.reporting();
    let Prepared {
        settings,
        save,
        job,
        post,
        several,
    } = args.prepare()?;
    let mut scenes = FrameScenes::new(args)?;
    // The devices are opened once, with the first frame's scene loaded: every frame after
    // it reuses them, and on each device what the frames before it left in that device's
    // `sequences` cache (pipelines, accumulation image, the scene upload while the scene's
    // data stay the same).
    let mut devices: Option<Devices> = None;
    let mut sequences: Vec<SequenceCache> = Vec::new();
    let mut first = true;
    let mut tally = SequenceTally::default();
    for frame in args.frames.frame_times() {
        let frame_started = if first {
            command_started
        } else {
            Instant::now()
        };
        let outputs = args.start_frame(frame)?;
        let scene = scenes.scene_at(args, frame, first, reporting)?;
        if first {
            warn_about_lights(&scene, &settings);
        }
        let camera = args.camera(&scene, reporting.talks() && first, scenes.animation_box)?;
        let scene = scenes.with_motion(args, frame, scene, &camera, first)?;
        let post = scenes.with_neighbours(args, frame, (&scene, &camera), &post, first)?;
        if first && !args.job.quiet {
            note_a_still_sequence(args, scenes.gltf_file.as_ref());
        }
        first = false;
        let asked = || {
            let mut asked = RenderMetadata::new(&settings, &scene, &camera, job.samples.clone());
            if args.frames.timed() {
                asked.set_frame(frame.frame, frame.time);
            }
            post.record(&mut asked);
            asked
        };
        if args.frames.skip(
            frame,
            &outputs,
            asked,
            &job.samples,
            reporting.json,
            args.job.quiet,
        ) {
            tally.skipped += 1;
            scenes.keep(scene);
            continue;
        }
        let position = args
            .frames
            .frames
            .clone()
            .filter(|f| f.len() > 1)
            .zip(frame.frame);
        if let Some((frames, number)) = &position {
            signals::set_frames_left(*number, frames);
        }
        let devices = match &mut devices {
            Some(devices) => devices,
            None => devices.insert(Devices::open(args, several.as_ref(), reporting)?),
        };
        sequences.resize_with(devices.count(), SequenceCache::default);
        for sequence in &mut sequences {
            sequence.moving_geometry = scenes.moving_geometry;
        }
        let request = RenderRequest {
            scene: &scene,
            scene_name: args.scene.name(),
            camera: &camera,
            settings: &settings,
            job: job.clone(),
            outputs: &outputs,
            save,
            reporting,
            shard: args.job.is_shard(),
            post: post.clone(),
            camera_data: args.camera_data,
            command_started: frame_started,
            frame: args.frames.timed().then_some(frame),
            position: position.map(|(frames, frame)| SequencePosition {
                frame,
                frames,
                seconds_per_frame: tally.seconds_per_frame(),
            }),
            tev: args.tev(),
            sequences: &mut sequences,
        };
        match devices {
            Devices::Several(contexts) => render_on_devices_and_save(contexts, request)?,
            Devices::One(context) => render_job_and_save(context, request)?,
        }
        // The frame is finished (a stop by a signal ended the command): what a stopped
        // render of it left beside its outputs is stale.
        if frame.frame.is_some() {
            remove_stale_partials(&outputs, frame, !args.job.quiet);
        }
        tally.rendered.push(frame_started.elapsed().as_secs_f64());
        scenes.keep(scene);
    }
    if let (Some(frames), true) = (&args.frames.frames, reporting.talks()) {
        tally.say_closing_line(frames, command_started);
    }
    Ok(())
}

/// What a render command decides before its first frame.
struct Prepared {
    /// The render settings.
    settings: RenderSettings,
    /// How the images are written.
    save: crate::image_io::output::SaveOptions,
    /// The job's options (every frame's).
    job: JobOptions<'static>,
    /// What happens to each finished image.
    post: PostProcess,
    /// The devices `--device` lists, when it names several (`DeviceArgs::several`).
    several: Option<(Vec<String>, String)>,
}

impl RenderArgs {
    /// The settings, job and post-processing these arguments ask for, checked with every
    /// file the render would write, before anything is loaded; installs the signal
    /// handlers (from here a signal ends the command at once, writing nothing, until the
    /// first sample) and warns about the options that have no effect.
    fn prepare(&self) -> anyhow::Result<Prepared> {
        let settings = self.settings();
        if settings.medium.is_some() && !settings.integrator.is_importance_sampled() {
            return Err(UsageError(format!("--medium: --integrator {} renders no media (the workshop's integrator stays the workshop's): use cosine, nee or mis", settings.integrator.name())).into());
        }
        settings.validate()?;
        let save = self.save.options(RENDER_PNG_TONE_MAP);
        let job = self.job.options(settings.spp, save)?;
        self.frames.check_outputs(&self.outputs)?;
        self.check_files(&job)?;
        if let Some(frames) = &self.frames.frames {
            check_frame_outputs(&self.outputs, frames)?;
        }
        if self.frames.frames.as_ref().is_some_and(|f| f.len() > 1)
            && (job.checkpoint.is_some() || job.resume.is_some())
        {
            return Err(UsageError("--checkpoint and --resume belong to one frame: render frames one at a time to use them".into()).into());
        }
        // From here a signal ends the command at once, writing nothing, until the first sample.
        let files: Vec<&std::path::Path> = self.outputs.iter().map(PathBuf::as_path).collect();
        signals::install(&files)?;
        self.warn_unused_options();
        let post = PostProcess {
            aovs: self.aov.clone(),
            denoise: self.denoise,
            neighbours: None,
            cryptomatte: crate::render::cryptomatte::CryptomatteOptions {
                levels: self.cryptomatte_levels,
                // Every shard takes the whole render's samples (--spp), 0.., for its coverage
                samples: self
                    .job
                    .is_shard()
                    .then(|| crate::render::cryptomatte::cryptomatte_samples(self.spp)),
            },
        };
        let averaged = post.aovs.iter().find(|aov| !aov.goes_into_shards());
        if self.job.is_shard() && (post.denoise || averaged.is_some()) {
            let what = averaged.map_or("--denoise".to_owned(), |aov| {
                format!("--aov {}", aov.name())
            });
            bail!("{what} works on whole renders: merge the shards first (the ground truth and cryptomatte go into every shard)");
        }
        // The devices, listed once (only `all` or a list asks Vulkan for them).
        let several = self.device.several()?;
        self.check_combinations(&settings, &job, &post, several.is_some())?;
        Ok(Prepared {
            settings,
            save,
            job,
            post,
            several,
        })
    }

    /// The outputs of `frame`, with the signal handlers installed for them. Each frame
    /// starts as the command does: a signal before its first sample ends the command at
    /// once, writing nothing of this frame (earlier frames are complete), so that a
    /// re-queued task with --skip-existing renders it again.
    fn start_frame(&self, frame: FrameTime) -> anyhow::Result<Vec<PathBuf>> {
        let outputs: Vec<PathBuf> = self
            .outputs
            .iter()
            .map(|o| frame_path(o, frame.frame))
            .collect();
        signals::RENDERING.store(false, std::sync::atomic::Ordering::SeqCst);
        let files: Vec<&std::path::Path> = outputs.iter().map(PathBuf::as_path).collect();
        signals::install(&files)?;
        Ok(outputs)
    }

    /// Where the live view goes (`--tev HOST:PORT`) and how often, if anywhere.
    fn tev(&self) -> Option<(String, std::time::Duration)> {
        self.job.tev.clone().map(|address| {
            (
                address,
                std::time::Duration::from_secs_f64(self.job.tev_interval),
            )
        })
    }

    /// Refuses the combinations of options that cannot render together (after post-processing
    /// with shards): adaptive sampling or guiding with shards, what several devices cannot do, a missing
    /// denoiser, an animation of a scene that has none.
    fn check_combinations(
        &self,
        settings: &RenderSettings,
        job: &JobOptions,
        post: &PostProcess,
        several: bool,
    ) -> anyhow::Result<()> {
        let shard = self.job.is_shard();
        if settings.noise_threshold.is_some() && (shard || several) {
            bail!("--noise-threshold decides per pixel how many of all the samples it takes: it cannot be split into shards or over several devices");
        }
        if settings.guiding.is_some() && shard && self.render.guide_training_spp.is_none() {
            bail!("--guiding with shards needs --guide-training-spp: every shard must train the same guide as the whole render (its default depends on --spp, which differs per shard)");
        }
        if self.denoise {
            crate::denoise::available()?;
        }
        if let Some(id) = self.aov.iter().find(|aov| aov.needs_exr()) {
            let exr = self
                .outputs
                .iter()
                .any(|p| ImageFormat::from_path(p).ok() == Some(ImageFormat::Exr));
            if !exr && id.is_id() {
                return Err(UsageError(format!("--aov {}: IDs are exact integers, which a PNG cannot hold: write an EXR output (-o NAME.exr) or use Python's vkpath.render", id.name())).into());
            }
            if !exr {
                return Err(UsageError("--aov cryptomatte: its ID layers and manifest live in an EXR (its layers and header), which a PNG cannot hold: write an EXR output (-o NAME.exr) or use Python's vkpath.render".into()).into());
            }
        }
        if let Err(crate::error::Error::InvalidSettings(line)) =
            crate::render::cryptomatte::check_levels(self.cryptomatte_levels)
        {
            return Err(UsageError(line).into());
        }
        if several {
            if job.checkpoint.is_some() || job.resume.is_some() || job.preview.is_some() {
                bail!("--checkpoint, --resume and --preview work with one device; render on several with shards instead");
            }
            if self.job.tev.is_some() {
                return Err(UsageError("--tev works with one device".into()).into());
            }
            if !post.is_empty() {
                bail!("--aov and --denoise work with one device");
            }
        }
        if let Some(animation) = &self.frames.animation {
            if self.gltf_path().is_none() {
                bail!("--animation {animation}: only glTF scenes (.gltf, .glb) have animations");
            }
        }
        Ok(())
    }

    /// The scene's file when it is a glTF file (the only scenes that move with time).
    fn gltf_path(&self) -> Option<PathBuf> {
        match self.scene.source() {
            crate::scene::source::SceneSource::File(path) if is_gltf_path(&path) => Some(path),
            _ => None,
        }
    }
}

/// The scenes of the frames: only glTF files move with time: one is read once and posed for
/// each frame (`GltfFile`); any other scene is loaded once and kept for every frame.
struct FrameScenes {
    /// The scene's glTF file, if it is one.
    gltf_path: Option<PathBuf>,
    /// The environment the command line asks for.
    environment: Option<EnvironmentSource>,
    /// The scene of the frame before, when it is not a glTF file (the same for every frame).
    still: Option<Scene>,
    /// The glTF file, read for the first frame.
    gltf_file: Option<GltfFile>,
    /// The environment as the first frame loaded it (a map is read and decoded once), for
    /// the frames of a glTF file after it.
    loaded_environment: Option<Option<crate::lights::Environment>>,
    /// What `--frames` decides once for a glTF file's whole sequence (on its first frame
    /// rendered, from the file alone, so that every task of a farm decides alike): whether
    /// its geometry moves (`--accel auto` then keeps the BVH: `SequenceCache`) ...
    moving_geometry: bool,
    /// ... and for a file without a camera the box of its whole animation, which frames
    /// every frame.
    animation_box: Option<(Vec3, Vec3)>,
}

impl FrameScenes {
    /// `scene`, the frame's, with motion blur's keys when `--shutter` asks for them and the
    /// scene moves across the shutter: the glTF file posed at each key's time, each key with
    /// its own camera (the command line's or the file's at that time; a camera that frames
    /// the scene keeps `camera`'s framing). A scene that does not move gets none, and the
    /// first frame says so once (the image is the still one).
    fn with_motion(
        &mut self,
        args: &RenderArgs,
        frame: FrameTime,
        scene: Scene,
        camera: &Camera,
        first: bool,
    ) -> anyhow::Result<Scene> {
        let Some(shutter) = args.shutter.shutter() else {
            return Ok(scene);
        };
        let note = first_frame_note(args, first, "--shutter", "the image is the still one");
        let key_camera = pose_camera(args, &scene, camera, self.animation_box);
        let Some(file) = self.animated_file() else {
            note("the scene has no animation");
            return Ok(scene);
        };
        let keys = KeyTimes {
            time: frame.time,
            fps: args.frames.fps,
        };
        let Some(motion) = pose_keys(file, shutter, keys, &args.frames.pick(), key_camera)? else {
            note("nothing in the scene moves across the shutter");
            return Ok(scene);
        };
        Ok(Scene {
            motion: Some(motion),
            ..scene
        })
    }

    /// `post` for the frame (`scene` seen by `camera`), with its neighbours for `--aov
    /// motion` (`neighbours`).
    fn with_neighbours(
        &mut self,
        args: &RenderArgs,
        frame: FrameTime,
        (scene, camera): (&Scene, &Camera),
        post: &PostProcess,
        first: bool,
    ) -> anyhow::Result<PostProcess> {
        Ok(PostProcess {
            neighbours: self.neighbours(args, frame, (scene, camera), post, first)?,
            ..post.clone()
        })
    }

    /// The frame's scene one frame interval before and after it, for `--aov motion` (`None`
    /// without it, or where nothing moves: the first frame then says once that the motion
    /// vectors are 0). Each neighbour has its own camera as `with_motion`'s keys have.
    fn neighbours(
        &mut self,
        args: &RenderArgs,
        frame: FrameTime,
        (scene, camera): (&Scene, &Camera),
        post: &PostProcess,
        first: bool,
    ) -> anyhow::Result<Option<Arc<FrameNeighbours>>> {
        if !post.aovs.contains(&Aov::Motion) {
            return Ok(None);
        }
        let note = first_frame_note(args, first, "--aov motion", "the motion vectors are 0");
        let neighbour_camera = pose_camera(args, scene, camera, self.animation_box);
        let Some(file) = self.animated_file() else {
            note("the scene has no animation");
            return Ok(None);
        };
        let mut pose = |time: f64| -> anyhow::Result<NeighbourPose> {
            let posed = file.pose(time as f32, &args.frames.pick())?;
            Ok(NeighbourPose::new(time, &posed, neighbour_camera(&posed)?))
        };
        let interval = 1.0 / args.frames.fps;
        let previous = pose(frame.time - interval)?;
        let next = pose(frame.time + interval)?;
        let neighbours = FrameNeighbours::new(scene.triangles.len(), previous, next)?;
        if neighbours.is_still(scene, camera) {
            note("nothing in the scene moves between the frames around it");
            return Ok(None);
        }
        Ok(Some(Arc::new(neighbours)))
    }

    /// The scene's glTF file where it has animations (read for the first frame), else `None`:
    /// nothing moves at other times than the frame's.
    fn animated_file(&mut self) -> Option<&mut GltfFile> {
        self.gltf_file.as_mut().filter(|file| file.has_animations())
    }

    /// Nothing loaded yet, for the scene and environment `args` name.
    fn new(args: &RenderArgs) -> anyhow::Result<FrameScenes> {
        Ok(FrameScenes {
            gltf_path: args.gltf_path(),
            environment: args.lights.source()?,
            still: None,
            gltf_file: None,
            loaded_environment: None,
            moving_geometry: false,
            animation_box: None,
        })
    }

    /// Keeps a frame's scene for the next frame, unless it is posed per frame.
    fn keep(&mut self, scene: Scene) {
        if self.gltf_path.is_none() {
            self.still = Some(scene);
        }
    }

    /// The scene of `frame`, with the environment (`first`: the first frame, which reads
    /// the file and says what it loaded).
    fn scene_at(
        &mut self,
        args: &RenderArgs,
        frame: FrameTime,
        first: bool,
        reporting: Reporting,
    ) -> anyhow::Result<Scene> {
        if let Some(scene) = self.still.take() {
            return Ok(scene);
        }
        let Some(path) = &self.gltf_path else {
            return Ok(args
                .scene
                .load_at(
                    "vkpath render",
                    reporting.talks() && first,
                    first,
                    frame.time as f32,
                    args.frames.pick(),
                )?
                .with_environment(self.environment.as_ref())?);
        };
        let started = Instant::now();
        let file = match &mut self.gltf_file {
            Some(file) => file,
            None => self.gltf_file.insert(GltfFile::open(
                path,
                &LoadOptions {
                    allow_external_paths: args.scene.allow_external_paths,
                    variant: args.scene.variant.clone(),
                    ..LoadOptions::default()
                },
            )?),
        };
        let scene = file.pose(frame.time as f32, &args.frames.pick())?;
        log::debug!(
            "scene {}posed in {:.3} s",
            if first { "read and " } else { "" },
            started.elapsed().as_secs_f64()
        );
        for warning in scene.warnings.iter().filter(|_| first) {
            eprintln!("vkpath: warning: {warning}");
        }
        if first && args.frames.frames.is_some() {
            let pick = args.frames.pick();
            self.moving_geometry = file.moves_geometry(&pick)?;
            if scene.camera.is_none() && !args.camera_given() {
                self.animation_box = file.animation_bounds(&pick)?;
            }
        }
        Ok(match &self.loaded_environment {
            Some(loaded) => Scene {
                environment: loaded.clone(),
                ..scene
            },
            None => {
                let scene = scene.with_environment(self.environment.as_ref())?;
                self.loaded_environment = Some(scene.environment.clone());
                scene
            }
        })
    }
}

/// What the frames of a sequence did, for the time left and its closing line.
#[derive(Default)]
struct SequenceTally {
    /// Seconds each rendered frame took, set-up included, in order.
    rendered: Vec<f64>,
    /// Frames `--skip-existing` left alone.
    skipped: u32,
}

impl SequenceTally {
    /// What a frame takes: the mean over the rendered frames after the first (which opened
    /// the device and built the kernels), else the first's; `None` before any.
    fn seconds_per_frame(&self) -> Option<f64> {
        let later = self.rendered.get(1..).filter(|later| !later.is_empty());
        let frames = later.or(self.rendered.get(..1).filter(|f| !f.is_empty()))?;
        Some(frames.iter().sum::<f64>() / frames.len() as f64)
    }

    /// Prints the closing line of a sequence of several frames (`line`).
    fn say_closing_line(&self, frames: &std::ops::Range<u32>, command_started: Instant) {
        if frames.len() > 1 {
            eprintln!(
                "{}",
                self.line(frames, command_started.elapsed().as_secs_f64())
            );
        }
    }

    /// The sequence's closing line: "vkpath: frames 0..10: 10 in 12.34 s (8 rendered,
    /// 1.45 s a frame after the first; 2 skipped)".
    fn line(&self, frames: &std::ops::Range<u32>, seconds: f64) -> String {
        let per_frame = match self.seconds_per_frame() {
            Some(each) if self.rendered.len() > 1 => {
                format!(", {each:.2} s a frame after the first")
            }
            Some(each) => format!(", {each:.2} s"),
            None => String::new(),
        };
        let skipped = match self.skipped {
            0 => String::new(),
            n => format!("; {n} skipped"),
        };
        format!(
            "vkpath: frames {}..{}: {} in {seconds:.2} s ({} rendered{per_frame}{skipped})",
            frames.start,
            frames.end,
            frames.len(),
            self.rendered.len()
        )
    }
}

/// Says once, for `--frames`, that the scene does not move: it has no animation (not a glTF
/// file, or one without animations), so every frame is the same image.
/// The camera that sees the scene posed at another time than the frame's (motion blur's keys,
/// the motion vectors' neighbours): with a camera of its own (the scene's, `frame_scene`'s,
/// or the command line's) that time's, lens and all (`RenderArgs::camera`); else the frame's
/// `camera`, so that a camera that frames the scene keeps the frame's framing.
fn pose_camera<'a>(
    args: &'a RenderArgs,
    frame_scene: &Scene,
    camera: &'a Camera,
    animation_box: Option<(Vec3, Vec3)>,
) -> impl Fn(&Scene) -> anyhow::Result<Camera> + 'a {
    let own_camera = frame_scene.camera.is_some() || args.camera_given();
    move |posed: &Scene| match own_camera {
        true => args.camera(posed, false, animation_box),
        false => Ok(*camera),
    }
}

/// A note `option` writes once, on the first frame (`first`) and unless `--quiet`: why the
/// scene does not move for it, and so what (`outcome`).
fn first_frame_note<'a>(
    args: &'a RenderArgs,
    first: bool,
    option: &'a str,
    outcome: &'a str,
) -> impl Fn(&str) + 'a {
    move |why: &str| {
        if first && !args.job.quiet {
            eprintln!("vkpath: note: {option}: {why}, so {outcome}");
        }
    }
}

fn note_a_still_sequence(args: &RenderArgs, gltf: Option<&GltfFile>) {
    let Some(frames) = &args.frames.frames else {
        return;
    };
    if gltf.is_some_and(GltfFile::has_animations) {
        return;
    }
    let same = match frames.len() {
        1 => "its frame is the scene as it stands".to_string(),
        n => format!("its {n} frames are the same image"),
    };
    eprintln!("vkpath: note: --frames: the scene has no animation, so {same}");
}

/// The devices a sequence renders on, opened for its first frame.
enum Devices {
    /// `--device` named one (or none: the default).
    One(std::sync::Arc<crate::vk::Context>),
    /// `--device` named several.
    Several(Vec<std::sync::Arc<crate::vk::Context>>),
}

impl Devices {
    /// Opens the devices `--device` names: `several`'s selectors (with why they were
    /// chosen), else one.
    fn open(
        args: &RenderArgs,
        several: Option<&(Vec<String>, String)>,
        reporting: Reporting,
    ) -> anyhow::Result<Devices> {
        Ok(match several {
            Some((selectors, reason)) => Devices::Several(args.device.create_contexts(
                selectors,
                reason,
                reporting.talks(),
            )?),
            None => Devices::One(args.device.create_context_reporting(reporting.talks())?),
        })
    }

    /// How many devices there are.
    fn count(&self) -> usize {
        match self {
            Devices::Several(contexts) => contexts.len(),
            Devices::One(_) => 1,
        }
    }
}

/// Warns that nothing lights the scene, or that its punctual lights are invisible to the
/// integrator.
fn warn_about_lights(scene: &Scene, settings: &RenderSettings) {
    if !scene.emits_light() {
        eprintln!(
            "vkpath: warning: nothing lights the scene (no emissive surface, punctual light, --environment or --background): the image will be black"
        );
    }
    if !scene.punctual_lights.is_empty()
        && !matches!(settings.integrator, Integrator::Nee | Integrator::Mis)
    {
        eprintln!(
            "vkpath: warning: the scene's {} punctual lights are invisible to --integrator {}: only nee and mis sample them",
            scene.punctual_lights.len(),
            settings.integrator.name()
        );
    }
}
