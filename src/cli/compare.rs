//! `vkpath compare A.exr B.exr`: is A an unbiased estimate of B? Exit status 0 when the
//! images are consistent, 1 when they are not, 2 when they cannot be compared (a missing or
//! unreadable file, different sizes, a bad option).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::compare::heatmap::{heat_legend, heat_map};
use crate::compare::{
    compare_images, CompareOptions, CompareReport, VarianceSource, DEFAULT_ALPHA,
    DEFAULT_BLOCK_SIZE,
};
use crate::image_io::exr_input::{check_exr_file, read_exr, ExrImage};
use crate::image_io::output::{check_writable, save_image, SaveOptions};

/// What `compare` reads, for the error about a file that is not one.
pub const COMPARE_READS: &str =
    "`vkpath compare` reads OpenEXR images, as `vkpath render -o NAME.exr --moments` writes them";

/// Reads image `path` for the comparison; a file that is not an OpenEXR image is refused
/// with what it is and what `compare` reads.
fn read_input(path: &Path) -> anyhow::Result<ExrImage> {
    check_exr_file(path, Some(COMPARE_READS))?;
    Ok(read_exr(path)?)
}

/// Exit status when the images are not consistent.
pub const EXIT_INCONSISTENT: i32 = 1;
/// Exit status when the images cannot be compared (clap's status for usage errors).
pub const EXIT_USAGE: i32 = 2;

/// Arguments of `vkpath compare`.
#[derive(Debug, Clone, clap::Args)]
pub struct CompareArgs {
    /// The image under test (EXR; with moments from `vkpath render --moments` if possible).
    pub a: PathBuf,
    /// The reference (EXR). Without moments, it is taken as exact unless A lacks them too.
    pub b: PathBuf,
    /// Family-wise significance level: the chance that consistent images are reported
    /// inconsistent (Šidák-corrected over all tests).
    #[arg(long, default_value_t = DEFAULT_ALPHA)]
    pub alpha: f64,
    /// Side of the square blocks of pixels that are tested (1: every pixel). Blocks pool
    /// samples, so their z-scores are close to normal where single pixels' are heavy-tailed.
    #[arg(long = "block", default_value_t = DEFAULT_BLOCK_SIZE)]
    pub block_size: usize,
    /// Write a PNG of the blocks: grey where they agree, red to yellow where they fail.
    #[arg(long)]
    pub heatmap: Option<PathBuf>,
    /// Print the report as JSON on stdout instead of text.
    #[arg(long)]
    pub json: bool,
    /// Instead of the statistical test: are the pixels (and moments, where both have
    /// them) identical, bit for bit? Exit 0 if so, 1 if not (headers are not compared).
    #[arg(long, conflicts_with_all = ["heatmap", "json"])]
    pub exact: bool,
    /// Print nothing on stderr but errors (no line about the heat map); the verdict still
    /// goes to stdout.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `vkpath compare`. Does not return when the verdict is "inconsistent" (exit status 1)
/// or the images cannot be compared (one error line, exit status 2): `main` maps every error
/// to status 1, and these statuses tell scripts what happened.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    if args.exact {
        return run_exact(args);
    }
    let report = match compare_files(args) {
        Ok(report) => report,
        Err(error) => {
            eprintln!("vkpath: error: {error:#}");
            std::process::exit(EXIT_USAGE);
        }
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", describe(&report, &args.a, &args.b));
    }
    if !report.consistent {
        std::io::stdout().flush()?;
        std::process::exit(EXIT_INCONSISTENT);
    }
    Ok(())
}

