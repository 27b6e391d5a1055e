//! Options that several subcommands take, parsed into the library's own types. Their
//! defaults are the library's (`RenderSettings::default()`), never written here.

use std::path::PathBuf;
use std::time::Instant;

use crate::image_io::output::SaveOptions;
use crate::render::settings::{Accel, LightSampling, RenderSettings, SamplerKind};
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
}

impl SceneArgs {
    /// The scene these options name.
    pub fn source(&self) -> SceneSource {
        SceneSource::new(self.scene.as_deref(), self.generated)
    }

    /// Loads the scene; prints the loader's warnings, and how long generating took (after
    /// `command`, e.g. "vkpath render").
    pub fn load(&self, command: &str) -> anyhow::Result<Scene> {
        let source = self.source();
        let started = Instant::now();
        let scene = source.load_with(&LoadOptions {
            allow_external_paths: self.allow_external_paths,
        })?;
        if let SceneSource::Generated(_) = source {
            eprintln!(
                "{command}: generated {} triangles in {:.2} s",
                scene.triangles.len(),
                started.elapsed().as_secs_f64()
            );
        }
        for warning in &scene.warnings {
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
    /// it off. --max-path-length stays a hard limit.
    #[arg(long, default_value_t = RenderSettings::default().russian_roulette_start)]
    pub russian_roulette_start: u32,
    /// Ray traversal: a BVH for scenes above 64 triangles (auto), the workshop's loop over
    /// all triangles (none), or always a BVH (bvh).
    #[arg(long, value_enum, default_value_t = RenderSettings::default().accel)]
    pub accel: Accel,
    /// Random numbers of cosine, nee and mis: the workshop's PCG2D (pcg) or Owen-scrambled
    /// Sobol points (sobol). The workshop integrator always uses PCG2D.
    #[arg(long, value_enum, default_value_t = RenderSettings::default().sampler)]
    pub sampler: SamplerKind,
    /// How nee and mis sample a point on the chosen light: uniformly in the solid angle it
    /// subtends (solid-angle) or uniformly on its area (area).
    #[arg(long, value_enum, default_value_t = RenderSettings::default().light_sampling)]
    pub light_sampling: LightSampling,
}

impl RenderOptions {
    /// `settings` with these options in place of its own.
    pub fn apply(&self, settings: RenderSettings) -> RenderSettings {
        RenderSettings {
            max_path_length: self.max_path_length,
            samples_per_frame: self.samples_per_frame,
            russian_roulette_start: self.russian_roulette_start,
            accel: self.accel,
            sampler: self.sampler,
            light_sampling: self.light_sampling,
            ..settings
        }
    }
}

/// How the image file is written: `render` and `exercise` take it alike.
#[derive(Debug, Clone, clap::Args)]
pub struct SaveArgs {
    /// PNG only: multiply radiance by 2^EXPOSURE before clamping to [0, 1] and sRGB encoding.
    #[arg(long, default_value_t = SaveOptions::default().exposure, allow_negative_numbers = true)]
    pub exposure: f32,
    /// EXR only: also store each pixel's second moment and sample count (for `vkpath compare`).
    #[arg(long)]
    pub moments: bool,
}

impl SaveArgs {
    /// The library's save options these arguments describe.
    pub fn options(&self) -> SaveOptions {
        SaveOptions {
            exposure: self.exposure,
            moments: self.moments,
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::ValueEnum;

    use crate::bench::integrator_name;
    use crate::render::settings::{Integrator, LightSampling};

    /// The library spells some names itself (in reports, without clap); they must be the
    /// command line's.
    #[test]
    fn library_names_are_the_command_line_names() {
        for integrator in Integrator::value_variants() {
            let value = integrator.to_possible_value().unwrap();
            assert_eq!(value.get_name(), integrator_name(*integrator));
        }
        for light_sampling in LightSampling::value_variants() {
            let value = light_sampling.to_possible_value().unwrap();
            assert_eq!(value.get_name(), light_sampling.name());
        }
    }
}
