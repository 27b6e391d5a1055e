//! Cryptomatte (`--aov cryptomatte`, issue 56), as the published specification has it
//! (Psyop 2015, "Cryptomatte Specification", github.com/Psyop/Cryptomatte): ID mattes that
//! a compositor (Nuke, Blender, Houdini) keys by name, anti-aliased.
//!
//! - **Names.** Objects are the glTF nodes that draw a mesh, by their names (`#index` for a
//!   nameless node, `scene` for a file without nodes: the names of the IDs' sidecar,
//!   `IdNames`); materials are `#index` (the material's index in the scene's list: the scene
//!   keeps no material names).
//! - **IDs.** A name's ID is the float whose bits are the name's MurmurHash3_x86_32 (seed 0,
//!   the UTF-8 bytes), its exponent clamped to [1, 254] so that no ID is a denormal, an
//!   infinity or a NaN (`hash_to_float`). The manifest maps each name to those bits as 8 hex
//!   digits.
//! - **Coverage.** The ranking pixel filter: each pixel's camera rays are traced `K` times
//!   (`cryptomatte_samples`: the render's samples, at most `CRYPTOMATTE_MAX_SAMPLES`), each
//!   one jittered sample of the kernels' INTEGRATOR_TRIANGLE (the render's own pixel filter,
//!   lens and shutter, sample index k of the pixel's sequence); each sample's first hit gives
//!   one object and one material, each found name's weight is the share of the `K` samples
//!   that hit it (the box filter), and the names are ranked by weight (ties: by ID bits).
//!   Samples that hit nothing count for no name, so coverage sums to 1 where every sample
//!   hits something and to the covered share at the edge of the background (0 where nothing
//!   is hit).
//! - **Layers.** `CryptoObject00`, `CryptoObject01`, ... and `CryptoMaterial00`, ...: RGBA,
//!   R and B the IDs of ranks 2i and 2i + 1, G and A their coverage; `levels` ranks
//!   (`--cryptomatte-levels`, default 6, at most 16) in ceil(levels / 2) layers, the unused
//!   ranks 0. The header names each kind under a key, the first 7 hex digits of the kind's
//!   name's hash: `cryptomatte/<key>/name`, `hash` (`MurmurHash3_32`), `conversion`
//!   (`uint32_to_float32`) and `manifest` (JSON, name to hex).

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::image_io::output::ImageLayer;
use crate::render::ground_truth::{
    check_triangle_count, first_hits_of, FirstHits, IdNames, SceneIds,
};
use crate::render::sequence::SequenceCache;
use crate::render::settings::{Integrator, RenderSettings};
use crate::render::Renderer;
use crate::scene::Scene;
use crate::vk::Context;

/// The ranks a Cryptomatte keeps per pixel unless asked (the specification's suggestion).
pub const DEFAULT_CRYPTOMATTE_LEVELS: u32 = 6;

/// The most ranks `--cryptomatte-levels` may ask for (8 layers per kind).
pub const MAX_CRYPTOMATTE_LEVELS: u32 = 16;

/// The most camera samples per pixel the coverage is accumulated over: each is one
/// INTEGRATOR_TRIANGLE pass (camera rays only), so a render of 1000 spp takes 32 passes, not
/// 1000; coverage is then a multiple of 1/32.
pub const CRYPTOMATTE_MAX_SAMPLES: u32 = 32;

/// The header's `hash` value: the only hash the specification names.
pub const CRYPTOMATTE_HASH: &str = "MurmurHash3_32";

/// The header's `conversion` value: the only conversion the specification names.
pub const CRYPTOMATTE_CONVERSION: &str = "uint32_to_float32";

