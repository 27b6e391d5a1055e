//! glTF fidelity through the binary (issue 59): vertex colours (`COLOR_0`) multiplied into
//! the base colour. Each test writes a small .gltf (with its buffer beside it) and renders
//! a few pixels of it.

use std::path::Path;

use serde_json::{json, Value};

use crate::common::runs::{exr_pixels, render_small};

/// Writes a quad (x, y in [-1, 1], z = 0, facing +z) with `attributes` (name -> (glTF
/// type, component type, normalized, the four vertices' little-endian bytes)) beside its
/// POSITION, the material `material` and a camera at z = `camera_z` looking at it (towards
/// -z, or back at it from behind where `camera_z` < 0), as `name` in `dir`; its path.
fn quad(
    dir: &Path,
    name: &str,
    attributes: &[(&str, &str, u32, bool, Vec<u8>)],
    material: Value,
    camera_z: f32,
) -> String {
    let positions: Vec<f32> = vec![
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ];
    let mut bytes: Vec<u8> = positions.iter().flat_map(|x| x.to_le_bytes()).collect();
    let mut views = vec![json!({"buffer": 0, "byteOffset": 0, "byteLength": 48})];
    let mut accessors = vec![
        json!({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}),
    ];
    let mut primitive_attributes = json!({"POSITION": 0});
    for (semantic, kind, component_type, normalized, data) in attributes {
        while !bytes.len().is_multiple_of(4) {
            bytes.push(0);
        }
        views.push(json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": data.len()}));
        bytes.extend_from_slice(data);
        accessors.push(
            json!({"bufferView": views.len() - 1, "componentType": component_type,
                              "normalized": normalized, "count": 4, "type": kind}),
        );
        primitive_attributes[*semantic] = json!(accessors.len() - 1);
    }
    let indices: Vec<u8> = [0u16, 1, 2, 0, 2, 3]
        .iter()
        .flat_map(|i| i.to_le_bytes())
        .collect();
    views.push(json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": 12}));
    bytes.extend_from_slice(&indices);
    accessors.push(
        json!({"bufferView": views.len() - 1, "componentType": 5123, "count": 6, "type": "SCALAR"}),
    );
    // glTF cameras look along their node's -z: turned half round about y to look at +z
    let rotation = if camera_z < 0.0 {
        json!([0, 1, 0, 0])
    } else {
        json!([0, 0, 0, 1])
    };
    let document = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, camera_z], "rotation": rotation}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.01}}],
        "meshes": [{"name": "quad", "primitives": [{"attributes": primitive_attributes, "indices": accessors.len() - 1, "material": 0}]}],
        "materials": [material],
        "buffers": [{"byteLength": bytes.len(), "uri": format!("{name}.bin")}],
        "bufferViews": views,
        "accessors": accessors,
    });
    std::fs::write(dir.join(format!("{name}.bin")), bytes).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, document.to_string()).unwrap();
    path.display().to_string()
}

/// An unlit material (its radiance is its base colour, exactly) with `base_color`.
fn unlit(base_color: [f32; 4]) -> Value {
    json!({"pbrMetallicRoughness": {"baseColorFactor": base_color},
           "extensions": {"KHR_materials_unlit": {}}})
}

#[test]
fn vertex_colors_multiply_the_base_color() {
    let dir = tempfile::tempdir().unwrap();
    // Red on the left edge (x = -1), blue on the right, as normalized bytes (VEC3); the base
    // colour halves them.
    let colors = vec![255u8, 0, 0, 0, 0, 255, 0, 0, 255, 255, 0, 0];
    let scene = quad(
        dir.path(),
        "colors",
        &[("COLOR_0", "VEC3", 5121, true, colors)],
        unlit([0.5, 0.5, 0.5, 1.0]),
        2.0,
    );
    render_small(dir.path(), &scene, &[], "colors.exr", "4");
    let pixels = exr_pixels(dir.path(), "colors.exr");
    for (i, [r, g, b, _]) in pixels.iter().copied().enumerate() {
        // Interpolated linearly: red and blue always sum to the base colour's 0.5; no green
        assert!(
            (r + b - 0.5).abs() < 1e-4 && g == 0.0,
            "pixel {i}: {r} {g} {b}"
        );
    }
    // Left of the middle redder than blue, right of it bluer (row 1, columns 0 and 3)
    let [left, right] = [pixels[4], pixels[7]];
    assert!(left[0] > 0.3 && right[2] > 0.3, "{left:?} {right:?}");
}

#[test]
fn a_vertex_color_of_a_forbidden_type_is_one_line_naming_the_mesh() {
    let dir = tempfile::tempdir().unwrap();
    // Bytes that are not normalized: glTF forbids them for COLOR_0
    let scene = quad(
        dir.path(),
        "bytes",
        &[("COLOR_0", "VEC4", 5121, false, vec![255u8; 16])],
        unlit([1.0; 4]),
        2.0,
    );
    let run = crate::common::runs::run(dir.path(), &["render", &scene, "-o", "bytes.exr"], &[]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(
        lines[0].contains("mesh 'quad' primitive 0: COLOR_0"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("bytes.exr").exists());
}

/// A 2 x 2 RGB texture as a PNG data URI: red, green (top row), blue, white.
fn four_colour_png() -> String {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, 2, 2);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().unwrap();
        writer
            .write_image_data(&[255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255])
            .unwrap();
    }
    format!("data:image/png;base64,{}", base64::encode(&bytes))
}

