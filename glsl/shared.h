// The contract between the host (Rust) and the shaders: binding indices, workgroup sizes,
// specialization-constant ids and their values, and the numbers that a GLSL function and its
// Rust twin must agree on. build.rs turns every `#define NAME <value>` line of this file into
// a constant of `vkpath::contract`, so that no number is written twice: a plain decimal
// integer (`8`) becomes a `pub const NAME: u32`, a float literal (`1.0e-3`, `0.5`,
// `7.62939453125e-06`: digits, a point and digits, and/or an exponent; no suffix) a
// `pub const NAME: f32` with the same literal, which Rust and GLSL round to the same float.
// Any other value fails the build. The comment lines right above a #define become its doc
// comment; a group's heading is set apart by a blank line.
#ifndef VKPATH_SHARED_H
#define VKPATH_SHARED_H

// ======== Common to the kernels ========

// ---- Workgroup sizes ----

// Workgroup size of the 2D kernels. lavapipe's subgroup size is 8 (AVX2), so 8x8 keeps each
// subgroup full and gives many workgroups for its thread pool.
#define WORKGROUP_SIZE_X 8
#define WORKGROUP_SIZE_Y 8
// Workgroup size of the 1D probe kernels that evaluate one function on a buffer of inputs.
#define PROBE_WORKGROUP_SIZE 64

// ---- Descriptor set 0 of the path tracer (glsl/path_tracer.comp), all its bindings ----
// The host's layouts and descriptor writes come from one table, src/kernels/bindings.rs,
// which a test checks against each build's SPIR-V.

// The scene's triangles: a texel buffer of packed_triangle_t (glsl/scene.glsl), GpuTriangle
// on the host.
#define BINDING_TRIANGLES 0
// render_uniforms (glsl/scene.glsl), RenderUniforms on the host.
#define BINDING_RENDER_UNIFORMS 1
// The accumulation image (an rgba32f 2D array image with the LAYER_* layers).
#define BINDING_ACCUMULATION 2
// Emissive triangles and their power CDF, for light sampling (nee, mis): a texel buffer of
// GpuLightHeader then one GpuLight per light (glsl/emissive_lights.glsl).
#define BINDING_LIGHTS 4
// The emissive triangles' selection word of every scene triangle, in the order of
// BINDING_TRIANGLES, for MIS (get_light_selection_probability(), glsl/emissive_lights.glsl): a
// texel buffer of R32_UINT, one word per triangle. With LIGHT_SELECTION_POWER the word is the
// triangle's selection probability as float bits (0 for non-emitters); with
// LIGHT_SELECTION_TREE its index in the light list (NO_LIGHT for non-emitters). Written by
// gpu_light_selection_words() of src/lights/gpu_emissive.rs. 25: the first free index (0-19
// are taken, 20-23 are the user's iChannels, 24 the acceleration structure).
#define BINDING_LIGHT_SELECTION 25
// The path tracer's count of pixels that its samples made converged under --noise-threshold
// (a storage buffer of one uint, g_converged_pixel_count): each pixel counts once, in the
// dispatch whose samples made it converged (it takes none after); the host zeroes it before a
// batch and adds it up after, for the progress bar's share of converged pixels.
#define BINDING_CONVERGED_PIXELS 26
// Builds with USE_BVH: the BVH's nodes, a texel buffer of RGBA32_UINT: the 4-wide tree's
// (WIDE_BVH_NODE_TEXEL_COUNT texels each, glsl/bvh.glsl; with motion blur the motion tree's,
// MOTION_BVH_KEY_TEXEL_COUNT * SPEC_MOTION_STEPS + 1 texels each) or, with SPEC_BVH_LAYOUT
// BVH_LAYOUT_COMPRESSED, the compressed tree's (CWBVH_NODE_TEXEL_COUNT, glsl/cwbvh.glsl).
#define BINDING_BVH_NODES 3
// Builds with USE_BVH: the triangles' vertex positions alone, for the traversal's triangle
// tests, a texel buffer of TRAVERSAL_TRIANGLE_TEXEL_COUNT RGBA32_UINT texels per triangle in
// the same (leaf) order as BINDING_TRIANGLES (get_traversal_triangle() of glsl/bvh.glsl,
// GpuTraversalTriangle on the host); with BVH_LAYOUT_COMPRESSED, PACKED_TRIANGLE_WORD_COUNT
// words per triangle back to back instead (get_packed_traversal_triangle() of
// glsl/cwbvh.glsl, packed_traversal_triangles() on the host).
#define BINDING_TRAVERSAL_TRIANGLES 15
// The texels of every texture, concatenated (TextureAtlas on the host): a uniform texel
// buffer of R8G8B8A8_UINT texels (utextureBuffer), rows top-down as in the image files.
#define BINDING_TEXTURE_TEXELS 5
// Builds with USE_MATERIALS: per-triangle shading data, a texel buffer of
// SHADING_TEXEL_COUNT RGBA32_UINT texels per triangle (GpuTriangleShading on the host):
// vertex normals (xyz; texel 0's w: the material index), texture coordinates (texel 3: uv_0,
// uv_1; texel 4: uv_2), tangents (xyzw).
#define BINDING_SHADING 6
// USE_MATERIALS: the materials, a texel buffer of MATERIAL_TEXEL_COUNT RGBA32_UINT texels
// per material (GpuMaterial on the host, glsl/materials.glsl says what each holds).
#define BINDING_MATERIALS 7
// USE_MATERIALS: the environment, a texel buffer of RGBA32_UINT (gpu_environment_words() of
// src/lights/gpu_environment.rs; glsl/environment.glsl says what each texel holds).
#define BINDING_ENVIRONMENT 16
// USE_MATERIALS: KHR_lights_punctual's lights, a texel buffer of RGBA32_UINT: a header texel
// (x = count) then PUNCTUAL_LIGHT_TEXEL_COUNT texels per light (gpu_punctual_light_words()
// of src/lights/gpu_punctual.rs).
#define BINDING_PUNCTUAL_LIGHTS 17
// Builds with USE_RAY_QUERY: the scene's top-level acceleration structure
// (glsl/ray_query.glsl, src/accel/ on the host), in place of the BVH's bindings.
#define BINDING_ACCELERATION_STRUCTURE 24

