//! The probe kernels: which workshop function each evaluates, its GLSL file, its embedded
//! SPIR-V and the sizes of its input and output structs, and the compute pipeline that runs
//! one (the embedded reference or SPIR-V compiled at run time, e.g. with a user's functions).

use std::sync::Arc;

use ash::vk;

use crate::contract;
use crate::error::Result;
use crate::probe::layout::{
    DirectIlluminationInput, DirectionOutput, IntersectionOutput, MeshIntersectionOutput,
    PrimaryRayInput, ProbePushConstants, RadianceOutput, RandomNumbersInput, RandomNumbersOutput,
    RayInput, RayRadianceInput, RayTriangleInput, SamplerInput,
};
use crate::shaders;
use crate::vk::spirv_words;
use crate::vk::{ComputePipeline, Context};

/// One probe kernel, `glsl/probe_<function>.comp`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ProbeKind {
    /// `get_random_numbers` (PCG2D): `RandomNumbersInput` -> `RandomNumbersOutput`.
    GetRandomNumbers,
    /// `sample_sphere`: `SamplerInput` -> `DirectionOutput`.
    SampleSphere,
    /// `sample_hemisphere`: `SamplerInput` -> `DirectionOutput`.
    SampleHemisphere,
    /// The naive `sample_sphere_spherical_coordinates`, defined in its probe kernel only
    /// (test-only): `SamplerInput` -> `DirectionOutput`.
    SampleSphereSphericalCoordinates,
    /// `ray_triangle_intersection`: `RayTriangleInput` -> `IntersectionOutput`.
    RayTriangleIntersection,
    /// `ray_mesh_intersection` with the bound scene: `RayInput` -> `MeshIntersectionOutput`.
    RayMeshIntersection,
    /// `get_primary_ray_direction`: `PrimaryRayInput` -> `DirectionOutput`.
    GetPrimaryRayDirection,
    /// `compute_direct_illumination` with the bound scene: `DirectIlluminationInput` ->
    /// `RadianceOutput`.
    ComputeDirectIllumination,
    /// `get_ray_radiance` with the bound scene: `RayRadianceInput` -> `RadianceOutput`.
    GetRayRadiance,
}

impl ProbeKind {
    /// Every probe kernel.
    pub const ALL: [ProbeKind; 9] = [
        ProbeKind::GetRandomNumbers,
        ProbeKind::SampleSphere,
        ProbeKind::SampleHemisphere,
        ProbeKind::SampleSphereSphericalCoordinates,
        ProbeKind::RayTriangleIntersection,
        ProbeKind::RayMeshIntersection,
        ProbeKind::GetPrimaryRayDirection,
        ProbeKind::ComputeDirectIllumination,
        ProbeKind::GetRayRadiance,
    ];

    /// The GLSL name of the function the kernel evaluates.
    pub fn function_name(self) -> &'static str {
        match self {
            ProbeKind::GetRandomNumbers => "get_random_numbers",
            ProbeKind::SampleSphere => "sample_sphere",
            ProbeKind::SampleHemisphere => "sample_hemisphere",
            ProbeKind::SampleSphereSphericalCoordinates => "sample_sphere_spherical_coordinates",
            ProbeKind::RayTriangleIntersection => "ray_triangle_intersection",
            ProbeKind::RayMeshIntersection => "ray_mesh_intersection",
            ProbeKind::GetPrimaryRayDirection => "get_primary_ray_direction",
            ProbeKind::ComputeDirectIllumination => "compute_direct_illumination",
            ProbeKind::GetRayRadiance => "get_ray_radiance",
        }
    }

    /// The kernel's file in `glsl/` (and in `shaders::GLSL_SOURCES`).
    pub fn source_file(self) -> String {
        format!("probe_{}.comp", self.function_name())
    }

    /// The kernel's text as embedded at build time.
    pub fn source(self) -> Option<&'static str> {
        let file = self.source_file();
        shaders::GLSL_SOURCES
            .iter()
            .find(|(name, _)| *name == file)
            .map(|(_, text)| *text)
    }

    /// The kernel compiled at build time with the reference functions.
    pub fn embedded_spirv(self) -> &'static [u8] {
        match self {
            ProbeKind::GetRandomNumbers => shaders::PROBE_GET_RANDOM_NUMBERS,
            ProbeKind::SampleSphere => shaders::PROBE_SAMPLE_SPHERE,
            ProbeKind::SampleHemisphere => shaders::PROBE_SAMPLE_HEMISPHERE,
            ProbeKind::SampleSphereSphericalCoordinates => {
                shaders::PROBE_SAMPLE_SPHERE_SPHERICAL_COORDINATES
            }
            ProbeKind::RayTriangleIntersection => shaders::PROBE_RAY_TRIANGLE_INTERSECTION,
            ProbeKind::RayMeshIntersection => shaders::PROBE_RAY_MESH_INTERSECTION,
            ProbeKind::GetPrimaryRayDirection => shaders::PROBE_GET_PRIMARY_RAY_DIRECTION,
            ProbeKind::ComputeDirectIllumination => shaders::PROBE_COMPUTE_DIRECT_ILLUMINATION,
            ProbeKind::GetRayRadiance => shaders::PROBE_GET_RAY_RADIANCE,
        }
    }

    /// Size in bytes of the kernel's `probe_input_t`.
    pub fn input_size(self) -> usize {
        use std::mem::size_of;
        match self {
            ProbeKind::GetRandomNumbers => size_of::<RandomNumbersInput>(),
            ProbeKind::SampleSphere
            | ProbeKind::SampleHemisphere
            | ProbeKind::SampleSphereSphericalCoordinates => size_of::<SamplerInput>(),
            ProbeKind::RayTriangleIntersection => size_of::<RayTriangleInput>(),
            ProbeKind::RayMeshIntersection => size_of::<RayInput>(),
            ProbeKind::GetPrimaryRayDirection => size_of::<PrimaryRayInput>(),
            ProbeKind::ComputeDirectIllumination => size_of::<DirectIlluminationInput>(),
            ProbeKind::GetRayRadiance => size_of::<RayRadianceInput>(),
        }
    }

    /// Size in bytes of the kernel's `probe_output_t`.
    pub fn output_size(self) -> usize {
        use std::mem::size_of;
        match self {
            ProbeKind::GetRandomNumbers => size_of::<RandomNumbersOutput>(),
            ProbeKind::SampleSphere
            | ProbeKind::SampleHemisphere
            | ProbeKind::SampleSphereSphericalCoordinates
            | ProbeKind::GetPrimaryRayDirection => size_of::<DirectionOutput>(),
            ProbeKind::RayTriangleIntersection => size_of::<IntersectionOutput>(),
            ProbeKind::RayMeshIntersection => size_of::<MeshIntersectionOutput>(),
            ProbeKind::ComputeDirectIllumination | ProbeKind::GetRayRadiance => {
                size_of::<RadianceOutput>()
            }
        }
    }
}