/// `vkpath compare --exact`: the pixels bit for bit.
fn run_exact(args: &CompareArgs) -> anyhow::Result<()> {
    let read = |path: &Path| {
        read_input(path).unwrap_or_else(|error| {
            eprintln!("vkpath: error: {error:#}");
            std::process::exit(EXIT_USAGE);
        })
    };
    let (a, b) = (read(&args.a), read(&args.b));
    if (a.image.width, a.image.height) != (b.image.width, b.image.height) {
        eprintln!("vkpath: error: the images differ in size");
        std::process::exit(EXIT_USAGE);
    }
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
    let moments = a.has_moments && b.has_moments;
    let differing = (0..a.image.mean.len())
        .filter(|&i| {
            bits(&a.image.mean[i][..3]) != bits(&b.image.mean[i][..3])
                || moments
                    && (bits(&a.image.second_moment[i]) != bits(&b.image.second_moment[i])
                        || a.image.sample_count[i].to_bits() != b.image.sample_count[i].to_bits())
        })
        .count();
    if differing == 0 {
        println!("identical: every pixel is bit for bit the same");
        Ok(())
    } else {
        println!(
            "different: {differing} of {} pixels differ",
            a.image.mean.len()
        );
        std::io::stdout().flush()?;
        std::process::exit(EXIT_INCONSISTENT);
    }
}

/// Reads both images, compares them and writes the heat map.
fn compare_files(args: &CompareArgs) -> anyhow::Result<CompareReport> {
    if let Some(path) = &args.heatmap {
        check_writable(path)?;
    }
    let a = read_input(&args.a)?;
    let b = read_input(&args.b)?;
    let options = CompareOptions {
        alpha: args.alpha,
        block_size: args.block_size,
    };
    let report = compare_images(&a, &b, &options).map_err(|error| {
        anyhow::anyhow!(
            "cannot compare '{}' with '{}': {error}",
            args.a.display(),
            args.b.display()
        )
    })?;
    if let Some(path) = &args.heatmap {
        let map = heat_map(&report, a.image.width, a.image.height);
        save_image(path, &map, &SaveOptions::default())?;
        if !args.quiet {
            eprintln!(
                "vkpath: wrote {} (heat map of {size}x{size} blocks: {})",
                path.display(),
                heat_legend(report.per_test_significance),
                size = report.block_size
            );
        }
    }
    Ok(report)
}

/// The report as text: the verdict, then how the test was made and what failed.
pub fn describe(report: &CompareReport, a: &Path, b: &Path) -> String {
    let verdict = if report.consistent {
        "consistent: no evidence that A is biased"
    } else {
        "INCONSISTENT: A is not an unbiased estimate of B"
    };
    let source = match report.variance_source {
        VarianceSource::BothMoments => "the moments of both images",
        VarianceSource::MomentsOfA => "the moments of A (B, without moments, taken as exact)",
        VarianceSource::MomentsOfB => "the moments of B (A, without moments, taken as exact)",
        VarianceSource::WithinBlockSpread => {
            "the spread of A - B within each block (neither image has moments)"
        }
    };
    let block_count = report.blocks_x * report.blocks_y;
    let worst = &report.worst;
    let channel = ["R", "G", "B"].get(worst.channel).copied().unwrap_or("?");
    let mut text = format!("{verdict}\n  A: {}\n  B: {}\n", a.display(), b.display());
    text += &format!(
        "  test: {size}x{size} blocks, variance from {source}\n",
        size = report.block_size
    );
    text += &format!(
        "  {} tests ({block_count} blocks x 3 channels), alpha {} -> {:.3e} per test (Šidák)\n",
        report.test_count, report.alpha, report.per_test_significance
    );
    text += &format!(
        "  failing: {} of {block_count} blocks ({:.2}%), {} of {} tests\n",
        report.failing_blocks,
        100.0 * report.failing_block_fraction,
        report.failing_tests,
        report.test_count
    );
    text += &format!(
        "  worst: block ({}, {}) channel {channel}: A - B = {:.4e}, z = {:.2}, p = {:.3e}\n",
        worst.block_x, worst.block_y, worst.difference, worst.z, worst.p_value
    );
    text += &format!(
        "  relMSE of A against B: {:.4e} (mean of (A - B)^2 / (B^2 + 0.01))\n",
        report.relative_mse
    );
    text
}
