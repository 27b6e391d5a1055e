//! EXT_mesh_gpu_instancing: a node that draws its mesh once per instance, each instance's
//! transform made of its TRANSLATION, ROTATION and SCALE (accessors with one element per
//! instance; a missing one is the identity) and applied in the node's space (an instance is
//! drawn with node-to-world times its transform). The loader flattens every instance as it
//! flattens every node, and records each as a copy of the mesh (`MeshInstance`).

use glam::{Mat4, Quat, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use serde_json::Value;

use super::gltf_loader::{check_accessor, label, malformed};
use super::SceneError;

/// The extension's name.
pub const INSTANCING: &str = "EXT_mesh_gpu_instancing";

/// Node `node`'s instance transforms (node space), or None where it has no
/// EXT_mesh_gpu_instancing. A malformed extension (no attribute, an accessor that does not
/// exist or of a type the extension does not allow, counts that differ) is an error naming
/// the node.
pub fn instance_transforms(
    path: &std::path::Path,
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    node: &gltf::Node,
) -> Result<Option<Vec<Mat4>>, SceneError> {
    let Some(json) = document
        .as_json()
        .nodes
        .get(node.index())
        .and_then(|n| n.extensions.as_ref())
        .and_then(|e| e.others.get(INSTANCING))
    else {
        return Ok(None);
    };
    let node_name = label(node.name(), node.index());
    let wrong =
        |reason: String| malformed(path, format!("node '{node_name}': {INSTANCING} {reason}"));
    let attributes = json.get("attributes").and_then(Value::as_object);
    let accessor = |name: &str| -> Result<Option<gltf::Accessor>, SceneError> {
        let Some(index) = attributes.and_then(|a| a.get(name)) else {
            return Ok(None);
        };
        index
            .as_u64()
            .and_then(|i| document.accessors().nth(usize::try_from(i).ok()?))
            .map(Some)
            .ok_or_else(|| wrong(format!("{name} names no accessor of the file")))
    };
    let get = |buffer: gltf::Buffer| buffers.get(buffer.index()).map(|d| &d[..]);
    let outside = |name: &str| wrong(format!("{name} data lies outside its buffer"));
    let mut count = None;
    let mut counted = |name: &str, accessor: &gltf::Accessor| match count {
        Some(n) if n != accessor.count() => Err(wrong(format!(
            "{name} has {} elements, another attribute {n}",
            accessor.count()
        ))),
        _ => {
            count = Some(accessor.count());
            Ok(())
        }
    };
    let mut vec3s = |name: &str| -> Result<Option<Vec<Vec3>>, SceneError> {
        let Some(accessor) = accessor(name)? else {
            return Ok(None);
        };
        check_accessor(&accessor, Dimensions::Vec3, &[DataType::F32])
            .map_err(|reason| wrong(format!("{name}: {reason}")))?;
        counted(name, &accessor)?;
        let values =
            gltf::accessor::Iter::<[f32; 3]>::new(accessor, get).ok_or_else(|| outside(name))?;
        Ok(Some(values.map(Vec3::from).collect()))
    };
    let translations = vec3s("TRANSLATION")?;
    let scales = vec3s("SCALE")?;
    let rotations = match accessor("ROTATION")? {
        None => None,
        Some(accessor) => {
            use gltf::animation::util::Rotations;
            let types = [DataType::F32, DataType::I8, DataType::I16];
            check_accessor(&accessor, Dimensions::Vec4, &types)
                .map_err(|reason| wrong(format!("ROTATION: {reason}")))?;
            if accessor.data_type() != DataType::F32 && !accessor.normalized() {
                return Err(wrong(
                    "ROTATION is not normalized (the extension allows float, normalized byte or short)".into(),
                ));
            }
            counted("ROTATION", &accessor)?;
            let rotations = match accessor.data_type() {
                DataType::F32 => gltf::accessor::Iter::new(accessor, get).map(Rotations::F32),
                DataType::I8 => gltf::accessor::Iter::new(accessor, get).map(Rotations::I8),
                _ => gltf::accessor::Iter::new(accessor, get).map(Rotations::I16),
            }
            .ok_or_else(|| outside("ROTATION"))?;
            Some(rotations.into_f32().map(Vec4::from).collect::<Vec<_>>())
        }
    };
    let Some(count) = count else {
        return Err(wrong(
            "has none of the attributes TRANSLATION, ROTATION and SCALE".into(),
        ));
    };
    let transforms = (0..count)
        .map(|i| {
            let translation = translations.as_ref().map_or(Vec3::ZERO, |t| t[i]);
            let scale = scales.as_ref().map_or(Vec3::ONE, |s| s[i]);
            // A rotation that is no unit quaternion is normalised (none at all: identity)
            let rotation = rotations.as_ref().map_or(Quat::IDENTITY, |r| {
                let q = r[i].normalize_or_zero();
                if q == Vec4::ZERO {
                    Quat::IDENTITY
                } else {
                    Quat::from_vec4(q)
                }
            });
            Mat4::from_scale_rotation_translation(scale, rotation, translation)
        })
        .collect();
    Ok(Some(transforms))
}
