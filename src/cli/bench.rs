//! `vkpath bench`: the integrators side by side on a fixed scene (see `crate::bench`).

use std::path::PathBuf;

use anyhow::bail;

use super::render::{load_scene_source, AccelArg, IntegratorArg, LightSamplingArg, SamplerArg};
use super::DeviceArgs;
use crate::bench::{format_table, run_bench, BenchSetup};
use crate::render::settings::{Accel, Integrator, RenderSettings};

/// Arguments of `vkpath bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchArgs {
    /// Scene file (.gltf, .glb or .obj with a camera); the workshop's Cornell box when omitted.
    pub scene: Option<PathBuf>,
    /// Instead of a scene file: the generated scale-test scene (the Cornell box with an
    /// icosphere and a displaced grid) of about this many triangles, e.g. 1000000.
    #[arg(long, conflicts_with = "scene")]
    pub generated: Option<usize>,
    /// Ray traversal: auto (BVH above 64 triangles), none (linear loop) or bvh.
    #[arg(long, value_enum, default_value_t = AccelArg::Auto)]
    pub accel: AccelArg,
    /// Random numbers of cosine, nee and mis: pcg (the workshop's PCG2D) or sobol
    /// (Owen-scrambled Sobol points); the workshop integrator always uses PCG2D.
    #[arg(long, value_enum, default_value_t = SamplerArg::Pcg)]
    pub sampler: SamplerArg,
    /// How nee and mis sample a point on the chosen light: solid-angle or area.
    #[arg(long, value_enum, default_value_t = LightSamplingArg::SolidAngle)]
    pub light_sampling: LightSamplingArg,
    /// Image width in pixels.
    #[arg(long, default_value_t = 64)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 64)]
    pub height: u32,
    /// Samples per pixel of each measured render.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Samples per pixel of the reference (rendered with mis); its own error adds
    /// 1/(reference_spp/spp) of a same-strategy render's to every relMSE.
    #[arg(long, default_value_t = 4096)]
    pub reference_spp: u32,
    /// Maximum number of surface hits per path.
    #[arg(long, default_value_t = 5)]
    pub max_path_length: u32,
    /// Path vertex after which Russian roulette may end a path (cosine, nee, mis); 0: off.
    #[arg(long, default_value_t = 3)]
    pub russian_roulette_start: u32,
    /// Samples per pixel per frame.
    #[arg(long, default_value_t = 4)]
    pub samples_per_frame: u32,
    /// Integrators to measure, in order; efficiency ratios are relative to the first.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "workshop,cosine,nee,mis"
    )]
    pub integrators: Vec<IntegratorArg>,
    /// Timed renders per integrator; the fastest counts.
    #[arg(long, default_value_t = 3)]
    pub repeats: u32,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// Runs `vkpath bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if args.integrators.is_empty() {
        bail!("--integrators is empty");
    }
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        spp: args.spp,
        max_path_length: args.max_path_length,
        samples_per_frame: args.samples_per_frame,
        russian_roulette_start: args.russian_roulette_start,
        accel: match args.accel {
            AccelArg::Auto => Accel::Auto,
            AccelArg::None => Accel::None,
            AccelArg::Bvh => Accel::Bvh,
        },
        sampler: args.sampler.into(),
        light_sampling: args.light_sampling.into(),
        ..Default::default()
    };
    settings.validate()?;
    RenderSettings {
        spp: args.reference_spp,
        ..settings.clone()
    }
    .validate()?;
    let scene = load_scene_source(args.scene.as_deref(), args.generated, "vkpath bench")?;
    let Some(camera) = scene.camera else {
        bail!("the scene has no camera; bench needs a scene with its own camera (glTF or the built-in one)");
    };
    let context = args.device.create_context()?;
    let setup = BenchSetup {
        repeats: args.repeats,
        settings,
        reference_spp: args.reference_spp,
        integrators: args
            .integrators
            .iter()
            .map(|arg| match arg {
                IntegratorArg::Workshop => Integrator::PathTracing,
                IntegratorArg::Cosine => Integrator::Cosine,
                IntegratorArg::Nee => Integrator::Nee,
                IntegratorArg::Mis => Integrator::Mis,
            })
            .collect(),
        scene_name: match (&args.scene, args.generated) {
            (Some(path), _) => path.display().to_string(),
            (None, Some(_)) => "generated scale-test scene".into(),
            (None, None) => "workshop Cornell box".into(),
        },
    };
    let report = run_bench(&context, &scene, &camera, &setup, |what| {
        eprintln!("vkpath bench: {what}")
    })?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", format_table(&report));
    }
    Ok(())
}
