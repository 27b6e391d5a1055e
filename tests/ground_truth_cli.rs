//! Ground truth for machine learning through the binary (issue 56, `src/render/ground_truth.rs`):
//! `--aov object_id,instance_id,material_id,position,uv,object_position,z` on a scene whose
//! answer is known pixel by pixel: three quads one behind the other, the nearest an
//! alpha-masked leaf whose left half is a hole, seen straight on. Every ID is exact, every
//! point within float rounding of the ray's analytic hit; the sidecar names the IDs, and
//! `--json` counts each object's pixels and box. IDs in a PNG are refused in one line.

use crate::common;

use std::path::Path;

use serde_json::{json, Value};

/// Image size: 16 x 16 pixels, each 0.25 wide in the plane z = 0.
const SIZE: u32 = 16;

/// A 2 x 1 RGBA texture as a PNG data URI: the left texel transparent, the right opaque.
fn half_transparent_png() -> String {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, 2, 1);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().unwrap();
        writer
            .write_image_data(&[255, 255, 255, 0, 255, 255, 255, 255])
            .unwrap();
    }
    format!("data:image/png;base64,{}", base64::encode(&bytes))
}

/// The scene: node 0 `back` (a 6 x 6 quad at z = 0), node 1 `group` holding node 2 `front`
/// (a 2 x 2 quad, moved to z = 1 by its node), node 3 `leaf` (a 2 x 2 quad moved to z = 2,
/// alpha MASK with the texture above, nearest filtering: a hole where x < 0), node 4 the
/// camera at z = 4 looking down -z with tan(yfov / 2) = 1/2, so that the image spans
/// [-2, 2]^2 of the plane z = 0. Materials 0, 1, 2: back, front, leaf.
fn write_scene(dir: &Path) -> String {
    let quad = |half: f32| -> Vec<f32> {
        vec![
            -half, -half, 0.0, half, -half, 0.0, half, half, 0.0, -half, half, 0.0,
        ]
    };
    let uvs: Vec<f32> = vec![0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let indices: Vec<u16> = vec![0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = Vec::new();
    for positions in [quad(3.0), quad(1.0)] {
        bytes.extend(positions.iter().flat_map(|x| x.to_le_bytes()));
    }
    bytes.extend(uvs.iter().flat_map(|x| x.to_le_bytes()));
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let primitive = |positions: usize, material: usize| json!({"attributes": {"POSITION": positions, "TEXCOORD_0": 2}, "indices": 3, "material": material});
    let document = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 3, 4]}],
        "nodes": [
            {"name": "back", "mesh": 0},
            {"name": "group", "children": [2]},
            {"name": "front", "mesh": 1, "translation": [0, 0, 1]},
            {"name": "leaf", "mesh": 2, "translation": [0, 0, 2]},
            {"name": "camera", "camera": 0, "translation": [0, 0, 4]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 2.0 * 0.5f64.atan(), "aspectRatio": 1.0, "znear": 0.1}}],
        "meshes": [
            {"primitives": [primitive(0, 0)]},
            {"primitives": [primitive(1, 1)]},
            {"primitives": [primitive(1, 2)]}
        ],
        "materials": [
            {"name": "back", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.2, 1]}, "doubleSided": true},
            {"name": "front", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1]}, "doubleSided": true},
            {"name": "leaf", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": true}
        ],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "images": [{"uri": half_transparent_png()}],
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bytes))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 32},
            {"buffer": 0, "byteOffset": 128, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-3, -3, 0], "max": [3, 3, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let path = dir.join("layers.gltf");
    std::fs::write(&path, document.to_string()).unwrap();
    path.display().to_string()
}

/// What the ray through pixel (column, row from the top)'s centre hits first, worked out by
/// hand: (object_id, instance_id, material_id, world point, object point, uv).
fn expected(column: u32, row: u32) -> (u32, u32, u32, [f32; 3], [f32; 3], [f32; 2]) {
    // The ray from (0, 0, 4) through (x, y, 0) is at (x, y) (4 - z) / 4 in the plane z.
    let x = -2.0 + (column as f32 + 0.5) * 0.25;
    let y = 2.0 - (row as f32 + 0.5) * 0.25;
    let at = |z: f32| [x * (4.0 - z) / 4.0, y * (4.0 - z) / 4.0];
    let uv = |[px, py]: [f32; 2], half: f32| [(px / half + 1.0) / 2.0, (1.0 - py / half) / 2.0];
    let [lx, ly] = at(2.0);
    if x > 0.0 {
        // The leaf's opaque half (u >= 1/2)
        return (4, 3, 3, [lx, ly, 2.0], [lx, ly, 0.0], uv([lx, ly], 1.0));
    }
    let [fx, fy] = at(1.0);
    if fx.abs() < 1.0 && fy.abs() < 1.0 {
        return (3, 2, 2, [fx, fy, 1.0], [fx, fy, 0.0], uv([fx, fy], 1.0));
    }
    (1, 1, 1, [x, y, 0.0], [x, y, 0.0], uv([x, y], 3.0))
}

