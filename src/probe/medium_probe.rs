//! The medium probe (`glsl/probe_medium.comp`): runs a homogeneous medium's functions
//! (`glsl/medium.glsl`) and its phase function (`glsl/phase_function.glsl`) on a buffer of
//! inputs, so that tests can compare them with their Rust twins (`crate::cpu::medium`,
//! `crate::cpu::phase_function`). It binds only its inputs and outputs (no scene);
//! `MediumProbeOutput::cpu` is the kernel's `main` on the CPU.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3, Vec4};

use crate::cpu::medium::{
    get_medium_distance_density, get_medium_passing_probability, get_medium_passing_weight,
    get_medium_scattering_weight, get_medium_transmittance, sample_medium_distance,
};
use crate::cpu::phase_function::{
    get_henyey_greenstein, get_phase_function, get_phase_function_density, sample_phase_function,
};
use crate::error::Result;
use crate::kernels;
use crate::medium::Medium;
use crate::probe::runner::Probe;
use crate::vk::Context;

/// `probe_input_t` of `glsl/probe_medium.comp` (80 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MediumProbeInput {
    /// rgb: sigma_a; a: g.
    pub absorption_anisotropy: [f32; 4],
    /// rgb: sigma_s; a: the distance of the transmittance, densities and weights.
    pub scattering_distance: [f32; 4],
    /// xyz: unit view direction, world space; w: 0.
    pub view: [f32; 4],
    /// xyz: unit direction of `get_phase_function`; w: 0.
    pub direction: [f32; 4],
    /// xy: the numbers of `sample_medium_distance`; zw: of `sample_phase_function`.
    pub random_numbers: [f32; 4],
}

impl MediumProbeInput {
    /// The input that evaluates every function with these arguments.
    pub fn new(
        medium: &Medium,
        distance: f32,
        view: Vec3,
        direction: Vec3,
        distance_randoms: Vec2,
        phase_randoms: Vec2,
    ) -> MediumProbeInput {
        MediumProbeInput {
            absorption_anisotropy: medium.absorption.extend(medium.anisotropy).into(),
            scattering_distance: medium.scattering.extend(distance).into(),
            view: view.extend(0.0).into(),
            direction: direction.extend(0.0).into(),
            random_numbers: [
                distance_randoms.x,
                distance_randoms.y,
                phase_randoms.x,
                phase_randoms.y,
            ],
        }
    }

    /// The medium, as the kernel unpacks it into a `medium_t`.
    pub fn medium(&self) -> Medium {
        Medium {
            absorption: Vec4::from_array(self.absorption_anisotropy).truncate(),
            scattering: Vec4::from_array(self.scattering_distance).truncate(),
            anisotropy: self.absorption_anisotropy[3],
        }
    }

    /// The distance.
    pub fn distance(&self) -> f32 {
        self.scattering_distance[3]
    }

    /// The view direction.
    pub fn view(&self) -> Vec3 {
        Vec4::from_array(self.view).truncate()
    }

    /// The direction of `get_phase_function`.
    pub fn direction(&self) -> Vec3 {
        Vec4::from_array(self.direction).truncate()
    }
}

/// `probe_output_t` of `glsl/probe_medium.comp` (80 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MediumProbeOutput {
    /// x: `get_phase_function`; y: its density; z: `get_henyey_greenstein(dot(view,
    /// direction), g)`; w: `sample_medium_distance`.
    pub phase: [f32; 4],
    /// xyz: `sample_phase_function`; w: `get_phase_function_density` there.
    pub sampled: [f32; 4],
    /// rgb: `get_medium_transmittance`; a: `get_medium_distance_density`.
    pub transmittance: [f32; 4],
    /// rgb: `get_medium_scattering_weight`; a: `get_medium_passing_probability`.
    pub scattering: [f32; 4],
    /// rgb: `get_medium_passing_weight`; a: 0.
    pub passing: [f32; 4],
}

