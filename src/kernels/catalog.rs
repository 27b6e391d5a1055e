//! Every kernel of `glsl/`, declared once: source, binding table, specialization constants
//! and push constants. Its builds are those of `builds`; the tests check each declaration
//! against the SPIR-V of every build (`reflect`) and that every `glsl/*.comp` is declared.

use std::mem::size_of;

use crate::contract as c;
use crate::kernels::bindings;
use crate::kernels::push_constants::{
    FramePushConstants, ProbePushConstants, SampleDisplayPushConstants,
};
use crate::kernels::{Kernel, SpecConstants};

/// The specialization constants of `glsl/scene.glsl` and `glsl/constant_triangles.glsl`,
/// which every kernel that traces rays declares.
const SCENE_SPEC: [SpecConstants; 4] = [
    SpecConstants::one(c::SPEC_CONSTANT_TRIANGLE_COUNT),
    SpecConstants {
        first_id: c::SPEC_CONSTANT_TRIANGLES,
        count: 9 * c::CONSTANT_TRIANGLE_CAPACITY,
    },
    SpecConstants::one(c::SPEC_SCENE_HAS_ALPHA),
    SpecConstants::one(c::SPEC_MOTION_STEPS),
];

/// The progressive path tracer (`crate::render::Renderer`), in the builds of
/// `builds::EXTRA_BUILDS` and its plain one; which of them a render takes, and with which
/// scene constants, the variant room decides (`crate::kernels::variant`).
pub static PATH_TRACER: Kernel = Kernel {
    source: "path_tracer.comp",
    bindings: bindings::PATH_TRACER,
    specialization: &[
        SCENE_SPEC[0],
        SCENE_SPEC[1],
        SCENE_SPEC[2],
        SCENE_SPEC[3],
        SpecConstants::one(c::SPEC_SAMPLE_COUNT),
        SpecConstants::one(c::SPEC_MAX_PATH_LENGTH),
        SpecConstants::one(c::SPEC_PIXEL_FILTER),
        SpecConstants::one(c::SPEC_INTEGRATOR),
        SpecConstants::one(c::SPEC_RUSSIAN_ROULETTE_START),
        SpecConstants::one(c::SPEC_SAMPLER),
        SpecConstants::one(c::SPEC_LIGHT_SAMPLING),
        SpecConstants::one(c::SPEC_LIGHT_SELECTION),
        SpecConstants::one(c::SPEC_GUIDING),
        SpecConstants::one(c::SPEC_LOOP_LIMIT),
        SpecConstants::one(c::SPEC_LOOPS_PER_SAMPLE),
        SpecConstants::one(c::SPEC_LOOPS_PER_RAY),
        SpecConstants::one(c::SPEC_LIGHT_SEARCHES_PER_RAY),
        SpecConstants::one(c::SPEC_TRIANGLE_LOOPS_PER_RAY),
        SpecConstants::one(c::SPEC_SCENE_TEXTURE_SLOTS),
        SpecConstants::one(c::SPEC_SCENE_HAS_LAYERS),
        SpecConstants::one(c::SPEC_SCENE_HAS_ENVIRONMENT),
        SpecConstants::one(c::SPEC_SCENE_HAS_PUNCTUAL_LIGHTS),
        SpecConstants::one(c::SPEC_SCENE_SAMPLES_ENVIRONMENT),
        SpecConstants::one(c::SPEC_SCENE_HAS_EMISSIVE_TRIANGLES),
        SpecConstants::one(c::SPEC_SCENE_HAS_SPECULAR),
        SpecConstants::one(c::SPEC_SCENE_VERTEX_ATTRIBUTES),
        SpecConstants::one(c::SPEC_BVH_LAYOUT),
        SpecConstants::one(c::SPEC_THIN_LENS),
        SpecConstants::one(c::SPEC_MEDIUM),
        SpecConstants {
            first_id: c::SPEC_MEDIUM_COEFFICIENTS,
            count: c::MEDIUM_COEFFICIENT_COUNT,
        },
        SpecConstants::one(c::SPEC_SCENE_HAS_VOLUME_SCATTER),
    ],
    push_constant_size: size_of::<FramePushConstants>() as u32,
};

