//! The `vkpath` command line: argument parsing and the subcommands. Errors reach `main` as
//! `anyhow` chains and are printed as one line. The subcommands parse and print; what they
//! share lives here (`DeviceArgs`, `parse_vec3`), in `options` (arguments), `output` (the
//! end of a render) and `summary`, never in one another.

use clap::{Parser, Subcommand};
use glam::{UVec2, Vec3};

use value_error::ValueError;

pub mod bench;
pub mod check;
pub mod compare;
pub mod devices;
pub mod exercise;
pub mod export;
pub mod frame_files;
pub mod frames;
pub mod lens;
pub mod merge;
pub mod options;
pub mod output;
pub mod render;
pub mod shadertoy;
pub mod shutter;
pub mod signals;
pub mod summary;
pub mod tev;
pub mod value_error;

/// Headless progressive path tracer: the Path Tracing Workshop's GLSL on Vulkan.
#[derive(Debug, Parser)]
#[command(name = "vkpath", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
// One is parsed per process: the size of the largest (`render`'s options) costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene (the workshop's Cornell box when none is given) to an EXR or PNG image.
    Render(render::RenderArgs),
    /// List the Vulkan devices.
    Devices(devices::DevicesArgs),
    /// Render one of the workshop's exercises as its ShaderToy framework shows it.
    Exercise(exercise::ExerciseArgs),
    /// Test whether image A is an unbiased estimate of image B (exit 0: consistent, 1: not, 2: unusable input).
    Compare(compare::CompareArgs),
    /// Judge your own versions of workshop functions in a GLSL file (exit 0: all pass, 1: a check fails, 2: unusable file).
    Check(check::CheckArgs),
    /// Compare the integrators' speed and efficiency on a fixed scene.
    Bench(bench::BenchArgs),
    /// Write a scene as PLY meshes (one per material) and a JSON manifest, for other renderers.
    Export(export::ExportArgs),
    /// Combine shards (`render --sample-range/--shard`) into one image (EXR or PNG).
    Merge(merge::MergeArgs),
    /// (internal) Judge functions for `vkpath check` in a child process.
    #[command(hide = true)]
    CheckWorker(check::CheckWorkerArgs),
    /// Run a whole ShaderToy program (Common, Buffers A-D, Image) headless for N frames.
    Shadertoy(shadertoy::ShadertoyArgs),
}

/// Options that choose and check the Vulkan device.
#[derive(Debug, Clone, clap::Args)]
pub struct DeviceArgs {
    /// Device to use: an index, a UUID (GPU-..., or a unique prefix) or part of a name, as
    /// `vkpath devices` lists them; for `render`, also `all` or a comma-separated list (e.g.
    /// 0,1) to render on several at once (a device may be listed twice). Without it:
    /// $VKPATH_DEVICE (same forms), then $CUDA_VISIBLE_DEVICES on machines with NVIDIA
    /// devices, then the first discrete GPU, integrated GPU, ..., CPU device.
    #[arg(long)]
    pub device: Option<String>,
    /// Fail unless the device is a GPU (not a CPU implementation such as lavapipe).
    #[arg(long)]
    pub require_gpu: bool,
    /// Enable the Vulkan validation layers (VK_LAYER_KHRONOS_validation).
    #[arg(long)]
    pub validate: bool,
    /// Neither read nor write the pipeline cache (compiled kernels kept between runs in
    /// $VKPATH_CACHE_DIR, else $XDG_CACHE_HOME/vkpath or ~/.cache/vkpath).
    #[arg(long)]
    pub no_cache: bool,
}

impl DeviceArgs {
    /// The devices of `--device all` or `--device A,B,...` (or the same in `VKPATH_DEVICE`)
    /// as indices, with why they were chosen; `None` for one device.
    pub fn several(&self) -> anyhow::Result<Option<(Vec<String>, String)>> {
        let environment = crate::vk::DeviceEnvironment::from_process();
        let selector = self.device.as_ref().or(environment.vkpath_device.as_ref());
        let asks_several = selector.is_some_and(|s| s.trim() == "all" || s.contains(','));
        if !asks_several {
            return Ok(None);
        }
        let devices = crate::vk::list_devices()?;
        let choice = crate::vk::choose_devices(
            &devices,
            self.device.as_deref(),
            &environment,
            self.require_gpu,
        )?;
        let indices = choice.indices.iter().map(ToString::to_string).collect();
        Ok(Some((indices, choice.reason)))
    }

