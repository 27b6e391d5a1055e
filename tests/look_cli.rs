//! The look of PNG files through the binary: `--tonemap`, `--exposure auto` and `render
//! --preview`, each with the validation layer on (a render fails when it reports anything),
//! and their bad values as one-line usage errors.

use crate::common;

use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// Runs vkpath in `dir`, expects success, returns stderr.
fn vkpath_ok(dir: &Path, args: &[&str]) -> String {
    let output = common::vkpath(dir, args);
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(output.status.success(), "{args:?}: {stderr}");
    stderr
}

/// The RGB bytes of a PNG, with its size.
fn pixels(path: &Path) -> (u32, u32, Vec<u8>) {
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    (image.width(), image.height(), image.into_raw())
}

/// The share of pixels with a channel at 255: clipped (or on the very top of the curve).
fn clipped_share(path: &Path) -> f64 {
    let (_, _, bytes) = pixels(path);
    let clipped = bytes.chunks(3).filter(|p| p.contains(&255)).count();
    clipped as f64 / (bytes.len() / 3) as f64
}

/// A small render of the built-in Cornell box with the validation layer on.
fn cornell(dir: &Path, output: &str, extra: &[&str]) -> String {
    let mut args = vec![
        "render",
        "-o",
        output,
        "--width",
        "64",
        "--height",
        "64",
        "--spp",
        "64",
        "--integrator",
        "mis",
        "--validate",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    vkpath_ok(dir, &args)
}

#[test]
fn tone_maps_change_pngs_but_never_exrs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    // Two stops up, the box's walls are far above 1: clamp clips them, the curves do not.
    for map in ["clamp", "aces", "agx"] {
        cornell(
            path,
            &format!("{map}.png"),
            &["--tonemap", map, "--exposure", "2"],
        );
        cornell(
            path,
            &format!("{map}.exr"),
            &["--tonemap", map, "--exposure", "2"],
        );
    }
    let (width, height, clamp) = pixels(&path.join("clamp.png"));
    assert_eq!((width, height), (64, 64));
    let (_, _, aces) = pixels(&path.join("aces.png"));
    let (_, _, agx) = pixels(&path.join("agx.png"));
    let differing = |a: &[u8], b: &[u8]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    // Measured: most channels differ; a tenth is a loose floor that still catches a
    // tone map that was silently ignored.
    for (name, other) in [("aces", &aces), ("agx", &agx)] {
        let n = differing(&clamp, other);
        assert!(
            n > clamp.len() / 10,
            "{name} differs from clamp in {n} channels"
        );
    }
    assert!(differing(&aces, &agx) > 0);
    // A bright scene: clamp clips, AgX rolls off.
    assert!(clipped_share(&path.join("clamp.png")) > 0.5);
    assert!(clipped_share(&path.join("agx.png")) < clipped_share(&path.join("clamp.png")));
    // EXR holds linear radiance whatever the tone map: the same file.
    let clamp_exr = std::fs::read(path.join("clamp.exr")).unwrap();
    for map in ["aces", "agx"] {
        assert!(
            std::fs::read(path.join(format!("{map}.exr"))).unwrap() == clamp_exr,
            "{map}.exr differs from clamp.exr"
        );
    }
}

#[test]
fn automatic_exposure_clips_under_one_percent_of_the_cornell_box() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    // The workshop's display (clamp at 0 stops), as every PNG was before tone maps: the
    // light and the walls near it clip (measured 31% of pixels at 512x512).
    cornell(
        path,
        "before.png",
        &["--tonemap", "clamp", "--exposure", "0"],
    );
    let before = clipped_share(&path.join("before.png"));
    assert!(before > 0.1, "clamp clipped only {before}");
    // The default tone map (agx) with automatic exposure.
    cornell(path, "auto.png", &["--exposure", "auto"]);
    let after = clipped_share(&path.join("auto.png"));
    assert!(after < 0.01, "{:.2}% of pixels clipped", after * 100.0);
    // Automatic exposure is scale-invariant: the picture is not black either (mid grey
    // lands near sRGB 118, so the mean byte is far from 0).
    let (_, _, bytes) = pixels(&path.join("auto.png"));
    let mean = bytes.iter().map(|&b| f64::from(b)).sum::<f64>() / bytes.len() as f64;
    assert!(mean > 40.0 && mean < 200.0, "mean byte {mean}");
}

