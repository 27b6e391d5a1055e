//! glTF 2.0 scenes (`.gltf` with external or data-URI buffers, `.glb`) via the `gltf` crate:
//! the default scene's node hierarchy flattened to world-space triangles, the material's
//! constant factors as the workshop's diffuse material, and the first perspective camera.
//!
//! Malformed input must give an error, never a panic. The `gltf` crate indexes and slices
//! without checks in a few places that its validation does not cover, so we check those
//! things ourselves before asking it: the GLB header's length, POSITION accessor indices,
//! accessor types and extents, and camera types.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::camera::Type as CameraType;
use gltf::json::validation::Checked;
use gltf::mesh::Mode;
use gltf::{Document, Node};

use super::files::LoadOptions;
use super::gltf_animation::Pose;
use super::gltf_deform::{Deformer, NodeDeformation};
use super::gltf_extensions::unsupported_extension_warnings;
use super::gltf_file::GltfFile;
use super::gltf_instancing;
use super::gltf_materials::{material_label, ConvertedMaterials, MaterialReader};
use super::gltf_variants;
use super::instances::{InstanceRecorder, NodeLabel};
use super::material_params::first_slot_on_tex_coord_1;
use super::materials::{ExtraVertexAttributes, TriangleShading};
use super::skinning::skin_mirrors;
use super::tangents::generate_tangents;
use super::{Material, Scene, SceneBuilder, SceneError};
use crate::camera::Camera;
use crate::lights::{PunctualKind, PunctualLight};

pub use super::gltf_extensions::is_supported_extension;

/// Loads a glTF 2.0 file (JSON or binary), resolving external buffers relative to its
/// directory. Textures are ignored with a warning per material.
pub fn load_gltf(path: &Path) -> Result<Scene, SceneError> {
    load_gltf_with(path, &LoadOptions::default())
}

/// `load_gltf` with options: whether buffers outside the file's folder may be read, and
/// the time and animations of its pose. The file is opened and posed once
/// (`GltfFile::open`, `GltfFile::pose`), as a sequence of frames does for each.
pub fn load_gltf_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    GltfFile::open(path, options)?.pose(options.time, &options.animation)
}

/// The scene of a file read (`document`, `buffers`, read with `options`) in `pose`, its
/// materials converted by a reader that takes up from `converted`; with what that reader
/// converted by the end.
pub(super) fn posed_scene(
    path: &Path,
    document: &Document,
    buffers: &[gltf::buffer::Data],
    options: &LoadOptions,
    pose: Pose,
    converted: ConvertedMaterials,
) -> Result<(Scene, ConvertedMaterials), SceneError> {
    let variant = options
        .variant
        .as_deref()
        .map(|name| gltf_variants::variant_index(path, document, name))
        .transpose()?;
    let mut loader = Loader {
        document,
        buffers,
        variant,
        builder: SceneBuilder::new(path),
        materials: MaterialReader::new(path, document, buffers, options, converted),
        orthographic_camera: None,
        instances: InstanceRecorder::default(),
        deformer: Deformer::new(path, document, buffers, pose),
    };
    for warning in unsupported_extension_warnings(document.extensions_used()) {
        loader.builder.warn(warning);
    }
    let variants = gltf_variants::variant_names(document);
    if variant.is_none() && !variants.is_empty() {
        loader.builder.warn(format!(
            "the file has material variants ({}); the primitives' own materials render (--variant NAME, Python's variant=, picks one)",
            variants.join(", ")
        ));
    }
    let flattened = flatten_hierarchy(path, document, loader.deformer.local_transforms())?;
    let mut parents = vec![None; document.as_json().nodes.len()];
    for (node, _, parent) in &flattened {
        parents[node.index()] = *parent;
    }
    for (node, world, _) in flattened {
        loader.visit(&node, world, &parents)?;
    }
    let converted = loader.materials.converted;
    for warning in &converted.warnings {
        loader.builder.warn(warning.clone());
    }
    loader
        .builder
        .set_materials(converted.materials.clone(), converted.textures.clone());
    if let (false, Some(camera)) = (loader.builder.has_camera(), loader.orthographic_camera) {
        return Err(SceneError::OrthographicCamera {
            path: path.to_owned(),
            camera,
        });
    }
    Ok((loader.builder.finish()?, converted))
}

