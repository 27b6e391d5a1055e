//! Options that several subcommands take, parsed into the library's own types. Their
//! defaults are the library's (`RenderSettings::default()`), never written here.

use std::ops::Range;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use super::output::Reporting;
use super::value_error::ValueError;
use crate::render::job::{
    shard_range, JobOptions, PreviewOptions, DEFAULT_CHECKPOINT_INTERVAL, DEFAULT_PREVIEW_INTERVAL,
};
use crate::render::metadata::parse_range;

use crate::image_io::output::{ImageFormat, SaveOptions};
use crate::image_io::tonemap::{Exposure, ToneMap};
use crate::medium::Medium;
use crate::render::settings::{
    default_russian_roulette_start, Accel, LightSampling, LightSelection, RenderSettings,
    SamplerKind, MAX_SPP,
};
use crate::scene::animation::AnimationPick;
use crate::scene::files::LoadOptions;
use crate::scene::{Scene, SceneSource};

/// Which scene: `render`, `bench` and `export` take it alike.
#[derive(Debug, Clone, clap::Args)]
pub struct SceneArgs {
    /// Scene file (.gltf, .glb or .obj); the workshop's Cornell box when omitted.
    pub scene: Option<PathBuf>,
    /// Instead of a scene file: the generated scale-test scene (the Cornell box with an
    /// icosphere and a displaced grid) of about this many triangles, e.g. 1000000.
    #[arg(long, conflicts_with = "scene")]
    pub generated: Option<usize>,
    /// Let a glTF file read buffers outside its own folder (absolute paths, `../`, `file:`
    /// URIs); off by default, so that a scene from elsewhere cannot read other files.
    #[arg(long)]
    pub allow_external_paths: bool,
    /// A glTF file's material variant (KHR_materials_variants) by name; without it each
    /// primitive's own material (an unknown name lists the file's variants).
    #[arg(long, value_name = "NAME")]
    pub variant: Option<String>,
}

impl SceneArgs {
    /// The scene these options name.
    pub fn source(&self) -> SceneSource {
        SceneSource::new(self.scene.as_deref(), self.generated)
    }

    /// How reports name the scene: its file, `builtin:cornell-box` or `generated:N`.
    pub fn name(&self) -> String {
        match self.source() {
            SceneSource::File(path) => path.display().to_string(),
            SceneSource::CornellBox => "builtin:cornell-box".into(),
            SceneSource::Generated(triangles) => format!("generated:{triangles}"),
        }
    }

    /// Loads the scene; prints the loader's warnings, and how long generating took (after
    /// `command`, e.g. "vkpath render").
    pub fn load(&self, command: &str) -> anyhow::Result<Scene> {
        self.load_reporting(command, true)
    }

    /// `load`, saying how long generating took only when `talk` is set (warnings always).
    pub fn load_reporting(&self, command: &str, talk: bool) -> anyhow::Result<Scene> {
        self.load_at(command, talk, true, 0.0, AnimationPick::All)
    }

    /// `load_reporting` with a glTF file's animations `animation` evaluated at `time`
    /// seconds; the loader's warnings printed only when `warn` is set (once per sequence).
    pub fn load_at(
        &self,
        command: &str,
        talk: bool,
        warn: bool,
        time: f32,
        animation: AnimationPick,
    ) -> anyhow::Result<Scene> {
        let source = self.source();
        let started = Instant::now();
        let scene = source.load_with(&LoadOptions {
            allow_external_paths: self.allow_external_paths,
            time,
            animation,
            variant: self.variant.clone(),
        })?;
        if let (SceneSource::Generated(_), true) = (source, talk) {
            eprintln!(
                "{command}: generated {} triangles in {:.2} s",
                scene.triangles.len(),
                started.elapsed().as_secs_f64()
            );
        }
        for warning in scene.warnings.iter().filter(|_| warn) {
            eprintln!("vkpath: warning: {warning}");
        }
        Ok(scene)
    }
}

