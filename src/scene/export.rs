//! Writes a scene for another renderer: one binary PLY mesh per material (albedo, emission,
//! double-sidedness and, for glTF scenes, the metallic-roughness material) and a JSON
//! manifest with the materials, the punctual lights and the camera. Used by
//! `benches/mitsuba_compare.py --generated N` to give Mitsuba 3 exactly the triangles vkpath
//! renders; `vkpath export` is the command line.
//!
//! The manifest, `scene.json`:
//!
//! ```json
//! { "camera": { "position": [x, y, z], "target": [x, y, z], "up": [x, y, z],
//!               "fov_y_degrees": 38.6 },
//!   "meshes": [ { "file": "mesh_0.ply", "triangles": 10, "color": [r, g, b],
//!                 "emission": [r, g, b], "double_sided": false,
//!                 "material": { "base_color": [r, g, b, a], "metallic": 1, "roughness": 0.3,
//!                               "specular": 1, "specular_color": [r, g, b], "ior": 1.5,
//!                               "alpha_mode": "opaque", "alpha_cutoff": null,
//!                               "transmission": { "factor": 1, "thickness": 0.1,
//!                                                 "attenuation_coefficient": [r, g, b] },
//!                               "clearcoat": { "factor": 1, "roughness": 0.1 },
//!                               "sheen": { "color": [r, g, b], "roughness": 0.5 },
//!                               "unlit": false,
//!                               "textures_not_exported": ["baseColorTexture"] } } ],
//!   "lights": [ { "type": "spot", "position": [x, y, z], "direction": [x, y, z],
//!                 "intensity": [r, g, b], "inner_cone_angle": 0, "outer_cone_angle": 0.785 } ],
//!   "medium": { "sigma_a": [r, g, b], "sigma_s": [r, g, b], "g": 0.6 } }
//! ```
//!
//! `camera` is `null` when the scene has none; `target` is the centre of the image plane and
//! `fov_y_degrees` the full vertical field of view. `material` is `null` for scenes of plain
//! Lambertian materials (the built-in box, OBJ files): `color` and `emission` say all; else
//! it holds the glTF factors (`color` is then the base colour's RGB), the layers' among them
//! (`transmission`, `clearcoat` and `sheen` are `null` for materials without that layer;
//! `vkpath export` notes once which layers the scene uses, since a consumer that reads only
//! the metallic-roughness factors renders glass as opaque plastic). Textures, vertex normals and texture
//! coordinates are not exported (the PLY files hold positions only): `textures_not_exported`
//! names the textures a material loses. `lights` lists KHR_lights_punctual lights in world
//! space, in the units of the README (`type` point, spot or directional; `position` is
//! unused for directional lights, `direction` for point lights; cone angles in radians, spot
//! lights only). Each PLY holds its triangles as a soup (3 vertices each, `float x, y, z`),
//! counter-clockwise seen from the side their normal points to: the side one-sided emitters
//! shine towards. `medium` is the global homogeneous medium of `render --medium` (`vkpath
//! export --medium`, `crate::medium::Medium`), or `null` without one: `sigma_a` and
//! `sigma_s` per scene unit of length, linear RGB, `g` the Henyey-Greenstein anisotropy. It
//! fills all space outside closed refracting volumes, the camera's included, and reaches to
//! infinity (docs/media.md): a consumer gives it to the camera and to both sides of every
//! surface that does not enclose glass (Mitsuba: the sensor's `medium`, each shape's
//! `interior` and `exterior`). Every file is written as the images are (`image_io::output`): through a
//! temporary file renamed into place, never into a device, FIFO or directory.

use std::collections::BTreeMap;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Serialize;

use crate::camera::Camera;
use crate::image_io::output::write_atomically;
use crate::lights::{PunctualKind, PunctualLight};
use crate::medium::Medium;
use crate::scene::material_params::MATERIAL_TEXTURES;
use crate::scene::materials::{AlphaMode, PbrMaterial};
use crate::scene::{Scene, Triangle};

/// What went wrong while exporting.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// A file could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A file was refused or failed while written (`write_atomically`'s message names it).
    #[error("{0}")]
    Refused(String),
}

