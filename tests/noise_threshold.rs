//! `render --noise-threshold` through the binary (issue 21): pixels stop once the kernel's
//! `is_pixel_converged` says so (checked against its Rust twin on the final state), the
//! render takes fewer samples than the uniform one, keeps each pixel's count in the EXR,
//! `compare` judges it consistent with a reference, and the image does not depend on how
//! samples are split into frames or tiles.

use crate::common;

use std::path::Path;

use vkpath::image_io::exr_input::read_exr;
use vkpath::render::adaptive::{is_noise_check_due, is_pixel_converged};
use vkpath::render::state_exr::read_state;

/// Runs vkpath, expects success, returns stderr.
fn vkpath_ok(dir: &Path, args: &[&str]) -> String {
    let output = common::vkpath(dir, args);
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(output.status.success(), "{args:?}: {stderr}");
    stderr
}

/// A 32x32 render of the built-in box (mis, Sobol) at `spp`, `extra` appended.
fn render(dir: &Path, spp: &str, extra: &[&str]) {
    let mut args = vec!["render", "--width", "32", "--height", "32", "--spp", spp];
    args.extend_from_slice(extra);
    vkpath_ok(dir, &args);
}

#[test]
fn converged_pixels_stop_with_fewer_samples_and_stay_consistent_with_a_reference() {
    let dir = tempfile::tempdir().unwrap();
    let threshold = 0.05f32;
    render(
        dir.path(),
        "256",
        &[
            "--noise-threshold",
            "0.05",
            "--noise-min-spp",
            "16",
            "-o",
            "adaptive.exr",
            "--checkpoint",
            "state.exr",
        ],
    );
    render(dir.path(), "1024", &["--moments", "-o", "reference.exr"]);
    // The EXR keeps every pixel's sample count (without --moments being asked for).
    let adaptive = read_exr(&dir.path().join("adaptive.exr")).unwrap();
    assert!(adaptive.has_moments, "an adaptive render keeps its counts");
    let counts = &adaptive.image.sample_count;
    assert!(
        counts.iter().all(|&n| (16.0..=256.0).contains(&n)),
        "{counts:?}"
    );
    let total: f64 = counts.iter().map(|&n| f64::from(n)).sum();
    let uniform_total = 256.0 * counts.len() as f64;
    // Measured: 69% of the uniform render's samples at this threshold (the dark and the
    // smooth pixels stop early, the noisy ones near the light and in the corners go on);
    // 85% leaves room for other drivers' rounding while still saying "fewer".
    assert!(
        total < 0.85 * uniform_total,
        "the adaptive render took {total} samples, the uniform one {uniform_total}"
    );
    let stopped = counts.iter().filter(|&&n| n < 256.0).count();
    assert!(
        stopped * 5 >= counts.len(),
        "only {stopped} pixels stopped early"
    );
    // Every pixel that stopped early did so because the kernel's is_pixel_converged held:
    // its Rust twin agrees on the state it stopped in (the raw sums of the checkpoint).
    let (state, _) = read_state(&dir.path().join("state.exr")).unwrap();
    let pixels = (state.width * state.height) as usize;
    assert_eq!(pixels, counts.len());
    for (pixel, &held) in counts.iter().enumerate() {
        let [s0, s1, s2, count] = state.texels[pixel];
        let [c0, c1, c2, _] = state.texels[pixels + pixel];
        let [q0, q1, q2, _] = state.texels[2 * pixels + pixel];
        assert_eq!(count, held, "pixel {pixel}: the EXR's count");
        if count < 256.0 {
            let sum = [s0 - c0, s1 - c1, s2 - c2];
            assert!(
                is_noise_check_due(count, 16) && is_pixel_converged(sum, count, [q0, q1, q2], threshold),
                "pixel {pixel} stopped at {count} samples, but the twins say it was not due or has not converged"
            );
        }
    }
    // And the image is an estimate of the same picture: block z-tests at the default
    // family-wise alpha of 1% (adaptive sampling's bias is far below the noise here).
    let output = common::vkpath(dir.path(), &["compare", "adaptive.exr", "reference.exr"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "compare: {stdout}");
}

#[test]
fn adaptive_images_do_not_depend_on_frames_or_tiles() {
    let dir = tempfile::tempdir().unwrap();
    let adaptive = ["--noise-threshold", "0.1", "--noise-min-spp", "4"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut args = adaptive.to_vec();
        args.extend_from_slice(extra);
        args
    };
    render(
        dir.path(),
        "48",
        &with(&["--samples-per-frame", "1", "-o", "a.exr"]),
    );
    render(
        dir.path(),
        "48",
        &with(&[
            "--samples-per-frame",
            "7",
            "--tile-size",
            "12",
            "-o",
            "b.exr",
        ]),
    );
    let output = common::vkpath(dir.path(), &["compare", "--exact", "a.exr", "b.exr"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}");
    let image = read_exr(&dir.path().join("a.exr")).unwrap().image;
    assert!(
        image.sample_count.iter().any(|&n| n < 48.0),
        "some pixel stopped early, so the split was put to the test"
    );
}

#[test]
fn bad_thresholds_and_splits_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (args, expected) in [
        (
            &["--noise-threshold", "0"][..],
            "must be a finite number > 0",
        ),
        (
            &["--noise-threshold", "0.1", "--noise-min-spp", "1"][..],
            "at least 2",
        ),
        (
            &["--noise-threshold", "0.1", "--shard", "0/2"][..],
            "cannot be split into shards",
        ),
        (
            &["--noise-threshold", "0.1", "--device", "0,0"][..],
            "cannot be split into shards or over several devices",
        ),
    ] {
        let mut all = vec!["render", "--width", "8", "--height", "8", "-o", "x.exr"];
        all.extend_from_slice(args);
        let output = common::vkpath(dir.path(), &all);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
    let stderr = vkpath_ok(
        dir.path(),
        &[
            "render",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "4",
            "--noise-min-spp",
            "8",
            "-o",
            "x.exr",
        ],
    );
    assert!(
        stderr.contains("--noise-min-spp has no effect without --noise-threshold"),
        "{stderr}"
    );
}
