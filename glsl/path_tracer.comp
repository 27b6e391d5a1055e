#version 460
// The progressive path tracer: each dispatch (a frame) adds up to SAMPLE_COUNT samples per
// pixel to the accumulation image, as the workshop's progressive ShaderToy does across
// frames. Samples are added one at a time in sample order with Kahan summation, so that the
// result is bit-identical however the samples are split into frames.

#extension GL_EXT_control_flow_attributes : require
#ifdef USE_RAY_QUERY
#extension GL_EXT_ray_query : require
#endif
#include "shared.h"

layout(local_size_x = WORKGROUP_SIZE_X, local_size_y = WORKGROUP_SIZE_Y, local_size_z = 1) in;

// Samples per pixel per frame (the workshop's SAMPLE_COUNT).
layout(constant_id = SPEC_SAMPLE_COUNT) const int SAMPLE_COUNT = 1;
// Maximum number of surface hits per path (the workshop's MAX_PATH_LENGTH).
layout(constant_id = SPEC_MAX_PATH_LENGTH) const int MAX_PATH_LENGTH = DEFAULT_MAX_PATH_LENGTH;
// PIXEL_FILTER_BOX or PIXEL_FILTER_CENTER.
layout(constant_id = SPEC_PIXEL_FILTER) const int PIXEL_FILTER = PIXEL_FILTER_BOX;
// INTEGRATOR_PATH_TRACING, INTEGRATOR_DIRECT_ILLUMINATION or INTEGRATOR_RAY_TRACING.
layout(constant_id = SPEC_INTEGRATOR) const int INTEGRATOR = INTEGRATOR_PATH_TRACING;
// Path vertex after which Russian roulette may end a path (importance-sampled integrators
// only); 0 turns it off.
layout(constant_id = SPEC_RUSSIAN_ROULETTE_START) const int RUSSIAN_ROULETTE_START = 0;
// SAMPLER_PCG or SAMPLER_SOBOL: the random numbers of the importance-sampled integrators
// (and of their pixel jitter); the workshop integrators always use PCG2D.
layout(constant_id = SPEC_SAMPLER) const int SAMPLER = SAMPLER_PCG;
// LIGHT_SAMPLING_AREA or LIGHT_SAMPLING_SOLID_ANGLE: how nee and mis sample their lights.
layout(constant_id = SPEC_LIGHT_SAMPLING) const int LIGHT_SAMPLING = LIGHT_SAMPLING_SOLID_ANGLE;
// 1 where the camera has a thin lens (glsl/thin_lens.glsl); 0 compiles the lens out.
layout(constant_id = SPEC_THIN_LENS) const int THIN_LENS = 0;
// LIGHT_SELECTION_POWER or LIGHT_SELECTION_TREE: how nee and mis choose the emissive
// triangle they sample (the tree's code is compiled out of power kernels). The lean builds
// (WITHOUT_LIGHT_TREE) hold a constant instead, so that their SPIR-V carries none of the
// tree's code: lavapipe translates a kernel's whole SPIR-V at every start, dead code too.
#ifdef WITHOUT_LIGHT_TREE
const int LIGHT_SELECTION = LIGHT_SELECTION_POWER;
#else
layout(constant_id = SPEC_LIGHT_SELECTION) const int LIGHT_SELECTION = LIGHT_SELECTION_POWER;
#endif
// LLVMPIPE_LOOP_LIMIT / LLVMPIPE_SIMD_WIDTH on lavapipe, 0 elsewhere.
layout(constant_id = SPEC_LOOP_LIMIT) const uint LOOP_LIMIT = 0u;
// The bound's coefficients, which the host derives from its description of this kernel's
// loops (src/kernels/loops.rs, whose test fails when a loop is not described there).
layout(constant_id = SPEC_LOOPS_PER_SAMPLE) const uint LOOPS_PER_SAMPLE = 0u;
layout(constant_id = SPEC_LOOPS_PER_RAY) const uint LOOPS_PER_RAY = 0u;
layout(constant_id = SPEC_LIGHT_SEARCHES_PER_RAY) const uint LIGHT_SEARCHES_PER_RAY = 0u;
layout(constant_id = SPEC_TRIANGLE_LOOPS_PER_RAY) const uint TRIANGLE_LOOPS_PER_RAY = 0u;
// GUIDING_OFF, GUIDING_ON or GUIDING_TRAINING: path guiding (glsl/path_guiding.glsl), compiled
// out when off, its training only in GUIDING_TRAINING; a constant GUIDING_OFF in the lean
// builds (WITHOUT_GUIDING), which carry none of its code.
#ifdef WITHOUT_GUIDING
const int GUIDING = GUIDING_OFF;
#else
layout(constant_id = SPEC_GUIDING) const int GUIDING = GUIDING_OFF;
#endif

