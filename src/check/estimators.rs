//! The estimators (`compute_direct_illumination`, Exercise 6; `get_ray_radiance`, Exercise
//! 7), judged end to end: `glsl/path_tracer.comp` is compiled at run time twice, with the
//! reference functions and with the user's, both render the workshop's Cornell box with the
//! matching integrator and independent seeds, and the two images are compared block by
//! block with z-tests (`crate::stats::ztest`): the variance of each block mean comes from
//! the per-pixel second moments, and a Šidák correction covers all blocks and channels. An
//! unbiased estimator written differently passes; a biased one (e.g. a path loop that never
//! multiplies the throughput by 2 a cos) fails. The reference, the user's image and a
//! difference image are written as PNG.

use std::path::Path;

use crate::check::compile::compile_kernel;
use crate::check::detect::WorkshopFunction;
use crate::check::report::FunctionReport;
use crate::check::Session;
use crate::error::{Error, Result};
use crate::image_data::RenderedImage;
use crate::output::{save_image, SaveOptions};
use crate::renderer::{spirv_words, Renderer, Traversal};
use crate::settings::{Integrator, PixelFilter, RenderSettings};
use crate::stats::ztest::{two_sided_p_value, z_score, z_test_images, MeanImage};

/// Side of the blocks whose means are compared: 8 x 8 pixels pool 64 x spp samples, so that
/// the block means are close to normal even though path-tracing samples are heavy-tailed
/// (see `crate::compare` for the same reasoning).
pub const BLOCK_SIZE: usize = 8;
/// Seeds of the two renders: different, so that the estimates are independent as the
/// z-test assumes.
const REFERENCE_SEED: u32 = 1;
/// See `REFERENCE_SEED`.
const USER_SEED: u32 = 2;
/// The renderer's default path length (the workshop's MAX_PATH_LENGTH).
const MAX_PATH_LENGTH: u32 = 5;

/// The integrator whose render exercises `function`.
pub fn integrator_for(function: WorkshopFunction) -> Option<Integrator> {
    match function {
        WorkshopFunction::ComputeDirectIllumination => Some(Integrator::DirectIllumination),
        WorkshopFunction::GetRayRadiance => Some(Integrator::PathTracing),
        _ => None,
    }
}

/// Renders the Cornell box with the reference and with the user's functions and z-tests the
/// block means at the session's per-test significance (Šidák-corrected again over the
/// blocks and channels).
pub fn check_estimator(session: &Session, function: WorkshopFunction) -> Result<FunctionReport> {
    let integrator = integrator_for(function).ok_or_else(|| {
        Error::InvalidSettings(format!("{} is not an estimator", function.name()))
    })?;
    let size = session.options.image_size;
    let spp = session.options.spp;
    let mut report = FunctionReport::new(
        function.name(),
        session.user.line_of(function),
        "render",
        format!(
            "the Cornell box rendered with your functions and with the reference ({size}x{size}, \
             {spp} spp each, independent seeds, {} integrator): the means of every \
             {BLOCK_SIZE}x{BLOCK_SIZE} block and colour channel must agree within their noise \
             (z-tests, variance from the per-pixel second moments, Šidák-corrected over all \
             blocks at {:.2e} family-wise)",
            match integrator {
                Integrator::DirectIllumination => "direct illumination (Exercise 6)",
                _ => "path tracing (Exercise 7)",
            },
            session.test_alpha
        ),
    );
    let reference = render(session, integrator, false)?;
    let yours = render(session, integrator, true)?;

    let mean_image = |image: &RenderedImage| -> Result<MeanImage> {
        let variances: Vec<[f64; 3]> = image
            .variance_of_mean()
            .iter()
            .map(|v| v.map(f64::from))
            .collect();
        MeanImage::from_rgb(size as usize, size as usize, &image.mean, &variances)
            .and_then(|m| m.block_average(BLOCK_SIZE))
            .map_err(|e| Error::InvalidSettings(e.to_string()))
    };
    let (reference_blocks, your_blocks) = (mean_image(&reference)?, mean_image(&yours)?);
    let z_report = z_test_images(&your_blocks, &reference_blocks, session.test_alpha)
        .map_err(|e| Error::InvalidSettings(e.to_string()))?;
    report.cases = z_report.test_count;
    report.measure("min_p_value", z_report.min_p_value);
    report.measure("worst_z", z_report.worst_z);
    report.measure("per_block_significance", z_report.significance);
    report.measure("reference_average", average(&reference));
    report.measure("your_average", average(&yours));
    list_failing_blocks(
        &mut report,
        &your_blocks,
        &reference_blocks,
        z_report.significance,
    );
    report.failures = z_report.rejected_count;
    report.passed = z_report.passed;
    report.summary = if report.passed {
        format!(
            "consistent with the reference: all {} block tests pass (average radiance {:.4} vs \
             {:.4})",
            report.cases,
            average(&yours),
            average(&reference)
        )
    } else {
        format!(
            "biased: {} of {} block tests reject (average radiance {:.4}, reference {:.4}; worst \
             z = {:.1})",
            report.failures,
            report.cases,
            average(&yours),
            average(&reference),
            z_report.worst_z
        )
    };
    report.images = save_images(session, function, &reference, &yours)?;
    Ok(report)
}

