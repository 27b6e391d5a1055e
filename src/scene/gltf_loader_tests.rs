//! Tests of the glTF loader (a child module of `gltf_loader`, in its own file for size): glTF
//! files are written by hand into a temporary directory, with the expected world-space values
//! worked out in the comments rather than by the code under test.

use std::path::PathBuf;

use glam::Vec2;
use serde_json::{json, Value};

use super::test_support::{project, write, TestBuffer};
use super::*;
use crate::scene::gltf_extensions::supported_extensions;
use crate::scene::materials::Transmission;
use crate::scene::Triangle;

/// sin 45° = cos 45°: quaternions of quarter turns.
const S: f32 = std::f32::consts::FRAC_1_SQRT_2;

fn assert_close(actual: Vec3, expected: Vec3) {
    assert!(actual.abs_diff_eq(expected, 1e-5), "{actual} != {expected}");
}

fn assert_positions(triangle: &Triangle, expected: [[f32; 3]; 3]) {
    for (actual, expected) in triangle.positions.iter().zip(expected) {
        assert_close(*actual, Vec3::from(expected));
    }
}

/// A hierarchy with every feature the loader handles, and the buffer it needs:
/// - "parent": T (1, 2, 3), R 90° about +Y ((x, y, z) -> (z, y, -x)), S 2; child "child":
///   T (0.5, 0, 0), R 90° about +Z ((x, y, z) -> (-y, x, z)), S (3, 1, 1), with the indexed
///   unit quad (u16 indices) in the z = 0 plane and material "glow";
/// - "mirror": a matrix that mirrors x and moves by (0, 0, -5), with a non-indexed triangle
///   and no material;
/// - "rig": T (10, 0, 0), R 90° about +Y, S 2; child "eye": T (0, 1, 0) with the camera.
fn hierarchy(buffer: &mut TestBuffer) -> Value {
    let quad = buffer.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let quad_indices = buffer.indices(&[0, 1, 2, 0, 2, 3]);
    let triangle = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    json!({
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0, 2, 3]}],
        "nodes": [
            {"name": "parent", "translation": [1, 2, 3], "rotation": [0, S, 0, S],
             "scale": [2, 2, 2], "children": [1]},
            {"name": "child", "translation": [0.5, 0, 0], "rotation": [0, 0, S, S],
             "scale": [3, 1, 1], "mesh": 0},
            {"name": "mirror", "mesh": 1,
             "matrix": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1]},
            {"name": "rig", "translation": [10, 0, 0], "rotation": [0, S, 0, S],
             "scale": [2, 2, 2], "children": [4]},
            {"name": "eye", "translation": [0, 1, 0], "camera": 0},
        ],
        "meshes": [
            {"name": "quad",
             "primitives": [{"attributes": {"POSITION": quad}, "indices": quad_indices,
                             "material": 0}]},
            {"name": "triangle", "primitives": [{"attributes": {"POSITION": triangle}}]},
        ],
        "materials": [{
            "name": "glow",
            "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1.5, 0.5]},
            "emissiveFactor": [1, 0.5, 0.25],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
            "doubleSided": true,
        }],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
    })
}

/// Checks the scene of [`hierarchy`].
fn assert_hierarchy(scene: &Scene) {
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.triangles.len(), 3);
    // Quad corner (1, 1, 0): child S -> (3, 1, 0), R -> (-1, 3, 0), T -> (-0.5, 3, 0);
    // parent R -> (0, 3, 0.5), S -> (0, 6, 1), T -> (1, 8, 4). Likewise for the others.
    // Object +z maps to world +x (R_z keeps z, R_y turns z into x).
    let quad = &scene.triangles[..2];
    assert_positions(
        &quad[0],
        [[1.0, 2.0, 2.0], [1.0, 8.0, 2.0], [1.0, 8.0, 4.0]],
    );
    assert_positions(
        &quad[1],
        [[1.0, 2.0, 2.0], [1.0, 8.0, 4.0], [1.0, 2.0, 4.0]],
    );
    for triangle in quad {
        assert_close(triangle.normal, Vec3::X);
        // baseColorFactor's blue 1.5 is clamped to 1; alpha is ignored.
        assert_eq!(triangle.color, Vec3::new(0.5, 0.25, 1.0));
        // emissiveFactor (1, 0.5, 0.25) times emissiveStrength 4.
        assert_eq!(triangle.emission, Vec3::new(4.0, 2.0, 1.0));
        assert!(triangle.double_sided);
    }
    // The mirrored triangle: (0,0,0), (1,0,0), (0,1,0) -> (0,0,-5), (-1,0,-5), (0,1,-5),
    // which is clockwise seen from +z; the loader swaps two vertices so that the normal stays
    // +z (the mirror in x does not move the z axis).
    let mirrored = &scene.triangles[2];
    assert_positions(
        mirrored,
        [[0.0, 0.0, -5.0], [0.0, 1.0, -5.0], [-1.0, 0.0, -5.0]],
    );
    assert_close(mirrored.normal, Vec3::Z);
    // No material: glTF's default, white and not emissive.
    assert_eq!(mirrored.color, Vec3::ONE);
    assert_eq!(mirrored.emission, Vec3::ZERO);
    assert!(!mirrored.double_sided);

    // The eye sits at rig T + S * R(0, 1, 0) = (10, 2, 0), looks along R(-z) = -x with +y up,
    // so +y is up in the image and -z is to the right. yfov = 0.8.
    let camera = scene.camera.expect("the scene has a camera");
    assert_close(camera.position, Vec3::new(10.0, 2.0, 0.0));
    let tan = 0.4f32.tan();
    let pixel = |point: Vec3| project(&camera, 200.0, 100.0, point);
    // Straight ahead: the image centre.
    assert!(pixel(Vec3::new(5.0, 2.0, 0.0)).abs_diff_eq(Vec2::new(100.0, 50.0), 1e-3));
    // yfov / 2 above the view axis: the top edge.
    assert!(pixel(Vec3::new(5.0, 2.0 + 5.0 * tan, 0.0)).abs_diff_eq(Vec2::new(100.0, 0.0), 1e-3));
    // At aspect 2 the right edge is 2 tan(yfov / 2) to the side per unit distance.
    let right_edge = Vec3::new(5.0, 2.0, -10.0 * tan);
    assert!(pixel(right_edge).abs_diff_eq(Vec2::new(200.0, 50.0), 1e-3));
    // Half-way down and half-way to the left edge, 10 m away.
    let point = Vec3::new(0.0, 2.0 - 5.0 * tan, 10.0 * tan);
    assert!(
        pixel(point).abs_diff_eq(Vec2::new(50.0, 75.0), 1e-3),
        "{}",
        pixel(point)
    );
}

#[test]
fn hierarchy_materials_and_camera_from_gltf_with_data_uri() {
    let directory = tempfile::tempdir().unwrap();
    let mut buffer = TestBuffer::default();
    let rest = hierarchy(&mut buffer);
    let path = write(&directory, "scene.gltf", buffer.embedded(rest));
    assert_hierarchy(&load_gltf(&path).unwrap());
}

#[test]
fn hierarchy_from_glb() {
    let directory = tempfile::tempdir().unwrap();
    let mut buffer = TestBuffer::default();
    let rest = hierarchy(&mut buffer);
    let path = write(&directory, "scene.glb", buffer.glb(rest));
    assert_hierarchy(&Scene::load(&path).unwrap());
}