/// The files an export wrote.
#[derive(Debug)]
pub struct ExportedFiles {
    /// `scene.json`.
    pub manifest: PathBuf,
    /// The `mesh_<k>.ply` files, in mesh order.
    pub meshes: Vec<PathBuf>,
}

/// The camera as the manifest stores it.
#[derive(Debug, Serialize)]
struct ManifestCamera {
    position: [f32; 3],
    target: [f32; 3],
    up: [f32; 3],
    fov_y_degrees: f64,
    /// The thin lens (depth of field), only where the camera has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    lens: Option<ManifestLens>,
}

/// A camera's thin lens, as the manifest stores it (`crate::camera::Lens`; the rotation in
/// degrees).
#[derive(Debug, Serialize)]
struct ManifestLens {
    aperture_radius: f32,
    focus_distance: f32,
    aperture_blades: u32,
    aperture_rotation_degrees: f32,
}

/// A glTF material's factors, as the manifest stores them.
#[derive(Debug, Serialize)]
struct ManifestMaterial {
    base_color: [f32; 4],
    metallic: f32,
    roughness: f32,
    specular: f32,
    specular_color: [f32; 3],
    ior: f32,
    alpha_mode: &'static str,
    alpha_cutoff: Option<f32>,
    /// KHR_materials_transmission and KHR_materials_volume, when the material transmits.
    transmission: Option<ManifestTransmission>,
    /// KHR_materials_clearcoat, when the material has a coat.
    clearcoat: Option<ManifestClearcoat>,
    /// KHR_materials_sheen, when the material has sheen.
    sheen: Option<ManifestSheen>,
    /// KHR_materials_unlit.
    unlit: bool,
    textures_not_exported: Vec<&'static str>,
}

/// A material's transmission and volume factors, as the manifest stores them.
#[derive(Debug, Serialize)]
struct ManifestTransmission {
    factor: f32,
    /// 0: thin-walled; above 0: the mesh encloses a refracting volume.
    thickness: f32,
    /// Absorption coefficient per unit length, per channel (Beer-Lambert; 0: none).
    attenuation_coefficient: [f32; 3],
}

/// A material's clear coat factors, as the manifest stores them.
#[derive(Debug, Serialize)]
struct ManifestClearcoat {
    factor: f32,
    roughness: f32,
}

/// A material's sheen factors, as the manifest stores them.
#[derive(Debug, Serialize)]
struct ManifestSheen {
    color: [f32; 3],
    roughness: f32,
}

/// The names of the layers (glTF extensions) `material` uses beyond metallic-roughness, for
/// the export's one note: their factors are in the manifest, which a consumer may not read.
pub fn layers_of(material: &PbrMaterial) -> Vec<&'static str> {
    let used = [
        material.transmission.factor > 0.0,
        material.clearcoat.factor > 0.0,
        material.sheen.color.max_element() > 0.0,
        material.unlit,
    ];
    LAYERS
        .iter()
        .zip(used)
        .filter(|(_, used)| *used)
        .map(|(name, _)| *name)
        .collect()
}

/// The manifest's keys of the layers beyond metallic-roughness (`layers_of`'s names).
pub const LAYERS: [&str; 4] = ["transmission", "clearcoat", "sheen", "unlit"];

impl ManifestMaterial {
    fn new(material: &PbrMaterial) -> ManifestMaterial {
        let (alpha_mode, alpha_cutoff) = match material.alpha_mode {
            AlphaMode::Opaque => ("opaque", None),
            AlphaMode::Mask { cutoff } => ("mask", Some(cutoff)),
            AlphaMode::Blend => ("blend", None),
        };
        let transmission = &material.transmission;
        let clearcoat = &material.clearcoat;
        let sheen = &material.sheen;
        ManifestMaterial {
            base_color: material.base_color.to_array(),
            metallic: material.metallic,
            roughness: material.roughness,
            specular: material.specular,
            specular_color: material.specular_color.to_array(),
            ior: material.ior,
            alpha_mode,
            alpha_cutoff,
            transmission: (transmission.factor > 0.0).then(|| ManifestTransmission {
                factor: transmission.factor,
                thickness: transmission.thickness,
                attenuation_coefficient: transmission.attenuation.to_array(),
            }),
            clearcoat: (clearcoat.factor > 0.0).then_some(ManifestClearcoat {
                factor: clearcoat.factor,
                roughness: clearcoat.roughness,
            }),
            sheen: (sheen.color.max_element() > 0.0).then(|| ManifestSheen {
                color: sheen.color.to_array(),
                roughness: sheen.roughness,
            }),
            unlit: material.unlit,
            textures_not_exported: MATERIAL_TEXTURES
                .iter()
                .filter(|texture| (texture.get)(material).is_some())
                .map(|texture| texture.name)
                .collect(),
        }
    }
}