/// Renders the Cornell box with `path_tracer.comp` compiled at run time, with the user's
/// functions or without, and the workshop's loop over all triangles (compiled into the
/// kernel: the Cornell box fits).
fn render(session: &Session, integrator: Integrator, with_user: bool) -> Result<RenderedImage> {
    let scene = &session.scene;
    let camera = scene
        .camera
        .ok_or_else(|| Error::MissingInput("the Cornell box has no camera".into()))?;
    let user = with_user.then_some(session.user);
    let compiled =
        compile_kernel("path_tracer.comp", user, &[]).map_err(Error::ShaderCompilation)?;
    let bytes: Vec<u8> = compiled
        .spirv
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
    let size = session.options.image_size;
    let settings = RenderSettings {
        width: size,
        height: size,
        spp: session.options.spp,
        max_path_length: MAX_PATH_LENGTH,
        seed: if with_user { USER_SEED } else { REFERENCE_SEED },
        pixel_filter: PixelFilter::Box,
        integrator,
        samples_per_frame: 8,
        ..RenderSettings::default()
    };
    let mut renderer = Renderer::with_kernel(
        &session.context,
        scene,
        &camera,
        settings,
        &spirv_words(&bytes)?,
        Traversal::ConstantTriangles,
    )?;
    while !renderer.is_complete() {
        renderer.render_batch()?;
    }
    renderer.read_back()
}

/// The average radiance over all pixels and channels.
fn average(image: &RenderedImage) -> f64 {
    image.average().iter().sum::<f64>() / 3.0
}

/// Lists the blocks whose z-test rejects, most significant first.
fn list_failing_blocks(
    report: &mut FunctionReport,
    yours: &MeanImage,
    reference: &MeanImage,
    significance: f64,
) {
    let channels = ["red", "green", "blue"];
    let mut failing: Vec<(f64, usize)> = Vec::new();
    for index in 0..yours.means.len() {
        let z = z_score(
            yours.means[index],
            yours.variances_of_mean[index],
            reference.means[index],
            reference.variances_of_mean[index],
        );
        let p_value = two_sided_p_value(z);
        if p_value < significance {
            failing.push((p_value, index));
        }
    }
    failing.sort_by(|a, b| a.0.total_cmp(&b.0));
    for &(p_value, index) in failing.iter().take(crate::check::report::SHOWN_MISMATCHES) {
        let element = index / yours.channel_count;
        let (x, y) = (element % yours.width, element / yours.width);
        let sd = |image: &MeanImage| image.variances_of_mean[index].sqrt();
        report.mismatches.push(crate::check::report::Mismatch {
            input: format!(
                "block of pixels x {}..{}, y {}..{} (from the top), {}",
                x * BLOCK_SIZE,
                (x + 1) * BLOCK_SIZE,
                y * BLOCK_SIZE,
                (y + 1) * BLOCK_SIZE,
                channels[index % yours.channel_count]
            ),
            expected: format!(
                "{:.5} ± {:.5} (reference)",
                reference.means[index],
                sd(reference)
            ),
            actual: format!(
                "{:.5} ± {:.5} (p = {p_value:.2e})",
                yours.means[index],
                sd(yours)
            ),
        });
    }
}

/// Writes `<function>-reference.png`, `<function>-yours.png` and
/// `<function>-difference.png` to the output directory and returns their paths.
fn save_images(
    session: &Session,
    function: WorkshopFunction,
    reference: &RenderedImage,
    yours: &RenderedImage,
) -> Result<Vec<String>> {
    let directory = &session.options.output_dir;
    std::fs::create_dir_all(directory).map_err(|e| {
        Error::Image(format!(
            "cannot create the output directory '{}': {e}",
            directory.display()
        ))
    })?;
    let mut written = Vec::new();
    for (suffix, image) in [
        ("reference", reference.clone()),
        ("yours", yours.clone()),
        ("difference", difference_image(reference, yours)),
    ] {
        let path = directory.join(format!("{}-{suffix}.png", function.name()));
        save_image(&path, &image, &SaveOptions::default())?;
        written.push(display(&path));
    }
    Ok(written)
}

fn display(path: &Path) -> String {
    path.display().to_string()
}

/// Where the user's image is brighter (red) or darker (blue) than the reference: the
/// difference of the pixels' average over the channels, at full intensity where it equals
/// the reference image's average radiance.
pub fn difference_image(reference: &RenderedImage, yours: &RenderedImage) -> RenderedImage {
    let scale = 1.0 / (average(reference) as f32).max(1e-6);
    let mean = reference
        .mean
        .iter()
        .zip(&yours.mean)
        .map(|(r, y)| {
            let d = ((y[0] - r[0]) + (y[1] - r[1]) + (y[2] - r[2])) / 3.0 * scale;
            [d.max(0.0), 0.0, (-d).max(0.0), 1.0]
        })
        .collect();
    RenderedImage {
        width: reference.width,
        height: reference.height,
        mean,
        second_moment: vec![[0.0; 3]; reference.mean.len()],
        sample_count: vec![1.0; reference.mean.len()],
    }
}
