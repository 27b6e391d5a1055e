//! `vkpath check FILE.glsl`: judges a workshop attendee's versions of workshop functions.
//!
//! The file may be anything an attendee has: a whole ShaderToy tab, a WebGL page shader, or
//! just the functions. `crate::glsl_intake` prepares it (drops entry points, `#version`, uniforms …,
//! supplies ShaderToy's inputs, renames what clashes with vkpath's own names), `detect`
//! finds the workshop functions it defines with the workshop's signatures (the prototypes of
//! `glsl/workshop.glsl`; other uses of those names are listed as not judged), `user_functions`
//! models what the file defines, and `compile`
//! builds the probe kernels and the path tracer at run time with one user function at a
//! time in place of the reference version, so that a mistake in one function never fails
//! another. Each function is judged the way its contract allows:
//! - `get_random_numbers`: bit for bit against the reference PCG2D (`deterministic`);
//! - `ray_triangle_intersection`, `ray_mesh_intersection`, `get_primary_ray_direction`:
//!   against the reference on many inputs, within tolerances that other correct algorithms
//!   meet, near-degenerate inputs excepted (`deterministic`);
//! - `sample_sphere`, `sample_hemisphere`: χ² tests of their distribution, never equality
//!   (`samplers`);
//! - `compute_direct_illumination`, `get_ray_radiance`: renders of the matching exercise
//!   compared statistically with the reference's (`estimators`).
//!
//! `report` holds the verdicts and their text and JSON forms.

pub mod compile;
pub mod detect;
pub mod deterministic;
pub mod estimators;
pub mod isolation;
pub mod program;
pub mod program_shape;
pub mod report;
pub mod samplers;
pub mod unavailable;
pub mod user_functions;

/// The intake's preparation, under its old name (see `crate::glsl_intake`).
pub use crate::glsl_intake::prepare as source;
/// The intake's syntax reader, under its old name (see `crate::glsl_intake`).
pub use crate::glsl_intake::syntax as glsl_syntax;

use std::path::PathBuf;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::image_io::output::{save_image, SaveOptions};
use crate::probe::{ProbeKind, ProbePipeline, ProbeRunner};
use crate::scene::Scene;
use crate::stats::sidak_alpha;
use crate::vk::Context;
pub use detect::WorkshopFunction;
pub use report::{CheckReport, FunctionReport};
pub use user_functions::{NotJudged, UserFunctions};

/// `MAX_PATH_LENGTH` of the probe kernels (only `get_ray_radiance` reads it): the renderer's
/// default.
const PROBE_MAX_PATH_LENGTH: u32 = crate::render::settings::DEFAULT_MAX_PATH_LENGTH;

/// How `vkpath check` judges.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckOptions {
    /// Where the images of the render comparisons go.
    pub output_dir: PathBuf,
    /// Family-wise significance level over all statistical tests of one check (χ² tests
    /// and render comparisons): the chance that correct functions are reported wrong.
    pub alpha: f64,
    /// Side of the square renders of the estimator checks, in pixels (a multiple of 8).
    pub image_size: u32,
    /// Samples per pixel of each render of the estimator checks.
    pub spp: u32,
    /// Frames a whole ShaderToy program runs for its `program` verdict
    /// (`program::DEFAULT_FRAMES` unless `check --frames` says otherwise; at least
    /// `program::MIN_FRAMES`).
    pub program_frames: u32,
}

impl Default for CheckOptions {
    /// `vkpath-check/`, 1% family-wise, 128 x 128 pixels at 64 spp: a million samples per
    /// render (about a second on lavapipe), 64 blocks of 16 x 16 pixels and 16384 samples
    /// each, which resolves a bias of a few percent of a block's radiance.
    fn default() -> CheckOptions {
        CheckOptions {
            output_dir: PathBuf::from("vkpath-check"),
            alpha: 0.01,
            image_size: 128,
            spp: 64,
            program_frames: program::DEFAULT_FRAMES,
        }
    }
}

