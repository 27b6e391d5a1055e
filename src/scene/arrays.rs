//! Scenes from arrays (Python's `Scene.from_arrays`, Mitsuba's `load_dict`): vertex
//! positions, triangles as vertex indices, materials as glTF factors (`MaterialFactors`),
//! optional vertex normals and texture coordinates, punctual lights and a camera.
//!
//! The triangles become what the glTF loader makes of one mesh drawn by one node without a
//! transform, step for step (the same face normals, the same normalisations, the same
//! materials through `MaterialFactors::material`), so that the same arrays written as a glTF
//! file render bit for bit the same.

use std::path::Path;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use super::instances::InstanceRecorder;
use super::material_factors::MaterialFactors;
use super::materials::TriangleShading;
use super::{Material, Scene, SceneBuilder, SceneError};
use crate::camera::Camera;
use crate::lights::PunctualLight;

/// What reports and errors call a scene made from arrays.
pub const ARRAYS_DESCRIPTION: &str = "arrays";

/// A scene's data as arrays. Every index must be in range; `normals` and `tex_coords`, when
/// given, have one element per position, `material_indices` one per triangle.
#[derive(Clone, Debug, Default)]
pub struct SceneArrays<'a> {
    /// Vertex positions, world space.
    pub positions: &'a [Vec3],
    /// Each triangle's three vertex indices, counter-clockwise seen from its front.
    pub triangles: &'a [[u32; 3]],
    /// The materials; empty: glTF's default material for every triangle.
    pub materials: &'a [MaterialFactors],
    /// Each triangle's index into `materials`; `None`: every triangle takes material 0.
    pub material_indices: Option<&'a [u32]>,
    /// Vertex normals, world space (need not be unit length); `None`: the face normals.
    pub normals: Option<&'a [Vec3]>,
    /// Vertex texture coordinates; `None`: 0.
    pub tex_coords: Option<&'a [Vec2]>,
    /// Punctual lights, world space.
    pub punctual_lights: Vec<PunctualLight>,
    /// The scene's camera; `None`: renders frame the scene.
    pub camera: Option<Camera>,
}

/// An error about the arrays themselves (a scene built from them names no file).
fn invalid(reason: String) -> SceneError {
    SceneError::Arrays(reason)
}

impl SceneArrays<'_> {
    /// Checks the lengths and every index, saying which array is wrong.
    fn check(&self) -> Result<(), SceneError> {
        let vertex_count = self.positions.len();
        for (name, length) in [
            ("normals", self.normals.map(<[Vec3]>::len)),
            ("uvs", self.tex_coords.map(<[Vec2]>::len)),
        ] {
            if let Some(length) = length.filter(|&l| l != vertex_count) {
                return Err(invalid(format!(
                    "{name} has {length} rows for {vertex_count} positions"
                )));
            }
        }
        if let Some((t, &index)) = self.triangles.iter().enumerate().find_map(|(t, corners)| {
            corners
                .iter()
                .find(|&&i| i as usize >= vertex_count)
                .map(|i| (t, i))
        }) {
            return Err(invalid(format!(
                "indices: triangle {t} refers to vertex {index}, but there are {vertex_count} positions"
            )));
        }
        let material_count = self.materials.len().max(1);
        if let Some(indices) = self.material_indices {
            if indices.len() != self.triangles.len() {
                return Err(invalid(format!(
                    "material_indices has {} entries for {} triangles",
                    indices.len(),
                    self.triangles.len()
                )));
            }
            if let Some((t, &index)) = indices
                .iter()
                .enumerate()
                .find(|(_, &i)| i as usize >= material_count)
            {
                return Err(invalid(format!(
                    "material_indices: triangle {t} takes material {index}, but there are {} materials",
                    self.materials.len()
                )));
            }
        }
        Ok(())
    }
}

