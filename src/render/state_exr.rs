//! The EXR files that hold a render's raw state: checkpoints, shards and merged images. They
//! are ordinary EXR images (R, G, B, A: the mean; the second moment and sample count, as
//! `render --moments` writes them) with the accumulation layers beside them (`state.*`
//! channels: the Kahan sums and compensations, the sample and ray counts, the sums of
//! squares) and the render's metadata as `vkpath.*` header attributes; a guided render's
//! guide is frozen into them too (`GUIDE_ATTRIBUTE`). A resumed render uploads the state
//! and goes on bit for bit; `vkpath merge` adds shards.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use exr::prelude::{read_first_flat_layer_from_file, AttributeValue};

use crate::contract;
use crate::error::{Error, Result};
use crate::guiding::Guide;
use crate::image_io::exr_input::{check_exr_file, check_exr_size, plain_cause, read_exr_channels};
use crate::image_io::output::{
    layer_attributes, layer_channels, read_png_texts, write_atomically, write_exr_channels,
    ByteAttribute, ImageFormat, ImageLayer, SAMPLE_COUNT_CHANNEL, SECOND_MOMENT_CHANNELS,
};
use crate::image_io::ImageError;
use crate::render::accumulation::Accumulation;
use crate::render::metadata::{RenderMetadata, RenderOutcome, ATTRIBUTE_NAME};

/// The state channels, four per accumulation layer (`LAYER_SUM`, `LAYER_COMPENSATION`,
/// `LAYER_SUM_OF_SQUARES`), in the texel order r, g, b, a.
pub const STATE_CHANNELS: [[&str; 4]; 3] = [
    [
        "state.sum.R",
        "state.sum.G",
        "state.sum.B",
        "state.sample_count",
    ],
    [
        "state.compensation.R",
        "state.compensation.G",
        "state.compensation.B",
        "state.ray_count",
    ],
    [
        "state.sum_of_squares.R",
        "state.sum_of_squares.G",
        "state.sum_of_squares.B",
        "state.loop_limit_flag",
    ],
];

/// The header attribute (of the EXR `bytes` type) that holds a guided render's guide: its
/// guided cells' words (`vkpath::guiding::Guide::sparse_words`), little-endian.
pub const GUIDE_ATTRIBUTE: &str = "vkpath.guide";
/// The type hint of `GUIDE_ATTRIBUTE`.
const GUIDE_TYPE_HINT: &str = "vkpath guide: u32 words of its guided cells, little-endian";

/// Writes `state` (with `metadata`, and its guide if it has one) to `path` atomically.
pub fn write_state(path: &Path, state: &Accumulation, metadata: &RenderMetadata) -> Result<()> {
    write_state_with_layers(path, state, metadata, &StateLayers::default())
}

/// The layers a shard carries beside its state (issue 56): the ground truth and the
/// Cryptomatte (`Aov::goes_into_shards`), the same in every shard of a render, which
/// `vkpath merge` checks and keeps bit for bit (`merge_state_layers`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StateLayers {
    /// The channels (`object_id.Z`, `CryptoObject00.R`, ...), one value per pixel.
    pub channels: Vec<(String, Vec<f32>)>,
    /// The header attributes they bring (`cryptomatte/<key>/...`).
    pub attributes: Vec<(String, String)>,
}

impl StateLayers {
    /// The channels and attributes of `layers`.
    pub fn of(layers: &[ImageLayer]) -> StateLayers {
        StateLayers {
            channels: layer_channels(layers),
            attributes: layer_attributes(layers),
        }
    }

    /// The layers of a file that `write_state_with_layers` wrote: its channels that are
    /// neither the image's nor the state's, and its `cryptomatte/` attributes. Reads no pixel
    /// where the header lists no such channel.
    pub fn read(path: &Path) -> Result<StateLayers> {
        let fail = |message: String| Error::from(ImageError::read(path, message));
        let meta =
            exr::meta::MetaData::read_from_file(path, false).map_err(|e| fail(plain_cause(&e)))?;
        let is_layer = |name: &str| {
            let image = ["R", "G", "B", "A", SAMPLE_COUNT_CHANNEL];
            !image.contains(&name)
                && !SECOND_MOMENT_CHANNELS.contains(&name)
                && !STATE_CHANNELS.iter().flatten().any(|&c| c == name)
        };
        let listed = meta.headers.iter().flat_map(|h| h.channels.list.iter());
        if !listed.into_iter().any(|c| is_layer(&c.name.to_string())) {
            return Ok(StateLayers::default());
        }
        let channels = read_exr_channels(path)?
            .channels
            .into_iter()
            .filter(|(name, _)| is_layer(name))
            .collect();
        let attributes = read_text_attributes(path)?
            .into_iter()
            .filter(|(name, _)| name.starts_with("cryptomatte/"))
            .collect();
        Ok(StateLayers {
            channels,
            attributes,
        })
    }
}

