//! Writing images: OpenEXR with linear radiance as 32-bit floats (optionally with the
//! per-pixel second moment and sample count), or PNG, sRGB-encoded after exposure and a
//! tone map (`tonemap`).
//! Files are written to a temporary name in the same directory and renamed into place, so a
//! failed write never leaves a partial file behind; only regular files (or new names) are
//! written, never a device, FIFO, socket or directory, even through a symbolic link.

use std::collections::BTreeMap;
use std::fmt::Display;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, FlatSamples, Image, Text, WritableImage,
};

use crate::image_io::data::RenderedImage;
use crate::image_io::error::{ImageError, ImageResult as Result};
use crate::image_io::tonemap::{tone_map, Exposure, ToneMap};

/// Why an image (or another output file) could not be written: the cause that
/// `ImageError::Write` names after the path. Messages are a cause alone (no path), in one
/// line; the underlying error's message is part of the text, not a `source()`, so that a
/// printed chain does not repeat it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutputError {
    /// Looking at the path (or a link on the way) failed.
    #[error("{0}")]
    Inspect(std::io::Error),
    /// The path names something other than a regular file (a directory, a device, ...).
    #[error("it is {what}, not a regular file")]
    NotAFile {
        /// What it is, in words ("a directory", "a FIFO (named pipe)", ...).
        what: &'static str,
    },
    /// The path is a symbolic link to something other than a regular file.
    #[error("it is a symbolic link to '{}', {what}, not a regular file", target.display())]
    LinkToNotAFile {
        /// Where the links lead.
        target: PathBuf,
        /// What is there, in words.
        what: &'static str,
    },
    /// The file exists and its mode does not let its owner write it.
    #[error("the file exists and is read-only")]
    ReadOnly,
    /// More symbolic links than `MAX_SYMLINK_HOPS` (a loop, most likely).
    #[error("more than {MAX_SYMLINK_HOPS} symbolic links (a loop?)")]
    LinkLoop,
    /// The folder a new file would go into is something else.
    #[error("'{}' is not a folder", folder.display())]
    NotAFolder {
        /// The would-be folder.
        folder: PathBuf,
    },
    /// The path is a symbolic link to a name in a folder that does not exist.
    #[error("it is a symbolic link to '{}', in a folder that does not exist", target.display())]
    LinkIntoMissingFolder {
        /// Where the links lead.
        target: PathBuf,
    },
    /// The folder a new file would go into does not exist.
    #[error("the folder '{}' does not exist", folder.display())]
    MissingFolder {
        /// The missing folder.
        folder: PathBuf,
    },
    /// The finished temporary file could not be renamed over the target.
    #[error("renaming into place: {0}")]
    Rename(std::io::Error),
    /// A text attribute that EXR's text type cannot hold.
    #[error("attribute {name} = {value} cannot be stored in EXR text")]
    ExrText {
        /// The attribute's name.
        name: String,
        /// Its value.
        value: String,
    },
    /// A bytes attribute whose name or type hint EXR's text type cannot hold.
    #[error("attribute {name} cannot be stored in EXR")]
    ExrBytes {
        /// The attribute's name.
        name: String,
    },
    /// The `exr` crate failed to write the file.
    #[error("{0}")]
    Exr(exr::error::Error),
    /// The file could not be created or opened.
    #[error("{0}")]
    File(std::io::Error),
    /// The `png` crate failed to encode the image or its texts.
    #[error("{0}")]
    PngEncoding(png::EncodingError),
}

/// The file formats vkpath writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// OpenEXR: linear radiance, 32-bit float per channel.
    Exr,
    /// PNG: 8-bit sRGB after exposure and a tone map.
    Png,
}

/// Names of the extra EXR channels written with `--moments`.
pub const SECOND_MOMENT_CHANNELS: [&str; 3] =
    ["second_moment.R", "second_moment.G", "second_moment.B"];
/// Name of the EXR channel holding each pixel's sample count (with `--moments`).
pub const SAMPLE_COUNT_CHANNEL: &str = "sample_count.Y";

