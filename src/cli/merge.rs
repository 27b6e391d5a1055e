//! `vkpath merge SHARD.exr... -o OUT.{exr,png} [-o OUT2...]`: combines the shards of one
//! render.

use std::path::PathBuf;

use anyhow::bail;

use super::options::SaveArgs;
use crate::image_io::exr_input::check_exr_file;
use crate::image_io::output::{check_writable, save_image, write_atomically, ImageFormat};
use crate::image_io::tonemap::RENDER_PNG_TONE_MAP;
use crate::render::state_exr::{merge_state_files, merge_state_layers, write_state_with_layers};

/// What `merge` reads, for the error about a file that is not one.
pub const MERGE_READS: &str =
    "`vkpath merge` reads the OpenEXR shards that `vkpath render --shard` or `--sample-range` writes";

/// Arguments of `vkpath merge`.
#[derive(Debug, Clone, clap::Args)]
pub struct MergeArgs {
    /// The shards: EXR files of `vkpath render --sample-range` or `--shard` (or checkpoints),
    /// of one scene and settings, whose sample ranges tile one range.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// The merged image: .exr (with the merged state, so it can be merged again) or .png;
    /// give it more than once (-o a.exr -o a.png) to write several files.
    #[arg(short, long = "output", required = true)]
    pub outputs: Vec<PathBuf>,
    /// How a PNG is written.
    #[command(flatten)]
    pub save: SaveArgs,
    /// Print nothing but warnings and errors.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `vkpath merge`.
pub fn run(args: &MergeArgs) -> anyhow::Result<()> {
    let mut formats = Vec::new();
    for (index, output) in args.outputs.iter().enumerate() {
        formats.push(check_writable(output)?);
        if args.outputs[..index].contains(output) {
            bail!("-o '{}' is given twice", output.display());
        }
    }
    for shard in &args.shards {
        check_exr_file(shard, Some(MERGE_READS))?;
    }
    args.save.warn_unused(&args.outputs, false);
    let (merged, metadata) = merge_state_files(&args.shards)?;
    // The shards' ground truth and Cryptomatte, the same in each: kept as they are
    let layers = merge_state_layers(&args.shards)?;
    for (output, format) in args.outputs.iter().zip(formats) {
        match format {
            ImageFormat::Exr => {
                write_state_with_layers(output, &merged, &metadata, &layers)?;
                copy_id_names(&args.shards[0], output)?;
            }
            ImageFormat::Png => save_image(
                output,
                &merged.image(),
                &args.save.options(RENDER_PNG_TONE_MAP),
            )?,
        }
    }
    if !args.quiet {
        let written: Vec<String> = args
            .outputs
            .iter()
            .map(|p| p.display().to_string())
            .collect();
        eprintln!(
            "vkpath: merged {} shards (samples {}..{}); wrote {}",
            args.shards.len(),
            merged.samples.start,
            merged.samples.end,
            written.join(", ")
        );
    }
    Ok(())
}

/// Copies the IDs' sidecar of the first shard (`NAME.ids.json`, which every shard with an ID
/// layer writes) beside `output`, if it has one.
fn copy_id_names(shard: &std::path::Path, output: &std::path::Path) -> anyhow::Result<()> {
    let sidecar = super::output::id_names_path(shard);
    if !sidecar.is_file() {
        return Ok(());
    }
    let text = std::fs::read(&sidecar)?;
    let target = super::output::id_names_path(output);
    write_atomically(&target, |temporary| std::fs::write(temporary, &text))?;
    Ok(())
}
