//! `vkpath bench`: the integrators side by side on a fixed scene (see `crate::bench`).

use std::sync::LazyLock;

use anyhow::bail;
use clap::ValueEnum;

use super::options::{parse_spp, RenderOptions, SceneArgs};
use super::DeviceArgs;
use crate::bench::{format_table, run_bench, BenchSetup};
use crate::render::settings::{Integrator, LightSelection, RenderSettings};

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
    #[arg(long, default_value_t = BenchSetup::default().settings.spp, value_parser = parse_spp)]
    pub spp: u32,
    /// Samples per pixel of the reference (rendered with mis); its own error adds
    /// 1/(reference_spp/spp) of a same-strategy render's to every relMSE.
    #[arg(long, default_value_t = BenchSetup::default().reference_spp, value_parser = parse_spp)]
    pub reference_spp: u32,
    /// Measure against this stored reference (an EXR of the same size, best written by
    /// `vkpath render --moments` at many spp) instead of rendering one: a reference far
    /// better than the renders, rendered once for many benches.
    #[arg(long, value_name = "EXR", conflicts_with = "reference_spp")]
    pub reference: Option<std::path::PathBuf>,
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
    /// Light selections to measure each integrator with, in order, against the same
    /// reference (e.g. `power,tree`); without it, `--light-selection`'s alone.
    #[arg(long, value_enum, value_delimiter = ',')]
    pub light_selections: Option<Vec<LightSelection>>,
    /// Timed renders per integrator; the fastest counts.
    #[arg(long, default_value_t = BenchSetup::default().repeats)]
    pub repeats: u32,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Measure start-up instead: whole `vkpath render` processes of 1 spp, cold (empty
    /// pipeline and driver caches) against warm, on the scene as it is and under a white
    /// sky (`--background 1,1,1`, the glTF-material kernels), with the first integrator.
    #[arg(long)]
    pub startup: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
    /// Motion blur: the glTF scene's shutter around time 0 at 24 frames per second (each
    /// key's camera the file's), to measure what the blur costs.
    #[command(flatten)]
    pub shutter: super::shutter::ShutterArgs,
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

/// `render`'s arguments for the scene, size, path options, first integrator and device of
/// `args` (for `--startup`).
fn startup_render_args(args: &BenchArgs) -> Vec<String> {
    let mut list: Vec<String> = Vec::new();
    let mut push = |items: &[&str]| list.extend(items.iter().map(|s| s.to_string()));
    if let Some(scene) = &args.scene.scene {
        push(&[&scene.to_string_lossy()]);
    }
    if let Some(count) = args.scene.generated {
        push(&["--generated", &count.to_string()]);
    }
    if args.scene.allow_external_paths {
        push(&["--allow-external-paths"]);
    }
    let name = |value: Option<clap::builder::PossibleValue>| {
        value.map(|v| v.get_name().to_owned()).unwrap_or_default()
    };
    let integrator = name(args.integrators[0].to_possible_value());
    let accel = name(args.render.accel.to_possible_value());
    push(&[
        "--width",
        &args.width.to_string(),
        "--height",
        &args.height.to_string(),
        "--integrator",
        &integrator,
        "--accel",
        &accel,
        "--max-path-length",
        &args.render.max_path_length.to_string(),
    ]);
    if let Some(device) = &args.device.device {
        push(&["--device", device]);
    }
    if args.device.require_gpu {
        push(&["--require-gpu"]);
    }
    list
}

/// Runs `vkpath bench --startup`.
fn run_startup(args: &BenchArgs) -> anyhow::Result<()> {
    use crate::bench::startup::{format_startup_table, measure_startup};
    let exe = std::env::current_exe()?;
    let render_args = startup_render_args(args);
    let scene = args.scene.source().description();
    let mut results = Vec::new();
    for (what, extra) in [
        (scene.clone(), &[][..]),
        (
            format!("{scene}, --background 1,1,1"),
            &["--background", "1,1,1"][..],
        ),
    ] {
        eprintln!("vkpath bench: start-up of {what}");
        let mut all = render_args.clone();
        all.extend(extra.iter().map(|s| s.to_string()));
        results.push(measure_startup(&exe, &what, &all)?);
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&results)?);
    } else {
        print!("{}", format_startup_table(&results));
    }
    Ok(())
}