/// How paths are traced: the render options `render` and `bench` share, with the same
/// defaults. (Image size and sample count are each subcommand's own: their defaults differ.)
#[derive(Debug, Clone, clap::Args)]
pub struct RenderOptions {
    /// Maximum number of surface hits per path (the workshop's MAX_PATH_LENGTH).
    #[arg(long, default_value_t = RenderSettings::default().max_path_length)]
    pub max_path_length: u32,
    /// Samples per pixel per frame (the workshop's SAMPLE_COUNT); the image does not depend
    /// on it. Fewer keep each dispatch short on a GPU; more amortise the per-frame cost.
    #[arg(long, default_value_t = RenderSettings::default().samples_per_frame)]
    pub samples_per_frame: u32,
    /// Path vertex after which Russian roulette may end a path (cosine, nee, mis); 0 turns
    /// it off. --max-path-length stays a hard limit [default: 3; 0 with --guiding, where
    /// roulette kills the paths the guide sends towards the light].
    #[arg(long, value_name = "N")]
    pub russian_roulette_start: Option<u32>,
    /// Ray traversal: a BVH for scenes above 64 triangles, or above 16 or with alpha-tested
    /// materials where glTF materials need the material kernels, and the device's ray
    /// queries instead of that BVH where it has them (auto), the workshop's loop over all
    /// triangles (none), always a BVH (bvh), always the compressed 8-wide BVH
    /// (compressed-bvh), or always the device's ray queries (hardware: VK_KHR_ray_query,
    /// e.g. Mesa 25's lavapipe; an error without them).
    #[arg(long, value_enum, default_value_t = RenderSettings::default().accel)]
    pub accel: Accel,
    /// Random numbers of cosine, nee and mis: independent PCG2D hashes (pcg) or
    /// Owen-scrambled Sobol points (sobol), each at a fixed sample dimension. The workshop
    /// integrator always uses the workshop's PCG2D stream [default: render: sobol; bench: pcg].
    #[arg(long, value_enum)]
    pub sampler: Option<SamplerKind>,
    /// How nee and mis sample a point on the chosen light: uniformly in the solid angle it
    /// subtends (solid-angle) or uniformly on its area (area).
    #[arg(long, value_enum, default_value_t = RenderSettings::default().light_sampling)]
    pub light_sampling: LightSampling,
    /// How nee and mis choose the emissive triangle they sample: the light tree above 16
    /// emissive triangles, else power (auto); in proportion to power (power); by a light
    /// tree's importance to the shading point (tree).
    #[arg(long, value_enum, default_value_t = RenderSettings::default().light_selection)]
    pub light_selection: LightSelection,
    /// Path guiding (nee, mis): first learn where light arrives from in each region of the
    /// scene (training iterations of 1, 2, 4, ... samples per pixel, thrown away), then
    /// sample directions from that mixed with the BSDF. For light that arrives through
    /// openings or from far away; --spp counts the render's samples, not the training's.
    #[arg(long)]
    pub guiding: bool,
    /// With --guiding: samples per pixel that train the guide, all iterations together
    /// [default: about a million paths in all (at least 4 per pixel), at most a quarter of
    /// --spp].
    #[arg(long, value_name = "N")]
    pub guide_training_spp: Option<u32>,
    /// A homogeneous medium (fog, haze) filling the space outside closed refracting volumes:
    /// sigma_a=R,G,B:sigma_s=R,G,B:g=G, absorption and scattering per scene unit (one value
    /// for all three channels allowed; a part left out is 0) and the Henyey-Greenstein g in
    /// (-1, 1). cosine, nee and mis render it; docs/media.md.
    #[arg(long, value_name = "sigma_a=R,G,B:sigma_s=R,G,B:g=G")]
    pub medium: Option<Medium>,
}

impl RenderOptions {
    /// `settings` with these options in place of its own (its sampler stays when --sampler
    /// is not given: the subcommand's default).
    pub fn apply(&self, settings: RenderSettings) -> RenderSettings {
        RenderSettings {
            max_path_length: self.max_path_length,
            samples_per_frame: self.samples_per_frame,
            russian_roulette_start: self
                .russian_roulette_start
                .unwrap_or(default_russian_roulette_start(self.guiding)),
            accel: self.accel,
            sampler: self.sampler.unwrap_or(settings.sampler),
            light_sampling: self.light_sampling,
            light_selection: self.light_selection,
            guiding: self
                .guiding
                .then(|| settings.guide_training(self.guide_training_spp)),
            medium: self.medium,
            ..settings
        }
    }
}

