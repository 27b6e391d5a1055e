//! Images in and out, and the judging commands: `vkpath.save` (the library's `save_image`),
//! `vkpath.read_exr`, `vkpath.compare` (`compare_images`, the report as JSON) and
//! `vkpath.check` (the check module's report, as JSON). The Python half passes pixels as
//! dicts of raw float32 bytes (`mean`: RGBA, `second_moment`: RGB, `sample_count`) and turns
//! the JSON into dicts.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::pybacked::PyBackedBytes;
use pyo3::types::{PyByteArray, PyDict};
use vkpath::check::{check as check_file, load_user_functions, CheckOptions};
use vkpath::compare::{DEFAULT_ALPHA, DEFAULT_BLOCK_SIZE};
use vkpath::image_io::exr_input::{
    read_exr as read_exr_file, read_exr_channels as read_channels, ExrImage,
};
use vkpath::image_io::tonemap::RENDER_PNG_TONE_MAP;
use vkpath::{compare_images, CompareOptions, Context, ContextOptions, Exposure, RenderedImage};

use crate::errors::{message, to_py};
use crate::names::parse_optional;

/// Reads raw float32 values (native byte order) from `bytes`, `per_pixel` per pixel.
fn floats(name: &str, bytes: &[u8], pixels: usize, per_pixel: usize) -> PyResult<Vec<f32>> {
    if bytes.len() != pixels * per_pixel * 4 {
        return Err(message(format!(
            "{name}: {} bytes are not {pixels} pixels of {per_pixel} float32 values",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(4)
        .map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
        .collect())
}

/// The image a dict of the Python half describes: `width`, `height`, `mean` (RGBA bytes)
/// and, when known, `second_moment` and `sample_count`. Without them it is what
/// `read_exr` makes of a file without moments: the squared mean, one sample.
fn image_of(pixels: &Bound<'_, PyDict>) -> PyResult<ExrImage> {
    let item = |key: &str| pixels.get_item(key);
    let required =
        |key: &str| item(key)?.ok_or_else(|| message(format!("the image has no '{key}'")));
    let width: u32 = required("width")?.extract()?;
    let height: u32 = required("height")?.extract()?;
    let count = width as usize * height as usize;
    let mean_bytes: PyBackedBytes = required("mean")?.extract()?;
    let mean: Vec<[f32; 4]> = floats("mean", &mean_bytes, count, 4)?
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect();
    let moments = match (item("second_moment")?, item("sample_count")?) {
        (Some(squares), Some(counts)) if !squares.is_none() && !counts.is_none() => {
            let squares: PyBackedBytes = squares.extract()?;
            let counts: PyBackedBytes = counts.extract()?;
            Some((
                floats("second_moment", &squares, count, 3)?,
                floats("sample_count", &counts, count, 1)?,
            ))
        }
        _ => None,
    };
    let has_moments = moments.is_some();
    let (second_moment, sample_count) = match moments {
        Some((squares, counts)) => (
            squares
                .chunks_exact(3)
                .map(|s| [s[0], s[1], s[2]])
                .collect(),
            counts,
        ),
        None => (
            mean.iter()
                .map(|p| [p[0] * p[0], p[1] * p[1], p[2] * p[2]])
                .collect(),
            vec![1.0; count],
        ),
    };
    Ok(ExrImage {
        image: RenderedImage {
            width,
            height,
            mean,
            second_moment,
            sample_count,
        },
        has_moments,
    })
}

/// The dict of the Python half for `image`.
fn dict_of<'py>(py: Python<'py>, image: &ExrImage) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let rendered = &image.image;
    dict.set_item("width", rendered.width)?;
    dict.set_item("height", rendered.height)?;
    dict.set_item(
        "mean",
        PyByteArray::new(py, bytemuck::cast_slice(&rendered.mean)),
    )?;
    if image.has_moments {
        dict.set_item(
            "second_moment",
            PyByteArray::new(py, bytemuck::cast_slice(&rendered.second_moment)),
        )?;
        dict.set_item(
            "sample_count",
            PyByteArray::new(py, bytemuck::cast_slice(&rendered.sample_count)),
        )?;
    }
    Ok(dict)
}

/// The exposure a Python value names: `None` (the command line's default, 0 stops), a
/// number of stops, or "auto".
fn exposure_of(value: Option<&Bound<'_, PyAny>>) -> PyResult<Exposure> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(Exposure::default());
    };
    if let Ok(text) = value.extract::<String>() {
        if text.eq_ignore_ascii_case("auto") {
            return Ok(Exposure::Auto);
        }
        return Err(message(format!(
            "exposure='{text}' is neither 'auto' nor a number of stops"
        )));
    }
    let stops: f32 = value.extract()?;
    if !stops.is_finite() {
        return Err(message(format!("exposure={stops} is not finite")));
    }
    Ok(Exposure::Stops(stops))
}

