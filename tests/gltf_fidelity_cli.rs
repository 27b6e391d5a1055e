//! glTF fidelity through the binary (issue 59): vertex colours (`COLOR_0`) multiplied into
//! the base colour. Each test writes a small .gltf (with its buffer beside it) and renders
//! a few pixels of it.

use std::path::Path;

use serde_json::{json, Value};

use crate::common::runs::{exr_pixels, render_small};

/// Writes a quad (x, y in [-1, 1], z = 0, facing +z) with `attributes` (name -> (glTF
/// type, component type, normalized, the four vertices' little-endian bytes)) beside its
/// POSITION, the material `material` and a camera at z = `camera_z` looking at it (towards
/// -z, or back at it from behind where `camera_z` < 0), as `name` in `dir`; its path.
fn quad(
    dir: &Path,
    name: &str,
    attributes: &[(&str, &str, u32, bool, Vec<u8>)],
    material: Value,
    camera_z: f32,
) -> String {
    let positions: Vec<f32> = vec![
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ];
    let mut bytes: Vec<u8> = positions.iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut views = vec![json!({"buffer": 0, "byteOffset": 0, "byteLength": 48})];
    let mut accessors = vec![
        json!({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}),
    ];
    let mut primitive_attributes = json!({"POSITION": 0});
    for (semantic, kind, component_type, normalized, data) in attributes {
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": data.len()}));
        bytes.extend_from_slice(data);
        accessors.push(
            json!({"bufferView": views.len() - 1, "componentType": component_type,
                              "normalized": normalized, "count": 4, "type": kind}),
        );
        primitive_attributes[*semantic] = json!(accessors.len() - 1);
    }
    let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3]
        .iter()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    views.push(json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": 12}));
    bytes.extend_from_slice(&indices);
    accessors.push(
        json!({"bufferView": views.len() - 1, "componentType": 5123, "count": 6, "type": "SCALAR"}),
    );
    // glTF cameras look along their node's -z: turned half round about y to look at +z
    let rotation = if camera_z < 0.0 {
        json!([0, 1, 0, 0])
    } else {
        json!([0, 0, 0, 1])
    };
    let document = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, camera_z], "rotation": rotation}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.01}}],
        "meshes": [{"name": "quad", "primitives": [{"attributes": primitive_attributes, "indices": accessors.len() - 1, "material": 0}]}],
        "materials": [material],
        "buffers": [{"byteLength": bytes.len(), "uri": format!("{name}.bin")}],
        "bufferViews": views,
        "accessors": accessors,
    });
    std::fs::write(dir.join(format!("{name}.bin")), bytes).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, document.to_string()).unwrap();
    path.display().to_string()
}

/// An unlit material (its radiance is its base colour, exactly) with `base_color`.
fn unlit(base_color: [f32; 4]) -> Value {
    json!({"pbrMetallicRoughness": {"baseColorFactor": base_color},
           "extensions": {"KHR_materials_unlit": {}}})
}

#[test]
fn vertex_colors_multiply_the_base_color() {
    let dir = tempfile::tempdir().unwrap();
    // Red on the left edge (x = -1), blue on the right, as normalized bytes (VEC3); the base
    // colour halves them.
    let colors = vec![255u8, 0, 0, 0, 0, 255, 0, 0, 255, 255, 0, 0];
    let scene = quad(
        dir.path(),
        "colors",
        &[("COLOR_0", "VEC3", 5121, true, colors)],
        unlit([0.5, 0.5, 0.5, 1.0]),
        2.0,
    );
    render_small(dir.path(), &scene, &[], "colors.exr", "4");
    let pixels = exr_pixels(dir.path(), "colors.exr");
    for (i, [r, g, b, _]) in pixels.iter().copied().enumerate() {
        // Interpolated linearly: red and blue always sum to the base colour's 0.5; no green
        assert!(
            (r + b - 0.5).abs() < 1e-4 && g == 0.0,
            "pixel {i}: {r} {g} {b}"
        );
    }
    // Left of the middle redder than blue, right of it bluer (row 1, columns 0 and 3)
    let [left, right] = [pixels[4], pixels[7]];
    assert!(left[0] > 0.3 && right[2] > 0.3, "{left:?} {right:?}");
}

#[test]
fn a_vertex_color_of_a_forbidden_type_is_one_line_naming_the_mesh() {
    let dir = tempfile::tempdir().unwrap();
    // Bytes that are not normalized: glTF forbids them for COLOR_0
    let scene = quad(
        dir.path(),
        "bytes",
        &[("COLOR_0", "VEC4", 5121, false, vec![255u8; 16])],
        unlit([1.0; 4]),
        2.0,
    );
    let run = crate::common::runs::run(dir.path(), &["render", &scene, "-o", "bytes.exr"], &[]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(
        lines[0].contains("mesh 'quad' primitive 0: COLOR_0"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("bytes.exr").exists());
}
