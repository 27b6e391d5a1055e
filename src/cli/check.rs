//! `vkpath check FILE.glsl...`: judges a user's versions of workshop functions (see
//! `crate::check`). Exit status 0 when every judged function passes, 1 when one fails
//! (including a function or file that does not compile: the compiler's messages name the
//! file's lines, and a function whose judging crashed the driver), 2 when the file cannot be
//! checked at all (it cannot be read, or nothing in it can be judged).
//!
//! Several files are one ShaderToy program: each pass (a file with an entry point) is
//! compiled on its own after the Common tab (`crate::check::load_user_passes`). The
//! functions and then the `program` verdict are judged in child processes (`vkpath
//! check-worker`, see `crate::check::isolation`), so that a driver crash costs one verdict;
//! each verdict is printed as soon as it is known, and `--json` prints one report whatever
//! happens.

use std::io::Write as _;
use std::path::PathBuf;
use std::time::Duration;

use super::value_error::ValueError;
use super::DeviceArgs;
use crate::check::isolation::{self, Outcome, WorkerEvent, WorkerJob, WorkerLauncher};
use crate::check::program::{
    is_workshop_program, is_workshop_program_tabs, judge_tabs_program, not_judged_of,
};
use crate::check::report::{
    describe_function, describe_header, describe_not_judged, describe_summary, CheckReport,
};
use crate::check::{
    judge_functions, load_user_passes, read_pasted_tabs, test_alpha_of_units, units_header,
    verdict_without_device, CheckOptions, UserFunctions, WorkshopFunction,
};

/// Exit status when a check fails.
pub const EXIT_FAILED: i32 = 1;
/// Exit status when the file cannot be checked (clap's status for usage errors).
pub const EXIT_USAGE: i32 = 2;