// ---- Layers of the accumulation image ----

// Layer 0: running sum of the radiance samples (rgb), sample count (a).
#define LAYER_SUM 0
// Layer 1: Kahan compensation of the sum (rgb), number of rays traced (a).
#define LAYER_COMPENSATION 1
// Layer 2: running sum of squared radiance samples (rgb), for variance estimates; a: 1 where
// an invocation may have run into llvmpipe's loop limit (see SPEC_LOOP_LIMIT), else 0.
#define LAYER_SUM_OF_SQUARES 2
// Number of layers of the accumulation image.
#define ACCUMULATION_LAYER_COUNT 3

// ---- Specialization-constant ids of the path tracer ----

// Samples per pixel per frame (the workshop's SAMPLE_COUNT).
#define SPEC_SAMPLE_COUNT 0
// Maximum number of surface hits per path (the workshop's MAX_PATH_LENGTH).
#define SPEC_MAX_PATH_LENGTH 1
// Which pixel filter: PIXEL_FILTER_*.
#define SPEC_PIXEL_FILTER 2
// Which integrator: INTEGRATOR_*.
#define SPEC_INTEGRATOR 3
// Path vertex (surface hit, from 1) after which Russian roulette may end a path; 0: never.
#define SPEC_RUSSIAN_ROULETTE_START 4
// Random numbers of the importance-sampled integrators: SAMPLER_PCG or SAMPLER_SOBOL.
#define SPEC_SAMPLER 5
// How nee and mis sample a point on the chosen light: LIGHT_SAMPLING_*.
#define SPEC_LIGHT_SAMPLING 7
// Kernels built with USE_MATERIALS: whether any material uses alpha (0: the traversal loops
// test no alpha) and the texture slots (bit 1 << MATERIAL_TEXTURE_*) in which some material
// has a texture (0: no texture is ever sampled; a slot outside it compiles that slot's
// lookups out, e.g. the emissive texture's at every light sample). On lavapipe, code under
// an `if` costs the whole SIMD program whenever any lane takes it, so what a scene does not
// use is compiled out instead.
#define SPEC_SCENE_HAS_ALPHA 9
#define SPEC_SCENE_TEXTURE_SLOTS 10
// ... and whether any material has layers beyond metallic-roughness: transmission
// (KHR_materials_transmission, with KHR_materials_volume), a clear coat
// (KHR_materials_clearcoat) or sheen (KHR_materials_sheen), or KHR_materials_specular's
// textures or KHR_materials_unlit. 0 compiles their lobes out (glsl/layered_bsdf.glsl).
#define SPEC_SCENE_HAS_LAYERS 15
// Number of triangles passed as specialization constants (0: read them from the texel buffer).
#define SPEC_CONSTANT_TRIANGLE_COUNT 6
// Loop iterations one invocation may run before the driver may end its loops silently: on
// lavapipe LLVMPIPE_LOOP_LIMIT / LLVMPIPE_SIMD_WIDTH, 0 (no limit) elsewhere. The path
// tracer counts (an upper bound of) its iterations and flags the pixel when they reach it.
#define SPEC_LOOP_LIMIT 8
// The coefficients of that bound, which the host derives from its description of the
// kernel's loops (src/kernels/loops.rs): iterations per sample, per ray, light searches per
// ray (each of the light count's bits) and loops over all triangles per ray.
#define SPEC_LOOPS_PER_SAMPLE 11
#define SPEC_LOOPS_PER_RAY 12
#define SPEC_LIGHT_SEARCHES_PER_RAY 13
#define SPEC_TRIANGLE_LOOPS_PER_RAY 14
// Mesa's llvmpipe ends the loops of a shader invocation, with no error, once all its loops
// together have run this many trips (LP_MAX_TGSI_LOOP_ITERATIONS): one limiter per SIMD
// program, decremented by every trip of every loop, the trip that leaves a loop included
// (measured on Mesa 22.3.6 by tests/long_paths.rs: after a first loop of 40000 iterations a
// second one runs 25534 of its 40000). So the kernel bounds the sum over all its loops; a
// bound per loop would not do.
#define LLVMPIPE_LOOP_LIMIT 65535
// llvmpipe runs this many invocations as one SIMD program (AVX2: 8 lanes); its loops run
// while any lane is active, so their iterations are at most the sum of the lanes' own,
// at most this many times the largest lane's. A lane that stays below
// LLVMPIPE_LOOP_LIMIT / LLVMPIPE_SIMD_WIDTH can never reach the limit.
#define LLVMPIPE_SIMD_WIDTH 8
// The first of the 9 * CONSTANT_TRIANGLE_CAPACITY specialization constants holding the
// vertex positions of those triangles: constant SPEC_CONSTANT_TRIANGLES + 9 i + 3 j + k is
// coordinate k of vertex j of triangle i.
#define SPEC_CONSTANT_TRIANGLES 16
// How nee and mis choose the emissive triangle they sample: LIGHT_SELECTION_* (an id past
// the constant triangles' 16 + 9 * CONSTANT_TRIANGLE_CAPACITY).
#define SPEC_LIGHT_SELECTION 600
// Path guiding (--guiding): GUIDING_OFF; GUIDING_ON, which samples directions from the guide
// bound at BINDING_GUIDE; or GUIDING_TRAINING, which also splats into BINDING_GUIDE_SPLATS
// (glsl/path_guiding.glsl). A guided render has two pipelines: its training frames use the
// last, its other frames the second, which holds none of the training's code.
#define SPEC_GUIDING 601
// Kernels built with USE_MATERIALS: whether the scene has an environment that emits light
// (glsl/environment.glsl) and whether it has punctual lights (glsl/punctual_lights.glsl).
// 0 compiles that kind's light sample out of sample_direct_light(): on lavapipe both sides of
// an `if` run, so a kind the scene lacks would still cost its BSDF evaluation and the start
// of its shadow ray's traversal at every vertex.
#define SPEC_SCENE_HAS_ENVIRONMENT 602
#define SPEC_SCENE_HAS_PUNCTUAL_LIGHTS 603
// Kernels built with USE_MATERIALS: whether next event estimation samples the environment,
// i.e. whether it is a map. A constant environment is found by the paths' BSDF-sampled rays
// alone, with weight 1 (as pbrt-v4's uniform infinite light with an incomplete PDF): the
// BSDF's own directions are already distributed as its integrand is, so a uniform light
// sample only adds a BSDF evaluation and a shadow ray (the 24 icospheres under a white sky:
// 30 % more efficient).
#define SPEC_SCENE_SAMPLES_ENVIRONMENT 604
// Kernels built with USE_MATERIALS: whether the scene has emissive triangles. 0 compiles their
// light sample's estimate (a BSDF evaluation, its density, a shadow ray) out of
// sample_direct_light(), which lavapipe would otherwise run masked at every vertex of a scene
// lit by its environment or punctual lights alone; the sample's random numbers are still
// drawn, so the other lights' stay the same.
#define SPEC_SCENE_HAS_EMISSIVE_TRIANGLES 605
// Kernels built with USE_MATERIALS: whether any material has a specular lobe (metallic or
// specular above 0, or layers). 0: every surface is Lambertian, and the surface seam skips
// the GGX maths (glsl/materials.glsl, SCENE_HAS_SPECULAR).
#define SPEC_SCENE_HAS_SPECULAR 606
// BVH builds (USE_BVH): which tree the nodes and traversal triangles hold, BVH_LAYOUT_WIDE (the
// 4-wide tree of glsl/bvh.glsl) or BVH_LAYOUT_COMPRESSED (glsl/cwbvh.glsl). Both use the same
// bindings; the host picks the layout with the traversal (`Traversal::CompressedBvh`).
#define SPEC_BVH_LAYOUT 607
#define BVH_LAYOUT_WIDE 0
#define BVH_LAYOUT_COMPRESSED 1
// 1 where the camera has a thin lens (depth of field, glsl/thin_lens.glsl), else 0: a pinhole
// kernel compiles the lens out, so that its camera rays keep one origin for all invocations
// (a lens in the kernel, even one never applied, cost lavapipe about 30 % on the Cornell box).
#define SPEC_THIN_LENS 608
// Motion blur (--shutter): how many keys across the shutter the scene was evaluated at
// (--motion-steps, 2 to MAX_MOTION_STEPS), or 0 for a render without motion blur, whose
// kernels read the triangles and the camera as before (the motion code folds away). With
// keys, BINDING_TRIANGLES holds after its triangle_count * TRIANGLE_TEXEL_COUNT texels the
// keys' triangles, MOTION_TRIANGLE_TEXEL_COUNT texels each (v_0, v_1, v_2, normal;
// triangle-major, so that the two keys a ray's time lerps are neighbours in memory: triangle
// i's key k at record i * MOTION_STEPS + k, in the triangles' order), then the
// keys' cameras, MOTION_CAMERA_TEXEL_COUNT texels each (the four render_uniforms camera
// vectors). glsl/scene.glsl reads them; src/render/gpu_motion.rs writes them.
#define SPEC_MOTION_STEPS 609
// Kernels built with USE_MATERIALS: the vertex attributes that some triangle of the scene
// has beyond the normals, UVs and tangents, VERTEX_ATTRIBUTE_* bits (0: none, the kernels
// read the shading data as before and the attributes' code folds away). With any bit set,
// each triangle's shading data is SHADING_TEXEL_COUNT + EXTRA_SHADING_TEXEL_COUNT texels:
// after the usual ones, texel 0: COLOR_0 of vertices 0 and 1 (RGBA as two unorm16x2 words
// each), texel 1: COLOR_0 of vertex 2 and TEXCOORD_1 of vertex 0 (float bits), texel 2:
// TEXCOORD_1 of vertices 1 and 2 (GpuExtraShading on the host).
#define SPEC_SCENE_VERTEX_ATTRIBUTES 610
// glTF's COLOR_0, multiplied into the base colour and its alpha.
#define VERTEX_ATTRIBUTE_COLOR 1
// glTF's TEXCOORD_1, read by texture slots whose texCoord is 1 (TEXTURE_FLAG_TEX_COORD_1);
// set where some material reads it (its values 0 where no triangle has one).
#define VERTEX_ATTRIBUTE_TEX_COORD_1 2
#define EXTRA_SHADING_TEXEL_COUNT 3
#define MAX_MOTION_STEPS 64
// A global homogeneous medium (render --medium, glsl/medium.glsl): 1 where the render has
// one, else 0, which compiles the medium out of the path loop, the scattering vertex and the
// shadow rays (every other render keeps its kernel and its image bit for bit). With 1, the
// seven constants from SPEC_MEDIUM_COEFFICIENTS hold the float bits of sigma_a (r, g, b),
// sigma_s (r, g, b) and the Henyey-Greenstein g, in that order (src/medium.rs).
#define SPEC_MEDIUM 611
#define SPEC_MEDIUM_COEFFICIENTS 612
#define MEDIUM_COEFFICIENT_COUNT 7
// Kernels built with USE_MATERIALS: 1 where some material encloses a scattering volume
// (KHR_materials_volume_scatter: a refracting volume whose scattering coefficient is above 0,
// `SceneMaterials::uses_volume_scatter`), else 0, which compiles the volume's medium out of
// the path loop (every scene without the extension keeps its kernel and its image bit for
// bit). The coefficients are the material's (MATERIAL_TEXEL_FLAGS .yzw, g in
// MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK .z).
#define SPEC_SCENE_HAS_VOLUME_SCATTER 619
#define MOTION_TRIANGLE_TEXEL_COUNT 4
#define MOTION_CAMERA_TEXEL_COUNT 4
// Most triangles that can be passed as specialization constants.
#define CONSTANT_TRIANGLE_CAPACITY 64
// Most constant triangles that the material kernels (USE_MATERIALS) test: their intersection
// code stands at four call sites (the closest hit and the shadow rays of three kinds of
// light), each unrolled over every triangle the kernel can hold, and lavapipe translates all
// of it at every start before it folds the unused ones away. 16 keeps their start within
// about 0.02 s of the BVH kernel's (docs/performance.md).
#define MATERIAL_CONSTANT_TRIANGLE_CAPACITY 16
// The workshop kernels' build for scenes of at most this many triangles (the workshop's box
// has 30), path_tracer_few_triangles (FEW_CONSTANT_TRIANGLES), unrolls its loops over this
// many instead of CONSTANT_TRIANGLE_CAPACITY: half the code for lavapipe to translate at every
// start (the box's set-up: 0.17-0.29 s → 0.12-0.20 s).
#define FEW_CONSTANT_TRIANGLE_CAPACITY 32

