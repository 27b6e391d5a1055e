//! The probe kernels: which workshop function each evaluates, its GLSL file, its kernel
//! declaration (`crate::kernels`) and the sizes of its input and output structs, and the compute pipeline that runs
//! one (the embedded reference or SPIR-V compiled at run time, e.g. with a user's functions).

use std::sync::Arc;

use crate::contract;
use crate::error::Result;
use crate::kernels::{self, Kernel};
use crate::probe::layout::{
    DirectIlluminationInput, DirectionOutput, IntersectionOutput, MeshIntersectionOutput,
    PrimaryRayInput, RadianceOutput, RandomNumbersInput, RandomNumbersOutput, RayInput,
    RayRadianceInput, RayTriangleInput, SamplerInput,
};
use crate::probe::runner::Probe;
use crate::shaders;
use crate::vk::Context;

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

    /// The kernel's declaration (`crate::kernels`).
    pub fn kernel(self) -> &'static Kernel {
        match self {
            ProbeKind::GetRandomNumbers => &kernels::PROBE_GET_RANDOM_NUMBERS,
            ProbeKind::SampleSphere => &kernels::PROBE_SAMPLE_SPHERE,
            ProbeKind::SampleHemisphere => &kernels::PROBE_SAMPLE_HEMISPHERE,
            ProbeKind::SampleSphereSphericalCoordinates => {
                &kernels::PROBE_SAMPLE_SPHERE_SPHERICAL_COORDINATES
            }
            ProbeKind::RayTriangleIntersection => &kernels::PROBE_RAY_TRIANGLE_INTERSECTION,
            ProbeKind::RayMeshIntersection => &kernels::PROBE_RAY_MESH_INTERSECTION,
            ProbeKind::GetPrimaryRayDirection => &kernels::PROBE_GET_PRIMARY_RAY_DIRECTION,
            ProbeKind::ComputeDirectIllumination => &kernels::PROBE_COMPUTE_DIRECT_ILLUMINATION,
            ProbeKind::GetRayRadiance => &kernels::PROBE_GET_RAY_RADIANCE,
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

/// A probe kernel ready to run: its pipeline and what it evaluates.
pub struct ProbePipeline {
    kind: ProbeKind,
    pub(crate) probe: Probe,
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
        let spirv = kind.kernel().builds()[0].embedded_spirv()?;
        ProbePipeline::from_spirv(context, kind, &spirv, max_path_length)
    }

    /// The kernel from SPIR-V compiled elsewhere (e.g. at run time with a user's functions,
    /// `crate::check`), which must declare `kind`'s structs and the probe bindings.
    pub fn from_spirv(
        context: &Arc<Context>,
        kind: ProbeKind,
        spirv: &[u32],
        max_path_length: u32,
    ) -> Result<ProbePipeline> {
        let probe = Probe::new(
            context,
            kind.kernel(),
            spirv,
            &[(contract::SPEC_MAX_PATH_LENGTH, max_path_length)],
            kind.function_name(),
        )?;
        Ok(ProbePipeline { kind, probe })
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
            assert!(
                kind.kernel().builds()[0].embedded_spirv().is_ok(),
                "{kind:?}"
            );
            assert_eq!(kind.kernel().source, kind.source_file());
            assert_eq!(kind.input_size() % 16, 0);
            assert_eq!(kind.output_size() % 16, 0);
        }
    }
}
