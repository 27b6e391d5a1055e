//! Shared helpers of the integration tests: a validated Vulkan context that fails loudly
//! (never skips) when Vulkan is missing, and running the `vkpath` binary.
#![allow(dead_code)]

pub mod runs;
pub mod scenes;
pub mod twins;

use std::path::Path;
use std::process::{Command, Output};
use std::sync::Arc;

use glam::Vec3;
use vkpath::vk::{Context, ContextOptions};
use vkpath::{RenderSettings, RenderedImage, Renderer, Scene};

/// What to install when Vulkan is missing.
pub const VULKAN_PACKAGES: &str =
    "apt-get install libvulkan1 mesa-vulkan-drivers vulkan-validationlayers";

/// A context on the default device with the validation layer on. Panics with the packages
/// to install when there is no Vulkan: a skipped test is a test that does not exist.
pub fn validated_context() -> Arc<Context> {
    Context::new(&ContextOptions { validate: true, ..Default::default() }).unwrap_or_else(|error| {
        panic!("this test needs Vulkan with validation layers ({error}); install them: {VULKAN_PACKAGES}")
    })
}

/// Fails if the validation layer reported any warning or error so far.
pub fn assert_validation_silent(context: &Context) {
    let messages = context.validation_messages().expect("validation is on");
    assert_eq!(
        (messages.errors(), messages.warnings()),
        (0, 0),
        "the validation layer reported errors/warnings (run with RUST_LOG=warn to see them)"
    );
}

/// Runs the `vkpath` binary with `args` in `dir`.
pub fn vkpath(dir: &Path, args: &[&str]) -> Output {
    vkpath_with_env(dir, args, &[])
}

/// The pipeline cache directory of every `vkpath` the tests run: in the temp directory,
/// shared by the tests (writes are atomic), so that no test writes to the user's home.
pub fn test_cache_dir() -> std::path::PathBuf {
    std::env::temp_dir().join("vkpath-tests-pipeline-cache")
}

/// Runs the `vkpath` binary with `args` and extra environment variables (which may set
/// another `VKPATH_CACHE_DIR` than `test_cache_dir()`).
pub fn vkpath_with_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_vkpath"));
    command
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_LOG")
        .env("VKPATH_CACHE_DIR", test_cache_dir());
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().expect("the vkpath binary runs")
}

/// Path of a fixture in tests/data.
pub fn fixture(name: &str) -> String {
    format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Renders `scene` from its camera with `settings` on a validated context, and fails if the
/// validation layer said anything.
pub fn render_scene(scene: &Scene, settings: RenderSettings) -> RenderedImage {
    let context = validated_context();
    let mut renderer = Renderer::new(&context, scene, &scene.camera.unwrap(), settings).unwrap();
    let image = renderer.render_all().unwrap();
    drop(renderer);
    assert_validation_silent(&context);
    image
}

/// How many floats lie between `a` and `b` (of either sign).
pub fn ulps(a: f32, b: f32) -> u64 {
    (i64::from(a.to_bits() as i32) - i64::from(b.to_bits() as i32)).unsigned_abs()
}

/// The most ulps by which two images' means differ in any pixel and colour channel (the
/// bound `Accumulation::merge` documents for a merge against the single render is 4).
pub fn worst_ulps_apart(a: &RenderedImage, b: &RenderedImage) -> u64 {
    a.mean
        .iter()
        .zip(&b.mean)
        .flat_map(|(p, q)| (0..3).map(move |c| ulps(p[c], q[c])))
        .max()
        .unwrap_or(0)
}

/// Per channel: the image mean and its standard error from the pixels' second moments (every
/// sample independent: N = pixels * spp), as tests/furnace.rs computes them.
pub fn mean_and_standard_error(image: &RenderedImage, spp: u32) -> [(f64, f64); 3] {
    let samples = image.mean.len() as f64 * f64::from(spp);
    std::array::from_fn(|channel| {
        let mean = image.average()[channel];
        let variance = image
            .mean
            .iter()
            .zip(&image.second_moment)
            .map(|(m, m2)| f64::from(m2[channel]) - f64::from(m[channel]).powi(2))
            .sum::<f64>()
            / image.mean.len() as f64;
        (mean, (variance.max(0.0) / samples).sqrt())
    })
}

/// Asserts |mean - expected| < 4 standard errors in every channel (a false failure has
/// probability 6e-5 per channel for a normal mean; a lost or doubled term is tens of them).
pub fn assert_mean(image: &RenderedImage, spp: u32, expected: Vec3, what: &str) {
    for (channel, (mean, error)) in mean_and_standard_error(image, spp).into_iter().enumerate() {
        let z = (mean - f64::from(expected[channel])) / error;
        println!(
            "{what} channel {channel}: mean {mean:.5}, expected {:.5}, SE {error:.2e}, z {z:.2}",
            expected[channel]
        );
        assert!(error > 0.0, "{what}: the estimate should be noisy");
        assert!(
            z.abs() < 4.0,
            "{what} channel {channel}: mean {mean} vs {}, z = {z}",
            expected[channel]
        );
    }
}
