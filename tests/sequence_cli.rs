//! What `vkpath render --frames` decides once for a whole sequence (issue 58): a file
//! without a camera is framed by its whole animation (every frame the same camera, not a
//! view that zooms and jumps with the pose), and `--accel auto` on a small mesh that moves
//! takes the BVH in every frame (not the constant triangles, whose kernel every pose would
//! build again: seconds a frame on lavapipe).

use serde_json::{json, Value};

use crate::common::runs::{exr_pixels, run};
use crate::frames_cli::write_animated_quad;

/// Small, quick renders: 24 x 24 at 1 spp, lit by a white background.
const SMALL: [&str; 8] = [
    "--width",
    "24",
    "--height",
    "24",
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

#[test]
fn a_camera_less_moving_asset_keeps_one_camera_for_the_whole_sequence() {
    let dir = tempfile::tempdir().unwrap();
    write_camera_less(dir.path());
    // The first hit's distance: where neither frame's quad is, the same camera sees the
    // static wall at the same distance, bit for bit.
    let mut args = vec!["render", "framed.gltf", "--frames", "0..2", "--fps", "1"];
    args.extend(["--integrator", "depth", "-o", "d_#.exr"]);
    args.extend(SMALL);
    let frames = run(dir.path(), &args, &[]);
    assert_eq!(frames.code, Some(0), "{}", frames.stderr);
    assert!(
        frames.stderr.contains("bounding sphere of its whole animation, for every frame"),
        "{}",
        frames.stderr
    );
    let (first, last) = (
        exr_pixels(dir.path(), "d_0.exr"),
        exr_pixels(dir.path(), "d_1.exr"),
    );
    let differing = first.iter().zip(&last).filter(|(a, b)| a != b).count();
    // The quad covers about a tenth of the view in each frame; a camera framed per pose
    // (before) moved the whole wall: 100% of the pixels differed.
    assert!(
        differing > 0 && differing * 3 < first.len(),
        "{differing} of {} pixels differ",
        first.len()
    );
    // A single frame's task of a farm frames it alike: frame 1 alone is the same image.
    let mut args = vec!["render", "framed.gltf", "--frames", "1..2", "--fps", "1"];
    args.extend(["--integrator", "depth", "-o", "alone_#.exr"]);
    args.extend(SMALL);
    let alone = run(dir.path(), &args, &[]);
    assert_eq!(alone.code, Some(0), "{}", alone.stderr);
    assert!(exr_pixels(dir.path(), "alone_1.exr") == last);
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
        assert_eq!(reused.contains(&json!("kernel")), index > 0, "frame {index}: {reused:?}");
    }
    // The summary line names the traversal that ran
    assert!(
        frames.stderr.contains("traversal compressed BVH, 24x24"),
        "{}",
        frames.stderr
    );
    // A still of the same scene keeps the constant triangles (compiled in: the fastest
    // samples where one kernel serves)
    let mut args = vec!["render", "animated.gltf", "--time", "0.5", "-o", "t.exr"];
    args.extend(["--json"]);
    args.extend(SMALL);
    let still = run(dir.path(), &args, &[]);
    assert_eq!(still.code, Some(0), "{}", still.stderr);
    assert_eq!(
        still.json()["scene_memory"]["traversal"],
        json!("constant triangles")
    );
}
