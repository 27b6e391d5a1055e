//! `vkpath shadertoy IMAGE.glsl [--common F] [--buffer-a F] … --frames N -o OUT` (or the
//! tabs as files in `vkpath check`'s order, `COMMON.glsl BUFFER_A.glsl IMAGE.glsl`): runs a
//! whole ShaderToy program headless (see `crate::shadertoy`) and writes the Image pass's
//! last frame and, on request, buffers' final contents. SIGINT, SIGTERM, SIGHUP and
//! `--time-limit` stop after the current frame, and what was reached is written. Exit
//! status: 0 done (or time limit), 1 a tab does not compile, its loops run past the limit
//! (nothing is written then: the frame's image would be wrong) or the device fails, 2
//! unusable arguments or files, 128 + the signal's number when a signal stopped it.

use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::options::parse_seconds;
use super::output::fail_on_validation_messages;
use super::value_error::ValueError;
use super::{signals, DeviceArgs};
use crate::image_io::output::{check_writable, ImageFormat};
use crate::shadertoy::display::save_pass_image;
use crate::shadertoy::{ChannelBinding, PassKind, Program, ShadertoyRunner};
use crate::vk::Context;

/// Exit status when a tab does not compile.
const EXIT_FAILED: i32 = 1;
/// Exit status of unusable arguments or files (clap's status for usage errors).
const EXIT_USAGE: i32 = 2;

/// Arguments of `vkpath shadertoy`.
#[derive(Debug, Clone, clap::Args)]
pub struct ShadertoyArgs {
    /// The Image tab (mainImage), or a page shader (main() with gl_FragCoord). Several files
    /// are the tabs of one program, read as `vkpath check` reads them: a file without an
    /// entry point is the Common tab and goes first whatever the order given, then the
    /// passes as given, Buffers A, B, … and the Image tab last.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// The Common tab, prepended to every pass.
    #[arg(long)]
    pub common: Option<PathBuf>,
    /// The Buffer A tab.
    #[arg(long)]
    pub buffer_a: Option<PathBuf>,
    /// The Buffer B tab.
    #[arg(long)]
    pub buffer_b: Option<PathBuf>,
    /// The Buffer C tab.
    #[arg(long)]
    pub buffer_c: Option<PathBuf>,
    /// The Buffer D tab.
    #[arg(long)]
    pub buffer_d: Option<PathBuf>,
    /// What a channel reads, PASS.N=SOURCE (e.g. image.1=buffer-b, buffer-a.2=noise.png, or
    /// a cube map: image.1=cube:sky_{}.png for six faces sky_px.png … sky_nz.png,
    /// image.1=cube:sky.exr for an equirectangular .exr/.hdr map); by default a buffer's
    /// iChannel0 is its own previous frame and the Image pass's iChannel0 is Buffer A.
    #[arg(long = "channel")]
    pub channels: Vec<ChannelBinding>,
    /// Frames to run (iFrame 0 .. N-1, iTime in steps of 1/60 s).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    pub frames: u32,
    /// Width in pixels.
    #[arg(long, default_value_t = 640, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 360, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub height: u32,
    /// The Image pass's last frame: .png as ShaderToy displays it (clamped, alpha
    /// ignored) or .exr (the floats the shader wrote, RGBA).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write a buffer's final contents as EXR, BUFFER=FILE.exr (e.g. a=A.exr).
    #[arg(long, value_parser = parse_save_buffer)]
    pub save_buffer: Vec<(PassKind, PathBuf)>,
    /// Stop after the frame during which this many seconds have passed, and write what
    /// was reached.
    #[arg(long, value_parser = parse_seconds)]
    pub time_limit: Option<f64>,
    /// Print only warnings and errors.
    #[arg(long)]
    pub quiet: bool,
    /// Device selection and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// `a=A.exr` or `buffer-b=B.exr`.
fn parse_save_buffer(text: &str) -> Result<(PassKind, PathBuf), ValueError> {
    let (name, path) = text
        .split_once('=')
        .ok_or_else(|| ValueError::NotBufferFile { text: text.into() })?;
    let kind = PassKind::from_name(name)
        .filter(|k| k.buffer_index().is_some())
        .ok_or_else(|| ValueError::NotABuffer {
            text: text.into(),
            name: name.into(),
        })?;
    let path = PathBuf::from(path);
    if ImageFormat::from_path(&path).ok() != Some(ImageFormat::Exr) {
        return Err(ValueError::BufferNotExr { text: text.into() });
    }
    Ok((kind, path))
}

/// Prints one error line and exits with the usage status.
fn usage_error(message: impl std::fmt::Display) -> ! {
    eprintln!("vkpath: error: {message}");
    std::process::exit(EXIT_USAGE);
}

/// Why the run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stop {
    Done,
    TimeLimit,
    Signal,
}

