//! `vkpath check FILE.glsl`: judges a workshop attendee's versions of workshop functions.
//!
//! The file holds one or more functions with the workshop's signatures (the prototypes of
//! `glsl/workshop.glsl`). vkpath finds which it defines (`detect`), compiles the probe
//! kernels and the path tracer at run time with them in place of the reference versions
//! (`compile`; the reference versions of the other functions stay and call the user's), and
//! judges each function the way its contract allows:
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
pub mod report;
pub mod samplers;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::probe::{ProbeKind, ProbePipeline, ProbeRunner};
use crate::scene::Scene;
use crate::stats::sidak_alpha;
use crate::vk::Context;
pub use compile::UserFunctions;
pub use detect::WorkshopFunction;
pub use report::{CheckReport, FunctionReport};

/// `MAX_PATH_LENGTH` of the probe kernels (only `get_ray_radiance` reads it).
const PROBE_MAX_PATH_LENGTH: u32 = 5;

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
    /// `vkpath-check/`, 1% family-wise, 64 x 64 pixels at 256 spp: a million samples per
    /// render (about a second on lavapipe), 64 blocks of 16384 samples each, which resolves
    /// a bias of a few percent of a block's radiance.
    fn default() -> CheckOptions {
        CheckOptions {
            output_dir: PathBuf::from("vkpath-check"),
            alpha: 0.01,
            image_size: 64,
            spp: 256,
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
}

/// Reads a user's file and finds the workshop functions it defines.
pub fn load_user_functions(path: &Path) -> std::result::Result<UserFunctions, LoadError> {
    let text = std::fs::read_to_string(path).map_err(|source| LoadError::Unreadable {
        path: path.to_owned(),
        source,
    })?;
    let user = UserFunctions::new(&path.display().to_string(), text);
    if user.definitions.is_empty() {
        return Err(LoadError::NoWorkshopFunction {
            path: path.to_owned(),
        });
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
    /// The probe kernel `kind` compiled with the user's functions.
    pub fn user_probe(&self, kind: ProbeKind) -> Result<ProbePipeline> {
        let compiled = compile::compile_kernel(&kind.source_file(), Some(self.user), &[])
            .map_err(Error::ShaderCompilation)?;
        ProbePipeline::from_spirv(&self.context, kind, &compiled.spirv, PROBE_MAX_PATH_LENGTH)
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

/// Checks every workshop function that `user` defines and returns the verdicts. A signature
/// that differs from the workshop's, or a file that does not compile, is reported (the
/// compiler's messages name the user's file and lines) and nothing else is checked.
pub fn check(
    context: &Arc<Context>,
    user: &UserFunctions,
    options: &CheckOptions,
) -> Result<CheckReport> {
    let functions = user.functions();
    let mut report = CheckReport {
        file: user.display_name.clone(),
        device: context.info.name.clone(),
        defined_functions: functions.iter().map(|f| f.name().to_string()).collect(),
        passed: false,
        signature_errors: Vec::new(),
        compile_errors: None,
        compile_warnings: String::new(),
        functions: Vec::new(),
    };
    for definition in &user.definitions {
        if !definition.has_workshop_signature() {
            let expected = definition
                .function
                .signature()
                .map_or_else(|| "unknown".to_string(), |s| s.to_string());
            report.signature_errors.push(format!(
                "{}:{}: error: {} is defined as {} but the workshop declares {}",
                user.display_name,
                definition.line,
                definition.function.name(),
                definition.signature,
                expected
            ));
        }
    }
    if !report.signature_errors.is_empty() {
        return Ok(report);
    }
    // Every probe kernel includes the whole file, so one compilation finds its errors.
    match compile::compile_kernel("probe_get_random_numbers.comp", Some(user), &[]) {
        Ok(compiled) => report.compile_warnings = compiled.warnings,
        Err(messages) => {
            report.compile_errors = Some(messages);
            return Ok(report);
        }
    }
    let statistical_tests: usize = functions
        .iter()
        .map(|&f| samplers::test_count(f) + usize::from(estimators::integrator_for(f).is_some()))
        .sum();
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
    for function in functions {
        let verdict = match function {
            WorkshopFunction::GetRandomNumbers => deterministic::check_random_numbers(&session),
            WorkshopFunction::SampleSphere | WorkshopFunction::SampleHemisphere => {
                samplers::check_sampler(&session, function)
            }
            WorkshopFunction::RayTriangleIntersection => {
                deterministic::check_ray_triangle(&session)
            }
            WorkshopFunction::RayMeshIntersection => deterministic::check_ray_mesh(&session),
            WorkshopFunction::GetPrimaryRayDirection => deterministic::check_primary_ray(&session),
            WorkshopFunction::ComputeDirectIllumination | WorkshopFunction::GetRayRadiance => {
                estimators::check_estimator(&session, function)
            }
        }?;
        report.functions.push(verdict);
    }
    report.passed = report.functions.iter().all(|f| f.passed);
    Ok(report)
}
