//! The estimators (`compute_direct_illumination`, Exercise 6; `get_ray_radiance`, Exercise
//! 7), judged end to end: `glsl/path_tracer.comp` is compiled at run time with the reference
//! functions and with the user's estimator (every other function the reference's), both
//! render the workshop's Cornell box with the matching integrator and independent seeds,
//! and the two images are compared block by block with z-tests (`crate::stats::ztest`): the
//! variance of each block mean comes from the per-pixel second moments, and a Šidák
//! correction covers all blocks and channels. An unbiased estimator written differently
//! passes; a biased one (e.g. a path loop that never multiplies the throughput by 2 a cos)
//! fails, with the likely cause named when the brightness ratio points to one.
//!
//! Both renders use intersections that ignore the surface a ray starts on
//! (`IGNORE_START_SURFACE`), so that the slides' loop, which moves the origin to the hit
//! point with no offset, is judged as the estimator it is. A third render runs the user's
//! estimator as their file does, with their own intersection functions (or the reference's,
//! which accept t >= 0 as the workshop's do): when that one comes out darker, a warning says
//! so, with the usual remedies, apart from the verdict. The reference, the user's image and
//! a difference image (with a colour bar) are written as PNG.

use crate::check::compile::{compile_kernel, UserCode};
use crate::check::detect::WorkshopFunction;
use crate::check::report::FunctionReport;
use crate::check::Session;
use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::kernels::variant::{path_tracer_variant, KernelSource, SceneSummary, VariantSettings};
use crate::kernels::PATH_TRACER;
use crate::render::settings::{Integrator, PixelFilter, RenderSettings};
use crate::render::{Renderer, Traversal};
use crate::stats::ztest::{two_sided_p_value, z_score, z_test_images, MeanImage};

/// The renders are compared in blocks of `block_size` pixels a side: at least 8 x 8
/// pixels, so that a block pools at least 64 x spp samples and its mean is close to normal
/// even though path-tracing samples are heavy-tailed (see `crate::compare` for the same
/// reasoning), and an 8 x 8 grid of blocks for larger images, so that a larger picture keeps
/// the statistics of the default 64 blocks.
pub fn block_size(image_size: u32) -> usize {
    (image_size as usize / 8).max(8)
}
/// Seeds of the two renders: different, so that the estimates are independent as the
/// z-test assumes.
const REFERENCE_SEED: u32 = 1;
/// See `REFERENCE_SEED`.
const USER_SEED: u32 = 2;
/// Seed of the render with the user's own intersection functions (independent of both).
const COMBINED_SEED: u32 = 3;
/// The render's path length when the file does not define MAX_PATH_LENGTH (the workshop's).
const MAX_PATH_LENGTH: u32 = crate::render::settings::DEFAULT_MAX_PATH_LENGTH;

/// Which kernel a render runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Variant {
    /// The reference functions, intersections ignoring the start surface.
    Reference,
    /// The user's estimator alone, intersections ignoring the start surface.
    Yours,
    /// The user's estimator with the user's own intersection functions (or the reference's),
    /// as the user's file runs.
    AsYourFileRuns,
}

/// The integrator whose render exercises `function`.
pub fn integrator_for(function: WorkshopFunction) -> Option<Integrator> {
    match function {
        WorkshopFunction::ComputeDirectIllumination => Some(Integrator::DirectIllumination),
        WorkshopFunction::GetRayRadiance => Some(Integrator::PathTracing),
        _ => None,
    }
}

