//! Skins and morph targets posed by `vkpath render --time / --frames` (issue 41): each frame of
//! a skinned strip and of a morphed quad is, pixel for pixel, the render of a static glTF with
//! the posed vertices written in (same seed and settings), and `--time` equals the matching
//! frame of `--frames` bit for bit.

use std::path::Path;

use serde_json::{json, Value};

use crate::common::runs::{exr_pixels as pixels, render_small, run, small_render_options};

/// A glTF document's buffer, views and accessors, written beside it as `NAME.bin`.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Buffer {
    /// An accessor of `kind` and `component` over `data`, `count` elements; its index.
    fn accessor(&mut self, data: Vec<u8>, kind: &str, component: u32, count: usize) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bytes.len(),
                               "byteLength": data.len()}));
        self.bytes.extend_from_slice(&data);
        let mut accessor = json!({"bufferView": self.views.len() - 1, "componentType": component,
                                  "count": count, "type": kind});
        if kind == "VEC3" {
            // POSITION needs its bounds; a loose box is allowed for any VEC3.
            accessor["min"] = json!([-9, -9, -9]);
            accessor["max"] = json!([9, 9, 9]);
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A FLOAT accessor of `kind` with `width` floats per element.
    fn floats(&mut self, kind: &str, width: usize, values: &[f32]) -> usize {
        let data = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(data, kind, 5126, values.len() / width)
    }

    /// An UNSIGNED_SHORT accessor of `kind` with `width` per element.
    fn shorts(&mut self, kind: &str, width: usize, values: &[u16]) -> usize {
        let data = values.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(data, kind, 5123, values.len() / width)
    }

    /// Writes `dir/NAME.gltf` and `dir/NAME.bin`: `rest` plus this buffer and a camera node
    /// at (3, 0.5, 4) turned 30° about +Y (looking towards (0.7, 0.5, 0)) as node `camera`.
    fn write(&self, dir: &Path, name: &str, mut rest: Value, camera: usize) {
        let (sin, cos) = 15f32.to_radians().sin_cos();
        rest["asset"] = json!({"version": "2.0"});
        rest["nodes"].as_array_mut().unwrap().push(json!(
            {"camera": 0, "translation": [3, 0.5, 4], "rotation": [0, sin, 0, cos]}));
        rest["scene"] = json!(0);
        rest["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(json!(camera));
        rest["cameras"] =
            json!([{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}]);
        rest["buffers"] = json!([{"uri": format!("{name}.bin"), "byteLength": self.bytes.len()}]);
        rest["bufferViews"] = json!(self.views);
        rest["accessors"] = json!(self.accessors);
        std::fs::write(dir.join(format!("{name}.bin")), &self.bytes).unwrap();
        std::fs::write(dir.join(format!("{name}.gltf")), rest.to_string()).unwrap();
    }
}

/// The strip's two quads, (0..1) x (0..1) and (1..2) x (0..1) at z = 0, as two triangles each.
const STRIP_INDICES: [u16; 12] = [0, 2, 1, 1, 2, 3, 2, 4, 3, 3, 4, 5];

/// Writes `skin.gltf`: the strip skinned to "shoulder" (origin) and its child "elbow" at
/// (1, 0, 0), whose rotation turns LINEAR from none at 0 s to a half turn about +X at 1 s
/// (a quarter turn's quaternion has components √½, whose rounding would keep the pose a few
/// ulps from any hand-written one; a half turn's are 0 and 1). x = 0 follows the shoulder,
/// (1, 0) half each, (1, 1) 3/4 the shoulder, x = 2 the elbow. The strip's node is
/// translated by (5, 0, 0), which skinning ignores.
fn write_skinned(dir: &Path) {
    let mut buffer = Buffer::default();
    let positions = buffer.floats("VEC3", 3, &STRIP_FLAT);
    let indices = buffer.shorts("SCALAR", 1, &STRIP_INDICES);
    let joints = buffer.shorts(
        "VEC4",
        4,
        &[
            0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0,
        ],
    );
    let weights = buffer.floats(
        "VEC4",
        4,
        &[
            1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.75, 0.25, 0.0, 0.0, 1.0,
            0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        ],
    );
    let mut inverse_binds = glam::Mat4::IDENTITY.to_cols_array().to_vec();
    inverse_binds.extend(glam::Mat4::from_translation(-glam::Vec3::X).to_cols_array());
    let inverse_binds = buffer.floats("MAT4", 16, &inverse_binds);
    let times = buffer.floats("SCALAR", 1, &[0.0, 1.0]);
    let turns = buffer.floats("VEC4", 4, &[0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
    let rest = json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "strip", "mesh": 0, "skin": 0, "translation": [5, 0, 0]},
            {"name": "shoulder", "children": [2]},
            {"name": "elbow", "translation": [1, 0, 0]},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions, "JOINTS_0": joints,
                                                   "WEIGHTS_0": weights}, "indices": indices}]}],
        "skins": [{"name": "arm", "joints": [1, 2], "inverseBindMatrices": inverse_binds}],
        "animations": [{"name": "bend",
            "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}],
            "samplers": [{"input": times, "output": turns}]}],
    });
    buffer.write(dir, "skin", rest, 3);
}

