//! What `vkpath render --frames` decides once for a whole sequence (issue 58): a file
//! without a camera is framed by its whole animation (every frame the same camera, not a
//! view that zooms and jumps with the pose), and `--accel auto` on a small mesh that moves
//! takes the BVH in every frame (not the constant triangles, whose kernel every pose would
//! build again: seconds a frame on lavapipe).

use serde_json::{json, Value};

use crate::common::runs::run;
use crate::frames_cli::write_animated_quad;

/// Small, quick renders: 16 x 16 at 1 spp, lit by a white background.
const SMALL: [&str; 8] = [
    "--width",
    "16",
    "--height",
    "16",
    "--spp",
    "1",
    "--background",
    "1,1,1",
];

/// `frames_cli`'s quad (sliding from x = -1 at 0 s to x = 1 at 1 s) without its camera,
/// in front of a static quad twice its size centred at the origin, as `framed.gltf`.
fn write_camera_less(dir: &std::path::Path) {
    write_animated_quad(dir);
    let text = std::fs::read_to_string(dir.join("animated.gltf")).unwrap();
    let mut document: Value = serde_json::from_str(&text).unwrap();
    document["nodes"][1] = json!({"name": "wall", "mesh": 0, "scale": [2, 2, 1],
                                  "translation": [0, 0, -0.5]});
    document.as_object_mut().unwrap().remove("cameras");
    std::fs::write(dir.join("framed.gltf"), document.to_string()).unwrap();
}

/// The cameras of each frame's JSON report of `vkpath render ARGS SMALL --json` in `dir`.
fn cameras(dir: &std::path::Path, args: &[&str]) -> Vec<Value> {
    let mut args = args.to_vec();
    args.push("--json");
    args.extend(SMALL);
    let frames = run(dir, &args, &[]);
    assert_eq!(frames.code, Some(0), "{}", frames.stderr);
    frames
        .stdout
        .lines()
        .map(|line| serde_json::from_str::<Value>(line).unwrap()["camera"].clone())
        .collect()
}

#[test]
fn a_camera_less_moving_asset_keeps_one_camera_for_the_whole_sequence() {
    let dir = tempfile::tempdir().unwrap();
    write_camera_less(dir.path());
    let frames = ["render", "framed.gltf", "--fps", "1", "-o", "f_#.exr"];
    let with = |range: &'static str| {
        let mut args = frames.to_vec();
        args.extend(["--frames", range]);
        cameras(dir.path(), &args)
    };
    // Frame 0 sees the quad at x = -1, frame 1 at x = 1: before, each was framed by its own
    // pose (the view jumped)
    let sequence = with("0..2");
    assert_eq!(sequence.len(), 2);
    assert!(sequence[0]["position"].is_array(), "{}", sequence[0]);
    assert_eq!(sequence[0], sequence[1]);
    // A farm's task of one frame frames it alike
    assert_eq!(with("1..2"), [sequence[1].clone()]);
    // One line says which framing it took (without --json)
    let mut noted = frames.to_vec();
    noted.extend(["--frames", "0..1"]);
    noted.extend(SMALL);
    let stderr = run(dir.path(), &noted, &[]).stderr;
    let note = "framing the bounding sphere of its whole animation, for every frame";
    assert_eq!(stderr.matches(note).count(), 1, "{stderr}");
}

#[test]
fn auto_takes_one_traversal_for_every_frame_of_a_moving_small_mesh() {
    let dir = tempfile::tempdir().unwrap();
    write_animated_quad(dir.path());
    let mut args = vec!["render", "animated.gltf", "--frames", "0..3", "--fps", "2"];
    args.extend(["-o", "f_#.exr", "--json"]);
    args.extend(SMALL);
    let frames = run(dir.path(), &args, &[]);
    assert_eq!(frames.code, Some(0), "{}", frames.stderr);
    let reports: Vec<Value> = frames
        .stdout
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    assert_eq!(reports.len(), 3, "{}", frames.stdout);
    for (index, report) in reports.iter().enumerate() {
        assert_eq!(
            report["scene_memory"]["traversal"],
            json!("compressed BVH"),
            "frame {index}"
        );
        // One kernel for the sequence: every frame after the first takes it
        let reused = report["reused"].as_array().unwrap();
        assert_eq!(
            reused.contains(&json!("kernel")),
            index > 0,
            "frame {index}: {reused:?}"
        );
    }
    // A still of the same scene keeps the constant triangles (compiled in: the fastest
    // samples where one kernel serves), and its summary line names the traversal that ran
    let mut args = vec!["render", "animated.gltf", "--time", "0.5", "-o", "t.exr"];
    args.extend(SMALL);
    let still = run(dir.path(), &args, &[]);
    assert_eq!(still.code, Some(0), "{}", still.stderr);
    let summary = still.stderr.lines().last().unwrap_or_default();
    assert!(
        summary.contains("], traversal constant triangles, 16x16"),
        "{}",
        still.stderr
    );
}