// ---- Values of the specialization constants ----

// The default of SPEC_MAX_PATH_LENGTH, the workshop's MAX_PATH_LENGTH: the value of every
// kernel's MAX_PATH_LENGTH unless the host specializes it, and the renderer's default
// (`vkpath::render::settings::DEFAULT_MAX_PATH_LENGTH`).
#define DEFAULT_MAX_PATH_LENGTH 5

// Values of SPEC_PIXEL_FILTER.
// Uniform jitter inside the pixel: the box-filtered image.
#define PIXEL_FILTER_BOX 0
// The pixel centre, as the workshop's ShaderToy framework uses.
#define PIXEL_FILTER_CENTER 1

// Values of SPEC_SAMPLER (glsl/sobol.glsl). The workshop integrators always use PCG2D.
// Independent numbers hashed from (pixel, sample, dimension pair) with PCG2D
// (get_pcg_sample_2d()).
#define SAMPLER_PCG 0
// Owen-scrambled, shuffled 2D Sobol points per dimension pair (Burley 2020).
#define SAMPLER_SOBOL 1

// Values of SPEC_LIGHT_SAMPLING (glsl/importance_sampling.glsl).
// A point uniformly distributed on the triangle's area (density 1 / area).
#define LIGHT_SAMPLING_AREA 0
// A direction uniformly distributed in the solid angle the triangle subtends (Arvo 1995);
// by area where that solid angle is tiny or nearly 2 pi (use_spherical_sampling()).
#define LIGHT_SAMPLING_SOLID_ANGLE 1

