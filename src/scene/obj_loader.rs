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
    let malformed = |line: Option<usize>, error| SceneError::Obj {
        path: path.to_owned(),
        line,
        error,
    };
    let text = index_every_corner(&bytes).map_err(|(line, error)| malformed(Some(line), error))?;
    drop(bytes);
    let directory = path.parent().unwrap_or(Path::new(""));
    // tobj keeps only one library error (and only when no library loaded at all), so we
    // record every failing library ourselves.
    let failed_libraries: RefCell<Vec<(PathBuf, Option<usize>, tobj::LoadError)>> =
        RefCell::new(Vec::new());
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
        .ok_or((None, tobj::LoadError::OpenFileFailed))
        .and_then(|text| {
            library_bytes.set(library_bytes.get() + text.len() as u64);
            // `sanitize_mtl` keeps one line per line, so its line numbers are the file's.
            let sanitized = sanitize_mtl(&text);
            tobj::load_mtl_buf(&mut sanitized.as_bytes()).map_err(|error| {
                let line = first_failing_line(&sanitized, |start| {
                    tobj::load_mtl_buf(&mut start.as_bytes()).err() == Some(error)
                });
                (line, error)
            })
        });
        match result {
            Ok(loaded) => Ok(loaded),
            Err((line, error)) => {
                failed_libraries
                    .borrow_mut()
                    .push((library_path, line, error));
                Err(error)
            }
        }
    })
    .map_err(|error| {
        // tobj stops at the first line it cannot read, and says which error but not where:
        // the line is the shortest start of the text that it rejects with that error.
        let line = first_failing_line(&text, |start| {
            let loaded =
                tobj::load_obj_buf(&mut start.as_bytes(), &options, |_| Ok(Default::default()));
            loaded.err() == Some(error)
        });
        malformed(line.and_then(original_line), error)
    })?;
    drop(text);

    let mut builder = SceneBuilder::new(path);
    for (library_path, line, error) in failed_libraries.into_inner() {
        if error != tobj::LoadError::OpenFileFailed {
            return Err(SceneError::Obj {
                path: library_path,
                line,
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
                line: None,
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

/// The lines [`MISSING_CORNER_DATA`] puts before the file's own.
const MISSING_CORNER_LINES: usize = 2;

/// The file's line (from 1) of line `line` of the text `index_every_corner` made, which
/// keeps one line per line after [`MISSING_CORNER_DATA`]'s; `None` for those.
fn original_line(line: usize) -> Option<usize> {
    line.checked_sub(MISSING_CORNER_LINES)
        .filter(|&line| line > 0)
}

/// The line (from 1) of `text` on which a parser that stops at the first line it cannot
/// read fails: the fewest whole lines from the start on which `fails` holds, found by
/// bisection (the parser is run about log2(lines) times, and only after it failed).
/// `None` for a text without lines, or when even all of it passes.
fn first_failing_line(text: &str, fails: impl Fn(&str) -> bool) -> Option<usize> {
    let mut ends: Vec<usize> = text.match_indices('\n').map(|(i, _)| i + 1).collect();
    if ends.last() != Some(&text.len()) && !text.is_empty() {
        ends.push(text.len());
    }
    if ends.is_empty() || !fails(text) {
        return None;
    }
    // The first `low` lines pass (none pass trivially), the first `high` lines fail.
    let (mut low, mut high) = (0, ends.len());
    while high - low > 1 {
        let middle = (low + high) / 2;
        if fails(&text[..ends[middle - 1]]) {
            high = middle;
        } else {
            low = middle;
        }
    }
    Some(high)
}

/// The OBJ text with every face corner naming its texture coordinate and normal explicitly
/// (`v/vt/vn`, absolute indices): corners without them refer to [`MISSING_CORNER_DATA`].
///
/// tobj gives a corner without `vn` (or `vt`) the previous corner's, so a faceted face next
/// to a smooth one would borrow its neighbour's normal. Indices out of range are errors
/// here, with their line (from 1): tobj overflows on some, and checks positions only at the
/// end of an object, far from the face. A corner that does not parse is left for tobj to
/// report.
fn index_every_corner(bytes: &[u8]) -> Result<String, (usize, tobj::LoadError)> {
    // tobj reads lines as UTF-8 and fails on any other.
    let text = std::str::from_utf8(bytes).map_err(|error| {
        let line = bytes[..error.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        (line + 1, tobj::LoadError::ReadError)
    })?;
    let total = |wanted: &str| {
        text.lines()
            .filter(|line| line.split_whitespace().next() == Some(wanted))
            .count()
    };
    let totals = [total("v"), total("vt"), total("vn")];
    let mut counts = [0usize; 3];
    let mut indexed = String::with_capacity(text.len() + text.len() / 4 + 32);
    indexed.push_str(MISSING_CORNER_DATA);
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            // Points and lines (one or two corners) are ignored; they stay as they are.
            Some("f") if words.clone().nth(2).is_some() => {
                let corners: Result<Option<Vec<String>>, _> = words
                    .map(|corner| index_corner(corner, counts, totals))
                    .collect();
                if let Some(corners) = corners.map_err(|error| (number + 1, error))? {
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

/// One face corner (`v`, `v/vt`, `v//vn`, `v/vt/vn`) as `v/vt/vn`, the texture coordinate
/// and normal as absolute indices shifted past [`MISSING_CORNER_DATA`] (the position as
/// written, for tobj); `counts` are the `v`, `vt` and `vn` lines so far (negative indices
/// count back from there), `totals` those of the whole file.
fn index_corner(
    corner: &str,
    counts: [usize; 3],
    totals: [usize; 3],
) -> Result<Option<String>, tobj::LoadError> {
    let parts: Vec<&str> = corner.split('/').collect();
    if parts.len() > 3 {
        return Ok(None);
    }
    let errors = [
        tobj::LoadError::FaceVertexOutOfBounds,
        tobj::LoadError::FaceTexCoordOutOfBounds,
        tobj::LoadError::FaceNormalOutOfBounds,
    ];
    let mut indices = [1usize; 3];
    for k in 0..3 {
        let part = parts.get(k).copied().unwrap_or("");
        if part.is_empty() && k > 0 {
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
    Ok(Some(format!("{}/{}/{}", parts[0], indices[1], indices[2])))
}

#[cfg(test)]
#[path = "obj_loader_tests.rs"]
mod tests;