/// The layers of shards (`StateLayers::read`), which must be the same bit for bit (the first
/// channel or attribute that differs is named, with both files).
pub fn merge_state_layers(paths: &[std::path::PathBuf]) -> Result<StateLayers> {
    let mut first: Option<(&std::path::PathBuf, StateLayers)> = None;
    for path in paths {
        let layers = StateLayers::read(path)?;
        let Some((first_path, first_layers)) = &first else {
            first = Some((path, layers));
            continue;
        };
        let names = |l: &StateLayers| l.channels.iter().map(|c| c.0.clone()).collect::<Vec<_>>();
        let bits = |values: &[f32]| values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let difference = if names(first_layers) != names(&layers) {
            Some(format!(
                "their layers differ ({} and {})",
                names(first_layers).join(","),
                names(&layers).join(",")
            ))
        } else if first_layers.attributes != layers.attributes {
            Some("their Cryptomatte manifests differ".to_owned())
        } else {
            let pairs = first_layers.channels.iter().zip(&layers.channels);
            pairs
                .into_iter()
                .find(|(a, b)| bits(&a.1) != bits(&b.1))
                .map(|(a, _)| format!("their {} channels differ", a.0))
        };
        if let Some(difference) = difference {
            return Err(Error::InvalidSettings(format!(
                "'{}' and '{}' are not shards of one render: {difference}",
                first_path.display(),
                path.display()
            )));
        }
    }
    Ok(first.map(|(_, layers)| layers).unwrap_or_default())
}

/// `write_state` with `layers` beside the state (a shard's ground truth, a merge's).
pub fn write_state_with_layers(
    path: &Path,
    state: &Accumulation,
    metadata: &RenderMetadata,
    layers: &StateLayers,
) -> Result<()> {
    let image = state.image();
    let pixels = (state.width * state.height) as usize;
    let mut channels: Vec<(String, Vec<f32>)> = ["R", "G", "B", "A"]
        .iter()
        .enumerate()
        .map(|(c, name)| (name.to_string(), image.mean.iter().map(|p| p[c]).collect()))
        .collect();
    for (c, name) in SECOND_MOMENT_CHANNELS.iter().enumerate() {
        channels.push((
            name.to_string(),
            image.second_moment.iter().map(|p| p[c]).collect(),
        ));
    }
    channels.push((SAMPLE_COUNT_CHANNEL.to_string(), image.sample_count.clone()));
    for (layer, names) in STATE_CHANNELS.iter().enumerate() {
        let texels = &state.texels[layer * pixels..(layer + 1) * pixels];
        for (c, name) in names.iter().enumerate() {
            channels.push((name.to_string(), texels.iter().map(|t| t[c]).collect()));
        }
    }
    let guide_attribute: Vec<ByteAttribute> = state
        .guide
        .iter()
        .map(|guide| ByteAttribute {
            name: GUIDE_ATTRIBUTE.to_string(),
            type_hint: GUIDE_TYPE_HINT.to_string(),
            bytes: guide
                .sparse_words()
                .iter()
                .flat_map(|w| w.to_le_bytes())
                .collect(),
        })
        .collect();
    channels.extend(layers.channels.iter().cloned());
    let mut attributes = metadata.attributes_with_counts(&image.sample_count);
    attributes.extend(layers.attributes.iter().cloned());
    write_atomically(path, |temporary| {
        write_exr_channels(
            temporary,
            state.width,
            state.height,
            channels,
            &attributes,
            &guide_attribute,
            metadata.window(),
        )
    })?;
    Ok(())
}

/// The render metadata that a vkpath EXR records (`vkpath render`'s images, checkpoints,
/// shards, merged files), read from its header alone: no pixel is read. A file without the
/// metadata is refused with a message that says so.
pub fn read_metadata(path: &Path) -> Result<RenderMetadata> {
    let attributes = read_text_attributes(path)?;
    let fail = |message: String| Error::from(ImageError::read(path, message));
    RenderMetadata::from_attributes(&attributes).map_err(|e| fail(e.to_string()))
}

/// The render metadata of an image that `vkpath render` may have written, EXR or PNG (its
/// `vkpath` tEXt chunk), read without its pixels: none for an image without it (another
/// program's, or a PNG of a version before the chunk).
pub fn read_image_metadata(path: &Path) -> Result<Option<RenderMetadata>> {
    let fail = |message: String| Error::from(ImageError::read(path, message));
    let attributes = match ImageFormat::from_path(path)? {
        ImageFormat::Exr => read_text_attributes(path)?,
        ImageFormat::Png => read_png_texts(path).map_err(|e| fail(e.to_string()))?,
    };
    if !attributes.contains_key(ATTRIBUTE_NAME) {
        return Ok(None);
    }
    RenderMetadata::from_attributes(&attributes)
        .map(Some)
        .map_err(|e| fail(e.to_string()))
}

