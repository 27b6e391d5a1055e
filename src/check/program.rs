//! The `program` verdict: a runnable ShaderToy program that accumulates the workshop's scene
//! (its Buffer A, or its Image pass when it has no buffer) is run for N frames with `vkpath
//! shadertoy`'s runner, and the image it accumulates is compared with vkpath's reference
//! render of the same camera (the workshop's Cornell box), pixel filter (the pixel centres,
//! as the workshop's `pixel_coord / iResolution.xy`), path length (the file's
//! MAX_PATH_LENGTH, else 5) and integrator, by block z-tests as the estimators are judged
//! (`crate::check::estimators`).
//!
//! Variances: the reference's come from its per-pixel second moments. The program's come
//! from its frames: the workshop's mainImage keeps the running mean of its frames,
//! A_f = mix(A_{f-1}, X_f, 1/(f+1)), so each frame's own estimate is recovered exactly as
//! X_f = (f+1) A_f - f A_{f-1}; the frames are independent estimates (each frame seeds its
//! random numbers with iFrame), so the variance of the final mean is the frames' sample
//! variance over N. A program that does not keep a running mean is caught: its recovered
//! frame estimates go negative, which no radiance estimate does, and it is not judged.
//!
//! A program that fails and renders darker is told the cause when the function verdicts
//! point to it: a get_ray_radiance that passes on its own (judged with intersections that
//! ignore the surface a ray starts on) but renders darker with the file's own intersections
//! is self-intersection; a get_ray_radiance that fails on its own is the program's bias.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::check::estimators::{block_size, difference_image};
use crate::check::report::FunctionReport;
use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::image_io::output::{save_image, SaveOptions};
use crate::render::settings::{Integrator, PixelFilter, RenderSettings};
use crate::render::Renderer;
use crate::scene::Scene;
use crate::shadertoy::{ChannelSource, Pass, PassKind, Program, ShadertoyRunner};
use crate::stats::ztest::{z_test_images, MeanImage};
use crate::vk::Context;

/// Frames run: at the workshop's 8 samples per frame, 1024 samples per pixel, so that a
/// block of 8 x 8 pixels pools 65536 paths; self-intersection (about 40% darker) and a
/// missing factor 2 are many standard deviations away.
pub const DEFAULT_FRAMES: u32 = 128;
/// Fewest frames the variance can be estimated from (the sample variance of each pixel's
/// frame estimates, pooled over a block, has 64 (N - 1) degrees of freedom).
pub const MIN_FRAMES: u32 = 8;
/// Samples per pixel of the reference render: more than the program's, so that the
/// comparison's noise is mostly the program's.
const REFERENCE_SPP: u32 = 2048;
/// Seed of the reference: not 0, whose samples are the workshop's own sequence, so that it
/// is independent of the program's (the z-test assumes independent estimates).
const REFERENCE_SEED: u32 = 11;
/// A recovered frame estimate below -NEGATIVE_TOLERANCE x the image's largest value is not
/// rounding: (f+1) A_f - f A_{f-1} in float loses about f ulps of A, 2^-23 x 256 = 3e-5
/// relative at 256 frames; 1e-3 leaves 30 times that.
const NEGATIVE_TOLERANCE: f64 = 1e-3;

/// How the program is judged.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramOptions {
    /// Side of the square image, in pixels.
    pub size: u32,
    /// Frames to run.
    pub frames: u32,
    /// Significance level of the test (Šidák-corrected again over blocks and channels).
    pub alpha: f64,
    /// The render's path length (the file's MAX_PATH_LENGTH).
    pub max_path_length: u32,
    /// Where the images go.
    pub output_dir: PathBuf,
}

/// The `method` of a program verdict that is no verdict: the program does not render the
/// workshop's scene with the workshop's running mean, so comparing it with the reference
/// means nothing. The report lists it as NOT JUDGED (`not_judged_of`), and it does not
/// change the exit status.
pub const NOT_JUDGED_METHOD: &str = "not judged";

