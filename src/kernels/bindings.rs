//! The binding table of every kernel: for each binding of descriptor set 0, its index (from
//! `glsl/shared.h`), its descriptor type and the resource the host puts there. The host's
//! descriptor-set layouts and descriptor writes are derived from these rows
//! (`crate::kernels::Kernel`), and a test reflects each kernel's SPIR-V against them
//! (`crate::kernels::reflect`): adding a binding to a kernel is one row here.

use ash::vk;

use crate::contract as c;
use crate::kernels::builds::{USE_BVH, USE_MATERIALS, USE_RAY_QUERY};

/// What the host binds: each names one buffer, view or image that some kernel reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Resource {
    /// The scene's triangles, packed (`GpuTriangle`, texel buffer).
    Triangles,
    /// `render_uniforms` (`RenderUniforms`).
    RenderUniforms,
    /// The accumulation image (`ACCUMULATION_LAYER_COUNT` layers of rgba32f).
    Accumulation,
    /// The BVH's nodes (texel buffer).
    BvhNodes,
    /// The triangles' vertex positions alone, in BVH leaf order, for the traversal's
    /// triangle tests (`GpuTraversalTriangle`, texel buffer).
    TraversalTriangles,
    /// The scene's top-level acceleration structure (`crate::accel`, builds with
    /// `USE_RAY_QUERY`).
    AccelerationStructure,
    /// The emissive triangles and their power CDF (`gpu_light_bytes`, texel buffer).
    Lights,
    /// Every triangle's light-selection word, for MIS (`gpu_light_selection_words`, R32_UINT
    /// texel buffer).
    LightSelection,
    /// The texels of every texture (`TextureAtlas`, RGBA8 texel buffer).
    TextureTexels,
    /// Per-triangle shading data (`GpuTriangleShading`, texel buffer).
    Shading,
    /// The materials (`GpuMaterial`, texel buffer).
    Materials,
    /// The environment (`gpu_environment_words`, texel buffer).
    Environment,
    /// KHR_lights_punctual's lights (`gpu_punctual_light_words`, texel buffer).
    PunctualLights,
    /// Path guiding's guide (`crate::guiding::Guide::words`, texel buffer).
    Guide,
    /// Path guiding's training splats (`crate::guiding::GuideSplats::from_device_words`,
    /// storage buffer).
    GuideSplats,
    /// The path tracer's count of pixels its samples made converged (`--noise-threshold`;
    /// one `u32`, storage buffer).
    ConvergedPixels,
    /// A probe's input structs, one per invocation.
    ProbeInputs,
    /// A probe's output structs, one per invocation.
    ProbeOutputs,
    /// A probe's per-invocation flag: nonzero where the user's loops hit their limit.
    ProbeFlags,
    /// The texture probe's packed `texture_slot_t`s.
    TextureSlots,
    /// The pixels of `vkpath exercise`'s sample display.
    ExercisePixels,
    /// The directions the sample display draws for `EXERCISE_SAMPLER_DIRECTIONS`.
    ExerciseDirections,
}

/// One row of a binding table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// The binding index in set 0.
    pub binding: u32,
    /// Its descriptor type.
    pub kind: vk::DescriptorType,
    /// What the host binds there.
    pub resource: Resource,
    /// The macro of the builds that declare it (`None`: every build).
    pub only_with: Option<&'static str>,
}

const TEXEL: vk::DescriptorType = vk::DescriptorType::UNIFORM_TEXEL_BUFFER;
const UNIFORM: vk::DescriptorType = vk::DescriptorType::UNIFORM_BUFFER;
const STORAGE: vk::DescriptorType = vk::DescriptorType::STORAGE_BUFFER;
const IMAGE: vk::DescriptorType = vk::DescriptorType::STORAGE_IMAGE;
const ACCELERATION_STRUCTURE: vk::DescriptorType = vk::DescriptorType::ACCELERATION_STRUCTURE_KHR;

/// A row that every build of the kernel declares.
const fn row(binding: u32, kind: vk::DescriptorType, resource: Resource) -> Binding {
    Binding {
        binding,
        kind,
        resource,
        only_with: None,
    }
}

/// A row that only the builds with `macro_name` defined declare.
const fn with(
    macro_name: &'static str,
    binding: u32,
    kind: vk::DescriptorType,
    resource: Resource,
) -> Binding {
    Binding {
        binding,
        kind,
        resource,
        only_with: Some(macro_name),
    }
}

use Resource as R;

/// `glsl/path_tracer.comp` in each of its builds.
pub const PATH_TRACER: &[Binding] = &[
    row(c::BINDING_TRIANGLES, TEXEL, R::Triangles),
    row(c::BINDING_RENDER_UNIFORMS, UNIFORM, R::RenderUniforms),
    row(c::BINDING_ACCUMULATION, IMAGE, R::Accumulation),
    row(c::BINDING_LIGHTS, TEXEL, R::Lights),
    row(c::BINDING_LIGHT_SELECTION, TEXEL, R::LightSelection),
    row(c::BINDING_GUIDE, TEXEL, R::Guide),
    row(c::BINDING_GUIDE_SPLATS, STORAGE, R::GuideSplats),
    row(c::BINDING_CONVERGED_PIXELS, STORAGE, R::ConvergedPixels),
    with(USE_BVH, c::BINDING_BVH_NODES, TEXEL, R::BvhNodes),
    with(
        USE_BVH,
        c::BINDING_TRAVERSAL_TRIANGLES,
        TEXEL,
        R::TraversalTriangles,
    ),
    with(
        USE_RAY_QUERY,
        c::BINDING_ACCELERATION_STRUCTURE,
        ACCELERATION_STRUCTURE,
        R::AccelerationStructure,
    ),
    with(
        USE_MATERIALS,
        c::BINDING_TEXTURE_TEXELS,
        TEXEL,
        R::TextureTexels,
    ),
    with(USE_MATERIALS, c::BINDING_SHADING, TEXEL, R::Shading),
    with(USE_MATERIALS, c::BINDING_MATERIALS, TEXEL, R::Materials),
    with(USE_MATERIALS, c::BINDING_ENVIRONMENT, TEXEL, R::Environment),
    with(
        USE_MATERIALS,
        c::BINDING_PUNCTUAL_LIGHTS,
        TEXEL,
        R::PunctualLights,
    ),
];

