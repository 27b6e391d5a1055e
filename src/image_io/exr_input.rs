//! Reading OpenEXR images back (for `vkpath compare`): the R, G, B channels of the first
//! layer as mean radiance, and, when the file has them (`vkpath render --moments`), each
//! pixel's second moment and sample count.

use std::path::Path;

use exr::prelude::{
    read_first_flat_layer_from_file, AnyChannel, AnyChannels, FlatSamples, Image, Layer,
};

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
    let file = read_checked_first_layer(path)?;
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

/// The first layer of an OpenEXR file, all of its channels as flat samples, read after the
/// file's magic number and its header's size were checked (a header may claim any size:
/// a hostile one is refused before a pixel is read).
fn read_checked_first_layer(path: &Path) -> Result<Image<Layer<AnyChannels<FlatSamples>>>> {
    let fail = |message: String| ImageError::read(path, message);
    check_exr_file(path, None)?;
    check_exr_size(path).map_err(|e| fail(e.to_string()))?;
    read_first_flat_layer_from_file(path).map_err(|e| fail(plain_cause(&e)))
}

/// Every channel of an EXR's first layer, by name, in the file's order (alphabetical), as
/// float32: what `read_exr` picks R, G, B and the moments from, with the AOV layers
/// (`albedo.R`, `depth.Z`, `noisy.G`, ...) and the render state beside them.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrChannels {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Each channel's name and its `width * height` values, rows top-down.
    pub channels: Vec<(String, Vec<f32>)>,
}

/// Reads every channel of an OpenEXR file's first layer (checked as `read_exr` checks the
/// file); a channel that does not cover the whole image is an error.
pub fn read_exr_channels(path: &Path) -> Result<ExrChannels> {
    let fail = |message: String| ImageError::read(path, message);
    let file = read_checked_first_layer(path)?;
    let layer = &file.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let channels: Vec<(String, Vec<f32>)> = layer
        .channel_data
        .list
        .iter()
        .map(|channel| {
            (
                channel.name.to_string(),
                channel.sample_data.values_as_f32().collect(),
            )
        })
        .collect();
    if channels
        .iter()
        .any(|(_, values)| values.len() != width * height)
    {
        return Err(fail(
            "a channel does not cover the whole image (subsampled channels are not supported)"
                .into(),
        ));
    }
    Ok(ExrChannels {
        width: width as u32,
        height: height as u32,
        channels,
    })
}

/// The four bytes every OpenEXR file starts with (its magic number 20000630, little-endian).
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Checks, before anything is decoded, that `path` is a regular file that starts as an
/// OpenEXR file does; the error names what it is instead (missing, a directory, a PNG, ...)
/// and, for a file of the wrong kind, what `reader` reads when given (e.g. "`vkpath merge`
/// reads the OpenEXR shards of ..."), so that a wrong file is not reported in the EXR
/// decoder's words ("file identifier missing").
pub fn check_exr_file(path: &Path, reader: Option<&str>) -> Result<()> {
    match (exr_file_problem(path), reader) {
        (None, _) => Ok(()),
        (Some(problem), Some(reader)) if problem != NO_SUCH_FILE => {
            Err(ImageError::read(path, format!("{problem} ({reader})")))
        }
        (Some(problem), _) => Err(ImageError::read(path, problem)),
    }
}

/// What `exr_file_problem` says of a path where there is nothing.
const NO_SUCH_FILE: &str = "no such file";

