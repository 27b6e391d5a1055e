//! The image files of a render: where they go (the outputs, or their `.partial` siblings after
//! Ctrl-C or a failure), what they hold (the image, then the post-processed image with its
//! EXR layers; a shard's state), and the rescue into the temp directory when an output cannot
//! be written.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::bail;

use super::{Finished, RenderRequest};
use crate::camera_data::CameraData;
use crate::cli::signals;
use crate::image_io::output::{
    save_image_with_attributes, save_image_with_layers, write_atomically, ImageFormat, ImageLayer,
    SaveOptions,
};
use crate::render::ground_truth::IdNames;
use crate::render::metadata::RenderMetadata;
use crate::render::settings::RenderSettings;
use crate::render::state_exr::{write_state_with_layers, StateLayers};
use crate::render::StopReason;
use crate::vk::Context;
use crate::RenderedImage;

/// What `render --denoise` says it did (after "vkpath: ", unless quiet): the filter
/// `PostProcess::apply` runs and where the original went.
pub const DENOISED_LINE: &str = "denoised with Intel Open Image Denoise's RT filter (HDR, \
     guided by the albedo and normal); an EXR keeps the noisy image in its `noisy` layer";

/// The files a render writes its image to: its outputs, or after Ctrl-C (SIGINT) or a
/// device failure their partial siblings (`out.png` -> `out.partial.png`), so that an
/// interrupted or failed render never replaces a finished image, as Mitsuba, pbrt and
/// Blender leave theirs. A time limit and SIGTERM or SIGHUP (a scheduler's stop, which
/// expects the outputs and checkpoint there) write the outputs themselves.
pub(super) fn written_outputs(outputs: &[PathBuf], stop: StopReason) -> Vec<PathBuf> {
    let interrupted =
        (stop == StopReason::Cancelled && signals::interrupted()) || stop == StopReason::Failed;
    outputs
        .iter()
        .map(|output| match interrupted {
            true => partial_path(output),
            false => output.clone(),
        })
        .collect()
}

/// Where an interrupted render writes what it rendered for `output`: `.partial` before its
/// extension (`out.png` -> `out.partial.png`; `out` -> `out.partial`).
pub fn partial_path(output: &Path) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = match output.extension() {
        Some(extension) => format!("{stem}.partial.{}", extension.to_string_lossy()),
        None => format!("{stem}.partial"),
    };
    output.with_file_name(name)
}

/// Writes the finished render to every output: the render state for a shard; otherwise the
/// image as rendered, then (for a finished render: every sample taken, or the time limit
/// reached) again after `request.post`, so that nothing is lost if post-processing fails.
pub(super) fn save_outputs(
    request: &RenderRequest,
    outputs: &[PathBuf],
    contexts: &[Arc<Context>],
    finished: &Finished,
    image: &RenderedImage,
) -> anyhow::Result<Option<(RenderedImage, Vec<ImageLayer>)>> {
    let metadata = &finished.metadata;
    if request.shard {
        let Some(state) = &finished.state else {
            bail!("the shard's render kept no state to write");
        };
        // The ground truth and Cryptomatte go into every shard (`Aov::goes_into_shards`)
        let layers = match contexts.first() {
            Some(context) if !request.post.is_empty() => {
                let (_, layers) = request.post.apply(
                    context,
                    request.scene,
                    request.camera,
                    request.settings,
                    image,
                )?;
                StateLayers::of(&layers)
            }
            _ => StateLayers::default(),
        };
        for output in outputs {
            write_state_with_layers(output, state, metadata, &layers)?;
        }
        if request.post.aovs.iter().any(|aov| aov.is_id()) {
            write_id_names(outputs, request.scene)?;
        }
        return Ok(None);
    }
    for output in outputs {
        save_or_rescue(output, image, &request.save, metadata, &[])?;
    }
    if request.post.is_empty() {
        return Ok(None);
    }
    if !finished.stop.is_finished() {
        eprintln!(
            "vkpath: warning: the render stopped early ({}): saved without --aov/--denoise",
            finished.stop.name()
        );
        return Ok(None);
    }
    let Some(context) = contexts.first() else {
        return Ok(None);
    };
    // The layers take the samples the colour took: all of them, or those before the time
    // limit (not the million asked, which would take far longer than the render did).
    let taken = RenderSettings {
        spp: metadata.samples.len() as u32,
        ..request.settings.clone()
    };
    let (processed, layers) =
        request
            .post
            .apply(context, request.scene, request.camera, &taken, image)?;
    let mut metadata = metadata.clone();
    request.post.record(&mut metadata);
    for output in outputs {
        save_or_rescue(output, &processed, &request.save, &metadata, &layers)?;
    }
    if request.post.aovs.iter().any(|aov| aov.is_id()) {
        write_id_names(outputs, request.scene)?;
    }
    if request.post.denoise && request.reporting.talks() {
        eprintln!("vkpath: {}", DENOISED_LINE);
    }
    Ok(Some((processed, layers)))
}

