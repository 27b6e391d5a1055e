//! Wavefront OBJ + MTL scenes via `tobj`: polygons are triangulated as fans, `Kd` is the
//! albedo and `Ke` the emission (the workshop's Lambertian material), `map_Kd` its texture
//! (see `obj_materials`). `vn` normals are interpolated over each triangle (faceted where a
//! face has none) and `vt` coordinates are flipped to glTF's convention (v down the image).
//! OBJ has no camera, so the scene has none.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3, Vec4};

use super::materials::TriangleShading;
use super::obj_materials::{sanitize_mtl, ObjMaterials};
use super::{Material, Scene, SceneBuilder, SceneError};

/// The albedo of faces without a material (no `usemtl`, or its library is missing) and of
/// materials without `Kd`: the MTL format's customary default diffuse colour.
pub const DEFAULT_ALBEDO: f32 = 0.8;

/// Loads an OBJ file and the MTL libraries it names (relative to the OBJ's directory).
///
/// A missing library is a warning, not an error: its materials fall back to
/// [`DEFAULT_ALBEDO`] and no emission. A `map_Kd` texture that cannot be used is a warning
/// too (the material keeps its `Kd`); other texture maps are ignored with a warning.
pub fn load_obj(path: &Path) -> Result<Scene, SceneError> {
    let bytes = super::files::read_bounded(path, super::files::MAX_SCENE_FILE_BYTES)?;
    let malformed = |error| SceneError::Obj {
        path: path.to_owned(),
        error,
    };
    let text = index_every_corner(&bytes).map_err(malformed)?;
    drop(bytes);
    let directory = path.parent().unwrap_or(Path::new(""));
    // tobj keeps only one library error (and only when no library loaded at all), so we
    // record every failing library ourselves.
    let failed_libraries: RefCell<Vec<(PathBuf, tobj::LoadError)>> = RefCell::new(Vec::new());
    let options = tobj::LoadOptions {
        triangulate: true,
        // Points and lines would become zero-area triangles; they have nothing to render.
        ignore_points: true,
        ignore_lines: true,
        // `single_index` stays false: normals and texture coordinates keep their own
        // per-corner indices (`normal_indices`, `texcoord_indices`).
        ..Default::default()
    };
    // tobj asks for a library at every `mtllib` line and keeps every copy: each is read once.
    let loaded_libraries: RefCell<std::collections::HashSet<PathBuf>> = RefCell::default();
    let library_bytes = std::cell::Cell::new(0u64);
    let (models, materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |library| {
        let library_path = directory.join(library);
        if !loaded_libraries.borrow_mut().insert(library_path.clone()) {
            return Ok((Vec::new(), Default::default()));
        }
        // Material libraries are read like the OBJ itself: regular files inside its folder,
        // of bounded size (all of them together too); any other is reported as a library
        // that cannot be opened.
        let budget = super::files::MAX_SCENE_FILE_BYTES.saturating_sub(library_bytes.get());
        let result = super::files::resolve_reference(
            path,
            &library.to_string_lossy(),
            &super::files::LoadOptions::default(),
        )
        .ok()
        .and_then(|file| super::files::read_bounded(&file, budget).ok())
        .ok_or(tobj::LoadError::OpenFileFailed)
        .and_then(|text| {
            library_bytes.set(library_bytes.get() + text.len() as u64);
            tobj::load_mtl_buf(&mut sanitize_mtl(&text).as_bytes())
        });
        if let Err(error) = &result {
            failed_libraries.borrow_mut().push((library_path, *error));
        }
        result
    })
    .map_err(malformed)?;
    drop(text);

    let mut builder = SceneBuilder::new(path);
    for (library_path, error) in failed_libraries.into_inner() {
        if error != tobj::LoadError::OpenFileFailed {
            return Err(SceneError::Obj {
                path: library_path,
                error,
            });
        }
        builder.warn(format!(
            "cannot open material library '{}'; its materials get albedo {DEFAULT_ALBEDO} \
             and no emission",
            library_path.display()
        ));
    }
    // With every library missing, tobj returns the error here instead of an empty list.
    let materials = ObjMaterials::new(path, &materials.unwrap_or_default());
    for warning in materials.warnings {
        builder.warn(warning);
    }
    let default_material = materials.workshop.len() - 1;

    for (model_index, model) in models.iter().enumerate() {
        let name = if model.name.is_empty() {
            format!("#{model_index}")
        } else {
            super::printable(&model.name)
        };
        let material = model
            .mesh
            .material_id
            .filter(|&id| id < default_material)
            .unwrap_or(default_material);
        push_mesh(
            &mut builder,
            &name,
            &model.mesh,
            &materials.workshop[material],
            material as u32,
        )?;
    }
    builder.set_materials(materials.materials, materials.textures);
    builder.finish()
}