/// Every node of the default scene (else the first scene, else all root nodes) with its
/// world matrix (parent * local), in depth-first pre-order, children in file order. A node
/// in `animated` has that local matrix in place of the file's.
fn flatten_hierarchy<'a>(
    path: &Path,
    document: &'a Document,
    animated: &HashMap<usize, Mat4>,
) -> Result<Vec<(Node<'a>, Mat4, Option<usize>)>, SceneError> {
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
    // Each entry carries its parent's index (for `NodeLabel::path`).
    let mut stack: Vec<(Node<'a>, Mat4, Option<usize>)> = roots
        .into_iter()
        .rev()
        .map(|node| (node, Mat4::IDENTITY, None))
        .collect();
    let mut flattened = Vec::new();
    while let Some((node, parent_to_world, parent)) = stack.pop() {
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
        let local_to_parent = animated
            .get(&node.index())
            .copied()
            .unwrap_or_else(|| Mat4::from_cols_array_2d(&node.transform().matrix()));
        let local_to_world = parent_to_world * local_to_parent;
        let children: Vec<Node<'a>> = node.children().collect();
        stack.extend(
            children
                .into_iter()
                .rev()
                .map(|child| (child, local_to_world, Some(node.index()))),
        );
        flattened.push((node, local_to_world, parent));
    }
    Ok(flattened)
}

/// The state of one load.
struct Loader<'a> {
    document: &'a Document,
    buffers: &'a [gltf::buffer::Data],
    builder: SceneBuilder,
    /// The materials met so far, with their textures.
    materials: MaterialReader<'a>,
    /// The first orthographic camera met, reported if no perspective camera follows.
    orthographic_camera: Option<String>,
    /// Each node's copy of its mesh, for the device's acceleration structures.
    instances: InstanceRecorder,
    /// The pose: morph targets and skins.
    deformer: Deformer<'a>,
    /// The material variant rendered (`KHR_materials_variants`), by index; `None`: the
    /// primitives' own materials.
    variant: Option<usize>,
}

