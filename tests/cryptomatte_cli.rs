//! Cryptomatte through the binary (issue 56, `src/render/cryptomatte.rs`), read back by a
//! reader written here from the specification (Psyop, "Cryptomatte Specification"): the
//! header's `cryptomatte/<key>/{name,hash,conversion,manifest}`, the layers
//! `{name}00`, `{name}01`, ... each holding two (ID, coverage) ranks in R, G and B, A, the
//! IDs MurmurHash3_x86_32 of the names with the exponent clamped to [1, 254].
//!
//! The scene is known pixel by pixel: two quads side by side in the plane z = 0, `left`
//! (x in [-1.8, 0.1]) and a nameless node (x in [0.1, 1.8]), both y in [-1, 1], each with a
//! material of its own, seen from z = 4 (tan(yfov / 2) = 1/2) in 16 x 16 pixels of 0.25: the
//! shared edge x = 0.1 cuts column 8 at 0.4, rows 0-3 and 12-15 see nothing.

use crate::common;

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use serde_json::json;

/// Image size in pixels.
const SIZE: usize = 16;

/// Writes the scene; returns its path.
fn write_scene(dir: &Path) -> String {
    let quad = |x0: f32, x1: f32| -> Vec<f32> {
        vec![x0, -1.0, 0.0, x1, -1.0, 0.0, x1, 1.0, 0.0, x0, 1.0, 0.0]
    };
    let indices: Vec<u16> = vec![0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = Vec::new();
    for positions in [quad(-1.8, 0.1), quad(0.1, 1.8)] {
        bytes.extend(positions.iter().flat_map(|x| x.to_le_bytes()));
    }
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let primitive = |positions: usize, material: usize| json!({"attributes": {"POSITION": positions}, "indices": 2, "material": material});
    let document = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"name": "left", "mesh": 0},
            {"mesh": 1},
            {"name": "camera", "camera": 0, "translation": [0, 0, 4]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 2.0 * 0.5f64.atan(), "aspectRatio": 1.0, "znear": 0.1}}],
        "meshes": [{"primitives": [primitive(0, 0)]}, {"primitives": [primitive(1, 1)]}],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1]}, "doubleSided": true},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.8, 0.1, 1]}, "doubleSided": true}
        ],
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&bytes))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.8, -1, 0], "max": [0.1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0.1, -1, 0], "max": [1.8, 1, 0]},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    });
    let path = dir.join("pair.gltf");
    std::fs::write(&path, document.to_string()).unwrap();
    path.display().to_string()
}

/// MurmurHash3_x86_32 with seed 0, written here from Appleby's reference (byte by byte, not
/// as the crate does), so that the check does not trust the code it checks.
fn reference_murmur3(bytes: &[u8]) -> u32 {
    let mix = |k: u32| {
        k.wrapping_mul(0xcc9e2d51)
            .rotate_left(15)
            .wrapping_mul(0x1b873593)
    };
    let mut h: u32 = 0;
    let whole = bytes.len() / 4 * 4;
    let mut i = 0;
    while i < whole {
        let k = u32::from(bytes[i])
            | u32::from(bytes[i + 1]) << 8
            | u32::from(bytes[i + 2]) << 16
            | u32::from(bytes[i + 3]) << 24;
        h ^= mix(k);
        h = h.rotate_left(13).wrapping_mul(5).wrapping_add(0xe6546b64);
        i += 4;
    }
    let mut k: u32 = 0;
    for (shift, byte) in bytes[whole..].iter().enumerate() {
        k |= u32::from(*byte) << (8 * shift);
    }
    if bytes.len() > whole {
        h ^= mix(k);
    }
    h ^= bytes.len() as u32;
    h ^= h >> 16;
    h = h.wrapping_mul(0x85ebca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2ae35);
    h ^ (h >> 16)
}

/// The specification's hash_to_float, as float bits: the exponent clamped to [1, 254].
fn reference_id_bits(name: &str) -> u32 {
    let hash = reference_murmur3(name.as_bytes());
    let exponent = ((hash >> 23) & 255).clamp(1, 254);
    (hash & 0x807f_ffff) | (exponent << 23)
}