/// The default time between live updates of `render --tev`.
pub const DEFAULT_TEV_INTERVAL: Duration = Duration::from_secs(2);

/// A production render's controls (`render` only).
#[derive(Debug, Clone, clap::Args)]
pub struct JobArgs {
    /// Stop after this many seconds (after the current batch, within about a second) and
    /// write the samples taken so far; the EXR header says how many. A time-limited render
    /// is a finished one: --denoise and --aov still apply.
    #[arg(long, value_parser = parse_seconds)]
    pub time_limit: Option<f64>,
    /// Write the render state (sums, compensations, counts, metadata) to this EXR every
    /// --checkpoint-interval seconds and whenever the render stops.
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Seconds between checkpoints.
    #[arg(long, value_parser = parse_seconds, default_value_t = DEFAULT_CHECKPOINT_INTERVAL.as_secs_f64())]
    pub checkpoint_interval: f64,
    /// Continue the render saved in this checkpoint (same scene and settings); the result
    /// equals the uninterrupted render bit for bit.
    #[arg(long)]
    pub resume: Option<PathBuf>,
    /// Render only samples START..END of every pixel's sequence (a shard; combine shards
    /// with `vkpath merge`). --spp is ignored.
    #[arg(long, value_parser = parse_sample_range, conflicts_with = "shard")]
    pub sample_range: Option<Range<u32>>,
    /// Shard INDEX/COUNT (INDEX from 0) of the --spp samples: the INDEX-th of COUNT
    /// contiguous sample ranges (e.g. from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX).
    #[arg(long, value_parser = parse_shard)]
    pub shard: Option<(u32, u32)>,
    /// Rewrite a tone-mapped PNG of the image so far here (atomically) every
    /// --preview-interval seconds and when the render stops, with the output's --exposure
    /// and --tonemap.
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Seconds between previews.
    #[arg(long, value_parser = parse_seconds, default_value_t = DEFAULT_PREVIEW_INTERVAL.as_secs_f64(),
        allow_negative_numbers = true, requires = "preview")]
    pub preview_interval: f64,
    /// Show the render live in tev (the HDR viewer) listening at HOST:PORT (tev's default is
    /// 127.0.0.1:14158): the image so far every --tev-interval seconds, the finished one
    /// with its AOVs at the end. The render never waits for tev; an unreachable tev costs a
    /// warning; an address that is not HOST:PORT is a usage error.
    #[arg(long, value_name = "HOST:PORT", value_parser = parse_host_port)]
    pub tev: Option<String>,
    /// Seconds between live updates.
    #[arg(long, value_parser = parse_seconds, default_value_t = DEFAULT_TEV_INTERVAL.as_secs_f64(), requires = "tev")]
    pub tev_interval: f64,
    /// Print one JSON object at the end on stdout (outputs, scene, size, integrator,
    /// sampler, samples requested and taken, set-up and render seconds, samples/s, devices,
    /// stop reason, checkpoint; schema in the README) instead of the progress bar and summary.
    #[arg(long)]
    pub json: bool,
    /// Print only warnings and errors: nothing at all on success.
    #[arg(long)]
    pub quiet: bool,
}