impl Loader<'_> {
    /// Adds a node's mesh and, if it is the first perspective one, its camera; `parents`
    /// holds each node's parent (for its path in the node tree, `NodeLabel::path`).
    fn visit(
        &mut self,
        node: &Node,
        local_to_world: Mat4,
        parents: &[Option<usize>],
    ) -> Result<(), SceneError> {
        if let Some(mesh) = node.mesh() {
            let deformation = self.deformer.node(node, &mesh)?;
            let node_label = NodeLabel {
                index: node.index(),
                name: label(node.name(), node.index()),
                path: node_path(self.document, parents, node.index()),
                mesh: mesh.index(),
            };
            let instances = gltf_instancing::instance_transforms(
                self.builder.path(),
                self.document,
                self.buffers,
                node,
            )?;
            match instances {
                None => self.add_mesh(&mesh, local_to_world, &deformation, node_label)?,
                // EXT_mesh_gpu_instancing: each instance in the node's space
                Some(transforms) => {
                    for transform in transforms {
                        let instance_to_world = local_to_world * transform;
                        self.add_mesh(&mesh, instance_to_world, &deformation, node_label.clone())?;
                    }
                }
            }
        }
        if let Some(camera) = node.camera() {
            if !self.builder.has_camera() {
                self.add_camera(&camera, local_to_world)?;
            } else {
                // Later cameras (for --camera N): an unusable one is a warning, not an error.
                let had = self.builder.camera_count();
                if let Err(error) = self.add_camera(&camera, local_to_world) {
                    self.builder.warn(format!("{error}; the camera is ignored"));
                }
                debug_assert!(self.builder.camera_count() >= had);
            }
        }
        self.add_punctual_light(node, local_to_world);
        Ok(())
    }

    /// Adds a node's KHR_lights_punctual light, read from the JSON (the `gltf` crate's
    /// accessors unwrap what validation does not check); unusable ones are warnings.
    fn add_punctual_light(&mut self, node: &Node, local_to_world: Mat4) {
        use gltf::json::extensions::scene::khr_lights_punctual::Type;
        let Some(reference) = node
            .extensions()
            .and_then(|_| self.document.as_json().nodes.get(node.index()))
            .and_then(|json| json.extensions.as_ref())
            .and_then(|extensions| extensions.khr_lights_punctual.as_ref())
        else {
            return;
        };
        let index = reference.light.value();
        let light = self
            .document
            .as_json()
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|l| l.lights.get(index));
        let node_name = label(node.name(), node.index());
        let Some(light) = light else {
            self.builder.warn(format!(
                "node '{node_name}' names light {index}, which does not exist; ignored"
            ));
            return;
        };
        let kind = match (&light.type_, &light.spot) {
            (Checked::Valid(Type::Point), _) => PunctualKind::Point,
            (Checked::Valid(Type::Directional), _) => PunctualKind::Directional,
            (Checked::Valid(Type::Spot), Some(spot)) => PunctualKind::Spot {
                inner_cone_angle: spot.inner_cone_angle,
                outer_cone_angle: spot.outer_cone_angle,
            },
            _ => {
                self.builder.warn(format!("light {index} of node '{node_name}' has an unknown type or a spot without its cone; ignored"));
                return;
            }
        };
        match PunctualLight::new(kind, Vec3::from(light.color), light.intensity, local_to_world) {
            Some(light) => self.builder.add_punctual_light(light),
            None => self.builder.warn(format!("light {index} of node '{node_name}' has a degenerate transform or intensity; ignored")),
        }
    }

    /// Adds every primitive of a mesh, posed (`deformation`) and transformed to world space,
    /// drawn by the node `node`.
    fn add_mesh(
        &mut self,
        mesh: &gltf::Mesh,
        local_to_world: Mat4,
        deformation: &NodeDeformation,
        node: NodeLabel,
    ) -> Result<(), SceneError> {
        let name = label(mesh.name(), mesh.index());
        // Skinning puts vertices in world space: the skinned node's transform is ignored.
        let local_to_world = match deformation.skin {
            Some(_) => Mat4::IDENTITY,
            None => local_to_world,
        };
        // A mirroring transform turns counter-clockwise into clockwise; swapping two
        // vertices keeps the normal on the side that was the front in object space.
        let mirrors = local_to_world.determinant() < 0.0;
        // The kept triangles in object space, vertex for vertex as in world space
        let first_triangle = self.builder.triangle_count();
        let mut kept_object_positions: Vec<[Vec3; 3]> = Vec::new();
        for (primitive_index, primitive) in mesh.primitives().enumerate() {
            let mode = primitive.mode();
            if !matches!(
                mode,
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
            ) {
                // Points and lines have no area to render: skipped, with a word.
                self.builder.warn(format!(
                    "mesh '{name}' primitive {primitive_index} is {mode:?}, skipped (only triangles are rendered)"
                ));
                continue;
            }
            let context = format!("mesh '{name}' primitive {primitive_index}");
            let (mut positions, indices) = self.read_geometry(&primitive, &context)?;
            let material = match gltf_variants::primitive_material(
                self.builder.path(),
                self.document,
                (&primitive, &context),
                self.variant,
            )? {
                Some(index) if Some(index) != primitive.material().index() => self
                    .document
                    .materials()
                    .nth(index)
                    .unwrap_or_else(|| primitive.material()),
                _ => primitive.material(),
            };
            let material_index = self.materials.material_index(&material);
            let pbr = self.materials.converted.materials[material_index as usize];
            // What reads TEXCOORD_1, for the error where the primitive lacks it
            let tex_coord_1_reading = first_slot_on_tex_coord_1(&pbr).map(|slot| {
                format!(
                    "{context}: material '{}' reads its {slot} from TEXCOORD_1",
                    material_label(&material)
                )
            });
            let material =
                Material::sanitized(pbr.base_color.truncate(), pbr.emission, pbr.double_sided);
            let mut attributes = self.read_attributes(&primitive, &context, positions.len())?;
            // TEXCOORD_1 only where the material reads it (others keep no table for it)
            if let Some(reading) = &tex_coord_1_reading {
                attributes.tex_coords_1 =
                    Some(self.read_tex_coords_1(&primitive, reading, positions.len())?);
            }
            let posed = self.deformer.primitive(
                &primitive,
                &context,
                deformation,
                &mut positions,
                attributes.normals.as_mut(),
                attributes.tangents.as_mut(),
            )?;
            if posed.renormalised > 0 {
                let count = posed.renormalised;
                self.builder.warn(format!(
                    "{context}: the joint weights of {count} vertices do not sum to 1; normalised"
                ));
            }
            let corners = triangle_corners(mode, indices.len());
            // Every per-corner attribute, gathered per triangle (indices checked in range).
            let gather = |values: &[Vec3]| -> Vec<[Vec3; 3]> {
                corners
                    .iter()
                    .map(|c| c.map(|corner| values[indices[corner] as usize]))
                    .collect()
            };
            let object_positions = gather(&positions);
            // A skin that mirrors a triangle turns its front to the clockwise side, as a
            // mirroring node transform does (its positions are already posed, in world space).
            let skin_mirrors: Vec<bool> = match &posed.skin_maps {
                Some(maps) => corners
                    .iter()
                    .map(|c| skin_mirrors(c.map(|corner| maps[indices[corner] as usize])))
                    .collect(),
                None => vec![false; corners.len()],
            };
            // Without NORMAL, the face's: on the counter-clockwise side of the (unposed)
            // triangle, i.e. the posed one's other side where the skin mirrors it.
            let face_normals: Vec<Vec3> = object_positions
                .iter()
                .zip(&skin_mirrors)
                .map(|([a, b, c], &mirrored)| {
                    let normal = (*b - *a).cross(*c - *a).normalize_or_zero();
                    if mirrored {
                        -normal
                    } else {
                        normal
                    }
                })
                .collect();
            let normals: Vec<[Vec3; 3]> = match &attributes.normals {
                Some(normals) => gather(normals),
                None => face_normals.iter().map(|&n| [n; 3]).collect(),
            };
            let tex_coords: Vec<[Vec2; 3]> = match &attributes.tex_coords {
                Some(uv) => corners
                    .iter()
                    .map(|c| c.map(|corner| uv[indices[corner] as usize]))
                    .collect(),
                None => vec![[Vec2::ZERO; 3]; corners.len()],
            };
            let colors: Option<Vec<[Vec4; 3]>> = attributes.colors.as_ref().map(|colors| {
                corners
                    .iter()
                    .map(|c| c.map(|corner| colors[indices[corner] as usize]))
                    .collect()
            });
            let tex_coords_1: Option<Vec<[Vec2; 3]>> = attributes.tex_coords_1.as_ref().map(|uv| {
                corners
                    .iter()
                    .map(|c| c.map(|corner| uv[indices[corner] as usize]))
                    .collect()
            });
            let tangents: Vec<[Vec4; 3]> = match (&attributes.tangents, pbr.normal_texture) {
                (_, None) => vec![[Vec4::ZERO; 3]; corners.len()],
                (Some(tangents), Some(_)) => corners
                    .iter()
                    .map(|c| c.map(|corner| tangents[indices[corner] as usize]))
                    .collect(),
                // MikkTSpace over the set the normal texture reads
                (None, Some(normal_texture)) => {
                    let uv = match (normal_texture.tex_coord, &tex_coords_1) {
                        (1, Some(uv_1)) => uv_1,
                        _ => &tex_coords,
                    };
                    generate_tangents(&object_positions, &normals, uv)
                        .unwrap_or_else(|| vec![[Vec4::ZERO; 3]; corners.len()])
                }
            };
            // Normals transform with the inverse transpose; tangents as vectors, and a
            // mirroring transform flips the bitangent's handedness.
            let normal_matrix = Mat3::from_mat4(local_to_world).inverse().transpose();
            let vector_matrix = Mat3::from_mat4(local_to_world);
            let handedness = if mirrors { -1.0 } else { 1.0 };
            for (t, corner_positions) in object_positions.iter().enumerate() {
                let mut object = *corner_positions;
                let mut world = corner_positions.map(|p| local_to_world.transform_point3(p));
                let mut shading = TriangleShading {
                    material: material_index,
                    normals: normals[t].map(|n| (normal_matrix * n).normalize_or_zero()),
                    tex_coords: tex_coords[t],
                    tangents: tangents[t].map(|tangent| {
                        (vector_matrix * tangent.truncate())
                            .normalize_or_zero()
                            .extend(if tangent.w < 0.0 {
                                -handedness
                            } else {
                                handedness
                            })
                    }),
                };
                let mut extra = ExtraVertexAttributes {
                    colors: colors.as_ref().map_or([Vec4::ONE; 3], |colors| colors[t]),
                    tex_coords_1: tex_coords_1.as_ref().map_or([Vec2::ZERO; 3], |uv| uv[t]),
                };
                if mirrors != skin_mirrors[t] {
                    object.swap(1, 2);
                    world.swap(1, 2);
                    shading.normals.swap(1, 2);
                    shading.tex_coords.swap(1, 2);
                    extra.swap(1, 2);
                    shading.tangents.swap(1, 2);
                }
                let kept = self.builder.triangle_count();
                self.builder
                    .push_shaded_extra(&name, world, &material, shading, &extra)?;
                if self.builder.triangle_count() > kept {
                    kept_object_positions.push(object);
                }
            }
        }
        if let Some(mut instance) = self.instances.instance(
            mesh.index(),
            first_triangle,
            local_to_world,
            kept_object_positions,
        ) {
            instance.node = Some(std::sync::Arc::new(node));
            self.builder.add_mesh_instance(instance);
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

    /// The primitive's NORMAL, TEXCOORD_0 and TANGENT, where present and usable: an
    /// attribute with another element count than POSITION is ignored with a warning.
    fn read_attributes(
        &mut self,
        primitive: &gltf::Primitive,
        context: &str,
        vertex_count: usize,
    ) -> Result<VertexAttributes, SceneError> {
        let reader = primitive.reader(|buffer| self.buffers.get(buffer.index()).map(|d| &d[..]));
        let mut attributes = VertexAttributes::default();
        let usable = |semantic: gltf::Semantic,
                      dimensions,
                      types: &[DataType],
                      builder: &mut SceneBuilder| {
            let accessor = primitive.get(&semantic)?;
            let name = format!("{semantic:?}");
            match check_accessor(&accessor, dimensions, types) {
                Err(reason) => builder.warn(format!("{context}: {name} ignored: {reason}")),
                Ok(()) if accessor.count() != vertex_count => builder.warn(format!(
                    "{context}: {name} ignored: {} elements for {vertex_count} vertices",
                    accessor.count()
                )),
                Ok(()) => return Some(()),
            }
            None
        };
        if usable(
            gltf::Semantic::Normals,
            Dimensions::Vec3,
            &[DataType::F32],
            &mut self.builder,
        )
        .is_some()
        {
            attributes.normals = reader.read_normals().map(|n| n.map(Vec3::from).collect());
        }
        let uv_types = [DataType::F32, DataType::U8, DataType::U16];
        if usable(
            gltf::Semantic::TexCoords(0),
            Dimensions::Vec2,
            &uv_types,
            &mut self.builder,
        )
        .is_some()
        {
            attributes.tex_coords = reader
                .read_tex_coords(0)
                .map(|uv| uv.into_f32().map(Vec2::from).collect());
        }
        if usable(
            gltf::Semantic::Tangents,
            Dimensions::Vec4,
            &[DataType::F32],
            &mut self.builder,
        )
        .is_some()
        {
            attributes.tangents = reader.read_tangents().map(|t| t.map(Vec4::from).collect());
        }
        attributes.colors = self.read_colors(primitive, context, vertex_count)?;
        Ok(attributes)
    }

    /// The primitive's `TEXCOORD_1`, which its material reads (`reading` says where, for
    /// the error): a primitive without it, or with one of a type glTF does not allow (VEC2
    /// of float, normalized unsigned byte or short) or another count than its vertices', is
    /// an error naming the mesh, primitive, material and slot.
    fn read_tex_coords_1(
        &self,
        primitive: &gltf::Primitive,
        reading: &str,
        vertex_count: usize,
    ) -> Result<Vec<Vec2>, SceneError> {
        let path = self.builder.path();
        let wrong = |reason: String| malformed(path, format!("{reading}, {reason}"));
        let Some(accessor) = primitive.get(&gltf::Semantic::TexCoords(1)) else {
            return Err(wrong("which the primitive does not have".to_owned()));
        };
        let types = [DataType::F32, DataType::U8, DataType::U16];
        check_accessor(&accessor, Dimensions::Vec2, &types)
            .map_err(|reason| wrong(format!("whose {reason}")))?;
        if accessor.data_type() != DataType::F32 && !accessor.normalized() {
            return Err(wrong(format!(
                "whose accessor '{}' is not normalized (glTF allows float, normalized unsigned byte or short)",
                label(accessor.name(), accessor.index())
            )));
        }
        if accessor.count() != vertex_count {
            return Err(wrong(format!(
                "which has {} elements for {vertex_count} vertices",
                accessor.count()
            )));
        }
        let reader = primitive.reader(|buffer| self.buffers.get(buffer.index()).map(|d| &d[..]));
        Ok(reader
            .read_tex_coords(1)
            .ok_or_else(|| wrong("whose data lies outside its buffer".to_owned()))?
            .into_f32()
            .map(Vec2::from)
            .collect())
    }

    /// The primitive's `COLOR_0` as linear RGBA (alpha 1 for VEC3), or `None` without one.
    /// glTF 2.0 (3.7.2.1) allows VEC3 or VEC4 of float, or of normalized unsigned bytes or
    /// shorts, one per vertex; anything else is an error naming the primitive (the crate's
    /// reader would panic on another type).
    fn read_colors(
        &self,
        primitive: &gltf::Primitive,
        context: &str,
        vertex_count: usize,
    ) -> Result<Option<Vec<Vec4>>, SceneError> {
        let Some(accessor) = primitive.get(&gltf::Semantic::Colors(0)) else {
            return Ok(None);
        };
        let path = self.builder.path();
        let types = [DataType::F32, DataType::U8, DataType::U16];
        let wrong = |reason: String| malformed(path, format!("{context}: COLOR_0 {reason}"));
        let dimensions = accessor.dimensions();
        let allowed = matches!(dimensions, Dimensions::Vec3 | Dimensions::Vec4)
            && types.contains(&accessor.data_type())
            && (accessor.data_type() == DataType::F32 || accessor.normalized());
        if !allowed {
            return Err(wrong(format!(
                "accessor '{}' holds {dimensions:?} of {:?}{}, but glTF allows VEC3 or VEC4 of float, normalized unsigned byte or normalized unsigned short",
                label(accessor.name(), accessor.index()),
                accessor.data_type(),
                if accessor.normalized() { " (normalized)" } else { "" },
            )));
        }
        check_accessor(&accessor, dimensions, &types)
            .map_err(|reason| wrong(reason.to_string()))?;
        if accessor.count() != vertex_count {
            return Err(wrong(format!(
                "has {} elements for {vertex_count} vertices",
                accessor.count()
            )));
        }
        let reader = primitive.reader(|buffer| self.buffers.get(buffer.index()).map(|d| &d[..]));
        let colors = reader
            .read_colors(0)
            .ok_or_else(|| wrong("data lies outside its buffer".to_owned()))?
            .into_rgba_f32()
            .map(Vec4::from)
            .collect();
        Ok(Some(colors))
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
        // A target at a distance like the camera's own from the origin, so that it does not
        // round back onto the position of a camera far from the origin.
        let reach = position.length().max(1.0);
        let camera = Camera::look_at(position, position + forward.normalize() * reach, up, yfov);
        let finite = [
            camera.position,
            camera.image_plane_middle,
            camera.up,
            camera.right_per_unit_aspect,
        ]
        .iter()
        .all(|v| v.is_finite());
        if !finite {
            return Err(invalid("its node's transform is degenerate"));
        }
        self.builder.set_camera(camera);
        Ok(())
    }
}

/// A primitive's optional vertex attributes, one element per vertex.
#[derive(Default)]
struct VertexAttributes {
    normals: Option<Vec<Vec3>>,
    tex_coords: Option<Vec<Vec2>>,
    tangents: Option<Vec<Vec4>>,
    /// `COLOR_0`, linear RGBA.
    colors: Option<Vec<Vec4>>,
    /// `TEXCOORD_1`, read only where the material samples a texture on it.
    tex_coords_1: Option<Vec<Vec2>>,
}

/// An accessor that the `gltf` crate's reader cannot be trusted with: the reason, naming
/// the accessor, for a message about the mesh, skin or animation that reads it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum AccessorError {
    /// Elements of another type than the reader expects.
    #[error("accessor '{name}' holds {found_dimensions:?} of {found_type:?}, expected {dimensions:?} of {data_types:?}")]
    WrongType {
        /// The accessor's name, or `#index`.
        name: String,
        /// Its element's shape.
        found_dimensions: Dimensions,
        /// Its component type.
        found_type: DataType,
        /// The shape expected.
        dimensions: Dimensions,
        /// The component types accepted.
        data_types: Vec<DataType>,
    },
    /// No elements, strides smaller than an element, or byte ranges beyond a `usize`.
    #[error("accessor '{name}' has an empty or impossible byte layout")]
    ImpossibleLayout {
        /// The accessor's name, or `#index`.
        name: String,
    },
}

