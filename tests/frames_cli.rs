//! `vkpath render --time / --frames / --fps / --animation / --skip-existing` (issue 41): a
//! keyframed glTF written by the test renders its motion, `--time` equals the matching frame
//! bit for bit, outputs take the frame number, and bad requests are one line before anything
//! renders.

use std::path::Path;

use serde_json::json;

use crate::common::runs::{exr_bits, run};

/// Writes `animated.gltf` (and `animated.bin`) into `dir`: a unit quad facing +Z whose node
/// slides LINEAR from x = -1 at 0 s to x = 1 at 1 s (animation "slide"), seen by a camera at
/// z = 3 looking down -Z.
pub(crate) fn write_animated_quad(dir: &Path) {
    let document = animated_quad(dir);
    std::fs::write(dir.join("animated.gltf"), document.to_string()).unwrap();
}

/// Writes `textured.gltf` (with `animated.bin` and `checker.png`) into `dir`: the quad of
/// `write_animated_quad` with a 2 x 2 red and blue checker as its base colour texture.
fn write_textured_quad(dir: &Path) {
    let mut document = animated_quad(dir);
    document["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = json!(4);
    document["meshes"][0]["primitives"][0]["material"] = json!(0);
    document["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
    document["textures"] = json!([{"source": 0}]);
    document["images"] = json!([{"uri": "checker.png"}]);
    let red_blue = [255, 0, 0, 0, 0, 255, 0, 0, 255, 255, 0, 0];
    vkpath::image_io::output::write_rgb8_png_with_texts(
        &dir.join("checker.png"),
        2,
        2,
        &red_blue,
        &[],
    )
    .unwrap();
    std::fs::write(dir.join("textured.gltf"), document.to_string()).unwrap();
}

/// The document of `write_animated_quad` (written with its `animated.bin`), whose buffer
/// also holds the quad's texture coordinates (accessor 4).
fn animated_quad(dir: &Path) -> serde_json::Value {
    let positions: [f32; 12] = [
        -0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0,
    ];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let times: [f32; 2] = [0.0, 1.0];
    let translations: [f32; 6] = [-1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    let tex_coords: [f32; 8] = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let mut bytes: Vec<u8> = Vec::new();
    let mut view = |data: Vec<u8>| {
        let offset = bytes.len();
        bytes.extend_from_slice(&data);
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
        json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len()})
    };
    let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let views = vec![
        view(floats(&positions)),
        view(indices.iter().flat_map(|i| i.to_le_bytes()).collect()),
        view(floats(&times)),
        view(floats(&translations)),
        view(floats(&tex_coords)),
    ];
    let document = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "quad", "mesh": 0},
            {"name": "camera", "camera": 0, "translation": [0, 0, 3]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "animations": [{
            "name": "slide",
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
            "samplers": [{"input": 2, "output": 3}],
        }],
        "buffers": [{"uri": "animated.bin", "byteLength": bytes.len()}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-0.5, -0.5, 0.0], "max": [0.5, 0.5, 0.0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR",
             "min": [0.0], "max": [1.0]},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC2"},
        ],
    });
    std::fs::write(dir.join("animated.bin"), &bytes).unwrap();
    document
}

/// Small, quick renders: 32 x 32 at 2 spp, lit by a white background.
const SMALL: [&str; 8] = [
    "--width",
    "32",
    "--height",
    "32",
    "--spp",
    "2",
    "--background",
    "1,1,1",
];

#[test]
fn frames_render_the_motion_and_time_equals_its_frame() {
    let dir = tempfile::tempdir().unwrap();
    write_animated_quad(dir.path());
    let mut args = vec![
        "render",
        "animated.gltf",
        "--frames",
        "0..3",
        "--fps",
        "2",
        "-o",
        "f_##.exr",
        "--json",
    ];
    args.extend(SMALL);
    let frames = run(dir.path(), &args, &[]);
    assert_eq!(frames.code, Some(0), "{}", frames.stderr);
    // One JSON object per line and frame, with its frame number and time.
    let reports: Vec<serde_json::Value> = frames
        .stdout
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    assert_eq!(reports.len(), 3, "{}", frames.stdout);
    for (index, report) in reports.iter().enumerate() {
        assert_eq!(report["frame"], json!(index));
        assert_eq!(report["time"], json!(index as f64 / 2.0));
        assert_eq!(report["outputs"], json!([format!("f_{index:02}.exr")]));
    }
    let read = |name: &str| exr_bits(dir.path(), name);
    // Frame 0 (x = -1) and frame 2 (x = 1) see the quad in different places.
    assert_ne!(read("f_00.exr"), read("f_02.exr"));
    // --time 1 is frame 2 at 2 fps, bit for bit.
    let mut args = vec!["render", "animated.gltf", "--time", "1", "-o", "t.exr"];
    args.extend(SMALL);
    let still = run(dir.path(), &args, &[]);
    assert_eq!(still.code, Some(0), "{}", still.stderr);
    assert!(
        read("t.exr") == read("f_02.exr"),
        "--time 1 differs from frame 2"
    );
}