/// The channels of an EXR in `dir`, by name.
fn channels(dir: &Path, name: &str) -> std::collections::HashMap<String, Vec<f32>> {
    vkpath::image_io::exr_input::read_exr_channels(&dir.join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .channels
        .into_iter()
        .collect()
}

const LAYERS: &str = "object_id,instance_id,material_id,position,uv,object_position,z,motion";

#[test]
fn ids_and_points_are_exact_through_an_alpha_masked_leaf() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let size = SIZE.to_string();
    let args = [
        "render",
        &scene,
        "-o",
        "truth.exr",
        "--width",
        &size,
        "--height",
        &size,
        "--spp",
        "2",
        "--aov",
        LAYERS,
        "--json",
        "--camera-data",
        "--validate",
    ];
    let run = common::vkpath(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let layers = channels(dir.path(), "truth.exr");
    let layer = |name: &str| {
        layers
            .get(name)
            .unwrap_or_else(|| panic!("{name} in {:?}", layers.keys()))
    };
    let mut counts = std::collections::HashMap::<u32, u64>::new();
    for row in 0..SIZE {
        for column in 0..SIZE {
            let i = (row * SIZE + column) as usize;
            let (object, instance, material, world, object_point, uv) = expected(column, row);
            let at = format!("pixel ({column}, {row})");
            // IDs: exact integers
            assert_eq!(layer("object_id.Z")[i], object as f32, "{at}");
            assert_eq!(layer("instance_id.Z")[i], instance as f32, "{at}");
            assert_eq!(layer("material_id.Z")[i], material as f32, "{at}");
            *counts.entry(object).or_default() += 1;
            // Points: the analytic hit within float rounding (coordinates up to 3)
            let close = |got: f32, want: f32, what: &str| {
                assert!(
                    (got - want).abs() < 2e-6 * 4.0,
                    "{at} {what}: {got} != {want}"
                );
            };
            for (c, suffix) in ["R", "G", "B"].iter().enumerate() {
                close(
                    layer(&format!("position.{suffix}"))[i],
                    world[c],
                    "position",
                );
                close(
                    layer(&format!("object_position.{suffix}"))[i],
                    object_point[c],
                    "object_position",
                );
            }
            close(layer("uv.R")[i], uv[0], "u");
            close(layer("uv.G")[i], uv[1], "v");
            close(layer("z.Z")[i], 4.0 - world[2], "z");
        }
    }
    // The sidecar names each ID
    let names: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("truth.ids.json")).unwrap())
            .unwrap();
    let paths: Vec<(u64, &str)> = names["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| (o["id"].as_u64().unwrap(), o["path"].as_str().unwrap()))
        .collect();
    assert_eq!(paths, [(1, "/back"), (3, "/group/front"), (4, "/leaf")]);
    assert_eq!(names["instances"][1]["object_id"], 3);
    assert_eq!(names["materials"].as_array().unwrap().len(), 3);
    // --json counts each visible object's pixels, with its box
    let report: Value = serde_json::from_slice(&run.stdout).unwrap();
    let objects = report["objects"].as_array().unwrap();
    assert_eq!(objects.len(), 3, "{report}");
    for object in objects {
        let id = object["id"].as_u64().unwrap() as u32;
        assert_eq!(object["pixels"].as_u64().unwrap(), counts[&id], "{object}");
    }
    // The leaf covers the right half, columns 8..16 of every row
    assert_eq!(objects[2]["name"], "leaf");
    assert_eq!(objects[2]["bbox"], json!([8, 0, 16, 16]));
    assert_eq!(report["visible_fraction"], 1.0);
    // The camera data: K and the camera-to-world matrix (OpenCV) project each pixel's
    // world point onto the pixel's centre, and a known corner where the geometry says
    let camera: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("truth.json")).unwrap())
            .unwrap();
    assert_eq!(camera, report["camera_data"]);
    let project = |point: [f64; 3]| -> [f64; 2] {
        let k = |r: usize, c: usize| camera["k"][r][c].as_f64().unwrap();
        let m = |r: usize, c: usize| camera["camera_to_world_opencv"][r][c].as_f64().unwrap();
        // world to camera: the rotation's transpose applied to (point - position)
        let d: Vec<f64> = (0..3).map(|r| point[r] - m(r, 3)).collect();
        let axis = |c: usize| (0..3).map(|r| m(r, c) * d[r]).sum::<f64>();
        let (x, y, z) = (axis(0), axis(1), axis(2));
        [k(0, 0) * x / z + k(0, 2), k(1, 1) * y / z + k(1, 2)]
    };
    for row in 0..SIZE {
        for column in 0..SIZE {
            let i = (row * SIZE + column) as usize;
            let point = ["R", "G", "B"].map(|c| f64::from(layer(&format!("position.{c}"))[i]));
            let [u, v] = project(point);
            let at = format!("pixel ({column}, {row}) sees {point:?} at ({u}, {v})");
            assert!((u - f64::from(column)).abs() < 1e-3, "{at}");
            assert!((v - f64::from(row)).abs() < 1e-3, "{at}");
        }
    }
    // The front quad's corner (1, 1, 1) is 4/3 right of and above the centre in the plane
    // z = 0, 16/3 pixels: u = 7.5 + 16/3, v = 7.5 - 16/3
    let [u, v] = project([1.0, 1.0, 1.0]);
    assert!((u - (7.5 + 16.0 / 3.0)).abs() < 1e-4 && (v - (7.5 - 16.0 / 3.0)).abs() < 1e-4);
    let fov_y = camera["fov_y_degrees"].as_f64().unwrap();
    assert!(
        (fov_y - 2.0 * 0.5f64.atan().to_degrees()).abs() < 1e-4,
        "{fov_y}"
    );
}