/// The specialization constants of the probes of the workshop's functions (and of the
/// sample display, which includes the same files).
const SCENE_PROBE_SPEC: [SpecConstants; 5] = [
    SCENE_SPEC[0],
    SCENE_SPEC[1],
    SCENE_SPEC[2],
    SCENE_SPEC[3],
    SpecConstants::one(c::SPEC_MAX_PATH_LENGTH),
];

/// A probe of one workshop function (`crate::probe::ProbeKind`, `glsl/probe_common.glsl`).
const fn scene_probe(source: &'static str) -> Kernel {
    Kernel {
        source,
        bindings: bindings::SCENE_PROBE,
        specialization: &SCENE_PROBE_SPEC,
        push_constant_size: size_of::<ProbePushConstants>() as u32,
    }
}

/// `glsl/probe_get_random_numbers.comp`.
pub static PROBE_GET_RANDOM_NUMBERS: Kernel = scene_probe("probe_get_random_numbers.comp");
/// `glsl/probe_sample_sphere.comp`.
pub static PROBE_SAMPLE_SPHERE: Kernel = scene_probe("probe_sample_sphere.comp");
/// `glsl/probe_sample_hemisphere.comp`.
pub static PROBE_SAMPLE_HEMISPHERE: Kernel = scene_probe("probe_sample_hemisphere.comp");
/// `glsl/probe_sample_sphere_spherical_coordinates.comp`.
pub static PROBE_SAMPLE_SPHERE_SPHERICAL_COORDINATES: Kernel =
    scene_probe("probe_sample_sphere_spherical_coordinates.comp");
/// `glsl/probe_ray_triangle_intersection.comp`.
pub static PROBE_RAY_TRIANGLE_INTERSECTION: Kernel =
    scene_probe("probe_ray_triangle_intersection.comp");
/// `glsl/probe_ray_mesh_intersection.comp`.
pub static PROBE_RAY_MESH_INTERSECTION: Kernel = scene_probe("probe_ray_mesh_intersection.comp");
/// `glsl/probe_get_primary_ray_direction.comp`.
pub static PROBE_GET_PRIMARY_RAY_DIRECTION: Kernel =
    scene_probe("probe_get_primary_ray_direction.comp");
/// `glsl/probe_compute_direct_illumination.comp`.
pub static PROBE_COMPUTE_DIRECT_ILLUMINATION: Kernel =
    scene_probe("probe_compute_direct_illumination.comp");
/// `glsl/probe_get_ray_radiance.comp`.
pub static PROBE_GET_RAY_RADIANCE: Kernel = scene_probe("probe_get_ray_radiance.comp");

/// The glTF BRDF's probe (`crate::probe::brdf_probe`).
pub static PROBE_BRDF: Kernel = Kernel {
    source: "probe_brdf.comp",
    bindings: bindings::BRDF_PROBE,
    specialization: &[],
    push_constant_size: size_of::<ProbePushConstants>() as u32,
};

/// The medium's probe (`crate::probe::medium_probe`): inputs and outputs only, as the
/// BRDF's.
pub static PROBE_MEDIUM: Kernel = Kernel {
    source: "probe_medium.comp",
    bindings: bindings::BRDF_PROBE,
    specialization: &[],
    push_constant_size: size_of::<ProbePushConstants>() as u32,
};

/// The texture functions' probe (`crate::probe::texture_probe`).
pub static PROBE_SAMPLE_TEXTURE: Kernel = Kernel {
    source: "probe_sample_texture.comp",
    bindings: bindings::TEXTURE_PROBE,
    specialization: &[],
    push_constant_size: size_of::<ProbePushConstants>() as u32,
};

