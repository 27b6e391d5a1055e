//! Tests of the OBJ loader: geometry, materials, shading data and textures.

use super::*;
use crate::scene::materials::SceneMaterials;
use crate::scene::textures::{TextureTransform, WrapMode};

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
    // Flat and untextured: the workshop's kernels render it.
    assert!(scene.materials.is_none());
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
fn other_maps_are_reported_once_per_material() {
    let directory = tempfile::tempdir().unwrap();
    write(
        directory.path(),
        "t.mtl",
        "newmtl brick\nKd 0.5 0.5 0.5\nmap_Ks shine.png\nmap_Ke glow.png\nbump b.png\n\
         newmtl plain\nKd 1 1 1\n",
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
            "material 'brick' has texture maps (map_Ks, map_Bump, map_Ke), which are ignored \
             (vkpath reads map_Kd only); using its constant colours"
                .to_owned()
        ]
    );
    assert_eq!(scene.triangles[0].color, Vec3::splat(0.5));
    assert_eq!(scene.triangles[1].color, Vec3::ONE);
    assert!(scene.materials.is_none());
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
    assert!(
        error
            .to_string()
            .ends_with("bad.obj:2': face vertex index out of bounds"),
        "{error}"
    );

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
    assert!(scene.materials.is_none());
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
        let centre = (triangle.positions[0] + triangle.positions[1] + triangle.positions[2]) / 3.0;
        assert!(triangle.normal.dot(centre) > 0.0);
    }
}

/// The shading data of a scene that must have some.
fn shading(scene: &Scene) -> &SceneMaterials {
    scene
        .materials
        .as_ref()
        .expect("the scene needs its shading data")
}

#[test]
fn smooth_normals_are_interpolated_per_corner() {
    let directory = tempfile::tempdir().unwrap();
    // A quad with a normal per corner (the last by a relative index), and a triangle
    // without normals that shares its corners.
    let obj = write(
        directory.path(),
        "smooth.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n\
         vn -1 0 1\nvn 0 0 2\nvn 1 0 1\nvn 0 1 1\n\
         f 1//1 2//2 3//3 4//-1\nf 1 4 5\n",
    );
    let scene = load_obj(&obj).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let shading = shading(&scene);
    assert_eq!(shading.triangles.len(), 3);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let (n1, n2, n3, n4) = (
        Vec3::new(-s, 0.0, s),
        Vec3::Z,
        Vec3::new(s, 0.0, s),
        Vec3::new(0.0, s, s),
    );
    // The fan (1 2 3), (1 3 4) keeps each corner's own normal, normalised.
    assert_eq!(shading.triangles[0].normals, [n1, n2, n3]);
    assert_eq!(shading.triangles[1].normals, [n1, n3, n4]);
    // The face without normals is faceted, not given its neighbour's last normal.
    assert_eq!(scene.triangles[2].normal, Vec3::X);
    assert_eq!(shading.triangles[2].normals, [Vec3::X; 3]);
    assert!(shading.triangles.iter().all(|t| t.material == 0));
    assert_eq!(shading.materials.len(), 1);
    assert!(shading.materials[0].is_plain_lambertian());
}

#[test]
fn face_normals_stay_flat() {
    let directory = tempfile::tempdir().unwrap();
    // Normals as exporters write flat shading: the face's, at every corner.
    let obj = write(
        directory.path(),
        "flat.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nvt 1 1\n\
         f 1/1/1 2/2/1 3/2/1 4/1/1\n",
    );
    let scene = load_obj(&obj).unwrap();
    assert_eq!(scene.triangles.len(), 2);
    assert!(scene.materials.is_none());
}

/// Writes a PNG of `width` x `height` RGBA texels.
fn write_png(path: &Path, width: u32, height: u32, texels: &[[u8; 4]]) {
    image::save_buffer(
        path,
        texels.as_flattened(),
        width,
        height,
        image::ExtendedColorType::Rgba8,
    )
    .unwrap();
}