#[test]
fn ids_in_a_png_are_refused_and_unknown_layers_list_the_known_ones() {
    let dir = tempfile::tempdir().unwrap();
    let run = common::vkpath(
        dir.path(),
        &[
            "render",
            "-o",
            "a.png",
            "--aov",
            "object_id",
            "--width",
            "4",
            "--height",
            "4",
        ],
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("--aov object_id: IDs are exact integers"),
        "{stderr}"
    );
    assert!(!dir.path().join("a.png").exists());
    let run = common::vkpath(dir.path(), &["render", "-o", "a.exr", "--aov", "object"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    for name in LAYERS.split(',') {
        assert!(stderr.contains(name), "{name}: {stderr}");
    }
}

/// The motion test's scene: a 10 x 10 quad in the plane z = 0 whose node slides along +x at
/// 1 unit/s (translation (t, 0, 0), LINEAR from 0 to 2 s), and a camera looking down -z
/// (tan(yfov / 2) = 1/2) whose node rises and comes closer, (0, t / 2, 4 - t / 2).
fn write_moving_scene(dir: &Path) -> String {
    let half = 5.0f32;
    let positions = [
        -half, -half, 0.0, half, -half, 0.0, half, half, 0.0, -half, half, 0.0,
    ];
    let times = [0.0f32, 2.0];
    let slide = [0.0f32, 0.0, 0.0, 2.0, 0.0, 0.0];
    let rise = [0.0f32, 0.0, 4.0, 0.0, 1.0, 3.0];
    let indices: Vec<u16> = vec![0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = Vec::new();
    for floats in [&positions[..], &times[..], &slide[..], &rise[..]] {
        bytes.extend(floats.iter().flat_map(|x| x.to_le_bytes()));
    }
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let document = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "quad", "mesh": 0},
            {"name": "camera", "camera": 0, "translation": [0, 0, 4]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 2.0 * 0.5f64.atan(), "aspectRatio": 1.0, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 4}]}],
        "animations": [{"channels": [
            {"sampler": 0, "target": {"node": 0, "path": "translation"}},
            {"sampler": 1, "target": {"node": 1, "path": "translation"}}
        ], "samplers": [{"input": 1, "output": 2}, {"input": 1, "output": 3}]}],
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bytes))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 8},
            {"buffer": 0, "byteOffset": 56, "byteLength": 24},
            {"buffer": 0, "byteOffset": 80, "byteLength": 24},
            {"buffer": 0, "byteOffset": 104, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-half, -half, 0], "max": [half, half, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [2.0]},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let path = dir.join("moving.gltf");
    std::fs::write(&path, document.to_string()).unwrap();
    path.display().to_string()
}

