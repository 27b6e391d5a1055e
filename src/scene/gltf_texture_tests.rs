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

#[test]
fn a_specular_glossiness_material_loads_converted_and_without_warnings() {
    use glam::{Vec3, Vec4};
    // A 1 x 1 RGBA PNG: specular (51, 102, 153), glossiness 200 / 255
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, 1, 1);
        encoder.set_color(png::ColorType::Rgba);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&[51, 102, 153, 200]).unwrap();
    }
    let spec_gloss_png = format!("data:image/png;base64,{}", base64(&bytes));
    let name = "KHR_materials_pbrSpecularGlossiness";
    let mut buffer = TestBuffer::default();
    let positions = buffer.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let uv = buffer.floats("VEC2", &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    let material = |texture: bool| {
        let mut spec_gloss = json!({"diffuseFactor": [0.5, 0.25, 0.125, 1.0],
                                    "specularFactor": [1.0, 0.766, 0.336],
                                    "glossinessFactor": 0.75});
        if texture {
            spec_gloss["specularGlossinessTexture"] = json!({"index": 0});
            spec_gloss["diffuseTexture"] = json!({"index": 1});
        }
        json!({"pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": 0.2},
               "extensions": {name: spec_gloss}})
    };
    let text = buffer.embedded(json!({
        "extensionsUsed": [name],
        "extensionsRequired": [name],
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 1}],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": positions, "TEXCOORD_0": uv}, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": positions, "TEXCOORD_0": uv}, "material": 1}]}
        ],
        "materials": [material(false), material(true)],
        "textures": [{"source": 0}, {"source": 1}],
        "images": [{"uri": spec_gloss_png}, {"uri": grey_png()}],
    }));
    let directory = tempfile::tempdir().unwrap();
    let scene = load_gltf(&write(&directory, "spec_gloss.gltf", text)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let materials = scene.materials.expect("glTF materials");
    let [factors, textured] = [&materials.materials[0], &materials.materials[1]];
    // glTF-Transform's metalRough(): diffuse as the base colour, a dielectric of ior 1000
    // whose specular colour is the specular factor, roughness 1 - glossiness
    assert_eq!(factors.base_color, Vec4::new(0.5, 0.25, 0.125, 1.0));
    assert_eq!(
        (factors.metallic, factors.ior, factors.specular),
        (0.0, 1000.0, 1.0)
    );
    assert_eq!(factors.specular_color, Vec3::new(1.0, 0.766, 0.336));
    assert_eq!(factors.roughness, 0.25);
    assert!(factors.metallic_roughness_texture.is_none());
    // With the textures: roughness 1 times the texture made from glossiness, the
    // specular colour texture the specular-glossiness texture, the diffuse the base colour
    assert_eq!(textured.roughness, 1.0);
    let rough = textured
        .metallic_roughness_texture
        .expect("a roughness texture");
    // 255 - round(200 * 0.75)
    assert_eq!(
        materials.textures[rough.texture as usize].texels,
        [[0, 105, 0, 255]]
    );
    let specular = textured
        .specular_color_texture
        .expect("a specular colour texture");
    assert_eq!(
        materials.textures[specular.texture as usize].texels,
        [[51, 102, 153, 200]]
    );
    let base = textured.base_color_texture.expect("the diffuse texture");
    assert_eq!(
        materials.textures[base.texture as usize].texels,
        [[128, 128, 128, 255]]
    );
    assert!(textured.specular_texture.is_none());
}
