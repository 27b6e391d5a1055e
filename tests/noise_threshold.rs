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

#[test]
fn the_summary_and_the_exr_say_how_many_samples_were_taken() {
    let dir = tempfile::tempdir().unwrap();
    let stderr = vkpath_ok(
        dir.path(),
        &[
            "render",
            "--width",
            "32",
            "--height",
            "32",
            "--spp",
            "256",
            "--noise-threshold",
            "0.1",
            "--noise-min-spp",
            "16",
            "-o",
            "a.exr",
        ],
    );
    let summary = stderr.lines().last().unwrap();
    // "... 32x32, mean M spp, cap 256, setup T s, render S s, R M samples/s"
    let after = |label: &str| -> f64 {
        let start = summary.find(label).unwrap_or_else(|| panic!("{summary}")) + label.len();
        summary[start..]
            .split([' ', ','])
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no number after '{label}': {summary}"))
    };
    let mean = after("mean ");
    assert!(summary.contains(" spp, cap 256, "), "{summary}");
    let image = read_exr(&dir.path().join("a.exr")).unwrap().image;
    let pixels = image.sample_count.len() as f64;
    let held: f64 = image.sample_count.iter().map(|&n| f64::from(n)).sum();
    assert!(
        held < 0.9 * 256.0 * pixels,
        "no pixel stopped early: {summary}"
    );
    assert!(
        (mean - held / pixels).abs() <= 0.5,
        "{summary}: {}",
        held / pixels
    );
    // The rate counts the samples taken, not 256 per pixel: rate x seconds is the samples
    // held, up to the rounding of the printed seconds (2 decimals) and rate (3).
    let seconds = after("render ");
    let rate = {
        let end = summary.rfind(" M samples/s").unwrap();
        let start = summary[..end].rfind(' ').unwrap() + 1;
        summary[start..end].parse::<f64>().unwrap()
    };
    let counted = rate * 1e6 * seconds;
    let slack = held * 0.006 / seconds.max(0.01) + 0.0006e6 * seconds + 0.01 * held;
    assert!(
        (counted - held).abs() <= slack,
        "{summary}: rate x seconds = {counted}, samples taken {held}"
    );
    // The EXR's vkpath attribute records the mean beside spp (the cap) and sample_range.
    let attributes =
        vkpath::render::state_exr::read_text_attributes(&dir.path().join("a.exr")).unwrap();
    let text = &attributes["vkpath"];
    let expected = format!(
        "spp=256; sample_range=0..256; spp_mean={:.2}; ",
        held / pixels
    );
    assert!(text.starts_with(&expected), "{text} vs {expected}");
}