// Values of SPEC_LIGHT_SELECTION (glsl/emissive_lights.glsl).
// In proportion to power, from the lights' CDF (sample_light_index()).
#define LIGHT_SELECTION_POWER 0
// By the light tree's importance to the shading point (glsl/light_tree.glsl).
#define LIGHT_SELECTION_TREE 1

// Values of SPEC_GUIDING (glsl/path_guiding.glsl).
// No guide: the path tracer's code for it is compiled out, its bindings unread.
#define GUIDING_OFF 0
// Guided directions at nee and mis vertices.
#define GUIDING_ON 1
// Guided directions, and training splats: the kernel of a guided render's training frames.
// On lavapipe both sides of every branch run, so code that a frame skips still costs: the
// render frames' kernel leaves the training out (Cornell box, 256^2, 256 spp: guided render
// seconds 9.8-11.8 -> 7.0-7.6, docs/guiding.md).
#define GUIDING_TRAINING 2

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
// Outputs for compositing and denoising (--aov), like INTEGRATOR_RAY_TRACING's albedo: the
// first hit's shading normal (world space, facing the camera; 0 where the ray escapes) and
// its distance from the camera (0 where the ray escapes).
#define INTEGRATOR_NORMAL 6
#define INTEGRATOR_DEPTH 7
// --aov material: the first hit's (metallic, roughness, 0) after texture lookups (the
// material_t of get_material(), glsl/materials.glsl); (0, 1, 0) in kernels without
// USE_MATERIALS, whose Lambertian triangles are glTF's metallic 0, roughness 1 (0 where the
// ray escapes).
#define INTEGRATOR_MATERIAL 8
// --aov object_id, instance_id, material_id, position, uv, object_position, z (ground
// truth, src/render/ground_truth.rs): the first hit's triangle as (index + 1, b_1, b_2), its
// index in the uploaded (leaf) order plus one, exact in a float up to 2^24, and the hit's
// barycentrics; (0, 0, 0) where the ray escapes. Rendered with one sample through the pixel
// centre, so that the host reads each pixel's triangle and point exactly, never averaged.
#define INTEGRATOR_TRIANGLE 9

// ---- Triangles ----

// Bit set in triangle_t's packed emission.w when the triangle emits from both sides.
#define TRIANGLE_FLAG_DOUBLE_SIDED 1
// Texels (RGBA32_UINT) per triangle in the texel-buffer layout: the vec4s of packed_triangle_t.
#define TRIANGLE_TEXEL_COUNT 6
// Texels (RGBA32_UINT) per triangle in the traversal-only layout (BINDING_TRAVERSAL_TRIANGLES):
// v_0, v_1, v_2, xyz each.
#define TRAVERSAL_TRIANGLE_TEXEL_COUNT 3

// ---- Numbers of the GLSL functions and their Rust twins (src/cpu/, src/bvh/) ----