#[test]
fn hierarchy_with_external_buffer() {
    let directory = tempfile::tempdir().unwrap();
    let mut buffer = TestBuffer::default();
    let rest = hierarchy(&mut buffer);
    write(&directory, "scene.bin", &buffer.bytes);
    let document = buffer.document(Some("scene.bin".into()), rest);
    let path = write(&directory, "scene.gltf", document.to_string());
    assert_hierarchy(&load_gltf(&path).unwrap());
}

/// A `.gltf` whose one node holds mesh 'm' with the one `primitive`, reading `buffer`.
fn single_primitive(buffer: &TestBuffer, primitive: Value) -> String {
    buffer.embedded(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "m", "primitives": [primitive]}],
    }))
}

#[test]
fn strips_and_fans_become_counter_clockwise_triangles() {
    let directory = tempfile::tempdir().unwrap();
    // A unit square listed as a zig-zag (strip) and around its border (fan).
    let strip = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let fan = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    for (mode, points) in [(5, strip), (6, fan)] {
        let mut buffer = TestBuffer::default();
        let positions = buffer.positions(&points);
        let text = single_primitive(
            &buffer,
            json!({"attributes": {"POSITION": positions}, "mode": mode}),
        );
        let scene = load_gltf(&write(&directory, "s.gltf", text)).unwrap();
        assert_eq!(scene.triangles.len(), 2, "mode {mode}");
        for triangle in &scene.triangles {
            assert_eq!(triangle.normal, Vec3::Z, "mode {mode}");
        }
        let area: f32 = scene
            .triangles
            .iter()
            .map(|t| {
                0.5 * (t.positions[1] - t.positions[0])
                    .cross(t.positions[2] - t.positions[0])
                    .length()
            })
            .sum();
        assert_eq!(area, 1.0, "mode {mode}");
    }
}

#[test]
fn degenerate_triangles_are_dropped_with_a_warning() {
    let directory = tempfile::tempdir().unwrap();
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
    ]);
    // The second triangle has three collinear corners.
    let indices = buffer.indices(&[0, 1, 2, 0, 1, 3]);
    let primitive = json!({"attributes": {"POSITION": positions}, "indices": indices});
    let path = write(&directory, "s.gltf", single_primitive(&buffer, primitive));
    let scene = load_gltf(&path).unwrap();
    assert_eq!(scene.triangles.len(), 1);
    assert_eq!(
        scene.warnings,
        vec!["dropped 1 degenerate triangles".to_owned()]
    );
    assert!(scene.camera.is_none());
}

/// A 2x1 RGBA PNG (red, then half-transparent green) as a data URI.
fn two_texel_png_uri() -> String {
    let image = image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, 255, 0, 255, 0, 128]).unwrap();
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .unwrap();
    format!(
        "data:image/png;base64,{}",
        super::test_support::base64(&bytes)
    )
}

/// One triangle with `material` and the given extra attributes, as a .gltf text.
fn triangle_with(material: Value, extra: &[(&str, Value)], more: Value) -> String {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let mut attributes = json!({"POSITION": positions});
    for (name, value) in extra {
        let accessor = match *name {
            "NORMAL" => buffer.floats(
                "VEC3",
                &serde_json::from_value::<Vec<f32>>(value.clone()).unwrap(),
            ),
            "TEXCOORD_0" => buffer.floats(
                "VEC2",
                &serde_json::from_value::<Vec<f32>>(value.clone()).unwrap(),
            ),
            _ => buffer.floats(
                "VEC4",
                &serde_json::from_value::<Vec<f32>>(value.clone()).unwrap(),
            ),
        };
        attributes[*name] = json!(accessor);
    }
    let mut document = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "material": 0}]}],
        "materials": [material],
    });
    if let (Some(target), Some(extra)) = (document.as_object_mut(), more.as_object()) {
        for (key, value) in extra {
            target.insert(key.clone(), value.clone());
        }
    }
    buffer.embedded(document)
}

#[test]
fn a_missing_image_is_ignored_once_with_a_warning_and_the_factor_stays() {
    let directory = tempfile::tempdir().unwrap();
    let material = json!({"name": "brick",
                          "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1.0, 1.0],
                                                   "baseColorTexture": {"index": 0}},
                          "normalTexture": {"index": 0}});
    let text = triangle_with(
        material,
        &[],
        json!({
            "textures": [{"source": 0}],
            "images": [{"uri": "not_loaded.png"}],
        }),
    );
    let scene = load_gltf(&write(&directory, "s.gltf", text)).unwrap();
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(
        scene.warnings[0].starts_with(
            "texture '#0' is ignored (the material uses its factor instead): image '#0': cannot read '"
        ) && scene.warnings[0].contains("not_loaded.png': No such file or directory"),
        "{}",
        scene.warnings[0]
    );
    // glTF's default metallic factor (1) makes it a metal: the materials stay.
    let materials = scene.materials.expect("a metal needs materials");
    let brick = materials.materials[0];
    assert_eq!(brick.base_color, glam::Vec4::new(0.5, 0.25, 1.0, 1.0));
    assert_eq!((brick.metallic, brick.roughness), (1.0, 1.0));
    assert!(brick.base_color_texture.is_none() && brick.normal_texture.is_none());
    assert!(materials.textures.is_empty());
}

