//! What a render was: the settings that decide its samples, the samples it holds and a hash
//! of the scene as loaded. Every EXR vkpath writes carries it as the header attribute
//! `vkpath` (text: `version=0.1.0; spp=64; sample_range=0..64; seed=0; ...`), so that a
//! checkpoint is resumed and shards are merged only with what they belong to. One attribute,
//! not one per field: the EXR writer stores attributes in hash order, which would make two
//! identical renders different files.

use std::collections::BTreeMap;
use std::ops::Range;

use sha2::{Digest, Sha256};

use crate::camera::Camera;
use crate::image_io::output::ImageWindow;
use crate::render::region::PixelRegion;
use crate::render::settings::{PixelFilter, RenderSettings, SamplerKind};
use crate::scene::Scene;

/// The name of vkpath's EXR header attribute.
pub const ATTRIBUTE_NAME: &str = "vkpath";
/// The field of an adaptive render's attribute that holds the mean over the pixels of the
/// samples each holds (`RenderMetadata::attributes_with_counts`).
pub const SPP_MEAN_FIELD: &str = "spp_mean";
/// The field of a finished image's attribute that holds the samples per pixel asked for.
pub const SPP_REQUESTED_FIELD: &str = "spp_requested";
/// The field of a finished image's attribute that says why its render stopped.
pub const STOP_FIELD: &str = "stop";
/// The field of an image of a sequence that holds its frame number (`--frames`).
pub const FRAME_FIELD: &str = "frame";
/// The field of an image rendered at a given time that holds the scene time in seconds
/// (`--time`, or frame / `--fps`).
pub const TIME_FIELD: &str = "time";
/// The field of a denoised image (`--denoise`) that names the denoiser.
pub const DENOISE_FIELD: &str = "denoise";
/// The field of an image with output layers (`--aov`) that lists them, comma-separated.
pub const AOV_FIELD: &str = "aov";
/// What an image records beside its samples, outcome and settings, none of which decides
/// its samples (resuming and merging ignore them; `render --skip-existing` compares them),
/// in order, each only when it applies: the frame and the scene time, then what was done
/// to the finished image (`--denoise`, `--aov`).
pub const IMAGE_FIELD_NAMES: [&str; 4] = [FRAME_FIELD, TIME_FIELD, DENOISE_FIELD, AOV_FIELD];
/// How `DENOISE_FIELD` names the denoiser: Open Image Denoise's `RT` filter.
pub const DENOISER_NAME: &str = "oidn-rt";
/// What separates the fields in the attribute's text.
const FIELD_SEPARATOR: &str = "; ";
/// The settings recorded, in order.
const SETTING_NAMES: [&str; 10] = [
    "version",
    "seed",
    "integrator",
    "sampler",
    "light_sampling",
    "max_path_length",
    "russian_roulette_start",
    "pixel_filter",
    "resolution",
    "scene_hash",
];
/// The settings recorded after those only when a render has them (files without them had
/// none), in order: `--region`, `--noise-threshold` and its minimum spp, and
/// `light_selection=tree` where the light tree chose the lights (power, the selection of
/// every render before the tree, is not recorded, so those files' metadata stays as it was),
/// and `--guiding`'s training samples per pixel (which, with the rest, decide the guide),
/// and a thin lens's aperture radius, focus distance, blades and rotation (depth of field),
/// and motion blur's shutter (frame intervals), its position and its keys (`--motion-steps`)
/// where the scene moves across it, and the global medium (`--medium`, as its text).
const OPTIONAL_SETTING_NAMES: [&str; 13] = [
    "region",
    "noise_threshold",
    "noise_min_spp",
    "light_selection",
    "guide_training_spp",
    "aperture_radius",
    "focus_distance",
    "aperture_blades",
    "aperture_rotation_degrees",
    "shutter",
    "shutter_position",
    "motion_steps",
    "medium",
];