// Initial out_t of ray_mesh_intersection() and bvh_closest_hit() (their Rust twins alike):
// hits at or beyond it are ignored.
#define NO_HIT_T 1.0e38
// Relative (and minimum absolute) offset of offset_ray_origin() (glsl/integrator.glsl): 2^-17
// of the largest coordinate, about 64 float ulps, far above the rounding error of
// ray_triangle_intersection() and far below any feature of a sensible scene.
#define RAY_ORIGIN_OFFSET 7.62939453125e-06
// Relative margin of is_occluded() (glsl/importance_sampling.glsl), 2^-14: a shadow ray ends
// at (1 - SHADOW_RAY_MARGIN) times the distance to the light sample, so that it cannot hit
// the emitter at its end.
#define SHADOW_RAY_MARGIN 6.103515625e-05
// Lights that subtend less than this solid angle (steradians) are sampled by area
// (use_spherical_sampling()): over so small a triangle the area density's distance^2 barely
// varies, so it is as good, while Arvo's sampler works with arcs below ~0.03 rad whose sines
// and cosines carry few digits.
#define MIN_SPHERICAL_SAMPLING_SOLID_ANGLE 1.0e-3
// Lights that subtend more than this (steradians) are sampled by area too: the point is then
// within a hair of the triangle's plane (2 pi is the whole half-space), where the spherical
// triangle's arcs approach great semicircles and their cross products vanish.
#define MAX_SPHERICAL_SAMPLING_SOLID_ANGLE 6.0
// Lower bound of |n_light.omega| in get_light_density()'s area density, so that a light seen
// exactly edge-on gives a huge density rather than a division by zero.
#define MIN_LIGHT_COSINE 1.0e-20
// The light tree (glsl/light_tree.glsl, vkpath::lights::light_tree): flags of a node's
// cos_theta_e_flags.y: a leaf (one light); some light below emits from both sides.
#define LIGHT_TREE_FLAG_LEAF 1
#define LIGHT_TREE_FLAG_TWO_SIDED 2
// Deepest leaf the tree may have: the bits of a light's leaf trail (a uint).
#define LIGHT_TREE_MAX_DEPTH 32
// The largest float below 1 (1 - 2^-24): where sample_light_tree() and
// sample_guide_direction() clamp their rescaled random numbers, which rounding could
// otherwise bring to 1.
#define ONE_MINUS_EPSILON 0.99999994

// ======== Path guiding (glsl/guiding.glsl, host side src/guiding/; Rust twins src/cpu/guiding.rs) ========

// The guide's texel buffer (RGBA32_UINT): GUIDE_HEADER_TEXEL_COUNT header texels (the grid's
// resolution and cell count; its lower corner; its cells per unit length), then
// GUIDE_CELL_TEXEL_COUNT texels per cell: the cumulative probabilities of its
// GUIDE_BIN_COUNT directional bins (floats, 1 at the last bin; all 0 where the cell is not
// guided), then the cell table: for each of the 6 orientations and grid position, the cell
// or 0xffffffff, padded to whole texels. Bound by glsl/probe_guiding.comp.
#define BINDING_GUIDE 18
#define GUIDE_HEADER_TEXEL_COUNT 3
// Orientations of the guide's cells (get_guide_orientation()): a normal's dominant axis
// (x, y, z) and its sign.
#define GUIDE_ORIENTATION_COUNT 6
// Bins per axis of a cell's directional histogram over the sphere's equal-area cylindrical
// map (cos theta, phi): GUIDE_DIRECTION_RESOLUTION^2 bins of equal solid angle.
#define GUIDE_DIRECTION_RESOLUTION 16
#define GUIDE_BIN_COUNT 256
#define GUIDE_CELL_TEXEL_COUNT 64
// The share of BSDF sampling in a guided vertex's one-sample mixture: the mixture's density
// is at least this times the BSDF's, so it never vanishes where the BSDF does not.
#define GUIDE_BSDF_FRACTION 0.5
// The share of a uniform distribution over the bins in each guided cell (host side): no
// bin's probability falls below GUIDE_UNIFORM_FRACTION / GUIDE_BIN_COUNT, which keeps a
// cell's density bounded away from 0 where few training paths went.
#define GUIDE_UNIFORM_FRACTION 0.1
// Training splats a cell needs before it is guided (host side): fewer give a histogram that
// is mostly noise.
#define GUIDE_MIN_SPLATS 64
// Descriptor set 0 of glsl/probe_guiding.comp: BINDING_GUIDE, then PROBE_BINDING_INPUTS and
// PROBE_BINDING_OUTPUTS.
// The path tracer's training splats (storage buffer of uints): for cell c and bin b, the
// low and high words of a 64-bit fixed-point sum at 2 (c GUIDE_BIN_COUNT + b) and + 1, added
// with carry so that the sum does not depend on the order of the atomics; then, after every
// cell's sums, one splat count per cell. Bound, with BINDING_GUIDE, by every build of
// glsl/path_tracer.comp (unread unless GUIDING_ON).
#define BINDING_GUIDE_SPLATS 19
// A splat's fixed-point units per unit of value (2^20), and the most one splat adds (2^40
// units): the host's GUIDE_FIXED_POINT_SCALE and GUIDE_MAX_SPLAT_UNITS.
#define GUIDE_FIXED_POINT_SCALE 1048576.0
#define GUIDE_MAX_SPLAT_UNITS 1099511627776.0
// Path vertices per sample whose incident radiance a training frame splats (the first ones
// of each path): the per-invocation record of glsl/path_guiding.glsl.
#define GUIDE_TRAINING_VERTEX_COUNT 8
// Metals smoother than this perceptual roughness sample their BSDF alone, unguided
// (is_guided_surface()).
#define GUIDE_MIN_ROUGHNESS 0.5

// ======== Materials (glsl/brdf.glsl, glsl/materials.glsl; Rust twins src/cpu/brdf.rs) ========

// Smallest GGX alpha (get_ggx_alpha()) of a roughness above 0: a roughness below 0.01
// becomes alpha 10^-4, a lobe about 10^-4 rad wide with a peak density of
// 1 / (pi alpha^2) = 3.2e7, whose square (MIS weights) stays far below float's 3.4e38.
// Roughness 0 exactly is a delta lobe (alpha 0), not this.
#define MIN_GGX_ALPHA 1.0e-4