/// The sidecar of `--camera-data`: `NAME.json` beside `NAME.exr` (or `.png`).
pub fn camera_data_path(output: &Path) -> PathBuf {
    output.with_extension("json")
}

/// Writes the request's camera (`CameraData`, for the full image) beside every output.
pub(super) fn write_camera_data(
    request: &RenderRequest,
    outputs: &[PathBuf],
) -> anyhow::Result<()> {
    let settings = request.settings;
    let data = CameraData::of(request.camera, settings.width, settings.height);
    let text = serde_json::to_string_pretty(&data)?;
    for output in outputs {
        write_atomically(&camera_data_path(output), |temporary| {
            std::fs::write(temporary, &text)
        })?;
    }
    Ok(())
}

/// The sidecar that names the IDs of an EXR's ID layers: `NAME.ids.json` beside `NAME.exr`.
pub fn id_names_path(output: &Path) -> PathBuf {
    output.with_extension("ids.json")
}

/// Writes `IdNames::of(scene)` beside every EXR output (`id_names_path`).
fn write_id_names(outputs: &[PathBuf], scene: &crate::scene::Scene) -> anyhow::Result<()> {
    let text = serde_json::to_string_pretty(&IdNames::of(scene))?;
    for output in outputs {
        if ImageFormat::from_path(output).ok() != Some(ImageFormat::Exr) {
            continue;
        }
        let path = id_names_path(output);
        write_atomically(&path, |temporary| std::fs::write(temporary, &text))?;
    }
    Ok(())
}

/// Saves `image` to `output` with the render's metadata in its header; when that fails,
/// nothing already rendered is lost: the image (with its moments) goes to the temp directory
/// and the error says where.
pub fn save_or_rescue(
    output: &Path,
    image: &RenderedImage,
    save: &SaveOptions,
    metadata: &RenderMetadata,
    layers: &[ImageLayer],
) -> anyhow::Result<()> {
    let attributes = metadata.attributes_with_counts(&image.sample_count);
    // A region's EXR is placed in the full image; an adaptive render's keeps every pixel's
    // sample count (and the second moments beside it, for `compare`).
    let save = &SaveOptions {
        window: metadata.window(),
        moments: save.moments || metadata.setting("noise_threshold").is_some(),
        ..*save
    };
    let Err(error) = save_image_with_layers(output, image, save, &attributes, layers) else {
        return Ok(());
    };
    let rescue = std::env::temp_dir().join(format!("vkpath-rescue-{}.exr", std::process::id()));
    let rescued = save_image_with_attributes(
        &rescue,
        image,
        &SaveOptions {
            moments: true,
            ..*save
        },
        &attributes,
    );
    match rescued {
        Ok(()) => bail!(
            "{error}; the render was saved to '{}' instead",
            rescue.display()
        ),
        Err(_) => bail!("{error}"),
    }
}
