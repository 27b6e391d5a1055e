//! glTF 2.0 scenes (`.gltf` with external or data-URI buffers, `.glb`) via the `gltf` crate:
//! the default scene's node hierarchy flattened to world-space triangles, the material's
//! constant factors as the workshop's diffuse material, and the first perspective camera.
//!
//! Malformed input must give an error, never a panic. The `gltf` crate indexes and slices
//! without checks in a few places that its validation does not cover, so we check those
//! things ourselves before asking it: the GLB header's length, POSITION accessor indices,
//! accessor types and extents, and camera types.

use std::collections::HashSet;
use std::path::Path;

use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::camera::Type as CameraType;
use gltf::json::validation::{Checked, Validate};
use gltf::mesh::Mode;
use gltf::{Document, Gltf, Node};

use super::{Material, Scene, SceneBuilder, SceneError};
use crate::camera::Camera;

/// Loads a glTF 2.0 file (JSON or binary), resolving external buffers relative to its
/// directory. Textures are ignored with a warning per material.
pub fn load_gltf(path: &Path) -> Result<Scene, SceneError> {
    let bytes = std::fs::read(path).map_err(|error| SceneError::Read {
        path: path.to_owned(),
        error,
    })?;
    let gltf_error = |error| SceneError::Gltf {
        path: path.to_owned(),
        error,
    };
    check_glb_header(path, &bytes)?;
    let Gltf { document, blob } =
        Gltf::from_slice_without_validation(&bytes).map_err(gltf_error)?;
    validate(path, &document)?;
    let base = path.parent().unwrap_or(Path::new(""));
    let buffers = gltf::import_buffers(&document, Some(base), blob).map_err(gltf_error)?;

    let mut loader = Loader {
        document: &document,
        buffers: &buffers,
        builder: SceneBuilder::new(path),
        warned_materials: HashSet::new(),
        orthographic_camera: None,
    };
    for (node, world) in flatten_hierarchy(path, &document)? {
        loader.visit(&node, world)?;
    }
    if let (false, Some(camera)) = (loader.builder.has_camera(), loader.orthographic_camera) {
        return Err(SceneError::OrthographicCamera {
            path: path.to_owned(),
            camera,
        });
    }
    loader.builder.finish()
}

/// The `gltf` crate computes `length - 12` from a GLB header unchecked; reject lengths that
/// would underflow.
fn check_glb_header(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    if let [b'g', b'l', b'T', b'F', _, _, _, _, l0, l1, l2, l3, ..] = *bytes {
        let length = u32::from_le_bytes([l0, l1, l2, l3]);
        if length < 12 {
            return Err(malformed(
                path,
                format!("GLB header declares {length} bytes, fewer than the header's own 12"),
            ));
        }
    }
    Ok(())
}