/// What a render was.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenderMetadata {
    /// (name, value) of everything that decides the samples, in a fixed order: vkpath
    /// version, seed, integrator, sampler, light sampling, max path length, Russian-roulette
    /// start, pixel filter, resolution and the scene hash; then, when set, the region and
    /// the noise threshold with its minimum spp.
    pub settings: Vec<(String, String)>,
    /// The samples of every pixel's sequence that the image holds.
    pub samples: Range<u32>,
    /// How the render that wrote the file ended, for finished images (`render`'s outputs);
    /// none for checkpoints, shards and merged files, whose samples say what they hold.
    pub outcome: Option<RenderOutcome>,
    /// (name, value) of the image's fields that do not decide its samples, in the order of
    /// `IMAGE_FIELD_NAMES`: its frame and time, and its post-processing (`denoise`, `aov`).
    pub image_fields: Vec<(String, String)>,
}

/// How a render ended, as an image records it beside its samples: the samples per pixel
/// asked for and why it stopped, so that a file left by a stop is told from a finished one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RenderOutcome {
    /// The samples per pixel the render was asked for (`--spp`).
    pub spp_requested: u32,
    /// Why it stopped, as `render --json` names it: `done`, `time-limit` or `signal`.
    pub stop: String,
}

impl RenderOutcome {
    /// Whether the render ran to the end of its samples (`stop=done`).
    pub fn is_finished(&self) -> bool {
        self.stop == "done"
    }
}

/// Why header attributes hold no render metadata (`RenderMetadata::from_attributes`), in
/// words that follow the file's name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MetadataError {
    /// No `vkpath` attribute.
    #[error("it has no vkpath attribute (not written by vkpath render)")]
    NoAttribute,
    /// The attribute lacks its sample range.
    #[error("its vkpath attribute has no sample_range")]
    NoSampleRange,
    /// A sample range that is not START..END: the text.
    #[error("its sample_range '{0}' is not START..END")]
    SampleRange(String),
    /// The attribute lacks a setting: its name.
    #[error("its vkpath attribute has no {0}")]
    NoSetting(&'static str),
    /// A requested sample count that is not a number: the text.
    #[error("its {field} '{0}' is not a number", field = SPP_REQUESTED_FIELD)]
    SppRequested(String),
}

impl RenderMetadata {
    /// The metadata of a render of `scene` seen by `camera` with `settings`, holding
    /// `samples`.
    pub fn new(
        settings: &RenderSettings,
        scene: &Scene,
        camera: &Camera,
        samples: Range<u32>,
    ) -> RenderMetadata {
        let entries: [(&str, String); 10] = [
            ("version", env!("CARGO_PKG_VERSION").to_string()),
            ("seed", settings.seed.to_string()),
            ("integrator", settings.integrator.name().to_string()),
            ("sampler", sampler_name(settings.sampler).to_string()),
            ("light_sampling", settings.light_sampling.name().to_string()),
            ("max_path_length", settings.max_path_length.to_string()),
            (
                "russian_roulette_start",
                settings.russian_roulette_start.to_string(),
            ),
            (
                "pixel_filter",
                pixel_filter_name(settings.pixel_filter).to_string(),
            ),
            (
                "resolution",
                format!("{}x{}", settings.width, settings.height),
            ),
            ("scene_hash", scene_hash(scene, camera)),
        ];
        let mut settings_list: Vec<(String, String)> = entries
            .into_iter()
            .map(|(name, value)| (name.to_string(), value))
            .collect();
        if let Some(region) = settings.region {
            settings_list.push(("region".into(), region.to_string()));
        }
        if let Some(noise) = settings.noise_threshold {
            settings_list.push(("noise_threshold".into(), noise.threshold.to_string()));
            settings_list.push(("noise_min_spp".into(), noise.min_spp.to_string()));
        }
        if settings.light_selection.uses_tree_over(&scene.triangles) {
            settings_list.push(("light_selection".into(), "tree".into()));
        }
        if let Some(training) = settings.guiding {
            settings_list.push(("guide_training_spp".into(), training.samples.to_string()));
        }
        let lens = &camera.lens;
        if !lens.is_pinhole() {
            settings_list.push(("aperture_radius".into(), lens.aperture_radius.to_string()));
            settings_list.push(("focus_distance".into(), lens.focus_distance.to_string()));
            settings_list.push(("aperture_blades".into(), lens.blades.to_string()));
            settings_list.push((
                "aperture_rotation_degrees".into(),
                lens.rotation.to_degrees().to_string(),
            ));
        }
        if let Some(motion) = &scene.motion {
            let shutter = &motion.shutter;
            settings_list.push(("shutter".into(), shutter.frames.to_string()));
            settings_list.push(("shutter_position".into(), shutter.position.name().into()));
            settings_list.push(("motion_steps".into(), shutter.steps.to_string()));
        }
        if let Some(medium) = &settings.medium {
            settings_list.push(("medium".into(), medium.to_string()));
        }
        RenderMetadata {
            settings: settings_list,
            samples,
            outcome: None,
            image_fields: Vec::new(),
        }
    }

