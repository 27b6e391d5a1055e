//! The workshop's exercises as its ShaderToy framework shows them (`vkpath exercise`): the
//! unshaded ray tracer of Part 1, the 512-sample displays of Exercises 4 and 5 (and the
//! slides' "too many samples at the top" counter-example), direct illumination (Exercise 6)
//! and path tracing (Exercise 7) in the workshop's Cornell box; and, beyond the workshop, the
//! same display of `sample_brdf` for a glTF material.

pub mod display;
pub mod guide_cell;
pub mod view;

pub use display::{
    render_brdf_sample_display, render_direction_display, render_sample_display,
    render_sample_display_with,
};
pub use guide_cell::{render_guide_cell_display, GuideCellSetup, GuideCellView};
pub use view::{BrdfDisplaySetup, ExerciseSampler};

use crate::render::settings::{Integrator, PixelFilter, RenderSettings};

/// The settings the workshop's ShaderToy framework renders its exercises with, and the
/// defaults of `vkpath exercise`: one frame of SAMPLE_COUNT = 1 sample per pixel at the pixel
/// centres, 256 x 256 pixels (quick even on a CPU device such as lavapipe). The integrator is
/// the exercise's own (`Exercise::kind`).
pub fn workshop_frame_settings() -> RenderSettings {
    RenderSettings {
        width: 256,
        height: 256,
        spp: 1,
        samples_per_frame: 1,
        pixel_filter: PixelFilter::Center,
        ..RenderSettings::default()
    }
}

/// One of the workshop's pictures; `vkpath exercise` names them in kebab case.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Exercise {
    /// Part 1: ray tracing, the albedo of the first hit, unshaded.
    #[cfg_attr(
        feature = "cli",
        value(
            help = "Part 1: unshaded ray tracing of the Cornell box (the albedo of the first hit)"
        )
    )]
    RayTracing,
    /// Exercise 4: 512 samples of `sample_sphere` on the sphere.
    #[cfg_attr(
        feature = "cli",
        value(help = "Exercise 4: 512 samples of sample_sphere() drawn on the sphere")
    )]
    SampleSphere,
    /// Exercise 5: 512 samples of `sample_hemisphere` (normal +z) on the sphere.
    #[cfg_attr(
        feature = "cli",
        value(
            help = "Exercise 5: 512 samples of sample_hemisphere() (normal +z) drawn on the sphere"
        )
    )]
    SampleHemisphere,
    /// The slide "Non-uniform sphere sampling": 512 samples of the naive spherical-
    /// coordinates mapping phi = 2 pi u_0, theta = pi u_1, crowded at the top.
    #[cfg_attr(
        feature = "cli",
        value(help = "The naive spherical-coordinates sampler: too many samples at the top")
    )]
    SphericalCoords,
    /// Exercise 6: emission plus one-sample direct illumination.
    #[cfg_attr(
        feature = "cli",
        value(
            help = "Exercise 6: direct illumination (one frame of --sample-count samples by default)"
        )
    )]
    DirectIllumination,
    /// Exercise 7: path tracing with uniform hemisphere sampling.
    #[cfg_attr(
        feature = "cli",
        value(help = "Exercise 7: path tracing (one frame of --sample-count samples by default)")
    )]
    PathTracing,
    /// Beyond the workshop: 512 samples of `sample_brdf` (normal +z) on the sphere, for the
    /// material and view angle of the command line.
    #[cfg_attr(
        feature = "cli",
        value(
            help = "512 samples of sample_brdf() (normal +z) for --metallic, --roughness, --view-angle ..."
        )
    )]
    BrdfSamples,
    /// Beyond the workshop: path guiding's learned distribution at one point of a scene
    /// (512 samples of its cell) next to the BSDF's (512 cosine-weighted samples).
    #[cfg_attr(
        feature = "cli",
        value(
            help = "Path guiding: 512 samples of the guide's cell at --pixel next to 512 of the BSDF (--scene, --guide-training-spp)"
        )
    )]
    GuideCell,
}

/// What an exercise draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExerciseKind {
    /// A render of the Cornell box with this integrator.
    Render(Integrator),
    /// The sample display of this sampler.
    Samples(ExerciseSampler),
    /// A guide's cell next to the BSDF (`render_guide_cell_display`).
    GuideCell,
}

impl Exercise {
    /// Every exercise, in the workshop's order.
    pub const ALL: [Exercise; 8] = [
        Exercise::RayTracing,
        Exercise::SampleSphere,
        Exercise::SampleHemisphere,
        Exercise::SphericalCoords,
        Exercise::DirectIllumination,
        Exercise::PathTracing,
        Exercise::BrdfSamples,
        Exercise::GuideCell,
    ];

    /// Whether the exercise renders the Cornell box or displays samples, and which.
    pub fn kind(self) -> ExerciseKind {
        match self {
            Exercise::RayTracing => ExerciseKind::Render(Integrator::RayTracing),
            Exercise::SampleSphere => ExerciseKind::Samples(ExerciseSampler::Sphere),
            Exercise::SampleHemisphere => ExerciseKind::Samples(ExerciseSampler::Hemisphere),
            Exercise::SphericalCoords => {
                ExerciseKind::Samples(ExerciseSampler::SphericalCoordinates)
            }
            Exercise::DirectIllumination => ExerciseKind::Render(Integrator::DirectIllumination),
            Exercise::PathTracing => ExerciseKind::Render(Integrator::PathTracing),
            Exercise::BrdfSamples => ExerciseKind::Samples(ExerciseSampler::Brdf),
            Exercise::GuideCell => ExerciseKind::GuideCell,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_integrator_and_sampler_has_an_exercise() {
        let kinds: Vec<ExerciseKind> = Exercise::ALL.iter().map(|e| e.kind()).collect();
        for integrator in [
            Integrator::RayTracing,
            Integrator::DirectIllumination,
            Integrator::PathTracing,
        ] {
            assert!(kinds.contains(&ExerciseKind::Render(integrator)));
        }
        for sampler in [
            ExerciseSampler::Sphere,
            ExerciseSampler::Hemisphere,
            ExerciseSampler::SphericalCoordinates,
            ExerciseSampler::Brdf,
        ] {
            assert!(kinds.contains(&ExerciseKind::Samples(sampler)));
        }
    }
}