#[test]
fn explicit_lambertian_materials_render_with_the_workshop_kernels() {
    let directory = tempfile::tempdir().unwrap();
    let lambertian = json!({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0], "metallicFactor": 0.0},
                            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}});
    // Flat vertex normals (the face's) change nothing either.
    let flat = [("NORMAL", json!([0, 0, 1, 0, 0, 1, 0, 0, 1]))];
    let scene = load_gltf(&write(
        &directory,
        "a.gltf",
        triangle_with(lambertian.clone(), &flat, json!({})),
    ))
    .unwrap();
    assert!(scene.materials.is_none());
    assert_eq!(scene.triangles[0].color, Vec3::splat(0.5));
    // Smooth normals need the materials kernels.
    let bent = [("NORMAL", json!([0, 0, 1, 0.6, 0, 0.8, 0, 0, 1]))];
    let scene = load_gltf(&write(
        &directory,
        "b.gltf",
        triangle_with(lambertian, &bent, json!({})),
    ))
    .unwrap();
    let materials = scene.materials.expect("smooth normals");
    assert_close(materials.triangles[0].normals[1], Vec3::new(0.6, 0.0, 0.8));
    // Without the specular extension a dielectric has glTF's specular lobe.
    let plastic = json!({"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.25}});
    let scene = load_gltf(&write(
        &directory,
        "c.gltf",
        triangle_with(plastic, &[], json!({})),
    ))
    .unwrap();
    let material = scene.materials.expect("specular lobe").materials[0];
    assert_eq!(
        (
            material.metallic,
            material.roughness,
            material.specular,
            material.ior
        ),
        (0.0, 0.25, 1.0, 1.5)
    );
}

#[test]
fn textures_transforms_and_extensions_are_read() {
    let directory = tempfile::tempdir().unwrap();
    let material = json!({
        "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2]}}},
            "metallicFactor": 0.0
        },
        "alphaMode": "MASK", "alphaCutoff": 0.25,
        "extensions": {"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.5, 0.25]},
                       "KHR_materials_ior": {"ior": 1.33}}
    });
    let uv = [("TEXCOORD_0", json!([0, 0, 1, 0, 0, 1]))];
    let text = triangle_with(
        material,
        &uv,
        json!({
            "extensionsUsed": ["KHR_texture_transform", "KHR_materials_specular", "KHR_materials_ior"],
            "samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33648}],
            "textures": [{"source": 0, "sampler": 0}],
            "images": [{"uri": two_texel_png_uri()}],
        }),
    );
    let scene = load_gltf(&write(&directory, "t.gltf", text)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let materials = scene.materials.expect("textured");
    let material = materials.materials[0];
    assert_eq!(
        material.alpha_mode,
        crate::scene::materials::AlphaMode::Mask { cutoff: 0.25 }
    );
    assert_eq!((material.specular, material.ior), (0.5, 1.33));
    assert_eq!(material.specular_color, Vec3::new(1.0, 0.5, 0.25));
    let binding = material.base_color_texture.expect("base colour texture");
    // Translation (0.5, 0) after scale 2: u' = 2 u + 0.5.
    assert_eq!(binding.transform.matrix, [[2.0, 0.0, 0.5], [0.0, 2.0, 0.0]]);
    let texture = &materials.textures[binding.texture as usize];
    assert_eq!((texture.width, texture.height), (2, 1));
    assert_eq!(texture.texels, vec![[255, 0, 0, 255], [0, 255, 0, 128]]);
    use crate::scene::textures::WrapMode;
    assert_eq!(
        (texture.wrap_s, texture.wrap_t, texture.nearest),
        (WrapMode::ClampToEdge, WrapMode::MirroredRepeat, true)
    );
    assert_eq!(
        materials.triangles[0].tex_coords,
        [Vec2::ZERO, Vec2::X, Vec2::Y]
    );
}

#[test]
fn volume_scatter_is_read_inside_a_volume_only() {
    // KHR_materials_volume_scatter: sigma_t of the volume's attenuation splits into
    // sigma_s = sigma_t rho_ss (the draft's albedo of multiscatterColor) and sigma_a; without
    // KHR_materials_volume it is ignored (the draft needs a volume)
    let directory = tempfile::tempdir().unwrap();
    let material = |with_volume: bool| {
        let mut extensions = json!({
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_volume_scatter": {"multiscatterColor": [1.0, 0.5, 0.0], "scatterAnisotropy": 0.7}
        });
        if with_volume {
            extensions["KHR_materials_volume"] = json!({"thicknessFactor": 1.0,
                "attenuationColor": [0.5, 0.5, 0.25], "attenuationDistance": 2.0});
        }
        json!({"pbrMetallicRoughness": {"metallicFactor": 0.0}, "extensions": extensions})
    };
    let more = json!({"extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume",
                                         "KHR_materials_volume_scatter"]});
    let load = |with_volume: bool, name: &str| {
        let text = triangle_with(material(with_volume), &[], more.clone());
        let scene = load_gltf(&write(&directory, name, text)).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        scene.materials.expect("layered")
    };
    let materials = load(true, "scatter.gltf");
    let transmission = materials.materials[0].transmission;
    let extinction = Transmission::attenuation_coefficient(Vec3::new(0.5, 0.5, 0.25), 2.0);
    let albedo = Transmission::single_scatter_albedo(Vec3::new(1.0, 0.5, 0.0));
    assert_eq!(albedo.x, 1.0);
    assert_eq!(albedo.z, 0.0);
    assert_eq!(transmission.scattering, extinction * albedo);
    assert_eq!(transmission.attenuation, extinction - extinction * albedo);
    assert_eq!(transmission.anisotropy, 0.7);
    assert!(materials.uses_volume_scatter());
    let without_volume = load(false, "no-volume.gltf");
    let transmission = without_volume.materials[0].transmission;
    assert_eq!(
        (transmission.scattering, transmission.anisotropy),
        (Vec3::ZERO, 0.0)
    );
    assert!(!without_volume.uses_volume_scatter());
}

#[test]
fn transmission_volume_clearcoat_unlit_and_specular_textures_are_read() {
    let directory = tempfile::tempdir().unwrap();
    let texture = |index: u32| json!({"index": index});
    let materials = json!([
        {
            "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.2},
            "extensions": {
                "KHR_materials_transmission": {"transmissionFactor": 0.9, "transmissionTexture": texture(0)},
                "KHR_materials_volume": {"thicknessFactor": 0.5, "thicknessTexture": texture(0),
                                         "attenuationColor": [0.5, 1.0, 0.25], "attenuationDistance": 2.0},
                "KHR_materials_ior": {"ior": 1.45},
                "KHR_materials_clearcoat": {"clearcoatFactor": 0.75, "clearcoatRoughnessFactor": 0.1,
                    "clearcoatTexture": texture(0), "clearcoatRoughnessTexture": texture(0),
                    "clearcoatNormalTexture": {"index": 0, "scale": 0.5,
                        "extensions": {"KHR_texture_transform": {"scale": [3, 3]}}}},
                "KHR_materials_specular": {"specularFactor": 0.8, "specularTexture": texture(0),
                                           "specularColorTexture": texture(0)}
            }
        }
    ]);
    let uv = [("TEXCOORD_0", json!([0, 0, 1, 0, 0, 1]))];
    let more = json!({
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
                           "KHR_materials_clearcoat", "KHR_materials_specular", "KHR_texture_transform"],
        "textures": [{"source": 0}],
        "images": [{"uri": two_texel_png_uri()}],
    });
    let text = triangle_with(materials[0].clone(), &uv, more);
    let scene = load_gltf(&write(&directory, "glass.gltf", text)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let materials = scene.materials.expect("layered");
    let material = materials.materials[0];
    assert!(material.is_layered() && materials.uses_layers());
    let transmission = material.transmission;
    assert_eq!((transmission.factor, transmission.thickness), (0.9, 0.5));
    assert!(transmission.texture.is_some() && transmission.thickness_texture.is_some());
    let expected = Transmission::attenuation_coefficient(Vec3::new(0.5, 1.0, 0.25), 2.0);
    assert_eq!(transmission.attenuation, expected);
    assert_eq!(material.ior, 1.45);
    let clearcoat = material.clearcoat;
    assert_eq!(
        (
            clearcoat.factor,
            clearcoat.roughness,
            clearcoat.normal_scale
        ),
        (0.75, 0.1, 0.5)
    );
    assert!(clearcoat.texture.is_some() && clearcoat.roughness_texture.is_some());
    let normal = clearcoat.normal_texture.expect("clear coat normal texture");
    assert_eq!(normal.transform.matrix, [[3.0, 0.0, 0.0], [0.0, 3.0, 0.0]]);
    assert_eq!(material.specular, 0.8);
    assert!(material.specular_texture.is_some() && material.specular_color_texture.is_some());
    // One decoded texture, shared by every slot.
    assert_eq!(materials.textures.len(), 1);
}

