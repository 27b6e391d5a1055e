//! Render settings: what the user chooses, validated before anything is rendered.

use crate::contract;
use crate::error::{Error, Result};
use crate::guiding::training::GuideTraining;
use crate::medium::Medium;
use crate::render::adaptive::NoiseThreshold;
use crate::render::region::PixelRegion;

/// Where in a pixel the samples look.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum PixelFilter {
    /// Uniformly jittered inside the pixel: the box-filtered image.
    #[default]
    #[cfg_attr(
        feature = "cli",
        value(help = "Jitter uniformly inside the pixel (box filter)")
    )]
    Box,
    /// Always the pixel centre, as the workshop's ShaderToy does.
    #[cfg_attr(
        feature = "cli",
        value(help = "The pixel centre, as the workshop does")
    )]
    Center,
}

impl PixelFilter {
    /// The `PIXEL_FILTER_*` value of `glsl/shared.h`.
    pub fn spec_constant(self) -> u32 {
        match self {
            PixelFilter::Box => contract::PIXEL_FILTER_BOX,
            PixelFilter::Center => contract::PIXEL_FILTER_CENTER,
        }
    }
}

/// What the kernel computes per sample. The command line's `--integrator` offers the four
/// path tracers (the first as `workshop`); the other two are `vkpath exercise` pictures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Integrator {
    /// Exercise 7: the workshop's path tracer (uniform hemisphere sampling).
    #[default]
    #[cfg_attr(
        feature = "cli",
        value(
            name = "workshop",
            help = "Uniform hemisphere sampling, exactly as the workshop's slides"
        )
    )]
    PathTracing,
    /// Exercise 6: emission plus one-sample direct illumination.
    #[cfg_attr(feature = "cli", value(skip))]
    DirectIllumination,
    /// Part 1: the albedo of the first hit, unshaded.
    #[cfg_attr(feature = "cli", value(skip))]
    RayTracing,
    /// Path tracing with cosine-weighted hemisphere sampling.
    #[cfg_attr(feature = "cli", value(help = "Cosine-weighted hemisphere sampling"))]
    Cosine,
    /// Next event estimation: a light sample at every vertex, cosine sampling to continue.
    #[cfg_attr(
        feature = "cli",
        value(help = "Next event estimation (light sampling)")
    )]
    Nee,
    /// Light and cosine samples combined with the power heuristic.
    #[cfg_attr(
        feature = "cli",
        value(help = "Light and cosine sampling combined with the power heuristic")
    )]
    Mis,
    /// The first hit's shading normal (world space, facing the camera), for `--aov normal`.
    #[cfg_attr(feature = "cli", value(skip))]
    Normal,
    /// The first hit's distance from the camera, for `--aov depth`.
    #[cfg_attr(feature = "cli", value(skip))]
    Depth,
    /// The first hit's (metallic, roughness, 0) after texture lookups, for `--aov material`.
    #[cfg_attr(feature = "cli", value(skip))]
    Material,
    /// The first hit's triangle (index + 1 in the uploaded order) and barycentrics, for the
    /// ground-truth AOVs (`--aov object_id`, `position`, ...).
    #[cfg_attr(feature = "cli", value(skip))]
    Triangle,
}

impl Integrator {
    /// The `INTEGRATOR_*` value of `glsl/shared.h`.
    pub fn spec_constant(self) -> u32 {
        match self {
            Integrator::PathTracing => contract::INTEGRATOR_PATH_TRACING,
            Integrator::DirectIllumination => contract::INTEGRATOR_DIRECT_ILLUMINATION,
            Integrator::RayTracing => contract::INTEGRATOR_RAY_TRACING,
            Integrator::Cosine => contract::INTEGRATOR_COSINE,
            Integrator::Nee => contract::INTEGRATOR_NEE,
            Integrator::Mis => contract::INTEGRATOR_MIS,
            Integrator::Normal => contract::INTEGRATOR_NORMAL,
            Integrator::Depth => contract::INTEGRATOR_DEPTH,
            Integrator::Material => contract::INTEGRATOR_MATERIAL,
            Integrator::Triangle => contract::INTEGRATOR_TRIANGLE,
        }
    }