    /// A context on each device of `selectors` (indices, as `several` gives them), each
    /// chosen because of `reason` (as `create_context_reporting` does for one).
    pub fn create_contexts(
        &self,
        selectors: &[String],
        reason: &str,
        announce: bool,
    ) -> crate::Result<Vec<std::sync::Arc<crate::vk::Context>>> {
        selectors
            .iter()
            .map(|selector| self.open(Some(selector.clone()), Some(reason.to_string()), announce))
            .collect()
    }

    /// These options as command-line arguments (for a child process).
    pub fn to_arguments(&self) -> Vec<String> {
        let mut arguments = Vec::new();
        if let Some(device) = &self.device {
            arguments.extend(["--device".to_string(), device.clone()]);
        }
        if self.require_gpu {
            arguments.push("--require-gpu".into());
        }
        if self.validate {
            arguments.push("--validate".into());
        }
        arguments
    }

    /// Creates the Vulkan context these options describe and prints which device it uses.
    pub fn create_context(&self) -> crate::Result<std::sync::Arc<crate::vk::Context>> {
        self.create_context_reporting(true)
    }

    /// `create_context`, printing the device only when `announce` is set (not with
    /// `--quiet`).
    pub fn create_context_reporting(
        &self,
        announce: bool,
    ) -> crate::Result<std::sync::Arc<crate::vk::Context>> {
        self.open(self.device.clone(), None, announce)
    }

    /// A context on `device` (`--device`'s syntax; `None`: the environment's or the default
    /// choice), chosen because of `chosen_because` if given; prints the device line (which
    /// device and why) when `announce` is set.
    fn open(
        &self,
        device: Option<String>,
        chosen_because: Option<String>,
        announce: bool,
    ) -> crate::Result<std::sync::Arc<crate::vk::Context>> {
        let context = crate::vk::Context::new(&crate::vk::ContextOptions {
            validate: self.validate,
            device,
            chosen_because,
            require_gpu: self.require_gpu,
            pipeline_cache: if self.no_cache {
                None
            } else {
                summary::pipeline_cache_store(announce)
            },
        })?;
        if announce {
            eprintln!(
                "vkpath: device {} (chosen by {})",
                context.info, context.chosen_because
            );
        }
        Ok(context)
    }
}

/// Parses "x,y,z" into a vector.
pub fn parse_vec3(text: &str) -> Result<Vec3, ValueError> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(ValueError::NotThreeNumbers { text: text.into() });
    }
    let mut values = [0.0f32; 3];
    for (value, part) in values.iter_mut().zip(&parts) {
        *value = part.parse::<f32>().map_err(|_| ValueError::NotNumber {
            text: part.to_string(),
        })?;
        if !value.is_finite() {
            return Err(ValueError::NotFinite {
                text: part.to_string(),
            });
        }
    }
    Ok(Vec3::from_array(values))
}

/// Parses "x,y" as a pixel (column, row).
pub fn parse_pixel(text: &str) -> Result<UVec2, ValueError> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [x, y] = parts[..] else {
        return Err(ValueError::NotPixel { text: text.into() });
    };
    let number = |s: &str| {
        s.parse::<u32>()
            .map_err(|_| ValueError::NotPixelIndex { text: s.into() })
    };
    Ok(UVec2::new(number(x)?, number(y)?))
}

/// Runs the command line; returns the process exit code.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Render(args) => render::run(&args),
        Command::Devices(args) => devices::run(&args),
        Command::Exercise(args) => exercise::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Check(args) => check::run(&args),
        Command::Export(args) => export::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::CheckWorker(args) => check::run_worker(&args),
        Command::Shadertoy(args) => shadertoy::run(&args),
    }
}