#[test]
fn unlit_materials_keep_their_colour_and_lose_their_emission() {
    let directory = tempfile::tempdir().unwrap();
    let material = json!({
        "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]},
        "emissiveFactor": [1.0, 1.0, 1.0],
        "extensions": {"KHR_materials_unlit": {}}
    });
    let text = triangle_with(
        material,
        &[],
        json!({"extensionsUsed": ["KHR_materials_unlit"]}),
    );
    let scene = load_gltf(&write(&directory, "unlit.gltf", text)).unwrap();
    let materials = scene.materials.expect("unlit is not plain");
    let material = materials.materials[0];
    assert!(material.unlit && materials.uses_layers());
    assert_eq!(material.emission, Vec3::ZERO);
    assert_eq!(material.base_color, glam::Vec4::new(0.2, 0.4, 0.6, 1.0));
}

#[test]
fn sheen_is_read_with_its_textures() {
    let directory = tempfile::tempdir().unwrap();
    let material = json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.5, 0.25],
            "sheenColorTexture": {"index": 0}, "sheenRoughnessFactor": 0.3,
            "sheenRoughnessTexture": {"index": 0}}}
    });
    let text = triangle_with(
        material,
        &[("TEXCOORD_0", json!([0, 0, 1, 0, 0, 1]))],
        json!({"extensionsUsed": ["KHR_materials_sheen"],
               "textures": [{"source": 0}], "images": [{"uri": two_texel_png_uri()}]}),
    );
    let scene = load_gltf(&write(&directory, "sheen.gltf", text)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let material = scene.materials.unwrap().materials[0];
    assert_eq!(material.sheen.color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(material.sheen.roughness, 0.3);
    assert!(material.sheen.color_texture.is_some() && material.sheen.roughness_texture.is_some());
    assert!(material.is_layered());
}

/// A clear-coat texture reference naming no texture of the file is a warning, not a panic.
#[test]
fn a_clearcoat_texture_that_names_no_texture_is_ignored_with_a_warning() {
    let directory = tempfile::tempdir().unwrap();
    let material = json!({
        "pbrMetallicRoughness": {"metallicFactor": 0.0},
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatTexture": {"index": 7}}}
    });
    let text = triangle_with(
        material,
        &[],
        json!({"extensionsUsed": ["KHR_materials_clearcoat"]}),
    );
    let scene = load_gltf(&write(&directory, "coat.gltf", text)).unwrap();
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("clearcoatTexture names no texture")),
        "{:?}",
        scene.warnings
    );
    let material = scene.materials.unwrap().materials[0];
    assert_eq!(material.clearcoat.factor, 1.0);
    assert!(material.clearcoat.texture.is_none());
}

/// Loads `text` as a .gltf and returns the error's message.
fn error_of(text: &str) -> String {
    let directory = tempfile::tempdir().unwrap();
    let path = write(&directory, "bad.gltf", text);
    let error = load_gltf(&path).expect_err("the file should be refused");
    let message = error.to_string();
    assert!(
        message.contains("bad.gltf"),
        "the message names the file: {message}"
    );
    message
}

#[test]
fn a_normal_map_without_tangents_gets_mikktspace_tangents() {
    let directory = tempfile::tempdir().unwrap();
    let material = json!({"normalTexture": {"index": 0, "scale": 0.5}});
    let attributes = [
        ("NORMAL", json!([0, 0, 1, 0, 0, 1, 0, 0, 1])),
        ("TEXCOORD_0", json!([0, 1, 1, 1, 0, 0])),
    ];
    let text = triangle_with(
        material,
        &attributes,
        json!({
            "textures": [{"source": 0}],
            "images": [{"uri": two_texel_png_uri()}],
        }),
    );
    let scene = load_gltf(&write(&directory, "n.gltf", text)).unwrap();
    let materials = scene.materials.expect("normal map");
    assert_eq!(materials.materials[0].normal_scale, 0.5);
    // u grows along +x, v (downwards in the image) along -y, so the image's top is +y:
    // tangent +x and bitangent +y = (n x t) w, w = +1.
    for tangent in materials.triangles[0].tangents {
        assert!(
            (tangent.truncate() - Vec3::X).length() < 1e-5 && tangent.w == 1.0,
            "{tangent}"
        );
    }
}

#[test]
fn missing_file_is_an_error() {
    let error = load_gltf(Path::new("no/such/scene.gltf")).unwrap_err();
    assert_eq!(
        error.to_string(),
        "cannot read scene 'no/such/scene.gltf': No such file or directory"
    );
}

#[test]
fn malformed_json_is_an_error() {
    let message = error_of("{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
    assert!(message.starts_with("malformed glTF '"), "{message}");
}

#[test]
fn lines_alone_leave_no_triangles_and_say_why() {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
    let text = single_primitive(
        &buffer,
        json!({"attributes": {"POSITION": positions}, "mode": 1}),
    );
    let message = error_of(&text);
    assert!(
        message.ends_with(
            "contains no triangles (mesh 'm' primitive 0 is Lines, skipped (only triangles are rendered))"
        ),
        "{message}"
    );
}

#[test]
fn a_scene_without_triangles_is_an_error() {
    let text = TestBuffer::default().embedded(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"camera": 0}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.1}}],
    }));
    assert!(error_of(&text).ends_with("' contains no triangles"));
}

#[test]
fn an_orthographic_camera_is_an_error() {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let text = buffer.embedded(json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions}}]}],
        "cameras": [{"name": "top", "type": "orthographic",
                     "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}],
    }));
    assert!(error_of(&text)
        .ends_with(": camera 'top' is orthographic; only perspective cameras are supported"));
}

/// Broken files that the `gltf` crate would panic on if we did not check them first.
#[test]
fn broken_files_are_errors_not_panics() {
    let triangle = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&triangle);

    // An index past the last vertex.
    let mut indexed = TestBuffer::default();
    let (p, i) = (indexed.positions(&triangle), indexed.indices(&[0, 1, 7]));
    let message = error_of(&single_primitive(
        &indexed,
        json!({"attributes": {"POSITION": p}, "indices": i}),
    ));
    assert!(
        message.ends_with("mesh 'm' primitive 0: index 7 is out of range (3 vertices)"),
        "{message}"
    );

    // A POSITION accessor that does not exist.
    let message = error_of(&single_primitive(
        &buffer,
        json!({"attributes": {"POSITION": 9}}),
    ));
    assert!(
        message.contains("accessor 9, which does not exist"),
        "{message}"
    );

    // Accessors whose data is not what POSITION needs, or lies past the buffer's end.
    for (field, value, expected) in [
        ("type", json!("VEC2"), "holds Vec2 of F32"),
        ("count", json!(0), "empty or impossible byte layout"),
        ("count", json!(4), "data lies outside its buffer"),
        (
            "byteOffset",
            json!(u64::MAX - 8),
            "empty or impossible byte layout",
        ),
    ] {
        let mut document: Value = serde_json::from_str(&single_primitive(
            &buffer,
            json!({"attributes": {"POSITION": positions}}),
        ))
        .unwrap();
        document["accessors"][0][field] = value;
        let message = error_of(&document.to_string());
        assert!(message.contains(expected), "{field}: {message}");
    }

    // Float indices would reach an `unreachable!` in the crate's index reader.
    let mut document: Value = serde_json::from_str(&single_primitive(
        &indexed,
        json!({"attributes": {"POSITION": 0}, "indices": 1}),
    ))
    .unwrap();
    document["accessors"][1]["componentType"] = json!(5126);
    assert!(error_of(&document.to_string()).contains("indices accessor '#1' holds Scalar of F32"));

    // A camera whose type names parameters it does not have.
    let text = buffer.embedded(json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions}}]}],
        "cameras": [{"type": "perspective",
                     "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}],
    }));
    assert!(error_of(&text).contains("camera '#0' is unusable"));

    // A node that is its own child.
    let text = buffer.embedded(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "children": [0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions}}]}],
    }));
    assert!(error_of(&text).contains("node '#0' is reached twice"));

    // A GLB header whose length is shorter than the header.
    let mut glb = buffer.glb(json!({}));
    glb[8..12].copy_from_slice(&4u32.to_le_bytes());
    let directory = tempfile::tempdir().unwrap();
    let error = load_gltf(&write(&directory, "bad.glb", glb)).unwrap_err();
    assert!(
        error.to_string().contains("GLB header declares 4 bytes"),
        "{error}"
    );
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