/// One mesh of the manifest: all triangles of one material.
#[derive(Debug, Serialize)]
struct ManifestMesh {
    file: String,
    triangles: usize,
    color: [f32; 3],
    emission: [f32; 3],
    double_sided: bool,
    material: Option<ManifestMaterial>,
}

/// A punctual light of the manifest.
#[derive(Debug, Serialize)]
struct ManifestLight {
    #[serde(rename = "type")]
    kind: &'static str,
    position: [f32; 3],
    direction: [f32; 3],
    intensity: [f32; 3],
    inner_cone_angle: Option<f32>,
    outer_cone_angle: Option<f32>,
}

impl ManifestLight {
    fn new(light: &PunctualLight) -> ManifestLight {
        let (kind, inner, outer) = match light.kind {
            PunctualKind::Point => ("point", None, None),
            PunctualKind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => ("spot", Some(inner_cone_angle), Some(outer_cone_angle)),
            PunctualKind::Directional => ("directional", None, None),
        };
        ManifestLight {
            kind,
            position: light.position.to_array(),
            direction: light.direction.to_array(),
            intensity: light.intensity.to_array(),
            inner_cone_angle: inner,
            outer_cone_angle: outer,
        }
    }
}

/// The global homogeneous medium, as the manifest stores it (`crate::medium::Medium`).
#[derive(Debug, Serialize)]
struct ManifestMedium {
    /// Absorption per scene unit of length, linear RGB.
    sigma_a: [f32; 3],
    /// Scattering per scene unit of length, linear RGB.
    sigma_s: [f32; 3],
    /// The Henyey-Greenstein anisotropy, in (-1, 1).
    g: f32,
}

impl ManifestMedium {
    fn new(medium: &Medium) -> ManifestMedium {
        ManifestMedium {
            sigma_a: medium.absorption.to_array(),
            sigma_s: medium.scattering.to_array(),
            g: medium.anisotropy,
        }
    }
}

/// `scene.json`.
#[derive(Debug, Serialize)]
struct Manifest {
    camera: Option<ManifestCamera>,
    meshes: Vec<ManifestMesh>,
    lights: Vec<ManifestLight>,
    /// `null` without a medium.
    medium: Option<ManifestMedium>,
}

/// A material, bit-exact, as the key that groups triangles into meshes: colour, emission,
/// sidedness and the glTF material's index (if the scene has glTF materials).
type MaterialKey = ([u32; 3], [u32; 3], bool, Option<u32>);

fn material_key(triangle: &Triangle, material: Option<u32>) -> MaterialKey {
    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
    (
        bits(triangle.color),
        bits(triangle.emission),
        triangle.double_sided,
        material,
    )
}