/// The Image tab, the Common tab and the buffers of the program: one file is the Image tab
/// with the `--common` and `--buffer-*` tabs; several are read as `vkpath check` reads them
/// (`crate::check::read_tabs`: the file without an entry point first, then the passes as
/// given), the last pass the Image tab and the others Buffers A, B, … in order. Exits with
/// one usage line where the files cannot make a program.
fn tabs_in_order(
    args: &ShadertoyArgs,
    buffers: Vec<(PassKind, PathBuf)>,
) -> (PathBuf, Option<PathBuf>, Vec<(PassKind, PathBuf)>) {
    // Read as check reads them: an unreadable file or a WGSL one is one usage line.
    let tabs = crate::check::read_tabs(&args.files).unwrap_or_else(|e| usage_error(e));
    let [image] = args.files.as_slice() else {
        if args.common.is_some() || !buffers.is_empty() {
            usage_error(
                "give the tabs either as files in order (Common, Buffers A…D, Image) or as one \
                 Image file with --common and --buffer-a…--buffer-d, not both",
            );
        }
        let (commons, passes): (Vec<_>, Vec<_>) = tabs
            .into_iter()
            .map(|(name, text)| (PathBuf::from(name), text))
            .partition(|(_, text)| crate::glsl_intake::find_entry_point(text).is_none());
        if let [first, second, ..] = commons.as_slice() {
            usage_error(format!(
                "'{}' and '{}' both have no entry point (mainImage or main): a program has one \
                 Common tab",
                first.0.display(),
                second.0.display()
            ));
        }
        let Some(((image, _), buffer_tabs)) = passes.split_last() else {
            usage_error("none of the files has an entry point (mainImage or main)");
        };
        if buffer_tabs.len() > PassKind::BUFFERS.len() {
            usage_error(format!(
                "{} files with an entry point: a program has at most 4 buffers and the Image tab",
                passes.len()
            ));
        }
        let buffers = PassKind::BUFFERS
            .into_iter()
            .zip(buffer_tabs.iter().map(|(path, _)| path.clone()))
            .collect();
        return (
            image.clone(),
            commons.into_iter().next().map(|c| c.0),
            buffers,
        );
    };
    (image.clone(), args.common.clone(), buffers)
}

/// Runs `vkpath shadertoy`.
pub fn run(args: &ShadertoyArgs) -> anyhow::Result<()> {
    let buffers: Vec<(PassKind, PathBuf)> = [
        (PassKind::BufferA, &args.buffer_a),
        (PassKind::BufferB, &args.buffer_b),
        (PassKind::BufferC, &args.buffer_c),
        (PassKind::BufferD, &args.buffer_d),
    ]
    .into_iter()
    .filter_map(|(kind, path)| path.clone().map(|p| (kind, p)))
    .collect();
    let (image, common, buffers) = tabs_in_order(args, buffers);
    let program = Program::from_files(&image, common.as_deref(), &buffers, &args.channels)
        .unwrap_or_else(|message| usage_error(message));
    for (kind, path) in &args.save_buffer {
        if program.pass(*kind).is_none() {
            usage_error(format!(
                "--save-buffer {}: the program has no {} (give it with --{})",
                path.display(),
                kind.name(),
                kind.name()
            ));
        }
    }
    if let Err(error) = check_writable(&args.output) {
        usage_error(error);
    }
    for (_, path) in &args.save_buffer {
        if let Err(error) = check_writable(path) {
            usage_error(error);
        }
    }
    let context = args.device.create_context()?;
    let mut runner = start_runner(&context, &program, args)?;
    signals::install(&[args.output.as_path()])?;
    // The passes are built: from here a first signal stops after the frame in flight.
    signals::RENDERING.store(true, Ordering::SeqCst);
    if !args.quiet {
        eprintln!(
            "vkpath: running {} pass(es) for {} frames at {}x{}",
            runner.pass_kinds().len(),
            args.frames,
            args.width,
            args.height
        );
    }
    let (stop, failure, seconds) = run_frames(&mut runner, args);
    if let Some(crate::Error::LoopLimit(message)) = &failure {
        // The frame's images hold loops that were cut short: a wrong image is not written.
        anyhow::bail!("{message}; nothing was written");
    }
    // Write what was reached, also after a failure (when the device still answers).
    let written = write_outputs(&runner, args);
    if let Some(error) = failure {
        let kept = match &written {
            Ok(()) => format!(
                "; the outputs hold the {} frames before it",
                runner.frames()
            ),
            Err(_) => String::new(),
        };
        anyhow::bail!("frame {} failed: {error}{kept}", runner.frames());
    }
    written?;
    if !args.quiet {
        eprintln!(
            "vkpath: {} of {} frames, {}x{}, {} pass(es), {seconds:.2} s ({:.1} frames/s){}",
            runner.frames(),
            args.frames,
            args.width,
            args.height,
            runner.pass_kinds().len(),
            f64::from(runner.frames()) / seconds.max(1e-9),
            match stop {
                Stop::Done => "",
                Stop::TimeLimit => ", stopped by --time-limit",
                Stop::Signal => ", stopped by a signal",
            }
        );
    }
    fail_on_validation_messages(&context)?;
    if stop == Stop::Signal {
        if let Some((name, status)) = signals::received() {
            eprintln!(
                "vkpath: stopped by {name} after {} frames; the outputs hold them",
                runner.frames()
            );
            std::process::exit(status);
        }
    }
    Ok(())
}