/// How a Cryptomatte is made (`PostProcess::cryptomatte`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CryptomatteOptions {
    /// The ranks kept per pixel (`--cryptomatte-levels`), 1 to `MAX_CRYPTOMATTE_LEVELS`.
    pub levels: u32,
    /// The samples per pixel the coverage takes, for shards (every shard must take the
    /// same: `cryptomatte_samples` of the whole render's `--spp`); `None`: those of the
    /// samples the render took (`cryptomatte_samples`).
    pub samples: Option<u32>,
}

impl Default for CryptomatteOptions {
    fn default() -> CryptomatteOptions {
        CryptomatteOptions {
            levels: DEFAULT_CRYPTOMATTE_LEVELS,
            samples: None,
        }
    }
}

/// Refuses a `--cryptomatte-levels` outside 1..=`MAX_CRYPTOMATTE_LEVELS`.
pub fn check_levels(levels: u32) -> Result<()> {
    if levels == 0 || levels > MAX_CRYPTOMATTE_LEVELS {
        return Err(Error::InvalidSettings(format!(
            "--cryptomatte-levels {levels}: a Cryptomatte keeps 1 to {MAX_CRYPTOMATTE_LEVELS} ranks per pixel (default {DEFAULT_CRYPTOMATTE_LEVELS})"
        )));
    }
    Ok(())
}

/// The samples per pixel a render of `spp` samples accumulates its coverage over.
pub fn cryptomatte_samples(spp: u32) -> u32 {
    spp.clamp(1, CRYPTOMATTE_MAX_SAMPLES)
}

/// MurmurHash3_x86_32 (Austin Appleby's, public domain) of `bytes` with `seed`: the 32-bit
/// hash that the Cryptomatte specification names (`MurmurHash3_32`).
pub fn murmur3_32(bytes: &[u8], seed: u32) -> u32 {
    const C1: u32 = 0xcc9e_2d51;
    const C2: u32 = 0x1b87_3593;
    // Each 4-byte block is mixed in, little-endian
    let scramble = |k: u32| k.wrapping_mul(C1).rotate_left(15).wrapping_mul(C2);
    let mut h = seed;
    let mut blocks = bytes.chunks_exact(4);
    for block in &mut blocks {
        let k = u32::from_le_bytes([block[0], block[1], block[2], block[3]]);
        h = (h ^ scramble(k))
            .rotate_left(13)
            .wrapping_mul(5)
            .wrapping_add(0xe654_6b64);
    }
    // The 1 to 3 bytes left over
    let tail = blocks.remainder();
    if !tail.is_empty() {
        let k = tail
            .iter()
            .rev()
            .fold(0u32, |k, &byte| (k << 8) | u32::from(byte));
        h ^= scramble(k);
    }
    // Finalization: the length, then the avalanche
    h ^= bytes.len() as u32;
    h ^= h >> 16;
    h = h.wrapping_mul(0x85eb_ca6b);
    h ^= h >> 13;
    h = h.wrapping_mul(0xc2b2_ae35);
    h ^ (h >> 16)
}

/// The specification's `uint32_to_float32`: the hash's bits as a float, its exponent clamped
/// to [1, 254] (no denormal, infinity or NaN), sign and mantissa kept.
pub fn hash_to_float(hash: u32) -> f32 {
    let exponent = (hash >> 23) & 0xff;
    let clamped = exponent.clamp(1, 254);
    f32::from_bits((hash & !(0xff << 23)) | (clamped << 23))
}

/// A name's ID in the layers: `hash_to_float(murmur3_32(name, 0))`.
pub fn name_id(name: &str) -> f32 {
    hash_to_float(murmur3_32(name.as_bytes(), 0))
}

/// An ID as the manifest writes it: its float bits as 8 lowercase hex digits.
pub fn id_hex(id: f32) -> String {
    format!("{:08x}", id.to_bits())
}

/// The header key of the kind named `type_name`: the first 7 hex digits of its hash.
pub fn metadata_key(type_name: &str) -> String {
    format!("{:08x}", murmur3_32(type_name.as_bytes(), 0))[..7].to_owned()
}