impl Scene {
    /// The scene the arrays describe (see `SceneArrays`): as the glTF loader loads the same
    /// data written as one mesh (one primitive per material, in material order) on one node
    /// without a transform. Degenerate triangles are dropped with a warning, as loaders do.
    pub fn from_arrays(arrays: &SceneArrays) -> Result<Scene, SceneError> {
        arrays.check()?;
        let default = [MaterialFactors::default()];
        let factors = if arrays.materials.is_empty() {
            &default[..]
        } else {
            arrays.materials
        };
        let materials: Vec<_> = factors.iter().map(|f| f.material().sanitized()).collect();
        let mut builder = SceneBuilder::new(Path::new(ARRAYS_DESCRIPTION));
        // The glTF loader's steps for a node without a transform (identity matrices
        // included: they turn -0 into +0, which the same bits need).
        let local_to_world = Mat4::IDENTITY;
        let normal_matrix = Mat3::from_mat4(local_to_world).inverse().transpose();
        let mut kept_object_positions = Vec::new();
        for (t, corners) in arrays.triangles.iter().enumerate() {
            let material_index = arrays.material_indices.map_or(0, |m| m[t]);
            let pbr = materials[material_index as usize];
            let material =
                Material::sanitized(pbr.base_color.truncate(), pbr.emission, pbr.double_sided);
            let object = corners.map(|i| arrays.positions[i as usize]);
            let normals = match arrays.normals {
                Some(normals) => corners.map(|i| normals[i as usize]),
                None => {
                    let [a, b, c] = object;
                    [(b - a).cross(c - a).normalize_or_zero(); 3]
                }
            };
            let shading = TriangleShading {
                material: material_index,
                normals: normals.map(|n| (normal_matrix * n).normalize_or_zero()),
                tex_coords: arrays
                    .tex_coords
                    .map_or([Vec2::ZERO; 3], |uv| corners.map(|i| uv[i as usize])),
                tangents: [Vec4::ZERO; 3],
            };
            let world = object.map(|p| local_to_world.transform_point3(p));
            let kept = builder.triangle_count();
            builder.push_shaded("arrays", world, &material, shading)?;
            if builder.triangle_count() > kept {
                kept_object_positions.push(object);
            }
        }
        if let Some(instance) =
            InstanceRecorder::default().instance(0, 0, local_to_world, kept_object_positions)
        {
            builder.add_mesh_instance(instance);
        }
        builder.set_materials(materials, Vec::new());
        if let Some(camera) = arrays.camera {
            builder.set_camera(camera);
        }
        for light in &arrays.punctual_lights {
            builder.add_punctual_light(*light);
        }
        builder.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const QUAD: [Vec3; 4] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];

    #[test]
    fn triangles_take_their_materials_and_face_normals() {
        let red = MaterialFactors {
            base_color: Vec4::new(1.0, 0.0, 0.0, 1.0),
            metallic: 0.0,
            ..MaterialFactors::default()
        };
        let scene = Scene::from_arrays(&SceneArrays {
            positions: &QUAD,
            triangles: &[[0, 1, 2], [0, 2, 3]],
            materials: &[MaterialFactors::default(), red],
            material_indices: Some(&[1, 0]),
            ..SceneArrays::default()
        })
        .unwrap();
        assert_eq!(scene.triangles.len(), 2);
        assert_eq!(scene.triangles[0].color, Vec3::X);
        assert_eq!(scene.triangles[0].normal, Vec3::Z);
        let materials = scene.materials.unwrap();
        assert_eq!(
            materials.materials,
            vec![
                MaterialFactors::default().material().sanitized(),
                red.material().sanitized()
            ]
        );
        assert_eq!(materials.triangles[0].material, 1);
        assert_eq!(materials.triangles[1].normals, [Vec3::Z; 3]);
        assert_eq!(scene.mesh_instances.len(), 1);
    }

    #[test]
    fn bad_indices_and_lengths_are_named() {
        let cases: [(SceneArrays, &str); 4] = [
            (
                SceneArrays {
                    positions: &QUAD,
                    triangles: &[[0, 1, 4]],
                    ..SceneArrays::default()
                },
                "indices: triangle 0 refers to vertex 4, but there are 4 positions",
            ),
            (
                SceneArrays {
                    positions: &QUAD,
                    triangles: &[[0, 1, 2]],
                    material_indices: Some(&[1]),
                    ..SceneArrays::default()
                },
                "material_indices: triangle 0 takes material 1, but there are 0 materials",
            ),
            (
                SceneArrays {
                    positions: &QUAD,
                    triangles: &[[0, 1, 2]],
                    material_indices: Some(&[0, 0]),
                    ..SceneArrays::default()
                },
                "material_indices has 2 entries for 1 triangles",
            ),
            (
                SceneArrays {
                    positions: &QUAD,
                    triangles: &[[0, 1, 2]],
                    normals: Some(&[Vec3::Z]),
                    ..SceneArrays::default()
                },
                "normals has 1 rows for 4 positions",
            ),
        ];
        for (arrays, expected) in cases {
            let error = Scene::from_arrays(&arrays).unwrap_err().to_string();
            assert_eq!(error, format!("scene from arrays: {expected}"));
        }
    }

    #[test]
    fn no_triangles_is_an_error_and_degenerate_ones_are_dropped() {
        let error = Scene::from_arrays(&SceneArrays {
            positions: &QUAD,
            ..SceneArrays::default()
        })
        .unwrap_err();
        assert_eq!(error.to_string(), "scene 'arrays' contains no triangles");
        let scene = Scene::from_arrays(&SceneArrays {
            positions: &QUAD,
            triangles: &[[0, 1, 2], [0, 0, 1]],
            ..SceneArrays::default()
        })
        .unwrap();
        assert_eq!(scene.triangles.len(), 1);
        assert_eq!(scene.warnings, vec!["dropped 1 degenerate triangles"]);
    }
}