/// How to turn radiance into an image file. The default writes a PNG's values as they are
/// (0 stops, clamped to [0, 1]), right for images that are not scene radiance (heat maps,
/// sample displays); `vkpath render` and `merge` use `tonemap::RENDER_PNG_TONE_MAP`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SaveOptions {
    /// PNG only: radiance is multiplied by 2^stops (or the image's automatic exposure)
    /// before the tone map.
    pub exposure: Exposure,
    /// PNG only: how exposed radiance becomes display values in [0, 1].
    pub tone_map: ToneMap,
    /// EXR only: also store the second moment and sample count of each pixel.
    pub moments: bool,
    /// EXR only: where the image lies in a larger one (a `--region` of it); `None`: it is
    /// the whole image.
    pub window: Option<ImageWindow>,
}

/// Where an image that is a part of a larger one (a `--region`) lies in it: its EXR's data
/// window is the part, at `origin` in a display window of `full_size` from (0, 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageWindow {
    /// The part's top-left pixel in the full image (column, row from the top).
    pub origin: [u32; 2],
    /// The full image's width and height.
    pub full_size: [u32; 2],
}

impl ImageFormat {
    /// The format for a path's extension (`.exr` or `.png`, any case).
    pub fn from_path(path: &Path) -> Result<ImageFormat> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("exr") => Ok(ImageFormat::Exr),
            Some("png") => Ok(ImageFormat::Png),
            _ => Err(ImageError::write(
                path,
                "unsupported image format (use .exr or .png)",
            )),
        }
    }
}

/// Checks, before rendering, that an image can be written to `path`: a known extension, and a
/// path that is (or links to) a regular file the owner may write or a new name in a folder
/// that accepts a new file (`resolve_output`). Returns the format.
pub fn check_writable(path: &Path) -> Result<ImageFormat> {
    let format = ImageFormat::from_path(path)?;
    check_writable_file(path)?;
    Ok(format)
}

/// `check_writable` for a file of any format (a checkpoint, a manifest): the path and its
/// folder, not the extension.
pub fn check_writable_file(path: &Path) -> Result<()> {
    let target = resolve_output(path).map_err(|error| ImageError::write(path, error))?;
    let probe = temporary_path(&target);
    let _pending = PendingTemporary::register(&probe);
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .map_err(|e| ImageError::write(path, e))
}

/// A hidden sibling of `path` to write into before renaming.
pub(crate) fn temporary_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.vkpath-{}.tmp", std::process::id()))
}

/// Writes `image` to `path` in the format its extension names.
pub fn save_image(path: &Path, image: &RenderedImage, options: &SaveOptions) -> Result<()> {
    save_image_with_attributes(path, image, options, &[])
}

/// `save_image` with header attributes (name, text value): EXR header attributes, or a PNG's
/// tEXt chunks (keyword, text).
pub fn save_image_with_attributes(
    path: &Path,
    image: &RenderedImage,
    options: &SaveOptions,
    attributes: &[(String, String)],
) -> Result<()> {
    match ImageFormat::from_path(path)? {
        ImageFormat::Exr => write_atomically(path, |temporary| {
            write_exr_channels(
                temporary,
                image.width,
                image.height,
                image_channels(image, options.moments),
                attributes,
                &[],
                options.window,
            )
        }),
        ImageFormat::Png => write_atomically(path, |temporary| {
            write_png(
                temporary,
                image,
                options.exposure,
                options.tone_map,
                attributes,
            )
        }),
    }
}

/// A layer of an EXR beside the colour: `name.R/G/B` (or `name.Z` for one channel, or
/// `name.R/G/B/A` with an alpha).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImageLayer {
    /// The layer's name (e.g. "albedo", "noisy").
    pub name: String,
    /// One value per pixel, rows top-down.
    pub pixels: Vec<[f32; 3]>,
    /// Whether the layer has one channel (`name.Z`, from the first component) not three.
    pub single_channel: bool,
    /// A fourth channel `name.A`, one value per pixel (Cryptomatte's rank pairs); `None`:
    /// none.
    pub alpha: Option<Vec<f32>>,
    /// Header attributes (name, text) the layer brings into the file (Cryptomatte's
    /// `cryptomatte/<key>/...`).
    pub attributes: Vec<(String, String)>,
}