/// Writes `scene` into `directory` (created if missing) as `scene.json` and `mesh_<k>.ply`,
/// with `camera` (the scene's own, or the one the user chose) and `medium` (the render's
/// global medium, if any). Returns the files written.
pub fn export_scene(
    scene: &Scene,
    camera: Option<&Camera>,
    medium: Option<&Medium>,
    directory: &Path,
) -> Result<ExportedFiles, ExportError> {
    fs::create_dir_all(directory).map_err(|source| ExportError::Write {
        path: directory.to_path_buf(),
        source,
    })?;
    // glTF materials, where the scene has them and they say more than colour and emission.
    let materials = scene.materials.as_ref().filter(|m| {
        m.materials
            .iter()
            .any(|material| !material.is_plain_lambertian())
    });
    let material_of = |index: usize| {
        materials.and_then(|m| m.triangles.get(index).map(|shading| shading.material))
    };
    // Group in first-appearance order, so that mesh numbers are stable for a given scene.
    let mut groups: Vec<(Option<u32>, Vec<&Triangle>)> = Vec::new();
    let mut group_of: BTreeMap<MaterialKey, usize> = BTreeMap::new();
    for (index, triangle) in scene.triangles.iter().enumerate() {
        let material = material_of(index);
        let next = groups.len();
        let group = *group_of
            .entry(material_key(triangle, material))
            .or_insert(next);
        if group == next {
            groups.push((material, Vec::new()));
        }
        groups[group].1.push(triangle);
    }
    let mut meshes = Vec::with_capacity(groups.len());
    let mut files = Vec::with_capacity(groups.len());
    for (index, (material, triangles)) in groups.iter().enumerate() {
        let file = format!("mesh_{index}.ply");
        let path = directory.join(&file);
        write_atomically(&path, |temporary| write_ply(temporary, triangles))
            .map_err(|e| ExportError::Refused(e.to_string()))?;
        files.push(path);
        let first = triangles[0];
        let material = material
            .and_then(|m| materials.and_then(|all| all.materials.get(m as usize)))
            .map(ManifestMaterial::new);
        meshes.push(ManifestMesh {
            file,
            triangles: triangles.len(),
            color: first.color.to_array(),
            emission: first.emission.to_array(),
            double_sided: first.double_sided,
            material,
        });
    }
    let manifest = Manifest {
        camera: camera.map(|camera| ManifestCamera {
            position: camera.position.to_array(),
            target: camera.image_plane_middle.to_array(),
            up: camera.up.normalize().to_array(),
            fov_y_degrees: (2.0
                * (0.5 * f64::from(camera.up.length())).atan2(f64::from(
                    (camera.image_plane_middle - camera.position).length(),
                )))
            .to_degrees(),
            lens: (!camera.lens.is_pinhole()).then(|| ManifestLens {
                aperture_radius: camera.lens.aperture_radius,
                focus_distance: camera.lens.focus_distance,
                aperture_blades: camera.lens.blades,
                aperture_rotation_degrees: camera.lens.rotation.to_degrees(),
            }),
        }),
        meshes,
        lights: scene
            .punctual_lights
            .iter()
            .map(ManifestLight::new)
            .collect(),
        medium: medium.map(ManifestMedium::new),
    };
    let path = directory.join("scene.json");
    let json = serde_json::to_string_pretty(&manifest)
        .map_err(|e| ExportError::Refused(format!("cannot describe the scene as JSON: {e}")))?;
    write_atomically(&path, |temporary| fs::write(temporary, &json))
        .map_err(|e| ExportError::Refused(e.to_string()))?;
    Ok(ExportedFiles {
        manifest: path,
        meshes: files,
    })
}