/// The flow of pixel (column, row) of `write_moving_scene` at time `t`, `dt` later (a
/// negative `dt`: earlier), worked out by hand: the pixel centre's ray meets the plane at
/// (X, Y, 0); the quad's point moves by dt along x; the camera (cx, cy, cz) sees (X', Y', 0)
/// at u = 16 (X' - cx) / cz + 7.5, v = 16 (cy - Y') / cz + 7.5 (16 pixels per unit at
/// distance 1: the image is 16 wide and tan(yfov / 2) = 1/2).
fn expected_flow(column: u32, row: u32, t: f64, dt: f64) -> [f64; 2] {
    let camera = |t: f64| (0.0, t / 2.0, 4.0 - t / 2.0);
    let (cx, cy, cz) = camera(t);
    let x = cx + cz * (f64::from(column) + 0.5 - 8.0) / 16.0 + dt;
    let y = cy - cz * (f64::from(row) + 0.5 - 8.0) / 16.0;
    let (cx, cy, cz) = camera(t + dt);
    let u = 16.0 * (x - cx) / cz + 7.5;
    let v = 16.0 * (cy - y) / cz + 7.5;
    [u - f64::from(column), v - f64::from(row)]
}

#[test]
fn motion_vectors_match_the_analytic_flow_and_regions_keep_them_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_moving_scene(dir.path());
    let size = SIZE.to_string();
    let render = |output: &str, extra: &[&str]| {
        let mut args = vec![
            "render", &scene, "-o", output, "--width", &size, "--height", &size, "--spp", "1",
            "--time", "1", "--fps", "4", "--aov", "motion",
        ];
        args.extend_from_slice(extra);
        let run = common::vkpath(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&run.stderr).to_string();
        assert!(run.status.success(), "{stderr}");
        stderr
    };
    let stderr = render("flow.exr", &[]);
    assert!(!stderr.contains("note: --aov motion"), "{stderr}");
    let layers = channels(dir.path(), "flow.exr");
    for row in 0..SIZE {
        for column in 0..SIZE {
            let i = (row * SIZE + column) as usize;
            for (layer, dt) in [("motion_forward", 0.25), ("motion_backward", -0.25)] {
                let want = expected_flow(column, row, 1.0, dt);
                let got = [
                    layers[&format!("{layer}.R")][i],
                    layers[&format!("{layer}.G")][i],
                ];
                let at = format!("pixel ({column}, {row}) {layer}: {got:?} != {want:?}");
                // The hit point's rounding (positions up to 5, f32) moves its projection by
                // about 1e-5 px; 0.05 px is the bound.
                assert!((f64::from(got[0]) - want[0]).abs() < 0.05, "{at}");
                assert!((f64::from(got[1]) - want[1]).abs() < 0.05, "{at}");
                assert_eq!(layers[&format!("{layer}.B")][i], 1.0, "{at}");
            }
        }
    }
    // The slide is 1 px a frame to the right; the camera's rise moves the image down
    assert!(layers["motion_forward.R"].iter().all(|&u| u > 0.5));
    // A region's layer is the full image's, bit for bit
    render("part.exr", &["--region", "3,2,11,9"]);
    let part = channels(dir.path(), "part.exr");
    for name in ["motion_forward.R", "motion_forward.G", "motion_backward.G"] {
        for y in 0..7u32 {
            for x in 0..8u32 {
                let whole = layers[name][((y + 2) * SIZE + x + 3) as usize];
                assert_eq!(
                    part[name][(y * 8 + x) as usize].to_bits(),
                    whole.to_bits(),
                    "{name} ({x}, {y})"
                );
            }
        }
    }
    // A still scene's motion vectors are 0, with one note
    let still = common::vkpath(
        dir.path(),
        &[
            "render",
            "-o",
            "still.exr",
            "--width",
            "4",
            "--height",
            "4",
            "--spp",
            "1",
            "--aov",
            "motion",
        ],
    );
    let stderr = String::from_utf8_lossy(&still.stderr);
    assert!(still.status.success(), "{stderr}");
    assert_eq!(stderr.matches("note: --aov motion").count(), 1, "{stderr}");
    let still = channels(dir.path(), "still.exr");
    assert!(still["motion_forward.R"].iter().all(|&u| u == 0.0));
    assert!(still["motion_backward.G"].iter().all(|&v| v == 0.0));
}
