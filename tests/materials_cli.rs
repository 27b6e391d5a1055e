//! Bad textures through the binary: an image that cannot be used is a one-line warning and
//! the render goes on with the material's factor; a texture index out of range is a one-line
//! error; the showcase scene renders without warnings.

use crate::common;

use std::path::Path;

use serde_json::json;

/// base64 of `bytes` (the standard alphabet, padded).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut text = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let bits = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for i in 0..4 {
            text.push(if i <= chunk.len() {
                ALPHABET[(bits >> (18 - 6 * i) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    text
}

/// CRC-32 (ISO-HDLC, PNG's), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A textured quad in front of an emitter, with the texture's image given by `image`, as
/// a .gltf in `dir`.
fn textured_quad(dir: &Path, name: &str, image: serde_json::Value, texture_index: usize) -> String {
    let positions: Vec<f32> = vec![
        -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
    ];
    let uvs: Vec<f32> = vec![0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let indices: Vec<u16> = vec![0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = positions
        .iter()
        .chain(&uvs)
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let document = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": texture_index}, "metallicFactor": 0},
                       "emissiveFactor": [1, 1, 1], "doubleSided": true}],
        "textures": [{"source": 0}],
        "images": [image],
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&bytes))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let path = dir.join(name);
    std::fs::write(&path, document.to_string()).unwrap();
    path.display().to_string()
}

fn render(dir: &Path, scene: &str) -> std::process::Output {
    common::vkpath(
        dir,
        &[
            "render",
            "--integrator",
            "workshop",
            scene,
            "-o",
            "out.exr",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "2",
            "--validate",
        ],
    )
}

#[test]
fn unusable_textures_are_warnings_and_the_render_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    // A valid PNG header chunk claiming 100000 x 100000 texels, then nothing.
    let mut chunk = b"IHDR".to_vec();
    chunk.extend_from_slice(&100_000u32.to_be_bytes());
    chunk.extend_from_slice(&100_000u32.to_be_bytes());
    chunk.extend_from_slice(&[8, 6, 0, 0, 0]);
    let mut huge = b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0d".to_vec();
    huge.extend_from_slice(&chunk);
    huge.extend_from_slice(&crc32(&chunk).to_be_bytes());
    for name in [b"IDAT", b"IEND"] {
        huge.extend_from_slice(&[0, 0, 0, 0]);
        huge.extend_from_slice(name);
        huge.extend_from_slice(&crc32(name).to_be_bytes());
    }
    let cases = [
        (
            "missing",
            json!({"uri": "no_such_file.png"}),
            "no_such_file.png",
        ),
        (
            "corrupt",
            json!({"uri": format!("data:image/png;base64,{}", base64(b"\x89PNG\r\n\x1a\nnot really"))}),
            "corrupt PNG texture",
        ),
        (
            "webp",
            json!({"uri": format!("data:image/webp;base64,{}", base64(b"RIFF\x10\x00\x00\x00WEBPVP8 "))}),
            "image '#0': corrupt WebP texture",
        ),
        (
            "huge",
            json!({"uri": format!("data:image/png;base64,{}", base64(&huge))}),
            "too large",
        ),
    ];
    for (name, image, expected) in cases {
        let scene = textured_quad(dir.path(), &format!("{name}.gltf"), image, 0);
        let output = render(dir.path(), &scene);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{name}: {stderr}");
        let warning = stderr
            .lines()
            .find(|line| line.contains("texture '#0' is ignored"))
            .unwrap_or_else(|| panic!("{name}: no warning in {stderr}"));
        assert!(warning.contains(expected), "{name}: {warning}");
        assert!(dir.path().join("out.exr").exists());
        std::fs::remove_file(dir.path().join("out.exr")).unwrap();
    }
}

#[test]
fn a_texture_index_out_of_range_is_one_line_and_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let scene = textured_quad(dir.path(), "bad.gltf", json!({"uri": "x.png"}), 7);
    let output = render(dir.path(), &scene);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let error: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(error.len(), 1, "{stderr}");
    assert!(error[0].contains("bad.gltf"), "{stderr}");
}

#[test]
fn the_showcase_scene_renders_without_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!("{}/scenes/materials.gltf", env!("CARGO_MANIFEST_DIR"));
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            &scene,
            "-o",
            "out.png",
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "1",
            "--integrator",
            "mis",
            "--validate",
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
}

/// The channel names of an EXR's first layer, and one channel's values.
fn exr_channel(path: &Path, name: &str) -> (Vec<String>, Vec<f32>) {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    let layer = &image.layer_data[0];
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    let values = layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == name)
        .map(|c| c.sample_data.values_as_f32().collect())
        .unwrap_or_default();
    (names, values)
}

