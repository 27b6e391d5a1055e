//! `vkpath check FILE.glsl`: judges a user's versions of workshop functions (see
//! `crate::check`). Exit status 0 when every judged function passes, 1 when one fails
//! (including a function or file that does not compile: the compiler's messages name the
//! file's lines), 2 when the file cannot be checked at all (it cannot be read, or nothing in
//! it can be judged).

use std::io::Write as _;
use std::path::PathBuf;

use super::output::fail_on_validation_messages;
use super::DeviceArgs;
use crate::check::{check, load_user_functions, report::describe, CheckOptions};

/// Exit status when a check fails.
pub const EXIT_FAILED: i32 = 1;
/// Exit status when the file cannot be checked (clap's status for usage errors).
pub const EXIT_USAGE: i32 = 2;

/// Arguments of `vkpath check`.
#[derive(Debug, Clone, clap::Args)]
pub struct CheckArgs {
    /// A GLSL file with your versions of workshop functions (with the workshop's
    /// signatures): a whole ShaderToy tab, a WebGL page shader, or just the functions.
    pub file: PathBuf,
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
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// A positive multiple of 8 up to 1024 (the renders are compared in 8 x 8 blocks).
fn parse_image_size(text: &str) -> Result<u32, String> {
    let size: u32 = text
        .parse()
        .map_err(|_| format!("'{text}' is not a whole number"))?;
    if size == 0 || !size.is_multiple_of(8) || size > 1024 {
        return Err(format!("{size} is not a multiple of 8 in 8..=1024"));
    }
    Ok(size)
}

/// Runs `vkpath check`. Does not return when a check fails (exit status 1) or the file
/// cannot be checked (one error line, exit status 2); other errors (no Vulkan, an image that
/// cannot be written) go to `main` as usual (status 1).
pub fn run(args: &CheckArgs) -> anyhow::Result<()> {
    let user = match load_user_functions(&args.file) {
        Ok(user) => user,
        Err(error) => {
            eprintln!("vkpath: error: {error}");
            std::process::exit(EXIT_USAGE);
        }
    };
    let context = args.device.create_context()?;
    let options = CheckOptions {
        output_dir: args.output_dir.clone(),
        spp: args.spp,
        image_size: args.size,
        ..CheckOptions::default()
    };
    let report = check(&context, &user, &options)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", describe(&report));
    }
    fail_on_validation_messages(&context)?;
    if !report.passed {
        std::io::stdout().flush()?;
        std::process::exit(EXIT_FAILED);
    }
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