    /// Records the image field `name` (one of `IMAGE_FIELD_NAMES`) as `value`, replacing
    /// what it held, in the order of `IMAGE_FIELD_NAMES`.
    pub fn set_image_field(&mut self, name: &str, value: String) {
        self.image_fields.retain(|(n, _)| n != name);
        self.image_fields.push((name.to_string(), value));
        let rank = |n: &str| IMAGE_FIELD_NAMES.iter().position(|&f| f == n);
        self.image_fields.sort_by_key(|(n, _)| rank(n));
    }

    /// Records where the image lies in time: `frame` (when it is a frame of `--frames`)
    /// and the scene `time` in seconds.
    pub fn set_frame(&mut self, frame: Option<u32>, time: f64) {
        if let Some(frame) = frame {
            self.set_image_field(FRAME_FIELD, frame.to_string());
        }
        self.set_image_field(TIME_FIELD, time.to_string());
    }

    /// The value of image field `name`, if recorded.
    pub fn image_field(&self, name: &str) -> Option<&str> {
        self.image_fields
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// The first setting or image field in which this image differs from `asked`, the one a
    /// render would write: (name, this value, the asked value; `none` where unrecorded).
    pub fn first_difference_from(
        &self,
        asked: &RenderMetadata,
    ) -> Option<(String, String, String)> {
        let value = |v: Option<&str>| v.unwrap_or("none").to_string();
        let settings = SETTING_NAMES
            .iter()
            .chain(&OPTIONAL_SETTING_NAMES)
            .map(|&name| (name, self.setting(name), asked.setting(name)));
        let fields = IMAGE_FIELD_NAMES
            .iter()
            .map(|&name| (name, self.image_field(name), asked.image_field(name)));
        settings
            .chain(fields)
            .find(|(_, held, wanted)| held != wanted)
            .map(|(name, held, wanted)| (name.to_string(), value(held), value(wanted)))
    }

    /// The value of setting `name`, if recorded.
    pub fn setting(&self, name: &str) -> Option<&str> {
        self.settings
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// Where the image lies in the full one when it is a `--region` of it (from the
    /// recorded region and resolution), for the EXR's data and display windows.
    pub fn window(&self) -> Option<ImageWindow> {
        let region = PixelRegion::parse(self.setting("region")?).ok()?;
        let (width, height) = self.setting("resolution")?.split_once('x')?;
        Some(ImageWindow {
            origin: [region.x0, region.y0],
            full_size: [width.parse().ok()?, height.parse().ok()?],
        })
    }

    /// The fields: `spp` (samples per pixel taken), `sample_range` ("start..end"), for a
    /// finished image `spp_requested` and `stop`, the image fields (`frame`, `time`,
    /// `denoise`, `aov`, those recorded), and the settings.
    pub fn fields(&self) -> Vec<(String, String)> {
        let mut fields = vec![
            ("spp".to_string(), self.samples.len().to_string()),
            (
                "sample_range".to_string(),
                format!("{}..{}", self.samples.start, self.samples.end),
            ),
        ];
        if let Some(outcome) = &self.outcome {
            fields.push((
                SPP_REQUESTED_FIELD.to_string(),
                outcome.spp_requested.to_string(),
            ));
            fields.push((STOP_FIELD.to_string(), outcome.stop.clone()));
        }
        fields.extend(self.image_fields.iter().cloned());
        fields.extend(self.settings.iter().cloned());
        fields
    }

    /// The header attributes: one, `vkpath`, with every field as `name=value`.
    pub fn attributes(&self) -> Vec<(String, String)> {
        Self::attribute_of(&self.fields())
    }

    /// The header attributes of a file whose pixels hold `sample_counts` samples:
    /// `attributes()`, and for an adaptive render (`noise_threshold` recorded), whose pixels
    /// hold different numbers of samples and whose `spp` is only the cap, the mean of the
    /// counts as `spp_mean` after `sample_range` (two decimals). Reading ignores it: `spp`
    /// and `sample_range` still say which samples the file holds.
    pub fn attributes_with_counts(&self, sample_counts: &[f32]) -> Vec<(String, String)> {
        let mut fields = self.fields();
        if self.setting("noise_threshold").is_some() && !sample_counts.is_empty() {
            let sum: f64 = sample_counts.iter().map(|&n| f64::from(n)).sum();
            let mean = sum / sample_counts.len() as f64;
            fields.insert(2, (SPP_MEAN_FIELD.to_string(), format!("{mean:.2}")));
        }
        Self::attribute_of(&fields)
    }

    /// The `vkpath` attribute holding `fields`.
    fn attribute_of(fields: &[(String, String)]) -> Vec<(String, String)> {
        let text: Vec<String> = fields
            .iter()
            .map(|(name, value)| format!("{name}={value}"))
            .collect();
        vec![(ATTRIBUTE_NAME.to_string(), text.join(FIELD_SEPARATOR))]
    }

    /// Reads the metadata back from header attributes (other attributes are ignored).
    pub fn from_attributes(
        attributes: &BTreeMap<String, String>,
    ) -> Result<RenderMetadata, MetadataError> {
        let text = attributes
            .get(ATTRIBUTE_NAME)
            .ok_or(MetadataError::NoAttribute)?;
        let fields: BTreeMap<&str, &str> = text
            .split(FIELD_SEPARATOR)
            .filter_map(|field| field.split_once('='))
            .collect();
        let range = fields
            .get("sample_range")
            .ok_or(MetadataError::NoSampleRange)?;
        let samples =
            parse_range(range).ok_or_else(|| MetadataError::SampleRange(range.to_string()))?;
        let mut settings = Vec::new();
        for name in SETTING_NAMES {
            let value = fields.get(name).ok_or(MetadataError::NoSetting(name))?;
            settings.push((name.to_string(), current_name(value).to_string()));
        }
        for name in OPTIONAL_SETTING_NAMES {
            if let Some(value) = fields.get(name) {
                settings.push((name.to_string(), value.to_string()));
            }
        }
        let image_fields = IMAGE_FIELD_NAMES
            .iter()
            .filter_map(|name| Some((name.to_string(), fields.get(name)?.to_string())))
            .collect();
        let outcome = match (fields.get(SPP_REQUESTED_FIELD), fields.get(STOP_FIELD)) {
            (Some(requested), Some(stop)) => Some(RenderOutcome {
                spp_requested: requested
                    .parse()
                    .map_err(|_| MetadataError::SppRequested(requested.to_string()))?,
                stop: stop.to_string(),
            }),
            _ => None,
        };
        Ok(RenderMetadata {
            settings,
            samples,
            outcome,
            image_fields,
        })
    }

    /// The first setting in which `other` differs, as "name: this vs other".
    pub fn first_difference(&self, other: &RenderMetadata) -> Option<String> {
        let names = SETTING_NAMES.iter().chain(&OPTIONAL_SETTING_NAMES);
        names
            .map(|name| (name, self.setting(name), other.setting(name)))
            .find(|(_, a, b)| a != b)
            .map(|(name, a, b)| {
                let value = |v: Option<&str>| v.unwrap_or("none").to_string();
                format!("{name}: {} vs {}", value(a), value(b))
            })
    }
}

/// How the command line spells a sampler ("pcg", "sobol"), as the metadata records it.
pub fn sampler_name(sampler: SamplerKind) -> &'static str {
    match sampler {
        SamplerKind::Pcg => "pcg",
        SamplerKind::Sobol => "sobol",
    }
}

/// How the command line spells a pixel filter ("box", "center").
pub fn pixel_filter_name(filter: PixelFilter) -> &'static str {
    match filter {
        PixelFilter::Box => "box",
        PixelFilter::Center => "center",
    }
}