/// `save_image_with_attributes` with extra EXR layers (PNG files get the colour only).
pub fn save_image_with_layers(
    path: &Path,
    image: &RenderedImage,
    options: &SaveOptions,
    attributes: &[(String, String)],
    layers: &[ImageLayer],
) -> Result<()> {
    if layers.is_empty() || ImageFormat::from_path(path)? != ImageFormat::Exr {
        return save_image_with_attributes(path, image, options, attributes);
    }
    let mut channels = image_channels(image, options.moments);
    channels.extend(layer_channels(layers));
    let mut attributes = attributes.to_vec();
    attributes.extend(layer_attributes(layers));
    write_atomically(path, |temporary| {
        write_exr_channels(
            temporary,
            image.width,
            image.height,
            channels,
            &attributes,
            &[],
            options.window,
        )
    })
}

/// The EXR channels of `layers`: `name.R/G/B` (`name.Z` for one channel; `name.A` too with
/// an alpha), in the layers' order.
pub fn layer_channels(layers: &[ImageLayer]) -> Vec<(String, Vec<f32>)> {
    let mut channels = Vec::new();
    for layer in layers {
        if layer.single_channel {
            channels.push((
                format!("{}.Z", layer.name),
                layer.pixels.iter().map(|p| p[0]).collect(),
            ));
        } else {
            for (c, suffix) in ["R", "G", "B"].iter().enumerate() {
                channels.push((
                    format!("{}.{suffix}", layer.name),
                    layer.pixels.iter().map(|p| p[c]).collect(),
                ));
            }
        }
        if let Some(alpha) = &layer.alpha {
            channels.push((format!("{}.A", layer.name), alpha.clone()));
        }
    }
    channels
}

/// The header attributes that `layers` bring (Cryptomatte's), in the layers' order.
pub fn layer_attributes(layers: &[ImageLayer]) -> Vec<(String, String)> {
    layers
        .iter()
        .flat_map(|l| l.attributes.iter().cloned())
        .collect()
}

/// Writes a file through `write` into a temporary file in the same folder, then renames it
/// into place: readers never see a partial file, and an interrupted write leaves the old
/// file as it was. Like `cp`, a symbolic link is written through (its target is replaced)
/// and an existing file that its owner cannot write is refused. `write`'s error is the
/// cause that the returned `ImageError::Write` names.
pub(crate) fn write_atomically<E: Display>(
    path: &Path,
    write: impl FnOnce(&Path) -> std::result::Result<(), E>,
) -> Result<()> {
    let target = resolve_output(path).map_err(|error| ImageError::write(path, error))?;
    let temporary = temporary_path(&target);
    let _pending = PendingTemporary::register(&temporary);
    let fail = |cause: &dyn Display| {
        let _ = std::fs::remove_file(&temporary);
        ImageError::write(path, cause)
    };
    write(&temporary).map_err(|error| fail(&error))?;
    std::fs::rename(&temporary, &target).map_err(|error| fail(&OutputError::Rename(error)))
}

/// Most symbolic links followed to find what an output replaces (Linux's own limit).
const MAX_SYMLINK_HOPS: usize = 40;