#[test]
fn emissive_quad_fixture_is_a_lit_box_with_a_camera() {
    let scene = Scene::load(&fixture("emissive_quad.gltf")).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // Five walls and the light, two triangles each.
    assert_eq!(scene.triangles.len(), 12);
    let lights: Vec<_> = scene
        .triangles
        .iter()
        .filter(|t| t.emission != Vec3::ZERO)
        .collect();
    assert_eq!(lights.len(), 2);
    for light in lights {
        assert_eq!(light.emission, Vec3::splat(8.0));
        assert_eq!(light.normal, Vec3::NEG_Y);
        assert!(light.positions.iter().all(|p| p.y == 0.99));
    }
    for wall in scene.triangles.iter().filter(|t| t.emission == Vec3::ZERO) {
        let centre = (wall.positions[0] + wall.positions[1] + wall.positions[2]) / 3.0;
        assert!(wall.normal.dot(-centre) > 0.0, "walls face into the box");
    }
    // The camera at (0, 0, 3.5) looks down -z into the box's open side.
    let camera = scene.camera.unwrap();
    assert_eq!(camera.position, Vec3::new(0.0, 0.0, 3.5));
    let centre = project(&camera, 64.0, 64.0, Vec3::new(0.0, 0.0, -1.0));
    assert!(centre.abs_diff_eq(Vec2::splat(32.0), 1e-3));
}

#[test]
fn lines_fixture_is_refused() {
    let error = Scene::load(&fixture("lines.gltf")).unwrap_err();
    assert!(matches!(error, SceneError::NoTriangles { .. }), "{error}");
}

#[test]
fn malformed_fixture_is_refused() {
    let error = Scene::load(&fixture("malformed.gltf")).unwrap_err();
    assert!(matches!(error, SceneError::Gltf { .. }), "{error}");
}

/// A triangle on node "mover" whose translation is animated LINEAR from (0, 0, 0) at 1 s to
/// (4, 0, 0) at 3 s (animation "slide"), and a node "turner" that animation "spin" turns
/// STEP to 90° about +Y at 2 s; `times` and `translations` replace slide's keys.
fn animated(times: &[f32], translations: &[f32]) -> String {
    let mut buffer = TestBuffer::default();
    let triangle = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let input = buffer.floats("SCALAR", times);
    let output = buffer.floats("VEC3", translations);
    let spin_input = buffer.floats("SCALAR", &[0.0, 2.0]);
    let spin_output = buffer.floats("VEC4", &[0.0, 0.0, 0.0, 1.0, 0.0, S, 0.0, S]);
    buffer.embedded(json!({
        "nodes": [
            {"name": "mover", "mesh": 0},
            {"name": "turner", "mesh": 0, "translation": [0, 0, -5]},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": triangle}}]}],
        "animations": [
            {"name": "slide",
             "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
             "samplers": [{"input": input, "output": output}]},
            {"name": "spin",
             "channels": [{"sampler": 0, "target": {"node": 1, "path": "rotation"}}],
             "samplers": [{"input": spin_input, "output": spin_output,
                           "interpolation": "STEP"}]},
        ],
    }))
}

fn load_at(path: &std::path::Path, time: f32, pick: AnimationPick) -> Result<Scene, SceneError> {
    load_gltf_with(
        path,
        &LoadOptions {
            time,
            animation: pick,
            ..LoadOptions::default()
        },
    )
}

use crate::scene::animation::AnimationPick;

#[test]
fn animated_nodes_move_with_time() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        &dir,
        "animated.gltf",
        animated(&[1.0, 3.0], &[0.0, 0.0, 0.0, 4.0, 0.0, 0.0]),
    );
    let first = |time, pick| load_at(&path, time, pick).unwrap().triangles[0].positions[0];
    // Before the first key the first key holds; halfway (2 s) x is 2; after the last, 4.
    assert_close(first(0.0, AnimationPick::All), Vec3::ZERO);
    assert_close(first(2.0, AnimationPick::All), Vec3::new(2.0, 0.0, 0.0));
    assert_close(first(7.0, AnimationPick::All), Vec3::new(4.0, 0.0, 0.0));
    // "spin" alone leaves "mover" where the file puts it.
    let spin = AnimationPick::One("spin".into());
    assert_close(first(2.0, spin.clone()), Vec3::ZERO);
    // The turned triangle at 2 s: (1, 0, 0) -> (0, 0, -1), then moved to z = -5.
    let turned = load_at(&path, 2.0, AnimationPick::One("1".into())).unwrap();
    assert_close(turned.triangles[1].positions[1], Vec3::new(0.0, 0.0, -6.0));
    let before = load_at(&path, 1.9, spin).unwrap();
    assert_close(before.triangles[1].positions[1], Vec3::new(1.0, 0.0, -5.0));
    let missing = load_at(&path, 0.0, AnimationPick::One("jump".into())).unwrap_err();
    assert!(missing.to_string().contains("slide, spin"), "{missing}");
}

#[test]
fn bad_animation_data_names_the_animation_and_accessor() {
    let dir = tempfile::tempdir().unwrap();
    let decreasing = write(
        &dir,
        "decreasing.gltf",
        animated(&[3.0, 1.0], &[0.0, 0.0, 0.0, 4.0, 0.0, 0.0]),
    );
    let error = load_at(&decreasing, 0.0, AnimationPick::All)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("animation 'slide'") && error.contains("accessor '#1'"),
        "{error}"
    );
    assert!(error.contains("not above the one before"), "{error}");
    let short = write(&dir, "short.gltf", animated(&[1.0, 3.0], &[0.0, 0.0, 0.0]));
    let error = load_at(&short, 0.0, AnimationPick::All)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("animation 'slide'") && error.contains("accessor '#2'"),
        "{error}"
    );
    assert!(!error.contains('\n'), "{error}");
}

/// A triangle with one morph target that lifts every vertex by 2 along +Z; the mesh's
/// default weight is 1, node 1 overrides it with 0.25, and animation "breathe" drives node 0's
/// weight LINEAR from 0 at 0 s to 1 at 2 s (`weight_keys` replaces its output).
fn morphed(weight_keys: &[f32]) -> String {
    let mut buffer = TestBuffer::default();
    let triangle = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let delta = buffer.positions(&[[0.0, 0.0, 2.0], [0.0, 0.0, 2.0], [0.0, 0.0, 2.0]]);
    let input = buffer.floats("SCALAR", &[0.0, 2.0]);
    let output = buffer.floats("SCALAR", weight_keys);
    buffer.embedded(json!({
        "nodes": [{"mesh": 0}, {"mesh": 0, "weights": [0.25]}, {"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": triangle},
                                    "targets": [{"POSITION": delta}]}],
                    "weights": [1.0]}],
        "animations": [{"name": "breathe",
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}],
            "samplers": [{"input": input, "output": output}]}],
    }))
}