/// What a Cryptomatte names: the objects or the materials.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CryptomatteKind {
    /// The glTF nodes (`IdNames::objects`' names).
    Object,
    /// The materials (`#index`).
    Material,
}

impl CryptomatteKind {
    /// Both kinds, in the order the layers are written.
    pub const ALL: [CryptomatteKind; 2] = [CryptomatteKind::Object, CryptomatteKind::Material];

    /// The type name: the layers' prefix and the header's `name`.
    pub fn type_name(self) -> &'static str {
        match self {
            CryptomatteKind::Object => "CryptoObject",
            CryptomatteKind::Material => "CryptoMaterial",
        }
    }
}

/// Each triangle's object and material names, as indices into the names' lists.
struct TriangleNames {
    /// The names of each kind, and each name's ID (`name_id`).
    names: [Vec<(String, f32)>; 2],
    /// Per triangle: the index of its object's name and of its material's.
    triangles: Vec<[u32; 2]>,
}

impl TriangleNames {
    fn of(scene: &Scene) -> TriangleNames {
        let ids = SceneIds::new(scene);
        let id_names = IdNames::of(scene);
        let mut names: [Vec<(String, f32)>; 2] = [Vec::new(), Vec::new()];
        let mut index_of: [BTreeMap<String, u32>; 2] = [BTreeMap::new(), BTreeMap::new()];
        let mut intern = |kind: usize, name: String| -> u32 {
            *index_of[kind].entry(name.clone()).or_insert_with(|| {
                names[kind].push((name.clone(), name_id(&name)));
                names[kind].len() as u32 - 1
            })
        };
        let object_names: BTreeMap<u64, String> = id_names
            .objects
            .iter()
            .map(|o| (o.id, o.name.clone()))
            .collect();
        let triangles = (0..scene.triangles.len() as u32)
            .map(|triangle| {
                let object = object_names
                    .get(&ids.object_id(triangle))
                    .cloned()
                    .unwrap_or_else(|| "scene".to_owned());
                let material = format!("#{}", ids.material_id(triangle) - 1);
                [intern(0, object), intern(1, material)]
            })
            .collect();
        TriangleNames { names, triangles }
    }
}

/// One pixel's ranks: (ID, coverage), highest coverage first.
pub type Ranks = Vec<(f32, f32)>;

/// Ranks each pixel's names by the share of `samples` (the same pixels, one first hit per
/// sample) whose hit names them; `name_of` gives a hit triangle's name's ID.
pub fn rank_pixels(samples: &[FirstHits], name_of: impl Fn(u32) -> f32) -> Vec<Ranks> {
    let Some(first) = samples.first() else {
        return Vec::new();
    };
    let weight = 1.0 / samples.len() as f32;
    (0..first.hits.len())
        .map(|pixel| {
            // (ID bits, samples that hit it), in the order first found
            let mut counts: Vec<(u32, u32)> = Vec::new();
            for sample in samples {
                let Some(hit) = sample.hits.get(pixel).copied().flatten() else {
                    continue;
                };
                let id = name_of(hit.triangle).to_bits();
                match counts.iter_mut().find(|(found, _)| *found == id) {
                    Some((_, count)) => *count += 1,
                    None => counts.push((id, 1)),
                }
            }
            counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
            counts
                .into_iter()
                .map(|(id, count)| (f32::from_bits(id), count as f32 * weight))
                .collect()
        })
        .collect()
}

