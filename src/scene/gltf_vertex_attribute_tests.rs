//! Tests of the glTF loader's extra vertex attributes (a child module of `gltf_loader`):
//! `COLOR_0` in every type glTF 2.0 allows (3.7.2.1), and the one-line error for the types
//! it forbids.

use glam::Vec4;
use serde_json::json;

use super::test_support::{write, TestBuffer};
use super::*;

/// A `.gltf` of one triangle whose COLOR_0 is the accessor `color` adds to `buffer` (which
/// holds nothing else yet).
fn triangle_with_colors(color: impl FnOnce(&mut TestBuffer) -> usize) -> String {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let colors = color(&mut buffer);
    buffer.embedded(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "m", "primitives": [
            {"attributes": {"POSITION": positions, "COLOR_0": colors}, "material": 0}
        ]}],
        "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0}}],
    }))
}

/// The vertex colours of the one triangle of `text`.
fn loaded_colors(text: String) -> [Vec4; 3] {
    let directory = tempfile::tempdir().unwrap();
    let scene = load_gltf(&write(&directory, "colors.gltf", text)).unwrap();
    let materials = scene.materials.expect("glTF materials");
    assert_eq!(materials.triangles.len(), 1);
    materials.extra.get(0).colors
}

#[test]
fn vertex_colors_are_read_as_float_and_normalized_integers() {
    // VEC3 of normalized bytes: alpha 1, 255 -> 1, 51 -> 0.2
    let bytes = [255u8, 0, 51, 0, 255, 0, 0, 0, 255];
    let colors = loaded_colors(triangle_with_colors(|b| {
        b.accessor("VEC3", 5121, true, 3, &bytes)
    }));
    assert!(
        colors[0].abs_diff_eq(Vec4::new(1.0, 0.0, 0.2, 1.0), 1e-6),
        "{}",
        colors[0]
    );
    assert_eq!(colors[2], Vec4::new(0.0, 0.0, 1.0, 1.0));
    // VEC4 of normalized shorts
    let shorts: Vec<u8> = [65535u16, 0, 0, 32768, 0, 65535, 0, 65535, 0, 0, 65535, 0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let colors = loaded_colors(triangle_with_colors(|b| {
        b.accessor("VEC4", 5123, true, 3, &shorts)
    }));
    assert_eq!(colors[0].x, 1.0);
    assert!((colors[0].w - 0.5).abs() < 1e-4, "{}", colors[0]);
    assert_eq!(colors[2], Vec4::new(0.0, 0.0, 1.0, 0.0));
    // VEC4 of floats
    let floats = [
        0.5, 0.25, 0.125, 0.75, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0,
    ];
    let colors = loaded_colors(triangle_with_colors(|b| b.floats("VEC4", &floats)));
    assert_eq!(colors[0], Vec4::new(0.5, 0.25, 0.125, 0.75));
    assert_eq!(colors[1], Vec4::ONE);
}

#[test]
fn a_triangle_without_vertex_colors_is_white() {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let text = buffer.embedded(json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0}}],
    }));
    let directory = tempfile::tempdir().unwrap();
    let scene = load_gltf(&write(&directory, "plain.gltf", text)).unwrap();
    let materials = scene.materials.expect("glTF materials");
    assert!(materials.extra.is_empty(), "{:?}", materials.extra);
    assert_eq!(materials.vertex_attributes(), 0);
}

#[test]
fn a_vertex_color_of_a_forbidden_type_is_one_line_naming_the_mesh() {
    let directory = tempfile::tempdir().unwrap();
    let bytes = [255u8; 9];
    let shorts = [0u8; 12];
    let forbidden = [
        // Bytes that are not normalized
        triangle_with_colors(|b| b.accessor("VEC3", 5121, false, 3, &bytes)),
        // Two components
        triangle_with_colors(|b| b.floats("VEC2", &[0.0; 6])),
        // Signed shorts
        triangle_with_colors(|b| b.accessor("VEC2", 5122, true, 3, &shorts)),
    ];
    for text in forbidden {
        let path = write(&directory, "bad.gltf", &text);
        let error = load_gltf(&path)
            .expect_err("a forbidden COLOR_0")
            .to_string();
        assert!(!error.contains('\n'), "{error}");
        assert!(error.contains("mesh 'm' primitive 0: COLOR_0"), "{error}");
        assert!(error.contains("glTF allows VEC3 or VEC4"), "{error}");
    }
    // One colour too few for the vertices
    let text = triangle_with_colors(|b| b.floats("VEC4", &[1.0; 8]));
    let error = load_gltf(&write(&directory, "short.gltf", &text))
        .expect_err("a short COLOR_0")
        .to_string();
    assert!(
        error.contains("COLOR_0 has 2 elements for 3 vertices"),
        "{error}"
    );
}

