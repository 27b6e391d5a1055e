//! `vkpath bench`: the integrators side by side on a fixed scene (see `crate::bench`).

use std::sync::LazyLock;

use anyhow::bail;
use clap::ValueEnum;

use super::options::{RenderOptions, SceneArgs};
use super::DeviceArgs;
use crate::bench::{format_table, run_bench, BenchSetup};
use crate::render::settings::{Integrator, RenderSettings};

/// Arguments of `vkpath bench`. Its defaults are `BenchSetup::default()`'s: a smaller image
/// than `render`'s, and a list of integrators instead of one.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchArgs {
    /// The scene; a scene file needs a camera of its own (glTF).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Image width in pixels.
    #[arg(long, default_value_t = BenchSetup::default().settings.width)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = BenchSetup::default().settings.height)]
    pub height: u32,
    /// Samples per pixel of each measured render.
    #[arg(long, default_value_t = BenchSetup::default().settings.spp)]
    pub spp: u32,
    /// Samples per pixel of the reference (rendered with mis); its own error adds
    /// 1/(reference_spp/spp) of a same-strategy render's to every relMSE.
    #[arg(long, default_value_t = BenchSetup::default().reference_spp)]
    pub reference_spp: u32,
    /// How paths are traced.
    #[command(flatten)]
    pub render: RenderOptions,
    /// Integrators to measure, in order; efficiency ratios are relative to the first.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = DEFAULT_INTEGRATORS.as_str()
    )]
    pub integrators: Vec<Integrator>,
    /// Timed renders per integrator; the fastest counts.
    #[arg(long, default_value_t = BenchSetup::default().repeats)]
    pub repeats: u32,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// `BenchSetup::default().integrators` as `--integrators` spells them: "workshop,cosine,...".
static DEFAULT_INTEGRATORS: LazyLock<String> = LazyLock::new(|| {
    let names: Vec<String> = BenchSetup::default()
        .integrators
        .iter()
        .filter_map(|integrator| integrator.to_possible_value())
        .map(|value| value.get_name().to_owned())
        .collect();
    names.join(",")
});

/// Runs `vkpath bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if args.integrators.is_empty() {
        bail!("--integrators is empty");
    }
    let settings = args.render.apply(RenderSettings {
        width: args.width,
        height: args.height,
        spp: args.spp,
        ..RenderSettings::default()
    });
    settings.validate()?;
    RenderSettings {
        spp: args.reference_spp,
        ..settings.clone()
    }
    .validate()?;
    let source = args.scene.source();
    let scene = args.scene.load("vkpath bench")?;
    let Some(camera) = scene.camera else {
        bail!("the scene has no camera; bench needs a scene with its own camera (glTF or the built-in one)");
    };
    let context = args.device.create_context()?;
    let setup = BenchSetup {
        repeats: args.repeats,
        settings,
        reference_spp: args.reference_spp,
        integrators: args.integrators.clone(),
        scene_name: source.description(),
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
