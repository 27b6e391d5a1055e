//! `vkpath merge SHARD.exr... -o OUT.{exr,png}`: combines the shards of one render.

use std::path::PathBuf;

use super::options::SaveArgs;
use crate::image_io::output::{check_writable, save_image, ImageFormat};
use crate::image_io::tonemap::RENDER_PNG_TONE_MAP;
use crate::render::state_exr::{merge_state_files, write_state};

/// Arguments of `vkpath merge`.
#[derive(Debug, Clone, clap::Args)]
pub struct MergeArgs {
    /// The shards: EXR files of `vkpath render --sample-range` or `--shard` (or checkpoints),
    /// of one scene and settings, whose sample ranges tile one range.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// The merged image: .exr (with the merged state, so it can be merged again) or .png.
    #[arg(short, long)]
    pub output: PathBuf,
    /// How a PNG is written (tone map: agx unless --tonemap says otherwise).
    #[command(flatten)]
    pub save: SaveArgs,
    /// Print nothing but warnings and errors.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `vkpath merge`.
pub fn run(args: &MergeArgs) -> anyhow::Result<()> {
    let format = check_writable(&args.output)?;
    let (merged, metadata) = merge_state_files(&args.shards)?;
    match format {
        ImageFormat::Exr => write_state(&args.output, &merged, &metadata)?,
        ImageFormat::Png => save_image(
            &args.output,
            &merged.image(),
            &args.save.options(RENDER_PNG_TONE_MAP),
        )?,
    }
    if !args.quiet {
        eprintln!(
            "vkpath: merged {} shards (samples {}..{}); wrote {}",
            args.shards.len(),
            merged.samples.start,
            merged.samples.end,
            args.output.display()
        );
    }
    Ok(())
}