/// The strip at rest.
const STRIP_FLAT: [f32; 18] = [
    0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 2.0, 0.0, 0.0, 2.0, 1.0, 0.0,
];

/// The strip turned a half turn about +X at the elbow, worked out by hand: (1, 0, 0) and
/// (2, 0, 0) lie on the axis and stay; (2, 1, 0) goes to (2, -1, 0); (1, 1, 0) goes 3/4 with
/// the shoulder (staying) and 1/4 with the elbow (to (1, -1, 0)): to (1, 0.5, 0).
const STRIP_BENT: [f32; 18] = [
    0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.5, 0.0, 2.0, 0.0, 0.0, 2.0, -1.0, 0.0,
];

/// Writes `NAME.gltf`: a static mesh with `positions` and `indices`, seen by the same camera.
fn write_static(dir: &Path, name: &str, positions: &[f32], indices: &[u16]) {
    let mut buffer = Buffer::default();
    let positions = buffer.floats("VEC3", 3, positions);
    let indices = buffer.shorts("SCALAR", 1, indices);
    let rest = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions}, "indices": indices}]}],
    });
    buffer.write(dir, name, rest, 1);
}

/// The quad of the morph test, (0..1) x (0..1) at z = 0.
const QUAD: [f32; 12] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];
const QUAD_INDICES: [u16; 6] = [0, 1, 2, 0, 2, 3];

/// The quad's morph target: its top edge moves by (0.5, 0.5, -1).
const QUAD_DELTA: [f32; 12] = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.5, -1.0, 0.5, 0.5, -1.0];

/// Writes `morph.gltf`: the quad whose one morph target's weight goes LINEAR from 0 at 0 s to
/// 1 at 1 s (animation "stretch").
fn write_morphed(dir: &Path) {
    let mut buffer = Buffer::default();
    let positions = buffer.floats("VEC3", 3, &QUAD);
    let indices = buffer.shorts("SCALAR", 1, &QUAD_INDICES);
    let delta = buffer.floats("VEC3", 3, &QUAD_DELTA);
    let times = buffer.floats("SCALAR", 1, &[0.0, 1.0]);
    let weights = buffer.floats("SCALAR", 1, &[0.0, 1.0]);
    let rest = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions}, "indices": indices,
                                    "targets": [{"POSITION": delta}]}],
                    "weights": [0.0]}],
        "animations": [{"name": "stretch",
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
            "samplers": [{"input": times, "output": weights}]}],
    });
    buffer.write(dir, "morph", rest, 1);
}

/// Renders `scene` with `extra` options to `output` in `dir`, small (`render_small`, 32 x 32),
/// and fails where vkpath says something is not supported.
fn render(dir: &Path, scene: &str, extra: &[&str], output: &str) {
    let result = render_small(dir, scene, extra, output, "32");
    assert!(
        !result.stderr.contains("not supported"),
        "{}",
        result.stderr
    );
}

#[test]
fn a_skinned_strip_turns_with_its_joint_and_time_equals_its_frame() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_skinned(d);
    write_static(d, "flat", &STRIP_FLAT, &STRIP_INDICES);
    write_static(d, "bent", &STRIP_BENT, &STRIP_INDICES);
    render(
        d,
        "skin.gltf",
        &["--frames", "0..3", "--fps", "2"],
        "f_#.exr",
    );
    render(d, "skin.gltf", &["--time", "1"], "t.exr");
    render(d, "flat.gltf", &[], "flat.exr");
    render(d, "bent.gltf", &[], "bent.exr");
    // The pose is the geometry written by hand, pixel for pixel: at rest at 0 s, bent at 1 s.
    assert!(
        pixels(d, "f_0.exr") == pixels(d, "flat.exr"),
        "frame 0 is not the flat strip"
    );
    assert!(
        pixels(d, "f_2.exr") == pixels(d, "bent.exr"),
        "frame 2 is not the bent strip"
    );
    // Half-way it is neither (the test can fail: the pose moves).
    assert!(pixels(d, "f_1.exr") != pixels(d, "f_2.exr"));
    assert!(pixels(d, "f_1.exr") != pixels(d, "f_0.exr"));
    // --time 1 is frame 2 at 2 fps, bit for bit.
    let read = |name: &str| crate::common::runs::exr_bits(d, name);
    assert!(
        read("t.exr") == read("f_2.exr"),
        "--time 1 differs from frame 2"
    );
}