/// Renders the Cornell box with the reference and with the user's estimator and z-tests the
/// block means at the session's per-test significance (Šidák-corrected again over the
/// blocks and channels); then renders it as the user's file runs, for the self-intersection
/// warning.
pub fn check_estimator(session: &Session, function: WorkshopFunction) -> Result<FunctionReport> {
    let integrator = integrator_for(function).ok_or_else(|| {
        Error::InvalidSettings(format!("{} is not an estimator", function.name()))
    })?;
    let size = session.options.image_size;
    let spp = session.options.spp;
    let block = block_size(size);
    let max_path_length = path_length(session, function);
    let mut report = FunctionReport::new(
        function.name(),
        session.user.line_of(function),
        "render",
        format!(
            "the Cornell box rendered with your {} and with the reference ({size}x{size}, \
             {spp} spp each, independent seeds, {} integrator{}, every other function the \
             reference's, intersections that ignore the surface a ray starts on): the means of \
             every {block}x{block} block and colour channel must agree within their noise \
             (z-tests, variance from the per-pixel second moments, Šidák-corrected over all \
             blocks at {:.2e} family-wise)",
            function.name(),
            match integrator {
                Integrator::DirectIllumination => "direct illumination (Exercise 6)",
                _ => "path tracing (Exercise 7)",
            },
            if function == WorkshopFunction::GetRayRadiance {
                format!(", MAX_PATH_LENGTH {max_path_length}")
            } else {
                String::new()
            },
            session.test_alpha
        ),
    );
    // A loop without end costs the loop guard's USER_LOOP_LIMIT iterations in every path
    // that enters it, each of which may trace the scene: a probe of few paths finds it in a
    // second, before the full renders would spend minutes on it.
    let your_kernel = Kernel::compile(session, function, Variant::Yours)?;
    your_kernel.run(session, function, PROBE_SIZE, 1)?;
    let reference = render(session, function, Variant::Reference)?;
    let yours = your_kernel.run(session, function, size, spp)?;
    let (reference_blocks, your_blocks) = (
        block_means(&reference, size, block)?,
        block_means(&yours, size, block)?,
    );
    let z_report = z_test_images(&your_blocks, &reference_blocks, session.test_alpha)
        .map_err(|e| Error::InvalidSettings(e.to_string()))?;
    report.cases = z_report.test_count;
    report.measure("min_p_value", z_report.min_p_value);
    report.measure("worst_z", z_report.worst_z);
    report.measure("per_block_significance", z_report.significance);
    report.measure("reference_average", average(&reference));
    report.measure("your_average", average(&yours));
    let ratio = median_block_ratio(&your_blocks, &reference_blocks);
    report.measure("median_block_ratio", ratio);
    list_failing_blocks(
        &mut report,
        &your_blocks,
        &reference_blocks,
        z_report.significance,
        block,
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
        report.hint = Some(likely_cause(function, ratio));
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

    // The estimator as the file runs it: a darker image there is self-intersection.
    if report.passed {
        let as_file_runs = render(session, function, Variant::AsYourFileRuns)?;
        let combined_blocks = block_means(&as_file_runs, size, block)?;
        let combined = z_test_images(&combined_blocks, &reference_blocks, session.test_alpha)
            .map_err(|e| Error::InvalidSettings(e.to_string()))?;
        let darker = 1.0 - average(&as_file_runs) / average(&reference);
        report.measure("as_your_file_runs_average", average(&as_file_runs));
        if !combined.passed {
            report
                .warnings
                .push(self_intersection_warning(session, function, darker));
        }
    }
    Ok(report)
}

/// MAX_PATH_LENGTH of the renders: the file's own, when it defines one in 1..=64, else the
/// workshop's 5. Only get_ray_radiance reads it.
fn path_length(session: &Session, function: WorkshopFunction) -> u32 {
    match session.user.prepared.max_path_length {
        Some(length)
            if function == WorkshopFunction::GetRayRadiance && (1..=64).contains(&length) =>
        {
            length
        }
        _ => MAX_PATH_LENGTH,
    }
}

/// The warning for an estimator that passes on its own but renders darker (or otherwise
/// differently) with the file's own intersection functions.
fn self_intersection_warning(session: &Session, function: WorkshopFunction, darker: f64) -> String {
    let user = session.user;
    let own: Vec<&str> = [
        WorkshopFunction::RayTriangleIntersection,
        WorkshopFunction::RayMeshIntersection,
    ]
    .into_iter()
    .filter(|f| user.judged_functions().contains(f))
    .map(WorkshopFunction::name)
    .collect();
    let with = if own.is_empty() {
        "with intersection functions that accept hits at t >= 0 (the workshop's and vkpath's reference)".to_string()
    } else {
        format!("together with your own {}", own.join(" and "))
    };
    if darker > 0.0 {
        format!(
            "{with}, your {} renders {:.0}% darker than the reference: a ray that leaves a \
             surface hits that same surface again at t ≈ 0 through rounding \
             (self-intersection), since the new origin x + t·ω lies on it. The usual remedies: \
             start the next ray a little off the surface (origin += 1e-4 * normal) or accept \
             only hits with t > 1e-4 in ray_triangle_intersection. Your {} itself is correct: \
             judged with intersections that ignore the surface a ray starts on, it passes.",
            function.name(),
            100.0 * darker,
            function.name()
        )
    } else {
        format!(
            "{with}, your {} renders {:.0}% brighter than the reference, although it passes \
             with the reference intersections: look at how your intersection functions and \
             your estimator work together.",
            function.name(),
            -100.0 * darker
        )
    }
}

/// An estimator's self-intersection warning (`self_intersection_warning`) rewritten when
/// intersection functions of the user's that fail on their own (`failing`, judged before
/// it) took part in the render as the file runs it: a triangle they miss (a loop that stops
/// one short) darkens that image as much as self-intersection would, so the warning names
/// them instead. Other verdicts are left as they are.
pub fn blame_failing_intersections(report: &mut FunctionReport, failing: &[&str]) {
    if failing.is_empty() {
        return;
    }
    let darker = match (
        report.measurements.get("as_your_file_runs_average"),
        report.measurements.get("reference_average"),
    ) {
        (Some(&yours), Some(&reference)) if reference > 0.0 => 100.0 * (1.0 - yours / reference),
        _ => return,
    };
    let function = report.function.clone();
    let verb = if failing.len() > 1 {
        "fail each"
    } else {
        "fails"
    };
    for warning in &mut report.warnings {
        if warning.contains("self-intersection") {
            *warning = format!(
                "together with your own {names}, which {verb} on its own (see its verdict), \
                 your {function} renders {amount:.0}% {direction} than the reference: fix {names} \
                 first (a triangle it misses is missing from the image too). Your {function} \
                 itself is correct: judged with intersections that ignore the surface a ray \
                 starts on, it passes.",
                names = failing.join(" and "),
                amount = darker.abs(),
                direction = if darker >= 0.0 { "darker" } else { "brighter" },
            );
        }
    }
}

/// The likely cause of a biased estimate, from the median ratio of the user's block means
/// to the reference's (a heuristic for the report; the verdict comes from the z-tests).
fn likely_cause(function: WorkshopFunction, ratio: f64) -> String {
    use std::f64::consts::PI;
    let factors = [
        (2.0 * PI, "a factor 2π too many"),
        (1.0 / (2.0 * PI), "a factor 2π missing"),
        (PI, "a factor π too many (the diffuse BRDF is a/π)"),
        (1.0 / PI, "a factor π missing"),
        (2.0, "a factor 2 too many"),
        (0.5, "a factor 2 missing (uniform hemisphere sampling has density 1/(2π), so a/π · cos / (1/(2π)) = 2·a·cos)"),
    ];
    if function == WorkshopFunction::ComputeDirectIllumination {
        if let Some((_, words)) = factors.iter().find(|(f, _)| (ratio / f - 1.0).abs() < 0.1) {
            return format!(
                "your image is {ratio:.3} times the reference's: {words}. The estimate is \
                 L_e(x) + a(x)/π · 2π · L_e(y) · dot(n(x), ω)"
            );
        }
    }
    if ratio > 1.3 {
        match function {
            WorkshopFunction::GetRayRadiance => format!(
                "your image is {ratio:.2} times as bright as the reference: light is not \
                 attenuated enough at the bounces; multiply the throughput by \
                 a(x) · 2 · dot(n(x), ω) after sampling each new direction ω"
            ),
            _ => format!(
                "your image is {ratio:.2} times as bright as the reference: check the factors \
                 a(x)/π · 2π · dot(n(x), ω)"
            ),
        }
    } else if ratio < 0.77 {
        format!(
            "your image is {ratio:.2} times as bright as the reference: light is lost; check \
             that the emission is added with the throughput weight, that dot(n(x), ω) uses \
             the sampled direction, and the factors (2 per bounce, not 1/π)"
        )
    } else {
        format!(
            "your image is {ratio:.2} times as bright as the reference overall, but some \
             regions differ (see the difference image): e.g. a direction sampled around the \
             wrong normal, or emission that is not found at the hit"
        )
    }
}

/// The median over blocks and channels of the user's block mean divided by the
/// reference's (blocks where the reference is 0 left out; 1 when none is left).
fn median_block_ratio(yours: &MeanImage, reference: &MeanImage) -> f64 {
    let mut ratios: Vec<f64> = yours
        .means
        .iter()
        .zip(&reference.means)
        .filter(|(_, r)| **r > 1e-6)
        .map(|(y, r)| y / r)
        .collect();
    if ratios.is_empty() {
        return 1.0;
    }
    ratios.sort_by(f64::total_cmp);
    ratios[ratios.len() / 2]
}

/// The block means of a square render, with their variances.
fn block_means(image: &RenderedImage, size: u32, block: usize) -> Result<MeanImage> {
    let variances: Vec<[f64; 3]> = image
        .variance_of_mean()
        .iter()
        .map(|v| v.map(f64::from))
        .collect();
    MeanImage::from_rgb(size as usize, size as usize, &image.mean, &variances)
        .and_then(|m| m.block_average(block))
        .map_err(|e| Error::InvalidSettings(e.to_string()))
}

/// Side of the probe render that runs the user's estimator before the full renders, at one
/// sample per pixel: 256 paths, of which many leave the box or end at the light, so a loop
/// that never ends on such a path is found at once (each path that enters it costs the loop
/// guard's 20 000 iterations, about as much as a whole 32 x 32 render).
const PROBE_SIZE: u32 = 16;

/// Renders the Cornell box with `path_tracer.comp` compiled at run time as `variant` says
/// (`Kernel`), at the session's size and samples per pixel.
fn render(
    session: &Session,
    function: WorkshopFunction,
    variant: Variant,
) -> Result<RenderedImage> {
    let size = session.options.image_size;
    Kernel::compile(session, function, variant)?.run(session, function, size, session.options.spp)
}

/// `path_tracer.comp` compiled at run time for one render variant, with the workshop's loop
/// over all triangles (compiled into the kernel, or read from the triangle buffer when the
/// user's own intersection functions need whole triangles).
struct Kernel {
    /// The kernel.
    spirv: Vec<u32>,
    /// How it finds the triangles.
    traversal: Traversal,
    /// Which render it is.
    variant: Variant,
}

impl Kernel {
    /// Compiles the kernel of `variant` for the estimator `function`.
    fn compile(session: &Session, function: WorkshopFunction, variant: Variant) -> Result<Kernel> {
        let user = session.user;
        let intersections = [
            WorkshopFunction::RayTriangleIntersection,
            WorkshopFunction::RayMeshIntersection,
        ];
        let code: Option<UserCode> = match variant {
            Variant::Reference => None,
            Variant::Yours => Some(user.code(&[function])),
            Variant::AsYourFileRuns => {
                let mut active = vec![function];
                active.extend(
                    intersections
                        .into_iter()
                        .filter(|f| user.judged_functions().contains(f)),
                );
                Some(user.code(&active))
            }
        };
        // The user's ray_triangle_intersection may read any member of the triangle, which the
        // constant triangles do not carry.
        let traversal = if variant == Variant::AsYourFileRuns {
            Traversal::Linear
        } else {
            Traversal::ConstantTriangles
        };
        // The path tracer's build for the traversal (crate::kernels), with check's own macros.
        let build = path_tracer_variant(
            &SceneSummary::default(),
            &VariantSettings::default(),
            traversal,
            KernelSource::Given,
        )?
        .build;
        let mut macros = build.macros.to_vec();
        if variant != Variant::AsYourFileRuns {
            macros.push(("IGNORE_START_SURFACE", "1"));
        }
        let compiled = compile_kernel(PATH_TRACER.source, code.as_ref(), &macros)
            .map_err(|error| Error::ShaderCompilation(error.to_string()))?;
        Ok(Kernel {
            spirv: compiled.spirv,
            traversal,
            variant,
        })
    }

    /// Renders the Cornell box with the kernel, `size` x `size` pixels at `spp` samples per
    /// pixel.
    fn run(
        &self,
        session: &Session,
        function: WorkshopFunction,
        size: u32,
        spp: u32,
    ) -> Result<RenderedImage> {
        let scene = &session.scene;
        let camera = scene
            .camera
            .ok_or_else(|| Error::MissingInput("the Cornell box has no camera".into()))?;
        let integrator = integrator_for(function).ok_or_else(|| {
            Error::InvalidSettings(format!("{} is not an estimator", function.name()))
        })?;
        let settings = RenderSettings {
            width: size,
            height: size,
            spp,
            max_path_length: path_length(session, function),
            seed: match self.variant {
                Variant::Reference => REFERENCE_SEED,
                Variant::Yours => USER_SEED,
                Variant::AsYourFileRuns => COMBINED_SEED,
            },
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
            &self.spirv,
            self.traversal,
        )?;
        renderer.render_all()
    }
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
    block: usize,
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
                x * block,
                (x + 1) * block,
                y * block,
                (y + 1) * block,
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
    session.save_pngs(&[
        (format!("{}-reference", function.name()), reference.clone()),
        (format!("{}-yours", function.name()), yours.clone()),
        (
            format!("{}-difference", function.name()),
            difference_image(reference, yours),
        ),
    ])
}

/// Where the user's image is brighter (red) or darker (blue) than the reference: the
/// difference of the pixels' average over the channels, at full intensity where it equals
/// the reference image's average radiance. Below the image, after a grey line, a colour bar
/// is the legend: from -100% (left, blue) through 0 (black, the middle) to +100% (right,
/// red) of the reference's average radiance.
pub fn difference_image(reference: &RenderedImage, yours: &RenderedImage) -> RenderedImage {
    let scale = 1.0 / (average(reference) as f32).max(1e-6);
    let colour = |d: f32| [d.max(0.0), 0.0, (-d).max(0.0), 1.0];
    let mut mean: Vec<[f32; 4]> = reference
        .mean
        .iter()
        .zip(&yours.mean)
        .map(|(r, y)| colour(((y[0] - r[0]) + (y[1] - r[1]) + (y[2] - r[2])) / 3.0 * scale))
        .collect();
    let width = reference.width;
    let bar_height = (reference.height / 12).max(3);
    mean.extend((0..width).map(|_| [0.5, 0.5, 0.5, 1.0]));
    for _ in 0..bar_height {
        mean.extend((0..width).map(|x| colour((x as f32 + 0.5) / width as f32 * 2.0 - 1.0)));
    }
    let pixel_count = mean.len();
    RenderedImage {
        width,
        height: reference.height + 1 + bar_height,
        mean,
        second_moment: vec![[0.0; 3]; pixel_count],
        sample_count: vec![1.0; pixel_count],
    }
}

/// The legend of `difference_image`, in words.
pub const DIFFERENCE_LEGEND: &str = "red where yours is brighter, blue where it is darker, \
    full intensity at a difference equal to the reference's average radiance; the bar below \
    the image runs from -100% (left, blue) through 0 (middle, black) to +100% (right, red)";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failing_mesh_takes_the_blame_from_self_intersection() {
        let mut report = FunctionReport::new("get_ray_radiance", 9, "render", String::new());
        report.passed = true;
        report.measure("reference_average", 0.5);
        report.measure("as_your_file_runs_average", 0.4);
        report.warnings.push(
            "together with your own ray_mesh_intersection, your get_ray_radiance renders 20% darker than the reference: a ray that leaves a surface hits that same surface again at t ≈ 0 through rounding (self-intersection) ...".into(),
        );
        let unchanged = report.clone();
        blame_failing_intersections(&mut report, &[]);
        assert_eq!(report, unchanged);
        blame_failing_intersections(&mut report, &["ray_mesh_intersection"]);
        let warning = &report.warnings[0];
        assert!(!warning.contains("self-intersection"), "{warning}");
        assert!(
            warning.contains("ray_mesh_intersection, which fails on its own")
                && warning.contains("renders 20% darker"),
            "{warning}"
        );
    }

    fn flat(width: u32, height: u32, value: f32) -> RenderedImage {
        let count = (width * height) as usize;
        RenderedImage {
            width,
            height,
            mean: vec![[value, value, value, 1.0]; count],
            second_moment: vec![[0.0; 3]; count],
            sample_count: vec![1.0; count],
        }
    }

    #[test]
    fn difference_image_has_a_colour_bar() {
        let difference = difference_image(&flat(16, 24, 1.0), &flat(16, 24, 1.5));
        assert_eq!((difference.width, difference.height), (16, 24 + 1 + 3));
        assert_eq!(
            difference.pixel(3, 5),
            [0.5, 0.0, 0.0, 1.0],
            "half brighter: half red"
        );
        assert_eq!(difference.pixel(0, 24), [0.5, 0.5, 0.5, 1.0]);
        let left = difference.pixel(0, 26);
        let right = difference.pixel(15, 26);
        assert!(left[2] > 0.9 && left[0] == 0.0, "{left:?}");
        assert!(right[0] > 0.9 && right[2] == 0.0, "{right:?}");
    }

    #[test]
    fn blocks_scale_with_the_image() {
        assert_eq!(block_size(32), 8);
        assert_eq!(block_size(64), 8);
        assert_eq!(block_size(128), 16);
    }

    #[test]
    fn likely_causes_name_the_factor() {
        let hint = likely_cause(
            WorkshopFunction::ComputeDirectIllumination,
            1.0 / (2.0 * std::f64::consts::PI),
        );
        assert!(hint.contains("2π missing"), "{hint}");
        let hint = likely_cause(WorkshopFunction::GetRayRadiance, 2.5);
        assert!(hint.contains("throughput"), "{hint}");
    }
}