#[test]
fn aovs_and_denoising_are_written_as_layers() {
    let dir = tempfile::tempdir().unwrap();
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            "--integrator",
            "workshop",
            "-o",
            "out.exr",
            "--width",
            "32",
            "--height",
            "32",
            "--spp",
            "16",
            "--aov",
            "albedo,normal,depth",
            "--denoise",
            "--validate",
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let path = dir.path().join("out.exr");
    let (names, albedo_red) = exr_channel(&path, "albedo.R");
    for channel in [
        "R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.R", "normal.G", "normal.B",
        "depth.Z", "noisy.R", "noisy.G", "noisy.B",
    ] {
        assert!(
            names.iter().any(|n| n == channel),
            "{channel} missing from {names:?}"
        );
    }
    // The box's red wall (albedo 0.73, 0.246, 0.251 in the workshop's scene) is in view.
    assert!(
        albedo_red.iter().any(|&r| (r - 0.73).abs() < 0.01),
        "no red wall in the albedo"
    );
    let (_, depth) = exr_channel(&path, "depth.Z");
    assert!(
        depth.iter().all(|&d| d > 0.0 && d.is_finite()),
        "the closed box fills the view"
    );
    let normals: Vec<Vec<f32>> = ["normal.R", "normal.G", "normal.B"]
        .iter()
        .map(|c| exr_channel(&path, c).1)
        .collect();
    // A pixel's average of unit normals is at most unit length, and exactly so on a face.
    let lengths: Vec<f32> = (0..depth.len())
        .map(|i| (normals[0][i].powi(2) + normals[1][i].powi(2) + normals[2][i].powi(2)).sqrt())
        .collect();
    assert!(lengths.iter().all(|&l| l <= 1.0 + 1e-5));
    assert!(lengths.iter().filter(|&&l| l > 0.999).count() > depth.len() / 2);
    // The denoised colour differs from the noisy one, and neither has NaNs.
    let (_, red) = exr_channel(&path, "R");
    let (_, noisy) = exr_channel(&path, "noisy.R");
    assert!(red.iter().chain(&noisy).all(|v| v.is_finite()));
    assert_ne!(red, noisy);
}

#[test]
fn a_file_without_a_camera_is_framed_and_lit_by_the_sky() {
    let dir = tempfile::tempdir().unwrap();
    let mut document: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(common::fixture("emissive_quad.gltf")).unwrap(),
    )
    .unwrap();
    document["scenes"][0]["nodes"] = json!([0]); // the room only: no light, no camera
    std::fs::write(dir.path().join("room.gltf"), document.to_string()).unwrap();
    let render = |extra: &[&str]| {
        let mut args = vec![
            "render",
            "room.gltf",
            "-o",
            "room.exr",
            "--width",
            "16",
            "--height",
            "16",
            "--spp",
            "2",
            "--validate",
        ];
        args.extend_from_slice(extra);
        common::vkpath(dir.path(), &args)
    };
    let output = render(&[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains("the scene has no camera: framing its bounding sphere"),
        "{stderr}"
    );
    assert!(stderr.contains("nothing lights the scene"), "{stderr}");
    // A constant sky lights it, and silences the warning.
    let output = render(&["--background", "0.5,0.5,0.5", "--integrator", "mis"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success() && !stderr.contains("nothing lights"),
        "{stderr}"
    );
    let (_, red) = exr_channel(&dir.path().join("room.exr"), "R");
    // Every pixel sees the sky or a wall that sees it (2 samples may miss it deep inside).
    let lit = red.iter().filter(|&&r| r > 0.0).count();
    assert!(
        lit * 10 >= red.len() * 9,
        "{lit} of {} pixels lit",
        red.len()
    );
    // An EXR map (the render just written) lights it too; a missing one is one error line.
    let output = render(&["--environment", "room.exr", "--environment-rotation", "90"]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let output = render(&["--environment", "missing.hdr"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(
        stderr.lines().filter(|l| l.contains("error")).count(),
        1,
        "{stderr}"
    );
    // --camera picks among the file's cameras: this one has none.
    let output = render(&["--camera", "1"]);
    assert_eq!(output.status.code(), Some(1));
}

#[test]
fn an_unsupported_extension_is_one_warning_naming_it_and_what_is_lost() {
    let dir = tempfile::tempdir().unwrap();
    let source = format!(
        "{}/tests/data/emissive_quad.gltf",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut document: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(source).unwrap()).unwrap();
    // Declared twice (and once more as a material extension would be): still one warning.
    document["extensionsUsed"] = json!([
        "KHR_materials_emissive_strength",
        "KHR_materials_specular",
        "KHR_materials_anisotropy",
        "KHR_materials_clearcoat",
        "KHR_materials_sheen",
        "KHR_materials_iridescence",
        "KHR_materials_anisotropy"
    ]);
    let scene = dir.path().join("declares.gltf");
    std::fs::write(&scene, document.to_string()).unwrap();
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            scene.to_str().unwrap(),
            "-o",
            "out.exr",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
            "--integrator",
            "mis",
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains("glTF extension"))
        .collect();
    assert_eq!(warnings.len(), 2, "{stderr}");
    assert!(
        warnings[0]
            .contains("KHR_materials_anisotropy: ignored, anisotropic highlights render isotropic"),
        "{stderr}"
    );
    assert!(
        warnings[1].contains(
            "KHR_materials_iridescence: ignored, surfaces render without thin-film colours"
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("KHR_materials_specular:"), "{stderr}");
    // Implemented extensions (the clear coat and the sheen, declared above) are not warned
    // about.
    assert!(!stderr.contains("KHR_materials_clearcoat"), "{stderr}");
    assert!(!stderr.contains("KHR_materials_sheen"), "{stderr}");
}