#[test]
fn a_morph_target_at_weight_0_half_and_1_is_its_base_midpoint_and_target() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_morphed(d);
    for (name, weight) in [("w0", 0.0f32), ("w05", 0.5), ("w1", 1.0)] {
        let posed: Vec<f32> = QUAD
            .iter()
            .zip(QUAD_DELTA)
            .map(|(p, d)| p + weight * d)
            .collect();
        write_static(d, name, &posed, &QUAD_INDICES);
        render(d, &format!("{name}.gltf"), &[], &format!("{name}.exr"));
    }
    render(
        d,
        "morph.gltf",
        &["--frames", "0..3", "--fps", "2"],
        "m_#.exr",
    );
    for (frame, name) in [(0, "w0"), (1, "w05"), (2, "w1")] {
        assert!(
            pixels(d, &format!("m_{frame}.exr")) == pixels(d, &format!("{name}.exr")),
            "frame {frame} is not the quad at weight {name}"
        );
    }
    assert!(pixels(d, "w05.exr") != pixels(d, "w0.exr"));
    assert!(pixels(d, "w05.exr") != pixels(d, "w1.exr"));
}

/// Khronos' RiggedSimple sample (CC BY 4.0, `tests/data/RiggedSimple.LICENSE.md`): a
/// cylinder skinned to two joints whose upper one bends (LINEAR keys at 1/24, 25/24 and 50/24
/// s, bent most at the middle one), seen from its side.
const RIGGED_SIMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/RiggedSimple.gltf");

/// A camera on +X, 18 units out, looking at the origin (the cylinder stands along Y, 9.2
/// tall, and bends in the YZ plane).
const SIDE_VIEW: [&str; 4] = ["--camera-position", "18,0,0", "--look-at", "0,0,0"];

#[test]
fn khronos_rigged_simple_bends_and_a_sequence_frame_equals_its_still() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut frames = vec!["render", RIGGED_SIMPLE, "-o", "r_#.exr", "--frames", "0..3"];
    frames.extend(["--fps", "2", "--json"]);
    frames.extend(SIDE_VIEW);
    frames.extend(small_render_options("32"));
    let sequence = run(d, &frames, &[]);
    assert_eq!(sequence.code, Some(0), "{}", sequence.stderr);
    // Each frame after the first keeps the kernel and the accumulation image; the scene
    // moved, so its geometry is uploaded again, and the parts that did not move are kept.
    let reused: Vec<Value> = sequence
        .stdout
        .lines()
        .map(|line| serde_json::from_str::<Value>(line).unwrap()["reused"].clone())
        .collect();
    let kept = json!([
        "kernel",
        "accumulation",
        "materials",
        "environment",
        "punctual_lights"
    ]);
    assert_eq!(
        reused,
        [json!([]), kept.clone(), kept],
        "{}",
        sequence.stdout
    );
    let mut still = vec!["--time", "1"];
    still.extend(SIDE_VIEW);
    render(d, RIGGED_SIMPLE, &still, "t.exr");
    let images: Vec<Vec<[f32; 4]>> = (0..3).map(|f| pixels(d, &format!("r_{f}.exr"))).collect();
    for (frame, image) in images.iter().enumerate() {
        assert!(
            image.iter().flatten().all(|c| c.is_finite()),
            "frame {frame} has a NaN or infinite pixel"
        );
        // The cylinder (green, base colour 0.28, 0.64, 0.21) covers some pixels: fewer than
        // all are the white background.
        let covered = image.iter().filter(|p| p[0] < 0.9).count();
        assert!(
            covered > 20,
            "frame {frame}: the cylinder covers {covered} pixels"
        );
    }
    // The upper joint bends between 0 s and 1 s (the test can fail: a rest pose throughout
    // gives the same image).
    assert!(images[0] != images[2], "frame 2 is the rest pose");
    assert!(images[1] != images[2], "frames 1 and 2 are the same pose");
    // Frame 2 came from a sequence that kept its kernel and accumulation image from frame 1
    // (and uploaded the moved scene again); `--time 1` renders it alone: bit for bit the same.
    let read = |name: &str| crate::common::runs::exr_bits(d, name);
    assert!(
        read("t.exr") == read("r_2.exr"),
        "--time 1 differs from frame 2"
    );
}