#[test]
fn exercise_keeps_the_workshops_clamp_and_merge_tone_maps() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let exercise = |output: &str, extra: &[&str]| {
        let mut args = vec![
            "exercise",
            "path-tracing",
            "-o",
            output,
            "--width",
            "32",
            "--height",
            "32",
            "--validate",
        ];
        args.extend_from_slice(extra);
        vkpath_ok(path, &args);
        std::fs::read(path.join(output)).unwrap()
    };
    let default = exercise("default.png", &[]);
    assert_eq!(default, exercise("clamp.png", &["--tonemap", "clamp"]));
    assert_ne!(default, exercise("agx.png", &["--tonemap", "agx"]));
}

#[test]
fn a_preview_is_written_while_the_render_runs_and_at_the_end() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let preview = path.join("preview.png");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_vkpath"))
        .env("VKPATH_CACHE_DIR", common::test_cache_dir())
        .args([
            "render",
            "--integrator",
            "workshop",
            "-o",
            "out.exr",
            "--width",
            "48",
            "--height",
            "32",
            "--spp",
            "1000000",
            "--time-limit",
            "4",
            "--preview",
            "preview.png",
            "--preview-interval",
            "0.2",
            "--exposure",
            "auto",
            "--validate",
        ])
        .current_dir(path)
        .env_remove("RUST_LOG")
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .expect("the vkpath binary runs");
    // The first preview comes after the first batch past 0.2 s (batches last about 250 ms),
    // long before the 4 s limit.
    let started = Instant::now();
    let mut seen_while_running = false;
    while started.elapsed() < Duration::from_secs(30) {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if preview.is_file() {
            seen_while_running = true;
            let (width, height, _) = pixels(&preview);
            assert_eq!((width, height), (48, 32), "a partial preview");
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        seen_while_running,
        "no preview before the render ended: {stderr}"
    );
    // The last preview is of the final image; one line says so, no line per rewrite.
    assert_eq!(pixels(&preview).0, 48);
    assert_eq!(
        stderr.lines().filter(|l| l.contains("preview")).count(),
        1,
        "{stderr}"
    );
    assert!(stderr.contains("wrote preview.png (preview)"), "{stderr}");
    // No temporary file is left behind.
    let mut names: Vec<String> = std::fs::read_dir(path)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["out.exr", "preview.png"]);
}

#[test]
fn bad_look_options_are_one_line_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let render = ["render", "-o", "out.png", "--width", "8", "--height", "8"];
    for (bad, named) in [
        (&["--tonemap", "foo"][..], "--tonemap"),
        (&["--exposure", "nope"], "--exposure"),
        (&["--exposure", "inf"], "--exposure"),
        (
            &["--preview", "p.png", "--preview-interval", "0"],
            "--preview-interval",
        ),
        (
            &["--preview", "p.png", "--preview-interval", "-1"],
            "--preview-interval",
        ),
        (&["--preview-interval", "1"], "--preview"),
    ] {
        let mut args = render.to_vec();
        args.extend_from_slice(bad);
        let output = common::vkpath(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{bad:?}: {stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
        assert_eq!(errors.len(), 1, "{bad:?}: {stderr}");
        // clap names a missing required argument on the line after the error.
        let named_line = stderr.lines().skip_while(|l| !l.contains("error")).take(2);
        assert!(
            named_line.collect::<String>().contains(named),
            "{bad:?}: {stderr}"
        );
    }
    let bad = ["merge", "a.exr", "-o", "m.png", "--tonemap", "foo"];
    assert_eq!(common::vkpath(dir.path(), &bad).status.code(), Some(2));
    // A preview is a picture: an .exr preview is refused before rendering.
    let mut args = render.to_vec();
    args.extend_from_slice(&["--preview", "p.exr"]);
    let output = common::vkpath(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("p.exr") && stderr.contains(".png"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "files left behind"
    );
}