/// Adds the triangles of one triangulated mesh, each with its shading data.
fn push_mesh(
    builder: &mut SceneBuilder,
    name: &str,
    mesh: &tobj::Mesh,
    material: &Material,
    material_index: u32,
) -> Result<(), SceneError> {
    let position = |index: u32| element::<3, _>(&mesh.positions, index).map(Vec3::from);
    // `index_every_corner` gives every corner its own normal and texture coordinate index;
    // the guards only cover a gap in tobj. A zero normal becomes the face's in the builder.
    let normal = |corner: usize| {
        mesh.normal_indices
            .get(corner)
            .and_then(|&index| element::<3, _>(&mesh.normals, index))
            .map_or(Vec3::ZERO, Vec3::from)
    };
    // OBJ's v points up the image, glTF's (and vkpath's) down.
    let tex_coord = |corner: usize| {
        mesh.texcoord_indices
            .get(corner)
            .and_then(|&index| element::<2, _>(&mesh.texcoords, index))
            .map(|uv| Vec2::new(uv[0], 1.0 - uv[1]))
            .filter(|uv| uv.is_finite())
            .unwrap_or(Vec2::ZERO)
    };
    for (triangle, face) in mesh.indices.chunks_exact(3).enumerate() {
        let corners = [position(face[0]), position(face[1]), position(face[2])];
        let [Some(v0), Some(v1), Some(v2)] = corners else {
            // tobj checks face indices while parsing; this guards against a gap there.
            return Err(SceneError::Obj {
                path: builder.path().to_owned(),
                error: tobj::LoadError::FaceVertexOutOfBounds,
            });
        };
        let corner = |k: usize| 3 * triangle + k;
        let shading = TriangleShading {
            material: material_index,
            normals: [0, 1, 2].map(|k| normal(corner(k))),
            tex_coords: [0, 1, 2].map(|k| tex_coord(corner(k))),
            tangents: [Vec4::ZERO; 3],
        };
        builder.push_shaded(name, [v0, v1, v2], material, shading)?;
    }
    Ok(())
}

/// Element `index` of a flattened array of `N`-vectors, if there is one.
/// (Generic because tobj's float type is f64 under its `use_f64` feature.)
fn element<const N: usize, F: Copy + Into<f64>>(values: &[F], index: u32) -> Option<[f32; N]> {
    let start = N.checked_mul(usize::try_from(index).ok()?)?;
    let values = values.get(start..start.checked_add(N)?)?;
    Some(std::array::from_fn(|i| values[i].into() as f32))
}

/// The texture coordinate and normal that corners without `vt` or `vn` refer to: they come
/// first, so that they are `vt 1` and `vn 1`. (0, 1) is glTF's (0, 0) (where glTF puts the
/// coordinates of a mesh without any); a zero normal becomes the face's normal.
const MISSING_CORNER_DATA: &str = "vt 0 1\nvn 0 0 0\n";

/// The OBJ text with every face corner naming its texture coordinate and normal explicitly
/// (`v/vt/vn`, absolute indices): corners without them refer to [`MISSING_CORNER_DATA`].
///
/// tobj gives a corner without `vn` (or `vt`) the previous corner's, so a faceted face next
/// to a smooth one would borrow its neighbour's normal. Indices out of range are errors
/// here (tobj overflows on some); a corner that does not parse is left for tobj to report.
fn index_every_corner(bytes: &[u8]) -> Result<String, tobj::LoadError> {
    // tobj reads lines as UTF-8 and fails on any other.
    let text = std::str::from_utf8(bytes).map_err(|_| tobj::LoadError::ReadError)?;
    let total = |wanted: &str| {
        text.lines()
            .filter(|line| line.split_whitespace().next() == Some(wanted))
            .count()
    };
    let totals = [total("vt"), total("vn")];
    let mut counts = [0usize; 2];
    let mut indexed = String::with_capacity(text.len() + text.len() / 4 + 32);
    indexed.push_str(MISSING_CORNER_DATA);
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("vt") => counts[0] += 1,
            Some("vn") => counts[1] += 1,
            // Points and lines (one or two corners) are ignored; they stay as they are.
            Some("f") if words.clone().nth(2).is_some() => {
                let corners: Result<Option<Vec<String>>, _> = words
                    .map(|corner| index_corner(corner, counts, totals))
                    .collect();
                if let Some(corners) = corners? {
                    indexed.push_str("f ");
                    indexed.push_str(&corners.join(" "));
                    indexed.push('\n');
                    continue;
                }
            }
            _ => {}
        }
        indexed.push_str(line);
        indexed.push('\n');
    }
    Ok(indexed)
}

/// One face corner (`v`, `v/vt`, `v//vn`, `v/vt/vn`) as `v/vt/vn` with absolute indices
/// shifted past [`MISSING_CORNER_DATA`]; `counts` are the `vt` and `vn` lines so far
/// (negative indices count back from there), `totals` those of the whole file.
fn index_corner(
    corner: &str,
    counts: [usize; 2],
    totals: [usize; 2],
) -> Result<Option<String>, tobj::LoadError> {
    let parts: Vec<&str> = corner.split('/').collect();
    if parts.len() > 3 {
        return Ok(None);
    }
    let errors = [
        tobj::LoadError::FaceTexCoordOutOfBounds,
        tobj::LoadError::FaceNormalOutOfBounds,
    ];
    let mut indices = [1usize; 2];
    for k in 0..2 {
        let part = parts.get(k + 1).copied().unwrap_or("");
        if part.is_empty() {
            continue;
        }
        let Ok(index) = part.parse::<i64>() else {
            return Ok(None);
        };
        // 0 is no OBJ index; tobj reads it as missing, and so do we.
        if index == 0 {
            continue;
        }
        // 1-based absolute index.
        let absolute = if index < 0 {
            counts[k] as i64 + 1 + index
        } else {
            index
        };
        if absolute < 1 || absolute > totals[k] as i64 {
            return Err(errors[k]);
        }
        indices[k] = absolute as usize + 1;
    }
    Ok(Some(format!("{}/{}/{}", parts[0], indices[0], indices[1])))
}

#[cfg(test)]
#[path = "obj_loader_tests.rs"]
mod tests;
