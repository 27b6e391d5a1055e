//! Khronos' public keyframed and morph-target samples played by `vkpath render --frames`
//! (issue 41): BoxAnimated (CC BY 4.0, `tests/data/BoxAnimated.LICENSE.md`) and SimpleMorph
//! (CC0, `tests/data/SimpleMorph.LICENSE.md`). At each key time a frame is, pixel for pixel,
//! the render of the same file with its animations removed and the key's value written into
//! the node or the mesh (same seed and settings), and where worked out by hand the posed
//! geometry written as a static mesh; between keys BoxAnimated is neither neighbour.

use std::path::Path;

use serde_json::{json, Value};

use crate::common::runs::{exr_pixels as pixels, render_small};

/// Khronos' BoxAnimated: a small box (node 2, mesh "inner_box") rises out of a larger hollow
/// one, flips over and sinks. Its animations, LINEAR: node 0's translation keys (0, 0, 0) at
/// 0 s, (0, 2.52, 0) at 1.25 s and 2.5 s, (0, 0, 0) at 3.708 s; node 2's rotation keys
/// (-0, -0, -0, -1) (the identity) at 1.25 s and (1, 0, 0, 4.49e-11) (a half turn about +X)
/// at 2.5 s.
const BOX_ANIMATED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/BoxAnimated.gltf");

/// Khronos' SimpleMorph: one triangle (0, 0, 0), (1, 0, 0), (0.5, 0.5, 0) with two morph
/// targets that move its apex by (-1, 1, 0) and (1, 1, 0); the mesh's own weights are
/// (0.5, 0.5) and the animation keys the weights (0, 0), (0, 1), (1, 1), (1, 0), (0, 0) at
/// 0, 1, 2, 3 and 4 s, LINEAR.
const SIMPLE_MORPH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/SimpleMorph.gltf");

/// The key value of BoxAnimated's risen translation, as the file's float holds it.
const RISEN: f32 = 2.52;

/// The half turn about +X that BoxAnimated's rotation reaches at 2.5 s, x y z w as stored.
const FLIPPED: [f32; 4] = [1.0, 0.0, 0.0, 4.489_659_3e-11];

/// Renders `scene` with `extra` options to `output` in `dir`, small (`render_small`, 40 x 40).
fn render(dir: &Path, scene: &str, extra: &[&str], output: &str) {
    render_small(dir, scene, extra, output, "40");
}

/// The glTF document at `path` without its animations.
fn still_of(path: &str) -> Value {
    let mut document: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap())
        .expect("a sample is JSON glTF");
    document.as_object_mut().unwrap().remove("animations");
    document
}

/// Writes `document` as `dir/NAME.gltf` (the samples' buffers are embedded: it stands alone).
fn write(dir: &Path, name: &str, document: &Value) {
    std::fs::write(dir.join(format!("{name}.gltf")), document.to_string()).unwrap();
}

/// How many pixels of `a` and `b` differ by more than 0.05 in some channel.
fn pixels_apart(a: &[[f32; 4]], b: &[[f32; 4]]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| (x - y).abs() > 0.05))
        .count()
}

/// BoxAnimated seen from the front and above, framing both boxes at any time (the inner one
/// tops out at y = 3.02).
const BOX_VIEW: [&str; 4] = ["--camera-position", "2.6,2.4,3.6", "--look-at", "0,1.4,0"];

#[test]
fn khronos_box_animated_at_its_keys_is_the_posed_still_and_flips_between() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Frames 0-4 at 1.6 fps: 0, 0.625, 1.25, 1.875 and 2.5 s (f / 1.6 in f64 rounds to the
    // key times 1.25 and 2.5 exactly).
    let mut frames = vec!["--frames", "0..5", "--fps", "1.6"];
    frames.extend(BOX_VIEW);
    render(d, BOX_ANIMATED, &frames, "b_#.exr");
    // The stills: at rest (0 s), risen (1.25 s), risen and flipped (2.5 s), and risen and
    // turned a quarter (1.875 s: half-way between the rotation keys, slerp's half-angle).
    let rest = still_of(BOX_ANIMATED);
    let mut risen = rest.clone();
    risen["nodes"][0]["translation"] = json!([0.0, RISEN, 0.0]);
    let mut flipped = risen.clone();
    flipped["nodes"][2]["rotation"] = json!(FLIPPED);
    let mut quarter = risen.clone();
    let half = std::f32::consts::FRAC_1_SQRT_2;
    // slerp((0, 0, 0, -1), FLIPPED, ½): the keys are 90° apart as quaternions (dot 0, so no
    // sign flip), the mid-point is their normalised sum.
    quarter["nodes"][2]["rotation"] = json!([half, 0.0, 0.0, -half]);
    for (name, document) in [
        ("rest", &rest),
        ("risen", &risen),
        ("flipped", &flipped),
        ("quarter", &quarter),
    ] {
        write(d, name, document);
        render(
            d,
            &format!("{name}.gltf"),
            &BOX_VIEW,
            &format!("{name}.exr"),
        );
    }
    let frame = |f: usize| pixels(d, &format!("b_{f}.exr"));
    // At the key times the pose is the key's value, pixel for pixel.
    assert!(
        frame(0) == pixels(d, "rest.exr"),
        "0 s is not the rest pose"
    );
    assert!(
        frame(2) == pixels(d, "risen.exr"),
        "1.25 s is not the risen box"
    );
    assert!(
        frame(4) == pixels(d, "flipped.exr"),
        "2.5 s is not the flipped box"
    );
    // It moves: half-way up (0.625 s) is neither end, and the box rose (the test can fail: a
    // file whose animations were ignored renders the rest pose throughout).
    assert!(frame(1) != frame(0) && frame(1) != frame(2));
    let rose = pixels_apart(&frame(0), &frame(2));
    assert!(rose > 40, "the risen box moved {rose} pixels");
    // Mid-flip the box lies on its side: far from both key poses, near the quarter turn
    // written by hand (√½ rounds differently in the posing's slerp and in the file, so a few
    // pixels on the box's edges may differ; the key poses differ from it by the box's
    // changed silhouette: tens of pixels at 40 x 40).
    let mid = frame(3);
    let near = pixels_apart(&mid, &pixels(d, "quarter.exr"));
    let from_risen = pixels_apart(&mid, &frame(2));
    let from_flipped = pixels_apart(&mid, &frame(4));
    assert!(
        near <= 4 && from_risen > 4 * near.max(3) && from_flipped > 4 * near.max(3),
        "mid-flip: {near} pixels from the quarter turn, {from_risen} from the risen box, \
         {from_flipped} from the flipped one"
    );
}