impl MediumProbeOutput {
    /// What the kernel computes for `input`, computed by the Rust twins.
    pub fn cpu(input: &MediumProbeInput) -> MediumProbeOutput {
        let medium = input.medium();
        let g = medium.anisotropy;
        let distance = input.distance();
        let (view, direction) = (input.view(), input.direction());
        let [u0, u1, u2, u3] = input.random_numbers;
        let sampled = sample_phase_function(Vec2::new(u2, u3), view, g);
        MediumProbeOutput {
            phase: [
                get_phase_function(view, direction, g),
                get_phase_function_density(view, direction, g),
                get_henyey_greenstein(view.dot(direction), g),
                sample_medium_distance(&medium, Vec2::new(u0, u1)),
            ],
            sampled: sampled
                .extend(get_phase_function_density(view, sampled, g))
                .into(),
            transmittance: get_medium_transmittance(&medium, distance)
                .extend(get_medium_distance_density(&medium, distance))
                .into(),
            scattering: get_medium_scattering_weight(&medium, distance)
                .extend(get_medium_passing_probability(&medium, distance))
                .into(),
            passing: get_medium_passing_weight(&medium, distance)
                .extend(0.0)
                .into(),
        }
    }

    /// The output's floats in one list, in field order (for comparisons).
    pub fn values(&self) -> [f32; 20] {
        let mut values = [0.0; 20];
        for (k, field) in [
            self.phase,
            self.sampled,
            self.transmittance,
            self.scattering,
            self.passing,
        ]
        .iter()
        .enumerate()
        {
            values[4 * k..4 * k + 4].copy_from_slice(field);
        }
        values
    }

    /// The direction `sample_phase_function` returned.
    pub fn sampled(&self) -> Vec3 {
        Vec4::from_array(self.sampled).truncate()
    }
}

/// Runs the medium probe.
pub struct MediumProbeRunner {
    probe: Probe,
}

impl MediumProbeRunner {
    /// Creates the kernel's pipeline.
    pub fn new(context: &Arc<Context>) -> Result<MediumProbeRunner> {
        Ok(MediumProbeRunner {
            probe: Probe::embedded(context, &kernels::PROBE_MEDIUM, &[], "the medium functions")?,
        })
    }

    /// Evaluates the medium's functions on every input and returns the outputs in order.
    pub fn run(&self, inputs: &[MediumProbeInput]) -> Result<Vec<MediumProbeOutput>> {
        self.probe.run(|_| None, inputs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{offset_of, size_of};

    #[test]
    fn structs_match_the_std430_declarations() {
        // five vec4 each
        assert_eq!(size_of::<MediumProbeInput>(), 80);
        assert_eq!(offset_of!(MediumProbeInput, scattering_distance), 16);
        assert_eq!(offset_of!(MediumProbeInput, view), 32);
        assert_eq!(offset_of!(MediumProbeInput, direction), 48);
        assert_eq!(offset_of!(MediumProbeInput, random_numbers), 64);
        assert_eq!(size_of::<MediumProbeOutput>(), 80);
        assert_eq!(offset_of!(MediumProbeOutput, sampled), 16);
        assert_eq!(offset_of!(MediumProbeOutput, transmittance), 32);
        assert_eq!(offset_of!(MediumProbeOutput, scattering), 48);
        assert_eq!(offset_of!(MediumProbeOutput, passing), 64);
    }

    #[test]
    fn inputs_round_trip_their_arguments() {
        let medium = Medium {
            absorption: Vec3::new(0.1, 0.2, 0.3),
            scattering: Vec3::new(1.0, 2.0, 3.0),
            anisotropy: -0.4,
        };
        let input = MediumProbeInput::new(
            &medium,
            2.5,
            Vec3::X,
            Vec3::Y,
            Vec2::new(0.1, 0.2),
            Vec2::new(0.3, 0.4),
        );
        assert_eq!(input.medium(), medium);
        assert_eq!(input.distance(), 2.5);
        assert_eq!((input.view(), input.direction()), (Vec3::X, Vec3::Y));
    }
}