/// One Cryptomatte of a file, as a reader of the specification finds it.
struct Matte {
    /// The header's `manifest`: name to ID bits.
    manifest: BTreeMap<String, u32>,
    /// Per pixel, its ranks (ID bits, coverage), in layer order, the empty ones left out.
    ranks: Vec<Vec<(u32, f32)>>,
    /// How many `{name}NN` layers the file has.
    layers: usize,
}

/// Reads the Cryptomatte named `type_name` (e.g. `CryptoObject`) from the EXR at `path`.
fn read_matte(path: &Path, type_name: &str) -> Matte {
    // The header: every `cryptomatte/<key>/<field>` attribute, wherever the file keeps it
    let meta = exr::meta::MetaData::read_from_file(path, false).unwrap();
    let header = &meta.headers[0];
    let mut fields: HashMap<String, HashMap<String, String>> = HashMap::new();
    let attributes = header
        .shared_attributes
        .other
        .iter()
        .chain(header.own_attributes.other.iter());
    for (name, value) in attributes {
        let name = name.to_string();
        let Some(rest) = name.strip_prefix("cryptomatte/") else {
            continue;
        };
        let (key, field) = rest.split_once('/').unwrap();
        let exr::meta::attribute::AttributeValue::Text(text) = value else {
            panic!("{name} is not text");
        };
        fields
            .entry(key.to_owned())
            .or_default()
            .insert(field.to_owned(), text.to_string());
    }
    let (key, matte) = fields
        .iter()
        .find(|(_, f)| f.get("name").map(String::as_str) == Some(type_name))
        .unwrap_or_else(|| panic!("no cryptomatte named {type_name}: {:?}", fields.keys()));
    assert!(key.len() <= 7, "{key}");
    assert_eq!(matte["hash"], "MurmurHash3_32");
    assert_eq!(matte["conversion"], "uint32_to_float32");
    let manifest: BTreeMap<String, String> = serde_json::from_str(&matte["manifest"]).unwrap();
    let manifest = manifest
        .into_iter()
        .map(|(name, hex)| {
            assert_eq!(hex.len(), 8, "{name}: {hex}");
            (name, u32::from_str_radix(&hex, 16).unwrap())
        })
        .collect();
    // The layers: {type_name}00.R = ID rank 0, .G its coverage, .B rank 1, .A its coverage
    let channels: HashMap<String, Vec<f32>> = vkpath::image_io::exr_input::read_exr_channels(path)
        .unwrap()
        .channels
        .into_iter()
        .collect();
    let mut ranks = vec![Vec::new(); SIZE * SIZE];
    let mut layers = 0;
    while let Some(r) = channels.get(&format!("{type_name}{layers:02}.R")) {
        let channel = |c: &str| &channels[&format!("{type_name}{layers:02}.{c}")];
        let (g, b, a) = (channel("G"), channel("B"), channel("A"));
        for (pixel, ranks) in ranks.iter_mut().enumerate() {
            for (id, coverage) in [(r[pixel], g[pixel]), (b[pixel], a[pixel])] {
                if coverage > 0.0 {
                    ranks.push((id.to_bits(), coverage));
                }
            }
        }
        layers += 1;
    }
    Matte {
        manifest,
        ranks,
        layers,
    }
}

/// Runs `vkpath render` in `dir` with `args`; returns (exit code, stderr).
fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let run = common::vkpath(dir, args);
    (
        run.status.code(),
        String::from_utf8_lossy(&run.stderr).into_owned(),
    )
}