/// SimpleMorph seen face on (the apex reaches y = 1.5 with one target, 2.5 with both).
const MORPH_VIEW: [&str; 4] = [
    "--camera-position",
    "0.5,1.25,4.2",
    "--look-at",
    "0.5,1.25,0",
];

/// SimpleMorph's triangle with `weights` applied, worked out by hand: only the apex moves.
fn simple_morph_posed(weights: [f32; 2]) -> [f32; 9] {
    let apex = [0.5 - weights[0] + weights[1], 0.5 + weights[0] + weights[1]];
    [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, apex[0], apex[1], 0.0]
}

/// A glTF with one triangle at `positions` and nothing else (its buffer embedded).
fn triangle(positions: [f32; 9]) -> Value {
    let mut bytes: Vec<u8> = [0u16, 1, 2, 0]
        .iter()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    bytes.extend(positions.iter().flat_map(|x| x.to_le_bytes()));
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::encode(&bytes)
    );
    json!({
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 1}, "indices": 0}]}],
        "buffers": [{"uri": uri, "byteLength": bytes.len()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 6},
                        {"buffer": 0, "byteOffset": 8, "byteLength": 36}],
        "accessors": [
            {"bufferView": 0, "componentType": 5123, "count": 3, "type": "SCALAR"},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [-0.5, 0.0, 0.0], "max": [1.5, 2.5, 0.0]}],
    })
}

#[test]
fn khronos_simple_morph_at_its_keys_is_the_mesh_with_those_weights() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Frames 0-3 at 1 fps: the keys (0, 0), (0, 1), (1, 1), (1, 0).
    let mut frames = vec!["--frames", "0..4", "--fps", "1"];
    frames.extend(MORPH_VIEW);
    render(d, SIMPLE_MORPH, &frames, "m_#.exr");
    // The file without its animation keeps the mesh's weights (0.5, 0.5): the animation
    // must override them at every frame.
    write(d, "own", &still_of(SIMPLE_MORPH));
    render(d, "own.gltf", &MORPH_VIEW, "own.exr");
    let keys = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
    for (f, weights) in keys.into_iter().enumerate() {
        // The same mesh with the key's weights as its own.
        let mut weighted = still_of(SIMPLE_MORPH);
        weighted["meshes"][0]["weights"] = json!(weights);
        write(d, &format!("w{f}"), &weighted);
        render(d, &format!("w{f}.gltf"), &MORPH_VIEW, &format!("w{f}.exr"));
        let frame = pixels(d, &format!("m_{f}.exr"));
        assert!(
            frame == pixels(d, &format!("w{f}.exr")),
            "{f} s is not the mesh with weights {weights:?}"
        );
        // The test can fail: a frame that kept the mesh's own weights is the (0.5, 0.5) pose.
        assert!(
            frame != pixels(d, "own.exr"),
            "{f} s kept the mesh's weights"
        );
    }
    // At 2 s both targets add: the triangle posed by hand, apex (0.5, 2.5, 0).
    write(d, "both", &triangle(simple_morph_posed(keys[2])));
    render(d, "both.gltf", &MORPH_VIEW, "both.exr");
    assert!(
        pixels(d, "m_2.exr") == pixels(d, "both.exr"),
        "2 s is not the triangle posed by hand with both weights 1"
    );
    // Every key is another shape.
    for f in 1..4 {
        let (a, b) = (
            pixels(d, &format!("m_{}.exr", f - 1)),
            pixels(d, &format!("m_{f}.exr")),
        );
        assert!(
            pixels_apart(&a, &b) > 20,
            "frames {} and {f} are alike",
            f - 1
        );
    }
}