/// The NOT JUDGED entry that stands for `verdict` when the program could not be judged
/// (`NOT_JUDGED_METHOD`), with the reason; `None` for a real verdict.
pub fn not_judged_of(verdict: &FunctionReport) -> Option<crate::check::NotJudged> {
    (verdict.method == NOT_JUDGED_METHOD).then(|| crate::check::NotJudged {
        function: verdict.function.clone(),
        line: verdict.line,
        reason: verdict
            .summary
            .strip_prefix("not judged: ")
            .unwrap_or(&verdict.summary)
            .to_string()
            + &verdict
                .hint
                .as_ref()
                .map_or(String::new(), |hint| format!(" ({hint})")),
        file: verdict.file.clone(),
    })
}

/// The Image pass of a program whose only tab is a buffer: shows Buffer A.
const SHOW_BUFFER_A: &str = "void mainImage(out vec4 fragColor, in vec2 fragCoord) {\n    fragColor = texelFetch(iChannel0, ivec2(fragCoord), 0);\n}\n";

/// Whether a tab is a runnable program of the workshop's scene: it has `mainImage` and
/// calls `get_ray_radiance`.
pub fn is_workshop_program(text: &str) -> bool {
    let tokens = crate::check::glsl_syntax::tokenize(text);
    tokens.iter().any(|t| t.text == "mainImage")
        && tokens.iter().any(|t| t.text == "get_ray_radiance")
}

/// Whether the tabs of a program (ShaderToy's order, each (name, text)) are a runnable
/// program of the workshop's scene as `is_workshop_program` reads one text: a tab has
/// `mainImage`, and a tab (the same, or its Common tab) names `get_ray_radiance`.
pub fn is_workshop_program_tabs(tabs: &[(PathBuf, String)]) -> bool {
    let names = |name: &str| {
        tabs.iter().any(|(_, text)| {
            crate::check::glsl_syntax::tokenize(text)
                .iter()
                .any(|t| t.text == name)
        })
    };
    names("mainImage") && names("get_ray_radiance")
}

/// The program of a user's tabs with entry points (`tabs`, in ShaderToy's order) after
/// their Common tab, and the pass that accumulates: one tab is a Buffer A whose iChannel0
/// is its own previous frame (the workshop's tab), shown by an Image pass of vkpath's;
/// several are Buffers A, B, … and the Image pass last, with `vkpath shadertoy`'s default
/// channels. Buffer A accumulates.
pub fn program_of_tabs(
    common: Option<(PathBuf, String)>,
    tabs: &[(PathBuf, String)],
) -> Option<(Program, PassKind)> {
    let (last, buffers) = tabs.split_last()?;
    if buffers.len() > 4 {
        return None;
    }
    // A pass whose iChannel0 reads `channel0`.
    let pass = |kind: PassKind, path: &Path, text: &str, channel0: PassKind| {
        let mut channels: [Option<ChannelSource>; 4] = Default::default();
        channels[0] = Some(ChannelSource::Buffer(channel0));
        Pass {
            kind,
            path: path.to_path_buf(),
            text: text.to_string(),
            channels,
        }
    };
    let mut passes = Vec::new();
    if buffers.is_empty() {
        passes.push(pass(PassKind::BufferA, &last.0, &last.1, PassKind::BufferA));
        passes.push(pass(
            PassKind::Image,
            Path::new("(vkpath's Image pass showing Buffer A)"),
            SHOW_BUFFER_A,
            PassKind::BufferA,
        ));
    } else {
        for ((path, text), kind) in buffers.iter().zip(PassKind::BUFFERS) {
            passes.push(pass(kind, path, text, kind));
        }
        passes.push(pass(PassKind::Image, &last.0, &last.1, PassKind::BufferA));
    }
    let mut program = Program { common, passes };
    // The VS Code Shader Toy directives wire the channels as in `vkpath shadertoy`; one that
    // names a tab not given leaves the defaults.
    let mut wired = program.clone();
    if wired.wire_channel_directives().is_ok() {
        program = wired;
    }
    Some((program, PassKind::BufferA))
}