#[test]
fn map_kd_is_decoded_and_texture_coordinates_are_flipped() {
    let directory = tempfile::tempdir().unwrap();
    std::fs::create_dir(directory.path().join("maps")).unwrap();
    let texels = [
        [255, 0, 0, 255],
        [0, 255, 0, 255],
        [0, 0, 255, 255],
        [9, 9, 9, 255],
    ];
    write_png(&directory.path().join("maps/brick.png"), 2, 2, &texels);
    write(
        directory.path(),
        "t.mtl",
        "newmtl brick\n\tKd 0.5 0.25 1\n\tmap_Kd maps\\brick.png\n\
         newmtl tiled\nmap_Kd -s 2 2 -bm 1 maps/brick.png\n",
    );
    // The second face has no vt: its corners get (0, 0).
    let obj = write(
        directory.path(),
        "t.obj",
        "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0\nvt 1 0.25\nvt 0 1\n\
         usemtl brick\nf 1/1 2/2 3/-1\nusemtl tiled\nf 1 2 3\n",
    );
    let scene = load_obj(&obj).unwrap();
    assert_eq!(
        scene.warnings,
        vec!["material 'tiled': map_Kd options -bm are ignored".to_owned()]
    );
    // The workshop's triangle keeps Kd; the texture multiplies it.
    assert_eq!(scene.triangles[0].color, Vec3::new(0.5, 0.25, 1.0));
    let shading = shading(&scene);
    // One texture for both materials: decoded once.
    assert_eq!(shading.textures.len(), 1);
    let texture = &shading.textures[0];
    assert_eq!((texture.width, texture.height), (2, 2));
    assert_eq!(texture.texels, texels);
    assert_eq!(
        (texture.wrap_s, texture.wrap_t),
        (WrapMode::Repeat, WrapMode::Repeat)
    );
    assert!(!texture.nearest);
    // Two MTL materials and the default one.
    assert_eq!(shading.materials.len(), 3);
    let brick = &shading.materials[0];
    assert_eq!(brick.base_color, glam::Vec4::new(0.5, 0.25, 1.0, 1.0));
    assert_eq!((brick.metallic, brick.specular), (0.0, 0.0));
    let binding = brick.base_color_texture.unwrap();
    assert_eq!(binding.texture, 0);
    assert_eq!(binding.transform, TextureTransform::identity());
    let tiled = shading.materials[1].base_color_texture.unwrap();
    // -s 2 2: v'_obj = 2 v_obj, so v'_gltf = 1 - 2 (1 - v_gltf) = 2 v_gltf - 1.
    assert_eq!(
        tiled.transform,
        TextureTransform::from_gltf([0.0, -1.0], 0.0, [2.0, 2.0])
    );
    assert_eq!(shading.triangles[0].material, 0);
    assert_eq!(shading.triangles[1].material, 1);
    // v_gltf = 1 - v_obj.
    assert_eq!(
        shading.triangles[0].tex_coords,
        [
            glam::Vec2::new(0.25, 1.0),
            glam::Vec2::new(1.0, 0.75),
            glam::Vec2::new(0.0, 0.0)
        ]
    );
    assert_eq!(shading.triangles[1].tex_coords, [glam::Vec2::ZERO; 3]);
    assert_eq!(shading.triangles[0].normals, [Vec3::Z; 3]);
}

#[test]
fn unusable_map_kd_is_a_warning_and_kd_stays() {
    let directory = tempfile::tempdir().unwrap();
    let folder = directory.path().join("scene");
    std::fs::create_dir(&folder).unwrap();
    // A real image, but outside the OBJ's folder.
    write_png(
        &directory.path().join("outside.png"),
        1,
        1,
        &[[1, 2, 3, 255]],
    );
    write(&folder, "not_png.png", "plain text");
    write(
        &folder,
        "t.mtl",
        "newmtl gone\nKd 0.5 0.5 0.5\nmap_Kd missing.png\n\
         newmtl escape\nKd 0.25 0.25 0.25\nmap_Kd ../outside.png\n\
         newmtl corrupt\nKd 1 0 0\nmap_Kd not_png.png\n",
    );
    let obj = write(
        &folder,
        "t.obj",
        "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl gone\nf 1/1 2/1 3/1\n\
         usemtl escape\nf 1 2 3\nusemtl corrupt\nf 1 2 3\n",
    );
    let scene = load_obj(&obj).unwrap();
    assert_eq!(scene.warnings.len(), 3, "{:?}", scene.warnings);
    let missing = &scene.warnings[0];
    assert!(
        missing.starts_with("material 'gone': map_Kd 'missing.png' is ignored (the material uses its Kd instead): cannot read '")
            && missing.contains("missing.png"),
        "{missing}"
    );
    assert_eq!(
        scene.warnings[1],
        "material 'escape': map_Kd '../outside.png' is ignored (the material uses its Kd \
         instead): it lies outside the OBJ file's folder, where vkpath does not read"
    );
    assert!(
        scene.warnings[2].contains("'not_png.png'"),
        "{}",
        scene.warnings[2]
    );
    let colors: Vec<Vec3> = scene.triangles.iter().map(|t| t.color).collect();
    assert_eq!(colors, [Vec3::splat(0.5), Vec3::splat(0.25), Vec3::X]);
    // Without its textures the scene is the workshop's again.
    assert!(scene.materials.is_none());
}

