//! The glTF camera convention end to end: a red marker at a known world point, seen by a
//! camera on a rotated node, lands on the expected pixel of a GPU render (loader, node
//! transforms, camera, image-plane maths and the row flip for output all take part).

use crate::common;

use std::path::Path;

use vkpath::{Integrator, RenderSettings, Renderer, Scene};

/// Writes a glTF scene: a camera node at (5, 0, 0) rotated +90 degrees about +Y (so it looks
/// down -X with +Y up and -Z to its right), yfov 0.8, and a 0.2 x 0.2 red square in the
/// plane x = 0, centred on the world point (0, 0.5, -1) through a parent node's translation.
fn write_marker_scene(dir: &Path) -> std::path::PathBuf {
    let half = 0.1f32;
    let positions: [[f32; 3]; 6] = [
        [0.0, -half, -half],
        [0.0, half, -half],
        [0.0, half, half],
        [0.0, -half, -half],
        [0.0, half, half],
        [0.0, -half, half],
    ];
    let bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(dir.join("marker.bin"), &bytes).unwrap();
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [
    {{"camera": 0, "translation": [5, 0, 0], "rotation": [0, {s}, 0, {s}]}},
    {{"translation": [0, 0.5, -1], "children": [2]}},
    {{"mesh": 0}}
  ],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.8, "znear": 0.01}}}}],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [1, 0, 0, 1]}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0}}]}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                  "min": [0, -{half}, -{half}], "max": [0, {half}, {half}]}}],
  "bufferViews": [{{"buffer": 0, "byteLength": {len}}}],
  "buffers": [{{"uri": "marker.bin", "byteLength": {len}}}]
}}"#,
        len = bytes.len()
    );
    let path = dir.join("marker.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn a_world_point_lands_on_the_expected_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::load(&write_marker_scene(dir.path())).unwrap();
    let camera = scene.camera.expect("the glTF camera is used");
    let (width, height) = (64u32, 64u32);
    let context = common::validated_context();
    let settings = RenderSettings {
        width,
        height,
        spp: 16,
        integrator: Integrator::RayTracing,
        ..Default::default()
    };
    let mut renderer = Renderer::new(&context, &scene, &camera, settings).unwrap();
    let image = renderer.render_all().unwrap();
    drop(renderer);
    common::assert_validation_silent(&context);

    // Expected: the marker is 5 m ahead, 1 m to the camera's right (world -Z) and 0.5 m up.
    // The image plane at 5 m spans 2 * 5 tan(0.4) in height (and width, aspect 1).
    let half_extent = 5.0 * 0.4f32.tan();
    let expected_x = (0.5 + 0.5 * 1.0 / half_extent) * width as f32;
    let expected_y = (0.5 - 0.5 * 0.5 / half_extent) * height as f32; // rows from the top
                                                                      // Centroid of the red coverage (box-filtered edges weigh in by their coverage).
    let (mut total, mut sum_x, mut sum_y) = (0.0f32, 0.0f32, 0.0f32);
    for y in 0..height {
        for x in 0..width {
            let red = image.pixel(x, y)[0];
            total += red;
            sum_x += red * (x as f32 + 0.5);
            sum_y += red * (y as f32 + 0.5);
        }
    }
    assert!(
        total > 4.0,
        "the marker is not in view (coverage {total} pixels)"
    );
    let (x, y) = (sum_x / total, sum_y / total);
    println!("marker centroid ({x:.2}, {y:.2}), expected ({expected_x:.2}, {expected_y:.2})");
    // A quarter pixel: the centroid of a 6-pixel-wide square with 16 jittered samples per
    // pixel is far more precise than that, while any convention error (a flipped axis, a
    // wrong handedness, a transform applied in the wrong order) moves it by many pixels.
    assert!((x - expected_x).abs() < 0.25 && (y - expected_y).abs() < 0.25);
}