// What changes per frame. Mirrors `vkpath::render::gpu_types::FramePushConstants`.
layout(push_constant) uniform frame_push_constants {
    // Index of the first sample this frame adds to each pixel.
    uint g_first_sample_index;
    // Samples with an index at or past this are not taken (the render's total spp).
    uint g_sample_end;
    // The full image's pixel (column, row from the top) of the accumulation image's texel
    // (0, 0): the corner of the region (--region) or tile this dispatch renders.
    uvec2 g_pixel_offset;
    // Width and height of that region or tile; texels beyond are not touched.
    uvec2 g_pixel_extent;
    // --noise-threshold: a pixel takes no more samples once is_pixel_converged() says so,
    // judged every g_noise_min_samples samples (is_noise_check_due()); 0 turns adaptive
    // sampling off.
    float g_noise_threshold;
    uint g_noise_min_samples;
};

#include "integrator.glsl"
#include "integrators.glsl"
#ifdef USE_BVH
#include "bvh.glsl"
#endif
#ifdef USE_RAY_QUERY
#include "ray_query.glsl"
#endif
#include "camera.glsl"
#include "thin_lens.glsl"
#include "motion_time.glsl"
#include "adaptive_sampling.glsl"
#include "path_loop.glsl"
#ifdef USER_FUNCTIONS
#include "user_functions.glsl"
#endif

layout(set = 0, binding = BINDING_ACCUMULATION, rgba32f) uniform image2DArray g_accumulation;
layout(set = 0, binding = BINDING_CONVERGED_PIXELS, std430) buffer converged_pixels {
    uint g_converged_pixel_count;
};


// One sample of the radiance through a pixel with the chosen integrator.
// \param camera_position Origin of the camera ray: the pinhole, or a point of the lens
vec3 get_sample_radiance(vec3 camera_position, vec3 ray_direction, inout uvec2 seed) {
#ifdef USE_MATERIALS
    // The sample's alpha coverage (glsl/materials.glsl)
    g_path.alpha_seed = seed;
#else
    // On the workshop's diffuse triangles, its own estimators, as its exercises write them
    // (glsl/integrator.glsl); on glTF materials the path loop runs them.
    if (INTEGRATOR == INTEGRATOR_PATH_TRACING)
        return get_ray_radiance(camera_position, ray_direction, seed);
    if (INTEGRATOR == INTEGRATOR_DIRECT_ILLUMINATION) {
        float t;
        triangle_t triangle;
        if (!ray_mesh_intersection(t, triangle, camera_position, ray_direction))
            return vec3(0.0);
        orient_towards_ray(triangle, ray_direction, is_double_sided(g_hit_triangle_index));
        return compute_direct_illumination(camera_position + t * ray_direction, triangle, seed);
    }
#endif
    // (ray tracing, normal, depth and material too: the loop returns their first hit's view)
    return get_path_radiance(camera_position, ray_direction, seed);
}