/// The `gltf` crate's validation, preceded by the one check its validation needs but does
/// not make: its POSITION hook indexes the accessor list with the unchecked index.
fn validate(path: &Path, document: &Document) -> Result<(), SceneError> {
    let root = document.as_json();
    for (mesh_index, mesh) in root.meshes.iter().enumerate() {
        for (primitive_index, primitive) in mesh.primitives.iter().enumerate() {
            for accessor in primitive.attributes.values() {
                if accessor.value() >= root.accessors.len() {
                    return Err(malformed(
                        path,
                        format!(
                            "mesh {mesh_index} primitive {primitive_index} refers to accessor \
                             {}, which does not exist",
                            accessor.value()
                        ),
                    ));
                }
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        errors.push((path(), error))
    });
    if errors.is_empty() {
        Ok(())
    } else {
        Err(SceneError::Gltf {
            path: path.to_owned(),
            error: gltf::Error::Validation(errors),
        })
    }
}

/// Every node of the default scene (else the first scene, else all root nodes) with its
/// world matrix (parent * local), in depth-first pre-order, children in file order.
fn flatten_hierarchy<'a>(
    path: &Path,
    document: &'a Document,
) -> Result<Vec<(Node<'a>, Mat4)>, SceneError> {
    let roots: Vec<Node<'a>> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: HashSet<usize> = document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()))
                .collect();
            document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    // An explicit stack, and each node visited once: a cyclic "hierarchy" in a broken file
    // must not recurse forever.
    let mut visited = vec![false; document.as_json().nodes.len()];
    let mut stack: Vec<(Node<'a>, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|node| (node, Mat4::IDENTITY))
        .collect();
    let mut flattened = Vec::new();
    while let Some((node, parent_to_world)) = stack.pop() {
        match visited.get_mut(node.index()) {
            Some(seen) if !*seen => *seen = true,
            _ => {
                return Err(malformed(
                    path,
                    format!(
                        "node '{}' is reached twice; nodes must form a tree",
                        label(node.name(), node.index())
                    ),
                ));
            }
        }
        let local_to_parent = Mat4::from_cols_array_2d(&node.transform().matrix());
        let local_to_world = parent_to_world * local_to_parent;
        let children: Vec<Node<'a>> = node.children().collect();
        stack.extend(
            children
                .into_iter()
                .rev()
                .map(|child| (child, local_to_world)),
        );
        flattened.push((node, local_to_world));
    }
    Ok(flattened)
}

/// The state of one load.
struct Loader<'a> {
    document: &'a Document,
    buffers: &'a [gltf::buffer::Data],
    builder: SceneBuilder,
    /// Materials whose textures we already warned about.
    warned_materials: HashSet<usize>,
    /// The first orthographic camera met, reported if no perspective camera follows.
    orthographic_camera: Option<String>,
}