/// What keeps `path` from being an OpenEXR file, in words, or `None` when it starts like
/// one.
fn exr_file_problem(path: &Path) -> Option<String> {
    use std::io::Read as _;
    let metadata = match std::fs::metadata(path) {
        Ok(metadata) => metadata,
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
            return Some(NO_SUCH_FILE.into())
        }
        Err(error) => return Some(error.to_string()),
    };
    if metadata.is_dir() {
        return Some("it is a directory, not a file".into());
    }
    if !metadata.is_file() {
        return Some("it is not a regular file".into());
    }
    let mut start = Vec::with_capacity(8);
    let read = std::fs::File::open(path).and_then(|file| file.take(8).read_to_end(&mut start));
    if let Err(error) = read {
        return Some(error.to_string());
    }
    if start.starts_with(&EXR_MAGIC) {
        return None;
    }
    let what = if start.is_empty() {
        return Some("it is empty, not an OpenEXR file".into());
    } else if start.starts_with(b"\x89PNG") {
        "a PNG image"
    } else if start.starts_with(b"#?") {
        "a Radiance HDR image"
    } else if start.starts_with(&[0xff, 0xd8, 0xff]) {
        "a JPEG image"
    } else if EXR_MAGIC.starts_with(&start) {
        return Some("it is truncated: it ends inside the OpenEXR header".into());
    } else {
        return Some(
            "it is not an OpenEXR file (it does not start with the OpenEXR magic number)".into(),
        );
    };
    Some(format!("it is {what}, not an OpenEXR file"))
}

/// The message of a failed read in plain words: a file that ends too early makes Rust's
/// readers say "failed to fill whole buffer", which is said here as "the file is truncated
/// (it ends before its image data does)"; the rest of the message stays.
pub fn plain_cause(error: &dyn std::fmt::Display) -> String {
    error.to_string().replace(
        "failed to fill whole buffer",
        "the file is truncated (it ends before its image data does)",
    )
}

/// Most pixels an EXR that vkpath reads may claim (the check happens on the header, before
/// any pixel is read): 2^28, a 16384 x 16384 image.
pub const MAX_EXR_PIXELS: usize = 1 << 28;

/// Why `check_exr_size` refuses an EXR's header, in the words that follow the file's name.
#[derive(Debug, thiserror::Error)]
pub enum ExrHeaderError {
    /// The header cannot be read: the exr crate's cause, plainly (`plain_cause`).
    #[error("{0}")]
    Unreadable(String),
    /// The header claims more than `MAX_EXR_PIXELS` pixels.
    #[error(
        "its header claims {width}x{height} pixels, more than the {MAX_EXR_PIXELS} vkpath reads"
    )]
    TooLarge {
        /// The claimed width.
        width: usize,
        /// The claimed height.
        height: usize,
    },
}

/// Refuses an EXR whose header claims more than `MAX_EXR_PIXELS` (read before any pixel,
/// so that a hostile header cannot make vkpath allocate terabytes).
pub fn check_exr_size(path: &Path) -> std::result::Result<(), ExrHeaderError> {
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| ExrHeaderError::Unreadable(plain_cause(&e)))?;
    for header in meta.headers.iter() {
        let (width, height) = (header.layer_size.width(), header.layer_size.height());
        if width
            .checked_mul(height)
            .is_none_or(|pixels| pixels > MAX_EXR_PIXELS)
        {
            return Err(ExrHeaderError::TooLarge { width, height });
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
        assert!(message.contains("not an OpenEXR file"), "{message}");
    }

    #[test]
    fn wrong_kinds_of_file_are_named_with_what_reads_them() {
        let dir = tempfile::tempdir().unwrap();
        let reader = Some("`vkpath compare` reads OpenEXR images");
        let message = |path: &Path| check_exr_file(path, reader).unwrap_err().to_string();
        let png = dir.path().join("a.png");
        save_image(&png, &test_image(), &SaveOptions::default()).unwrap();
        assert_eq!(
            message(&png),
            format!(
                "cannot read '{}': it is a PNG image, not an OpenEXR file (`vkpath compare` \
                 reads OpenEXR images)",
                png.display()
            )
        );
        assert!(message(dir.path()).contains("it is a directory, not a file"));
        let empty = dir.path().join("empty.exr");
        std::fs::write(&empty, b"").unwrap();
        assert!(message(&empty).contains("it is empty"));
        let exr = dir.path().join("a.exr");
        save_image(&exr, &test_image(), &SaveOptions::default()).unwrap();
        assert!(check_exr_file(&exr, reader).is_ok());
        // A whole header but no pixels: truncated, in those words.
        let bytes = std::fs::read(&exr).unwrap();
        let cut = dir.path().join("cut.exr");
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        let message = read_exr(&cut).unwrap_err().to_string();
        assert!(!message.contains("fill whole buffer"), "{message}");
    }
}
