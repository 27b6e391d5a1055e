//! Mirroring poses (a child module of `gltf_loader`): a triangle drawn through a transform
//! with a negative determinant keeps its front, whether the mirror is the node's own scale,
//! an animated scale or a skin's joint. Each mirrored quad must load triangle for triangle
//! as the quad under a static node with scale (-1, 1, 1): corners swapped so that the
//! counter-clockwise side is the mirrored front, +Z, and the shading normals on that side.

use glam::Vec3;
use serde_json::{json, Value};

use super::test_support::{write, TestBuffer};
use super::*;
use crate::scene::animation::AnimationPick;

/// The unit quad at z = 0, counter-clockwise seen from +Z, as a mesh's primitive: with a
/// NORMAL of +Z per vertex when `with_normals` (else the face's normal is used), and
/// JOINTS_0 / WEIGHTS_0 binding every vertex to joint 0 when `skinned`.
fn quad_primitive(buffer: &mut TestBuffer, with_normals: bool, skinned: bool) -> Value {
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let mut attributes = json!({"POSITION": buffer.positions(&corners)});
    if with_normals {
        attributes["NORMAL"] = json!(buffer.floats("VEC3", &[0.0, 0.0, 1.0].repeat(4)));
    }
    if skinned {
        attributes["JOINTS_0"] = json!(buffer.joints(&[[0; 4]; 4]));
        let weights = [1.0, 0.0, 0.0, 0.0].repeat(4);
        attributes["WEIGHTS_0"] = json!(buffer.floats("VEC4", &weights));
    }
    let indices = buffer.indices(&[0, 1, 2, 0, 2, 3]);
    json!({"attributes": attributes, "indices": indices})
}

/// The scale that mirrors x.
const MIRROR_X: [f32; 3] = [-1.0, 1.0, 1.0];

/// The quad on a node with scale (-1, 1, 1).
fn scaled(with_normals: bool) -> String {
    let mut buffer = TestBuffer::default();
    let primitive = quad_primitive(&mut buffer, with_normals, false);
    buffer.embedded(json!({
        "nodes": [{"mesh": 0, "scale": MIRROR_X}],
        "meshes": [{"primitives": [primitive]}],
    }))
}

/// The quad skinned to one joint "mirror" with scale (-1, 1, 1) (its inverse bind matrix the
/// identity); the skinned node itself is moved by (5, 0, 0), which skinning ignores.
fn skinned(with_normals: bool) -> String {
    let mut buffer = TestBuffer::default();
    let primitive = quad_primitive(&mut buffer, with_normals, true);
    buffer.embedded(json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "skin": 0, "translation": [5, 0, 0]},
            {"name": "mirror", "scale": MIRROR_X},
        ],
        "meshes": [{"primitives": [primitive]}],
        "skins": [{"joints": [1]}],
    }))
}

/// The quad on a node whose scale is animated LINEAR from (1, 1, 1) at 0 s to (-1, 1, 1) at
/// 1 s.
fn animated(with_normals: bool) -> String {
    let mut buffer = TestBuffer::default();
    let primitive = quad_primitive(&mut buffer, with_normals, false);
    let input = buffer.floats("SCALAR", &[0.0, 1.0]);
    let output = buffer.floats("VEC3", &[1.0, 1.0, 1.0, -1.0, 1.0, 1.0]);
    buffer.embedded(json!({
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [primitive]}],
        "animations": [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "scale"}}],
                        "samplers": [{"input": input, "output": output}]}],
    }))
}

/// The triangles' corners, winding normals and shading normals (glTF scenes have them, from
/// NORMAL or the face) of `text` loaded at `time`.
fn load(text: String, time: f32) -> Vec<([Vec3; 3], Vec3, Option<[Vec3; 3]>)> {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "quad.gltf", text);
    let options = LoadOptions {
        time,
        animation: AnimationPick::All,
        ..LoadOptions::default()
    };
    let scene = load_gltf_with(&path, &options).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let shading = scene.materials.as_ref().map(|m| &m.triangles);
    scene
        .triangles
        .iter()
        .enumerate()
        .map(|(t, triangle)| {
            let normals = shading.map(|s| s[t].normals);
            (triangle.positions, triangle.normal, normals)
        })
        .collect()
}

#[test]
fn mirrored_nodes_animations_and_skins_keep_the_front_on_the_counter_clockwise_side() {
    for with_normals in [false, true] {
        let reference = load(scaled(with_normals), 0.0);
        assert_eq!(reference.len(), 2);
        for (corners, normal, shading) in &reference {
            // Mirrored in x, the quad spans x in [-1, 0]; its front is still +Z.
            assert!(corners.iter().all(|c| c.x <= 0.0), "{corners:?}");
            assert_eq!(*normal, Vec3::Z);
            if let Some(shading) = shading {
                assert_eq!(*shading, [Vec3::Z; 3]);
            }
        }
        // The same triangles, corner for corner, where the mirror comes from an animated
        // scale or a skin's joint (before the fix a skinned mirror kept the bind pose's
        // corner order: its winding normal was -Z, its shading normals +Z).
        assert_eq!(
            load(animated(with_normals), 1.0),
            reference,
            "animated scale"
        );
        assert_eq!(
            load(skinned(with_normals), 0.0),
            reference,
            "mirroring joint"
        );
        // Unmirrored (the animation's first key) the quad keeps its corner order.
        let unmirrored = load(animated(with_normals), 0.0);
        assert_eq!(unmirrored[0].0[1], Vec3::X, "{unmirrored:?}");
        assert_eq!(unmirrored[0].1, Vec3::Z);
    }
}
