//! The end of a render command: render with a progress bar, save the image (into the temp
//! directory when the output cannot be written), print the summary line, and fail when the
//! validation layer complained.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::bail;

use super::summary::{summary_line, RenderProgress};
use crate::camera::Camera;
use crate::image_io::output::{save_image, SaveOptions};
use crate::render::settings::RenderSettings;
use crate::render::Renderer;
use crate::scene::Scene;
use crate::vk::Context;
use crate::RenderedImage;

/// Set by Ctrl-C: stop after the current batch and save what was rendered.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Renders with a progress bar, saves the image and prints the summary line. Ctrl-C stops
/// early and saves the samples taken so far.
pub fn render_and_save(
    context: &Arc<Context>,
    scene: &Scene,
    camera: &Camera,
    settings: RenderSettings,
    output: &Path,
    save: &SaveOptions,
) -> anyhow::Result<()> {
    // A second handler cannot be installed (e.g. in tests calling this twice); the render
    // then simply is not interruptible, which is harmless.
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
    let mut renderer = Renderer::new(context, scene, camera, settings.clone())?;
    let mut progress = RenderProgress::new(settings.spp);
    let outcome = renderer.render_to_end(|done| progress.update(done), Some(&INTERRUPTED))?;
    progress.finish();
    let (seconds, done, image) = (outcome.seconds, outcome.samples, outcome.image);
    if let Some(error) = outcome.failure {
        eprintln!("vkpath: error after {done} spp: {error}; saving what was rendered");
    }
    save_or_rescue(output, &image, save)?;
    eprintln!(
        "{}",
        summary_line(
            &context.info,
            settings.width,
            settings.height,
            done,
            seconds
        )
    );
    if INTERRUPTED.load(Ordering::SeqCst) && done < settings.spp {
        bail!(
            "interrupted after {done} of {} spp; the partial render was saved to '{}'",
            settings.spp,
            output.display()
        );
    }
    fail_on_validation_messages(context)
}

/// Saves `image` to `output`; when that fails, nothing already rendered is lost: the image
/// (with its moments) goes to the temp directory and the error says where.
pub fn save_or_rescue(
    output: &Path,
    image: &RenderedImage,
    save: &SaveOptions,
) -> anyhow::Result<()> {
    let Err(error) = save_image(output, image, save) else {
        return Ok(());
    };
    let rescue = std::env::temp_dir().join(format!("vkpath-rescue-{}.exr", std::process::id()));
    let rescued = save_image(
        &rescue,
        image,
        &SaveOptions {
            moments: true,
            ..*save
        },
    );
    match rescued {
        Ok(()) => bail!(
            "{error}; the render was saved to '{}' instead",
            rescue.display()
        ),
        Err(_) => bail!("{error}"),
    }
}

/// Fails, after a command has done its work, when the validation layer (`--validate`)
/// reported any error or warning; they were logged as they came.
pub fn fail_on_validation_messages(context: &Context) -> anyhow::Result<()> {
    if let Some(messages) = context.validation_messages() {
        if messages.total() > 0 {
            bail!(
                "the validation layer reported {} errors and {} warnings (see the log above)",
                messages.errors(),
                messages.warnings()
            );
        }
    }
    Ok(())
}