/// The text attributes of an EXR's headers (name to text), read from the headers alone: no
/// pixel is read. vkpath's metadata is the one named `metadata::ATTRIBUTE_NAME`.
pub fn read_text_attributes(path: &Path) -> Result<BTreeMap<String, String>> {
    let fail = |message: String| Error::from(ImageError::read(path, message));
    check_exr_file(path, None)?;
    let meta =
        exr::meta::MetaData::read_from_file(path, false).map_err(|e| fail(plain_cause(&e)))?;
    let mut attributes = BTreeMap::new();
    for header in meta.headers.iter() {
        let both = header
            .shared_attributes
            .other
            .iter()
            .chain(header.own_attributes.other.iter());
        for (name, value) in both {
            if let AttributeValue::Text(text) = value {
                attributes.insert(name.to_string(), text.to_string());
            }
        }
    }
    Ok(attributes)
}

/// Why a state channel of a file that `read_state` reads is unusable, in the words that
/// follow the file's name.
#[derive(Debug, thiserror::Error)]
enum StateChannelError {
    /// The file lacks the channel.
    #[error("it has no {0} channel (not a checkpoint or shard of vkpath render)")]
    Missing(String),
    /// The channel has fewer or more values than the image has pixels.
    #[error("its {0} channel does not cover the image")]
    Short(String),
}

/// Reads a file that `write_state` wrote: the state and its metadata. Files without the
/// state channels or the metadata, or claiming more than `MAX_EXR_PIXELS`, are refused
/// with a message that says so.
pub fn read_state(path: &Path) -> Result<(Accumulation, RenderMetadata)> {
    let fail = |message: String| Error::from(ImageError::read(path, message));
    check_exr_file(path, None)?;
    check_exr_size(path).map_err(|e| fail(e.to_string()))?;
    let file = read_first_flat_layer_from_file(path).map_err(|e| fail(plain_cause(&e)))?;
    let mut attributes = BTreeMap::new();
    let mut guide = None;
    for (name, value) in file
        .attributes
        .other
        .iter()
        .chain(file.layer_data.attributes.other.iter())
    {
        match value {
            AttributeValue::Text(text) => {
                attributes.insert(name.to_string(), text.to_string());
            }
            AttributeValue::Bytes { bytes, .. } if name.eq(GUIDE_ATTRIBUTE) => {
                if bytes.len() % 4 != 0 {
                    return Err(fail(format!("its {GUIDE_ATTRIBUTE} is not whole words")));
                }
                let words: Vec<u32> = bytes
                    .chunks_exact(4)
                    .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    .collect();
                let frozen = Guide::from_sparse_words(&words)
                    .map_err(|e| fail(format!("its {GUIDE_ATTRIBUTE}: {e}")))?;
                guide = Some(Arc::new(frozen));
            }
            _ => {}
        }
    }
    let metadata = RenderMetadata::from_attributes(&attributes).map_err(|e| fail(e.to_string()))?;
    let layer = &file.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let pixels = width * height;
    let channel = |name: &str| -> std::result::Result<Vec<f32>, StateChannelError> {
        let values: Vec<f32> = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq(name))
            .ok_or_else(|| StateChannelError::Missing(name.into()))?
            .sample_data
            .values_as_f32()
            .collect();
        if values.len() == pixels {
            Ok(values)
        } else {
            Err(StateChannelError::Short(name.into()))
        }
    };
    let mut texels = vec![[0.0f32; 4]; pixels * contract::ACCUMULATION_LAYER_COUNT as usize];
    for (layer_index, names) in STATE_CHANNELS.iter().enumerate() {
        for (c, name) in names.iter().enumerate() {
            let values = channel(name).map_err(|e| fail(e.to_string()))?;
            for (pixel, value) in values.into_iter().enumerate() {
                texels[layer_index * pixels + pixel][c] = value;
            }
        }
    }
    let state = Accumulation {
        width: width as u32,
        height: height as u32,
        texels,
        samples: metadata.samples.clone(),
        guide,
    };
    Ok((state, metadata))
}