#[test]
fn cryptomatte_reads_back_as_the_specification_says() {
    // The reader's hash against the specification's own manifests
    assert_eq!(reference_id_bits("bunny"), 0x13851a76);
    assert_eq!(reference_id_bits("default"), 0x42c9679f);
    assert_eq!(reference_id_bits("bunny_porcelain_mat"), 0xb24b26d4);
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let size = SIZE.to_string();
    let base = [
        "render", &scene, "--width", &size, "--height", &size, "--spp", "16",
    ];
    let render = |extra: &[&str]| {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let (code, stderr) = run(dir.path(), &args);
        assert_eq!(code, Some(0), "{stderr}");
    };
    render(&["-o", "matte.exr", "--aov", "cryptomatte"]);
    let path = dir.path().join("matte.exr");
    let objects = read_matte(&path, "CryptoObject");
    let materials = read_matte(&path, "CryptoMaterial");
    // 6 ranks by default, in 3 layers per kind
    assert_eq!((objects.layers, materials.layers), (3, 3));
    // The manifests name every object and material, hashed as the specification says
    let names: Vec<&str> = objects.manifest.keys().map(String::as_str).collect();
    assert_eq!(names, ["#1", "left"]);
    let names: Vec<&str> = materials.manifest.keys().map(String::as_str).collect();
    assert_eq!(names, ["#0", "#1"]);
    for matte in [&objects, &materials] {
        for (name, bits) in &matte.manifest {
            assert_eq!(*bits, reference_id_bits(name), "{name}");
        }
    }
    let (left, right) = (objects.manifest["left"], objects.manifest["#1"]);
    for row in 0..SIZE {
        for column in 0..SIZE {
            let ranks = &objects.ranks[row * SIZE + column];
            let at = format!("pixel ({column}, {row}): {ranks:?}");
            let sum: f32 = ranks.iter().map(|r| r.1).sum();
            // Coverage is a share of 16 samples: exact in a float, and so is its sum
            let inside = (4..12).contains(&row) && (1..15).contains(&column);
            if inside {
                assert!((sum - 1.0).abs() < 1e-6, "{at}");
            }
            if !(4..12).contains(&row) {
                assert!(ranks.is_empty() && sum == 0.0, "{at}");
            }
            // Ranks come highest coverage first
            assert!(ranks.windows(2).all(|w| w[0].1 >= w[1].1), "{at}");
            if inside && column != 8 {
                let want = if column < 8 { left } else { right };
                assert_eq!(ranks.as_slice(), [(want, 1.0)], "{at}");
            }
        }
    }
    // The edge: column 8 is 0.4 `left` and 0.6 the nameless node's, anti-aliased
    for row in 4..12 {
        let ranks = &objects.ranks[row * SIZE + 8];
        assert_eq!(ranks.len(), 2, "row {row}: {ranks:?}");
        let mut ids: Vec<u32> = ranks.iter().map(|r| r.0).collect();
        ids.sort_unstable();
        let mut want = vec![left, right];
        want.sort_unstable();
        assert_eq!(ids, want, "row {row}");
        assert!(ranks.iter().all(|r| r.1 > 0.0 && r.1 < 1.0), "row {row}");
    }
    // The materials follow the objects here: material 0 is left's, 1 the other's
    let (red, green) = (materials.manifest["#0"], materials.manifest["#1"]);
    for (pixel, ranks) in objects.ranks.iter().enumerate() {
        // (Equal coverage ranks by ID, which differs between the kinds: compare as sets)
        let mut swapped: Vec<(u32, f32)> = ranks
            .iter()
            .map(|&(id, c)| (if id == left { red } else { green }, c))
            .collect();
        let mut found = materials.ranks[pixel].clone();
        swapped.sort_by_key(|r| r.0);
        found.sort_by_key(|r| r.0);
        assert_eq!(found, swapped, "pixel {pixel}");
    }
    // The colour is the colour without Cryptomatte, bit for bit
    render(&["-o", "plain.exr"]);
    let colour = |name: &str| {
        let channels: HashMap<String, Vec<f32>> =
            vkpath::image_io::exr_input::read_exr_channels(&dir.path().join(name))
                .unwrap()
                .channels
                .into_iter()
                .collect();
        ["R", "G", "B"].map(|c| channels[c].iter().map(|v| v.to_bits()).collect::<Vec<_>>())
    };
    assert!(colour("matte.exr") == colour("plain.exr"));
    // Three ranks: two layers, the second's second rank empty
    render(&[
        "-o",
        "three.exr",
        "--aov",
        "cryptomatte",
        "--cryptomatte-levels",
        "3",
    ]);
    let three = read_matte(&dir.path().join("three.exr"), "CryptoObject");
    assert_eq!(three.layers, 2);
}

#[test]
fn bad_levels_and_a_png_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for levels in ["0", "17"] {
        let (code, stderr) = run(
            dir.path(),
            &[
                "render",
                "-o",
                "a.exr",
                "--aov",
                "cryptomatte",
                "--cryptomatte-levels",
                levels,
            ],
        );
        assert_eq!(code, Some(2), "{stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(stderr.contains("1 to 16 ranks"), "{stderr}");
    }
    let (code, stderr) = run(
        dir.path(),
        &["render", "-o", "a.png", "--aov", "cryptomatte"],
    );
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("--aov cryptomatte"), "{stderr}");
    assert!(!dir.path().join("a.png").exists());
}