/// The user's files as (name, text), split where each begins.
pub fn user_tabs(user: &crate::check::UserFunctions) -> Vec<(PathBuf, String)> {
    if user.sources.len() < 2 {
        return vec![(PathBuf::from(&user.display_name), user.text.clone())];
    }
    let lines: Vec<&str> = user.text.split_inclusive('\n').collect();
    user.sources
        .iter()
        .enumerate()
        .map(|(i, source)| {
            let start = source.first_line.saturating_sub(1).min(lines.len());
            let end = user
                .sources
                .get(i + 1)
                .map_or(lines.len(), |next| next.first_line.saturating_sub(1))
                .clamp(start, lines.len());
            (PathBuf::from(&source.name), lines[start..end].concat())
        })
        .collect()
}

/// The `program` verdict on the user's files when they are a runnable program of the
/// workshop's scene (`is_workshop_program`): `judge_tabs_program` on the files of `user`
/// with its `MAX_PATH_LENGTH`. `None` for other files.
pub fn judge_user_program(
    context: &Arc<Context>,
    user: &crate::check::UserFunctions,
    options: &crate::check::CheckOptions,
    test_alpha: f64,
    functions: &[FunctionReport],
) -> Result<Option<FunctionReport>> {
    judge_tabs_program(
        context,
        &user_tabs(user),
        user.prepared.max_path_length,
        options,
        test_alpha,
        functions,
    )
}

/// The `program` verdict on `tabs` (the user's files in ShaderToy's order, each (name,
/// text)) when they are a runnable program of the workshop's scene: the tabs with
/// `mainImage` as `program_of_tabs` makes them (a tab without one, first, is the Common
/// tab), at the check's image size up to `MAX_PROGRAM_SIZE`, for `options.program_frames`
/// frames, at the per-test significance `test_alpha`, with the file's `max_path_length`
/// (else 5). `None` for other files.
pub fn judge_tabs_program(
    context: &Arc<Context>,
    tabs: &[(PathBuf, String)],
    max_path_length: Option<u32>,
    options: &crate::check::CheckOptions,
    test_alpha: f64,
    functions: &[FunctionReport],
) -> Result<Option<FunctionReport>> {
    if !is_workshop_program_tabs(tabs) {
        return Ok(None);
    }
    let has_entry = |text: &str| {
        crate::check::glsl_syntax::tokenize(text)
            .iter()
            .any(|t| t.text == "mainImage")
    };
    let mut common = None;
    let mut passes = Vec::new();
    for (index, (path, text)) in tabs.iter().enumerate() {
        if has_entry(text) {
            passes.push((path.clone(), text.clone()));
        } else if index == 0 {
            common = Some((path.clone(), text.clone()));
        }
    }
    let shaped = program_of_tabs(common, &passes);
    let reason = match &shaped {
        None => Some(format!(
            "your files have {} tabs with mainImage, more than ShaderToy's 4 buffers and the \
             Image tab",
            passes.len()
        )),
        Some(_) => crate::check::program_shape::not_the_workshops_scene(tabs),
    };
    if let Some(reason) = reason {
        let (file, line) = program_place(tabs);
        let mut report = FunctionReport::new(
            "program",
            line,
            NOT_JUDGED_METHOD,
            "judged only when it renders the workshop's scene with the workshop's running mean"
                .into(),
        );
        report.file = file;
        report.summary = format!("not judged: {reason}");
        return Ok(Some(report));
    }
    let Some((program, accumulated)) = shaped else {
        return Ok(None);
    };
    let program_options = ProgramOptions {
        size: options.image_size.min(MAX_PROGRAM_SIZE),
        frames: options.program_frames,
        alpha: test_alpha,
        max_path_length: max_path_length
            .filter(|l| (1..=64).contains(l))
            .unwrap_or(crate::render::settings::DEFAULT_MAX_PATH_LENGTH),
        output_dir: options.output_dir.clone(),
    };
    judge_program(context, &program, accumulated, functions, &program_options).map(Some)
}

/// Side of the probe frame that runs the program before its full frames (see
/// `judge_program`): 64 pixels, each with the workshop's 8 samples.
const PROBE_SIZE: u32 = 8;

/// Largest side of the program's image: the user's code runs once per pixel and frame
/// (about 0.5 M paths/s on lavapipe for the workshop's tab), so 64 x 64 at 128 frames is
/// 4.2 M paths, under 10 s there.
pub const MAX_PROGRAM_SIZE: u32 = 64;

