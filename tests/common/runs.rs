//! Running the `vkpath` binary and reading what it printed, for the tests of `check` and
//! `shadertoy` (tests/check_cli.rs, tests/shadertoy_cli.rs): the exit code, stdout, stderr,
//! the JSON report of `--json`, and `check` with the small renders those tests use; and the
//! small renders of posed geometry (tests/skin_morph_cli.rs, tests/khronos_animation_cli.rs).

use std::path::Path;

use serde_json::Value;

/// What one run of the binary printed and how it ended.
pub struct Run {
    /// The exit code (`None` when a signal ended it).
    pub code: Option<i32>,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

impl Run {
    /// Standard output as JSON (runs with `--json`); panics with both outputs when it is not.
    pub fn json(&self) -> Value {
        serde_json::from_str(&self.stdout)
            .unwrap_or_else(|e| panic!("not JSON ({e}): {}\n{}", self.stdout, self.stderr))
    }
}

/// Runs `vkpath ARGS` in `dir` with extra environment variables; fails the test if it
/// panicked (bad input must be one error line, never a panic).
pub fn run(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    let output = super::vkpath_with_env(dir, args, env);
    let run = Run {
        code: output.status.code(),
        stdout: String::from_utf8_lossy(&output.stdout).into(),
        stderr: String::from_utf8_lossy(&output.stderr).into(),
    };
    assert!(
        !run.stderr.contains("panicked"),
        "vkpath {args:?} panicked: {}",
        run.stderr
    );
    run
}

/// Runs `vkpath check FILES… --validate EXTRA…` with the small renders of the tests (32 x 32
/// at 256 spp, images into `out/`) in `dir`.
pub fn check(dir: &Path, files: &[String], extra: &[&str], env: &[(&str, &str)]) -> Run {
    let mut args: Vec<&str> = vec!["check"];
    args.extend(files.iter().map(String::as_str));
    args.extend_from_slice(&[
        "--validate",
        "--size",
        "32",
        "--spp",
        "256",
        "--output-dir",
        "out",
    ]);
    args.extend_from_slice(extra);
    run(dir, &args, env)
}

/// The entry of `function` in a `check --json` report's verdicts, if any.
pub fn verdict(report: &Value, function: &str) -> Option<Value> {
    report["functions"].as_array().and_then(|functions| {
        functions
            .iter()
            .find(|f| f["function"] == function)
            .cloned()
    })
}

/// The options of the posed-geometry tests' small, quick renders (`skin_morph_cli`,
/// `khronos_animation_cli`): `size` x `size` pixels at 2 spp, lit by a white background,
/// traced through a BVH (`--accel bvh`): under `auto` a scene of a few triangles is compiled
/// into the kernel, a new kernel (seconds on lavapipe) for every pose, where the BVH's kernel
/// is one for all poses and comes from the tests' pipeline cache after its first build
/// (`frames_cli` renders poses the compiled-in way).
pub fn small_render_options(size: &'static str) -> [&'static str; 10] {
    [
        "--accel",
        "bvh",
        "--width",
        size,
        "--height",
        size,
        "--spp",
        "2",
        "--background",
        "1,1,1",
    ]
}

/// Renders `scene` with `extra` options and `small_render_options(size)` to `output` in
/// `dir`; fails the test unless the render succeeds. Returns the run.
pub fn render_small(
    dir: &Path,
    scene: &str,
    extra: &[&str],
    output: &str,
    size: &'static str,
) -> Run {
    let mut args = vec!["render", scene, "-o", output];
    args.extend(extra);
    args.extend(small_render_options(size));
    let result = run(dir, &args, &[]);
    assert_eq!(result.code, Some(0), "{args:?}: {}", result.stderr);
    result
}

/// The mean radiance of the EXR `name` in `dir`.
pub fn exr_pixels(dir: &Path, name: &str) -> Vec<[f32; 4]> {
    vkpath::image_io::exr_input::read_exr(&dir.join(name))
        .unwrap()
        .image
        .mean
}

/// The bits of every channel of the EXR `name` in `dir`, by name, without its header: what
/// "bit for bit the same image" compares now that a frame's metadata records its frame and
/// time (a `--time` still's records no frame, so the files differ in their headers).
pub fn exr_bits(dir: &Path, name: &str) -> Vec<(String, Vec<u32>)> {
    let exr = vkpath::image_io::exr_input::read_exr_channels(&dir.join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    exr.channels
        .into_iter()
        .map(|(channel, values)| (channel, values.iter().map(|v| v.to_bits()).collect()))
        .collect()
}