    /// The name the CLI (`--integrator`), `vkpath bench` and reports use: "workshop",
    /// "cosine", "nee" or "mis" (the others are not on the command line).
    pub fn name(self) -> &'static str {
        match self {
            Integrator::PathTracing => "workshop",
            Integrator::Cosine => "cosine",
            Integrator::Nee => "nee",
            Integrator::Mis => "mis",
            Integrator::DirectIllumination => "direct-illumination",
            Integrator::RayTracing => "ray-tracing",
            Integrator::Normal => "normal",
            Integrator::Depth => "depth",
            Integrator::Material => "material",
            Integrator::Triangle => "triangle",
        }
    }

    /// Whether this integrator takes light samples (nee and mis): the ones path guiding
    /// guides.
    pub fn takes_light_samples(self) -> bool {
        matches!(self, Integrator::Nee | Integrator::Mis)
    }

    /// Whether this is a path tracer with importance sampling (and Russian roulette).
    pub fn is_importance_sampled(self) -> bool {
        matches!(self, Integrator::Cosine | Integrator::Nee | Integrator::Mis)
    }
}

/// Where the importance-sampled integrators (cosine, nee, mis) get their random numbers, one
/// pair per fixed sample dimension (`glsl/sample_dimensions.glsl`); the workshop integrators
/// always draw the workshop's PCG2D stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum SamplerKind {
    /// PCG2D as a hash of the pixel, the sample index and the dimension pair
    /// (`get_pcg_sample_2d()`): independent random numbers.
    #[default]
    #[cfg_attr(
        feature = "cli",
        value(help = "PCG2D hashed per pixel, sample and dimension: independent random numbers")
    )]
    Pcg,
    /// Owen-scrambled, shuffled 2D Sobol points per dimension pair (Burley 2020,
    /// `glsl/sobol.glsl`): low-discrepancy, still unbiased.
    #[cfg_attr(
        feature = "cli",
        value(help = "Owen-scrambled Sobol points (Burley 2020): lower error at the same spp")
    )]
    Sobol,
}

impl SamplerKind {
    /// The `SAMPLER_*` value of `glsl/shared.h`.
    pub fn spec_constant(self) -> u32 {
        match self {
            SamplerKind::Pcg => contract::SAMPLER_PCG,
            SamplerKind::Sobol => contract::SAMPLER_SOBOL,
        }
    }
}

/// How nee and mis sample a point on the light they chose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum LightSampling {
    /// A direction uniformly distributed in the solid angle the triangle subtends (Arvo
    /// 1995); by area where that is below 10^-3 sr or above 6 sr.
    #[default]
    #[cfg_attr(
        feature = "cli",
        value(
            help = "A direction uniform in the light's solid angle (Arvo 1995): less noise near lights"
        )
    )]
    SolidAngle,
    /// A point uniformly distributed on the triangle's area, as the nee describes:
    /// its density in solid angle grows as distance^2, so points near a light are noisy.
    #[cfg_attr(feature = "cli", value(help = "A point uniform on the light's area"))]
    Area,
}

impl LightSampling {
    /// The `LIGHT_SAMPLING_*` value of `glsl/shared.h`.
    pub fn spec_constant(self) -> u32 {
        match self {
            LightSampling::Area => contract::LIGHT_SAMPLING_AREA,
            LightSampling::SolidAngle => contract::LIGHT_SAMPLING_SOLID_ANGLE,
        }
    }

    /// The name the CLI and `vkpath bench` use: "area" or "solid-angle".
    pub fn name(self) -> &'static str {
        match self {
            LightSampling::Area => "area",
            LightSampling::SolidAngle => "solid-angle",
        }
    }
}

/// How nee and mis choose the light they sample: the lights' own setting, declared in the
/// lights' room.
pub use crate::lights::LightSelection;

/// How rays find the closest triangle, and the size above which `Accel::Auto` takes a BVH:
/// declared in the variant room, which decides the traversal.
pub use crate::kernels::variant::{Accel, BVH_THRESHOLD};

/// Largest image side we accept (also bounded by the device's limit).
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Largest sample count per pixel: counts are accumulated in f32, exact up to 2^24.
pub const MAX_SPP: u32 = 1 << 24;
/// Longest path we accept (surface hits); beyond this, contributions are negligible for any
/// physically plausible albedo and the frames get needlessly long.
pub const MAX_PATH_LENGTH_LIMIT: u32 = 1024;

/// The workshop's MAX_PATH_LENGTH, the default path length.
pub const DEFAULT_MAX_PATH_LENGTH: u32 = crate::contract::DEFAULT_MAX_PATH_LENGTH;