#define SHADING_TEXEL_COUNT 8
// ---- A material's layout: declared here once; glsl/materials.glsl reads it, the host's
// `GpuMaterial` (src/render/gpu_materials.rs) writes it and the twins of
// src/cpu/gltf_surface.rs read it, through `contract::MATERIAL_TEXEL_*`. A material is
// MATERIAL_TEXEL_COUNT RGBA32_UINT texels: MATERIAL_FACTOR_TEXEL_COUNT texels of factors, then
// three texels per texture slot (texture_slot_t). A new factor takes a free component or a new
// texel here (and MATERIAL_FACTOR_TEXEL_COUNT, MATERIAL_TEXEL_COUNT grow by one).

// Texel of the base colour factor (linear RGB, alpha).
#define MATERIAL_TEXEL_BASE_COLOR 0
// Texel of the emissive factor (rgb) and the metallic factor (a).
#define MATERIAL_TEXEL_EMISSIVE_METALLIC 1
// Texel of the roughness factor (x), specular factor (y), ior (z) and normal texture's scale (w).
#define MATERIAL_TEXEL_ROUGHNESS_SPECULAR_IOR_NORMAL_SCALE 2
// Texel of the specular colour factor (rgb) and the alpha cutoff (a).
#define MATERIAL_TEXEL_SPECULAR_COLOR_ALPHA_CUTOFF 3
// Texel of the alpha mode (x, ALPHA_MODE_*), the mask of texture slots present (y) and the
// volume's Henyey-Greenstein g (z, KHR_materials_volume_scatter's scatterAnisotropy).
#define MATERIAL_TEXEL_ALPHA_MODE_TEXTURE_MASK 4
// Texel of the transmission (x), thickness (y), clearcoat (z) and clearcoat roughness (w) factors.
#define MATERIAL_TEXEL_TRANSMISSION_THICKNESS_CLEARCOAT 5
// Texel of the volume's absorption coefficient sigma_a per unit length (rgb; with
// KHR_materials_volume_scatter the part of the extinction that is not scattering) and the
// clearcoat normal texture's scale (a).
#define MATERIAL_TEXEL_ATTENUATION_CLEARCOAT_NORMAL_SCALE 6
// Texel of the MATERIAL_FLAG_* bits (x) and the volume's scattering coefficient sigma_s per
// unit length (yzw, KHR_materials_volume_scatter; 0 without it).
#define MATERIAL_TEXEL_FLAGS 7
// Texel of the sheen colour (rgb) and sheen roughness (a).
#define MATERIAL_TEXEL_SHEEN 8
// Texels of a material in all: the factors, then 3 per texture slot
// (MATERIAL_FACTOR_TEXEL_COUNT + 3 MATERIAL_TEXTURE_SLOT_COUNT, a layout test checks it).
#define MATERIAL_TEXEL_COUNT 48
// A material's texture slots, in the order of their texture_slot_t (3 texels each) after the
// material's first MATERIAL_FACTOR_TEXEL_COUNT texels; bit (1 << slot) of the material's
// texture flags says that the slot holds a texture.
#define MATERIAL_FACTOR_TEXEL_COUNT 9
#define MATERIAL_TEXTURE_BASE_COLOR 0
#define MATERIAL_TEXTURE_METALLIC_ROUGHNESS 1
#define MATERIAL_TEXTURE_NORMAL 2
#define MATERIAL_TEXTURE_EMISSIVE 3
// KHR_materials_transmission's transmissionTexture (R) and KHR_materials_volume's
// thicknessTexture (G)
#define MATERIAL_TEXTURE_TRANSMISSION 4
#define MATERIAL_TEXTURE_THICKNESS 5
// KHR_materials_clearcoat's clearcoatTexture (R), clearcoatRoughnessTexture (G) and
// clearcoatNormalTexture
#define MATERIAL_TEXTURE_CLEARCOAT 6
#define MATERIAL_TEXTURE_CLEARCOAT_ROUGHNESS 7
#define MATERIAL_TEXTURE_CLEARCOAT_NORMAL 8
// KHR_materials_specular's specularTexture (A) and specularColorTexture (sRGB RGB)
#define MATERIAL_TEXTURE_SPECULAR 9
#define MATERIAL_TEXTURE_SPECULAR_COLOR 10
// KHR_materials_sheen's sheenColorTexture (sRGB RGB) and sheenRoughnessTexture (A)
#define MATERIAL_TEXTURE_SHEEN_COLOR 11
#define MATERIAL_TEXTURE_SHEEN_ROUGHNESS 12
#define MATERIAL_TEXTURE_SLOT_COUNT 13
// The clear coat's index of refraction (KHR_materials_clearcoat: 1.5, F0 = 0.04).
#define CLEARCOAT_IOR 1.5
// KHR_materials_sheen: the side of the directional albedo table
// (src/cpu/sheen_albedo_table.rs), the texels it takes at the end of the material texels
// (SHEEN_ALBEDO_SIZE^2 / 4) and the smallest alpha (sheen roughness^2) of the Charlie lobe.
#define SHEEN_ALBEDO_SIZE 32
#define SHEEN_ALBEDO_TEXEL_COUNT 256
#define SHEEN_MIN_ALPHA 1.0e-3
// Bits of a material's flags (material texel MATERIAL_TEXEL_FLAGS .x): KHR_materials_unlit
// (the base colour is what camera rays see; nothing reflects or emits light).
#define MATERIAL_FLAG_UNLIT 1
// Values of a material's alpha mode (glTF alphaMode).
#define ALPHA_MODE_OPAQUE 0
#define ALPHA_MODE_MASK 1
#define ALPHA_MODE_BLEND 2

// ======== Lights beyond emissive triangles (glsl/environment.glsl, glsl/punctual_lights.glsl) ========

#define PUNCTUAL_LIGHT_TEXEL_COUNT 4
// What the environment is: black (nothing to sample), a constant colour, a map.
#define ENVIRONMENT_NONE 0
#define ENVIRONMENT_CONSTANT 1
#define ENVIRONMENT_MAP 2
// Kinds of punctual light (KHR_lights_punctual's type).
#define PUNCTUAL_LIGHT_POINT 0
#define PUNCTUAL_LIGHT_SPOT 1
#define PUNCTUAL_LIGHT_DIRECTIONAL 2

