//! Wavefront OBJ + MTL scenes via `tobj`: polygons are triangulated as fans, `Kd` is the
//! albedo and `Ke` the emission. OBJ has no camera, so the scene has none.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::{Material, Scene, SceneBuilder, SceneError};

/// The albedo of faces without a material (no `usemtl`, or its library is missing) and of
/// materials without `Kd`: the MTL format's customary default diffuse colour.
pub const DEFAULT_ALBEDO: f32 = 0.8;

/// Loads an OBJ file and the MTL libraries it names (relative to the OBJ's directory).
///
/// A missing library is a warning, not an error: its materials fall back to
/// [`DEFAULT_ALBEDO`] and no emission. Texture maps are ignored with a warning.
pub fn load_obj(path: &Path) -> Result<Scene, SceneError> {
    let bytes = super::files::read_bounded(path, super::files::MAX_SCENE_FILE_BYTES)?;
    let directory = path.parent().unwrap_or(Path::new(""));
    // tobj keeps only one library error (and only when no library loaded at all), so we
    // record every failing library ourselves.
    let failed_libraries: RefCell<Vec<(PathBuf, tobj::LoadError)>> = RefCell::new(Vec::new());
    let options = tobj::LoadOptions {
        triangulate: true,
        // Points and lines would become zero-area triangles; they have nothing to render.
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // tobj asks for a library at every `mtllib` line and keeps every copy: each is read once.
    let loaded_libraries: RefCell<std::collections::HashSet<PathBuf>> = RefCell::default();
    let library_bytes = std::cell::Cell::new(0u64);
    let (models, materials) = tobj::load_obj_buf(&mut bytes.as_slice(), &options, |library| {
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
    .map_err(|error| SceneError::Obj {
        path: path.to_owned(),
        error,
    })?;

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
    let materials = materials.unwrap_or_default();
    for material in &materials {
        if let Some(warning) = texture_warning(material) {
            builder.warn(warning);
        }
    }
    let materials: Vec<Material> = materials.iter().map(convert_material).collect();
    let default_material = Material::sanitized(Vec3::splat(DEFAULT_ALBEDO), Vec3::ZERO, false);

    for (model_index, model) in models.iter().enumerate() {
        let name = if model.name.is_empty() {
            format!("#{model_index}")
        } else {
            super::printable(&model.name)
        };
        let material = model
            .mesh
            .material_id
            .and_then(|id| materials.get(id))
            .unwrap_or(&default_material);
        push_mesh(&mut builder, &name, &model.mesh, material)?;
    }
    builder.finish()
}

/// Adds the triangles of one triangulated mesh.
fn push_mesh(
    builder: &mut SceneBuilder,
    name: &str,
    mesh: &tobj::Mesh,
    material: &Material,
) -> Result<(), SceneError> {
    // `as f32` because tobj's float type is f64 under its `use_f64` feature.
    #[allow(clippy::unnecessary_cast)]
    let position = |index: u32| -> Option<Vec3> {
        let start = 3 * usize::try_from(index).ok()?;
        let xyz = mesh.positions.get(start..start + 3)?;
        Some(Vec3::new(xyz[0] as f32, xyz[1] as f32, xyz[2] as f32))
    };
    for face in mesh.indices.chunks_exact(3) {
        let corners = [position(face[0]), position(face[1]), position(face[2])];
        let [Some(v0), Some(v1), Some(v2)] = corners else {
            // tobj checks face indices while parsing; this guards against a gap there.
            return Err(SceneError::Obj {
                path: builder.path().to_owned(),
                error: tobj::LoadError::FaceVertexOutOfBounds,
            });
        };
        builder.push(name, [v0, v1, v2], material)?;
    }
    Ok(())
}

/// `Kd` as albedo (default [`DEFAULT_ALBEDO`]), `Ke` as emission (default 0).
fn convert_material(material: &tobj::Material) -> Material {
    // `as f32` because tobj's float type is f64 under its `use_f64` feature.
    #[allow(clippy::unnecessary_cast)]
    let to_vec3 = |c: [_; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
    let color = material
        .diffuse
        .map(to_vec3)
        .unwrap_or(Vec3::splat(DEFAULT_ALBEDO));
    let emission = material.emissive.map(to_vec3).unwrap_or(Vec3::ZERO);
    Material::sanitized(color, emission, false)
}

/// A warning naming the material and its texture maps, if it has any.
fn texture_warning(material: &tobj::Material) -> Option<String> {
    let known = [
        ("map_Ka", &material.ambient_texture),
        ("map_Kd", &material.diffuse_texture),
        ("map_Ks", &material.specular_texture),
        ("map_Bump", &material.normal_texture),
        ("map_Ns", &material.shininess_texture),
        ("map_d", &material.dissolve_texture),
    ];
    let mut maps: Vec<String> = known
        .iter()
        .filter(|(_, texture)| texture.is_some())
        .map(|(keyword, _)| keyword.to_string())
        .collect();
    // Maps tobj does not know (map_Ke, map_Pr, ...) land among the unknown parameters.
    let mut unknown: Vec<String> = material
        .unknown_param
        .keys()
        .filter(|key| key.starts_with("map_"))
        .cloned()
        .collect();
    unknown.sort();
    maps.extend(unknown);
    if maps.is_empty() {
        return None;
    }
    Some(format!(
        "material '{}' has texture maps ({}), which are ignored; using its constant colours",
        material.name,
        maps.join(", ")
    ))
}

/// An MTL text that tobj can parse without panicking: a colour statement (`Ka`, `Kd`,
/// `Ks`, `Ke`, `Tf`) with fewer than three numbers gets its missing components from the
/// first (the MTL format lets `Kd r` stand for `Kd r r r`), and one with none is dropped
/// (tobj 4 unwraps three numbers).
fn sanitize_mtl(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    let mut sanitized = String::with_capacity(text.len());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        if ["Ka", "Kd", "Ks", "Ke", "Tf"].contains(&keyword) {
            let numbers: Vec<&str> = words.collect();
            match numbers.as_slice() {
                [] => continue,
                [r] => sanitized.push_str(&format!("{keyword} {r} {r} {r}")),
                [r, g] => sanitized.push_str(&format!("{keyword} {r} {g} {g}")),
                _ => sanitized.push_str(line),
            }
        } else {
            sanitized.push_str(line);
        }
        sanitized.push('\n');
    }
    sanitized
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(directory: &Path, name: &str, text: &str) -> PathBuf {
        let path = directory.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn quad_is_triangulated_with_kd_and_ke() {
        let directory = tempfile::tempdir().unwrap();
        write(
            directory.path(),
            "quad.mtl",
            "newmtl lamp\nKd 0.25 0.5 0.75\nKe 4 2 1\n",
        );
        let obj = write(
            directory.path(),
            "quad.obj",
            "mtllib quad.mtl\no lamp\nv 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nusemtl lamp\nf 1 2 3 4\n",
        );
        let scene = load_obj(&obj).unwrap();
        assert!(scene.camera.is_none());
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        assert_eq!(scene.triangles.len(), 2);
        // A fan around the first corner, keeping the face's counter-clockwise winding.
        let expected = [
            [
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 1.0, 0.0),
            ],
            [
                Vec3::ZERO,
                Vec3::new(2.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
        ];
        for (triangle, positions) in scene.triangles.iter().zip(expected) {
            assert_eq!(triangle.positions, positions);
            assert_eq!(triangle.normal, Vec3::Z);
            assert_eq!(triangle.color, Vec3::new(0.25, 0.5, 0.75));
            assert_eq!(triangle.emission, Vec3::new(4.0, 2.0, 1.0));
            assert!(!triangle.double_sided);
        }
    }

    #[test]
    fn missing_library_warns_and_uses_the_default_material() {
        let directory = tempfile::tempdir().unwrap();
        let obj = write(
            directory.path(),
            "t.obj",
            "mtllib gone.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        );
        let scene = load_obj(&obj).unwrap();
        assert_eq!(scene.triangles.len(), 1);
        assert_eq!(scene.triangles[0].color, Vec3::splat(DEFAULT_ALBEDO));
        assert_eq!(scene.triangles[0].emission, Vec3::ZERO);
        assert_eq!(scene.warnings.len(), 1);
        assert!(
            scene.warnings[0].contains("gone.mtl"),
            "{}",
            scene.warnings[0]
        );
    }

    #[test]
    fn textures_are_reported_once_per_material() {
        let directory = tempfile::tempdir().unwrap();
        write(
            directory.path(),
            "t.mtl",
            "newmtl brick\nKd 0.5 0.5 0.5\nmap_Kd brick.png\nmap_Ke glow.png\nnewmtl plain\nKd 1 1 1\n",
        );
        let obj = write(
            directory.path(),
            "t.obj",
            "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl brick\nf 1 2 3\nusemtl plain\nf 1 2 3\n",
        );
        let scene = load_obj(&obj).unwrap();
        assert_eq!(
            scene.warnings,
            vec![
                "material 'brick' has texture maps (map_Kd, map_Ke), which are ignored; \
                 using its constant colours"
                    .to_owned()
            ]
        );
        assert_eq!(scene.triangles[0].color, Vec3::splat(0.5));
        assert_eq!(scene.triangles[1].color, Vec3::ONE);
    }

    #[test]
    fn errors_name_the_file() {
        let directory = tempfile::tempdir().unwrap();
        let missing = directory.path().join("missing.obj");
        let error = load_obj(&missing).unwrap_err();
        assert!(matches!(error, SceneError::Read { .. }), "{error}");

        let bad_index = write(directory.path(), "bad.obj", "v 0 0 0\nf 1 2 3\n");
        let error = load_obj(&bad_index).unwrap_err();
        assert!(matches!(error, SceneError::Obj { .. }), "{error}");
        assert!(error.to_string().starts_with("malformed OBJ '"), "{error}");

        let empty = write(directory.path(), "empty.obj", "v 0 0 0\n");
        let error = load_obj(&empty).unwrap_err();
        assert!(matches!(error, SceneError::NoTriangles { .. }), "{error}");

        let infinite = write(
            directory.path(),
            "inf.obj",
            "o x\nv 0 0 0\nv 1 0 0\nv inf 1 0\nf 1 2 3\n",
        );
        let error = load_obj(&infinite).unwrap_err();
        assert!(
            matches!(error, SceneError::NonFinitePosition { .. }),
            "{error}"
        );
    }

    #[test]
    fn cube_fixture_has_an_emissive_top() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cube.obj");
        let scene = Scene::load(&path).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        assert_eq!(scene.triangles.len(), 12);
        let lights: Vec<_> = scene
            .triangles
            .iter()
            .filter(|t| t.emission != Vec3::ZERO)
            .collect();
        assert_eq!(lights.len(), 2);
        for light in lights {
            assert_eq!(light.emission, Vec3::new(4.0, 3.0, 2.0));
            assert_eq!(light.normal, Vec3::Y);
        }
        // Every face points out of the box centred at the origin.
        for triangle in &scene.triangles {
            let centre =
                (triangle.positions[0] + triangle.positions[1] + triangle.positions[2]) / 3.0;
            assert!(triangle.normal.dot(centre) > 0.0);
        }
    }
}