#[test]
fn corner_indices_out_of_range_are_errors() {
    let directory = tempfile::tempdir().unwrap();
    for (name, face, expected) in [
        (
            "n.obj",
            "f 1//2 2//1 3//1",
            tobj::LoadError::FaceNormalOutOfBounds,
        ),
        (
            "r.obj",
            "f 1//-2 2//1 3//1",
            tobj::LoadError::FaceNormalOutOfBounds,
        ),
        (
            "t.obj",
            "f 1/9223372036854775807 2/1 3/1",
            tobj::LoadError::FaceTexCoordOutOfBounds,
        ),
    ] {
        let obj = write(
            directory.path(),
            name,
            &format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n{face}\n"),
        );
        match load_obj(&obj) {
            Err(SceneError::Obj { error, .. }) => assert_eq!(error, expected, "{face}"),
            other => panic!("{face}: {other:?}"),
        }
    }
    // A line (two corners) is ignored, whatever its indices.
    let obj = write(
        directory.path(),
        "line.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//9 2//9\nf 1 2 3\n",
    );
    assert_eq!(load_obj(&obj).unwrap().triangles.len(), 1);
}

#[test]
fn errors_give_the_line_as_file_colon_line() {
    let directory = tempfile::tempdir().unwrap();
    let message = |name: &str, text: &str| {
        let path = write(directory.path(), name, text);
        let message = load_obj(&path).unwrap_err().to_string();
        let location = format!("{}:", path.display());
        message
            .split_once(&location)
            .map(|(_, rest)| rest.to_string())
            .unwrap_or(message)
    };
    let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\n# a comment\n";
    // tobj's parse errors, found at the line tobj stopped on.
    assert_eq!(
        message("position.obj", &format!("{cube}v 1 2 x\nf 1 2 3\n")),
        "5': position parse error"
    );
    assert_eq!(
        message("face.obj", &format!("{cube}f 1 2 3\nf 1 x 3\n")),
        "6': face parse error"
    );
    // Our own checks: indices out of range, before tobj's.
    assert_eq!(
        message("normal.obj", &format!("{cube}vn 0 0 1\nf 1//1 2//1 3//2\n")),
        "6': face normal index out of bounds"
    );
    assert_eq!(
        message("vertex.obj", &format!("{cube}f 1 2 3\nf 1 2 -4\n")),
        "6': face vertex index out of bounds"
    );
    // Bytes that are not UTF-8, on line 2.
    let path = directory.path().join("latin1.obj");
    std::fs::write(&path, b"v 0 0 0\n# caf\xe9\n").unwrap();
    let error = load_obj(&path).unwrap_err().to_string();
    assert!(error.ends_with("latin1.obj:2': read error"), "{error}");
    // A material library's errors give its own line.
    write(
        directory.path(),
        "bad.mtl",
        "newmtl red\nKd 1 0 0\n\nKd\nmap_Kd\n",
    );
    let error = message(
        "library.obj",
        &format!("mtllib bad.mtl\n{cube}usemtl red\nf 1 2 3\n"),
    );
    assert!(
        error.contains("bad.mtl:5': material parse error"),
        "{error}"
    );
}
