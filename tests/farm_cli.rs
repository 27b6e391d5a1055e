//! Sequences as a render farm expects them (issue 58): a time-limited render is a finished
//! one (`--denoise` and `--aov` still apply), `--skip-existing` skips only a finished image
//! of this very render, every frame's outputs are checked before the first sample, images
//! record their frame and time, and a finished frame's stale `.partial` files go. Tiny
//! images of the built-in box, 1 to 4 spp.

use std::path::Path;

use crate::common::runs::{run, Run};

/// The box at 8 x 8: a few milliseconds a frame on lavapipe.
const TINY: [&str; 4] = ["--width", "8", "--height", "8"];

/// `vkpath render` of the built-in box with `args` (and `TINY`, unless they give a
/// `--width`) in `dir`, which must succeed.
fn render(dir: &Path, args: &[&str]) -> Run {
    let mut all = vec!["render"];
    all.extend(args);
    if !args.contains(&"--width") {
        all.extend(TINY);
    }
    let result = run(dir, &all, &[]);
    assert_eq!(result.code, Some(0), "{all:?}: {}", result.stderr);
    result
}

/// The `vkpath` metadata text of an image (EXR header attribute or PNG tEXt chunk).
fn metadata_text(path: &Path) -> String {
    vkpath::render::state_exr::read_image_metadata(path)
        .unwrap()
        .expect("vkpath metadata")
        .fields()
        .iter()
        .map(|(name, value)| format!("{name}={value}"))
        .collect::<Vec<_>>()
        .join("; ")
}

/// Rewrites the metadata of the EXR `from` into `to`, its pixels as they are, with `edit`
/// applied to the metadata's text.
fn with_metadata(from: &Path, to: &Path, edit: impl Fn(String) -> String) {
    let image = vkpath::image_io::exr_input::read_exr(from).unwrap().image;
    let attributes = vec![("vkpath".to_string(), edit(metadata_text(from)))];
    vkpath::image_io::output::save_image_with_attributes(
        to,
        &image,
        &vkpath::image_io::output::SaveOptions::default(),
        &attributes,
    )
    .unwrap();
}

#[test]
fn a_time_limited_render_is_denoised_and_writes_its_aov_layers() {
    let dir = tempfile::tempdir().unwrap();
    // A million spp: the time limit stops it (the JSON says so), long before its end.
    let result = render(
        dir.path(),
        &[
            "--spp",
            "1048576",
            "--time-limit",
            "0.3",
            "--aov",
            "albedo",
            "--aov",
            "depth",
            "--denoise",
            "--json",
            "-o",
            "limited.exr",
        ],
    );
    assert_eq!(result.json()["stop"], "time-limit", "{}", result.stdout);
    assert!(
        !result.stderr.contains("without --aov"),
        "{}",
        result.stderr
    );
    let exr =
        vkpath::image_io::exr_input::read_exr_channels(&dir.path().join("limited.exr")).unwrap();
    let names: Vec<&str> = exr.channels.iter().map(|(n, _)| n.as_str()).collect();
    for channel in ["albedo.R", "depth.Z", "noisy.R", "R"] {
        assert!(names.contains(&channel), "no {channel}: {names:?}");
    }
    // The file says what was done to it (and that its render ended at the limit).
    let text = metadata_text(&dir.path().join("limited.exr"));
    assert!(
        text.contains("stop=time-limit; denoise=oidn-rt; aov=albedo,depth; version="),
        "{text}"
    );
}

