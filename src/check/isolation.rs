//! Judging each function in a child process, so that a driver crash, a hang or a lost device
//! while one function runs costs only that function's verdict.
//!
//! The parent (`vkpath check`) never touches Vulkan: it prepares the user's file and starts
//! `vkpath check-worker` (a hidden subcommand of the same binary) with the functions to
//! judge, writing the prepared file as JSON to the worker's stdin. The worker creates the device and prints one
//! JSON line per event on its stdout: `started` (the device), one `verdict` per function as
//! soon as it is known, and `finished` (what the validation layer reported). When the
//! worker ends before a function's verdict (a crash: llvmpipe's segfaults end the process)
//! or runs past the time limit (then it is killed), that function is NOT JUDGED with the
//! reason, and a new worker judges the functions that remain.
//!
//! The `program` verdict (`crate::check::program`) is judged the same way, by a worker of
//! its own once the functions' verdicts are known (they name its likely cause): a crash
//! while the user's program runs costs only that verdict.
//!
//! `VKPATH_CHECK_FAULT=<function>` (for tests only) makes the worker abort, as a driver
//! crash would, just before it judges that function; `VKPATH_CHECK_FAULT=program` just
//! before it runs the program.

use std::io::{BufRead, BufReader, Write as _};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::check::detect::WorkshopFunction;
use crate::check::report::FunctionReport;
use crate::check::user_functions::{NotJudged, UserFunctions};
use crate::check::CheckOptions;

/// The test-only fault switch (see the module documentation).
pub const FAULT_VARIABLE: &str = "VKPATH_CHECK_FAULT";
/// The name that stands for the `program` verdict among the functions a worker judges.
pub const PROGRAM: &str = "program";

/// What a worker reads on its stdin (JSON): the prepared file, and for the `program`
/// verdict the user's tabs and the verdicts on the functions.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WorkerJob {
    /// The user's functions: one unit of the program (`crate::check::load_user_passes`).
    pub user: UserFunctions,
    /// The user's files in ShaderToy's order, (name, text), for the `program` verdict.
    #[serde(default)]
    pub tabs: Vec<(PathBuf, String)>,
    /// The verdicts on the functions, for the `program` verdict's likely cause.
    #[serde(default)]
    pub verdicts: Vec<FunctionReport>,
}

impl WorkerJob {
    /// The file and line of what `name` judges: a workshop function's definition, or the
    /// program's `mainImage`.
    fn place(&self, name: &str) -> (String, usize) {
        match WorkshopFunction::from_name(name) {
            Some(function) => self.user.locate(self.user.line_of(function)),
            None => crate::check::program::program_place(&self.tabs),
        }
    }
}

/// What a worker reports, one JSON object per line of its stdout.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum WorkerEvent {
    /// The device is ready.
    Started {
        /// Its name.
        device: String,
    },
    /// One function's verdict.
    Verdict {
        /// The verdict.
        report: Box<FunctionReport>,
    },
    /// Judging one function failed with an error that is vkpath's, not the user's code's
    /// (an image that cannot be written, a Vulkan error).
    Error {
        /// The function.
        function: String,
        /// The error, in one line.
        message: String,
    },
    /// Every function given was judged.
    Finished {
        /// Errors the validation layer reported (0 without `--validate`).
        validation_errors: u32,
        /// Warnings the validation layer reported.
        validation_warnings: u32,
    },
}

/// How the parent starts workers.
#[derive(Clone, Debug)]
pub struct WorkerLauncher {
    /// The vkpath binary.
    pub executable: PathBuf,
    /// Device arguments passed on (`--device`, `--validate`, `--require-gpu`).
    pub device_arguments: Vec<String>,
    /// How long one function may take before its worker is killed.
    pub function_time_limit: Duration,
    /// Whether the workers print nothing on stderr but warnings and errors (`check --quiet`:
    /// no device line, no note about building kernels).
    pub quiet: bool,
}

/// What became of one function judged in a worker.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Its verdict.
    Verdict(Box<FunctionReport>),
    /// Its worker crashed or hung: not judged, with the reason.
    Lost(NotJudged),
}

/// What the workers found besides the verdicts.
#[derive(Clone, Debug, Default)]
pub struct WorkerSummary {
    /// The device the workers ran on.
    pub device: Option<String>,
    /// Errors the validation layer reported, over all workers.
    pub validation_errors: u32,
    /// Warnings the validation layer reported.
    pub validation_warnings: u32,
}

impl WorkerSummary {
    /// Adds what other workers found.
    pub fn add(&mut self, other: WorkerSummary) {
        self.device = self.device.take().or(other.device);
        self.validation_errors += other.validation_errors;
        self.validation_warnings += other.validation_warnings;
    }
}