/// Everything a render needs besides the scene and camera.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel in total.
    pub spp: u32,
    /// Maximum number of surface hits per path (the workshop's MAX_PATH_LENGTH).
    pub max_path_length: u32,
    /// Mixed into every pixel's random seed; 0 is exactly the workshop's seeding.
    pub seed: u32,
    /// Where samples look inside a pixel.
    pub pixel_filter: PixelFilter,
    /// What each sample computes.
    pub integrator: Integrator,
    /// Samples per pixel per frame (the workshop's SAMPLE_COUNT). Keep frames short: a GPU
    /// watchdog may kill a long dispatch. The default, 4, is 1.2x (mis) to 1.5x (workshop)
    /// as fast as 1 on lavapipe, where each frame costs about as much per pixel as a sample.
    pub samples_per_frame: u32,
    /// Path vertex after which Russian roulette may end a path (importance-sampled
    /// integrators only); 0 turns it off. `max_path_length` stays a hard limit.
    pub russian_roulette_start: u32,
    /// How rays find triangles.
    pub accel: Accel,
    /// Random numbers of the importance-sampled integrators.
    pub sampler: SamplerKind,
    /// How nee and mis sample their lights.
    pub light_sampling: LightSampling,
    /// How nee and mis choose the emissive triangle they sample.
    pub light_selection: LightSelection,
    /// The part of the `width` x `height` image to render (`--region`); `None`: all of it.
    /// Its pixels get exactly the values the full render gives them.
    pub region: Option<PixelRegion>,
    /// Side of the square tiles in which the render's part is put on the device one at a
    /// time (`--tile-size`); `None`: in one piece unless it would not fit the device
    /// (`region::automatic_tile_side`). Tiles never change the image.
    pub tile_size: Option<u32>,
    /// Adaptive sampling (`--noise-threshold`): pixels stop taking samples once their
    /// estimate is good enough, `spp` being the cap; `None`: every pixel takes every sample.
    pub noise_threshold: Option<NoiseThreshold>,
    /// Path guiding (`--guiding`, nee and mis only): a guide trained with this budget before
    /// the render's `spp` samples (`crate::guiding::training`); `None`: BSDF sampling alone.
    pub guiding: Option<GuideTraining>,
    /// A homogeneous medium filling the space outside closed refracting volumes
    /// (`--medium`; cosine, nee and mis only); `None`: a vacuum, and kernels without media.
    pub medium: Option<Medium>,
}

/// Russian roulette's start where none is given: from vertex 3, or never with path guiding.
/// Roulette from the throughput kills most of the paths a guide sends towards an opening
/// (their weight f cos / p is small where the guide's density is high): on
/// `scenes/opening.gltf` with 8 vertices it took away the guide's whole gain (relMSE
/// 0.0041 with it, 0.0010 without, at 256 spp), and on lavapipe it saved no time
/// (docs/guiding.md, "Russian roulette").
pub fn default_russian_roulette_start(guided: bool) -> u32 {
    if guided {
        0
    } else {
        3
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 512,
            height: 512,
            spp: 64,
            max_path_length: DEFAULT_MAX_PATH_LENGTH,
            seed: 0,
            pixel_filter: PixelFilter::Box,
            integrator: Integrator::PathTracing,
            samples_per_frame: 4,
            russian_roulette_start: default_russian_roulette_start(false),
            accel: Accel::Auto,
            sampler: SamplerKind::Pcg,
            light_sampling: LightSampling::SolidAngle,
            light_selection: LightSelection::Auto,
            region: None,
            tile_size: None,
            noise_threshold: None,
            guiding: None,
            medium: None,
        }
    }
}

impl RenderSettings {
    /// These settings with the sampler the integrator really uses: the workshop's
    /// integrators always draw PCG2D, so a render with one of them records and reports
    /// `pcg` whatever sampler was asked for (`vkpath render` and the Python package both
    /// call this).
    pub fn with_effective_sampler(self) -> RenderSettings {
        if self.integrator.is_importance_sampled() {
            self
        } else {
            RenderSettings {
                sampler: SamplerKind::Pcg,
                ..self
            }
        }
    }

