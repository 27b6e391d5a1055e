//! `vkpath bench --startup`: cold against warm start-up in one run. Start-up is what a user
//! waits for before the first sample, so it is measured on whole processes: `vkpath render`
//! of one sample per pixel, three times with the same fresh cache directories (vkpath's
//! pipeline cache and the drivers' shader caches: Mesa's, NVIDIA's): cold (all empty), warm
//! (all filled by the cold run), and warm with `--no-cache` (the drivers' caches alone, to
//! tell what vkpath's own cache adds).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use serde::Serialize;

use anyhow::{bail, Context as _, Result};

/// One configuration's start-up times.
#[derive(Clone, Debug, Serialize)]
pub struct StartupResult {
    /// What was rendered (the scene and the extra arguments).
    pub what: String,
    /// Seconds of the whole cold process (empty caches).
    pub cold_seconds: f64,
    /// Seconds of the whole warm process (caches the cold run filled).
    pub warm_seconds: f64,
    /// Seconds of a warm process with `--no-cache` (only the drivers' caches help).
    pub warm_no_cache_seconds: f64,
    /// `setup_seconds` of `render --json` (building the renderer) cold, warm and warm
    /// without vkpath's cache.
    pub setup_seconds: [f64; 3],
    /// cold_seconds / warm_seconds.
    pub cold_over_warm: f64,
}

/// Environment variables that point each cache at `dir` (vkpath's, Mesa's, NVIDIA's).
fn cache_environment(dir: &Path) -> Vec<(&'static str, std::path::PathBuf)> {
    vec![
        ("VKPATH_CACHE_DIR", dir.join("vkpath")),
        ("MESA_SHADER_CACHE_DIR", dir.join("mesa")),
        ("__GL_SHADER_DISK_CACHE_PATH", dir.join("nvidia")),
    ]
}

/// Runs `exe render ARGS --spp 1 --json --quiet -o DIR/out.exr` with the caches in `dir`;
/// returns its wall-clock seconds and the `setup_seconds` it reported.
fn timed_render(exe: &Path, args: &[String], dir: &Path) -> Result<(f64, f64)> {
    let output = dir.join("out.exr");
    let mut command = Command::new(exe);
    command
        .arg("render")
        .args(args)
        .args(["--spp", "1", "--json", "--quiet", "-o"])
        .arg(&output);
    for (name, value) in cache_environment(dir) {
        command.env(name, value);
    }
    let started = Instant::now();
    let result = command
        .output()
        .with_context(|| format!("running '{}'", exe.display()))?;
    let seconds = started.elapsed().as_secs_f64();
    if !result.status.success() {
        bail!(
            "the start-up render failed: {}",
            String::from_utf8_lossy(&result.stderr).trim()
        );
    }
    let report: serde_json::Value = serde_json::from_slice(&result.stdout)
        .context("the start-up render printed no JSON report")?;
    let setup = report["setup_seconds"].as_f64().unwrap_or(f64::NAN);
    Ok((seconds, setup))
}

/// Measures one configuration: `args` are `render`'s (scene, size, device, extra options).
pub fn measure_startup(exe: &Path, what: &str, args: &[String]) -> Result<StartupResult> {
    let dir = tempfile::tempdir().context("creating a temporary directory")?;
    let (cold_seconds, cold_setup) = timed_render(exe, args, dir.path())?;
    let (warm_seconds, warm_setup) = timed_render(exe, args, dir.path())?;
    let mut no_cache = args.to_vec();
    no_cache.push("--no-cache".into());
    let (warm_no_cache_seconds, no_cache_setup) = timed_render(exe, &no_cache, dir.path())?;
    Ok(StartupResult {
        what: what.to_owned(),
        cold_seconds,
        warm_seconds,
        warm_no_cache_seconds,
        setup_seconds: [cold_setup, warm_setup, no_cache_setup],
        cold_over_warm: cold_seconds / warm_seconds.max(1e-9),
    })
}

/// The results as a table for people.
pub fn format_startup_table(results: &[StartupResult]) -> String {
    let mut text = format!(
        "{:<44} {:>7} {:>7} {:>10} {:>16} {:>20}\n",
        "start-up, whole process, 1 spp",
        "cold s",
        "warm s",
        "cold/warm",
        "warm no-cache s",
        "setup s (c/w/nc)"
    );
    for r in results {
        text += &format!(
            "{:<44} {:>7.2} {:>7.2} {:>9.2}x {:>16.2} {:>6.2}/{:>5.2}/{:>5.2}\n",
            r.what,
            r.cold_seconds,
            r.warm_seconds,
            r.cold_over_warm,
            r.warm_no_cache_seconds,
            r.setup_seconds[0],
            r.setup_seconds[1],
            r.setup_seconds[2]
        );
    }
    text
}