// ======== Probe kernels (glsl/probe_*.comp, host side src/probe/) ========

// Descriptor set 0 of the probe kernels: the scene's BINDING_TRIANGLES (texel buffer) and
// BINDING_RENDER_UNIFORMS above, for the functions that trace rays, then a storage buffer of
// inputs and one of outputs. Numbered apart from the path tracer's bindings, which the
// included GLSL may declare too.
#define PROBE_BINDING_INPUTS 8
#define PROBE_BINDING_OUTPUTS 9
// A storage buffer of one uint per input: 1 where the user's function (vkpath check) ran
// past its loop limit (an endless loop), else 0.
#define PROBE_BINDING_FLAGS 13

// ======== The sample display of `vkpath exercise` (glsl/exercise_samples.comp, host side src/exercise/) ========

// Descriptor set 0 of the sample display: a storage buffer of one vec4 colour per pixel.
// Numbered apart from the path tracer's bindings, which the included scene files declare too.
#define BINDING_EXERCISE_PIXELS 10
// ... and a storage buffer of EXERCISE_SAMPLE_COUNT directions (vec4, xyz) that
// EXERCISE_SAMPLER_DIRECTIONS draws (a one-vec4 buffer for the other samplers).
#define BINDING_EXERCISE_DIRECTIONS 11
// Values of the sample display's sampler (its push constant).
// Exercise 4: sample_sphere().
#define EXERCISE_SAMPLER_SPHERE 0
// Exercise 5: sample_hemisphere() around +z.
#define EXERCISE_SAMPLER_HEMISPHERE 1
// The slides' naive sample_sphere_spherical_coordinates() ("too many samples at the top").
#define EXERCISE_SAMPLER_SPHERICAL_COORDINATES 2
// glsl/brdf.glsl's sample_brdf() at a surface with normal +z, for the material and view
// direction of the push constants (`vkpath exercise brdf-samples`).
#define EXERCISE_SAMPLER_BRDF 3
// Directions the host sampled (BINDING_EXERCISE_DIRECTIONS), e.g. a path guide's cell and
// the BSDF next to it (`vkpath exercise guide-cell`); the random numbers are drawn all the
// same.
#define EXERCISE_SAMPLER_DIRECTIONS 4
// Number of sample directions the workshop's framework displays (Exercises 4 and 5).
#define EXERCISE_SAMPLE_COUNT 512
// Cosine and sine of the elevation of the display's camera, 30 degrees above the sphere's
// equator: the view's up vector is (0, sin, cos), the direction to the viewer (0, -cos, sin)
// (SAMPLE_VIEW_UP and SAMPLE_VIEW_TOWARD_VIEWER, Rust twins in src/exercise/view.rs).
#define SAMPLE_VIEW_ELEVATION_COS 0.8660254037844386
#define SAMPLE_VIEW_ELEVATION_SIN 0.5
// Half the image height in sphere radii: a margin of 15% around the sphere.
#define SAMPLE_VIEW_HALF_HEIGHT 1.15

// ======== The bounding volume hierarchy (glsl/bvh.glsl, host side src/bvh/) and its probe ========

// Depth limit of the builder's binary tree: it makes no leaf deeper than this (root: depth
// 0), so a traversal of the binary tree pushes at most this many entries, one per interior
// node on the path from the root (the bound of the wide tree's fallback below).
#define BVH_STACK_SIZE 32
// The BVH that the kernels traverse is 4-wide (src/bvh/wide.rs collapses the binary tree of
// the builder): a node holds up to WIDE_BVH_WIDTH child boxes in WIDE_BVH_NODE_TEXEL_COUNT
// RGBA32 texels (lower x, upper x, lower y, upper y, lower z, upper z of the four children,
// then the four child references). A reference is a node index (interior child), or a leaf's
// first triangle | triangle count << WIDE_BVH_LEAF_COUNT_SHIFT, or WIDE_BVH_EMPTY_CHILD for
// an unused slot: 0, the root's index, which is no node's child.
#define WIDE_BVH_WIDTH 4
#define WIDE_BVH_NODE_TEXEL_COUNT 7
// Motion blur's 4-wide BVH (SPEC_MOTION_STEPS != 0; src/bvh/motion.rs, Embree's linear motion
// blur): the still tree's node with its six box texels once per key, so a node takes
// MOTION_BVH_KEY_TEXEL_COUNT * MOTION_STEPS + 1 texels: key 0's six (lower x, upper x, lower y,
// upper y, lower z, upper z of the four children), key 1's, ..., then the child references.
// The traversal lerps the two keys' boxes around the ray's time (glsl/bvh.glsl).
#define MOTION_BVH_KEY_TEXEL_COUNT 6
#define WIDE_BVH_LEAF_COUNT_SHIFT 24
#define WIDE_BVH_INDEX_MASK 16777215
#define WIDE_BVH_EMPTY_CHILD 0
// Entries of the wide traversal's stack: a node pushes up to WIDE_BVH_WIDTH - 1 children, and
// the collapse keeps every path's pushes within this (else it keeps the binary tree, whose
// paths push at most BVH_STACK_SIZE).
#define WIDE_BVH_STACK_SIZE 64
// The compressed wide BVH (glsl/cwbvh.glsl, host side src/bvh/compressed.rs; Ylitie, Karras
// and Laine 2017, "Efficient incoherent ray traversal on GPUs through compressed wide BVHs"),
// built by the obvhs crate: 8 children per node, their boxes quantised to 8 bits per plane
// against the node's grid (origin, power-of-two scale per axis), CWBVH_NODE_TEXEL_COUNT RGBA32
// texels (80 bytes) per node. Leaves hold 1 to 3 triangles; a node's leaves hold at most 24.
#define CWBVH_WIDTH 8
#define CWBVH_NODE_TEXEL_COUNT 5
// Entries (node groups) of the compressed traversal's stack: at most one per interior level
// below the root, so the builder refuses trees whose interior nodes lie deeper than this
// (src/bvh/compressed.rs); obvhs itself assumes the same bound of 32.
#define CWBVH_STACK_SIZE 32
// Nodes a compressed tree may have: a stack entry keeps a node's index in 24 bits
// (cwbvh_stack_entry()); the builder refuses larger trees (about 10^8 triangles and more).
#define CWBVH_MAX_NODE_COUNT 16777216
// 32-bit words per triangle of the compressed tree's traversal triangles: v_0, v_1, v_2, 9
// floats packed back to back in RGBA32 texels (36 bytes instead of 48), so triangle i starts
// at word 9 i, component (9 i) mod 4 of texel (9 i) / 4, and spans 3 texels.
#define PACKED_TRIANGLE_WORD_COUNT 9
// Slab exits are scaled by this before the comparison, so that rounding errors never cull a
// box that the ray touches: pbrt-v4 (6.8.2) shows that 1 + 2 gamma_3 (3.6e-7) suffices for
// exact division; 1e-6 (8 ulps) leaves room for a GPU's approximate reciprocal (NVIDIA: 2 ulps).
#define BVH_SLAB_PADDING 1.000001
// Direction components below this magnitude are replaced by it (keeping the sign), so that
// the inverse direction is finite (at most 1e30) and slab products are never 0 * inf = NaN.
#define BVH_MIN_DIRECTION 1.0e-30
// Descriptor set 0 of glsl/probe_bvh.comp (tests/bvh_gpu.rs): the scene's BINDING_TRIANGLES,
// BINDING_RENDER_UNIFORMS and BINDING_BVH_NODES, then a storage buffer of rays and one of
// results.
#define BVH_PROBE_BINDING_RAYS 11
#define BVH_PROBE_BINDING_RESULTS 12
// Specialization-constant id of glsl/probe_bvh.comp: 1 to run the brute-force
// ray_mesh_intersection() beside the BVH, 0 not to.
#define BVH_PROBE_SPEC_BRUTE_FORCE 0