#[test]
fn each_device_of_a_sequence_keeps_its_own_kernels_and_frames_equal_their_stills() {
    let dir = tempfile::tempdir().unwrap();
    write_animated_quad(dir.path());
    // Device 0 listed twice: two renderers, each with its own cache (on lavapipe, as in CI).
    // With the BVH: without one (`--accel auto` on 2 triangles) the triangles are the
    // kernel's specialization constants, and a quad that moves is a new kernel every frame.
    let devices = ["--device", "0,0", "--accel", "bvh"];
    let mut args = vec![
        "render",
        "animated.gltf",
        "--frames",
        "0..3",
        "--fps",
        "2",
        "-o",
        "d_#.exr",
        "--json",
    ];
    args.extend(devices);
    args.extend(SMALL);
    let frames = run(dir.path(), &args, &[]);
    assert_eq!(frames.code, Some(0), "{}", frames.stderr);
    let reused: Vec<serde_json::Value> = frames
        .stdout
        .lines()
        .map(|line| serde_json::from_str::<serde_json::Value>(line).unwrap()["reused"].clone())
        .collect();
    // Every frame after the first found its kernel and accumulation image on both devices,
    // and the parts of its upload that did not move (the quad moves: its geometry is
    // uploaded again). Before each device kept a cache, no frame on several devices reused
    // anything (`reused` was absent: null).
    let kept = json!([
        "kernel",
        "accumulation",
        "materials",
        "environment",
        "punctual_lights"
    ]);
    assert_eq!(reused, [json!([]), kept.clone(), kept], "{}", frames.stdout);
    // And a frame that took them is the still of its time on the same devices, bit for bit.
    let mut still = vec!["render", "animated.gltf", "--time", "1", "-o", "t.exr"];
    still.extend(devices);
    still.extend(SMALL);
    let still = run(dir.path(), &still, &[]);
    assert_eq!(still.code, Some(0), "{}", still.stderr);
    let read = |name: &str| exr_bits(dir.path(), name);
    assert!(
        read("t.exr") == read("d_2.exr"),
        "--time 1 on two devices differs from frame 2"
    );
    assert_ne!(read("d_0.exr"), read("d_2.exr"));
}

#[test]
fn a_textured_quad_that_moves_keeps_its_materials_and_frames_equal_their_stills() {
    let dir = tempfile::tempdir().unwrap();
    write_textured_quad(dir.path());
    let small = [
        "--width", "16", "--height", "16", "--spp", "1", "--accel", "bvh",
    ];
    let mut args = vec![
        "render",
        "textured.gltf",
        "--frames",
        "0..2",
        "--fps",
        "2",
        "-o",
        "q_#.exr",
        "--json",
        "--background",
        "1,1,1",
    ];
    args.extend(small);
    let frames = run(dir.path(), &args, &[]);
    assert_eq!(frames.code, Some(0), "{}", frames.stderr);
    let last: serde_json::Value =
        serde_json::from_str(frames.stdout.lines().last().unwrap()).unwrap();
    // The geometry moved ("scene" is not reused); the texture atlas and material words,
    // the background and the (no) punctual lights were taken from frame 0's upload.
    assert_eq!(
        last["reused"],
        json!([
            "kernel",
            "accumulation",
            "materials",
            "environment",
            "punctual_lights"
        ]),
        "{}",
        frames.stdout
    );
    let mut still = vec![
        "render",
        "textured.gltf",
        "--time",
        "0.5",
        "-o",
        "t.exr",
        "--background",
        "1,1,1",
    ];
    still.extend(small);
    let still = run(dir.path(), &still, &[]);
    assert_eq!(still.code, Some(0), "{}", still.stderr);
    let read = |name: &str| exr_bits(dir.path(), name);
    assert!(
        read("t.exr") == read("q_1.exr"),
        "--time 0.5 differs from frame 1"
    );
    assert_ne!(read("q_0.exr"), read("q_1.exr"));
}