/// The EXR layers of one kind: `{type_name}00`, ... (ceil(levels / 2) of them), each rank
/// pair as (ID, coverage, ID, coverage); the first carries the header attributes, with the
/// manifest of `names` (name, ID).
pub fn kind_layers(
    kind: CryptomatteKind,
    ranks: &[Ranks],
    levels: u32,
    names: &[(String, f32)],
) -> Vec<ImageLayer> {
    let type_name = kind.type_name();
    let key = metadata_key(type_name);
    let manifest: BTreeMap<&str, String> = names
        .iter()
        .map(|(name, id)| (name.as_str(), id_hex(*id)))
        .collect();
    let manifest = serde_json::to_string(&manifest).unwrap_or_default();
    let attributes = vec![
        (format!("cryptomatte/{key}/name"), type_name.to_owned()),
        (
            format!("cryptomatte/{key}/hash"),
            CRYPTOMATTE_HASH.to_owned(),
        ),
        (
            format!("cryptomatte/{key}/conversion"),
            CRYPTOMATTE_CONVERSION.to_owned(),
        ),
        (format!("cryptomatte/{key}/manifest"), manifest),
    ];
    let rank = |pixel: &Ranks, r: usize| pixel.get(r).copied().unwrap_or((0.0, 0.0));
    (0..levels.div_ceil(2) as usize)
        .map(|layer| {
            let (pixels, alpha): (Vec<[f32; 3]>, Vec<f32>) = ranks
                .iter()
                .map(|pixel| {
                    let (id_0, coverage_0) = rank(pixel, 2 * layer);
                    // An odd level count leaves the last layer's second rank empty
                    let (id_1, coverage_1) = if 2 * layer + 1 < levels as usize {
                        rank(pixel, 2 * layer + 1)
                    } else {
                        (0.0, 0.0)
                    };
                    ([id_0, coverage_0, id_1], coverage_1)
                })
                .unzip();
            ImageLayer {
                name: format!("{type_name}{layer:02}"),
                pixels,
                single_channel: false,
                alpha: Some(alpha),
                attributes: if layer == 0 {
                    attributes.clone()
                } else {
                    Vec::new()
                },
            }
        })
        .collect()
}

/// The Cryptomatte of `scene` from `samples` (one first hit per pixel and sample): the
/// object layers, then the material layers, `levels` ranks each.
pub fn cryptomatte_layers(scene: &Scene, samples: &[FirstHits], levels: u32) -> Vec<ImageLayer> {
    let names = TriangleNames::of(scene);
    let mut layers = Vec::new();
    for (k, kind) in CryptomatteKind::ALL.into_iter().enumerate() {
        let name_of = |triangle: u32| {
            names
                .triangles
                .get(triangle as usize)
                .map_or(0.0, |t| names.names[k][t[k] as usize].1)
        };
        let ranks = rank_pixels(samples, name_of);
        layers.extend(kind_layers(kind, &ranks, levels, &names.names[k]));
    }
    layers
}

