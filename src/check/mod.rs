//! `vkpath check FILE.glsl`: judges a workshop attendee's versions of workshop functions.
//!
//! The file may be anything an attendee has: a whole ShaderToy tab, a WebGL page shader, or
//! just the functions. `source` prepares it (drops entry points, `#version`, uniforms …,
//! supplies ShaderToy's inputs, renames what clashes with vkpath's own names), `detect`
//! finds the workshop functions it defines with the workshop's signatures (the prototypes of
//! `glsl/workshop.glsl`; other uses of those names are listed as not judged), and `compile`
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
pub mod glsl_syntax;
pub mod program;
pub mod report;
pub mod samplers;
pub mod source;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::image_io::data::RenderedImage;
use crate::image_io::output::{save_image, SaveOptions};
use crate::probe::{ProbeKind, ProbePipeline, ProbeRunner};
use crate::scene::Scene;
use crate::stats::sidak_alpha;
use crate::vk::Context;
pub use compile::UserFunctions;
pub use detect::WorkshopFunction;
pub use report::{CheckReport, FunctionReport};

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
         function's name, its parameter list and '{{'",
        WorkshopFunction::ALL.map(WorkshopFunction::name).join(", ")
    )]
    NoWorkshopFunction {
        /// The file.
        path: PathBuf,
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

/// Reads a user's file, finds the workshop functions it defines and compiles it once (the
/// functions that do not compile are set aside, see `UserFunctions::find_broken_functions`).
pub fn load_user_functions(path: &Path) -> std::result::Result<UserFunctions, LoadError> {
    let bytes = std::fs::read(path).map_err(|source| LoadError::Unreadable {
        path: path.to_owned(),
        source,
    })?;
    // Published files come with a byte-order mark or Windows line ends now and then.
    let text = String::from_utf8_lossy(&bytes)
        .trim_start_matches('\u{feff}')
        .replace("\r\n", "\n");
    let mut user = UserFunctions::new(&path.display().to_string(), text);
    if user.definitions.is_empty() {
        if user.not_judged.is_empty() {
            return Err(LoadError::NoWorkshopFunction {
                path: path.to_owned(),
            });
        }
        return Err(LoadError::NothingToJudge {
            path: path.to_owned(),
            reasons: user
                .not_judged
                .iter()
                .map(|n| format!("{} (line {}): {}", n.function, n.line, n.reason))
                .collect::<Vec<_>>()
                .join("; "),
        });
    }
    match user.find_broken_functions() {
        Ok(warnings) => user.compile_warnings = warnings,
        Err(messages) => user.compile_errors = Some(messages),
    }
    Ok(user)
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
            .map_err(Error::ShaderCompilation)?;
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

/// Checks every workshop function that `user` defines with the workshop's signature and
/// returns the verdicts: one per function, those that do not compile failed with the
/// compiler's messages. Other uses of workshop names are listed as not judged. A file that
/// does not compile outside its functions is reported (the compiler's messages name the
/// user's file and lines) and nothing is judged.
pub fn check(
    context: &Arc<Context>,
    user: &UserFunctions,
    options: &CheckOptions,
) -> Result<CheckReport> {
    let functions = user.judged_functions();
    let mut report = CheckReport {
        file: user.display_name.clone(),
        device: context.info.name.clone(),
        defined_functions: user
            .functions()
            .iter()
            .map(|f| f.name().to_string())
            .collect(),
        passed: false,
        not_judged: user.not_judged.clone(),
        notes: user.prepared.notes.clone(),
        compile_errors: user.compile_errors.clone(),
        compile_warnings: user.compile_warnings.clone(),
        functions: Vec::new(),
    };
    if report.compile_errors.is_some() {
        return Ok(report);
    }
    for broken in &user.broken {
        if WorkshopFunction::from_name(&broken.name).is_none() {
            report.notes.push(format!(
                "line {}: your {} does not compile and is left out: {}",
                broken.line,
                broken.name,
                broken.messages.lines().next().unwrap_or_default()
            ));
        }
    }
    let statistical_tests: usize = functions
        .iter()
        .map(|&f| samplers::test_count(f) + usize::from(estimators::integrator_for(f).is_some()))
        .sum::<usize>()
        + usize::from(program::is_workshop_program(&user.text));
    let test_alpha = if statistical_tests > 0 {
        sidak_alpha(options.alpha, statistical_tests)
            .map_err(|e| Error::InvalidSettings(e.to_string()))?
    } else {
        options.alpha
    };
    let scene = Scene::builtin_cornell_box()?;
    let session = Session {
        context: context.clone(),
        user,
        options,
        runner: ProbeRunner::new(context, &scene.triangles)?,
        scene,
        test_alpha,
    };
    for function in user.functions() {
        let verdict = match user.broken.iter().find(|b| b.name == function.name()) {
            Some(broken) => does_not_compile(function, broken),
            None => match judge(&session, function) {
                Err(Error::LoopLimit(message)) => loops_without_end(function, user, message),
                verdict => verdict?,
            },
        };
        report.functions.push(verdict);
    }
    if let Some(verdict) = program::judge_file_as_program(&session, &report.functions)? {
        report.functions.push(verdict);
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
    report.hint = Some(message);
    report
}

/// The verdict on a function that does not compile: failed, with the compiler's messages.
fn does_not_compile(
    function: WorkshopFunction,
    broken: &compile::BrokenFunction,
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