    /// Checks every value's range; the error names the offending option.
    pub fn validate(&self) -> Result<()> {
        let bad = |message: String| Err(Error::InvalidSettings(message));
        if self.width == 0 || self.height == 0 {
            return bad(format!(
                "image size {}x{} is empty (--width/--height must be at least 1)",
                self.width, self.height
            ));
        }
        if self.width > MAX_IMAGE_SIDE || self.height > MAX_IMAGE_SIDE {
            return bad(format!(
                "image size {}x{} exceeds {MAX_IMAGE_SIDE} pixels per side",
                self.width, self.height
            ));
        }
        if self.spp == 0 || self.spp > MAX_SPP {
            return bad(format!("--spp {} is outside 1..={MAX_SPP}", self.spp));
        }
        if self.max_path_length == 0 || self.max_path_length > MAX_PATH_LENGTH_LIMIT {
            return bad(format!(
                "--max-path-length {} is outside 1..={MAX_PATH_LENGTH_LIMIT}",
                self.max_path_length
            ));
        }
        if self.samples_per_frame == 0 || self.samples_per_frame > 4096 {
            return bad(format!(
                "--samples-per-frame {} is outside 1..=4096",
                self.samples_per_frame
            ));
        }
        if let Some(region) = self.region {
            region.validate(self.width, self.height)?;
        }
        if self.tile_size == Some(0) {
            return bad("--tile-size 0: a tile needs at least one pixel a side".into());
        }
        if let Some(noise) = self.noise_threshold {
            noise.validate()?;
        }
        if let Some(training) = self.guiding {
            if !self.integrator.takes_light_samples() {
                return bad(format!(
                    "--guiding guides nee and mis, not --integrator {}",
                    self.integrator.name()
                ));
            }
            if training.samples == 0 || training.samples > MAX_SPP {
                return bad(format!(
                    "--guide-training-spp {} is outside 1..={MAX_SPP}",
                    training.samples
                ));
            }
        }
        if let Some(medium) = &self.medium {
            if !self.integrator.is_importance_sampled() {
                return bad(format!(
                    "--medium: --integrator {} renders no media: use cosine, nee or mis",
                    self.integrator.name()
                ));
            }
            medium
                .validate()
                .map_err(|error| Error::InvalidSettings(format!("--medium: {error}")))?;
        }
        Ok(())
    }

    /// The part of the image rendered: `region`, or the whole image.
    pub fn area(&self) -> PixelRegion {
        self.region
            .unwrap_or(PixelRegion::whole(self.width, self.height))
    }

    /// The training budget of a guided render with these settings when none is given:
    /// `GuideTraining::default_for` its spp and area.
    pub fn default_guide_training(&self) -> GuideTraining {
        let area = self.area();
        GuideTraining::default_for(self.spp, u64::from(area.width()) * u64::from(area.height()))
    }

    /// The training budget of a guided render with these settings: `samples` per pixel
    /// where given (`--guide-training-spp`), else `default_guide_training`.
    pub fn guide_training(&self, samples: Option<u32>) -> GuideTraining {
        samples.map_or(self.default_guide_training(), |samples| GuideTraining {
            samples,
        })
    }

    /// Width / height.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// The path tracer's specialization constants for these settings, as
    /// (`SPEC_*` id, value).
    pub fn specialization(&self) -> Vec<(u32, u32)> {
        let mut constants = vec![
            (contract::SPEC_SAMPLE_COUNT, self.samples_per_frame),
            (contract::SPEC_MAX_PATH_LENGTH, self.max_path_length),
            (
                contract::SPEC_PIXEL_FILTER,
                self.pixel_filter.spec_constant(),
            ),
            (contract::SPEC_INTEGRATOR, self.integrator.spec_constant()),
            (
                contract::SPEC_RUSSIAN_ROULETTE_START,
                self.russian_roulette_start,
            ),
            (contract::SPEC_SAMPLER, self.sampler.spec_constant()),
            (
                contract::SPEC_LIGHT_SAMPLING,
                self.light_sampling.spec_constant(),
            ),
        ];
        // Without a medium none: the kernel's default compiles media out, bit for bit
        if let Some(medium) = &self.medium {
            constants.extend(medium.specialization());
        }
        constants
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_out_of_range_values() {
        let ok = RenderSettings::default();
        assert!(ok.validate().is_ok());
        for bad in [
            RenderSettings {
                width: 0,
                ..ok.clone()
            },
            RenderSettings {
                height: MAX_IMAGE_SIDE + 1,
                ..ok.clone()
            },
            RenderSettings {
                spp: 0,
                ..ok.clone()
            },
            RenderSettings {
                spp: MAX_SPP + 1,
                ..ok.clone()
            },
            RenderSettings {
                max_path_length: 0,
                ..ok.clone()
            },
            RenderSettings {
                samples_per_frame: 0,
                ..ok.clone()
            },
        ] {
            let message = bad.validate().unwrap_err().to_string();
            assert!(message.starts_with("invalid settings"), "{message}");
        }
    }
}
