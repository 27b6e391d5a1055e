//! `vkpath compare` through the binary: renders of the Cornell box that differ only in their
//! seed are consistent; a render with a shorter maximum path length, or with its radiance
//! scaled as a wrong exposure or emission would, is not; a reference without moments is
//! taken as exact; bad inputs give exit status 2 and one error line.

use crate::common;

use std::path::Path;
use std::process::Output;

use vkpath::image_io::exr_input::read_exr;
use vkpath::image_io::output::{save_image, SaveOptions};

/// 64x64 pixels: 8x8 blocks of 8x8, 192 tests.
const SIZE: &str = "64";

/// Renders the Cornell box with `extra` options into `dir/name`.
fn render(dir: &Path, name: &str, spp: &str, extra: &[&str]) {
    let mut args = vec![
        "render",
        "--integrator",
        "workshop",
        "-o",
        name,
        "--width",
        SIZE,
        "--height",
        SIZE,
        "--spp",
        spp,
    ];
    args.extend_from_slice(extra);
    let output = common::vkpath(dir, &args);
    assert!(
        output.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// Runs `vkpath compare ARGS` in `dir`.
fn compare(dir: &Path, args: &[&str]) -> Output {
    let mut full = vec!["compare"];
    full.extend_from_slice(args);
    let output = common::vkpath(dir, &full);
    println!(
        "compare {args:?} -> {:?}\n{}{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// `vkpath compare --json` and its parsed report.
fn compare_json(dir: &Path, a: &str, b: &str) -> (i32, serde_json::Value) {
    let output = compare(dir, &[a, b, "--json"]);
    let report = serde_json::from_slice(&output.stdout).expect("--json prints JSON");
    (output.status.code().expect("an exit status"), report)
}

/// Rewrites an EXR with every radiance scaled by `factor` (second moments by its square),
/// as a wrong exposure or a wrongly scaled emission would render it.
fn scale_exr(source: &Path, target: &Path, factor: f32) {
    let mut read = read_exr(source).unwrap();
    for (mean, square) in read
        .image
        .mean
        .iter_mut()
        .zip(&mut read.image.second_moment)
    {
        for c in 0..3 {
            mean[c] *= factor;
            square[c] *= factor * factor;
        }
    }
    let options = SaveOptions {
        moments: read.has_moments,
        ..Default::default()
    };
    save_image(target, &read.image, &options).unwrap();
}

/// Rewrites an EXR without its moment channels, as a renderer other than vkpath would.
fn drop_moments(source: &Path, target: &Path) {
    let read = read_exr(source).unwrap();
    save_image(target, &read.image, &SaveOptions::default()).unwrap();
}

#[test]
fn renders_with_moments_are_consistent_across_seeds_and_biased_ones_are_not() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    render(dir, "seed1.exr", "32", &["--seed", "1", "--moments"]);
    render(dir, "seed2.exr", "32", &["--seed", "2", "--moments"]);
    render(
        dir,
        "short.exr",
        "32",
        &["--seed", "3", "--moments", "--max-path-length", "2"],
    );

    let (code, report) = compare_json(dir, "seed1.exr", "seed2.exr");
    assert_eq!(code, 0, "{report}");
    assert_eq!(report["consistent"], true);
    assert_eq!(report["variance_source"], "both_moments");
    assert_eq!(report["test_count"], 192);

    // Paths of at most 2 hits miss all light that takes 3 or more: dark everywhere but on
    // the light itself.
    let output = compare(dir, &["short.exr", "seed2.exr", "--heatmap", "heat.png"]);
    assert_eq!(output.status.code(), Some(1));
    let text = String::from_utf8_lossy(&output.stdout);
    assert!(text.starts_with("INCONSISTENT"), "{text}");
    let (_, report) = compare_json(dir, "short.exr", "seed2.exr");
    let fraction = report["failing_block_fraction"].as_f64().unwrap();
    assert!(fraction > 0.5, "{report}");
    // The error beside the verdict, as `vkpath bench` measures it.
    assert!(report["relative_mse"].as_f64().unwrap() > 0.0, "{report}");
    assert!(text.contains("relMSE of A against B: "), "{text}");
    let heat = image::open(dir.join("heat.png")).unwrap().to_rgb8();
    assert_eq!(heat.dimensions(), (64, 64));
    let red = heat
        .pixels()
        .filter(|p| p.0[0] == 255 && p.0[2] == 0)
        .count();
    assert!(
        red as f64 >= 0.5 * 64.0 * 64.0,
        "{red} heat-map pixels are red"
    );

    // 20% too bright, as a wrong exposure or emission: measured 25 of 64 blocks fail, the
    // worst (the light, nearly noise-free) at z = 33.
    scale_exr(&dir.join("seed1.exr"), &dir.join("bright.exr"), 1.2);
    let (code, report) = compare_json(dir, "bright.exr", "seed2.exr");
    assert_eq!(code, 1, "{report}");
    // The direction of the bias is visible in the worst block.
    assert!(report["worst"]["z"].as_f64().unwrap() > 0.0, "{report}");
}

#[test]
fn a_reference_without_moments_is_taken_as_exact() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    // 16x the samples of the image under test: treating it as exact understates the
    // variance of the difference by 1/16, which inflates z by sqrt(1 + 1/16) = 3%.
    render(dir, "reference.exr", "512", &["--seed", "9"]);
    render(dir, "test.exr", "32", &["--seed", "1", "--moments"]);
    render(
        dir,
        "short.exr",
        "32",
        &["--seed", "3", "--moments", "--max-path-length", "2"],
    );
    let (code, report) = compare_json(dir, "test.exr", "reference.exr");
    assert_eq!(
        (code, &report["variance_source"]),
        (0, &"moments_of_a".into()),
        "{report}"
    );
    let (code, report) = compare_json(dir, "reference.exr", "test.exr");
    assert_eq!(
        (code, &report["variance_source"]),
        (0, &"moments_of_b".into()),
        "{report}"
    );
    let (code, _) = compare_json(dir, "short.exr", "reference.exr");
    assert_eq!(code, 1);

    // Neither has moments: the spread of the differences within each block.
    drop_moments(&dir.join("test.exr"), &dir.join("test-plain.exr"));
    drop_moments(&dir.join("short.exr"), &dir.join("short-plain.exr"));
    let (code, report) = compare_json(dir, "test-plain.exr", "reference.exr");
    assert_eq!(
        (code, &report["variance_source"]),
        (0, &"within_block_spread".into()),
        "{report}"
    );
    let (code, report) = compare_json(dir, "short-plain.exr", "reference.exr");
    assert_eq!(code, 1, "{report}");
}

/// Expects exit status 2 and exactly one line on stderr that mentions `expected`.
fn expect_usage_error(dir: &Path, args: &[&str], expected: &str) {
    let output = compare(dir, args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: {stderr}");
    assert!(
        lines[0].contains(expected) && !stderr.contains("panicked"),
        "{args:?}: '{}' does not mention '{expected}'",
        lines[0]
    );
}

#[test]
fn bad_inputs_exit_with_status_2() {
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    for (name, size) in [("a.exr", "8"), ("wide.exr", "9")] {
        let output = common::vkpath(
            dir,
            &[
                "render",
                "--integrator",
                "workshop",
                "-o",
                name,
                "--width",
                size,
                "--height",
                "8",
                "--spp",
                "2",
            ],
        );
        assert!(output.status.success());
    }
    std::fs::write(dir.join("garbage.exr"), b"not an image").unwrap();
    expect_usage_error(dir, &["a.exr", "missing.exr"], "missing.exr");
    expect_usage_error(dir, &["a.exr", "wide.exr"], "differ in size: 8x8 vs 9x8");
    expect_usage_error(dir, &["garbage.exr", "a.exr"], "garbage.exr");
    expect_usage_error(dir, &["a.exr", "a.exr", "--block", "0"], "--block");
    expect_usage_error(dir, &["a.exr", "a.exr", "--block", "1"], "--block 2");
    expect_usage_error(dir, &["a.exr", "a.exr", "--alpha", "1.5"], "--alpha");
    expect_usage_error(
        dir,
        &["a.exr", "a.exr", "--heatmap", "/nonexistent-dir/heat.png"],
        "/nonexistent-dir/heat.png",
    );
    // clap's own usage errors have status 2 too.
    assert_eq!(compare(dir, &["a.exr"]).status.code(), Some(2));
    // An image is consistent with itself.
    assert_eq!(compare(dir, &["a.exr", "a.exr"]).status.code(), Some(0));
}

/// Runs `vkpath compare A B` in `dir`; (exit code, stderr).
fn compare_outcome(dir: &std::path::Path, a: &str, b: &str) -> (Option<i32>, String) {
    let output = common::vkpath(dir, &["compare", a, b]);
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{stderr}");
    (output.status.code(), stderr)
}

#[test]
fn hostile_headers_and_infinite_pixels_are_unusable_input() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let pixels = 64;
    let image = |value: f32| vkpath::RenderedImage {
        width: 8,
        height: 8,
        mean: vec![[value, 1.0, 1.0, 1.0]; pixels],
        second_moment: vec![[1.0; 3]; pixels],
        sample_count: vec![4.0; pixels],
    };
    let save = |name: &str, value: f32| {
        vkpath::save_image(&path.join(name), &image(value), &Default::default()).unwrap();
    };
    save("finite.exr", 1.0);
    save("infinite.exr", f32::INFINITY);
    let (code, stderr) = compare_outcome(path, "infinite.exr", "infinite.exr");
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("infinite or NaN"), "{stderr}");

    // A header that claims 10^6 x 10^6 pixels: refused from the header, one line.
    let mut bytes = std::fs::read(path.join("finite.exr")).unwrap();
    for name in [&b"dataWindow"[..], &b"displayWindow"[..]] {
        let at = bytes.windows(name.len()).position(|w| w == name).unwrap();
        let values = at + name.len() + 1 + b"box2i".len() + 1 + 4;
        for (k, value) in [0i32, 0, 999_999, 999_999].iter().enumerate() {
            bytes[values + 4 * k..values + 4 * k + 4].copy_from_slice(&value.to_le_bytes());
        }
    }
    std::fs::write(path.join("huge.exr"), &bytes).unwrap();
    let (code, stderr) = compare_outcome(path, "huge.exr", "finite.exr");
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("claims 1000000x1000000 pixels"), "{stderr}");
}