/// Per-pixel statistics of the frame estimates recovered from a running mean.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameStatistics {
    /// Frames seen.
    pub frames: u32,
    /// Per pixel and channel (RGB): sum of the recovered frame estimates.
    sums: Vec<[f64; 3]>,
    /// Per pixel and channel: sum of their squares.
    sums_of_squares: Vec<[f64; 3]>,
    /// The running mean after the last frame.
    last: Vec<[f32; 4]>,
    /// Recovered estimates below -NEGATIVE_TOLERANCE x the largest value.
    pub negative: usize,
    /// Running means below -NEGATIVE_TOLERANCE x the largest value: the program's own
    /// estimates are negative (a mean of non-negative values never is, nor is any one of
    /// them), whether it keeps a running mean or not.
    pub negative_means: usize,
    /// Largest value of any running mean seen.
    largest: f64,
}

impl FrameStatistics {
    /// Adds the running mean after the next frame: its frame estimate is
    /// X_f = (f+1) A_f - f A_{f-1}.
    pub fn add(&mut self, running_mean: &[[f32; 4]]) {
        let f = f64::from(self.frames);
        if self.last.is_empty() {
            self.last = vec![[0.0; 4]; running_mean.len()];
            self.sums = vec![[0.0; 3]; running_mean.len()];
            self.sums_of_squares = vec![[0.0; 3]; running_mean.len()];
        }
        for (i, current) in running_mean.iter().enumerate() {
            for (c, &channel) in current.iter().take(3).enumerate() {
                let value = f64::from(channel);
                self.largest = self.largest.max(value.abs());
                if value < -NEGATIVE_TOLERANCE * self.largest {
                    self.negative_means += 1;
                }
                let estimate = (f + 1.0) * value - f * f64::from(self.last[i][c]);
                if estimate < -NEGATIVE_TOLERANCE * self.largest {
                    self.negative += 1;
                }
                self.sums[i][c] += estimate;
                self.sums_of_squares[i][c] += estimate * estimate;
            }
        }
        self.last = running_mean.to_vec();
        self.frames += 1;
    }

    /// Whether some pixel's frame estimates differ by more than rounding (a standard
    /// deviation over 1e-3 x the largest value; recovering a frame's estimate from a float
    /// running mean loses about f ulps, 3e-5 relative at 256 frames): a path tracer's do
    /// wherever a path can bounce, a constant colour's never.
    pub fn varies(&self) -> bool {
        let n = f64::from(self.frames);
        let threshold = (1e-3 * self.largest).powi(2);
        n > 1.0
            && self
                .sums
                .iter()
                .zip(&self.sums_of_squares)
                .any(|(sum, square)| {
                    (0..3).any(|c| (square[c] - sum[c] * sum[c] / n) / (n - 1.0) > threshold)
                })
    }

    /// The final running mean with the variance of each pixel's mean: the sample variance
    /// of its frame estimates over the number of frames.
    pub fn mean_image(&self, width: usize, height: usize) -> Result<MeanImage> {
        let n = f64::from(self.frames);
        let variances: Vec<[f64; 3]> = self
            .sums
            .iter()
            .zip(&self.sums_of_squares)
            .map(|(sum, square)| {
                [0, 1, 2].map(|c| {
                    let mean = sum[c] / n;
                    ((square[c] - n * mean * mean) / (n - 1.0)).max(0.0) / n
                })
            })
            .collect();
        MeanImage::from_rgb(width, height, &self.last, &variances)
            .map_err(|e| Error::InvalidSettings(e.to_string()))
    }
}