impl JobArgs {
    /// The library's job options for a render of `spp` samples per pixel; a preview is
    /// written with `save`.
    pub fn options(&self, spp: u32, save: SaveOptions) -> anyhow::Result<JobOptions<'static>> {
        let samples = match (&self.sample_range, self.shard) {
            (Some(range), _) => range.clone(),
            (None, Some((index, count))) => shard_range(index, count, spp)?,
            (None, None) => 0..spp,
        };
        if samples.is_empty() {
            anyhow::bail!(
                "the sample range {}..{} is empty",
                samples.start,
                samples.end
            );
        }
        Ok(JobOptions {
            samples,
            time_limit: self.time_limit.map(Duration::from_secs_f64),
            cancel: None,
            checkpoint: self.checkpoint.clone(),
            checkpoint_interval: Duration::from_secs_f64(self.checkpoint_interval),
            resume: self.resume.clone(),
            preview: self.preview.clone().map(|path| PreviewOptions {
                path,
                interval: Duration::from_secs_f64(self.preview_interval),
                save: SaveOptions {
                    moments: false,
                    ..save
                },
            }),
            started: None,
            live: None,
            keep_state: self.is_shard(),
        })
    }

    /// Whether the render is a shard (its EXR holds the render state).
    pub fn is_shard(&self) -> bool {
        self.sample_range.is_some() || self.shard.is_some()
    }

    /// How the command reports.
    pub fn reporting(&self) -> Reporting {
        Reporting {
            json: self.json,
            quiet: self.quiet,
        }
    }
}

/// A positive, finite number of seconds.
pub(crate) fn parse_seconds(text: &str) -> Result<f64, ValueError> {
    let seconds: f64 = text
        .parse()
        .map_err(|_| ValueError::NotSeconds { text: text.into() })?;
    if !(seconds > 0.0 && seconds < 1e9) {
        return Err(ValueError::NotPositiveSeconds { text: text.into() });
    }
    Ok(seconds)
}

/// HOST:PORT for `--tev`: a host (a name, an IPv4 address or a bracketed IPv6 one) and a
/// port in 1..=65535. Only the form is checked here; whether tev listens there is the
/// render's business (a warning).
pub(crate) fn parse_host_port(text: &str) -> Result<String, ValueError> {
    let bad = |why| ValueError::NotHostPort {
        text: text.into(),
        why,
    };
    let (host, port) = text.rsplit_once(':').ok_or_else(|| bad("no ':PORT'"))?;
    if host.is_empty() || host.contains(char::is_whitespace) {
        return Err(bad("no host before ':'"));
    }
    if host.contains(':') && !(host.starts_with('[') && host.ends_with(']')) {
        return Err(bad("an IPv6 address goes in brackets, [::1]:14158"));
    }
    match port.parse::<u16>() {
        Ok(port) if port > 0 => Ok(text.to_string()),
        _ => Err(bad("the port is not a number in 1..=65535")),
    }
}

/// A sample count per pixel for `--spp`: a whole number in 1..=`MAX_SPP`. Parsed here, so
/// that `--spp 0` is a usage error (exit status 2) as every other malformed option is.
pub(crate) fn parse_spp(text: &str) -> Result<u32, ValueError> {
    match text.trim().parse::<u32>() {
        Ok(spp) if (1..=MAX_SPP).contains(&spp) => Ok(spp),
        _ => Err(ValueError::NotSpp { text: text.into() }),
    }
}

/// START..END with START < END.
fn parse_sample_range(text: &str) -> Result<Range<u32>, ValueError> {
    parse_range(text)
        .filter(|r| !r.is_empty())
        .ok_or_else(|| ValueError::NotSampleRange { text: text.into() })
}

