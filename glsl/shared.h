// The contract between the host (Rust) and the shaders: binding indices, workgroup size,
// specialization-constant ids and enumerations. build.rs turns every `#define NAME <integer>`
// line of this file into a `pub const NAME: u32` in `vkpath::contract`, so that no number is
// written twice. Keep the values plain decimal integers.
#ifndef VKPATH_SHARED_H
#define VKPATH_SHARED_H

// Workgroup size of the 2D kernels. lavapipe's subgroup size is 8 (AVX2), so 8x8 keeps each
// subgroup full and gives many workgroups for its thread pool.
#define WORKGROUP_SIZE_X 8
#define WORKGROUP_SIZE_Y 8
// Workgroup size of the 1D probe kernels that evaluate one function on a buffer of inputs.
#define PROBE_WORKGROUP_SIZE 64

// Descriptor set 0 of the path tracer.
#define BINDING_TRIANGLES 0
#define BINDING_RENDER_UNIFORMS 1
#define BINDING_ACCUMULATION 2

// Descriptor set 0 of the probe kernels (glsl/probe_*.comp, host side src/probe/): the scene's
// BINDING_TRIANGLES (storage buffer) and BINDING_RENDER_UNIFORMS above, for the functions that
// trace rays, then a storage buffer of inputs and one of outputs. Numbered apart from the path
// tracer's bindings, which the included GLSL may declare too.
#define PROBE_BINDING_INPUTS 8
#define PROBE_BINDING_OUTPUTS 9
// Emissive triangles and their power CDF, for light sampling (nee, mis).
#define BINDING_LIGHTS 4

// Layers of the accumulation image (an rgba32f 2D array image).
// Layer 0: running sum of the radiance samples (rgb), sample count (a).
#define LAYER_SUM 0
// Layer 1: Kahan compensation of the sum (rgb), number of rays traced (a).
#define LAYER_COMPENSATION 1
// Layer 2: running sum of squared radiance samples (rgb), for variance estimates.
#define LAYER_SUM_OF_SQUARES 2
#define ACCUMULATION_LAYER_COUNT 3

// Specialization-constant ids of the path tracer.
#define SPEC_SAMPLE_COUNT 0
#define SPEC_MAX_PATH_LENGTH 1
#define SPEC_PIXEL_FILTER 2
#define SPEC_INTEGRATOR 3
// Path vertex (surface hit, from 1) after which Russian roulette may end a path; 0: never.
#define SPEC_RUSSIAN_ROULETTE_START 4
// Random numbers of the importance-sampled integrators: SAMPLER_PCG or SAMPLER_SOBOL.
#define SPEC_SAMPLER 5
// How nee and mis sample a point on the chosen light: LIGHT_SAMPLING_*.
#define SPEC_LIGHT_SAMPLING 7
// Number of triangles passed as specialization constants (0: read them from the texel buffer).
#define SPEC_CONSTANT_TRIANGLE_COUNT 6
// The first of the 9 * CONSTANT_TRIANGLE_CAPACITY specialization constants holding the
// vertex positions of those triangles: constant SPEC_CONSTANT_TRIANGLES + 9 i + 3 j + k is
// coordinate k of vertex j of triangle i.
#define SPEC_CONSTANT_TRIANGLES 16
// Most triangles that can be passed as specialization constants.
#define CONSTANT_TRIANGLE_CAPACITY 64

// Values of SPEC_PIXEL_FILTER.
// Uniform jitter inside the pixel: the box-filtered image.
#define PIXEL_FILTER_BOX 0
// The pixel centre, as the workshop's ShaderToy framework uses.
#define PIXEL_FILTER_CENTER 1

// Values of SPEC_SAMPLER (glsl/sobol.glsl). The workshop integrators always use PCG2D.
// The workshop's PCG2D, get_random_numbers().
#define SAMPLER_PCG 0
// Owen-scrambled, shuffled 2D Sobol points per dimension pair (Burley 2020).
#define SAMPLER_SOBOL 1