/// Reads shards (files `write_state` wrote) and merges them: every shard must come from the
/// same render (the first setting that differs is named, with both files) and their sample
/// ranges must tile one range (overlaps and gaps are named). Returns the merged state and
/// its metadata, whose outcome (when the shards record theirs) asks for the merged samples
/// and says `done` unless a shard stopped early (then that shard's stop).
pub fn merge_state_files(paths: &[std::path::PathBuf]) -> Result<(Accumulation, RenderMetadata)> {
    let mut states = Vec::new();
    let mut stops = Vec::new();
    let mut first: Option<(&std::path::PathBuf, RenderMetadata)> = None;
    for path in paths {
        let (state, metadata) = read_state(path)?;
        stops.extend(metadata.outcome.as_ref().map(|o| o.stop.clone()));
        match &first {
            None => first = Some((path, metadata)),
            Some((first_path, first_metadata)) => {
                if let Some(difference) = first_metadata.first_difference(&metadata) {
                    return Err(Error::InvalidSettings(format!(
                        "'{}' and '{}' are not shards of one render: {difference}",
                        first_path.display(),
                        path.display()
                    )));
                }
            }
        }
        states.push(state);
    }
    if !Accumulation::same_guide(&states.iter().collect::<Vec<_>>()) {
        log::warn!(
            "the shards sampled with different guides (trained on other devices or drivers?): \
             the merged image is unbiased, but not bit for bit the single render's, and keeps \
             no guide"
        );
    }
    let merged = Accumulation::merge(&states)
        .map_err(|e| Error::InvalidSettings(format!("cannot merge: {e}")))?;
    let mut metadata = first
        .map(|(_, m)| m)
        .ok_or_else(|| Error::InvalidSettings("no shards to merge".into()))?;
    metadata.samples = merged.samples.clone();
    metadata.outcome = (!stops.is_empty()).then(|| RenderOutcome {
        spp_requested: merged.samples.len() as u32,
        stop: stops
            .into_iter()
            .find(|stop| stop != "done")
            .unwrap_or_else(|| "done".into()),
    });
    Ok((merged, metadata))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::settings::RenderSettings;
    use crate::scene::Scene;

    #[test]
    fn state_round_trips_bit_for_bit() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("state.exr");
        let scene = Scene::builtin_cornell_box().unwrap();
        let metadata = RenderMetadata::new(
            &RenderSettings::default(),
            &scene,
            &scene.camera.unwrap(),
            8..24,
        );
        let mut state = Accumulation::empty(3, 2, 8);
        for (i, texel) in state.texels.iter_mut().enumerate() {
            *texel = [
                i as f32 * 0.1,
                -1e-9 * i as f32,
                f32::MAX / (i + 1) as f32,
                16.0,
            ];
        }
        state.samples = 8..24;
        write_state(&path, &state, &metadata).unwrap();
        let (read, read_metadata) = read_state(&path).unwrap();
        assert_eq!(read, state);
        assert_eq!(read_metadata, metadata);
        // The header alone gives the same metadata.
        assert_eq!(super::read_metadata(&path).unwrap(), metadata);
        // An image without the state is refused with a reason; without the metadata too.
        let plain = dir.path().join("plain.exr");
        crate::image_io::output::save_image(&plain, &state.image(), &Default::default()).unwrap();
        let message = read_state(&plain).unwrap_err().to_string();
        assert!(message.contains("no vkpath attribute"), "{message}");
        let message = super::read_metadata(&plain).unwrap_err().to_string();
        assert!(message.contains("no vkpath attribute"), "{message}");
    }

    #[test]
    fn a_guided_state_keeps_its_guide_and_the_same_state_the_same_file() {
        let dir = tempfile::tempdir().unwrap();
        let scene = Scene::builtin_cornell_box().unwrap();
        let metadata = RenderMetadata::new(
            &RenderSettings::default(),
            &scene,
            &scene.camera.unwrap(),
            0..4,
        );
        let mut state = Accumulation::empty(4, 2, 0);
        state.samples = 0..4;
        let grid =
            crate::guiding::GuideGrid::around(glam::Vec3::ZERO, glam::Vec3::new(2.0, 1.0, 1.0), 2);
        let mut splats = crate::guiding::GuideSplats::new(grid);
        for i in 0..500 {
            let direction = glam::Vec3::new((i as f32).sin(), (i as f32).cos(), 0.5).normalize();
            splats.splat(
                glam::Vec3::splat(0.5),
                glam::Vec3::X,
                direction,
                1.0 + i as f32,
            );
        }
        let guide = splats.build();
        assert_eq!(guide.guided_cell_count(), 1);
        state.guide = Some(Arc::new(guide));
        let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.exr"));
        write_state(&a, &state, &metadata).unwrap();
        write_state(&b, &state, &metadata).unwrap();
        let (read, _) = read_state(&a).unwrap();
        assert_eq!(read, state);
        // Text and bytes live in separate attribute maps, so their order is fixed.
        assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    }
}