/// The probes of the workshop's functions (`glsl/probe_common.glsl`): the scene they trace
/// rays in, their inputs and outputs, and the flags of the user's loops (`vkpath check`).
pub const SCENE_PROBE: &[Binding] = &[
    row(c::BINDING_TRIANGLES, TEXEL, R::Triangles),
    row(c::BINDING_RENDER_UNIFORMS, UNIFORM, R::RenderUniforms),
    row(c::PROBE_BINDING_INPUTS, STORAGE, R::ProbeInputs),
    row(c::PROBE_BINDING_OUTPUTS, STORAGE, R::ProbeOutputs),
    row(c::PROBE_BINDING_FLAGS, STORAGE, R::ProbeFlags),
];

/// `glsl/probe_brdf.comp`.
pub const BRDF_PROBE: &[Binding] = &[
    row(c::PROBE_BINDING_INPUTS, STORAGE, R::ProbeInputs),
    row(c::PROBE_BINDING_OUTPUTS, STORAGE, R::ProbeOutputs),
];

/// `glsl/probe_sample_texture.comp`.
pub const TEXTURE_PROBE: &[Binding] = &[
    row(c::BINDING_TEXTURE_TEXELS, TEXEL, R::TextureTexels),
    row(c::PROBE_BINDING_TEXTURE_SLOTS, STORAGE, R::TextureSlots),
    row(c::PROBE_BINDING_INPUTS, STORAGE, R::ProbeInputs),
    row(c::PROBE_BINDING_OUTPUTS, STORAGE, R::ProbeOutputs),
];

/// `glsl/probe_punctual_lights.comp`.
pub const PUNCTUAL_LIGHTS_PROBE: &[Binding] = &[
    row(c::BINDING_PUNCTUAL_LIGHTS, TEXEL, R::PunctualLights),
    row(c::PROBE_BINDING_INPUTS, STORAGE, R::ProbeInputs),
    row(c::PROBE_BINDING_OUTPUTS, STORAGE, R::ProbeOutputs),
];

/// `glsl/probe_light_tree.comp`.
pub const LIGHT_TREE_PROBE: &[Binding] = &[
    row(c::BINDING_LIGHTS, TEXEL, R::Lights),
    row(c::PROBE_BINDING_INPUTS, STORAGE, R::ProbeInputs),
    row(c::PROBE_BINDING_OUTPUTS, STORAGE, R::ProbeOutputs),
];

/// `glsl/probe_guiding.comp`.
pub const GUIDING_PROBE: &[Binding] = &[
    row(c::BINDING_GUIDE, TEXEL, R::Guide),
    row(c::PROBE_BINDING_INPUTS, STORAGE, R::ProbeInputs),
    row(c::PROBE_BINDING_OUTPUTS, STORAGE, R::ProbeOutputs),
];

/// `glsl/probe_surface.comp`: the scene and its materials as the path tracer binds them.
pub const SURFACE_PROBE: &[Binding] = &[
    row(c::BINDING_TRIANGLES, TEXEL, R::Triangles),
    row(c::BINDING_RENDER_UNIFORMS, UNIFORM, R::RenderUniforms),
    row(c::BINDING_TEXTURE_TEXELS, TEXEL, R::TextureTexels),
    row(c::BINDING_SHADING, TEXEL, R::Shading),
    row(c::BINDING_MATERIALS, TEXEL, R::Materials),
    row(c::PROBE_BINDING_INPUTS, STORAGE, R::ProbeInputs),
    row(c::PROBE_BINDING_OUTPUTS, STORAGE, R::ProbeOutputs),
];

/// `glsl/probe_bvh.comp`: the BVH path tracer's scene, rays in, results out.
pub const BVH_PROBE: &[Binding] = &[
    row(c::BINDING_TRIANGLES, TEXEL, R::Triangles),
    row(c::BINDING_RENDER_UNIFORMS, UNIFORM, R::RenderUniforms),
    row(c::BINDING_BVH_NODES, TEXEL, R::BvhNodes),
    row(c::BINDING_TRAVERSAL_TRIANGLES, TEXEL, R::TraversalTriangles),
    row(c::BVH_PROBE_BINDING_RAYS, STORAGE, R::ProbeInputs),
    row(c::BVH_PROBE_BINDING_RESULTS, STORAGE, R::ProbeOutputs),
];

/// `glsl/exercise_samples.comp`.
pub const EXERCISE_SAMPLES: &[Binding] = &[
    row(c::BINDING_EXERCISE_PIXELS, STORAGE, R::ExercisePixels),
    row(
        c::BINDING_EXERCISE_DIRECTIONS,
        STORAGE,
        R::ExerciseDirections,
    ),
];