#[test]
fn morph_targets_take_animated_node_and_mesh_weights() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "morph.gltf", morphed(&[0.0, 1.0]));
    let z = |time: f32, node: usize| {
        let scene = load_at(&path, time, AnimationPick::All).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        scene.triangles[node].positions[0].z
    };
    // Node 0 animated: weight 0, 0.5, 1 at 0, 1, 2 s; node 1 its own 0.25; node 2 the mesh's 1.
    assert_eq!([z(0.0, 0), z(1.0, 0), z(2.0, 0)], [0.0, 1.0, 2.0]);
    assert_eq!(z(1.0, 1), 0.5);
    assert_eq!(z(1.0, 2), 2.0);
    // One weight per key is needed; two per key is one too many.
    let bad = write(&dir, "bad.gltf", morphed(&[0.0, 1.0, 0.0, 1.0]));
    let error = load_at(&bad, 0.0, AnimationPick::All)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("animation 'breathe'") && error.contains("accessor '#3'"),
        "{error}"
    );
    assert!(error.contains("1 morph targets per key"), "{error}");
}

/// A strip of two quads along +X (x = 0, 1, 2), the mesh of node "strip" (translated by
/// (5, 0, 0), which skinning ignores) with skin "arm": joint 0 "shoulder" at the origin and its
/// child joint 1 "elbow" at (1, 0, 0), turned a quarter turn about +Z. Vertices at x = 0 follow
/// the shoulder, (1, 0) half each, (1, 1) 3/4 the shoulder, at x = 2 the elbow. `joints_of_last` and `weights_of_last`
/// are the last vertex's (elbow only); `inverse_binds` the number of inverse bind matrices; `with_joints` whether
/// the primitive has JOINTS_0 and WEIGHTS_0.
fn skinned(
    joints_of_last: [u16; 4],
    weights_of_last: [f32; 4],
    inverse_binds: usize,
    with_joints: bool,
) -> String {
    let mut buffer = TestBuffer::default();
    let strip = buffer.positions(&[
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
    ]);
    let indices = buffer.indices(&[0, 2, 1, 1, 2, 3, 2, 4, 3, 3, 4, 5]);
    let joints = buffer.joints(&[
        [0, 0, 0, 0],
        [0, 0, 0, 0],
        [0, 1, 0, 0],
        [0, 1, 0, 0],
        [1, 0, 0, 0],
        joints_of_last,
    ]);
    let mut weights = vec![
        1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.75, 0.25, 0.0, 0.0, 1.0, 0.0,
        0.0, 0.0,
    ];
    weights.extend(weights_of_last);
    let weights = buffer.floats("VEC4", &weights);
    let inverse: Vec<f32> = [Mat4::IDENTITY, Mat4::from_translation(-Vec3::X)]
        .iter()
        .cycle()
        .take(inverse_binds)
        .flat_map(|m| m.to_cols_array())
        .collect();
    let inverse = buffer.floats("MAT4", &inverse);
    let mut attributes = json!({"POSITION": strip});
    if with_joints {
        attributes["JOINTS_0"] = json!(joints);
        attributes["WEIGHTS_0"] = json!(weights);
    }
    buffer.embedded(json!({
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "strip", "mesh": 0, "skin": 0, "translation": [5, 0, 0]},
            {"name": "shoulder", "children": [2]},
            {"name": "elbow", "translation": [1, 0, 0], "rotation": [0, 0, S, S]},
        ],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": indices}]}],
        "skins": [{"name": "arm", "joints": [1, 2], "inverseBindMatrices": inverse}],
    }))
}

/// All of a vertex's weight on its first joint.
const ELBOW: [f32; 4] = [1.0, 0.0, 0.0, 0.0];

#[test]
fn a_skinned_strip_bends_at_its_elbow() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "skin.gltf", skinned([1, 0, 0, 0], ELBOW, 2, true));
    let scene = load_gltf(&path).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let corners: Vec<Vec3> = scene.triangles.iter().flat_map(|t| t.positions).collect();
    let has = |p: Vec3| corners.iter().any(|c| (*c - p).length() < 1e-5);
    // x = 0 stays, and (1, 0) at the elbow; (1, 1) 3/4 of the way from (0, 0) (the elbow's
    // turn) to itself: (0.75, 0.75);
    // (2, 0) -> (1, 1) and (2, 1) -> (0, 1) around the elbow at (1, 0); the node's
    // translation by 5 ignored.
    for p in [
        Vec3::ZERO,
        Vec3::Y,
        Vec3::X,
        Vec3::new(0.75, 0.75, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
    ] {
        assert!(has(p), "{p} not among {corners:?}");
    }
    assert!(corners.iter().all(|c| c.x < 1.5), "{corners:?}");
}

#[test]
fn broken_skins_name_the_skin_and_the_accessor() {
    let dir = tempfile::tempdir().unwrap();
    let error = |name: &str, text: String| {
        let error = load_gltf(&write(&dir, name, text)).unwrap_err().to_string();
        assert!(!error.contains('\n'), "{error}");
        assert!(error.contains("skin 'arm'"), "{error}");
        error
    };
    let past = error("past.gltf", skinned([2, 0, 0, 0], ELBOW, 2, true));
    assert!(
        past.contains("JOINTS_0 accessor '#2'") && past.contains("joint 2"),
        "{past}"
    );
    let count = error("count.gltf", skinned([1, 0, 0, 0], ELBOW, 1, true));
    assert!(
        count.contains("inverseBindMatrices accessor '#4' holds 1 matrices for 2 joints"),
        "{count}"
    );
    let bare = error("bare.gltf", skinned([1, 0, 0, 0], ELBOW, 2, false));
    assert!(bare.contains("no JOINTS_0"), "{bare}");
}

#[test]
fn a_skin_with_more_inverse_bind_matrices_than_joints_takes_the_first() {
    // glTF 2.0: inverseBindMatrices holds at least one matrix per joint (issue 58: three
    // for two joints was refused)
    let dir = tempfile::tempdir().unwrap();
    let positions = |inverse_binds| {
        let text = skinned([1, 0, 0, 0], ELBOW, inverse_binds, true);
        let name = format!("{inverse_binds}.gltf");
        let scene = load_gltf(&write(&dir, &name, text)).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        scene
            .triangles
            .iter()
            .map(|t| t.positions)
            .collect::<Vec<_>>()
    };
    assert_eq!(positions(3), positions(2));
    assert_eq!(positions(5), positions(2));
}