/// Checks what the `gltf` crate's accessor reader assumes but does not check (it asserts or
/// overflows otherwise): the element type, a non-zero count, strides no smaller than an
/// element, and byte ranges that fit in a `usize`. Whether the range lies inside the buffer
/// the reader checks itself.
pub(super) fn check_accessor(
    accessor: &gltf::Accessor,
    dimensions: Dimensions,
    data_types: &[DataType],
) -> Result<(), AccessorError> {
    let name = label(accessor.name(), accessor.index());
    let (found_dimensions, found_type) = (accessor.dimensions(), accessor.data_type());
    if found_dimensions != dimensions || !data_types.contains(&found_type) {
        return Err(AccessorError::WrongType {
            name,
            found_dimensions,
            found_type,
            dimensions,
            data_types: data_types.to_vec(),
        });
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
        Err(AccessorError::ImpossibleLayout { name })
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

/// Most ancestors a node's path (`NodeLabel::path`) names: a deeper node's path starts with
/// `/...`, so that a chain of 10^5 nodes does not take 10^10 bytes of paths.
const MAX_PATH_DEPTH: usize = 32;

/// The path of node `index` in the node tree: `/` and the labels of its ancestors and its
/// own, `/` between (`parents`: each node's parent).
fn node_path(document: &Document, parents: &[Option<usize>], index: usize) -> String {
    let nodes = &document.as_json().nodes;
    let mut chain = vec![index];
    while let Some(Some(parent)) = parents.get(*chain.last().unwrap_or(&index)) {
        if chain.len() > MAX_PATH_DEPTH {
            break;
        }
        chain.push(*parent);
    }
    let cut = chain.len() > MAX_PATH_DEPTH;
    chain.truncate(MAX_PATH_DEPTH);
    let mut path = if cut {
        "/...".to_owned()
    } else {
        String::new()
    };
    for &node in chain.iter().rev() {
        let name = nodes.get(node).and_then(|n| n.name.as_deref());
        path.push('/');
        path.push_str(&label(name, node));
    }
    path
}

/// An object's name (printable), or `#index` when it has none (names are optional in glTF).
pub(super) fn label(name: Option<&str>, index: usize) -> String {
    name.map_or_else(|| format!("#{index}"), super::printable)
}

/// A [`SceneError::MalformedGltf`] for `path`.
pub(super) fn malformed(path: &Path, reason: String) -> SceneError {
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

#[cfg(test)]
#[path = "gltf_mirror_tests.rs"]
mod mirror_tests;

#[cfg(test)]
#[path = "gltf_vertex_attribute_tests.rs"]
mod vertex_attribute_tests;

#[cfg(test)]
#[path = "gltf_texture_tests.rs"]
mod texture_tests;

#[cfg(test)]
#[path = "gltf_instancing_tests.rs"]
mod instancing_tests;
