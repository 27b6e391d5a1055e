//! Builds the path tracer's pipelines for a scene, one per integrator, without rendering
//! anything: with `RADV_DEBUG=shaderstats` on Mesa's RADV, the driver prints each kernel's
//! statistics for an AMD GPU (registers, instructions, occupancy), and RADV's null device
//! (`RADV_FORCE_FAMILY`) gives them without the GPU, which no command buffer reaches.
//! `scripts/kernel-statistics.sh` runs it so and tabulates them (docs/performance.md).
//!
//! Usage: `kernel_statistics [--traversal constant|bvh|compressed-bvh] [SCENE.gltf]
//! INTEGRATOR...` (the built-in Cornell box when no scene is given). The specialization is
//! the renderer's on a GPU: the variant room's, the settings' defaults (PCG2D, path length
//! 5) and no loop limit.

use std::path::Path;

use clap::ValueEnum;
use vkpath::kernels::loops::LoopCoefficients;
use vkpath::kernels::specialization::{path_tracer_specialization, SpecializationParts};
use vkpath::kernels::variant::Traversal;
use vkpath::kernels::PATH_TRACER;
use vkpath::render::gpu_scene::host_variant;
use vkpath::vk::{Context, ContextOptions};
use vkpath::{contract, RenderSettings, Scene};
use vkpath::{Integrator, SamplerKind};

fn main() {
    if let Err(error) = run() {
        eprintln!("kernel_statistics: {error}");
        std::process::exit(2);
    }
    // RADV's null device cannot be destroyed cleanly (its winsys lacks the calls), and
    // nothing here needs a clean exit.
    std::process::exit(0);
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut traversal_name = "constant".to_string();
    if let Some(at) = args.iter().position(|a| a == "--traversal") {
        traversal_name = args.get(at + 1).ok_or("--traversal needs a value")?.clone();
        args.drain(at..at + 2);
    }
    let scene = match args
        .first()
        .filter(|a| a.ends_with(".gltf") || a.ends_with(".glb"))
    {
        Some(path) => {
            let scene = Scene::load(Path::new(path))?;
            args.remove(0);
            scene
        }
        None => Scene::builtin_cornell_box()?,
    };
    let traversal = match traversal_name.as_str() {
        "constant" => Traversal::ConstantTriangles,
        "bvh" => Traversal::Bvh,
        "compressed-bvh" => Traversal::CompressedBvh,
        other => return Err(format!("unknown traversal {other}").into()),
    };
    let context = Context::new(&ContextOptions::default())?;
    eprintln!("device: {}", context.info);
    for name in &args {
        let integrator = Integrator::from_str(name, true)?;
        let settings = RenderSettings {
            integrator,
            sampler: SamplerKind::Pcg,
            ..Default::default()
        };
        let variant = host_variant(&scene, &settings, traversal)?;
        let materials = scene.needs_material_kernels() || scene.materials.is_some();
        let parts = SpecializationParts {
            settings: &settings.specialization(),
            traversal,
            triangles: &scene.triangles,
            variant: &variant,
            // A GPU's loop budget: no limit (`LoopBudget`).
            loop_limit: 0,
            loops: LoopCoefficients::path_tracer(traversal, false, materials),
        };
        let specialization = path_tracer_specialization(&parts, contract::GUIDING_OFF);
        let spirv = variant.build.embedded_spirv()?;
        eprintln!("kernel: {name} {} {}", variant.build.name, traversal.name());
        PATH_TRACER.pipeline(&context, &variant.build, &spirv, &specialization)?;
    }
    Ok(())
}