/// Runs `vkpath bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if args.integrators.is_empty() {
        bail!("--integrators is empty");
    }
    if args.startup {
        return run_startup(args);
    }
    let settings = args.render.apply(RenderSettings {
        width: args.width,
        height: args.height,
        spp: args.spp,
        ..RenderSettings::default()
    });
    // --guiding measures nee and mis with and without a guide (each run sets its own).
    RenderSettings {
        guiding: None,
        ..settings.clone()
    }
    .validate()?;
    RenderSettings {
        spp: args.reference_spp,
        guiding: None,
        ..settings.clone()
    }
    .validate()?;
    let source = args.scene.source();
    let scene = args.scene.load("vkpath bench")?;
    let Some(camera) = scene.camera else {
        bail!("the scene has no camera; bench needs a scene with its own camera (glTF or the built-in one)");
    };
    let scene = with_motion(args, scene)?;
    let stored_reference = match &args.reference {
        Some(path) => {
            let read = crate::image_io::exr_input::read_exr(path)?;
            Some((read.image, path.display().to_string()))
        }
        None => None,
    };
    let context = args.device.create_context()?;
    let guiding = settings.guiding;
    let setup = BenchSetup {
        repeats: args.repeats,
        settings,
        // Each run takes its own roulette default: guided runs none, unguided from vertex 3.
        russian_roulette_start: args.render.russian_roulette_start,
        reference_spp: args.reference_spp,
        stored_reference,
        integrators: args.integrators.clone(),
        light_selections: args.light_selections.clone().unwrap_or_default(),
        compare_guiding: guiding.is_some(),
        guide_training: guiding,
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

/// `scene` with motion blur's keys where `--shutter` asks for them: its glTF file posed
/// across the shutter around time 0 at `DEFAULT_FPS`, each key seen by the file's camera
/// then. A scene that is not an animated glTF file, or does not move, stays still (a note
/// says so).
fn with_motion(
    args: &BenchArgs,
    scene: crate::scene::Scene,
) -> anyhow::Result<crate::scene::Scene> {
    use crate::scene::gltf_file::{is_gltf_path, GltfFile};
    use crate::scene::source::SceneSource;
    let Some(shutter) = args.shutter.shutter() else {
        return Ok(scene);
    };
    for warning in args.shutter.warnings() {
        eprintln!("vkpath: warning: {warning}");
    }
    let path = match args.scene.source() {
        SceneSource::File(path) if is_gltf_path(&path) => path,
        _ => {
            eprintln!(
                "vkpath: note: --shutter: the scene has no animation, so it is measured still"
            );
            return Ok(scene);
        }
    };
    let options = crate::scene::files::LoadOptions {
        allow_external_paths: args.scene.allow_external_paths,
        ..Default::default()
    };
    let mut file = GltfFile::open(&path, &options)?;
    let at = super::shutter::KeyTimes {
        time: 0.0,
        fps: super::frames::DEFAULT_FPS,
    };
    let pick = crate::scene::animation::AnimationPick::All;
    let camera_at = |key: &crate::scene::Scene| {
        key.camera
            .ok_or_else(|| anyhow::anyhow!("--shutter: the scene has no camera at a key"))
    };
    match super::shutter::pose_keys(&mut file, shutter, at, &pick, camera_at)? {
        Some(motion) => Ok(crate::scene::Scene {
            motion: Some(motion),
            ..scene
        }),
        None => {
            eprintln!("vkpath: note: --shutter: nothing in the scene moves across the shutter, so it is measured still");
            Ok(scene)
        }
    }
}
