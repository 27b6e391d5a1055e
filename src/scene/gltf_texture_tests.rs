//! Tests of the glTF loader's texture images (a child module of `gltf_loader`): WebP
//! through `EXT_texture_webp` and `KHR_texture_webp`, with and without a fallback `source`.

use serde_json::{json, Value};

use super::test_support::{base64, write, TestBuffer};
use super::*;

/// tests/data/four_colours.webp (`cwebp -lossless -exact` of a 2 x 2 PNG of red, green /
/// blue, white) as a data URI.
fn webp_uri() -> String {
    let bytes = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/four_colours.webp"
    ))
    .unwrap();
    format!("data:image/webp;base64,{}", base64(&bytes))
}

/// A 1 x 1 grey PNG as a data URI.
fn grey_png() -> String {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, 1, 1);
        encoder.set_color(png::ColorType::Rgb);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&[128, 128, 128]).unwrap();
    }
    format!("data:image/png;base64,{}", base64(&bytes))
}

/// The scene of one triangle whose base colour texture is texture 0 of `more` (which
/// holds `textures`, `images` and the extensions).
fn textured_scene(more: Value) -> Scene {
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let uv = buffer.floats("VEC2", &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    let mut document = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": positions, "TEXCOORD_0": uv},
                                    "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
    });
    for (key, value) in more.as_object().unwrap() {
        document[key] = value.clone();
    }
    let directory = tempfile::tempdir().unwrap();
    load_gltf(&write(&directory, "webp.gltf", buffer.embedded(document))).unwrap()
}

/// The texels of the scene's one texture (None without one).
fn texels(scene: &Scene) -> Option<Vec<[u8; 4]>> {
    let materials = scene.materials.as_ref()?;
    let binding = materials.materials[0].base_color_texture?;
    Some(materials.textures[binding.texture as usize].texels.clone())
}

const FOUR_COLOURS: [[u8; 4]; 4] = [
    [255, 0, 0, 255],
    [0, 255, 0, 255],
    [0, 0, 255, 255],
    [255, 255, 255, 255],
];

#[test]
fn a_required_webp_texture_without_a_source_loads_without_warnings() {
    for name in ["EXT_texture_webp", "KHR_texture_webp"] {
        let scene = textured_scene(json!({
            "extensionsUsed": [name],
            "extensionsRequired": [name],
            "textures": [{"extensions": {name: {"source": 0}}}],
            "images": [{"uri": webp_uri()}],
        }));
        assert!(scene.warnings.is_empty(), "{name}: {:?}", scene.warnings);
        assert_eq!(texels(&scene).as_deref(), Some(&FOUR_COLOURS[..]), "{name}");
    }
}

#[test]
fn a_corrupt_webp_image_is_one_line_naming_it_and_its_fallback_is_used() {
    let corrupt = format!(
        "data:image/webp;base64,{}",
        base64(b"RIFF\x10\x00\x00\x00WEBPVP8 ")
    );
    // With a fallback source: the fallback's texels, and a warning naming the WebP image
    let scene = textured_scene(json!({
        "extensionsUsed": ["EXT_texture_webp"],
        "textures": [{"source": 0, "extensions": {"EXT_texture_webp": {"source": 1}}}],
        "images": [{"uri": grey_png()}, {"name": "broken", "uri": corrupt}],
    }));
    assert_eq!(texels(&scene), Some(vec![[128, 128, 128, 255]]));
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    let warning = &scene.warnings[0];
    assert!(
        warning.starts_with(
            "texture '#0': its WebP image cannot be used (image 'broken': corrupt WebP texture"
        ) && warning.ends_with("so its fallback image '#0' is used"),
        "{warning}"
    );
    assert_eq!(warning.lines().count(), 1);
    // Without one: the texture is ignored, the warning names the image
    let scene = textured_scene(json!({
        "extensionsUsed": ["EXT_texture_webp"],
        "extensionsRequired": ["EXT_texture_webp"],
        "textures": [{"extensions": {"EXT_texture_webp": {"source": 0}}}],
        "images": [{"name": "broken", "uri": format!("data:image/webp;base64,{}", base64(b"RIFF\x10\x00\x00\x00WEBPVP8 "))}],
    }));
    assert_eq!(texels(&scene), None);
    assert!(
        scene.warnings.iter().any(|w| w.starts_with(
            "texture '#0' is ignored (the material uses its factor instead): image 'broken': corrupt WebP texture"
        ) && w.lines().count() == 1),
        "{:?}",
        scene.warnings
    );
}