/// Writes `triangles` as a binary little-endian PLY triangle soup.
fn write_ply(path: &Path, triangles: &[&Triangle]) -> std::io::Result<()> {
    let mut out = BufWriter::new(fs::File::create(path)?);
    write!(
        out,
        "ply\nformat binary_little_endian 1.0\ncomment written by vkpath\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        3 * triangles.len(),
        triangles.len()
    )?;
    for triangle in triangles {
        for position in triangle.positions {
            for coordinate in position.to_array() {
                out.write_all(&coordinate.to_le_bytes())?;
            }
        }
    }
    for index in 0..triangles.len() as u32 {
        out.write_all(&[3u8])?;
        for corner in 0..3 {
            out.write_all(&(3 * index + corner).to_le_bytes())?;
        }
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads back a PLY written by `write_ply`: its vertex positions, in order.
    fn read_ply_positions(path: &Path) -> Vec<[f32; 3]> {
        let bytes = fs::read(path).unwrap();
        let header_end = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        let header = std::str::from_utf8(&bytes[..header_end]).unwrap();
        let vertices: usize = header
            .lines()
            .find_map(|line| line.strip_prefix("element vertex "))
            .unwrap()
            .parse()
            .unwrap();
        let body = &bytes[header_end..];
        let floats: Vec<f32> = body[..12 * vertices]
            .chunks(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        // The faces follow: one (3, i, i + 1, i + 2) record of 13 bytes per triangle.
        let faces = &body[12 * vertices..];
        assert_eq!(faces.len(), 13 * vertices / 3);
        for (t, face) in faces.chunks(13).enumerate() {
            assert_eq!(face[0], 3);
            let index =
                |k: usize| u32::from_le_bytes(face[1 + 4 * k..5 + 4 * k].try_into().unwrap());
            assert_eq!(
                [index(0), index(1), index(2)],
                [3 * t as u32, 3 * t as u32 + 1, 3 * t as u32 + 2]
            );
        }
        floats.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
    }

    #[test]
    fn cornell_box_exports_by_material_with_its_camera() {
        let scene = Scene::builtin_cornell_box().unwrap();
        let directory = std::env::temp_dir().join(format!("vkpath-export-{}", std::process::id()));
        let exported = export_scene(&scene, scene.camera.as_ref(), None, &directory).unwrap();
        let manifest_path = exported.manifest;
        let manifest: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(&manifest_path).unwrap()).unwrap();
        let meshes = manifest["meshes"].as_array().unwrap();
        // Every triangle lands in exactly one mesh, and each mesh's file holds its triangles
        // in scene order with their vertices bit-exact.
        let total: u64 = meshes
            .iter()
            .map(|m| m["triangles"].as_u64().unwrap())
            .sum();
        assert_eq!(total as usize, scene.triangles.len());
        for mesh in meshes {
            let color: Vec<f32> = serde_json::from_value(mesh["color"].clone()).unwrap();
            let emission: Vec<f32> = serde_json::from_value(mesh["emission"].clone()).unwrap();
            let expected: Vec<[f32; 3]> = scene
                .triangles
                .iter()
                .filter(|t| {
                    t.color.to_array() == color[..] && t.emission.to_array() == emission[..]
                })
                .flat_map(|t| t.positions.map(|p| p.to_array()))
                .collect();
            let file = directory.join(mesh["file"].as_str().unwrap());
            assert_eq!(read_ply_positions(&file), expected);
        }
        let emitters = meshes
            .iter()
            .filter(|m| m["emission"][0].as_f64().unwrap() > 0.0)
            .count();
        assert_eq!(emitters, 1, "the ceiling light is one material");
        // The workshop's camera: fov_y = 2 atan(0.28 / 0.8) = 38.58 degrees.
        let fov = manifest["camera"]["fov_y_degrees"].as_f64().unwrap();
        assert!((fov - 38.58).abs() < 0.01, "fov {fov}");
        assert!(manifest["medium"].is_null(), "no medium: null");
        fs::remove_dir_all(&directory).unwrap();
    }

    #[test]
    fn the_medium_is_exported_with_its_coefficients() {
        let scene = Scene::builtin_cornell_box().unwrap();
        let directory =
            std::env::temp_dir().join(format!("vkpath-export-medium-{}", std::process::id()));
        let medium: Medium = "sigma_a=0.05,0.1,0.2:sigma_s=0.3:g=0.6".parse().unwrap();
        let exported =
            export_scene(&scene, scene.camera.as_ref(), Some(&medium), &directory).unwrap();
        let manifest: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(&exported.manifest).unwrap()).unwrap();
        let floats = |key: &str| -> Vec<f32> {
            serde_json::from_value(manifest["medium"][key].clone()).unwrap()
        };
        // Bit for bit: f32 -> JSON -> f32 round trips (serde_json writes the shortest form).
        assert_eq!(floats("sigma_a"), [0.05, 0.1, 0.2]);
        assert_eq!(floats("sigma_s"), [0.3, 0.3, 0.3]);
        assert_eq!(manifest["medium"]["g"].as_f64().unwrap() as f32, 0.6);
        fs::remove_dir_all(&directory).unwrap();
    }
}