/// How a log record reads on the terminal: a warning or an error as the command's own lines
/// are written (`vkpath: warning: ...`), not as env_logger's `[WARN vkpath::render::renderer]
/// ...` (issue 58); the levels only `RUST_LOG` shows keep their level and module, for whoever
/// asked for them.
pub fn log_line(record: &log::Record) -> String {
    match record.level() {
        log::Level::Error => format!("vkpath: error: {}", record.args()),
        log::Level::Warn => format!("vkpath: warning: {}", record.args()),
        level => format!("[{level} {}] {}", record.target(), record.args()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warnings_from_the_log_read_as_the_commands_own() {
        let line = |level, text: &str| {
            log_line(
                &log::Record::builder()
                    .level(level)
                    .target("vkpath::render::renderer")
                    .args(format_args!("{text}"))
                    .build(),
            )
        };
        assert_eq!(
            line(log::Level::Warn, "no ray queries: the BVH"),
            "vkpath: warning: no ray queries: the BVH"
        );
        assert_eq!(line(log::Level::Error, "lost"), "vkpath: error: lost");
        assert_eq!(
            line(log::Level::Debug, "posed"),
            "[DEBUG vkpath::render::renderer] posed"
        );
    }

    #[test]
    fn vec3_parsing_accepts_triples_and_rejects_the_rest() {
        assert_eq!(parse_vec3("1, 2.5,-3").unwrap(), Vec3::new(1.0, 2.5, -3.0));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,2,x").is_err());
        assert!(parse_vec3("1,2,inf").is_err());
    }

    /// The help of subcommand `name`, as `vkpath NAME --help` prints it.
    fn long_help(name: &str) -> String {
        use clap::CommandFactory;
        let mut command = Cli::command();
        command.build();
        command
            .find_subcommand_mut(name)
            .expect("the subcommand exists")
            .render_long_help()
            .to_string()
    }

    /// The help of option `--long` of subcommand `name`.
    fn option_help(name: &str, long: &str) -> String {
        use clap::CommandFactory;
        let command = Cli::command();
        let subcommand = command
            .find_subcommand(name)
            .expect("the subcommand exists");
        let argument = subcommand
            .get_arguments()
            .find(|a| a.get_long() == Some(long))
            .expect("the option exists");
        argument
            .get_long_help()
            .or(argument.get_help())
            .map(ToString::to_string)
            .unwrap_or_default()
    }

    #[test]
    fn the_tone_map_help_names_the_default_the_code_uses() {
        use crate::image_io::tonemap::RENDER_PNG_TONE_MAP;
        for name in ["render", "merge"] {
            let help = option_help(name, "tonemap");
            let default = format!("[default: {}]", RENDER_PNG_TONE_MAP.name());
            assert!(help.contains(&default), "{name}: {help}");
        }
        let help = option_help("exercise", "tonemap");
        let default = format!("[default: {},", exercise::EXERCISE_TONE_MAP.name());
        assert!(help.contains(&default), "exercise: {help}");
    }

    #[test]
    fn help_mentions_no_option_the_subcommand_lacks() {
        // `--preview` is render's; `exercise` and `merge` share its image options.
        for name in ["exercise", "merge"] {
            let help = long_help(name);
            assert!(!help.contains("--preview"), "{name} --help: {help}");
        }
        for name in ["exercise", "compare", "check", "merge", "render"] {
            assert!(long_help(name).contains("--quiet"), "{name} has no --quiet");
        }
    }

    #[test]
    fn zero_samples_are_usage_errors() {
        for arguments in [
            &["vkpath", "render", "-o", "a.png", "--spp", "0"][..],
            &["vkpath", "bench", "--spp", "0"],
            &[
                "vkpath",
                "exercise",
                "path-tracing",
                "-o",
                "a.png",
                "--spp",
                "0",
            ],
        ] {
            let error = Cli::try_parse_from(arguments).unwrap_err();
            assert_eq!(error.exit_code(), 2, "{arguments:?}");
            assert!(
                error
                    .to_string()
                    .contains("'0' is not a number of samples per pixel in 1..="),
                "{error}"
            );
        }
    }

    #[test]
    fn merge_takes_several_outputs() {
        let cli = Cli::try_parse_from([
            "vkpath", "merge", "a.exr", "b.exr", "-o", "m.exr", "-o", "m.png",
        ])
        .unwrap();
        let Command::Merge(args) = cli.command else {
            panic!("not merge");
        };
        assert_eq!(args.outputs.len(), 2);
    }

    #[test]
    fn cli_definition_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