#[test]
fn a_mirroring_node_keeps_each_color_on_its_vertex() {
    // The node's scale -1 in x swaps corners 1 and 2 (gltf_mirror_tests); the colours go
    // with them.
    let floats = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0];
    let text = triangle_with_colors(|b| b.floats("VEC4", &floats)).replace(
        "\"nodes\":[{\"mesh\":0}]",
        "\"nodes\":[{\"mesh\":0,\"scale\":[-1,1,1]}]",
    );
    assert!(text.contains("\"scale\""), "the node was rewritten");
    let directory = tempfile::tempdir().unwrap();
    let scene = load_gltf(&write(&directory, "mirrored.gltf", text)).unwrap();
    let triangle = &scene.triangles[0];
    let colors = scene.materials.unwrap().extra.get(0).colors;
    // Vertex (0, 1, 0) is blue wherever it went
    let blue = triangle
        .positions
        .iter()
        .position(|p| p.y == 1.0)
        .expect("the top corner");
    assert_eq!(colors[blue], Vec4::new(0.0, 0.0, 1.0, 1.0));
}

/// A 1 x 1 white PNG as a data URI.
fn white_png() -> String {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, 1, 1);
        encoder.set_color(png::ColorType::Rgb);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&[255, 255, 255]).unwrap();
    }
    format!(
        "data:image/png;base64,{}",
        super::test_support::base64(&bytes)
    )
}

/// The materials of one triangle with TEXCOORD_0 and TEXCOORD_1 whose base colour texture
/// is `texture` (a texture info).
fn textured_triangle(texture: serde_json::Value) -> super::super::materials::SceneMaterials {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let uv_0 = buffer.floats("VEC2", &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    let uv_1 = buffer.floats("VEC2", &[0.5, 0.25, 0.75, 0.25, 0.5, 1.0]);
    let text = buffer.embedded(json!({
        "extensionsUsed": ["KHR_texture_transform"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions,
            "TEXCOORD_0": uv_0, "TEXCOORD_1": uv_1}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": texture}}],
        "textures": [{"source": 0}],
        "images": [{"uri": white_png()}],
    }));
    let directory = tempfile::tempdir().unwrap();
    let scene = load_gltf(&write(&directory, "uv.gltf", text)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    scene.materials.expect("glTF materials")
}

#[test]
fn tex_coord_1_is_kept_only_where_a_material_reads_it() {
    use crate::contract::VERTEX_ATTRIBUTE_TEX_COORD_1;
    use glam::Vec2;
    // On set 0 the file's TEXCOORD_1 is not read: no table, the layout of before
    let on_0 = textured_triangle(json!({"index": 0}));
    assert!(on_0.extra.is_empty(), "{:?}", on_0.extra);
    assert_eq!(on_0.vertex_attributes(), 0);
    let uv_1 = [
        Vec2::new(0.5, 0.25),
        Vec2::new(0.75, 0.25),
        Vec2::new(0.5, 1.0),
    ];
    // texCoord 1, and KHR_texture_transform's texCoord overriding a texCoord of 0
    for texture in [
        json!({"index": 0, "texCoord": 1}),
        json!({"index": 0, "texCoord": 0,
               "extensions": {"KHR_texture_transform": {"texCoord": 1}}}),
    ] {
        let on_1 = textured_triangle(texture.clone());
        let binding = on_1.materials[0].base_color_texture.expect("the texture");
        assert_eq!(binding.tex_coord, 1, "{texture}");
        assert_eq!(on_1.extra.get(0).tex_coords_1, uv_1, "{texture}");
        assert!(on_1.extra.colors.is_none());
        assert_eq!(on_1.vertex_attributes(), VERTEX_ATTRIBUTE_TEX_COORD_1);
    }
}