/// A triangle whose node turns about +Z by the rotation keys `keys` (LINEAR, at 0 s and
/// 1 s), with `rest` added to the document's animation (more channels and samplers).
fn turning_triangle(keys: [[f32; 4]; 2], extra_channels: Value, extensions_used: Value) -> String {
    let mut buffer = TestBuffer::default();
    let triangle = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let input = buffer.floats("SCALAR", &[0.0, 1.0]);
    let output = buffer.floats("VEC4", &keys.concat());
    let factor = buffer.floats("VEC4", &[1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0]);
    let mut channels = vec![json!({"sampler": 0, "target": {"node": 0, "path": "rotation"}})];
    channels.extend(extra_channels.as_array().cloned().unwrap_or_default());
    buffer.embedded(json!({
        "extensionsUsed": extensions_used,
        "nodes": [{"mesh": 0}],
        "materials": [{}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": triangle}, "material": 0}]}],
        "animations": [{
            "name": "turn",
            "channels": channels,
            "samplers": [{"input": input, "output": output}, {"input": input, "output": factor}],
        }],
    }))
}

/// The second corner ((1, 0, 0) unposed) of the triangle, posed at `time`.
fn second_corner(path: &std::path::Path, time: f32) -> Vec3 {
    let options = LoadOptions {
        time,
        ..LoadOptions::default()
    };
    load_gltf_with(path, &options).unwrap().triangles[0].positions[1]
}

#[test]
fn animation_pointer_channels_are_skipped_with_one_warning() {
    // KHR_animation_pointer: a channel without a node, targeting a material's factor. It
    // was "malformed ... missing field `node`" (issue 58); the node channel still plays.
    let dir = tempfile::tempdir().unwrap();
    let turn = [[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, S, S]];
    let pointer = json!([{"sampler": 1, "target": {"path": "pointer", "extensions": {
        "KHR_animation_pointer": {"pointer": "/materials/0/pbrMetallicRoughness/baseColorFactor"}}}}]);
    for (name, used) in [
        ("named.gltf", json!(["KHR_animation_pointer"])),
        ("bare.gltf", json!([])),
    ] {
        let path = write(&dir, name, turning_triangle(turn, pointer.clone(), used));
        let scene = load_gltf(&path).unwrap();
        assert_eq!(scene.warnings.len(), 1, "{name}: {:?}", scene.warnings);
        let warning = &scene.warnings[0];
        assert!(warning.contains("KHR_animation_pointer"), "{warning}");
        if name == "bare.gltf" {
            assert!(
                warning.contains("/materials/0/pbrMetallicRoughness/baseColorFactor"),
                "{warning}"
            );
        }
        // The node's own channel plays: (1, 0, 0) turned a quarter about +Z at 1 s
        assert!((second_corner(&path, 1.0) - Vec3::Y).length() < 1e-5);
    }
    // The same in a GLB
    let mut buffer = TestBuffer::default();
    let triangle = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let input = buffer.floats("SCALAR", &[0.0, 1.0]);
    let fov = buffer.floats("SCALAR", &[0.5, 0.9]);
    let glb = buffer.glb(json!({
        "extensionsUsed": ["KHR_animation_pointer"],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": triangle}}]}],
        "animations": [{"channels": [{"sampler": 0, "target": {"path": "pointer", "extensions": {
            "KHR_animation_pointer": {"pointer": "/cameras/0/perspective/yfov"}}}}],
            "samplers": [{"input": input, "output": fov}]}],
    }));
    let scene = load_gltf(&write(&dir, "pointer.glb", glb)).unwrap();
    assert_eq!(scene.triangles.len(), 1);
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
}

#[test]
fn rotation_keys_that_are_no_rotations_warn_once() {
    let dir = tempfile::tempdir().unwrap();
    let turned = [0.0, 0.0, S, S];
    let load = |name: &str, keys: [[f32; 4]; 2]| {
        let path = write(&dir, name, turning_triangle(keys, json!([]), json!([])));
        let scene = load_gltf(&path).unwrap();
        (path, scene.warnings)
    };
    // NaN, zero: no rotation, said once for the file
    for (name, bad) in [
        ("nan.gltf", [f32::NAN, 0.0, 0.0, 1.0]),
        ("zero.gltf", [0.0; 4]),
    ] {
        let (path, warnings) = load(name, [bad, bad]);
        assert_eq!(warnings.len(), 1, "{name}: {warnings:?}");
        assert!(
            warnings[0].contains("2 are NaN, infinite or of length 0"),
            "{}",
            warnings[0]
        );
        assert!(
            warnings[0].contains("animation 'turn' channel 0"),
            "{}",
            warnings[0]
        );
        assert!(
            (second_corner(&path, 1.0) - Vec3::X).length() < 1e-6,
            "{name}"
        );
    }
    // Too long to normalise in floats (its squared length overflows): still the rotation
    let (path, warnings) = load(
        "huge.gltf",
        [[0.0, 0.0, 0.0, 1.0], turned.map(|v| v * 1e30)],
    );
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("scaled first"), "{}", warnings[0]);
    assert!((second_corner(&path, 1.0) - Vec3::Y).length() < 1e-5);
    // Unit keys: no warning
    let (_, warnings) = load("unit.gltf", [[0.0, 0.0, 0.0, 1.0], turned]);
    assert!(warnings.is_empty(), "{warnings:?}");
}

#[test]
fn joint_weights_not_summing_to_one_are_normalised_with_one_warning() {
    // The last vertex's weights are (1, 1): normalised to half and half, it lands between
    // (2, 1) about the shoulder (unmoved) and about the elbow ((0, 1)): at (1, 1).
    let dir = tempfile::tempdir().unwrap();
    let text = skinned([0, 1, 0, 0], [1.0, 1.0, 0.0, 0.0], 2, true);
    let scene = load_gltf(&write(&dir, "sum.gltf", text)).unwrap();
    let warnings: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("do not sum to 1"))
        .collect();
    assert_eq!(warnings.len(), 1, "{:?}", scene.warnings);
    assert!(warnings[0].contains("1 vertices"), "{warnings:?}");
}

#[test]
fn an_animated_camera_node_moves_the_camera() {
    // The camera node slides CUBICSPLINE from z = 2 at 0 s to z = 6 at 2 s with zero
    // tangents: at 1 s (s = 1/2) the Hermite basis gives 2 + (6 - 2) * 1/2 = 4.
    let mut buffer = TestBuffer::default();
    let triangle = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let input = buffer.floats("SCALAR", &[0.0, 2.0]);
    let zero = [0.0; 3];
    let keys: Vec<f32> = [zero, [0.0, 0.0, 2.0], zero, zero, [0.0, 0.0, 6.0], zero]
        .into_iter()
        .flatten()
        .collect();
    let output = buffer.floats("VEC3", &keys);
    let text = buffer.embedded(json!({
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 9]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": triangle}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "animations": [{
            "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
            "samplers": [{"input": input, "output": output, "interpolation": "CUBICSPLINE"}],
        }],
    }));
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "camera.gltf", text);
    let camera_at = |time| {
        load_at(&path, time, AnimationPick::All)
            .unwrap()
            .camera
            .unwrap()
            .position
    };
    assert_close(camera_at(0.0), Vec3::new(0.0, 0.0, 2.0));
    assert_close(camera_at(1.0), Vec3::new(0.0, 0.0, 4.0));
    assert_close(camera_at(5.0), Vec3::new(0.0, 0.0, 6.0));
}