/// Why a file cannot be checked at all (usage errors, not verdicts).
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file cannot be read.
    #[error("cannot read '{path}': {source}")]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// The file defines none of the workshop functions.
    #[error(
        "'{path}' defines none of the workshop functions ({}); a definition is the \
         function's name, its parameter list and '{{'{hint}",
        WorkshopFunction::ALL.map(WorkshopFunction::name).join(", ")
    )]
    NoWorkshopFunction {
        /// The file.
        path: PathBuf,
        /// Why a definition was not read, when the reading knows (": line 3: this '{' is
        /// never closed ..."), else empty.
        hint: String,
    },
    /// The file is WGSL (WebGPU's shading language), not GLSL.
    #[error(
        "'{path}' is WGSL (line {line}: '{seen}'); check reads GLSL (the workshop's ShaderToy \
         tabs, Vulkan or WebGL GLSL): give it your GLSL version"
    )]
    Wgsl {
        /// The file.
        path: PathBuf,
        /// The first line that only WGSL writes (from 1).
        line: usize,
        /// What it starts with.
        seen: String,
    },
    /// The file uses workshop names, but none with the workshop's parameters.
    #[error("'{path}' has nothing check can judge: {reasons}")]
    NothingToJudge {
        /// The file.
        path: PathBuf,
        /// Each function with why it is not judged.
        reasons: String,
    },
}

/// Reads the user's files as the tabs of one ShaderToy program, in ShaderToy's order: the
/// files without an entry point (the Common tab) first, then the others in the order given;
/// each (file name, text).
pub fn read_tabs(paths: &[PathBuf]) -> std::result::Result<Vec<(String, String)>, LoadError> {
    let mut files = Vec::new();
    for path in paths {
        let text =
            crate::glsl_intake::read_source_file(path).map_err(|source| LoadError::Unreadable {
                path: path.to_owned(),
                source,
            })?;
        if let Some((line, seen)) = wgsl_line(&text) {
            return Err(LoadError::Wgsl {
                path: path.to_owned(),
                line,
                seen,
            });
        }
        files.push((path.display().to_string(), text));
    }
    let (commons, passes): (Vec<_>, Vec<_>) = files
        .into_iter()
        .partition(|(_, text)| crate::glsl_intake::find_entry_point(text).is_none());
    Ok(commons.into_iter().chain(passes).collect())
}

/// One of the user's files as check reads it: its GLSL (`crate::glsl_intake::glsl_of_paste`:
/// a Markdown post's code blocks, a page's shader tags, a script's template strings, with
/// prose, front matter and HTML blanked on their lines) and the notes on what was dropped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PastedTab {
    /// The file as the user named it.
    pub name: String,
    /// Its GLSL, every line where the user wrote it.
    pub text: String,
    /// What was dropped, with the file's own lines.
    pub notes: Vec<crate::glsl_intake::PasteNote>,
}

/// `read_tabs` for `check`: each file's GLSL as published around it is read
/// (`PastedTab`), then the files are put in ShaderToy's order. A file whose GLSL defines no
/// function and that has a line only WGSL writes is WGSL.
pub fn read_pasted_tabs(paths: &[PathBuf]) -> std::result::Result<Vec<PastedTab>, LoadError> {
    let mut files = Vec::new();
    for path in paths {
        let raw =
            crate::glsl_intake::read_source_file(path).map_err(|source| LoadError::Unreadable {
                path: path.to_owned(),
                source,
            })?;
        let pasted = crate::glsl_intake::glsl_of_paste(&raw);
        let wgsl = wgsl_line(&pasted.text).or_else(|| {
            wgsl_line(&raw).filter(|_| {
                !crate::glsl_intake::find_functions(&pasted.text)
                    .iter()
                    .any(|f| f.has_body)
            })
        });
        if let Some((line, seen)) = wgsl {
            return Err(LoadError::Wgsl {
                path: path.to_owned(),
                line,
                seen,
            });
        }
        files.push(PastedTab {
            name: path.display().to_string(),
            text: pasted.text,
            notes: pasted.notes,
        });
    }
    let (commons, passes): (Vec<_>, Vec<_>) = files
        .into_iter()
        .partition(|tab| crate::glsl_intake::find_entry_point(&tab.text).is_none());
    Ok(commons.into_iter().chain(passes).collect())
}