/// Runs `program` and judges the image that `accumulated` holds (see the module
/// documentation). `functions` are the verdicts on the file's functions, for the cause.
pub fn judge_program(
    context: &Arc<Context>,
    program: &Program,
    accumulated: PassKind,
    functions: &[FunctionReport],
    options: &ProgramOptions,
) -> Result<FunctionReport> {
    let size = options.size;
    let frames = options.frames.max(MIN_FRAMES);
    let block = block_size(size);
    let line = program
        .pass(accumulated)
        .map_or(0, |pass| mainimage_line(&pass.text));
    let file = program
        .pass(accumulated)
        .map_or_else(String::new, |pass| pass.path.display().to_string());
    let mut report = FunctionReport::new(
        "program",
        line,
        "render",
        format!(
            "your program's {} after {frames} frames ({size}x{size}) and vkpath's reference \
             render of the Cornell box (pixel centres, MAX_PATH_LENGTH {}, {REFERENCE_SPP} spp, \
             an independent seed): the means of every {block}x{block} block and colour channel \
             must agree within their noise (z-tests, the program's variance from its frames, \
             the reference's from its second moments, Šidák-corrected over all blocks at {:.2e} \
             family-wise)",
            match accumulated {
                PassKind::Image => "Image pass",
                _ => "Buffer A",
            },
            options.max_path_length,
            options.alpha
        ),
    );
    report.file = file;
    // A loop without end costs the loop guard's iterations in every pixel that enters it: a
    // probe frame of few pixels finds it in a second, before the full frames would spend
    // minutes on it.
    let probe = ShadertoyRunner::new(context, program, PROBE_SIZE, PROBE_SIZE)
        .and_then(|mut probe| probe.run_frame());
    if let Err(Error::LoopLimit(message)) = probe {
        report.method = "loop limit".into();
        report.summary = "loops without end: a pixel's loops ran past their limit".into();
        report.hint = Some(crate::check::loop_hint_for_check(&message));
        return Ok(report);
    }
    let mut runner = match ShadertoyRunner::new(context, program, size, size) {
        Ok(runner) => runner,
        Err(Error::ShaderCompilation(messages)) => {
            // The tab's hint on names no tab declares (the Common tab's), as function mode
            // gives it, goes into the summary.
            report.summary = messages
                .lines()
                .find(|line| line.contains("not defined in any of your files"))
                .and_then(|line| line.split_once(": "))
                .map_or_else(
                    || "does not compile as a ShaderToy program".to_string(),
                    |(_, hint)| format!("does not compile as a ShaderToy program: {hint}"),
                );
            report.hint = Some(messages);
            return Ok(report);
        }
        Err(error) => return Err(error),
    };
    let mut statistics = FrameStatistics::default();
    let mut image = None;
    for _ in 0..frames {
        match runner.run_frame() {
            Ok(()) => {}
            Err(Error::LoopLimit(message)) => {
                report.method = "loop limit".into();
                report.summary = "loops without end: a pixel's loops ran past their limit".into();
                report.hint = Some(crate::check::loop_hint_for_check(&message));
                return Ok(report);
            }
            Err(error) => return Err(error),
        }
        let frame = runner.read(accumulated)?.ok_or_else(|| {
            Error::MissingInput(format!("the program has no {}", accumulated.name()))
        })?;
        statistics.add(&frame.mean);
        image = Some(frame);
    }
    let Some(yours) = image else {
        return Err(Error::InvalidSettings("no frame ran".into()));
    };
    report.measure("frames", f64::from(frames));
    if !statistics.varies() {
        report.method = NOT_JUDGED_METHOD.into();
        report.summary = format!(
            "not judged: every one of the {frames} frames gave every pixel the same value, so your \
             program's image is no Monte Carlo estimate of the workshop's scene (a colour of its own)"
        );
        return Ok(report);
    }
    // Negative running means are negative radiance, which the z-tests judge (and which
    // fails whatever they say); only negative frame estimates behind non-negative means
    // tell a program that does not average its frames.
    if statistics.negative > 0 && statistics.negative_means == 0 {
        report.method = NOT_JUDGED_METHOD.into();
        report.summary = format!(
            "not judged: {} recovered frame estimates are negative, so your program does not keep \
             the running mean of its frames (the workshop's mix(previous, color, 1.0 / float(iFrame + 1)))",
            statistics.negative
        );
        report.hint = Some(
            "check accumulates the image your Buffer A holds: keep the average of all frames there"
                .into(),
        );
        return Ok(report);
    }
    let your_blocks = statistics
        .mean_image(size as usize, size as usize)?
        .block_average(block)
        .map_err(|e| Error::InvalidSettings(e.to_string()))?;
    let reference = render_reference(context, options)?;
    let reference_variances: Vec<[f64; 3]> = reference
        .variance_of_mean()
        .iter()
        .map(|v| v.map(f64::from))
        .collect();
    let reference_blocks = MeanImage::from_rgb(
        size as usize,
        size as usize,
        &reference.mean,
        &reference_variances,
    )
    .and_then(|m| m.block_average(block))
    .map_err(|e| Error::InvalidSettings(e.to_string()))?;
    let z = z_test_images(&your_blocks, &reference_blocks, options.alpha)
        .map_err(|e| Error::InvalidSettings(e.to_string()))?;
    let (your_average, reference_average) = (average(&yours), average(&reference));
    report.cases = z.test_count;
    report.failures = z.rejected_count;
    report.passed = z.passed;
    report.measure("min_p_value", z.min_p_value);
    report.measure("worst_z", z.worst_z);
    report.measure("your_average", your_average);
    report.measure("reference_average", reference_average);
    report.measure("negative_values", statistics.negative_means as f64);
    report.summary = if statistics.negative_means > 0 {
        // Radiance is never negative: biased, whatever the block tests say.
        report.passed = false;
        report.failures = report.failures.max(1);
        report.hint = Some(
            "radiance is never negative: look at the factors of the path weight (a cosine \
             taken with a normal that faces away, dot(normal, direction) where the slides have \
             dot(tri.normal, direction) after the normal is turned towards the ray) and at \
             the sign of what get_ray_radiance and mainImage write"
                .into(),
        );
        format!(
            "biased: {} values of your program's image went negative over its frames, and radiance never is ({} of {} block tests reject; average radiance {your_average:.4}, reference {reference_average:.4})",
            statistics.negative_means, z.rejected_count, z.test_count
        )
    } else if z.passed {
        format!(
            "consistent with the reference: all {} block tests pass (average radiance {your_average:.4} vs {reference_average:.4})",
            z.test_count
        )
    } else {
        report.hint = Some(cause(functions, your_average, reference_average));
        format!(
            "biased: {} of {} block tests reject (average radiance {your_average:.4}, reference {reference_average:.4}; worst z = {:.1})",
            z.rejected_count, z.test_count, z.worst_z
        )
    };
    report.images = save_images(&options.output_dir, &reference, &yours)?;
    Ok(report)
}