/// The descriptor bindings of every probe kernel (`glsl/probe_common.glsl`).
pub(crate) fn probe_bindings() -> [(u32, vk::DescriptorType); 5] {
    [
        (
            contract::BINDING_TRIANGLES,
            vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
        ),
        (
            contract::BINDING_RENDER_UNIFORMS,
            vk::DescriptorType::UNIFORM_BUFFER,
        ),
        (
            contract::PROBE_BINDING_INPUTS,
            vk::DescriptorType::STORAGE_BUFFER,
        ),
        (
            contract::PROBE_BINDING_OUTPUTS,
            vk::DescriptorType::STORAGE_BUFFER,
        ),
        (
            contract::PROBE_BINDING_FLAGS,
            vk::DescriptorType::STORAGE_BUFFER,
        ),
    ]
}

/// A probe kernel ready to run: its compute pipeline and what it evaluates.
pub struct ProbePipeline {
    kind: ProbeKind,
    pub(crate) pipeline: ComputePipeline,
}

impl ProbePipeline {
    /// The kernel as compiled at build time, with the reference (workshop) functions.
    /// \param max_path_length `MAX_PATH_LENGTH` for `get_ray_radiance` (any value >= 1 for
    ///        the other kernels)
    pub fn reference(
        context: &Arc<Context>,
        kind: ProbeKind,
        max_path_length: u32,
    ) -> Result<ProbePipeline> {
        ProbePipeline::from_spirv(
            context,
            kind,
            &spirv_words(kind.embedded_spirv())?,
            max_path_length,
        )
    }

    /// The kernel from SPIR-V compiled elsewhere (e.g. at run time with a user's functions,
    /// `crate::check`), which must declare `kind`'s structs and the probe bindings.
    pub fn from_spirv(
        context: &Arc<Context>,
        kind: ProbeKind,
        spirv: &[u32],
        max_path_length: u32,
    ) -> Result<ProbePipeline> {
        let pipeline = ComputePipeline::new(
            context,
            spirv,
            &probe_bindings(),
            std::mem::size_of::<ProbePushConstants>() as u32,
            &[(contract::SPEC_MAX_PATH_LENGTH, max_path_length)],
        )?;
        Ok(ProbePipeline { kind, pipeline })
    }

    /// What the kernel evaluates.
    pub fn kind(&self) -> ProbeKind {
        self.kind
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_has_its_source_and_spirv() {
        for kind in ProbeKind::ALL {
            let source = kind.source().expect("the probe's GLSL is embedded");
            assert!(
                source.contains(&format!("{}(", kind.function_name())),
                "{kind:?}"
            );
            assert!(
                source.contains("#include \"user_functions.glsl\""),
                "{kind:?} must include the user's functions"
            );
            assert!(spirv_words(kind.embedded_spirv()).is_ok(), "{kind:?}");
            assert_eq!(kind.input_size() % 16, 0);
            assert_eq!(kind.output_size() % 16, 0);
        }
    }
}