/// The first line (from 1, and its first words) that only WGSL writes: a function
/// declared with `fn`, an attribute such as `@fragment` or `@group(0)`, a `var<...>`
/// declaration or a `struct` member typed `name: vec3<f32>`; `None` for GLSL.
pub fn wgsl_line(text: &str) -> Option<(usize, String)> {
    const ATTRIBUTES: [&str; 6] = [
        "@fragment",
        "@vertex",
        "@compute",
        "@group(",
        "@binding(",
        "@workgroup_size(",
    ];
    text.lines().enumerate().find_map(|(index, line)| {
        let line = line.trim_start();
        let is_wgsl = line.starts_with("fn ") && line.contains('(')
            || ATTRIBUTES.iter().any(|a| line.starts_with(a))
            || line.starts_with("var<")
            || line.contains("<f32>") && line.contains(':');
        is_wgsl.then(|| {
            let seen: String = line.chars().take(40).collect();
            (index + 1, seen.trim_end().to_string())
        })
    })
}

/// The user's functions in `files` read as one text, whose lines are mapped back to each
/// file's (`UserFunctions::sources`); not compiled yet. The notes on what each file's
/// reading dropped come first.
fn read_unit(files: &[PastedTab]) -> UserFunctions {
    let display_name = files
        .iter()
        .map(|tab| tab.name.as_str())
        .collect::<Vec<_>>()
        .join(" + ");
    let mut text = String::new();
    let mut sources = Vec::new();
    let mut notes = Vec::new();
    for tab in files {
        let first_line = text.matches('\n').count() + 1;
        sources.push(user_functions::SourceFile {
            name: tab.name.clone(),
            first_line,
        });
        notes.extend(
            tab.notes
                .iter()
                .map(|note| format!("line {}: {}", first_line - 1 + note.line, note.text)),
        );
        text.push_str(&tab.text);
        if !text.ends_with('\n') {
            text.push('\n');
        }
    }
    let mut user = UserFunctions::new(&display_name, text);
    user.sources = sources;
    user.prepared.notes.splice(0..0, notes);
    user
}

/// The usage error of files that define nothing check can judge (`units` all empty).
fn nothing_to_judge(paths: &[PathBuf], units: &[UserFunctions]) -> Option<LoadError> {
    if units.iter().any(|u| !u.definitions.is_empty()) {
        return None;
    }
    let path = paths.first().cloned().unwrap_or_default();
    let reasons: Vec<String> = units
        .iter()
        .flat_map(|u| {
            u.not_judged
                .iter()
                .map(|n| format!("{} (line {}): {}", n.function, n.line, n.reason))
        })
        .collect();
    Some(if reasons.is_empty() {
        // A definition hidden inside a brace never closed: the note of the reading says
        // where.
        let hint = units
            .iter()
            .flat_map(|u| u.prepared.notes.iter().map(move |note| u.localize(note)))
            .find(|note| note.contains("stands inside it and is not read"))
            .map_or_else(String::new, |note| format!(": {note}"));
        LoadError::NoWorkshopFunction { path, hint }
    } else {
        LoadError::NothingToJudge {
            path,
            reasons: reasons.join("; "),
        }
    })
}

/// Compiles a unit once, setting aside the functions that do not compile.
fn compile_unit(user: &mut UserFunctions) {
    match user.find_broken_functions() {
        Ok(warnings) => user.compile_warnings = warnings,
        Err(messages) => user.compile_errors = Some(messages.to_string()),
    }
}

/// Reads a user's files, finds the workshop functions they define and compiles them once
/// (the functions that do not compile are set aside, see
/// `UserFunctions::find_broken_functions`). Several files are the tabs of one ShaderToy
/// program (`read_tabs`), read here as one text, Common first; `vkpath check` compiles each
/// pass on its own instead (`load_user_passes`).
pub fn load_user_functions(paths: &[PathBuf]) -> std::result::Result<UserFunctions, LoadError> {
    let files = read_pasted_tabs(paths)?;
    let mut user = read_unit(&files);
    if let Some(error) = nothing_to_judge(paths, std::slice::from_ref(&user)) {
        return Err(error);
    }
    compile_unit(&mut user);
    Ok(user)
}