/// The channels of an EXR in `dir` whose names start with one of `prefixes`, as bits.
fn layer_bits(dir: &Path, name: &str, prefixes: &[&str]) -> BTreeMap<String, Vec<u32>> {
    vkpath::image_io::exr_input::read_exr_channels(&dir.join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .channels
        .into_iter()
        .filter(|(channel, _)| prefixes.iter().any(|p| channel.starts_with(p)))
        .map(|(channel, values)| (channel, values.iter().map(|v| v.to_bits()).collect()))
        .collect()
}

#[test]
fn shards_tiles_resume_and_merge_keep_the_ground_truth_and_cryptomatte_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path());
    let size = SIZE.to_string();
    let layers = "object_id,position,z,cryptomatte";
    let render = |extra: &[&str]| {
        let mut args = vec![
            "render", &scene, "--width", &size, "--height", &size, "--spp", "4", "--aov", layers,
        ];
        args.extend_from_slice(extra);
        let (code, stderr) = run(dir.path(), &args);
        assert_eq!(code, Some(0), "{stderr}");
    };
    render(&["-o", "whole.exr"]);
    render(&["-o", "tiled.exr", "--tile-size", "8"]);
    render(&["-o", "s0.exr", "--shard", "0/2"]);
    render(&["-o", "s1.exr", "--shard", "1/2"]);
    let (code, stderr) = run(
        dir.path(),
        &["merge", "s0.exr", "s1.exr", "-o", "merged.exr"],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let prefixes = [
        "object_id.",
        "position.",
        "z.",
        "CryptoObject",
        "CryptoMaterial",
    ];
    let whole = layer_bits(dir.path(), "whole.exr", &prefixes);
    assert_eq!(whole.len(), 1 + 3 + 1 + 2 * 3 * 4, "{:?}", whole.keys());
    for name in ["tiled.exr", "s0.exr", "s1.exr", "merged.exr"] {
        assert!(layer_bits(dir.path(), name, &prefixes) == whole, "{name}");
    }
    // A render whose device is lost after its samples are checkpointed, during the layers'
    // passes, resumed from its checkpoint, writes the same layers. The loss is injected at
    // the first submission that leaves a checkpoint (how many submissions come before the
    // samples' last batch depends on the scene's uploads).
    let mut stopped = vec![
        "render",
        &scene,
        "--width",
        &size,
        "--height",
        &size,
        "--spp",
        "4",
        "--aov",
        layers,
        "--samples-per-frame",
        "1",
        "--checkpoint",
        "ck.exr",
        "--checkpoint-interval",
        "0.001",
        "-o",
        "resumed.exr",
    ];
    let stopped_at = (2..24).find(|submission| {
        let fault = format!("device-lost:{submission}");
        let output =
            common::vkpath_with_env(dir.path(), &stopped, &[("VKPATH_INJECT_FAULT", &fault)]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(
            output.status.code(),
            Some(1),
            "the fault stops it: {stderr}"
        );
        dir.path().join("ck.exr").is_file()
    });
    assert!(stopped_at.is_some(), "no lost submission left a checkpoint");
    stopped.extend_from_slice(&["--resume", "ck.exr"]);
    let (code, stderr) = run(dir.path(), &stopped);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        layer_bits(dir.path(), "resumed.exr", &prefixes) == whole,
        "resumed.exr"
    );
    // The merged file's header keeps the manifests, and its sidecar the IDs' names
    let merged = read_matte(&dir.path().join("merged.exr"), "CryptoObject");
    assert_eq!(merged.manifest.len(), 2);
    assert!(dir.path().join("merged.ids.json").is_file());
    // Averaged layers still need the whole render
    let (code, stderr) = run(
        dir.path(),
        &["render", "-o", "s.exr", "--shard", "0/2", "--aov", "albedo"],
    );
    assert_ne!(code, Some(0));
    assert!(
        stderr.contains("--aov albedo works on whole renders"),
        "{stderr}"
    );
}
