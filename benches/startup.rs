//! How a small scene's traversal pays once building its kernel is counted: for each way of
//! finding hits (the loop compiled into the kernel, the loop over the texel buffer, the BVH)
//! the seconds to build the renderer, to run its first frame (llvmpipe compiles lazily, at
//! the first dispatch), and the steady-state samples per second, all in one run.
//!
//! `cargo bench --bench startup [-- SCENE.gltf]`: the built-in Cornell box under a white sky
//! (`--background 1,1,1`, which needs the glTF-material kernels), and the given scene if any
//! (e.g. the textured box that `benches/mitsuba_textured.py` writes). Mesa's shader disk cache
//! is switched off (MESA_SHADER_CACHE_DISABLE) so that every build is a first build, and no
//! pipeline cache is used. What `Traversal::choose` picks rests on this table.
//!
//! Run without `--bench` (as `cargo test --all-targets` runs every bench target), it is a
//! smoke test: the workshop's box, one integrator, so the suite checks it still runs
//! without paying for the table.

use std::path::Path;
use std::time::Instant;

use glam::Vec3;
use vkpath::lights::EnvironmentSource;
use vkpath::render::gpu_scene::embedded_build;
use vkpath::render::Traversal;
use vkpath::{Context, ContextOptions, Integrator, RenderSettings, Renderer, Scene};

/// One traversal's timings on one scene.
struct Row {
    traversal: Traversal,
    integrator: Integrator,
    build_seconds: f64,
    first_frame_seconds: f64,
    samples_per_second: f64,
}

fn measure(
    scene: &Scene,
    traversal: Traversal,
    integrator: Integrator,
) -> Result<Row, Box<dyn std::error::Error>> {
    // A fresh device each time, so that nothing the driver kept from a previous build helps.
    let context = Context::new(&ContextOptions::default())?;
    let camera = scene.camera.ok_or("the scene has no camera")?;
    // The smoke run renders 4 samples per pixel (the linear loop takes ~40 s for 64).
    let spp = if benchmarking() { 64 } else { 4 };
    let settings = RenderSettings {
        width: 64,
        height: 64,
        spp,
        integrator,
        ..RenderSettings::default()
    };
    // The build that `Renderer::new` would take for this traversal
    let spirv = embedded_build(scene, &settings, traversal)?.embedded_spirv()?;
    let samples = f64::from(settings.width * settings.height);
    let started = Instant::now();
    let mut renderer =
        Renderer::with_kernel(&context, scene, &camera, settings, &spirv, traversal)?;
    let build_seconds = started.elapsed().as_secs_f64();
    let started = Instant::now();
    let first = renderer.render_frame()?;
    let first_frame_seconds = started.elapsed().as_secs_f64();
    let started = Instant::now();
    let done = renderer.render_all()?;
    let steady = started.elapsed().as_secs_f64();
    let steady_samples = samples * f64::from(spp - first);
    assert_eq!(done.width, 64);
    Ok(Row {
        traversal,
        integrator,
        build_seconds,
        first_frame_seconds,
        samples_per_second: steady_samples / steady.max(1e-9),
    })
}

/// Whether `cargo bench` runs this (it passes `--bench`); else `cargo test`'s smoke run.
fn benchmarking() -> bool {
    std::env::args().any(|a| a == "--bench")
}

fn report(name: &str, scene: &Scene) -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "{name}: {} triangles, {} kernels",
        scene.triangles.len(),
        if scene.needs_material_kernels() {
            "glTF-material"
        } else {
            "workshop"
        }
    );
    println!(
        "{:<20} {:<9} {:>8} {:>13} {:>11} {:>18}",
        "traversal", "integr.", "build s", "1st frame s", "Msamples/s", "s to 64x64x64 spp"
    );
    let integrators: &[Integrator] = match benchmarking() {
        true => &[Integrator::PathTracing, Integrator::Mis],
        false => &[Integrator::PathTracing],
    };
    for &integrator in integrators {
        let mut rows = Vec::new();
        let constant = Traversal::constant_triangles_can_trace(
            scene.triangles.len(),
            scene.needs_material_kernels(),
            scene.uses_alpha(),
        );
        for traversal in [
            Traversal::ConstantTriangles,
            Traversal::Linear,
            Traversal::Bvh,
        ] {
            if traversal == Traversal::ConstantTriangles && !constant {
                println!(
                    "{:<20} {:<9} (more triangles than these kernels compile in, or alpha)",
                    traversal.name(),
                    format!("{integrator:?}")
                );
                continue;
            }
            rows.push(measure(scene, traversal, integrator)?);
        }
        for row in &rows {
            // What a user waits for: the build, the first frame, and the rest at speed.
            let total = row.build_seconds
                + row.first_frame_seconds
                + 64.0 * 64.0 * 64.0 / row.samples_per_second;
            println!(
                "{:<20} {:<9} {:>8.2} {:>13.2} {:>11.3} {:>18.2}",
                row.traversal.name(),
                format!("{:?}", row.integrator),
                row.build_seconds,
                row.first_frame_seconds,
                row.samples_per_second / 1e6,
                total
            );
        }
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // Read by Mesa when a device is created; this program is single-threaded here.
    std::env::set_var("MESA_SHADER_CACHE_DISABLE", "true");
    if !benchmarking() {
        return report(
            "Cornell box (smoke run: cargo bench for the table)",
            &Scene::builtin_cornell_box()?,
        );
    }
    let white = EnvironmentSource::Background(Vec3::ONE);
    let white_sky = Scene::builtin_cornell_box()?.with_environment(Some(&white))?;
    report("Cornell box, --background 1,1,1", &white_sky)?;
    report("Cornell box", &Scene::builtin_cornell_box()?)?;
    if let Some(path) = std::env::args().skip(1).find(|a| !a.starts_with('-')) {
        let scene = Scene::load(Path::new(&path))?.with_environment(Some(&white))?;
        report(&format!("{path}, --background 1,1,1"), &scene)?;
    }
    Ok(())
}