/// The file that writing to `path` replaces: `path`, or where its symbolic links lead
/// (followed as `cp` follows them). It must be a regular file that its mode lets the owner
/// write, or a name that does not exist yet in an existing folder. Anything else is refused:
/// a directory, a device, a FIFO or a socket (renaming a new file over it would destroy it,
/// and writing into it makes no image), and a read-only file, as `cp` refuses it.
fn resolve_output(path: &Path) -> std::result::Result<PathBuf, OutputError> {
    let mut target = path.to_path_buf();
    for _ in 0..=MAX_SYMLINK_HOPS {
        let metadata = match std::fs::symlink_metadata(&target) {
            Ok(metadata) => metadata,
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
                return new_name_in_a_folder(path, target);
            }
            Err(error) => return Err(OutputError::Inspect(error)),
        };
        let file_type = metadata.file_type();
        if file_type.is_symlink() {
            let link = std::fs::read_link(&target).map_err(OutputError::Inspect)?;
            target = match target.parent() {
                Some(parent) if link.is_relative() => parent.join(link),
                _ => link,
            };
            continue;
        }
        if !file_type.is_file() {
            let what = file_type_name(file_type);
            return Err(if target == path {
                OutputError::NotAFile { what }
            } else {
                OutputError::LinkToNotAFile { target, what }
            });
        }
        if metadata.permissions().readonly() {
            return Err(OutputError::ReadOnly);
        }
        return Ok(target);
    }
    Err(OutputError::LinkLoop)
}

/// `target` (what `path` names, after its links), which does not exist yet: it must be a new
/// name in an existing folder.
fn new_name_in_a_folder(path: &Path, target: PathBuf) -> std::result::Result<PathBuf, OutputError> {
    let folder = match target.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    match std::fs::metadata(&folder) {
        Ok(metadata) if metadata.is_dir() => Ok(target),
        Ok(_) => Err(OutputError::NotAFolder { folder }),
        Err(_) if target != path => Err(OutputError::LinkIntoMissingFolder { target }),
        Err(_) => Err(OutputError::MissingFolder { folder }),
    }
}

