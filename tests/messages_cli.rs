//! What the commands say about themselves (issue 43): `render --json` on failure, `merge`
//! with several outputs, `--quiet` on `exercise`, `compare` and `check`, the heat map's
//! legend, and the lines of `--resume` and `--denoise`. Tiny images and few samples.

use crate::common;

use std::path::Path;

use common::runs::Run as Outcome;

/// Runs vkpath in `dir`, expects success, and returns what it printed.
fn ok(dir: &Path, args: &[&str]) -> Outcome {
    let outcome = common::runs::run(dir, args, &[]);
    assert_eq!(
        outcome.code,
        Some(0),
        "{args:?}: {}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    outcome
}

/// A tiny render of the built-in box, `extra` appended.
fn render(dir: &Path, extra: &[&str]) -> Outcome {
    let mut args = vec!["render", "--width", "8", "--height", "8", "--spp", "2"];
    args.extend_from_slice(extra);
    ok(dir, &args)
}

#[test]
fn a_failed_json_render_prints_one_json_object() {
    let dir = tempfile::tempdir().unwrap();
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            "--json",
            "-o",
            "/nonexistent-dir/a.png",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
        ],
    );
    assert_eq!(output.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("one JSON object");
    assert_eq!(report["schema_version"], 1);
    assert_eq!(report["stop"], "failed");
    let error = report["error"].as_str().expect("an error");
    assert!(
        error.contains("cannot write '/nonexistent-dir/a.png'"),
        "{error}"
    );
    // The same error, on stderr as always.
    assert_eq!(stderr.trim(), format!("vkpath: error: {error}"), "{stderr}");
}

#[test]
fn merge_writes_several_outputs() {
    let dir = tempfile::tempdir().unwrap();
    for shard in ["0/2", "1/2"] {
        let name = format!("s{}.exr", &shard[..1]);
        render(dir.path(), &["--shard", shard, "-o", &name, "--quiet"]);
    }
    let outcome = ok(
        dir.path(),
        &["merge", "s0.exr", "s1.exr", "-o", "m.exr", "-o", "m.png"],
    );
    assert!(
        outcome
            .stderr
            .contains("merged 2 shards (samples 0..2); wrote m.exr, m.png"),
        "{}",
        outcome.stderr
    );
    assert!(dir.path().join("m.exr").is_file() && dir.path().join("m.png").is_file());
}

#[test]
fn quiet_exercise_and_compare_print_nothing_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["ray-tracing", "sample-sphere"] {
        let outcome = ok(
            dir.path(),
            &[
                "exercise", name, "-o", "e.png", "--width", "16", "--height", "16", "--quiet",
            ],
        );
        assert_eq!(outcome.stderr, "", "exercise {name}");
    }
    render(dir.path(), &["--moments", "-o", "a.exr", "--quiet"]);
    render(
        dir.path(),
        &["--moments", "-o", "b.exr", "--seed", "3", "--quiet"],
    );
    let outcome = ok(
        dir.path(),
        &["compare", "a.exr", "b.exr", "--heatmap", "h.png", "--quiet"],
    );
    assert_eq!(outcome.stderr, "");
    assert!(
        outcome.stdout.starts_with("consistent"),
        "{}",
        outcome.stdout
    );
    // Without --quiet, the heat map's line says what its colours mean.
    let outcome = ok(
        dir.path(),
        &["compare", "a.exr", "b.exr", "--heatmap", "h.png"],
    );
    let line = outcome.stderr.trim();
    assert!(
        line.starts_with("vkpath: wrote h.png (heat map of 8x8 blocks: black: p = 1; grey"),
        "{line}"
    );
    assert!(
        line.contains("red: p = ") && line.contains("yellow"),
        "{line}"
    );
}

#[test]
fn quiet_check_prints_its_verdicts_and_nothing_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let solution = format!(
        "{}/tests/solutions/pcg2d_separate_statements.glsl",
        env!("CARGO_MANIFEST_DIR")
    );
    let outcome = common::runs::check(dir.path(), &[solution], &["--quiet"], &[]);
    assert_eq!(
        outcome.code,
        Some(0),
        "{}\n{}",
        outcome.stdout,
        outcome.stderr
    );
    assert_eq!(outcome.stderr, "");
    assert!(outcome.stdout.contains("pcg2d"), "{}", outcome.stdout);
}

#[test]
fn resume_and_denoise_say_what_they_did() {
    let dir = tempfile::tempdir().unwrap();
    render(
        dir.path(),
        &["-o", "a.exr", "--checkpoint", "ck.exr", "--quiet"],
    );
    let outcome = ok(
        dir.path(),
        &[
            "render", "--width", "8", "--height", "8", "--spp", "4", "-o", "b.exr", "--resume",
            "ck.exr",
        ],
    );
    assert!(
        outcome
            .stderr
            .contains("vkpath: resumed from 'ck.exr' at 2 of 4 spp; this run took 2 more"),
        "{}",
        outcome.stderr
    );
    let outcome = ok(
        dir.path(),
        &[
            "render", "--width", "8", "--height", "8", "--spp", "4", "-o", "c.exr", "--resume",
            "ck.exr", "--quiet",
        ],
    );
    assert_eq!(outcome.stderr, "");
    let outcome = render(dir.path(), &["-o", "d.exr", "--denoise"]);
    assert!(
        outcome
            .stderr
            .contains("vkpath: denoised with Intel Open Image Denoise's RT filter (HDR, guided by the albedo and normal)"),
        "{}",
        outcome.stderr
    );
    let outcome = render(dir.path(), &["-o", "e.exr", "--denoise", "--quiet"]);
    assert_eq!(outcome.stderr, "");
}