/// Writes `pixels` to `path` (.exr: linear float32, with the moments if `moments` and the
/// image has them; .png: sRGB after `exposure` and `tonemap`, by default the command line's
/// for `render`), atomically, as the command line writes its outputs.
#[pyfunction]
#[pyo3(signature = (pixels, path, *, tonemap=None, exposure=None, moments=false))]
pub fn save(
    py: Python<'_>,
    pixels: &Bound<'_, PyDict>,
    path: PathBuf,
    tonemap: Option<&str>,
    exposure: Option<&Bound<'_, PyAny>>,
    moments: bool,
) -> PyResult<()> {
    let image = image_of(pixels)?;
    if moments && !image.has_moments {
        return Err(message(
            "moments=True needs an image with moments (a vkpath.RenderResult or an EXR written with them)",
        ));
    }
    let options = vkpath::SaveOptions {
        exposure: exposure_of(exposure)?,
        tone_map: parse_optional("tonemap", tonemap)?.unwrap_or(RENDER_PNG_TONE_MAP),
        moments,
        window: None,
    };
    py.detach(|| vkpath::save_image(&path, &image.image, &options))
        .map_err(to_py)
}

/// Reads an EXR (any with R, G and B channels; vkpath's moments when it has them).
#[pyfunction]
pub fn read_exr(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let image = py.detach(|| read_exr_file(&path)).map_err(to_py)?;
    dict_of(py, &image)
}

/// Every channel of an EXR's first layer: a dict of `width`, `height` and `channels`, a list
/// of (name, bytearray of float32) in the file's order.
#[pyfunction]
pub fn read_exr_channels(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let file = py.detach(|| read_channels(&path)).map_err(to_py)?;
    let dict = PyDict::new(py);
    dict.set_item("width", file.width)?;
    dict.set_item("height", file.height)?;
    let channels = file
        .channels
        .iter()
        .map(|(name, values)| {
            (
                name.clone(),
                PyByteArray::new(py, bytemuck::cast_slice(values)),
            )
        })
        .collect::<Vec<_>>();
    dict.set_item("channels", channels)?;
    Ok(dict)
}

/// Tests whether image `a` is an unbiased estimate of `b` (`vkpath compare`); each is a
/// path to an EXR or a dict of pixels. Returns the report as JSON.
#[pyfunction]
#[pyo3(signature = (a, b, *, alpha=DEFAULT_ALPHA, block_size=DEFAULT_BLOCK_SIZE),
    text_signature = "(a, b, *, alpha=0.01, block_size=8)")]
pub fn compare(
    py: Python<'_>,
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    alpha: f64,
    block_size: usize,
) -> PyResult<String> {
    let load = |value: &Bound<'_, PyAny>| -> PyResult<ExrImage> {
        match value.cast::<PyDict>() {
            Ok(dict) => image_of(dict),
            Err(_) => {
                let path: PathBuf = value.extract()?;
                py.detach(|| read_exr_file(&path)).map_err(to_py)
            }
        }
    };
    let (a, b) = (load(a)?, load(b)?);
    let options = CompareOptions { alpha, block_size };
    let report = py
        .detach(|| compare_images(&a, &b, &options))
        .map_err(|error| message(format!("cannot compare the images: {error}")))?;
    serde_json::to_string(&report).map_err(to_py)
}

/// Judges the workshop functions in a GLSL file (`vkpath check`) and returns its report as
/// JSON; the comparison images go to `output_dir`.
#[pyfunction]
#[pyo3(signature = (path, *, output_dir=None, spp=None, size=None, device=None))]
pub fn check(
    py: Python<'_>,
    path: PathBuf,
    output_dir: Option<PathBuf>,
    spp: Option<u32>,
    size: Option<u32>,
    device: Option<String>,
) -> PyResult<String> {
    let defaults = CheckOptions::default();
    let options = CheckOptions {
        output_dir: output_dir.unwrap_or(defaults.output_dir),
        spp: spp.unwrap_or(defaults.spp),
        image_size: size.unwrap_or(defaults.image_size),
        ..CheckOptions::default()
    };
    if !(4..=65536).contains(&options.spp) {
        return Err(message(format!("spp={} is outside 4..=65536", options.spp)));
    }
    if options.image_size == 0 || !options.image_size.is_multiple_of(8) || options.image_size > 1024
    {
        return Err(message(format!(
            "size={} is not a multiple of 8 in 8..=1024",
            options.image_size
        )));
    }
    let report = py.detach(|| {
        // Worded as `vkpath check` words it: the load error's own line (its message already
        // names the cause), the others with their chain of causes.
        let user = load_user_functions(std::slice::from_ref(&path))
            .map_err(|error| message(error.to_string()))?;
        let context = Context::new(&ContextOptions {
            device,
            ..ContextOptions::default()
        })
        .map_err(to_py)?;
        check_file(&context, &user, &options).map_err(to_py)
    })?;
    serde_json::to_string(&report).map_err(to_py)
}