#[test]
fn skip_existing_skips_only_a_finished_image_of_this_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Frames 1 and 2 finished at 4 spp; each other frame's file is wrong in one way.
    render(d, &["--frames", "1..3", "--spp", "4", "-o", "c_#.exr"]);
    std::fs::write(d.join("c_0.exr"), b"").unwrap();
    let whole = std::fs::read(d.join("c_1.exr")).unwrap();
    std::fs::write(d.join("c_1.exr"), &whole[..whole.len() / 2]).unwrap();
    render(
        d,
        &[
            "--frames", "3..4", "--spp", "2", "-o", "c_#.exr", "--width", "12", "--height", "8",
        ],
    );
    with_metadata(&d.join("c_2.exr"), &d.join("c_4.exr"), |text| {
        text.replace("integrator=mis", "integrator=nee").replace(
            "frame=2; time=0.08333333333333333",
            "frame=4; time=0.16666666666666666",
        )
    });
    render(
        d,
        &[
            "--frames",
            "5..6",
            "--spp",
            "2",
            "-o",
            "c_#.exr",
            "--background",
            "0.5,0.5,0.5",
        ],
    );
    render(d, &["--frames", "6..7", "--spp", "1", "-o", "c_#.exr"]);
    // A .partial file that a Ctrl-C left beside frame 6, holding fewer samples than the
    // frame will, and one beside frame 1 holding more: the first is stale, the second not.
    std::fs::copy(d.join("c_6.exr"), d.join("c_6.partial.exr")).unwrap();
    std::fs::copy(d.join("c_2.exr"), d.join("c_1.partial.exr")).unwrap();
    let kept = std::fs::read(d.join("c_2.exr")).unwrap();
    let result = render(
        d,
        &[
            "--frames",
            "0..7",
            "--spp",
            "2",
            "-o",
            "c_#.exr",
            "--skip-existing",
            "--json",
        ],
    );
    let says = |line: &str| {
        assert!(
            result.stderr.contains(line),
            "no '{line}':\n{}",
            result.stderr
        );
    };
    says("frame 0: 'c_0.exr' is unreadable (it is empty, not an OpenEXR file): rendering it again");
    says("frame 1: 'c_1.exr' is unreadable (");
    // A 4-spp frame asked at 2 is finished: skipped, not called partial.
    says("frame 2: 'c_2.exr' already finished, skipped (--skip-existing)");
    says("frame 3: 'c_3.exr' is another render (resolution 12x8, asked 8x8): rendering it again");
    says("frame 4: 'c_4.exr' is another render (integrator nee, asked mis): rendering it again");
    says("frame 5: 'c_5.exr' is another render (scene_hash ");
    says("frame 6: 'c_6.exr' is partial (it holds samples 0..1 of 0..2): rendering it again");
    says("removed 'c_6.partial.exr', left by a stopped render of frame 6");
    let stops: Vec<String> = result
        .stdout
        .lines()
        .map(|line| serde_json::from_str::<serde_json::Value>(line).unwrap()["stop"].to_string())
        .collect();
    assert_eq!(
        stops,
        ["done", "done", "skipped", "done", "done", "done", "done"].map(|s| format!("\"{s}\"")),
        "{}",
        result.stdout
    );
    assert_eq!(std::fs::read(d.join("c_2.exr")).unwrap(), kept);
    assert!(!d.join("c_6.partial.exr").exists());
    assert!(
        d.join("c_1.partial.exr").exists(),
        "a partial with more samples went"
    );
    // Every frame rendered again is now a finished image of its frame and time (24 fps).
    for frame in [0u32, 1, 3, 4, 5, 6] {
        let text = metadata_text(&d.join(format!("c_{frame}.exr")));
        let time = f64::from(frame) / 24.0;
        assert!(
            text.starts_with(&format!(
                "spp=2; sample_range=0..2; spp_requested=2; stop=done; frame={frame}; time={time}; version="
            )),
            "{text}"
        );
    }
    // The same command again skips every frame.
    let again = render(
        d,
        &[
            "--frames",
            "0..7",
            "--spp",
            "2",
            "-o",
            "c_#.exr",
            "--skip-existing",
        ],
    );
    assert_eq!(
        again.stderr.matches("already finished, skipped").count(),
        7,
        "{}",
        again.stderr
    );
}

#[test]
fn every_frames_output_is_checked_before_the_first_sample() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("d_0003.exr")).unwrap();
    let mut args = vec![
        "render",
        "--frames",
        "0..5",
        "-o",
        "d_####.exr",
        "--spp",
        "1",
    ];
    args.extend(TINY);
    let result = run(d, &args, &[]);
    assert_eq!(result.code, Some(1), "{}", result.stderr);
    assert_eq!(result.stderr.trim().lines().count(), 1, "{}", result.stderr);
    assert!(
        result.stderr.contains("frame 3's output")
            && result.stderr.contains("d_0003.exr")
            && result.stderr.contains("a directory"),
        "{}",
        result.stderr
    );
    assert!(!d.join("d_0000.exr").exists(), "frame 0 was rendered");
    // A frame outside the range, and a name of another width, are not its outputs.
    std::fs::remove_dir(d.join("d_0003.exr")).unwrap();
    std::fs::create_dir(d.join("d_0009.exr")).unwrap();
    std::fs::create_dir(d.join("d_3.exr")).unwrap();
    let result = run(d, &args, &[]);
    assert_eq!(result.code, Some(0), "{}", result.stderr);
    // The scene has no animation: said once, not per frame.
    assert_eq!(
        result.stderr.matches("no animation").count(),
        1,
        "{}",
        result.stderr
    );
    assert!(
        result.stderr.contains(
            "note: --frames: the scene has no animation, so its 5 frames are the same image"
        ),
        "{}",
        result.stderr
    );
}

#[test]
fn a_stopped_sequence_says_which_frame_stopped_and_which_remain() {
    use std::io::{BufRead, BufReader, Read};
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    // A million spp: the frame is still rendering (or setting up) when the signal comes.
    let mut child = Command::new(env!("CARGO_BIN_EXE_vkpath"))
        .args([
            "render", "--frames", "0..3", "-o", "s_#.png", "--spp", "1048576",
        ])
        .args(TINY)
        .current_dir(dir.path())
        .env("VKPATH_CACHE_DIR", crate::common::test_cache_dir())
        .env_remove("RUST_LOG")
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while !line.contains("vkpath: device") {
        line.clear();
        assert!(stderr.read_line(&mut line).unwrap() > 0, "no device line");
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    assert_eq!(child.wait().unwrap().code(), Some(130));
    let mut rest = String::new();
    stderr.read_to_string(&mut rest).unwrap();
    // Stopped in set-up (nothing written) or after some samples (saved beside): either way
    // the line names the frame and what remains.
    assert!(
        rest.contains(
            "; frame 0 of 0..3 stopped: frames 0..3 remain (--frames 0..3 --skip-existing renders them)"
        ),
        "{rest}"
    );
    assert!(!dir.path().join("s_1.png").exists());
}