/// The command-line name of a value that files written before vkpath 0.1's metadata used
/// the command line's names spelled as Rust names (`PathTracing`, `SolidAngle`, ...), so that
/// their checkpoints and shards still resume and merge; other values are returned as they
/// are.
fn current_name(value: &str) -> &str {
    match value {
        "PathTracing" => "workshop",
        "DirectIllumination" => "direct-illumination",
        "RayTracing" => "ray-tracing",
        "Cosine" => "cosine",
        "Nee" => "nee",
        "Mis" => "mis",
        "Pcg" => "pcg",
        "Sobol" => "sobol",
        "SolidAngle" => "solid-angle",
        "Area" => "area",
        "Box" => "box",
        "Center" => "center",
        other => other,
    }
}

/// "START..END" with START <= END.
pub fn parse_range(text: &str) -> Option<Range<u32>> {
    let (start, end) = text.split_once("..")?;
    let (start, end) = (start.trim().parse().ok()?, end.trim().parse().ok()?);
    (start <= end).then_some(start..end)
}

/// A hash of the scene as loaded (every triangle's positions, normal, albedo, emission and
/// sidedness, in order; the materials, textures, per-triangle shading data and lights where
/// the scene has them) and the camera: the first 16 hex digits of a SHA-256 of their float
/// bits.
pub fn scene_hash(scene: &Scene, camera: &Camera) -> String {
    let mut hasher = Sha256::new();
    // The bits are gathered and hashed in one call per part (the same digest as one call
    // per value, without its cost per call)
    let mut bytes: Vec<u8> = Vec::with_capacity(4 * 19 * scene.triangles.len());
    let add = |bytes: &mut Vec<u8>, values: &[f32]| {
        for value in values {
            bytes.extend_from_slice(&value.to_bits().to_le_bytes());
        }
    };
    for triangle in &scene.triangles {
        for position in triangle.positions {
            add(&mut bytes, &position.to_array());
        }
        add(&mut bytes, &triangle.normal.to_array());
        add(&mut bytes, &triangle.color.to_array());
        add(&mut bytes, &triangle.emission.to_array());
        add(&mut bytes, &[f32::from(u8::from(triangle.double_sided))]);
    }
    hasher.update(&bytes);
    // What plain scenes lack, only when present (plain scenes keep their hashes).
    if let Some(materials) = &scene.materials {
        hasher.update(format!("{:?}", materials.materials).as_bytes());
        for texture in &materials.textures {
            hasher.update(
                format!(
                    "{}x{} {:?} {:?} {}",
                    texture.width, texture.height, texture.wrap_s, texture.wrap_t, texture.nearest
                )
                .as_bytes(),
            );
            hasher.update(texture.texels.as_flattened());
        }
        // The shading data's bits, not their Debug text: formatting the floats of 10^5
        // triangles took a fifth of a glTF scene's set-up
        bytes.clear();
        for shading in &materials.triangles {
            bytes.extend_from_slice(&shading.material.to_le_bytes());
            for normal in shading.normals {
                add(&mut bytes, &normal.to_array());
            }
            for tex_coord in shading.tex_coords {
                add(&mut bytes, &tex_coord.to_array());
            }
            for tangent in shading.tangents {
                add(&mut bytes, &tangent.to_array());
            }
        }
        // The extra vertex attributes where the kernels read them (a scene without them
        // keeps its hash)
        if let Some(colors) = &materials.extra.colors {
            bytes.extend_from_slice(b"COLOR_0");
            for color in colors.as_flattened() {
                add(&mut bytes, &color.to_array());
            }
        }
        if let Some(tex_coords) = &materials.extra.tex_coords_1 {
            bytes.extend_from_slice(b"TEXCOORD_1");
            for tex_coord in tex_coords.as_flattened() {
                add(&mut bytes, &tex_coord.to_array());
            }
        }
        hasher.update(&bytes);
    }
    crate::lights::hash_description(scene, &mut |bytes| hasher.update(bytes));
    bytes.clear();
    for vector in [
        camera.position,
        camera.image_plane_middle,
        camera.up,
        camera.right_per_unit_aspect,
    ] {
        add(&mut bytes, &vector.to_array());
    }
    // A lens only where there is one (pinhole renders keep their hashes), so that a frame
    // rendered without depth of field is not taken for one with it (--skip-existing).
    let lens = &camera.lens;
    if !lens.is_pinhole() {
        add(
            &mut bytes,
            &[
                lens.aperture_radius,
                lens.focus_distance,
                lens.blades as f32,
                lens.rotation,
            ],
        );
    }
    // Motion blur's keys only where there are some (still renders keep their hashes)
    if let Some(motion) = &scene.motion {
        for key in &motion.triangles {
            for triangle in key {
                for position in triangle.positions {
                    add(&mut bytes, &position.to_array());
                }
            }
        }
        for key_camera in &motion.cameras {
            add(&mut bytes, &key_camera.position.to_array());
            add(&mut bytes, &key_camera.image_plane_middle.to_array());
            add(&mut bytes, &key_camera.up.to_array());
            add(&mut bytes, &key_camera.right_per_unit_aspect.to_array());
        }
    }
    hasher.update(&bytes);
    let digest = hasher.finalize();
    digest[..8].iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_without_metadata_are_refused_in_words() {
        let refused = |text: Option<&str>| {
            let attributes: BTreeMap<String, String> = text
                .map(|t| (ATTRIBUTE_NAME.to_string(), t.to_string()))
                .into_iter()
                .collect();
            RenderMetadata::from_attributes(&attributes)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            refused(None),
            "it has no vkpath attribute (not written by vkpath render)"
        );
        assert_eq!(
            refused(Some("spp=4")),
            "its vkpath attribute has no sample_range"
        );
        assert_eq!(
            refused(Some("sample_range=4")),
            "its sample_range '4' is not START..END"
        );
        assert_eq!(
            refused(Some("sample_range=0..4")),
            format!("its vkpath attribute has no {}", SETTING_NAMES[0])
        );
    }

    #[test]
    fn a_plain_scenes_hash_is_what_earlier_versions_wrote() {
        // The built-in box's hash as every version since the hash was introduced wrote it
        // (the build of a7c2ddf), so that their checkpoints resume and merge
        let scene = Scene::builtin_cornell_box().unwrap();
        assert_eq!(
            scene_hash(&scene, &scene.camera.unwrap()),
            "32174f6d22dfdcf7"
        );
    }

    #[test]
    fn every_part_of_the_shading_data_changes_the_hash() {
        let mut scene = Scene::builtin_cornell_box().unwrap();
        let camera = scene.camera.unwrap();
        scene.materials = Some(crate::scene::materials::SceneMaterials::from_plain(
            &scene.triangles,
        ));
        let hash = scene_hash(&scene, &camera);
        let changes: [fn(&mut crate::scene::materials::TriangleShading); 4] = [
            |s| s.material += 1,
            |s| s.normals[2].y = -s.normals[2].y,
            |s| s.tex_coords[1].x += 0.5,
            |s| s.tangents[0].w = -1.0,
        ];
        for change in changes {
            let mut changed = scene.clone();
            change(&mut changed.materials.as_mut().unwrap().triangles[7]);
            assert_ne!(scene_hash(&changed, &camera), hash);
        }
        // The side tables of the extra vertex attributes, each where it exists
        let count = scene.triangles.len();
        let mut coloured = scene.clone();
        let tables = &mut coloured.materials.as_mut().unwrap().extra;
        tables.colors = Some(vec![[glam::Vec4::ONE; 3]; count]);
        let coloured_hash = scene_hash(&coloured, &camera);
        assert_ne!(coloured_hash, hash);
        let tables = &mut coloured.materials.as_mut().unwrap().extra;
        tables.colors.as_mut().unwrap()[7][2].x = 0.5;
        assert_ne!(scene_hash(&coloured, &camera), coloured_hash);
        let mut uv1 = scene.clone();
        uv1.materials.as_mut().unwrap().extra.tex_coords_1 =
            Some(vec![[glam::Vec2::ZERO; 3]; count]);
        assert_ne!(scene_hash(&uv1, &camera), hash);
    }

    #[test]
    fn attributes_round_trip_and_differences_are_named() {
        let scene = Scene::builtin_cornell_box().unwrap();
        let camera = scene.camera.unwrap();
        let settings = RenderSettings::default();
        let metadata = RenderMetadata::new(&settings, &scene, &camera, 4..20);
        let attributes: BTreeMap<String, String> = metadata.attributes().into_iter().collect();
        assert!(attributes["vkpath"].starts_with("spp=16; sample_range=4..20; version="));
        assert_eq!(
            RenderMetadata::from_attributes(&attributes),
            Ok(metadata.clone())
        );
        let mut other_settings = settings.clone();
        other_settings.seed = 7;
        let other = RenderMetadata::new(&other_settings, &scene, &camera, 0..4);
        assert_eq!(
            metadata.first_difference(&other).as_deref(),
            Some("seed: 0 vs 7")
        );
        let mut moved = scene.clone();
        moved.triangles[0].emission.x += 1.0;
        assert_ne!(scene_hash(&scene, &camera), scene_hash(&moved, &camera));
        // The command line's names, and the old Rust-spelled ones read as those.
        let text = &attributes["vkpath"];
        for field in [
            "integrator=workshop",
            "sampler=pcg",
            "light_sampling=solid-angle",
            "pixel_filter=box",
        ] {
            assert!(text.contains(field), "{text} lacks {field}");
        }
        let old: BTreeMap<String, String> = [(
            ATTRIBUTE_NAME.to_string(),
            text.replace("=workshop", "=PathTracing")
                .replace("=solid-angle", "=SolidAngle"),
        )]
        .into();
        assert_eq!(RenderMetadata::from_attributes(&old), Ok(metadata.clone()));
        // A finished image's outcome follows its samples and is read back; files without
        // one (checkpoints, and images of earlier versions) read as none.
        let finished = RenderMetadata {
            outcome: Some(RenderOutcome {
                spp_requested: 64,
                stop: "signal".into(),
            }),
            ..metadata.clone()
        };
        let attributes: BTreeMap<String, String> = finished.attributes().into_iter().collect();
        assert!(attributes["vkpath"]
            .starts_with("spp=16; sample_range=4..20; spp_requested=64; stop=signal; version="));
        let read = RenderMetadata::from_attributes(&attributes).unwrap();
        assert_eq!(read, finished);
        assert!(!read.outcome.unwrap().is_finished());
        // A region and a noise threshold are recorded, read back and told apart.
        let mut region_settings = settings.clone();
        region_settings.region = Some(PixelRegion::parse("1,2,30,40").unwrap());
        region_settings.noise_threshold = Some(crate::render::adaptive::NoiseThreshold {
            threshold: 0.05,
            min_spp: 16,
        });
        let region = RenderMetadata::new(&region_settings, &scene, &camera, 0..4);
        let region_attributes: BTreeMap<String, String> = region.attributes().into_iter().collect();
        assert!(region_attributes["vkpath"]
            .ends_with("region=1,2,30,40; noise_threshold=0.05; noise_min_spp=16"));
        assert_eq!(
            RenderMetadata::from_attributes(&region_attributes),
            Ok(region.clone())
        );
        assert_eq!(
            metadata.first_difference(&region).as_deref(),
            Some("region: none vs 1,2,30,40")
        );
        let window = region.window().unwrap();
        assert_eq!((window.origin, window.full_size), ([1, 2], [512, 512]));
        assert_eq!(metadata.window(), None);
        assert_eq!(parse_range("3..9"), Some(3..9));
        assert_eq!(parse_range("9..3"), None);
        assert_eq!(parse_range("x"), None);
    }

    #[test]
    fn frame_time_and_post_processing_are_read_back_and_compared_but_not_by_merges() {
        let scene = Scene::builtin_cornell_box().unwrap();
        let camera = scene.camera.unwrap();
        let plain = RenderMetadata::new(&RenderSettings::default(), &scene, &camera, 0..4);
        let mut framed = RenderMetadata {
            outcome: Some(RenderOutcome {
                spp_requested: 4,
                stop: "done".into(),
            }),
            ..plain.clone()
        };
        // Set out of order, written in IMAGE_FIELD_NAMES' order after the outcome.
        framed.set_image_field(DENOISE_FIELD, DENOISER_NAME.into());
        framed.set_frame(Some(7), 0.291_666_666_666_666_7);
        let attributes: BTreeMap<String, String> = framed.attributes().into_iter().collect();
        assert!(
            attributes["vkpath"].starts_with(
                "spp=4; sample_range=0..4; spp_requested=4; stop=done; frame=7; \
                 time=0.2916666666666667; denoise=oidn-rt; version="
            ),
            "{}",
            attributes["vkpath"]
        );
        let read = RenderMetadata::from_attributes(&attributes).unwrap();
        assert_eq!(read, framed);
        assert_eq!(read.image_field(FRAME_FIELD), Some("7"));
        // Shards and checkpoints compare settings only; an image is compared field by field.
        assert_eq!(plain.first_difference(&framed), None);
        assert_eq!(
            plain.first_difference_from(&framed),
            Some(("frame".into(), "none".into(), "7".into()))
        );
        let mut other = framed.clone();
        other.set_frame(Some(8), 0.3333);
        assert_eq!(
            framed.first_difference_from(&other),
            Some(("frame".into(), "7".into(), "8".into()))
        );
        assert_eq!(framed.first_difference_from(&read), None);
    }

    #[test]
    fn an_adaptive_render_records_its_mean_samples_beside_spp_and_sample_range() {
        let scene = Scene::builtin_cornell_box().unwrap();
        let camera = scene.camera.unwrap();
        let mut settings = RenderSettings::default();
        let uniform = RenderMetadata::new(&settings, &scene, &camera, 0..1024);
        // A uniform render's attribute stays as it was: every pixel holds `spp`.
        assert_eq!(
            uniform.attributes_with_counts(&[1024.0; 4]),
            uniform.attributes()
        );
        settings.noise_threshold = Some(crate::render::adaptive::NoiseThreshold {
            threshold: 0.05,
            min_spp: 16,
        });
        let adaptive = RenderMetadata::new(&settings, &scene, &camera, 0..1024);
        let attributes: BTreeMap<String, String> = adaptive
            .attributes_with_counts(&[16.0, 1024.0, 100.0, 101.0])
            .into_iter()
            .collect();
        assert!(
            attributes["vkpath"].starts_with("spp=1024; sample_range=0..1024; spp_mean=310.25; "),
            "{}",
            attributes["vkpath"]
        );
        // Merge and resume read `spp` and `sample_range`, and nothing else changes.
        assert_eq!(RenderMetadata::from_attributes(&attributes), Ok(adaptive));
    }
}