// ======== `vkpath check` (src/check/source.rs) ========

// ShaderToy's iChannel0..3 that a user's file reads get bindings USER_OPAQUE_BINDING_FIRST +
// 0..3, the file's own sampler uniforms the bindings from USER_OPAQUE_BINDING_FIRST + 4 on.
// No kernel's layout has them: a function that reads them cannot be judged.
#define USER_OPAQUE_BINDING_FIRST 20

// ======== Textures (glsl/textures.glsl, host side src/render/gpu_textures.rs) ========

// RGBA32_UINT texels (uvec4) per texture_slot_t as packed (GpuTextureSlot, 48 bytes).
#define TEXTURE_SLOT_TEXEL_COUNT 3

// ---- Bits of texture_slot_t.flags ----

// The texture's rgb is sRGB-encoded (base colour, emission) and decoded to linear per texel,
// before filtering; alpha is always linear.
#define TEXTURE_FLAG_SRGB 1
// The wrap mode along u (glTF wrapS, a WRAP_* value) is (flags >> TEXTURE_WRAP_S_SHIFT) &
// TEXTURE_WRAP_MASK.
#define TEXTURE_WRAP_S_SHIFT 1
// The wrap mode along v (glTF wrapT) is (flags >> TEXTURE_WRAP_T_SHIFT) & TEXTURE_WRAP_MASK.
#define TEXTURE_WRAP_T_SHIFT 3
// Mask of a wrap mode once shifted down.
#define TEXTURE_WRAP_MASK 3
// Nearest-texel lookup (glTF magFilter NEAREST) instead of bilinear filtering.
#define TEXTURE_FLAG_NEAREST 32
// The slot reads TEXCOORD_1 (glTF's texCoord 1) instead of TEXCOORD_0 (set only in scenes
// whose SPEC_SCENE_VERTEX_ATTRIBUTES has VERTEX_ATTRIBUTE_TEX_COORD_1;
// select_tex_coord() of glsl/materials.glsl reads it).
#define TEXTURE_FLAG_TEX_COORD_1 64

// ---- Wrap modes (wrap_texel_coordinate()) ----

// glTF REPEAT (10497): the texture tiles the plane.
#define WRAP_REPEAT 0
// glTF CLAMP_TO_EDGE (33071): texels outside repeat the edge texel.
#define WRAP_CLAMP_TO_EDGE 1
// glTF MIRRORED_REPEAT (33648): tiles alternate with their mirror image (OpenGL 4.6, 8.14.2).
#define WRAP_MIRRORED_REPEAT 2

// ---- Numbers of the texture functions and their Rust twins (src/cpu/textures.rs) ----

// 1/255 rounded to float: a byte b reads as b * TEXEL_UNORM_SCALE. A multiplication is
// correctly rounded on every Vulkan device (a division only to 2.5 ulps), so GPU and CPU
// agree bit for bit; 255 * TEXEL_UNORM_SCALE rounds to exactly 1.0, and b * scale is within
// one ulp of b / 255.
#define TEXEL_UNORM_SCALE 0.00392156862745098
// Texel coordinates (u * width - 0.5 and the like) are clamped to +-2^30 before they become
// ints, so that huge or infinite texture coordinates give a defined texel (GLSL's int() of
// a float out of range is undefined); a float that large has no fractional part left.
#define TEXTURE_COORDINATE_LIMIT 1073741824.0

// Descriptor set 0 of glsl/probe_sample_texture.comp (tests/texture_twins.rs, host side
// src/probe/texture_probe.rs): BINDING_TEXTURE_TEXELS, a storage buffer of packed
// texture_slot_t (uvec4s) here, and PROBE_BINDING_INPUTS and PROBE_BINDING_OUTPUTS.
#define PROBE_BINDING_TEXTURE_SLOTS 14

#endif