/// Reads a user's files as ShaderToy compiles a program: one unit per pass (a file with an
/// entry point), each the Common tab followed by that pass, compiled on its own, so that
/// two passes may define the same helper as ShaderToy allows and every message names the
/// tab and its own line. A function of the Common tab is judged once, in the first unit;
/// the others judge only their pass's functions. Files without a second pass are one unit,
/// as `load_user_functions` reads them.
pub fn load_user_passes(paths: &[PathBuf]) -> std::result::Result<Vec<UserFunctions>, LoadError> {
    let files = read_pasted_tabs(paths)?;
    let commons: Vec<PastedTab> = files
        .iter()
        .filter(|tab| crate::glsl_intake::find_entry_point(&tab.text).is_none())
        .cloned()
        .collect();
    let passes = &files[commons.len()..];
    let mut units: Vec<UserFunctions> = if passes.len() < 2 {
        vec![read_unit(&files)]
    } else {
        passes
            .iter()
            .enumerate()
            .map(|(index, pass)| {
                let mut tabs = commons.clone();
                tabs.push(pass.clone());
                let mut unit = read_unit(&tabs);
                if index > 0 {
                    // The Common tab's functions are judged in the first unit.
                    let pass_name = pass.name.clone();
                    let in_pass =
                        |unit: &UserFunctions, line: usize| unit.locate(line).0 == pass_name;
                    let keep: Vec<bool> = unit
                        .definitions
                        .iter()
                        .map(|d| in_pass(&unit, d.line))
                        .collect();
                    let mut keep = keep.into_iter();
                    unit.definitions.retain(|_| keep.next().unwrap_or(false));
                    let keep: Vec<bool> = unit
                        .not_judged
                        .iter()
                        .map(|n| in_pass(&unit, n.line))
                        .collect();
                    let mut keep = keep.into_iter();
                    unit.not_judged.retain(|_| keep.next().unwrap_or(false));
                }
                unit
            })
            .collect()
    };
    if let Some(error) = nothing_to_judge(paths, &units) {
        return Err(error);
    }
    for unit in &mut units {
        compile_unit(unit);
    }
    Ok(units)
}

/// What every check needs: the device, the user's functions, the options, the Cornell box
/// and a probe runner on it, and the per-test significance level.
pub struct Session<'a> {
    /// The device.
    pub context: Arc<Context>,
    /// The user's functions.
    pub user: &'a UserFunctions,
    /// The options.
    pub options: &'a CheckOptions,
    /// The workshop's Cornell box (for ray_mesh_intersection and the renders).
    pub scene: Scene,
    /// Runs probe kernels with the Cornell box bound.
    pub runner: ProbeRunner,
    /// The significance level of each statistical test: `options.alpha` Šidák-corrected
    /// over all of them.
    pub test_alpha: f64,
}

impl Session<'_> {
    /// The probe kernel `kind` compiled with the user's version of the function it
    /// evaluates (and the reference versions of all others).
    pub fn user_probe(&self, kind: ProbeKind) -> Result<ProbePipeline> {
        let function = WorkshopFunction::from_name(kind.function_name()).ok_or_else(|| {
            Error::InvalidSettings(format!(
                "{} is not a workshop function",
                kind.function_name()
            ))
        })?;
        let code = self.user.code(&[function]);
        let compiled = compile::compile_kernel(&kind.source_file(), Some(&code), &[])
            .map_err(|error| Error::ShaderCompilation(error.to_string()))?;
        ProbePipeline::from_spirv(&self.context, kind, &compiled.spirv, PROBE_MAX_PATH_LENGTH)
    }

    /// Writes each (name, image) as `<output_dir>/<name>.png` and returns the paths.
    pub fn save_pngs(&self, images: &[(String, RenderedImage)]) -> Result<Vec<String>> {
        let directory = &self.options.output_dir;
        std::fs::create_dir_all(directory).map_err(|e| {
            Error::Image(format!(
                "cannot create the output directory '{}': {e}",
                directory.display()
            ))
        })?;
        let mut written = Vec::new();
        for (name, image) in images {
            let path = directory.join(format!("{name}.png"));
            save_image(&path, image, &SaveOptions::default())?;
            written.push(path.display().to_string());
        }
        Ok(written)
    }

    /// Runs the reference probe and the user's on the same inputs: (expected, actual).
    pub fn run_both<I: bytemuck::Pod, O: bytemuck::Pod>(
        &self,
        kind: ProbeKind,
        inputs: &[I],
    ) -> Result<(Vec<O>, Vec<O>)> {
        let reference = ProbePipeline::reference(&self.context, kind, PROBE_MAX_PATH_LENGTH)?;
        let expected = self.runner.run(&reference, inputs)?;
        let actual = self.runner.run(&self.user_probe(kind)?, inputs)?;
        Ok((expected, actual))
    }
}