/// INDEX/COUNT with INDEX < COUNT.
fn parse_shard(text: &str) -> Result<(u32, u32), ValueError> {
    let parsed = text
        .split_once('/')
        .and_then(|(i, c)| Some((i.trim().parse::<u32>().ok()?, c.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((index, count)) if index < count => Ok((index, count)),
        _ => Err(ValueError::NotShard { text: text.into() }),
    }
}

/// `auto`, or a finite number of stops.
fn parse_exposure(text: &str) -> Result<Exposure, ValueError> {
    if text.eq_ignore_ascii_case("auto") {
        return Ok(Exposure::Auto);
    }
    match text.parse::<f32>() {
        Ok(value) if value.is_finite() => Ok(Exposure::Stops(value)),
        _ => Err(ValueError::NotExposure { text: text.into() }),
    }
}

/// How the image file is written: `render`, `merge` and `exercise` take it alike; only the
/// default tone map differs (`options`).
#[derive(Debug, Clone, clap::Args)]
pub struct SaveArgs {
    /// PNG only: multiply radiance by 2^EXPOSURE before the tone map; `auto` maps the
    /// image's log-average luminance to middle grey 0.18 [default: 0].
    #[arg(long, allow_negative_numbers = true, value_parser = parse_exposure)]
    pub exposure: Option<Exposure>,
    // The default named here is `RENDER_PNG_TONE_MAP`'s; `exercise` replaces this help with
    // its own (`exercise::EXERCISE_TONEMAP_HELP`); `cli::tests` keeps both true.
    /// PNG only: how exposed radiance becomes display values [default: agx-punchy].
    #[arg(long, value_enum)]
    pub tonemap: Option<ToneMap>,
    /// EXR only: also store each pixel's second moment and sample count (for `vkpath compare`).
    #[arg(long)]
    pub moments: bool,
}

impl SaveArgs {
    /// The library's save options these arguments describe, with `default_tone_map` when
    /// --tonemap is not given.
    pub fn options(&self, default_tone_map: ToneMap) -> SaveOptions {
        SaveOptions {
            exposure: self.exposure.unwrap_or_default(),
            tone_map: self.tonemap.unwrap_or(default_tone_map),
            moments: self.moments,
            window: None,
        }
    }

    /// Warns about the options that none of `outputs` uses (with `preview`, a PNG that
    /// takes the PNG options too): --exposure and --tonemap without a PNG, --moments without
    /// an EXR.
    pub fn warn_unused(&self, outputs: &[PathBuf], preview: bool) {
        let has = |format: ImageFormat| {
            outputs
                .iter()
                .any(|p| ImageFormat::from_path(p).ok() == Some(format))
        };
        let names = || {
            outputs
                .iter()
                .map(|p| format!("'{}'", p.display()))
                .collect::<Vec<_>>()
                .join(", ")
        };
        if !has(ImageFormat::Png) && !preview {
            for (given, flag) in [
                (self.exposure.is_some(), "--exposure"),
                (self.tonemap.is_some(), "--tonemap"),
            ] {
                if given {
                    eprintln!(
                        "vkpath: warning: {flag} has no effect: it shapes PNG pictures, and {} holds linear radiance",
                        names()
                    );
                }
            }
        }
        if self.moments && !has(ImageFormat::Exr) {
            eprintln!(
                "vkpath: warning: --moments has no effect: it adds EXR channels, and {} is not an EXR",
                names()
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::ValueEnum;

    use crate::image_io::tonemap::ToneMap;
    use crate::render::settings::{Integrator, LightSampling, LightSelection};

    #[test]
    fn tev_addresses_are_host_and_port() {
        for good in [
            "127.0.0.1:14158",
            "localhost:1",
            "[::1]:14158",
            "viewer.lan:65535",
        ] {
            assert_eq!(super::parse_host_port(good).as_deref(), Ok(good));
        }
        for bad in [
            "localhost",
            "127.0.0.1",
            ":14158",
            "host:0",
            "host:70000",
            "host:port",
            "::1:14158",
            "a b:1",
        ] {
            assert!(super::parse_host_port(bad).is_err(), "{bad}");
        }
    }

    /// The library spells some names itself (in reports, without clap); they must be the
    /// command line's.
    #[test]
    fn library_names_are_the_command_line_names() {
        for integrator in Integrator::value_variants() {
            let value = integrator.to_possible_value().unwrap();
            assert_eq!(value.get_name(), integrator.name());
        }
        for light_sampling in LightSampling::value_variants() {
            let value = light_sampling.to_possible_value().unwrap();
            assert_eq!(value.get_name(), light_sampling.name());
        }
        for selection in LightSelection::value_variants() {
            let value = selection.to_possible_value().unwrap();
            assert_eq!(value.get_name(), selection.name());
        }
        for tone_map in ToneMap::value_variants() {
            let value = tone_map.to_possible_value().unwrap();
            assert_eq!(value.get_name(), tone_map.name());
        }
    }
}
