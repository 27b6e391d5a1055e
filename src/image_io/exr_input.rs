//! Reading OpenEXR images back (for `vkpath compare`): the R, G, B channels of the first
//! layer as mean radiance, and, when the file has them (`vkpath render --moments`), each
//! pixel's second moment and sample count.

use std::path::Path;

use exr::prelude::{read_first_flat_layer_from_file, AnyChannel, FlatSamples};

use crate::image_io::data::RenderedImage;
use crate::image_io::error::{ImageError, ImageResult as Result};
use crate::image_io::output::{SAMPLE_COUNT_CHANNEL, SECOND_MOMENT_CHANNELS};

/// An EXR image as read back.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrImage {
    /// The pixels, rows top-down. Without moments, `second_moment` holds the squared mean
    /// and `sample_count` is 1 everywhere: the file says nothing about the noise.
    pub image: RenderedImage,
    /// Whether the file had the second-moment and sample-count channels.
    pub has_moments: bool,
}

/// Reads an OpenEXR file written by `vkpath render` (or any EXR with R, G and B channels in
/// its first layer, of any sample type). Alpha is set to 1. The moment channels are used
/// only when all four (`SECOND_MOMENT_CHANNELS` and `SAMPLE_COUNT_CHANNEL`) are present; a
/// file with only some of them is an error, since it cannot have come from vkpath intact.
pub fn read_exr(path: &Path) -> Result<ExrImage> {
    let fail = |message: String| ImageError::read(path, message);
    if !path.is_file() {
        return Err(fail("no such file".into()));
    }
    // A header may claim any size: refuse a hostile one before a pixel is read.
    check_exr_size(path).map_err(&fail)?;
    let file = read_first_flat_layer_from_file(path).map_err(|e| fail(e.to_string()))?;
    let layer = &file.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let pixel_count = width * height;
    let find = |name: &str| -> Option<&AnyChannel<FlatSamples>> {
        layer
            .channel_data
            .list
            .iter()
            .find(|channel| channel.name.eq(name))
    };
    let values = |name: &str| -> Option<Vec<f32>> {
        find(name).map(|channel| channel.sample_data.values_as_f32().collect())
    };
    let (Some(red), Some(green), Some(blue)) = (values("R"), values("G"), values("B")) else {
        return Err(fail("it has no R, G and B channels".into()));
    };
    let moment_names = [
        SECOND_MOMENT_CHANNELS[0],
        SECOND_MOMENT_CHANNELS[1],
        SECOND_MOMENT_CHANNELS[2],
        SAMPLE_COUNT_CHANNEL,
    ];
    let moments: Vec<Option<Vec<f32>>> = moment_names.iter().map(|name| values(name)).collect();
    let present = moments.iter().filter(|m| m.is_some()).count();
    if present != 0 && present != moments.len() {
        return Err(fail(format!(
            "it has only some of the moment channels {moment_names:?}"
        )));
    }
    let channels = [&red, &green, &blue];
    if channels.iter().any(|c| c.len() != pixel_count)
        || moments.iter().flatten().any(|m| m.len() != pixel_count)
    {
        return Err(fail(
            "a channel does not cover the whole image (subsampled channels are not supported)"
                .into(),
        ));
    }
    // Statistics over infinite or NaN pixels mean nothing (inf - inf is NaN, inf <= inf
    // holds): such an image cannot be compared.
    let non_finite = channels
        .iter()
        .map(|c| c.iter().filter(|v| !v.is_finite()).count())
        .sum::<usize>()
        + moments
            .iter()
            .flatten()
            .map(|m| m.iter().filter(|v| !v.is_finite()).count())
            .sum::<usize>();
    if non_finite > 0 {
        return Err(fail(format!(
            "{non_finite} of its values are infinite or NaN; it cannot be compared"
        )));
    }
    let mean: Vec<[f32; 4]> = (0..pixel_count)
        .map(|i| [red[i], green[i], blue[i], 1.0])
        .collect();
    let has_moments = present == moments.len();
    let (second_moment, sample_count) = match moments.as_slice() {
        [Some(r), Some(g), Some(b), Some(n)] => (
            (0..pixel_count).map(|i| [r[i], g[i], b[i]]).collect(),
            n.clone(),
        ),
        _ => (
            mean.iter()
                .map(|m| [m[0] * m[0], m[1] * m[1], m[2] * m[2]])
                .collect(),
            vec![1.0; pixel_count],
        ),
    };
    Ok(ExrImage {
        image: RenderedImage {
            width: width as u32,
            height: height as u32,
            mean,
            second_moment,
            sample_count,
        },
        has_moments,
    })
}