/// What a file that is not a regular file is, in words ("a directory", "a FIFO", ...).
fn file_type_name(file_type: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_dir() {
        "a directory"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_fifo() {
        "a FIFO (named pipe)"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

/// The temporary files that writes are filling right now (`write_atomically`), so that an
/// abort that ends the process at once (a second Ctrl-C) can remove them first.
static PENDING_TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// A temporary file listed in `PENDING_TEMPORARIES` while it lives.
struct PendingTemporary(PathBuf);

impl PendingTemporary {
    /// Lists `path` (before it is created, so that no moment exists where it is unlisted).
    fn register(path: &Path) -> PendingTemporary {
        pending_temporaries().push(path.to_path_buf());
        PendingTemporary(path.to_path_buf())
    }
}

impl Drop for PendingTemporary {
    fn drop(&mut self) {
        let mut pending = pending_temporaries();
        if let Some(index) = pending.iter().position(|p| *p == self.0) {
            pending.swap_remove(index);
        }
    }
}

/// The list, even if a thread panicked while holding it (a list of paths stays valid).
fn pending_temporaries() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    PENDING_TEMPORARIES
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Writes stopped for good (`abort_pending_writes`): while this lives, no write starts or
/// ends. Meant to be held until the process exits.
pub struct AbortedWrites(#[allow(dead_code)] std::sync::MutexGuard<'static, Vec<PathBuf>>);

/// Removes the temporary files of the writes in progress and keeps every other write from
/// starting or finishing while the result lives: for an abort that then ends the process at
/// once (a second Ctrl-C), leaving no temporary file behind. Every target stays intact: a
/// write replaces its target only by renaming a finished file over it.
pub fn abort_pending_writes() -> AbortedWrites {
    let pending = pending_temporaries();
    for path in pending.iter() {
        let _ = std::fs::remove_file(path);
    }
    AbortedWrites(pending)
}

/// The channels of an image: R, G, B, A (the mean), with `moments` the second moment and
/// sample count too.
fn image_channels(image: &RenderedImage, moments: bool) -> Vec<(String, Vec<f32>)> {
    let mean = |c: usize| image.mean.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let mut channels: Vec<(String, Vec<f32>)> = ["R", "G", "B", "A"]
        .iter()
        .enumerate()
        .map(|(c, name)| (name.to_string(), mean(c)))
        .collect();
    if moments {
        for (c, name) in SECOND_MOMENT_CHANNELS.iter().enumerate() {
            channels.push((
                name.to_string(),
                image.second_moment.iter().map(|p| p[c]).collect(),
            ));
        }
        channels.push((SAMPLE_COUNT_CHANNEL.to_string(), image.sample_count.clone()));
    }
    channels
}

/// An EXR header attribute of bytes (the `bytes` type): a render state's frozen guide.
pub(crate) struct ByteAttribute {
    /// The attribute's name.
    pub name: String,
    /// What the bytes are, for other readers.
    pub type_hint: String,
    /// The contents.
    pub bytes: Vec<u8>,
}

/// Writes float channels (rows top-down), text attributes and byte attributes as one EXR
/// layer, placed in a larger display window when `window` says so. Blocks are written in
/// order on one thread, so identical images make identical files.
pub(crate) fn write_exr_channels(
    path: &Path,
    width: u32,
    height: u32,
    channels: Vec<(String, Vec<f32>)>,
    attributes: &[(String, String)],
    byte_attributes: &[ByteAttribute],
    window: Option<ImageWindow>,
) -> std::result::Result<(), OutputError> {
    let channels: Vec<AnyChannel<FlatSamples>> = channels
        .into_iter()
        .map(|(name, values)| AnyChannel::new(name.as_str(), FlatSamples::F32(values)))
        .collect();
    let mut exr_image = Image::from_channels(
        (width as usize, height as usize),
        AnyChannels::sort(channels.into()),
    );
    if let Some(window) = window {
        let [x, y] = window.origin.map(|v| v as i32);
        let [full_width, full_height] = window.full_size.map(|v| v as usize);
        exr_image.attributes.display_window =
            exr::meta::attribute::IntegerBounds::new((0, 0), (full_width, full_height));
        exr_image.layer_data.attributes.layer_position = exr::math::Vec2(x, y);
    }
    for (name, value) in attributes {
        let (Some(name), Some(value)) = (Text::new_or_none(name), Text::new_or_none(value)) else {
            return Err(OutputError::ExrText {
                name: name.clone(),
                value: value.clone(),
            });
        };
        exr_image
            .attributes
            .other
            .insert(name, AttributeValue::Text(value));
    }
    // In the layer's attributes, apart from the text ones: each map is written in hash
    // order, and one entry per map keeps identical renders identical files.
    for attribute in byte_attributes {
        let (Some(name), Some(type_hint)) = (
            Text::new_or_none(&attribute.name),
            Text::new_or_none(&attribute.type_hint),
        ) else {
            return Err(OutputError::ExrBytes {
                name: attribute.name.clone(),
            });
        };
        exr_image.layer_data.attributes.other.insert(
            name,
            AttributeValue::Bytes {
                type_hint,
                bytes: attribute.bytes.as_slice().into(),
            },
        );
    }
    exr_image
        .write()
        .non_parallel()
        .to_file(path)
        .map_err(OutputError::Exr)
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
pub fn linear_to_srgb(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit sRGB of a linear radiance value: times 2^exposure, clamped to [0, 1] (NaN to 0),
/// encoded, rounded (the `Clamp` tone map of one channel).
pub fn to_srgb8(radiance: f32, exposure: f32) -> u8 {
    let scaled = radiance * exposure.exp2();
    let clamped = if scaled.is_nan() {
        0.0
    } else {
        scaled.clamp(0.0, 1.0)
    };
    encode_srgb8(clamped)
}

/// 8-bit sRGB of a display-linear value in [0, 1], rounded.
fn encode_srgb8(display_linear: f32) -> u8 {
    (linear_to_srgb(display_linear) * 255.0).round() as u8
}

/// The 8-bit sRGB pixels (RGB, rows top-down) of `image` after `exposure` and `map`.
pub fn tone_mapped_srgb8(image: &RenderedImage, exposure: Exposure, map: ToneMap) -> Vec<u8> {
    let scale = exposure.scale_for(image);
    image
        .mean
        .iter()
        .flat_map(|p| tone_map([p[0], p[1], p[2]], scale, map).map(encode_srgb8))
        .collect()
}

fn write_png(
    path: &Path,
    image: &RenderedImage,
    exposure: Exposure,
    map: ToneMap,
    texts: &[(String, String)],
) -> std::result::Result<(), OutputError> {
    let bytes = tone_mapped_srgb8(image, exposure, map);
    write_rgb8_png_with_texts(path, image.width, image.height, &bytes, texts)
}

/// Writes 8-bit RGB pixels (rows top-down) as a PNG at `path` (no atomic rename: callers
/// write to a temporary file through `write_atomically`).
pub fn write_rgb8_png(
    path: &Path,
    width: u32,
    height: u32,
    bytes: &[u8],
) -> std::result::Result<(), OutputError> {
    write_rgb8_png_with_texts(path, width, height, bytes, &[])
}

/// `write_rgb8_png` with tEXt chunks (keyword, Latin-1 text) before the pixels.
pub fn write_rgb8_png_with_texts(
    path: &Path,
    width: u32,
    height: u32,
    bytes: &[u8],
    texts: &[(String, String)],
) -> std::result::Result<(), OutputError> {
    let file = std::fs::File::create(path).map_err(OutputError::File)?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    // What the image crate's encoder chose (its defaults), so that a PNG without texts is
    // the same file it wrote before.
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::Filter::Adaptive);
    for (keyword, text) in texts {
        encoder
            .add_text_chunk(keyword.clone(), text.clone())
            .map_err(OutputError::PngEncoding)?;
    }
    let mut writer = encoder.write_header().map_err(OutputError::PngEncoding)?;
    writer
        .write_image_data(bytes)
        .map_err(OutputError::PngEncoding)?;
    writer.finish().map_err(OutputError::PngEncoding)
}

/// Why `read_png_texts` cannot read a PNG's text chunks, in the words that follow the file's
/// name.
#[derive(Debug, thiserror::Error)]
pub enum PngTextError {
    /// The file does not open.
    #[error("{0}")]
    Open(#[from] std::io::Error),
    /// Its signature or header chunks do not decode.
    #[error("{0}")]
    Decode(#[from] png::DecodingError),
}

/// The tEXt chunks of the PNG at `path` (keyword to text), read without decoding a pixel.
pub fn read_png_texts(path: &Path) -> std::result::Result<BTreeMap<String, String>, PngTextError> {
    let file = std::fs::File::open(path)?;
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let reader = decoder.read_info()?;
    Ok(reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .map(|chunk| (chunk.keyword.clone(), chunk.text.clone()))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_matches_reference_points() {
        assert_eq!(to_srgb8(0.0, 0.0), 0);
        assert_eq!(to_srgb8(1.0, 0.0), 255);
        assert_eq!(to_srgb8(7.0, 0.0), 255);
        assert_eq!(to_srgb8(f32::NAN, 0.0), 0);
        // Linear 0.5 is sRGB 0.735 -> 188; exposure -1 halves the radiance first.
        assert_eq!(to_srgb8(0.5, 0.0), 188);
        assert_eq!(to_srgb8(1.0, -1.0), 188);
    }

    #[test]
    fn the_clamp_tone_map_writes_what_to_srgb8_wrote() {
        // `exercise` PNGs must stay byte for byte what they were before tone maps existed.
        let values = [
            0.0,
            1e-4,
            0.003,
            0.2,
            0.5,
            0.99,
            1.0,
            7.0,
            -2.0,
            f32::NAN,
            f32::INFINITY,
        ];
        let mut image = RenderedImage::from_accumulation(values.len() as u32, 1, &[[0.0; 4]; 33]);
        for (pixel, &v) in image.mean.iter_mut().zip(&values) {
            *pixel = [v, v * 0.5, v * 3.0, 1.0];
        }
        for stops in [0.0f32, -1.0, 2.5] {
            let expected: Vec<u8> = image
                .mean
                .iter()
                .flat_map(|p| {
                    [
                        to_srgb8(p[0], stops),
                        to_srgb8(p[1], stops),
                        to_srgb8(p[2], stops),
                    ]
                })
                .collect();
            let written = tone_mapped_srgb8(&image, Exposure::Stops(stops), ToneMap::Clamp);
            assert_eq!(written, expected, "exposure {stops}");
        }
    }

    #[test]
    fn outputs_follow_symlinks_refuse_read_only_files_and_are_deterministic() {
        use std::os::unix::fs::{symlink, PermissionsExt};
        let dir = tempfile::tempdir().unwrap();
        let image = RenderedImage::from_accumulation(2, 1, &[[1.0, 2.0, 3.0, 1.0]; 6]);
        let target = dir.path().join("target.exr");
        let link = dir.path().join("link.exr");
        symlink("target.exr", &link).unwrap();
        save_image(&link, &image, &SaveOptions::default()).unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        let first = std::fs::read(&target).unwrap();
        save_image(&target, &image, &SaveOptions::default()).unwrap();
        assert_eq!(
            std::fs::read(&target).unwrap(),
            first,
            "identical images, identical files"
        );
        std::fs::set_permissions(&target, std::fs::Permissions::from_mode(0o444)).unwrap();
        let message = save_image(&target, &image, &SaveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(message.contains("read-only"), "{message}");
        // (As root the file could still be opened; vkpath refuses by its mode all the same.)
        let leftovers = std::fs::read_dir(dir.path()).unwrap().count();
        assert_eq!(leftovers, 2, "no temporary file is left behind");
    }

    #[test]
    fn devices_fifos_and_directories_are_refused_even_through_links() {
        use std::os::unix::fs::{symlink, FileTypeExt};
        let dir = tempfile::tempdir().unwrap();
        let path = |name: &str| dir.path().join(name);
        let fifo = path("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.unwrap().success(), "mkfifo (coreutils) makes a FIFO");
        symlink(&fifo, path("to-fifo.exr")).unwrap();
        symlink("/dev/null", path("null.png")).unwrap();
        symlink(dir.path(), path("folder.png")).unwrap();
        symlink("to-fifo.exr", path("chain.exr")).unwrap();
        std::fs::create_dir(path("dir.exr")).unwrap();
        let image = RenderedImage::from_accumulation(2, 1, &[[1.0, 2.0, 3.0, 1.0]; 6]);
        for (name, expected) in [
            ("to-fifo.exr", "a FIFO"),
            ("chain.exr", "a FIFO"),
            (
                "null.png",
                "symbolic link to '/dev/null', a character device",
            ),
            ("folder.png", "a directory"),
            ("dir.exr", "it is a directory"),
        ] {
            let message = check_writable(&path(name)).unwrap_err().to_string();
            assert!(message.contains(expected), "{name}: {message}");
            let message = save_image(&path(name), &image, &SaveOptions::default())
                .unwrap_err()
                .to_string();
            assert!(message.contains(expected), "{name}: {message}");
        }
        let fifo_type = std::fs::symlink_metadata(&fifo).unwrap().file_type();
        assert!(fifo_type.is_fifo(), "the FIFO survives");
        let null_type = std::fs::metadata("/dev/null").unwrap().file_type();
        assert!(null_type.is_char_device(), "/dev/null survives");
        // A link to a name that does not exist yet is a new file there.
        symlink("new.exr", path("dangling.exr")).unwrap();
        save_image(&path("dangling.exr"), &image, &SaveOptions::default()).unwrap();
        assert!(std::fs::metadata(path("new.exr")).unwrap().is_file());
        let message = check_writable(&path("nowhere/x.exr"))
            .unwrap_err()
            .to_string();
        assert!(message.contains("does not exist"), "{message}");
    }

    #[test]
    fn unsupported_extensions_and_missing_directories_are_rejected() {
        assert!(check_writable(Path::new("out.jpg")).is_err());
        let message = check_writable(Path::new("/nonexistent-dir/out.exr"))
            .unwrap_err()
            .to_string();
        assert!(message.contains("/nonexistent-dir/out.exr"), "{message}");
    }
}
