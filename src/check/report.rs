//! What `vkpath check` found: a verdict per function with how it was judged, the tolerance,
//! the measured errors or statistics, and the first few mismatching inputs; as text for
//! people and as JSON for scripts.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::{Deserialize, Deserializer, Serialize};

pub use crate::check::user_functions::NotJudged;

/// How many mismatching inputs a report shows (the count covers all of them).
pub const SHOWN_MISMATCHES: usize = 5;

/// One input on which the user's function and the reference disagree.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Mismatch {
    /// The input, as GLSL-like text.
    pub input: String,
    /// What the reference returned.
    pub expected: String,
    /// What the user's function returned.
    pub actual: String,
}

/// The verdict on one function of the user's file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FunctionReport {
    /// The GLSL name.
    pub function: String,
    /// The user's file where it is defined (one of several tabs).
    #[serde(default)]
    pub file: String,
    /// Line of the user's file where it is defined.
    pub line: usize,
    /// How it was judged: "bit-exact", "tolerance", "chi-square" or "render".
    pub method: String,
    /// Whether it passed.
    pub passed: bool,
    /// One line saying what was found.
    pub summary: String,
    /// The tolerance or significance it was judged by, in words.
    pub tolerance: String,
    /// Inputs (or statistical tests) judged.
    pub cases: usize,
    /// Inputs (or tests) that failed.
    pub failures: usize,
    /// Near-degenerate inputs that were not judged (see `crate::probe::compare`).
    pub skipped: usize,
    /// Measured errors and statistics by name (e.g. "max_t_error_units", "p_value"); JSON
    /// writes a value that is not a number as `null`.
    #[serde(deserialize_with = "numbers_or_null")]
    pub measurements: BTreeMap<String, f64>,
    /// The first `SHOWN_MISMATCHES` failing inputs.
    pub mismatches: Vec<Mismatch>,
    /// Images written for this function (render comparisons, sample pictures).
    pub images: Vec<String>,
    /// The likely cause of a failure, in words, when the measurements point to a typical
    /// mistake (a heuristic: the verdict does not depend on it).
    pub hint: Option<String>,
    /// Findings that do not change the verdict (e.g. self-intersection together with the
    /// file's own intersection functions).
    pub warnings: Vec<String>,
}

impl FunctionReport {
    /// A report with the given identity and nothing measured yet.
    pub fn new(function: &str, line: usize, method: &str, tolerance: String) -> FunctionReport {
        FunctionReport {
            function: function.to_string(),
            file: String::new(),
            line,
            method: method.to_string(),
            passed: false,
            summary: String::new(),
            tolerance,
            cases: 0,
            failures: 0,
            skipped: 0,
            measurements: BTreeMap::new(),
            mismatches: Vec::new(),
            images: Vec::new(),
            hint: None,
            warnings: Vec::new(),
        }
    }

    /// Records a failing input (kept if fewer than `SHOWN_MISMATCHES` are kept).
    pub fn add_mismatch(&mut self, input: String, expected: String, actual: String) {
        self.failures += 1;
        if self.mismatches.len() < SHOWN_MISMATCHES {
            self.mismatches.push(Mismatch {
                input,
                expected,
                actual,
            });
        }
    }

    /// Records a measurement.
    pub fn measure(&mut self, name: &str, value: f64) {
        self.measurements.insert(name.to_string(), value);
    }
}

/// Measurements as JSON has them: `null` (what serde_json writes for NaN) read as NaN.
fn numbers_or_null<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<BTreeMap<String, f64>, D::Error> {
    let values: BTreeMap<String, Option<f64>> = BTreeMap::deserialize(deserializer)?;
    Ok(values
        .into_iter()
        .map(|(name, value)| (name, value.unwrap_or(f64::NAN)))
        .collect())
}

/// Everything `vkpath check` found about one file.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckReport {
    /// The user's file (the files, comma-separated, for several tabs).
    pub file: String,
    /// Why the file cannot be checked at all (exit status 2), if so; then nothing else is
    /// filled in.
    pub error: Option<String>,
    /// The Vulkan device that ran the checks.
    pub device: String,
    /// The workshop functions the file defines.
    pub defined_functions: Vec<String>,
    /// Whether every check passed.
    pub passed: bool,
    /// Workshop names that the file uses for something else (other parameters, another
    /// struct): listed with the reason, not judged.
    pub not_judged: Vec<NotJudged>,
    /// What check dropped, renamed or supplied to make the file compile as a kernel.
    pub notes: Vec<String>,
    /// The compiler's messages when the file does not compile outside any function (naming
    /// the user's file and lines); nothing is judged then. Functions that do not compile are
    /// reported one by one instead.
    pub compile_errors: Option<String>,
    /// The compiler's warnings about the file.
    pub compile_warnings: String,
    /// One verdict per defined function.
    pub functions: Vec<FunctionReport>,
    /// Functions whose judging crashed the driver, hung or failed in vkpath: not judged,
    /// with the reason; the check fails (exit status 1) when there is one.
    pub lost: Vec<NotJudged>,
}

impl CheckReport {
    /// The report on files that cannot be checked at all, saying why.
    pub fn unusable(files: &[std::path::PathBuf], error: &str) -> CheckReport {
        CheckReport {
            file: files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(" + "),
            error: Some(error.to_string()),
            device: String::new(),
            defined_functions: Vec::new(),
            passed: false,
            not_judged: Vec::new(),
            notes: Vec::new(),
            compile_errors: None,
            compile_warnings: String::new(),
            functions: Vec::new(),
            lost: Vec::new(),
        }
    }
}