/// The punctual lights' probe (`crate::probe::punctual_probe`).
pub static PROBE_PUNCTUAL_LIGHTS: Kernel = Kernel {
    source: "probe_punctual_lights.comp",
    bindings: bindings::PUNCTUAL_LIGHTS_PROBE,
    specialization: &[],
    push_constant_size: size_of::<ProbePushConstants>() as u32,
};

/// The light tree's probe (`crate::probe::light_tree_probe`).
pub static PROBE_LIGHT_TREE: Kernel = Kernel {
    source: "probe_light_tree.comp",
    bindings: bindings::LIGHT_TREE_PROBE,
    specialization: &[],
    push_constant_size: size_of::<ProbePushConstants>() as u32,
};

/// The guide's probe (`crate::probe::guiding_probe`).
pub static PROBE_GUIDING: Kernel = Kernel {
    source: "probe_guiding.comp",
    bindings: bindings::GUIDING_PROBE,
    specialization: &[],
    push_constant_size: size_of::<ProbePushConstants>() as u32,
};

/// The surface functions' probe (`crate::probe::surface_probe`).
pub static PROBE_SURFACE: Kernel = Kernel {
    source: "probe_surface.comp",
    bindings: bindings::SURFACE_PROBE,
    specialization: &[
        SCENE_SPEC[0],
        SCENE_SPEC[1],
        SCENE_SPEC[2],
        SCENE_SPEC[3],
        SpecConstants::one(c::SPEC_SCENE_TEXTURE_SLOTS),
        SpecConstants::one(c::SPEC_SCENE_HAS_LAYERS),
        SpecConstants::one(c::SPEC_SCENE_HAS_SPECULAR),
        SpecConstants::one(c::SPEC_SCENE_VERTEX_ATTRIBUTES),
    ],
    push_constant_size: size_of::<ProbePushConstants>() as u32,
};

/// The BVH traversal's probe (`tests/bvh_gpu.rs`). It reads no push constants: every
/// dispatch starts at its first ray (`crate::probe::Probe` runs it one dispatch per chunk).
pub static PROBE_BVH: Kernel = Kernel {
    source: "probe_bvh.comp",
    bindings: bindings::BVH_PROBE,
    specialization: &[
        SCENE_SPEC[0],
        SCENE_SPEC[1],
        SCENE_SPEC[2],
        SCENE_SPEC[3],
        SpecConstants::one(c::BVH_PROBE_SPEC_BRUTE_FORCE),
        SpecConstants::one(c::SPEC_BVH_LAYOUT),
    ],
    push_constant_size: 0,
};

/// `vkpath exercise`'s sample display (`crate::exercise::display`).
pub static EXERCISE_SAMPLES: Kernel = Kernel {
    source: "exercise_samples.comp",
    bindings: bindings::EXERCISE_SAMPLES,
    specialization: &SCENE_PROBE_SPEC,
    push_constant_size: size_of::<SampleDisplayPushConstants>() as u32,
};

/// Every kernel.
pub static ALL_KERNELS: [&Kernel; 19] = [
    &PATH_TRACER,
    &PROBE_GET_RANDOM_NUMBERS,
    &PROBE_SAMPLE_SPHERE,
    &PROBE_SAMPLE_HEMISPHERE,
    &PROBE_SAMPLE_SPHERE_SPHERICAL_COORDINATES,
    &PROBE_RAY_TRIANGLE_INTERSECTION,
    &PROBE_RAY_MESH_INTERSECTION,
    &PROBE_GET_PRIMARY_RAY_DIRECTION,
    &PROBE_COMPUTE_DIRECT_ILLUMINATION,
    &PROBE_GET_RAY_RADIANCE,
    &PROBE_BRDF,
    &PROBE_MEDIUM,
    &PROBE_SAMPLE_TEXTURE,
    &PROBE_PUNCTUAL_LIGHTS,
    &PROBE_LIGHT_TREE,
    &PROBE_GUIDING,
    &PROBE_SURFACE,
    &PROBE_BVH,
    &EXERCISE_SAMPLES,
];