#[test]
fn a_static_scene_is_the_same_every_frame_and_existing_frames_are_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec![
        "render",
        "--frames",
        "0..3",
        "-o",
        "c_#.exr",
        "--skip-existing",
        "--json",
    ];
    args.extend(&SMALL[..6]);
    // Frame 1 finished in an earlier run: --skip-existing leaves it as it is, and says so.
    let mut earlier = args.clone();
    earlier[2] = "1..2";
    let before = run(dir.path(), &earlier, &[]);
    assert_eq!(before.code, Some(0), "{}", before.stderr);
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    let finished_before = read("c_1.exr");
    let frames = run(dir.path(), &args, &[]);
    assert_eq!(frames.code, Some(0), "{}", frames.stderr);
    assert!(
        frames
            .stderr
            .contains("frame 1: 'c_1.exr' already finished, skipped"),
        "{}",
        frames.stderr
    );
    // One object per frame, the skipped one included.
    let stops: Vec<String> = frames
        .stdout
        .lines()
        .map(|line| serde_json::from_str::<serde_json::Value>(line).unwrap()["stop"].to_string())
        .collect();
    assert_eq!(stops, ["\"done\"", "\"skipped\"", "\"done\""]);
    // Frame 2 took frame 0's kernel, accumulation image and scene upload (the scene is
    // static), and is still the same image (below).
    let last: serde_json::Value =
        serde_json::from_str(frames.stdout.lines().last().unwrap()).unwrap();
    assert_eq!(last["reused"], json!(["kernel", "accumulation", "scene"]));
    assert!(
        read("c_1.exr") == finished_before,
        "frame 1 was rendered again"
    );
    assert!(
        exr_bits(dir.path(), "c_0.exr") == exr_bits(dir.path(), "c_2.exr"),
        "a static scene changed"
    );
    // A frame that holds fewer samples than asked (as a stop leaves it) is rendered again.
    let whole = read("c_2.exr");
    let partial = run(
        dir.path(),
        &[
            "render", "--width", "32", "--height", "32", "--spp", "1", "-o", "c_2.exr",
        ],
        &[],
    );
    assert_eq!(partial.code, Some(0), "{}", partial.stderr);
    let again = run(dir.path(), &args, &[]);
    assert_eq!(again.code, Some(0), "{}", again.stderr);
    assert!(
        again
            .stderr
            .contains("frame 2: 'c_2.exr' is partial (it holds samples 0..1 of 0..2)"),
        "{}",
        again.stderr
    );
    assert!(
        read("c_2.exr") == whole,
        "the partial frame was not rendered again"
    );
    // A PNG frame carries its metadata in tEXt chunks: one whose render a signal stopped
    // (its samples complete, as after a last batch) is rendered again; a finished one is
    // skipped.
    let mut png_args = args.clone();
    png_args[4] = "p_#.png";
    let pngs = run(dir.path(), &png_args, &[]);
    assert_eq!(pngs.code, Some(0), "{}", pngs.stderr);
    let texts = vkpath::image_io::output::read_png_texts(&dir.path().join("p_1.png")).unwrap();
    assert!(
        texts["vkpath"].contains("spp_requested=2; stop=done"),
        "{texts:?}"
    );
    let (width, height) = (32, 32);
    let stopped = vec![(
        "vkpath".to_string(),
        texts["vkpath"].replace("stop=done", "stop=signal"),
    )];
    vkpath::image_io::output::write_rgb8_png_with_texts(
        &dir.path().join("p_1.png"),
        width,
        height,
        &vec![0u8; (width * height * 3) as usize],
        &stopped,
    )
    .unwrap();
    let again = run(dir.path(), &png_args, &[]);
    assert_eq!(again.code, Some(0), "{}", again.stderr);
    assert!(
        again
            .stderr
            .contains("frame 1: 'p_1.png' is partial (its render stopped: signal)"),
        "{}",
        again.stderr
    );
    assert!(
        again
            .stderr
            .contains("frame 0: 'p_0.png' already finished, skipped"),
        "{}",
        again.stderr
    );
    let pixels = |name: &str| image::open(dir.path().join(name)).unwrap().to_rgb8();
    assert!(
        pixels("p_1.png") == pixels("p_0.png"),
        "frame 1 rendered again"
    );
}

#[test]
fn bad_times_frames_and_outputs_are_one_line_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    write_animated_quad(dir.path());
    for (args, expected) in [
        (vec!["--frames", "5..2", "-o", "a_#.png"], "START < END"),
        (
            vec!["--frames", "0..2", "--fps", "0", "-o", "a_#.png"],
            "frame rate",
        ),
        (vec!["--time", "-1", "-o", "a.png"], "at or after 0"),
        (vec!["--frames", "0..2", "-o", "a.png"], "no run of '#'"),
    ] {
        let mut full = vec!["render", "animated.gltf"];
        full.extend(&args);
        let result = run(dir.path(), &full, &[]);
        assert_eq!(result.code, Some(2), "{args:?}: {}", result.stderr);
        assert!(
            result.stderr.contains(expected),
            "{args:?}: {}",
            result.stderr
        );
    }
    assert!(!dir.path().join("a.png").exists());
    let mut full = vec![
        "render",
        "animated.gltf",
        "--animation",
        "jump",
        "-o",
        "a.png",
    ];
    full.extend(SMALL);
    let missing = run(dir.path(), &full, &[]);
    assert_eq!(missing.code, Some(1), "{}", missing.stderr);
    assert!(
        missing
            .stderr
            .contains("no animation of that name or index")
            && missing.stderr.contains("slide")
            && missing.stderr.trim().lines().count() == 1,
        "{}",
        missing.stderr
    );
}