/// The report before any function is judged: the file, the functions it defines, the
/// notes, the functions not judged and the compiler's messages (`device` is filled in when
/// known).
pub fn report_header(user: &UserFunctions, device: &str) -> CheckReport {
    let mut report = CheckReport {
        file: user.display_name.clone(),
        error: None,
        device: device.to_string(),
        defined_functions: user
            .functions()
            .iter()
            .map(|f| f.name().to_string())
            .collect(),
        passed: false,
        not_judged: user
            .not_judged
            .iter()
            .map(|n| NotJudged {
                function: n.function.clone(),
                line: user.locate(n.line).1,
                reason: user.localize(&n.reason),
                file: user.locate(n.line).0,
            })
            .collect(),
        lost: Vec::new(),
        notes: user
            .prepared
            .notes
            .iter()
            .map(|note| user.localize(note))
            .collect(),
        compile_errors: user.compile_errors.as_deref().map(|e| user.localize(e)),
        compile_warnings: user.localize(&user.compile_warnings),
        functions: Vec::new(),
    };
    for broken in &user.broken {
        if WorkshopFunction::from_name(&broken.name).is_none() {
            report.notes.push(user.localize(&format!(
                "line {}: your {} does not compile and is left out: {}",
                broken.line,
                broken.name,
                broken.messages.lines().next().unwrap_or_default()
            )));
        }
    }
    report
}

/// The significance level of each statistical test when `user`'s judged functions are
/// judged: `options.alpha` Šidák-corrected over all their tests.
pub fn test_alpha(user: &UserFunctions, options: &CheckOptions) -> Result<f64> {
    let statistical_tests: usize = user
        .judged_functions()
        .iter()
        .map(|&f| samplers::test_count(f) + usize::from(estimators::integrator_for(f).is_some()))
        .sum::<usize>()
        + usize::from(program::is_workshop_program(&user.text));
    if statistical_tests > 0 {
        sidak_alpha(options.alpha, statistical_tests)
            .map_err(|e| Error::InvalidSettings(e.to_string()))
    } else {
        Ok(options.alpha)
    }
}

/// `test_alpha` over several units of one program (`load_user_passes`): `options.alpha`
/// Šidák-corrected over the statistical tests of all their judged functions and the
/// program's, counted once.
pub fn test_alpha_of_units(units: &[UserFunctions], options: &CheckOptions) -> Result<f64> {
    let statistical_tests: usize = units
        .iter()
        .flat_map(|user| user.judged_functions())
        .map(|f| samplers::test_count(f) + usize::from(estimators::integrator_for(f).is_some()))
        .sum::<usize>()
        + usize::from(units.iter().any(|u| program::is_workshop_program(&u.text)));
    if statistical_tests > 0 {
        sidak_alpha(options.alpha, statistical_tests)
            .map_err(|e| Error::InvalidSettings(e.to_string()))
    } else {
        Ok(options.alpha)
    }
}