/// The file and line of the program that `judge_tabs_program` judges: the `mainImage` of
/// the first tab that calls `get_ray_radiance` (the pass that accumulates), else of the
/// first tab with one.
pub fn program_place(tabs: &[(PathBuf, String)]) -> (String, usize) {
    tabs.iter()
        .find(|(_, text)| is_workshop_program(text))
        .or_else(|| tabs.iter().find(|(_, text)| mainimage_line(text) > 0))
        .map_or_else(
            || (String::new(), 0),
            |(path, text)| (path.display().to_string(), mainimage_line(text)),
        )
}

/// The line of `mainImage` in a tab (0 if none).
fn mainimage_line(text: &str) -> usize {
    crate::check::glsl_syntax::tokenize(text)
        .iter()
        .find(|t| t.text == "mainImage")
        .map_or(0, |t| t.line)
}

/// The likely cause of a biased program, from the function verdicts and the brightness.
fn cause(functions: &[FunctionReport], yours: f64, reference: f64) -> String {
    let others: Vec<&str> = functions
        .iter()
        .filter(|f| !f.passed && f.function != "get_ray_radiance")
        .map(|f| f.function.as_str())
        .collect();
    let mut cause = cause_from_radiance(functions, yours, reference);
    let others: Vec<&str> = others
        .into_iter()
        .filter(|name| {
            !cause.contains(&format!("your {name}")) && !cause.contains(&format!(" and {name}"))
        })
        .collect();
    if !others.is_empty() {
        cause.push_str(&format!(
            "; the program also uses functions of yours that fail on their own (see above): {}",
            others.join(", ")
        ));
    }
    cause
}