/// Builds the program's passes on `context`, printing its notes and warnings; a program that
/// does not compile ends the command (its messages printed), and a bad input is a usage
/// error.
fn start_runner(
    context: &Arc<Context>,
    program: &Program,
    args: &ShadertoyArgs,
) -> anyhow::Result<ShadertoyRunner> {
    let runner = match ShadertoyRunner::new(context, program, args.width, args.height) {
        Ok(runner) => runner,
        Err(crate::Error::ShaderCompilation(messages)) => {
            eprintln!("vkpath: error: the program does not compile:\n{messages}");
            std::process::exit(EXIT_FAILED);
        }
        Err(crate::Error::Image(message)) => usage_error(message),
        Err(error) => return Err(error).context("setting up the program"),
    };
    if !args.quiet {
        for note in program
            .hidden_buffer_note()
            .into_iter()
            .chain(program.setting_notes())
        {
            eprintln!("note: {note}");
        }
        for note in &runner.notes {
            eprintln!("note: {note}");
        }
    }
    if !runner.warnings.trim().is_empty() {
        eprintln!("{}", runner.warnings.trim_end());
    }
    Ok(runner)
}

/// Runs the frames asked for with a progress bar (after a second), until they are done, a
/// signal or the time limit stops them, or one fails: how they stopped, the failure and
/// the seconds they took.
fn run_frames(
    runner: &mut ShadertoyRunner,
    args: &ShadertoyArgs,
) -> (Stop, Option<crate::Error>, f64) {
    let bar =
        ProgressBar::with_draw_target(Some(u64::from(args.frames)), ProgressDrawTarget::hidden());
    if let Ok(style) =
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} frames, eta {eta}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    let started = Instant::now();
    let limit = args.time_limit.map(Duration::from_secs_f64);
    let mut stop = Stop::Done;
    let mut failure = None;
    while runner.frames() < args.frames {
        if signals::STOP_REQUESTED.load(Ordering::SeqCst) {
            stop = Stop::Signal;
            break;
        }
        if limit.is_some_and(|l| started.elapsed() >= l) {
            stop = Stop::TimeLimit;
            break;
        }
        if let Err(error) = runner.run_frame() {
            failure = Some(error);
            break;
        }
        if !args.quiet && started.elapsed() > Duration::from_secs(1) && bar.is_hidden() {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.set_position(u64::from(runner.frames()));
    }
    bar.finish_and_clear();
    (stop, failure, started.elapsed().as_secs_f64())
}

/// Writes the Image pass's last frame and the buffers asked for.
fn write_outputs(runner: &ShadertoyRunner, args: &ShadertoyArgs) -> anyhow::Result<()> {
    let mut outputs = vec![(PassKind::Image, args.output.clone())];
    outputs.extend(args.save_buffer.iter().cloned());
    for (kind, path) in outputs {
        let image = runner
            .read(kind)?
            .with_context(|| format!("the program has no {}", kind.name()))?;
        save_pass_image(&path, &image)?;
        if !args.quiet {
            eprintln!("wrote {}", path.display());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn save_buffer_takes_a_buffer_and_an_exr() {
        assert_eq!(
            parse_save_buffer("a=A.exr"),
            Ok((PassKind::BufferA, PathBuf::from("A.exr")))
        );
        assert!(parse_save_buffer("image=I.exr").is_err());
        assert!(parse_save_buffer("b=B.png").is_err());
        assert!(parse_save_buffer("B.exr").is_err());
    }
}