// Values of SPEC_LIGHT_SAMPLING (glsl/importance_sampling.glsl).
// A point uniformly distributed on the triangle's area (density 1 / area).
#define LIGHT_SAMPLING_AREA 0
// A direction uniformly distributed in the solid angle the triangle subtends (Arvo 1995);
// by area where that solid angle is tiny or nearly 2 pi (use_spherical_sampling()).
#define LIGHT_SAMPLING_SOLID_ANGLE 1

// Values of SPEC_INTEGRATOR.
// Exercise 7: the path-tracing loop of get_ray_radiance().
#define INTEGRATOR_PATH_TRACING 0
// Exercise 6: emission plus one-bounce direct illumination, compute_direct_illumination().
#define INTEGRATOR_DIRECT_ILLUMINATION 1
// Part 1: unshaded ray tracing, the albedo of the first triangle hit.
#define INTEGRATOR_RAY_TRACING 2
// Path tracing with cosine-weighted hemisphere sampling (BRDF importance sampling).
#define INTEGRATOR_COSINE 3
// Next event estimation: a light sample (power-proportional triangle, uniform point, shadow
// ray) at every vertex, cosine sampling to continue; emission found by BRDF rays is ignored.
#define INTEGRATOR_NEE 4
// Multiple importance sampling of light and cosine samples with the power heuristic.
#define INTEGRATOR_MIS 5

// Bit set in triangle_t's packed emission.w when the triangle emits from both sides.
#define TRIANGLE_FLAG_DOUBLE_SIDED 1
// Texels (RGBA32_UINT) per triangle in the texel-buffer layout: the vec4s of packed_triangle_t.
#define TRIANGLE_TEXEL_COUNT 6

// Descriptor set 0 of the sample display of `vkpath exercise` (glsl/exercise_samples.comp,
// host side src/exercise/): a storage buffer of one vec4 colour per pixel. Numbered apart from
// the path tracer's bindings, which the included scene files declare too.
#define BINDING_EXERCISE_PIXELS 10
// Values of the sample display's sampler (its push constant).
// Exercise 4: sample_sphere().
#define EXERCISE_SAMPLER_SPHERE 0
// Exercise 5: sample_hemisphere() around +z.
#define EXERCISE_SAMPLER_HEMISPHERE 1
// The slides' naive sample_sphere_spherical_coordinates() ("too many samples at the top").
#define EXERCISE_SAMPLER_SPHERICAL_COORDINATES 2
// Number of sample directions the workshop's framework displays (Exercises 4 and 5).
#define EXERCISE_SAMPLE_COUNT 512

// The bounding volume hierarchy (glsl/bvh.glsl, host side src/bvh/): a storage buffer of
// bvh_node_t, 32 bytes each, in descriptor set 0 beside the triangles it indexes.
#define BINDING_BVH_NODES 3
// Entries of the traversal stack of bvh_closest_hit() and bvh_any_hit(). The builder makes no
// leaf deeper than this (root: depth 0), which is what the stack needs: at most one entry is
// pushed per interior node on the path from the root.
#define BVH_STACK_SIZE 32
// Descriptor set 0 of glsl/probe_bvh.comp (tests/bvh_gpu.rs): the scene's BINDING_TRIANGLES
// (storage buffer), BINDING_RENDER_UNIFORMS and BINDING_BVH_NODES, then a storage buffer of
// rays and one of results.
#define BVH_PROBE_BINDING_RAYS 11
#define BVH_PROBE_BINDING_RESULTS 12
// Specialization-constant id of glsl/probe_bvh.comp: 1 to run the brute-force
// ray_mesh_intersection() beside the BVH, 0 not to.
#define BVH_PROBE_SPEC_BRUTE_FORCE 0

// `vkpath check` (src/check/source.rs): ShaderToy's iChannel0..3 that a user's file reads get
// bindings USER_OPAQUE_BINDING_FIRST + 0..3, the file's own sampler uniforms the bindings from
// USER_OPAQUE_BINDING_FIRST + 4 on. No kernel's layout has them: a function that reads them
// cannot be judged.
#define USER_OPAQUE_BINDING_FIRST 20

#endif