impl Loader<'_> {
    /// Adds a node's mesh and, if it is the first perspective one, its camera.
    fn visit(&mut self, node: &Node, local_to_world: Mat4) -> Result<(), SceneError> {
        if let Some(mesh) = node.mesh() {
            self.add_mesh(&mesh, local_to_world)?;
        }
        if let Some(camera) = node.camera() {
            if !self.builder.has_camera() {
                self.add_camera(&camera, local_to_world)?;
            }
        }
        Ok(())
    }

    /// Adds every primitive of a mesh, transformed to world space.
    fn add_mesh(&mut self, mesh: &gltf::Mesh, local_to_world: Mat4) -> Result<(), SceneError> {
        let name = label(mesh.name(), mesh.index());
        // A mirroring transform turns counter-clockwise into clockwise; swapping two
        // vertices keeps the normal on the side that was the front in object space.
        let mirrors = local_to_world.determinant() < 0.0;
        for (primitive_index, primitive) in mesh.primitives().enumerate() {
            let mode = primitive.mode();
            if !matches!(
                mode,
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
            ) {
                return Err(SceneError::UnsupportedPrimitive {
                    path: self.builder.path().to_owned(),
                    mesh: name,
                    primitive: primitive_index,
                    mode: format!("{mode:?}"),
                });
            }
            let context = format!("mesh '{name}' primitive {primitive_index}");
            let (positions, indices) = self.read_geometry(&primitive, &context)?;
            let material = self.material(&primitive.material());
            for corners in triangle_corners(mode, indices.len()) {
                let mut world = corners.map(|corner| {
                    // In range: read_geometry checked every index against the vertex count.
                    local_to_world.transform_point3(positions[indices[corner] as usize])
                });
                if mirrors {
                    world.swap(1, 2);
                }
                self.builder.push(&name, world, &material)?;
            }
        }
        Ok(())
    }

    /// The primitive's object-space positions, and its vertex indices (0, 1, 2, ... when it
    /// has none), every index checked to be in range.
    fn read_geometry(
        &self,
        primitive: &gltf::Primitive,
        context: &str,
    ) -> Result<(Vec<Vec3>, Vec<u32>), SceneError> {
        let path = self.builder.path();
        let position_accessor = primitive
            .get(&gltf::Semantic::Positions)
            .ok_or_else(|| malformed(path, format!("{context} has no POSITION attribute")))?;
        check_accessor(&position_accessor, Dimensions::Vec3, &[DataType::F32])
            .map_err(|reason| malformed(path, format!("{context}: POSITION {reason}")))?;
        let reader = primitive.reader(|buffer| self.buffers.get(buffer.index()).map(|d| &d[..]));
        let outside = |what: &str| {
            malformed(
                path,
                format!("{context}: {what} data lies outside its buffer"),
            )
        };
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| outside("POSITION"))?
            .map(Vec3::from)
            .collect();

        let indices: Vec<u32> = match primitive.indices() {
            Some(accessor) => {
                let types = [DataType::U8, DataType::U16, DataType::U32];
                check_accessor(&accessor, Dimensions::Scalar, &types)
                    .map_err(|reason| malformed(path, format!("{context}: indices {reason}")))?;
                reader
                    .read_indices()
                    .ok_or_else(|| outside("index"))?
                    .into_u32()
                    .collect()
            }
            None => (0..positions.len() as u32).collect(),
        };
        if let Some(&index) = indices
            .iter()
            .find(|&&index| index as usize >= positions.len())
        {
            return Err(malformed(
                path,
                format!(
                    "{context}: index {index} is out of range ({} vertices)",
                    positions.len()
                ),
            ));
        }
        Ok((positions, indices))
    }

    /// The workshop's material from a glTF material's constant factors; warns (once per
    /// material) when it has textures, which we ignore.
    fn material(&mut self, material: &gltf::Material) -> Material {
        let pbr = material.pbr_metallic_roughness();
        let textures = [
            ("baseColor", pbr.base_color_texture().is_some()),
            (
                "metallicRoughness",
                pbr.metallic_roughness_texture().is_some(),
            ),
            ("normal", material.normal_texture().is_some()),
            ("occlusion", material.occlusion_texture().is_some()),
            ("emissive", material.emissive_texture().is_some()),
        ];
        let used: Vec<&str> = textures
            .iter()
            .filter(|(_, has)| *has)
            .map(|(n, _)| *n)
            .collect();
        // The default material (index None) has no textures.
        if let (false, Some(index)) = (used.is_empty(), material.index()) {
            if self.warned_materials.insert(index) {
                self.builder.warn(format!(
                    "material '{}' has textures ({}), which are ignored; using its constant \
                     factors",
                    label(material.name(), index),
                    used.join(", ")
                ));
            }
        }
        let [red, green, blue, _alpha] = pbr.base_color_factor();
        // KHR_materials_emissive_strength scales emissiveFactor beyond glTF's [0, 1].
        let strength = material.emissive_strength().unwrap_or(1.0);
        let emission = strength * Vec3::from(material.emissive_factor());
        Material::sanitized(
            Vec3::new(red, green, blue),
            emission,
            material.double_sided(),
        )
    }

    /// Sets the scene camera from a perspective camera on a node: glTF cameras look along
    /// their node's -Z with +Y up.
    fn add_camera(
        &mut self,
        camera: &gltf::Camera,
        local_to_world: Mat4,
    ) -> Result<(), SceneError> {
        let path = self.builder.path();
        let name = label(camera.name(), camera.index());
        let invalid = |reason: &str| SceneError::InvalidCamera {
            path: path.to_owned(),
            camera: name.clone(),
            reason: reason.to_owned(),
        };
        // Read the JSON ourselves: `Camera::projection` unwraps the parameters that the
        // type names, and validation does not check that they are there.
        let json = self.document.as_json().cameras.get(camera.index());
        let yfov = match json.map(|json| (&json.type_, &json.perspective)) {
            Some((Checked::Valid(CameraType::Perspective), Some(perspective))) => perspective.yfov,
            Some((Checked::Valid(CameraType::Orthographic), _)) => {
                self.orthographic_camera.get_or_insert(name);
                return Ok(());
            }
            _ => return Err(invalid("its type and parameters do not match")),
        };
        if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
            return Err(invalid(&format!("yfov {yfov} is not in (0, pi)")));
        }
        let position = local_to_world.transform_point3(Vec3::ZERO);
        let forward = local_to_world.transform_vector3(Vec3::NEG_Z);
        let up = local_to_world.transform_vector3(Vec3::Y);
        let right = forward.normalize_or_zero().cross(up.normalize_or_zero());
        if !position.is_finite() || !forward.is_finite() || right.length() <= 1e-6 {
            return Err(invalid("its node's transform is degenerate"));
        }
        let camera = Camera::look_at(position, position + forward, up, yfov);
        self.builder.set_camera(camera);
        Ok(())
    }
}