#[test]
fn a_channel_on_a_missing_node_or_unknown_path_is_one_line() {
    // The gltf crate validates neither and unwraps both (the loaders' fuzzer found it).
    let dir = tempfile::tempdir().unwrap();
    let text = animated(&[1.0, 3.0], &[0.0, 0.0, 0.0, 4.0, 0.0, 0.0]);
    assert!(text.contains(r#""node":1,"path":"rotation""#), "{text}");
    for (name, broken, expected) in [
        (
            "node.gltf",
            r#""node":9,"path":"rotation""#,
            "targets node 9",
        ),
        (
            "path.gltf",
            r#""node":1,"path":"spin""#,
            "unknown target path",
        ),
    ] {
        let path = write(
            &dir,
            name,
            text.replace(r#""node":1,"path":"rotation""#, broken),
        );
        let error = load_at(&path, 0.0, AnimationPick::All)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("animation 'spin' channel 0") && error.contains(expected),
            "{error}"
        );
    }
}

/// A mesh under a chain of 100,000 nodes (issue 58: 0.45 s at 444540f, still loading after
/// 300 s at 2d68d8d, the pose's world matrices climbing each node's whole chain): the root
/// moves by -99,999 in x and every node under it by +1, so the triangle lands where its
/// vertices say, exactly (whole numbers below 2^24 are exact in f32). Loading is linear in the
/// nodes and uses no recursion; were either to return, this test would take minutes or
/// overflow the stack.
#[test]
fn a_mesh_under_a_chain_of_100000_nodes_loads() {
    const DEPTH: usize = 100_000;
    let directory = tempfile::tempdir().unwrap();
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let nodes: Vec<Value> = (0..DEPTH)
        .map(|i| {
            let x = if i == 0 { -(DEPTH as f32 - 1.0) } else { 1.0 };
            match i + 1 < DEPTH {
                true => json!({"translation": [x, 0.0, 0.0], "children": [i + 1]}),
                false => json!({"translation": [x, 0.0, 0.0], "mesh": 0}),
            }
        })
        .collect();
    let text = buffer.embedded(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": nodes,
        "meshes": [{"name": "m", "primitives": [{"attributes": {"POSITION": positions}}]}],
    }));
    let scene = load_gltf(&write(&directory, "chain.gltf", text)).unwrap();
    assert_eq!(scene.triangles.len(), 1);
    assert_eq!(
        scene.triangles[0].positions,
        [Vec3::ZERO, Vec3::X, Vec3::Y],
        "the chain's translations sum to 0"
    );
}

#[test]
fn a_file_that_requires_extensions_vkpath_implements_loads_and_others_are_named() {
    // The gltf crate's validation refused every required name outside its own features,
    // clearcoat, sheen, specular, volume and mesh quantization among them (issue 59).
    let directory = tempfile::tempdir().unwrap();
    let names = supported_extensions();
    assert!(names.len() >= 11, "{names:?}");
    for name in names {
        let text = triangle_with(
            json!({}),
            &[],
            json!({"extensionsUsed": [name], "extensionsRequired": [name]}),
        );
        let path = write(&directory, "required.gltf", &text);
        if let Err(error) = load_gltf(&path) {
            panic!("a file requiring {name} is refused: {error}");
        }
    }
    let both = ["KHR_materials_sheen", "KHR_draco_mesh_compression"];
    let text = triangle_with(
        json!({}),
        &[],
        json!({"extensionsUsed": both, "extensionsRequired": both}),
    );
    let message = error_of(&text);
    assert!(
        message.contains("KHR_draco_mesh_compression") && !message.contains("KHR_materials_sheen"),
        "{message}"
    );
}

#[test]
fn an_emissive_texture_that_cannot_be_used_takes_its_factor_with_it() {
    // Khronos' MultiUVTest: an emissive factor of 1 scales a texture on TEXCOORD_1; without
    // the texture the factor alone lit the whole cube white.
    let directory = tempfile::tempdir().unwrap();
    let glowing = |texture: Value| {
        let material = json!({"name": "glow", "emissiveFactor": [1.0, 1.0, 1.0],
                              "emissiveTexture": texture});
        let text = triangle_with(
            material,
            &[],
            json!({"textures": [{"source": 0}], "images": [{"uri": "not_loaded.png"}]}),
        );
        load_gltf(&write(&directory, "glow.gltf", text)).unwrap()
    };
    for texture in [json!({"index": 0, "texCoord": 1}), json!({"index": 0})] {
        let scene = glowing(texture.clone());
        let emission: Vec<Vec3> = scene.triangles.iter().map(|t| t.emission).collect();
        assert_eq!(emission, [Vec3::ZERO], "{texture}");
        assert!(
            scene.warnings.iter().any(|w| w.contains(
                "material 'glow': its emissiveTexture cannot be used, so it emits nothing"
            )),
            "{:?}",
            scene.warnings
        );
    }
}

/// A triangle whose primitive takes material 0 (red) and, in KHR_materials_variants'
/// "Beach", material 1 (blue), in "Midnight" material `midnight`.
fn variant_triangle(midnight: usize) -> String {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let lambert = |rgb: [f32; 3]| {
        json!({"pbrMetallicRoughness": {"baseColorFactor": [rgb[0], rgb[1], rgb[2], 1.0],
                                        "metallicFactor": 0.0}})
    };
    buffer.embedded(json!({
        "extensionsUsed": ["KHR_materials_variants"],
        "extensions": {"KHR_materials_variants": {"variants": [{"name": "Beach"}, {"name": "Midnight"}]}},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": positions},
            "material": 0,
            "extensions": {"KHR_materials_variants": {"mappings": [
                {"material": 1, "variants": [0]},
                {"material": midnight, "variants": [1]},
            ]}},
        }]}],
        "materials": [lambert([0.8, 0.1, 0.1]), lambert([0.1, 0.1, 0.8]), lambert([0.1, 0.8, 0.1])],
    }))
}

#[test]
fn a_material_variant_is_rendered_by_name_and_an_unknown_one_lists_the_files() {
    let directory = tempfile::tempdir().unwrap();
    let path = write(&directory, "shoe.gltf", variant_triangle(2));
    let colour_of = |variant: Option<&str>| {
        let options = LoadOptions {
            variant: variant.map(str::to_owned),
            ..LoadOptions::default()
        };
        let scene = load_gltf_with(&path, &options).unwrap();
        (scene.triangles[0].color, scene.warnings)
    };
    let (own, warnings) = colour_of(None);
    assert_eq!(own, Vec3::new(0.8, 0.1, 0.1));
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("material variants (Beach, Midnight)")),
        "{warnings:?}"
    );
    let (beach, warnings) = colour_of(Some("Beach"));
    assert_eq!(beach, Vec3::new(0.1, 0.1, 0.8));
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(colour_of(Some("Midnight")).0, Vec3::new(0.1, 0.8, 0.1));
    let file = GltfFile::open(&path, &LoadOptions::default()).unwrap();
    assert_eq!(file.variant_names(), ["Beach", "Midnight"]);
    let unknown = LoadOptions {
        variant: Some("Street".into()),
        ..LoadOptions::default()
    };
    let Err(error) = GltfFile::open(&path, &unknown) else {
        panic!("an unknown variant should be refused");
    };
    let message = error.to_string();
    assert!(
        message.contains("has no material variant 'Street' (its variants: Beach, Midnight)"),
        "{message}"
    );
    let broken = write(&directory, "broken.gltf", variant_triangle(9));
    let options = LoadOptions {
        variant: Some("Midnight".into()),
        ..LoadOptions::default()
    };
    let message = load_gltf_with(&broken, &options).unwrap_err().to_string();
    assert!(
        message.contains("mesh '#0' primitive 0: its KHR_materials_variants mapping for variant 1 names no material"),
        "{message}"
    );
}