/// Renders `count` jittered first hits of every pixel: sample k of each pixel's sequence,
/// with `settings`' pixel filter, lens and shutter (its integrator INTEGRATOR_TRIANGLE, one
/// sample a pass; the passes share one pipeline and upload through a `SequenceCache`).
pub fn render_hit_samples(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: &RenderSettings,
    count: u32,
) -> Result<Vec<FirstHits>> {
    check_triangle_count(scene)?;
    let settings = RenderSettings {
        integrator: Integrator::Triangle,
        spp: 1,
        noise_threshold: None,
        guiding: None,
        ..settings.clone()
    };
    let mut sequence = SequenceCache::default();
    let mut samples = Vec::new();
    for k in 0..count {
        let mut renderer =
            Renderer::in_sequence(context, scene, camera, settings.clone(), &mut sequence)?;
        renderer.start_at_sample(k)?;
        let image = renderer.render_all()?;
        samples.push(first_hits_of(&image, renderer.triangle_order()));
        renderer.keep_for_next(&mut sequence);
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::ground_truth::FirstHit;
    use glam::Vec3;

    #[test]
    fn murmur3_matches_the_published_vectors() {
        // MurmurHash3_x86_32's reference vectors (SMHasher's and the common ports')
        assert_eq!(murmur3_32(b"", 0), 0);
        assert_eq!(murmur3_32(b"", 1), 0x514e_28b7);
        assert_eq!(murmur3_32(b"", 0xffff_ffff), 0x81f1_6f39);
        assert_eq!(murmur3_32(b"\0\0\0\0", 0), 0x2362_f9de);
        assert_eq!(murmur3_32(b"aaaa", 0x9747_b28c), 0x5a97_808a);
        assert_eq!(murmur3_32(b"abc", 0), 0xb3dd_93fa);
        assert_eq!(murmur3_32(b"Hello, world!", 0x9747_b28c), 0x2488_4cba);
        assert_eq!(
            murmur3_32(b"The quick brown fox jumps over the lazy dog", 0),
            0x2e4f_f723
        );
    }

    #[test]
    fn ids_and_keys_match_the_specifications_examples() {
        // The specification's manifests: {"bunny":"13851a76", "default":"42c9679f"},
        // {"bunny_porcelain_mat":"b24b26d4"}
        assert_eq!(id_hex(name_id("bunny")), "13851a76");
        assert_eq!(id_hex(name_id("default")), "42c9679f");
        assert_eq!(id_hex(name_id("bunny_porcelain_mat")), "b24b26d4");
        // The exponent is clamped: 0 becomes 1, 255 becomes 254; sign and mantissa stay
        assert_eq!(hash_to_float(0x0000_0001).to_bits(), 0x0080_0001);
        assert_eq!(hash_to_float(0xff80_0000).to_bits(), 0xff00_0000);
        assert_eq!(hash_to_float(0x7fff_ffff).to_bits(), 0x7f7f_ffff);
        assert!(hash_to_float(0x7f80_0001).is_finite());
        assert_eq!(metadata_key("CryptoObject").len(), 7);
    }

    #[test]
    fn levels_outside_1_to_16_are_refused() {
        assert!(check_levels(1).is_ok() && check_levels(16).is_ok());
        for levels in [0, 17] {
            let error = check_levels(levels).unwrap_err().to_string();
            assert!(error.contains("1 to 16 ranks"), "{error}");
        }
        assert_eq!(cryptomatte_samples(1000), CRYPTOMATTE_MAX_SAMPLES);
        assert_eq!(cryptomatte_samples(3), 3);
    }

    #[test]
    fn ranks_are_sorted_by_coverage_and_layers_pack_them_in_pairs() {
        let hit = |triangle| {
            Some(FirstHit {
                triangle,
                barycentrics: Vec3::ZERO,
            })
        };
        // One pixel, four samples: triangle 1 twice, triangle 2 once, nothing once
        let samples: Vec<FirstHits> = [hit(1), hit(2), hit(1), None]
            .into_iter()
            .map(|h| FirstHits {
                width: 1,
                height: 1,
                hits: vec![h],
            })
            .collect();
        let ranks = rank_pixels(&samples, |t| t as f32 * 10.0);
        assert_eq!(ranks, vec![vec![(10.0, 0.5), (20.0, 0.25)]]);
        let names = [("a".to_owned(), 10.0), ("b".to_owned(), 20.0)];
        let layers = kind_layers(CryptomatteKind::Object, &ranks, 3, &names);
        assert_eq!(layers.len(), 2);
        assert_eq!(layers[0].name, "CryptoObject00");
        assert_eq!(layers[0].pixels, vec![[10.0, 0.5, 20.0]]);
        assert_eq!(layers[0].alpha, Some(vec![0.25]));
        // Level 3 is empty; the odd layer's fourth channel is always 0
        assert_eq!(layers[1].pixels, vec![[0.0; 3]]);
        assert_eq!(layers[1].alpha, Some(vec![0.0]));
        let manifest = &layers[0].attributes[3];
        assert!(manifest.0.ends_with("/manifest"));
        assert_eq!(manifest.1, r#"{"a":"41200000","b":"41a00000"}"#);
        assert!(layers[1].attributes.is_empty());
    }
}