/// Most pixels an EXR that vkpath reads may claim (the check happens on the header, before
/// any pixel is read): 2^28, a 16384 x 16384 image.
pub const MAX_EXR_PIXELS: usize = 1 << 28;

/// Refuses an EXR whose header claims more than `MAX_EXR_PIXELS` (read before any pixel,
/// so that a hostile header cannot make vkpath allocate terabytes).
pub fn check_exr_size(path: &Path) -> std::result::Result<(), String> {
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| e.to_string())?;
    for header in meta.headers.iter() {
        let (width, height) = (header.layer_size.width(), header.layer_size.height());
        if width
            .checked_mul(height)
            .is_none_or(|pixels| pixels > MAX_EXR_PIXELS)
        {
            return Err(format!(
                "its header claims {width}x{height} pixels, more than the {MAX_EXR_PIXELS} vkpath reads"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image_io::output::{save_image, SaveOptions};

    fn test_image() -> RenderedImage {
        RenderedImage {
            width: 3,
            height: 2,
            mean: (0..6)
                .map(|i| [i as f32, 0.5, 2.0 * i as f32, 1.0])
                .collect(),
            second_moment: (0..6).map(|i| [i as f32 * 1.5, 0.3, 7.0]).collect(),
            sample_count: vec![16.0; 6],
        }
    }

    #[test]
    fn round_trip_with_and_without_moments() {
        let dir = tempfile::tempdir().unwrap();
        let image = test_image();
        let with = dir.path().join("with.exr");
        save_image(
            &with,
            &image,
            &SaveOptions {
                moments: true,
                ..Default::default()
            },
        )
        .unwrap();
        let read = read_exr(&with).unwrap();
        assert!(read.has_moments);
        assert_eq!(read.image, image);

        let without = dir.path().join("without.exr");
        save_image(&without, &image, &SaveOptions::default()).unwrap();
        let read = read_exr(&without).unwrap();
        assert!(!read.has_moments);
        assert_eq!(read.image.mean, image.mean);
        assert_eq!(read.image.sample_count, vec![1.0; 6]);
    }

    #[test]
    fn partial_moments_and_missing_colours_are_errors() {
        use exr::prelude::{AnyChannels, Image, WritableImage};
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, channels: &[&str]| {
            let list: Vec<AnyChannel<FlatSamples>> = channels
                .iter()
                .map(|c| AnyChannel::new(*c, FlatSamples::F32(vec![1.0; 4])))
                .collect();
            let path = dir.path().join(name);
            Image::from_channels((2, 2), AnyChannels::sort(list.into()))
                .write()
                .to_file(&path)
                .unwrap();
            read_exr(&path).map_err(|e| e.to_string())
        };
        let partial = write("partial.exr", &["R", "G", "B", SAMPLE_COUNT_CHANNEL]).unwrap_err();
        assert!(
            partial.contains("only some of the moment channels"),
            "{partial}"
        );
        let grey = write("grey.exr", &["Y"]).unwrap_err();
        assert!(grey.contains("no R, G and B"), "{grey}");
        let plain = write("plain.exr", &["B", "G", "R"]).unwrap();
        assert!(!plain.has_moments && plain.image.mean == vec![[1.0; 4]; 4]);
    }

    #[test]
    fn missing_and_malformed_files_name_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.exr");
        let message = read_exr(&missing).unwrap_err().to_string();
        assert!(
            message.contains("missing.exr") && message.contains("no such file"),
            "{message}"
        );
        let garbage = dir.path().join("garbage.exr");
        std::fs::write(&garbage, b"not an exr").unwrap();
        let message = read_exr(&garbage).unwrap_err().to_string();
        assert!(message.contains("garbage.exr"), "{message}");
    }
}