/// Checks what the `gltf` crate's accessor reader assumes but does not check (it asserts or
/// overflows otherwise): the element type, a non-zero count, strides no smaller than an
/// element, and byte ranges that fit in a `usize`. Whether the range lies inside the buffer
/// the reader checks itself.
fn check_accessor(
    accessor: &gltf::Accessor,
    dimensions: Dimensions,
    data_types: &[DataType],
) -> Result<(), String> {
    let name = label(accessor.name(), accessor.index());
    let (found_dimensions, found_type) = (accessor.dimensions(), accessor.data_type());
    if found_dimensions != dimensions || !data_types.contains(&found_type) {
        return Err(format!(
            "accessor '{name}' holds {found_dimensions:?} of {found_type:?}, expected \
             {dimensions:?} of {data_types:?}"
        ));
    }
    let size = accessor.size();
    let fits = |view: gltf::buffer::View, offset: usize, count: usize, element_size: usize| {
        let stride = view.stride().unwrap_or(element_size);
        count >= 1
            && stride >= element_size
            && view.offset().checked_add(view.length()).is_some()
            && stride
                .checked_mul(count - 1)
                .and_then(|bytes| bytes.checked_add(element_size))
                .and_then(|bytes| bytes.checked_add(offset))
                .is_some()
    };
    let base_fits = match accessor.view() {
        Some(view) => fits(view, accessor.offset(), accessor.count(), size),
        None => accessor.count() >= 1,
    };
    let sparse_fits = accessor.sparse().is_none_or(|sparse| {
        let (indices, values) = (sparse.indices(), sparse.values());
        fits(
            indices.view(),
            indices.offset(),
            sparse.count(),
            indices.index_type().size(),
        ) && fits(values.view(), values.offset(), sparse.count(), size)
    });
    if base_fits && sparse_fits {
        Ok(())
    } else {
        Err(format!(
            "accessor '{name}' has an empty or impossible byte layout"
        ))
    }
}

/// For `vertex_count` vertices in a primitive of `mode`, the positions in its vertex (index)
/// list of each triangle's corners, counter-clockwise (glTF 2.0 spec, section 3.7.2.1).
fn triangle_corners(mode: Mode, vertex_count: usize) -> Vec<[usize; 3]> {
    let strip_or_fan_count = vertex_count.saturating_sub(2);
    match mode {
        Mode::Triangles => (0..vertex_count / 3)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect(),
        // Every other triangle of a strip is clockwise as listed; the spec swaps its last two.
        Mode::TriangleStrip => (0..strip_or_fan_count)
            .map(|i| [i, i + 1 + i % 2, i + 2 - i % 2])
            .collect(),
        Mode::TriangleFan => (0..strip_or_fan_count).map(|i| [i + 1, i + 2, 0]).collect(),
        _ => Vec::new(),
    }
}

/// An object's name, or `#index` when it has none (names are optional in glTF).
fn label(name: Option<&str>, index: usize) -> String {
    name.map_or_else(|| format!("#{index}"), str::to_owned)
}

/// A [`SceneError::MalformedGltf`] for `path`.
fn malformed(path: &Path, reason: String) -> SceneError {
    SceneError::MalformedGltf {
        path: path.to_owned(),
        reason,
    }
}

#[cfg(test)]
#[path = "gltf_test_support.rs"]
mod test_support;

#[cfg(test)]
#[path = "gltf_loader_tests.rs"]
mod tests;