/// Arguments of `vkpath check`.
#[derive(Debug, Clone, clap::Args)]
pub struct CheckArgs {
    /// GLSL files with your versions of workshop functions (with the workshop's
    /// signatures): a whole ShaderToy tab, a WebGL page shader, or just the functions.
    /// Several files are the tabs of one ShaderToy program in ShaderToy's order: a file
    /// without an entry point (mainImage or main) is the Common tab, prepended to the
    /// others, then the Buffer tabs, then the Image tab.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Where to write the images of the render comparisons (created if needed).
    #[arg(long, default_value = "vkpath-check")]
    pub output_dir: PathBuf,
    /// Print the results as JSON on stdout instead of text.
    #[arg(long)]
    pub json: bool,
    /// Samples per pixel of each render (compute_direct_illumination, get_ray_radiance).
    #[arg(long, default_value_t = CheckOptions::default().spp, value_parser = clap::value_parser!(u32).range(4..=65536))]
    pub spp: u32,
    /// Side of the square renders in pixels, a multiple of 8.
    #[arg(long, default_value_t = CheckOptions::default().image_size, value_parser = parse_image_size)]
    pub size: u32,
    /// Frames to run a whole ShaderToy program (a tab with mainImage that accumulates the
    /// workshop's scene) for its `program` verdict; more frames resolve smaller biases.
    #[arg(long, default_value_t = crate::check::program::DEFAULT_FRAMES, value_parser = clap::value_parser!(u32).range(i64::from(crate::check::program::MIN_FRAMES)..=65536))]
    pub frames: u32,
    /// Seconds one function's judging may take before it is stopped and reported as not
    /// judged (a hang in the driver or in the function).
    #[arg(long, default_value_t = 600, value_parser = clap::value_parser!(u64).range(1..))]
    pub function_time_limit: u64,
    /// Print nothing on stderr but warnings and errors (no device line, no note about
    /// building kernels); the verdicts still go to stdout.
    #[arg(long)]
    pub quiet: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// Arguments of the hidden `vkpath check-worker`: judges functions of a prepared file read
/// as JSON from stdin, printing one JSON event per line (see `crate::check::isolation`).
#[derive(Debug, Clone, clap::Args)]
pub struct CheckWorkerArgs {
    /// The functions to judge, comma-separated (`program`: the program verdict).
    #[arg(long, value_delimiter = ',')]
    pub functions: Vec<String>,
    /// Frames the program runs for its verdict.
    #[arg(long, default_value_t = crate::check::program::DEFAULT_FRAMES)]
    pub frames: u32,
    /// Side of the square renders.
    #[arg(long)]
    pub size: u32,
    /// Samples per pixel of each render.
    #[arg(long)]
    pub spp: u32,
    /// The significance level of each statistical test (over all judged functions).
    #[arg(long)]
    pub test_alpha: f64,
    /// Where the images go.
    #[arg(long)]
    pub output_dir: PathBuf,
    /// Print nothing on stderr but warnings and errors (`check --quiet`).
    #[arg(long)]
    pub quiet: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// A positive multiple of 8 up to 1024 (the renders are compared in 8 x 8 blocks).
fn parse_image_size(text: &str) -> Result<u32, ValueError> {
    let size: u32 = text
        .parse()
        .map_err(|_| ValueError::NotWholeNumber { text: text.into() })?;
    if size == 0 || !size.is_multiple_of(8) || size > 1024 {
        return Err(ValueError::NotBlockSize { size });
    }
    Ok(size)
}

/// Prints text at once (the verdicts appear as they are known, also through a pipe).
fn print_now(text: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(text.as_bytes());
    let _ = stdout.flush();
}

/// Runs `vkpath check`. Does not return when a check fails (exit status 1) or the file
/// cannot be checked (one error line, exit status 2); other errors (no Vulkan, an image that
/// cannot be written) go to `main` as usual (status 1), after `--json` has printed the
/// report so far.
pub fn run(args: &CheckArgs) -> anyhow::Result<()> {
    let loaded =
        load_user_passes(&args.files).and_then(|units| Ok((units, read_pasted_tabs(&args.files)?)));
    let (units, tabs) = match loaded {
        Ok(loaded) => loaded,
        Err(error) => {
            if args.json {
                let report = CheckReport::unusable(&args.files, &error.to_string());
                println!("{}", serde_json::to_string_pretty(&report)?);
            }
            eprintln!("vkpath: error: {error}");
            std::process::exit(EXIT_USAGE);
        }
    };
    let options = CheckOptions {
        output_dir: args.output_dir.clone(),
        spp: args.spp,
        image_size: args.size,
        program_frames: args.frames,
        ..CheckOptions::default()
    };
    let tabs: Vec<(PathBuf, String)> = tabs
        .into_iter()
        .map(|tab| (PathBuf::from(tab.name), tab.text))
        .collect();
    let mut report = units_header(&units, "");
    if !args.json {
        print_now(&describe_header(&report));
    }
    let outcome = judge_all(args, &units, &tabs, &options, &mut report);
    // The verdicts came as they were known; the report lists them in the workshop's order.
    report.functions.sort_by_key(|f| {
        WorkshopFunction::from_name(&f.function).map_or(usize::MAX, |function| {
            WorkshopFunction::ALL
                .iter()
                .position(|&f| f == function)
                .unwrap_or(usize::MAX)
        })
    });
    report.passed = report.compile_errors.is_none()
        && report.functions.iter().all(|f| f.passed)
        && report.lost.is_empty();
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_now(&describe_summary(&report));
    }
    let validation = outcome?;
    if validation.validation_errors + validation.validation_warnings > 0 {
        anyhow::bail!(
            "the validation layer reported {} errors and {} warnings (see the log above)",
            validation.validation_errors,
            validation.validation_warnings
        );
    }
    if !report.passed {
        std::io::stdout().flush()?;
        std::process::exit(EXIT_FAILED);
    }
    Ok(())
}

/// Judges every function of every unit (pass) into `report`, printing each verdict
/// (without `--json`) as soon as it is known: those that do not compile at once, the others
/// in workers; then the `program` verdict when the tabs are a runnable program of the
/// workshop's scene, in a worker of its own. A unit that does not compile outside its
/// functions is judged no further, and then neither is the program.
fn judge_all(
    args: &CheckArgs,
    units: &[UserFunctions],
    tabs: &[(PathBuf, String)],
    options: &CheckOptions,
    report: &mut CheckReport,
) -> anyhow::Result<isolation::WorkerSummary> {
    let mut summary = isolation::WorkerSummary::default();
    let launcher = WorkerLauncher {
        executable: std::env::current_exe()
            .map_err(|e| anyhow::anyhow!("cannot find the vkpath binary to judge with: {e}"))?,
        device_arguments: args.device.to_arguments(),
        function_time_limit: Duration::from_secs(args.function_time_limit),
        quiet: args.quiet,
    };
    let alpha = test_alpha_of_units(units, options)?;
    let json = args.json;
    let record = |report: &mut CheckReport, outcome: Outcome| match outcome {
        Outcome::Verdict(verdict) => match not_judged_of(&verdict) {
            // A program that is not the workshop's (its own scene, no running mean): listed
            // with the reason, and the exit status comes from the functions alone.
            Some(not_judged) => {
                if !json {
                    print_now(&describe_not_judged(&not_judged));
                }
                report.not_judged.push(not_judged);
            }
            None => {
                if !json {
                    print_now(&describe_function(&verdict));
                }
                report.functions.push(*verdict);
            }
        },
        Outcome::Lost(lost) => {
            if !json {
                print_now(&describe_not_judged(&lost));
            }
            report.lost.push(lost);
        }
    };
    for unit in units.iter().filter(|u| u.compile_errors.is_none()) {
        let mut on_device = Vec::new();
        for function in unit.functions() {
            match verdict_without_device(unit, function) {
                Some(verdict) => record(report, Outcome::Verdict(Box::new(verdict))),
                None => on_device.push(function.name()),
            }
        }
        if on_device.is_empty() {
            continue;
        }
        let job = WorkerJob {
            user: unit.clone(),
            tabs: Vec::new(),
            verdicts: Vec::new(),
        };
        let judged =
            isolation::judge_in_workers(&launcher, &job, options, alpha, &on_device, |outcome| {
                record(report, outcome)
            })?;
        summary.add(judged);
    }
    // The unit that calls get_ray_radiance, else the first (its Common tab may define it).
    let program_unit = units
        .iter()
        .find(|u| is_workshop_program(&u.text))
        .or(units.first())
        .filter(|_| is_workshop_program_tabs(tabs));
    if let (Some(unit), None) = (program_unit, &report.compile_errors) {
        let job = WorkerJob {
            user: unit.clone(),
            tabs: tabs.to_vec(),
            verdicts: report.functions.clone(),
        };
        let judged = isolation::judge_in_workers(
            &launcher,
            &job,
            options,
            alpha,
            &[isolation::PROGRAM],
            |outcome| record(report, outcome),
        )?;
        summary.add(judged);
    }
    if let Some(device) = &summary.device {
        report.device = device.clone();
    }
    Ok(summary)
}

/// Runs `vkpath check-worker` (see `CheckWorkerArgs`).
pub fn run_worker(args: &CheckWorkerArgs) -> anyhow::Result<()> {
    let mut state = Vec::new();
    std::io::Read::read_to_end(&mut std::io::stdin(), &mut state)?;
    let job: WorkerJob = serde_json::from_slice(&state)
        .map_err(|e| anyhow::anyhow!("the check worker's input is not a prepared file: {e}"))?;
    let user = &job.user;
    let program = args.functions.iter().any(|name| name == isolation::PROGRAM);
    let functions: Vec<WorkshopFunction> = args
        .functions
        .iter()
        .filter(|name| *name != isolation::PROGRAM)
        .map(|name| {
            WorkshopFunction::from_name(name)
                .ok_or_else(|| anyhow::anyhow!("{name} is not a workshop function"))
        })
        .collect::<anyhow::Result<_>>()?;
    let context = args.device.create_context_reporting(!args.quiet)?;
    isolation::emit(&WorkerEvent::Started {
        device: context.info.name.clone(),
    })?;
    let options = CheckOptions {
        output_dir: args.output_dir.clone(),
        spp: args.spp,
        image_size: args.size,
        program_frames: args.frames,
        ..CheckOptions::default()
    };
    let fault = std::env::var(isolation::FAULT_VARIABLE).ok();
    let mut failure = None;
    let mut stopped = false;
    let judged = judge_functions(
        &context,
        user,
        &options,
        args.test_alpha,
        &functions,
        |function, verdict| {
            let event = match verdict {
                Ok(report) => WorkerEvent::Verdict {
                    report: Box::new(report),
                },
                Err(error) => WorkerEvent::Error {
                    function: function.name().to_string(),
                    message: error.to_string(),
                },
            };
            let stop = matches!(event, WorkerEvent::Error { .. });
            if let Err(error) = isolation::emit(&event) {
                failure = Some(error);
            }
            // After an error the device may be lost: a new worker judges the rest.
            stopped |= stop || failure.is_some();
            if stopped {
                return Err(crate::Error::InvalidSettings("stopped".into()));
            }
            Ok(())
        },
        |function| {
            if fault.as_deref() == Some(function.name()) {
                // Test-only: end the process as a driver crash would.
                std::process::abort();
            }
        },
    );
    if let Some(error) = failure {
        return Err(error);
    }
    match judged {
        // An error reported as an event: the parent goes on with a new worker.
        Err(_) if stopped => return Ok(()),
        Err(error) => return Err(error.into()),
        Ok(()) => {}
    }
    if program {
        if fault.as_deref() == Some(isolation::PROGRAM) {
            // Test-only: end the process as a driver crash while the program runs would.
            std::process::abort();
        }
        let verdict = judge_tabs_program(
            &context,
            &job.tabs,
            user.prepared.max_path_length,
            &options,
            args.test_alpha,
            &job.verdicts,
        );
        let event = match verdict {
            Ok(Some(report)) => WorkerEvent::Verdict {
                report: Box::new(report),
            },
            Ok(None) => WorkerEvent::Error {
                function: isolation::PROGRAM.into(),
                message: "the files are not a runnable program of the workshop's scene".into(),
            },
            Err(error) => WorkerEvent::Error {
                function: isolation::PROGRAM.into(),
                message: error.to_string(),
            },
        };
        let stop = matches!(event, WorkerEvent::Error { .. });
        isolation::emit(&event)?;
        if stop {
            return Ok(());
        }
    }
    let (errors, warnings) = context
        .validation_messages()
        .map_or((0, 0), |m| (m.errors(), m.warnings()));
    isolation::emit(&WorkerEvent::Finished {
        validation_errors: errors,
        validation_warnings: warnings,
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_sizes_are_multiples_of_eight() {
        assert_eq!(parse_image_size("64"), Ok(64));
        assert!(parse_image_size("0").is_err());
        assert!(parse_image_size("12").is_err());
        assert!(parse_image_size("2048").is_err());
        assert!(parse_image_size("x").is_err());
    }
}