/// `report_header` over several units of one program: the files once each, every note,
/// function not judged and compiler message once (a Common tab's appear in every unit).
pub fn units_header(units: &[UserFunctions], device: &str) -> CheckReport {
    let mut headers = units.iter().map(|unit| report_header(unit, device));
    let Some(mut report) = headers.next() else {
        return report_header(&UserFunctions::new("", String::new()), device);
    };
    let mut files: Vec<String> = units
        .iter()
        .flat_map(|u| u.sources.iter().map(|s| s.name.clone()))
        .collect();
    let mut seen = std::collections::BTreeSet::new();
    files.retain(|f| seen.insert(f.clone()));
    report.file = files.join(" + ");
    for header in headers {
        for function in header.defined_functions {
            if !report.defined_functions.contains(&function) {
                report.defined_functions.push(function);
            }
        }
        for entry in header.not_judged {
            if !report.not_judged.contains(&entry) {
                report.not_judged.push(entry);
            }
        }
        for note in header.notes {
            if !report.notes.contains(&note) {
                report.notes.push(note);
            }
        }
        report.compile_errors = match (report.compile_errors.take(), header.compile_errors) {
            (Some(a), Some(b)) if a != b => Some(format!("{a}\n{b}")),
            (a, b) => a.or(b),
        };
        if !header.compile_warnings.trim().is_empty()
            && !report.compile_warnings.contains(&header.compile_warnings)
        {
            report.compile_warnings.push_str(&header.compile_warnings);
        }
    }
    report
}

/// The verdict on a function that does not compile (known without a device), if it does not.
pub fn verdict_without_device(
    user: &UserFunctions,
    function: WorkshopFunction,
) -> Option<FunctionReport> {
    let broken = user.broken.iter().find(|b| b.name == function.name())?;
    Some(user.annotate(function, does_not_compile(function, broken)))
}

/// Judges `functions` of `user` on `context` in this process, one after another, calling
/// `before` as each begins and `on_verdict` with each verdict as soon as it is known (an
/// error of `on_verdict` stops). `test_alpha` is `test_alpha(user, options)`, computed over
/// all judged functions even when only some are given here.
pub fn judge_functions(
    context: &Arc<Context>,
    user: &UserFunctions,
    options: &CheckOptions,
    test_alpha: f64,
    functions: &[WorkshopFunction],
    mut on_verdict: impl FnMut(WorkshopFunction, Result<FunctionReport>) -> Result<()>,
    mut before: impl FnMut(WorkshopFunction),
) -> Result<()> {
    let scene = Scene::builtin_cornell_box()?;
    let session = Session {
        context: context.clone(),
        user,
        options,
        runner: ProbeRunner::new(context, &scene.triangles)?,
        scene,
        test_alpha,
    };
    // The intersections judged so far that fail on their own (they come before the
    // estimators): an estimator's darker image with them is theirs, not self-intersection.
    let mut failing_intersections: Vec<&'static str> = Vec::new();
    for &function in functions {
        before(function);
        let verdict = match verdict_without_device(user, function) {
            Some(verdict) => Ok(verdict),
            None => match judge(&session, function) {
                Err(Error::LoopLimit(message)) => {
                    Ok(user.annotate(function, loops_without_end(function, user, message)))
                }
                verdict => verdict.map(|v| user.annotate(function, v)),
            },
        };
        let verdict = verdict.map(|mut report| {
            let intersection = matches!(
                function,
                WorkshopFunction::RayTriangleIntersection | WorkshopFunction::RayMeshIntersection
            );
            if intersection && !report.passed {
                failing_intersections.push(function.name());
            }
            estimators::blame_failing_intersections(&mut report, &failing_intersections);
            report
        });
        on_verdict(function, verdict)?;
    }
    Ok(())
}

/// Checks every workshop function that `user` defines with the workshop's signature in this
/// process and returns the verdicts: one per function, those that do not compile failed
/// with the compiler's messages. Other uses of workshop names are listed as not judged. A
/// file that does not compile outside its functions is reported (the compiler's messages
/// name the user's file and lines) and nothing is judged. (`vkpath check` judges in child
/// processes instead, see `isolation`.)
pub fn check(
    context: &Arc<Context>,
    user: &UserFunctions,
    options: &CheckOptions,
) -> Result<CheckReport> {
    let mut report = report_header(user, &context.info.name);
    if report.compile_errors.is_some() {
        return Ok(report);
    }
    let alpha = test_alpha(user, options)?;
    judge_functions(
        context,
        user,
        options,
        alpha,
        &user.functions(),
        |_, verdict| {
            report.functions.push(verdict?);
            Ok(())
        },
        |_| {},
    )?;
    if let Some(verdict) =
        program::judge_user_program(context, user, options, alpha, &report.functions)?
    {
        match program::not_judged_of(&verdict) {
            Some(not_judged) => report.not_judged.push(not_judged),
            None => report.functions.push(verdict),
        }
    }
    report.passed = report.functions.iter().all(|f| f.passed);
    Ok(report)
}