/// Judges `names` (workshop functions, or `PROGRAM`) of `job` in workers, calling
/// `on_outcome` as each verdict is known. Fails only when no worker can start (no Vulkan
/// device, say: the worker's error is returned) or vkpath itself fails judging a function.
pub fn judge_in_workers(
    launcher: &WorkerLauncher,
    job: &WorkerJob,
    options: &CheckOptions,
    test_alpha: f64,
    names: &[&str],
    mut on_outcome: impl FnMut(Outcome),
) -> anyhow::Result<WorkerSummary> {
    let state = serde_json::to_vec(job)?;
    let mut summary = WorkerSummary::default();
    let mut remaining: Vec<String> = names.iter().map(|n| n.to_string()).collect();
    while !remaining.is_empty() {
        let mut child = launcher.spawn(options, test_alpha, &remaining)?;
        if let Some(mut stdin) = child.stdin.take() {
            // A worker that dies at once closes the pipe; that is reported below.
            let _ = stdin.write_all(&state);
        }
        let stdout = child
            .stdout
            .take()
            .ok_or_else(|| anyhow::anyhow!("the check worker has no output"))?;
        let (sender, receiver) = mpsc::channel::<String>();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if sender.send(line).is_err() {
                    break;
                }
            }
        });
        let mut started = false;
        let lost_reason = loop {
            let line = match receiver.recv_timeout(launcher.function_time_limit) {
                Ok(line) => line,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    let _ = child.kill();
                    let _ = child.wait();
                    break Some(format!(
                        "judging it did not finish within {} s (a hang in the driver or your code); the other functions are judged without it",
                        launcher.function_time_limit.as_secs()
                    ));
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    let status = child.wait()?;
                    if !started {
                        anyhow::bail!(
                            "the check worker could not start ({}); see the messages above",
                            describe_status(&status)
                        );
                    }
                    break Some(format!(
                        "the Vulkan driver crashed running your function (the checking process ended: {}); the other functions are judged without it",
                        describe_status(&status)
                    ));
                }
            };
            let Ok(event) = serde_json::from_str::<WorkerEvent>(&line) else {
                continue; // not an event (a driver printing to stdout)
            };
            match event {
                WorkerEvent::Started { device } => {
                    started = true;
                    summary.device = Some(device);
                }
                WorkerEvent::Verdict { report } => {
                    remaining.retain(|f| *f != report.function);
                    on_outcome(Outcome::Verdict(report));
                }
                WorkerEvent::Error { function, message } => {
                    let _ = child.kill();
                    let _ = child.wait();
                    break Some(format!(
                        "judging {function} failed in vkpath: {message}; the other functions are judged without it"
                    ));
                }
                WorkerEvent::Finished {
                    validation_errors,
                    validation_warnings,
                } => {
                    summary.validation_errors += validation_errors;
                    summary.validation_warnings += validation_warnings;
                    let _ = child.wait();
                    break None;
                }
            }
        };
        if let Some(reason) = lost_reason {
            let lost = remaining.remove(0);
            let (file, line) = job.place(&lost);
            let reason = if lost == PROGRAM {
                reason.replace("running your function", "running your program")
            } else {
                reason
            };
            on_outcome(Outcome::Lost(NotJudged {
                function: lost,
                line,
                reason,
                file,
            }));
        } else if !remaining.is_empty() {
            anyhow::bail!(
                "the check worker finished without judging {}",
                remaining.join(", ")
            );
        }
    }
    Ok(summary)
}

impl WorkerLauncher {
    /// Starts a worker for `names` (the job goes to its stdin).
    fn spawn(
        &self,
        options: &CheckOptions,
        test_alpha: f64,
        names: &[String],
    ) -> anyhow::Result<Child> {
        Command::new(&self.executable)
            .arg("check-worker")
            .arg("--functions")
            .arg(names.join(","))
            .arg("--size")
            .arg(options.image_size.to_string())
            .arg("--spp")
            .arg(options.spp.to_string())
            .arg("--frames")
            .arg(options.program_frames.to_string())
            .arg("--test-alpha")
            .arg(format!("{test_alpha:e}"))
            .arg("--output-dir")
            .arg(&options.output_dir)
            .args(&self.device_arguments)
            .args(self.quiet.then_some("--quiet"))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| {
                anyhow::anyhow!(
                    "cannot start the check worker '{}': {e}",
                    self.executable.display()
                )
            })
    }
}

/// An exit status in words ("killed by signal 11 (SIGSEGV)", "exit status 1").
fn describe_status(status: &std::process::ExitStatus) -> String {
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt as _;
        if let Some(signal) = status.signal() {
            let name = match signal {
                4 => " (SIGILL)",
                6 => " (SIGABRT)",
                7 => " (SIGBUS)",
                8 => " (SIGFPE)",
                9 => " (SIGKILL)",
                11 => " (SIGSEGV)",
                _ => "",
            };
            return format!("killed by signal {signal}{name}");
        }
    }
    match status.code() {
        Some(code) => format!("exit status {code}"),
        None => "no exit status".into(),
    }
}

/// Prints one event as a JSON line on stdout, at once (the parent reads them as they come).
pub fn emit(event: &WorkerEvent) -> anyhow::Result<()> {
    let mut stdout = std::io::stdout().lock();
    serde_json::to_writer(&mut stdout, event)?;
    stdout.write_all(b"\n")?;
    stdout.flush()?;
    Ok(())
}
