//! Tests of EXT_mesh_gpu_instancing in the glTF loader (a child module of `gltf_loader`).

use glam::Vec3;
use serde_json::json;

use super::test_support::{write, TestBuffer};
use super::*;

/// A triangle mesh drawn by a node at z = 1 with EXT_mesh_gpu_instancing's `attributes`
/// (name -> VEC3 floats) as a .gltf.
fn instanced_triangle(attributes: &[(&str, &[f32])]) -> String {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let mut instancing = json!({});
    for (name, values) in attributes {
        instancing[*name] = json!(buffer.floats("VEC3", values));
    }
    buffer.embedded(json!({
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, 1], "name": "forest",
                   "extensions": {"EXT_mesh_gpu_instancing": {"attributes": instancing}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions}}]}],
    }))
}

#[test]
fn each_instance_is_a_copy_of_the_mesh_in_the_nodes_space() {
    let text = instanced_triangle(&[
        (
            "TRANSLATION",
            &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 3.0, 0.0],
        ),
        ("SCALE", &[1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 1.0, 1.0, 1.0]),
    ]);
    let directory = tempfile::tempdir().unwrap();
    let scene = load_gltf(&write(&directory, "instanced.gltf", text)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let corners: Vec<[Vec3; 3]> = scene.triangles.iter().map(|t| t.positions).collect();
    let z = Vec3::Z;
    assert_eq!(
        corners,
        [
            [z, Vec3::X + z, Vec3::Y + z],
            [
                Vec3::new(2.0, 0.0, 1.0),
                Vec3::new(4.0, 0.0, 1.0),
                Vec3::new(2.0, 2.0, 1.0)
            ],
            [
                Vec3::new(0.0, 3.0, 1.0),
                Vec3::new(1.0, 3.0, 1.0),
                Vec3::new(0.0, 4.0, 1.0)
            ],
        ]
    );
    // Each instance is a copy of the mesh for the device's structures, named by its node
    assert_eq!(scene.mesh_instances.len(), 3);
    assert!(scene
        .mesh_instances
        .iter()
        .all(|i| i.node.as_ref().is_some_and(|n| n.name == "forest")));
}

#[test]
fn instances_whose_counts_differ_are_one_line_naming_the_node() {
    let text = instanced_triangle(&[
        ("TRANSLATION", &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0]),
        ("SCALE", &[1.0, 1.0, 1.0]),
    ]);
    let directory = tempfile::tempdir().unwrap();
    let error = load_gltf(&write(&directory, "bad.gltf", text))
        .unwrap_err()
        .to_string();
    assert!(!error.contains('\n'), "{error}");
    assert!(
        error.contains(
            "node 'forest': EXT_mesh_gpu_instancing SCALE has 1 elements, another attribute 2"
        ),
        "{error}"
    );
}
