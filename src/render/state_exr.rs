//! The EXR files that hold a render's raw state: checkpoints, shards and merged images. They
//! are ordinary EXR images (R, G, B, A: the mean; the second moment and sample count, as
//! `render --moments` writes them) with the accumulation layers beside them (`state.*`
//! channels: the Kahan sums and compensations, the sample and ray counts, the sums of
//! squares) and the render's metadata as `vkpath.*` header attributes. A resumed render
//! uploads the state and goes on bit for bit; `vkpath merge` adds shards.

use std::collections::BTreeMap;
use std::path::Path;

use exr::prelude::{read_first_flat_layer_from_file, AttributeValue};

use crate::contract;
use crate::error::{Error, Result};
use crate::image_io::exr_input::check_exr_size;
use crate::image_io::output::{
    write_atomically, write_exr_channels, SAMPLE_COUNT_CHANNEL, SECOND_MOMENT_CHANNELS,
};
use crate::image_io::ImageError;
use crate::render::accumulation::Accumulation;
use crate::render::metadata::RenderMetadata;

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

/// Writes `state` (with `metadata`) to `path` atomically.
pub fn write_state(path: &Path, state: &Accumulation, metadata: &RenderMetadata) -> Result<()> {
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
    write_atomically(path, |temporary| {
        write_exr_channels(
            temporary,
            state.width,
            state.height,
            channels,
            &metadata.attributes(),
            metadata.window(),
        )
    })?;
    Ok(())
}

/// Reads a file that `write_state` wrote: the state and its metadata. Files without the
/// state channels or the metadata, or claiming more than `MAX_EXR_PIXELS`, are refused
/// with a message that says so.
pub fn read_state(path: &Path) -> Result<(Accumulation, RenderMetadata)> {
    let fail = |message: String| Error::from(ImageError::read(path, message));
    check_exr_size(path).map_err(&fail)?;
    let file = read_first_flat_layer_from_file(path).map_err(|e| fail(e.to_string()))?;
    let mut attributes = BTreeMap::new();
    for (name, value) in file
        .attributes
        .other
        .iter()
        .chain(file.layer_data.attributes.other.iter())
    {
        if let AttributeValue::Text(text) = value {
            attributes.insert(name.to_string(), text.to_string());
        }
    }
    let metadata = RenderMetadata::from_attributes(&attributes).map_err(&fail)?;
    let layer = &file.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let pixels = width * height;
    let channel = |name: &str| -> std::result::Result<Vec<f32>, String> {
        let values: Vec<f32> = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq(name))
            .ok_or_else(|| {
                format!("it has no {name} channel (not a checkpoint or shard of vkpath render)")
            })?
            .sample_data
            .values_as_f32()
            .collect();
        if values.len() == pixels {
            Ok(values)
        } else {
            Err(format!("its {name} channel does not cover the image"))
        }
    };
    let mut texels = vec![[0.0f32; 4]; pixels * contract::ACCUMULATION_LAYER_COUNT as usize];
    for (layer_index, names) in STATE_CHANNELS.iter().enumerate() {
        for (c, name) in names.iter().enumerate() {
            for (pixel, value) in channel(name).map_err(&fail)?.into_iter().enumerate() {
                texels[layer_index * pixels + pixel][c] = value;
            }
        }
    }
    let state = Accumulation {
        width: width as u32,
        height: height as u32,
        texels,
        samples: metadata.samples.clone(),
    };
    Ok((state, metadata))
}

/// Reads shards (files `write_state` wrote) and merges them: every shard must come from the
/// same render (the first setting that differs is named, with both files) and their sample
/// ranges must tile one range (overlaps and gaps are named). Returns the merged state and
/// its metadata.
pub fn merge_state_files(paths: &[std::path::PathBuf]) -> Result<(Accumulation, RenderMetadata)> {
    let mut states = Vec::new();
    let mut first: Option<(&std::path::PathBuf, RenderMetadata)> = None;
    for path in paths {
        let (state, metadata) = read_state(path)?;
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
    let merged = Accumulation::merge(&states)
        .map_err(|e| Error::InvalidSettings(format!("cannot merge: {e}")))?;
    let mut metadata = first
        .map(|(_, m)| m)
        .ok_or_else(|| Error::InvalidSettings("no shards to merge".into()))?;
    metadata.samples = merged.samples.clone();
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
        // An image without the state is refused with a reason.
        let plain = dir.path().join("plain.exr");
        crate::image_io::output::save_image(&plain, &state.image(), &Default::default()).unwrap();
        let message = read_state(&plain).unwrap_err().to_string();
        assert!(message.contains("no vkpath attribute"), "{message}");
    }
}