/// Adds texture 0 (`four_colour_png`) to the glTF file at `path`.
fn add_texture(path: &str) {
    set_textures(
        path,
        json!([{"source": 0}]),
        json!([{"uri": four_colour_png()}]),
    );
}

/// Sets the `textures` and `images` of the glTF file at `path` (and the extensions it uses).
fn set_textures(path: &str, textures: Value, images: Value) {
    let mut document: Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    document["textures"] = textures;
    document["images"] = images;
    document["extensionsUsed"] = json!([
        "KHR_materials_unlit",
        "KHR_materials_emissive_strength",
        "EXT_texture_webp"
    ]);
    std::fs::write(path, document.to_string()).unwrap();
}

/// Four VEC2 float texture coordinates as a quad attribute's bytes.
fn uv_bytes(uv: [[f32; 2]; 4]) -> Vec<u8> {
    uv.iter().flatten().flat_map(|x| x.to_le_bytes()).collect()
}

#[test]
fn a_texture_on_tex_coord_1_renders_as_on_tex_coord_0_with_the_sets_swapped() {
    let dir = tempfile::tempdir().unwrap();
    // Two different mappings of the quad's corners
    let a = uv_bytes([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    let b = uv_bytes([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.25, 0.5]]);
    let mut images = Vec::new();
    for (set, first, second) in [(1, &a, &b), (0, &b, &a)] {
        // The base colour and an emissive texture (which used to be dropped with its
        // factor on TEXCOORD_1), 8 times as bright as any reflection under the white
        // background can be
        let info = json!({"index": 0, "texCoord": set});
        let material = json!({
            "pbrMetallicRoughness": {"baseColorTexture": info, "metallicFactor": 0},
            "emissiveFactor": [1, 1, 1], "emissiveTexture": info,
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8}}});
        let file = format!("set{set}");
        let scene = quad(
            dir.path(),
            &file,
            &[
                ("TEXCOORD_0", "VEC2", 5126, false, first.clone()),
                ("TEXCOORD_1", "VEC2", 5126, false, second.clone()),
            ],
            material,
            2.0,
        );
        add_texture(&scene);
        let output = format!("{file}.exr");
        render_small(dir.path(), &scene, &[], &output, "4");
        images.push(crate::common::runs::exr_bits(dir.path(), &output));
    }
    assert!(
        images[0] == images[1],
        "TEXCOORD_1 renders otherwise than TEXCOORD_0 with the sets swapped"
    );
    // The texture's texels sum to 1 or 3 over rgb, times 8; a reflection at most to ~3
    let pixels = exr_pixels(dir.path(), "set1.exr");
    let mean = pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / pixels.len() as f32;
    assert!(mean > 6.0, "the emissive texture does not light ({mean})");
}

#[test]
fn a_texture_on_a_missing_tex_coord_1_is_one_line_naming_the_primitive_material_and_slot() {
    let dir = tempfile::tempdir().unwrap();
    let mut material = unlit([1.0; 4]);
    material["name"] = json!("decal");
    material["emissiveTexture"] = json!({"index": 0, "texCoord": 1});
    let uv = uv_bytes([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    let scene = quad(
        dir.path(),
        "missing",
        &[("TEXCOORD_0", "VEC2", 5126, false, uv)],
        material,
        2.0,
    );
    add_texture(&scene);
    let run = crate::common::runs::run(dir.path(), &["render", &scene, "-o", "missing.exr"], &[]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{}", run.stderr);
    assert!(
        lines[0].contains("mesh 'quad' primitive 0: material 'decal' reads its emissiveTexture from TEXCOORD_1, which the primitive does not have"),
        "{}",
        run.stderr
    );
    assert!(!dir.path().join("missing.exr").exists());
}

#[test]
fn a_webp_texture_renders_as_the_same_png() {
    let dir = tempfile::tempdir().unwrap();
    // tests/data/four_colours.webp is four_colour_png's texels, lossless (cwebp -lossless
    // -exact); its fallback here is a black PNG, so an image equal to the PNG's is the WebP's
    let webp = std::fs::read(crate::common::fixture("four_colours.webp")).unwrap();
    let webp_uri = format!("data:image/webp;base64,{}", base64::encode(&webp));
    let black = {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, 1, 1);
        encoder.set_color(png::ColorType::Rgb);
        encoder
            .write_header()
            .unwrap()
            .write_image_data(&[0, 0, 0])
            .unwrap();
        format!("data:image/png;base64,{}", base64::encode(&bytes))
    };
    let uv = uv_bytes([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    let material = json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}},
                          "extensions": {"KHR_materials_unlit": {}}});
    let cases = [
        (
            "png",
            json!([{"source": 0}]),
            json!([{"uri": four_colour_png()}]),
        ),
        (
            "webp",
            json!([{"source": 0, "extensions": {"EXT_texture_webp": {"source": 1}}}]),
            json!([{"uri": black}, {"uri": webp_uri}]),
        ),
    ];
    let mut images = Vec::new();
    for (name, textures, image_list) in cases {
        let scene = quad(
            dir.path(),
            name,
            &[("TEXCOORD_0", "VEC2", 5126, false, uv.clone())],
            material.clone(),
            2.0,
        );
        set_textures(&scene, textures, image_list);
        let output = format!("{name}.exr");
        let run = render_small(dir.path(), &scene, &[], &output, "4");
        assert!(!run.stderr.contains("warning"), "{name}: {}", run.stderr);
        images.push(crate::common::runs::exr_bits(dir.path(), &output));
    }
    assert!(
        images[0] == images[1],
        "the WebP texture renders otherwise than its PNG"
    );
}