/// A measurement as text: whole numbers as such, others with 4 significant digits.
fn number_text(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e9 {
        format!("{value}")
    } else if value != 0.0 && (value.abs() < 1e-3 || value.abs() >= 1e5) {
        format!("{value:.3e}")
    } else {
        format!("{value:.4}")
    }
}

/// The report as text: a line per function with its verdict and summary, its tolerance, its
/// measurements, the first mismatches and the images written.
pub fn describe(report: &CheckReport) -> String {
    let mut text = describe_header(report);
    for function in &report.functions {
        text.push_str(&describe_function(function));
    }
    text.push_str(&describe_summary(report));
    text
}

/// A "NOT JUDGED" line.
pub fn describe_not_judged(skipped: &NotJudged) -> String {
    let place = if skipped.file.is_empty() {
        format!("line {}", skipped.line)
    } else {
        format!("{}:{}", skipped.file, skipped.line)
    };
    format!(
        "NOT JUDGED {} ({place}): {}\n",
        skipped.function, skipped.reason
    )
}

/// Compiler output indented under its item: each message on its own line, continuation
/// lines (those that do not start a message) indented further.
pub fn indent_compiler_output(messages: &str, indent: &str) -> String {
    let mut text = String::new();
    for line in messages.trim_end().lines() {
        let starts_message = line.contains(": error:")
            || line.contains(": warning:")
            || line.contains(": note:")
            || line.starts_with("ERROR:")
            || line.starts_with("WARNING:");
        let _ = writeln!(
            text,
            "{indent}{}{}",
            if starts_message { "" } else { "  " },
            line.trim_end()
        );
    }
    text
}

/// What is known before any function is judged: the header line, the notes, the functions
/// not judged, the compiler's messages.
pub fn describe_header(report: &CheckReport) -> String {
    let mut text = String::new();
    let device = if report.device.is_empty() {
        String::new()
    } else {
        format!(" ({})", report.device)
    };
    let _ = writeln!(
        text,
        "vkpath check {}: {}{device}",
        report.file,
        report.defined_functions.join(", ")
    );
    for note in &report.notes {
        let _ = writeln!(text, "note: {note}");
    }
    for skipped in &report.not_judged {
        text.push_str(&describe_not_judged(skipped));
    }
    if let Some(errors) = &report.compile_errors {
        let _ = writeln!(text, "{} does not compile:", report.file);
        text.push_str(&indent_compiler_output(errors, "    "));
    }
    if !report.compile_warnings.trim().is_empty() {
        text.push_str(&indent_compiler_output(&report.compile_warnings, ""));
    }
    text
}

/// One function's verdict with its details.
pub fn describe_function(function: &FunctionReport) -> String {
    let mut text = String::new();
    {
        let verdict = if function.passed { "PASS" } else { "FAIL" };
        let place = if function.file.is_empty() {
            format!("line {}", function.line)
        } else {
            format!("{}:{}", function.file, function.line)
        };
        let _ = writeln!(
            text,
            "{verdict} {} ({place}, {}): {}",
            function.function, function.method, function.summary
        );
        let _ = writeln!(text, "    judged by: {}", function.tolerance);
        if !function.measurements.is_empty() {
            let measured: Vec<String> = function
                .measurements
                .iter()
                .map(|(name, value)| format!("{name} = {}", number_text(*value)))
                .collect();
            let _ = writeln!(text, "    measured: {}", measured.join(", "));
        }
        for mismatch in &function.mismatches {
            let _ = writeln!(
                text,
                "    input {}\n      expected {}\n      actual   {}",
                mismatch.input, mismatch.expected, mismatch.actual
            );
        }
        if function.failures > function.mismatches.len() && !function.mismatches.is_empty() {
            let _ = writeln!(
                text,
                "    ... and {} more",
                function.failures - function.mismatches.len()
            );
        }
        if let Some(hint) = &function.hint {
            let mut lines = hint.trim_end().lines();
            let _ = writeln!(
                text,
                "    {}: {}",
                if function.method == "compile" {
                    "compiler"
                } else {
                    "likely cause"
                },
                lines.next().unwrap_or_default()
            );
            for line in lines {
                let _ = writeln!(text, "      {}", line.trim_end());
            }
        }
        for warning in &function.warnings {
            let _ = writeln!(text, "    warning: {warning}");
        }
        for image in &function.images {
            let _ = writeln!(text, "    wrote {image}");
            if image.ends_with("-samples.png") {
                let _ = writeln!(
                    text,
                    "      (left: the reference's 512 samples, right: yours, drawn as `vkpath exercise` draws them)"
                );
            }
            if image.ends_with("-difference.png") {
                let _ = writeln!(
                    text,
                    "      ({})",
                    crate::check::estimators::DIFFERENCE_LEGEND
                );
            }
        }
    }
    text
}

/// The last line: how many functions passed, failed and were not judged.
pub fn describe_summary(report: &CheckReport) -> String {
    let mut text = String::new();
    let judged = report.functions.len();
    let failed = report.functions.iter().filter(|f| !f.passed).count();
    let _ = writeln!(
        text,
        "{}",
        if report.compile_errors.is_some() {
            "nothing judged: the file does not compile".to_string()
        } else if failed == 0 && report.lost.is_empty() {
            format!(
                "all {judged} judged functions passed ({} not judged)",
                report.not_judged.len()
            )
        } else if report.lost.is_empty() {
            format!(
                "{failed} of {judged} judged functions FAILED ({} not judged)",
                report.not_judged.len()
            )
        } else {
            format!(
                "{failed} of {judged} judged functions FAILED, {} could not be judged (vkpath's driver failed running them), {} not judged",
                report.lost.len(),
                report.not_judged.len()
            )
        }
    );
    text
}