/// The verdict on one function that compiles.
fn judge(session: &Session, function: WorkshopFunction) -> Result<FunctionReport> {
    match function {
        WorkshopFunction::GetRandomNumbers => deterministic::check_random_numbers(session),
        WorkshopFunction::SampleSphere | WorkshopFunction::SampleHemisphere => {
            samplers::check_sampler(session, function)
        }
        WorkshopFunction::RayTriangleIntersection => deterministic::check_ray_triangle(session),
        WorkshopFunction::RayMeshIntersection => deterministic::check_ray_mesh(session),
        WorkshopFunction::GetPrimaryRayDirection => deterministic::check_primary_ray(session),
        WorkshopFunction::ComputeDirectIllumination | WorkshopFunction::GetRayRadiance => {
            estimators::check_estimator(session, function)
        }
    }
}

/// The verdict on a function whose loops ran past their limit: failed (on lavapipe an
/// endless loop would otherwise end silently and the function might pass).
fn loops_without_end(
    function: WorkshopFunction,
    user: &UserFunctions,
    message: String,
) -> FunctionReport {
    let mut report = FunctionReport::new(
        function.name(),
        user.line_of(function),
        "loop limit",
        format!(
            "every call must end its loops within {} iterations",
            source::USER_LOOP_LIMIT
        ),
    );
    report.summary = "loops without end: a call's loops ran past their limit".into();
    report.hint = Some(loop_hint_for_check(&message));
    report
}

/// What `check` says after a loop-limit message: the renderer's advice (`--samples-per-frame`,
/// `--max-path-length`, `--accel`) names options of `render`, which `check` does not have, so
/// it gives way to what the user can change, the loop itself.
pub fn loop_hint_for_check(message: &str) -> String {
    let cause = match message.rfind(": use ") {
        Some(at) => &message[..at],
        None => message,
    };
    format!(
        "{cause}; look for a loop whose condition never turns false, or a `continue` where a \
         `break` was meant"
    )
}

/// The verdict on a function that does not compile: failed, with the compiler's messages.
fn does_not_compile(
    function: WorkshopFunction,
    broken: &user_functions::BrokenFunction,
) -> FunctionReport {
    let mut report = FunctionReport::new(
        function.name(),
        broken.line,
        "compile",
        "the function must compile as GLSL 4.60 for Vulkan".into(),
    );
    report.summary = "does not compile (the rest of the file is judged without it)".into();
    report.hint = Some(broken.messages.trim_end().to_string());
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loop_hints_name_no_option_check_lacks() {
        let hint = loop_hint_for_check(
            "the loop limit may have cut paths short in 12 pixels, so the image would be wrong: use fewer --samples-per-frame, a shorter --max-path-length or --accel bvh",
        );
        assert!(hint.starts_with("the loop limit may have cut paths short in 12 pixels"));
        assert!(!hint.contains("--"), "{hint}");
        assert!(hint.contains("continue"));
    }

    #[test]
    fn wgsl_is_named_and_glsl_is_not() {
        let wgsl = "// a port\nstruct Hit { t: f32, n: vec3<f32> }\nfn sample_sphere(u: vec2<f32>) -> vec3<f32> {\n    return vec3<f32>(0.0, 0.0, 1.0);\n}\n";
        assert_eq!(wgsl_line(wgsl).map(|(line, _)| line), Some(2));
        let glsl = "// fn is not a GLSL word\nvec3 sample_sphere(vec2 u) {\n    float fn_value = 1.0;\n    return vec3(0.0, 0.0, fn_value);\n}\n";
        assert_eq!(wgsl_line(glsl), None);
    }
}