/// `cause` from get_ray_radiance's verdict, the intersections' and the brightness alone.
fn cause_from_radiance(functions: &[FunctionReport], yours: f64, reference: f64) -> String {
    let ratio = yours / reference.max(1e-12);
    let radiance = functions.iter().find(|f| f.function == "get_ray_radiance");
    let darker = 100.0 * (1.0 - ratio);
    let failing_intersections: Vec<&str> = functions
        .iter()
        .filter(|f| {
            !f.passed
                && matches!(
                    f.function.as_str(),
                    "ray_triangle_intersection" | "ray_mesh_intersection"
                )
        })
        .map(|f| f.function.as_str())
        .collect();
    match radiance {
        Some(f) if !f.passed => format!(
            "your program's image is {ratio:.2} times as bright as the reference, and your get_ray_radiance fails on its own (see its verdict): fix it first"
        ),
        // An intersection that fails on its own (a loop that misses a triangle, hits
        // behind the origin) changes the image by itself: no sign of self-intersection.
        _ if !failing_intersections.is_empty() => format!(
            "your program's image is {ratio:.2} times as bright as the reference, and your {} {} on its own (see its verdict): a triangle it misses is missing from the image too; fix it first",
            failing_intersections.join(" and "),
            if failing_intersections.len() > 1 { "fail each" } else { "fails" }
        ),
        Some(f) if ratio < 1.0 && f.warnings.iter().any(|w| w.contains("self-intersection")) => format!(
            "self-intersection: your program renders {darker:.0}% darker than the reference. Your \
             get_ray_radiance is correct on its own (judged with intersections that ignore the \
             surface a ray starts on), but with your ray_triangle_intersection a ray that leaves \
             a surface at x + t·ω hits that same surface again at t ≈ 0 through rounding. Accept \
             only hits with t > 1e-4 in ray_triangle_intersection, or start the next ray a little \
             off the surface (origin += 1e-4 * normal)"
        ),
        _ if ratio < 1.0 => format!(
            "your program renders {darker:.0}% darker than the reference: if your functions pass, look at mainImage (the camera, the seed, the averaging) and at rays that hit the surface they leave (self-intersection)"
        ),
        _ => format!(
            "your program renders {ratio:.2} times as bright as the reference: look at mainImage (the camera, the averaging over frames) and at the factors of the path weight"
        ),
    }
}

/// The average over all pixels and RGB channels.
fn average(image: &RenderedImage) -> f64 {
    image.average().iter().sum::<f64>() / 3.0
}

/// vkpath's reference render with the program's camera (the workshop's), pixel centres and
/// path length.
fn render_reference(context: &Arc<Context>, options: &ProgramOptions) -> Result<RenderedImage> {
    let scene = Scene::builtin_cornell_box()?;
    let camera = scene
        .camera
        .ok_or_else(|| Error::MissingInput("the Cornell box has no camera".into()))?;
    let settings = RenderSettings {
        width: options.size,
        height: options.size,
        spp: REFERENCE_SPP,
        max_path_length: options.max_path_length,
        seed: REFERENCE_SEED,
        pixel_filter: PixelFilter::Center,
        integrator: Integrator::PathTracing,
        ..RenderSettings::default()
    };
    Renderer::new(context, &scene, &camera, settings)?.render_all()
}