void main() {
    uvec2 resolution = g_resolution_triangle_count_seed.xy;
    // The accumulation image holds a region or tile of the image: its texel `texel` is the
    // full image's pixel `image_texel`, which alone decides the samples (seeds, jitter).
    uvec2 texel = gl_GlobalInvocationID.xy;
    uvec2 image_texel = texel + g_pixel_offset;
    if (texel.x >= g_pixel_extent.x || texel.y >= g_pixel_extent.y || image_texel.x >= resolution.x || image_texel.y >= resolution.y)
        return;
    // Image rows run top-down; ShaderToy counts pixels from the bottom-left.
    uvec2 pixel = uvec2(image_texel.x, resolution.y - 1u - image_texel.y);

    // Only what the samples change is held across them; what they leave as it was (the ray
    // count, the loop-limit flag, the sample count before them) is loaded again after the
    // loop, so that fewer registers live through the path tracer (GPU occupancy).
    vec4 sum = imageLoad(g_accumulation, ivec3(texel, LAYER_SUM));
    precise vec3 compensation = imageLoad(g_accumulation, ivec3(texel, LAYER_COMPENSATION)).rgb;
    vec3 sum_of_squares = imageLoad(g_accumulation, ivec3(texel, LAYER_SUM_OF_SQUARES)).rgb;
    // Not unrolled: one copy of the path tracer compiles faster and runs as fast.
    [[dont_unroll]] for (int i = 0; i != SAMPLE_COUNT; ++i) {
        uint sample_index = g_first_sample_index + uint(i);
        if (sample_index >= g_sample_end)
            break;
        // Adaptive sampling decides from the pixel's state alone, before each sample, so the
        // image does not depend on how samples are split into frames.
        if (g_noise_threshold > 0.0 && is_noise_check_due(sum.a, g_noise_min_samples)
            && is_pixel_converged(sum.rgb - compensation, sum.a, sum_of_squares, g_noise_threshold))
            break;
        uvec2 seed = get_sample_seed(pixel, sample_index, g_resolution_triangle_count_seed.w);
        // The sample that the importance-sampled integrators' numbers belong to
        // (glsl/sobol.glsl); the workshop's integrators draw from `seed`.
        g_path.sample_index = sample_index;
        g_path.pixel_seed = get_sobol_pixel_seed(pixel, g_resolution_triangle_count_seed.w);
        // The importance-sampled integrators draw their jitter at CAMERA_PAIR_PIXEL
        // (glsl/sample_dimensions.glsl); the workshop's stay on PCG2D, exactly.
        vec2 tex_coord = (is_importance_sampled() && PIXEL_FILTER == PIXEL_FILTER_BOX)
            ? (vec2(pixel) + get_path_random_numbers(CAMERA_PAIR_PIXEL)) / vec2(resolution)
            : get_sample_tex_coord(pixel, resolution, seed);
        vec3 ray_origin;
        vec3 ray_direction;
        // Motion blur (glsl/motion_time.glsl): the sample's time in the shutter, which the
        // triangles and the lights are read at, and the camera's ray (lens and all) at that time
        if (MOTION_STEPS != 0u)
            get_moving_camera_ray(ray_origin, ray_direction, tex_coord, get_sample_seed(pixel, sample_index, g_resolution_triangle_count_seed.w));
        else {
            ray_direction = get_primary_ray_direction(tex_coord.x, tex_coord.y, g_camera_position.xyz, g_left_bottom.xyz, g_right.xyz, g_up.xyz);
            ray_origin = g_camera_position.xyz;
            // Depth of field (glsl/thin_lens.glsl): the lens's ray instead of the pinhole's
            if (THIN_LENS != 0 && g_camera_position.w > 0.0) {
                vec2 lens_random_numbers = get_lens_random_numbers(get_sample_seed(pixel, sample_index, g_resolution_triangle_count_seed.w));
                vec3 image_plane_middle = g_left_bottom.xyz + 0.5 * (g_right.xyz + g_up.xyz);
                apply_thin_lens(ray_origin, ray_direction, g_right.xyz, g_up.xyz, image_plane_middle, g_camera_position.w, g_left_bottom.w, uint(g_right.w), g_up.w, lens_random_numbers);
            }
        }
        vec3 radiance = get_sample_radiance(ray_origin, ray_direction, seed);
        // Kahan summation: the sum stays within a few ulps however many samples it holds.
        // `precise` forbids the compiler to reassociate or fuse these operations.
        precise vec3 corrected = radiance - compensation;
        precise vec3 new_sum = sum.rgb + corrected;
        compensation = (new_sum - sum.rgb) - corrected;
        sum.rgb = new_sum;
        sum.a += 1.0;
        sum_of_squares += radiance * radiance;
    }
    float samples_before = imageLoad(g_accumulation, ivec3(texel, LAYER_SUM)).a;
    float rays_before = imageLoad(g_accumulation, ivec3(texel, LAYER_COMPENSATION)).a;
    float sum_of_squares_flag = imageLoad(g_accumulation, ivec3(texel, LAYER_SUM_OF_SQUARES)).a;
    // --noise-threshold: a pixel whose samples in this dispatch made it converged counts once
    // (BINDING_CONVERGED_PIXELS); from the next dispatch on it takes no sample, so never again.
    if (g_noise_threshold > 0.0 && sum.a > samples_before && is_noise_check_due(sum.a, g_noise_min_samples)
        && is_pixel_converged(sum.rgb - compensation, sum.a, sum_of_squares, g_noise_threshold))
        atomicAdd(g_converged_pixel_count, 1u);
    // llvmpipe ends the loops of a SIMD program once they have run LLVMPIPE_LOOP_LIMIT trips
    // all together, without an error; a program's iterations are at most LLVMPIPE_SIMD_WIDTH times
    // the largest lane's (see shared.h). An upper bound of this lane's iterations, with the
    // coefficients of src/kernels/loops.rs: per sample; per ray (g_path.ray_count) the path loop's,
    // the light search's (get_light_search_iterations()) and the loops over all
    // triangles; and what the BVH's traversal counted itself. Reaching LOOP_LIMIT flags the
    // pixel; the host refuses a flagged image.
    if (LOOP_LIMIT != 0u) {
        uint per_ray = LOOPS_PER_RAY + LIGHT_SEARCHES_PER_RAY * get_light_search_iterations()
            + TRIANGLE_LOOPS_PER_RAY * g_resolution_triangle_count_seed.z;
        uint samples = min(uint(SAMPLE_COUNT), g_sample_end - min(g_first_sample_index, g_sample_end));
        uint iterations = LOOPS_PER_SAMPLE * samples + g_path.ray_count * per_ray + g_path.traversal_iterations;
        if (iterations >= LOOP_LIMIT || g_path.ray_count * per_ray >= LOOP_LIMIT)
            sum_of_squares_flag = 1.0;
    }
#ifdef USER_FUNCTIONS
    // vkpath check: the user's loops ran past their limit (an endless loop)
    if (g_user_loop_limit_hit)
        sum_of_squares_flag = 1.0;
#endif
    imageStore(g_accumulation, ivec3(texel, LAYER_SUM), sum);
    // Ray counts are exact in a float up to 2^24 per pixel, far beyond what a benchmark takes.
    imageStore(g_accumulation, ivec3(texel, LAYER_COMPENSATION), vec4(compensation, rays_before + float(g_path.ray_count)));
    imageStore(g_accumulation, ivec3(texel, LAYER_SUM_OF_SQUARES), vec4(sum_of_squares, sum_of_squares_flag));
}