/// Writes program-reference.png, program-yours.png and program-difference.png.
fn save_images(
    directory: &Path,
    reference: &RenderedImage,
    yours: &RenderedImage,
) -> Result<Vec<String>> {
    std::fs::create_dir_all(directory).map_err(|e| {
        Error::Image(format!(
            "cannot create the output directory '{}': {e}",
            directory.display()
        ))
    })?;
    let mut written = Vec::new();
    let mut yours = yours.clone();
    for pixel in &mut yours.mean {
        pixel[3] = 1.0;
    }
    for (name, image) in [
        ("program-reference", reference.clone()),
        ("program-difference", difference_image(reference, &yours)),
        ("program-yours", yours),
    ] {
        let path = directory.join(format!("{name}.png"));
        save_image(&path, &image, &SaveOptions::default())?;
        written.push(path.display().to_string());
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_estimates_come_back_from_a_running_mean() {
        // Frame estimates 1, 3, 2, 6 of one pixel, kept as the workshop's running mean.
        let estimates = [1.0f32, 3.0, 2.0, 6.0];
        let mut statistics = FrameStatistics::default();
        let mut mean = 0.0f32;
        for (f, x) in estimates.iter().enumerate() {
            mean += (x - mean) / (f as f32 + 1.0);
            statistics.add(&[[mean, 2.0 * mean, 0.0, 1.0]]);
        }
        let image = statistics.mean_image(1, 1).unwrap();
        assert!((image.means[0] - 3.0).abs() < 1e-6);
        // Sample variance of 1, 3, 2, 6: 14 / 3; of the mean: 14 / 12.
        assert!(
            (image.variances_of_mean[0] - 14.0 / 12.0).abs() < 1e-5,
            "{:?}",
            image.variances_of_mean
        );
        assert!((image.variances_of_mean[1] - 4.0 * 14.0 / 12.0).abs() < 1e-4);
        assert_eq!(image.variances_of_mean[2], 0.0);
        assert_eq!(statistics.negative, 0);
        assert!(statistics.varies());
    }

    #[test]
    fn a_constant_colour_does_not_vary() {
        let mut statistics = FrameStatistics::default();
        let mut mean = 0.0f32;
        for f in 0..16 {
            mean += (0.3 - mean) / (f as f32 + 1.0);
            statistics.add(&[[mean, 0.5, 0.0, 1.0], [0.25, 0.25, 0.25, 1.0]]);
        }
        assert!(!statistics.varies());
    }

    #[test]
    fn a_buffer_that_keeps_no_running_mean_is_recognised() {
        // Each frame overwrites the buffer with its own estimate: 5, 1, 5, 1 ...
        let mut statistics = FrameStatistics::default();
        for f in 0..8 {
            let value = if f % 2 == 0 { 5.0 } else { 1.0 };
            statistics.add(&[[value, value, value, 1.0]]);
        }
        assert!(statistics.negative > 0);
        assert_eq!(statistics.negative_means, 0);
    }

    #[test]
    fn negative_radiance_is_told_from_a_missing_running_mean() {
        // A running mean of negative estimates (an estimator that returns negative
        // radiance): its recovered estimates are negative too, and so are the means.
        let mut statistics = FrameStatistics::default();
        let mut mean = 0.0f32;
        for f in 0..8 {
            let x = if f % 2 == 0 { -2.0 } else { 1.0 };
            mean += (x - mean) / (f as f32 + 1.0);
            statistics.add(&[[mean, mean, mean, 1.0], [0.5, 0.5, 0.5, 1.0]]);
        }
        assert!(statistics.negative > 0);
        assert!(statistics.negative_means > 0);
    }

    #[test]
    fn a_failing_intersection_is_named_before_self_intersection() {
        let verdict = |function: &str, passed: bool, warning: &str| {
            let mut report = FunctionReport::new(function, 1, "render", String::new());
            report.passed = passed;
            if !warning.is_empty() {
                report.warnings.push(warning.into());
            }
            report
        };
        // An off-by-one loop over the mesh: the mesh fails on its own, the estimator passes
        // but renders darker with it (which its warning would call self-intersection).
        let functions = [
            verdict("ray_mesh_intersection", false, ""),
            verdict("get_ray_radiance", true, "... (self-intersection) ..."),
        ];
        let text = cause(&functions, 0.8, 1.0);
        assert!(!text.contains("self-intersection"), "{text}");
        assert!(
            text.contains("your ray_mesh_intersection fails on its own"),
            "{text}"
        );
        assert_eq!(text.matches("ray_mesh_intersection").count(), 1, "{text}");
        // With intersections that pass, the darker image is self-intersection.
        let functions = [
            verdict("ray_mesh_intersection", true, ""),
            verdict("get_ray_radiance", true, "... (self-intersection) ..."),
        ];
        assert!(cause(&functions, 0.6, 1.0).starts_with("self-intersection"));
    }

    #[test]
    fn one_tab_is_a_buffer_shown_by_vkpaths_image_pass() {
        let tab = (
            PathBuf::from("tab.glsl"),
            "void mainImage(out vec4 c, in vec2 p) { c = vec4(get_ray_radiance()); }".to_string(),
        );
        assert!(is_workshop_program(&tab.1));
        let (program, accumulated) = program_of_tabs(None, std::slice::from_ref(&tab)).unwrap();
        assert_eq!(accumulated, PassKind::BufferA);
        assert_eq!(program.passes.len(), 2);
        assert_eq!(program.passes[0].path, PathBuf::from("tab.glsl"));
        assert_eq!(program.passes[1].kind, PassKind::Image);
    }
}
