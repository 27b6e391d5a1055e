// The scene as the shaders see it: the triangle buffer, the render uniforms, and the
// workshop's ray_mesh_intersection() over all triangles. The workshop keeps its 30 triangles
// in a constant array; here they come from a texel buffer, and for scenes of up to 64
// triangles their positions are also compiled in (constant_triangles.glsl), as constants.
#ifndef VKPATH_SCENE_GLSL
#define VKPATH_SCENE_GLSL

#include "shared.h"
#include "workshop.glsl"

// triangle_t as stored on the GPU: std430 with every member 16-byte aligned (no bare vec3).
// Mirrors `vkpath::render::gpu_types::GpuTriangle`, whose layout test checks these offsets.
struct packed_triangle_t {
    // xyz: v_0, v_1, v_2 (world space); w: unused (0)
    vec4 positions[3];
    // xyz: unit normal (world space, the side the vertices are counter-clockwise from);
    // w: unused (0)
    vec4 normal;
    // rgb: albedo (linear RGB in [0, 1]); a: unused (0)
    vec4 color;
    // rgb: emitted radiance (linear RGB); a: flags (TRIANGLE_FLAG_*) as float bits
    vec4 emission;
};

// The triangles: a texel buffer of RGBA32_UINT, TRIANGLE_TEXEL_COUNT texels per triangle in
// the member order of packed_triangle_t. On lavapipe a texel fetch is a vector gather, faster
// than both alternatives measured: a storage-buffer load at a per-lane index is a loop over
// lanes with a bounds check per component, and a uniform-buffer load an 8-lane gather of
// scalar loads (docs/performance.md).
layout(set = 0, binding = BINDING_TRIANGLES) uniform utextureBuffer g_triangle_texels;

// Motion blur: the number of keys across the shutter (SPEC_MOTION_STEPS in glsl/shared.h), 0
// without motion blur (the keys' code then folds away and every triangle is read as before).
layout(constant_id = SPEC_MOTION_STEPS) const uint MOTION_STEPS = 0u;

// Motion blur: the sample's time within the shutter, in [0, 1] (0: the shutter opens), set
// by main() before each sample when MOTION_STEPS != 0 (glsl/motion_time.glsl); the whole
// path (camera, bounces, shadow rays, light samples) sees the scene at this time.
float g_motion_time = 0.0;

// Defined below: triangle i at g_motion_time (motion blur).
packed_triangle_t get_moving_packed_triangle(uint index);

// Triangle i of the scene as stored on the GPU. Members that the caller does not use are
// never read (the compiler drops their loads). With motion blur, at g_motion_time
// (get_moving_packed_triangle()).
packed_triangle_t get_packed_triangle(uint index) {
    if (MOTION_STEPS != 0u)
        return get_moving_packed_triangle(index);
    int first = int(uint(TRIANGLE_TEXEL_COUNT) * index);
    packed_triangle_t packed;
    packed.positions[0] = uintBitsToFloat(texelFetch(g_triangle_texels, first));
    packed.positions[1] = uintBitsToFloat(texelFetch(g_triangle_texels, first + 1));
    packed.positions[2] = uintBitsToFloat(texelFetch(g_triangle_texels, first + 2));
    packed.normal = uintBitsToFloat(texelFetch(g_triangle_texels, first + 3));
    packed.color = uintBitsToFloat(texelFetch(g_triangle_texels, first + 4));
    packed.emission = uintBitsToFloat(texelFetch(g_triangle_texels, first + 5));
    return packed;
}

// What stays fixed during a render. Mirrors `vkpath::render::gpu_types::RenderUniforms`.
layout(std140, set = 0, binding = BINDING_RENDER_UNIFORMS) uniform render_uniforms {
    // The pinhole camera (see get_primary_ray_direction()), world space, and in the w
    // components its thin lens (glsl/thin_lens.glsl): g_camera_position.w the aperture radius
    // (0: a pinhole), g_left_bottom.w the focus distance, g_right.w the number of aperture
    // blades (0: a disc), g_up.w the aperture's rotation in radians.
    vec4 g_camera_position;
    vec4 g_left_bottom;
    vec4 g_right;
    vec4 g_up;
    // x: image width, y: image height (pixels), z: triangle count, w: user seed
    uvec4 g_resolution_triangle_count_seed;
};

// Unpacks a triangle as stored on the GPU into the workshop's struct.
triangle_t unpack_triangle(packed_triangle_t packed) {
    triangle_t triangle;
    triangle.positions[0] = packed.positions[0].xyz;
    triangle.positions[1] = packed.positions[1].xyz;
    triangle.positions[2] = packed.positions[2].xyz;
    triangle.normal = packed.normal.xyz;
    triangle.color = packed.color.rgb;
    triangle.emission = packed.emission.rgb;
    return triangle;
}

// Unpacks triangle i of the scene into the workshop's struct.
triangle_t get_triangle(uint index) {
    return unpack_triangle(get_packed_triangle(index));
}

// Whether triangle i emits from both sides (TRIANGLE_FLAG_DOUBLE_SIDED).
bool is_double_sided(uint index) {
    return (floatBitsToUint(get_packed_triangle(index).emission.a) & TRIANGLE_FLAG_DOUBLE_SIDED) != 0u;
}

// Barycentric coordinates (b_0, b_1, b_2) of a point in a triangle's plane (the material
// kernels' texture coordinates and normals, the ground-truth pass INTEGRATOR_TRIANGLE).
vec3 get_barycentrics(vec3 position, triangle_t triangle) {
    vec3 edge_1 = triangle.positions[1] - triangle.positions[0];
    vec3 edge_2 = triangle.positions[2] - triangle.positions[0];
    vec3 offset = position - triangle.positions[0];
    vec3 normal = cross(edge_1, edge_2);
    float inverse_squared_area = 1.0 / dot(normal, normal);
    float b_1 = dot(cross(offset, edge_2), normal) * inverse_squared_area;
    float b_2 = dot(cross(edge_1, offset), normal) * inverse_squared_area;
    return vec3(1.0 - b_1 - b_2, b_1, b_2);
}

// The hit triangle's index, the ray count and the traversal's iterations
#include "path_state.glsl"

// The two keys around a time of the shutter and the fraction between them: the keys are
// evenly spread, key k at time k / (MOTION_STEPS - 1), and the scene moves linearly between
// two keys (Embree's and Cycles' linear motion blur).
// \param time The time within the shutter, in [0, 1]
// \param out_key The key at or before the time, 0 .. MOTION_STEPS - 2
// \return The fraction of the way from key out_key to key out_key + 1, in [0, 1]
float get_motion_segment(float time, out uint out_key) {
    float scaled = clamp(time, 0.0, 1.0) * float(MOTION_STEPS - 1u);
    out_key = min(uint(scaled), MOTION_STEPS - 2u);
    return scaled - float(out_key);
}

// The texel of BINDING_TRIANGLES where the motion records start (see glsl/shared.h).
int get_motion_texel_offset(uint triangle_count) {
    return int(uint(TRIANGLE_TEXEL_COUNT) * triangle_count);
}

// Motion blur: triangle i as stored on the GPU with its vertices and normal those of the
// keys around g_motion_time, interpolated linearly (the normal renormalized).
packed_triangle_t get_moving_packed_triangle(uint index) {
    int first = int(uint(TRIANGLE_TEXEL_COUNT) * index);
    packed_triangle_t packed;
    packed.color = uintBitsToFloat(texelFetch(g_triangle_texels, first + 4));
    packed.emission = uintBitsToFloat(texelFetch(g_triangle_texels, first + 5));
    uint key;
    float fraction = get_motion_segment(g_motion_time, key);
    uint triangle_count = g_resolution_triangle_count_seed.z;
    int before = get_motion_texel_offset(triangle_count) + MOTION_TRIANGLE_TEXEL_COUNT * int(index * MOTION_STEPS + key);
    int after = before + MOTION_TRIANGLE_TEXEL_COUNT;
    packed.positions[0] = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before)), uintBitsToFloat(texelFetch(g_triangle_texels, after)), fraction);
    packed.positions[1] = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before + 1)), uintBitsToFloat(texelFetch(g_triangle_texels, after + 1)), fraction);
    packed.positions[2] = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before + 2)), uintBitsToFloat(texelFetch(g_triangle_texels, after + 2)), fraction);
    vec3 normal = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before + 3)).xyz, uintBitsToFloat(texelFetch(g_triangle_texels, after + 3)).xyz, fraction);
    packed.normal = vec4(normalize(normal), 0.0);
    return packed;
}

// Motion blur: the camera at g_motion_time, interpolated linearly between the keys' cameras
// (glsl/shared.h's motion records), as render_uniforms holds it (w: the lens).
void get_camera_at_time(out vec4 out_position, out vec4 out_left_bottom, out vec4 out_right, out vec4 out_up) {
    uint key;
    float fraction = get_motion_segment(g_motion_time, key);
    uint triangle_count = g_resolution_triangle_count_seed.z;
    int before = get_motion_texel_offset(triangle_count) + MOTION_TRIANGLE_TEXEL_COUNT * int(MOTION_STEPS * triangle_count) + MOTION_CAMERA_TEXEL_COUNT * int(key);
    int after = before + MOTION_CAMERA_TEXEL_COUNT;
    out_position = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before)), uintBitsToFloat(texelFetch(g_triangle_texels, after)), fraction);
    out_left_bottom = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before + 1)), uintBitsToFloat(texelFetch(g_triangle_texels, after + 1)), fraction);
    out_right = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before + 2)), uintBitsToFloat(texelFetch(g_triangle_texels, after + 2)), fraction);
    out_up = mix(uintBitsToFloat(texelFetch(g_triangle_texels, before + 3)), uintBitsToFloat(texelFetch(g_triangle_texels, after + 3)), fraction);
}

#include "constant_triangles.glsl"

#ifdef IGNORE_START_SURFACE
// Whether a ray starts on the plane of a triangle (`vkpath check` only, in kernels built with
// IGNORE_START_SURFACE). The workshop's path loop moves the origin to the hit point,
// x_{j+1} = x_j + t_j omega_j, without an offset, so with intersections that accept t >= 0
// the next ray may hit the surface it starts on again through rounding. check judges the
// user's estimator with intersections that ignore that surface: a ray leaving a plane
// cannot hit it again, so skipping it changes no correct estimate (only rays starting
// within 1e-5 relative of a triangle's plane, i.e. on it, skip that triangle).
// \param ray_origin The ray's origin, world space
// \param triangle The triangle, world space
bool starts_on_triangle_plane(vec3 ray_origin, triangle_t triangle) {
    vec3 normal = cross(triangle.positions[1] - triangle.positions[0], triangle.positions[2] - triangle.positions[0]);
    vec3 magnitude = abs(ray_origin);
    float scale = max(1.0, max(magnitude.x, max(magnitude.y, magnitude.z)));
    return abs(dot(ray_origin - triangle.positions[0], normal)) <= 1.0e-5 * scale * length(normal);
}
// ray_triangle_intersection(), skipping the triangle the ray starts on.
#define RAY_HITS_TRIANGLE(out_t, ray_origin, ray_direction, triangle) \
    (!starts_on_triangle_plane(ray_origin, triangle) && ray_triangle_intersection(out_t, ray_origin, ray_direction, triangle))
#else
// ray_triangle_intersection() (the loops below call it through this macro, which kernels
// built for `vkpath check` with IGNORE_START_SURFACE replace).
#define RAY_HITS_TRIANGLE(out_t, ray_origin, ray_direction, triangle) \
    ray_triangle_intersection(out_t, ray_origin, ray_direction, triangle)
#endif

#ifdef USE_MATERIALS
// Whether a candidate hit counts, for alpha-masked and alpha-blended materials
// (glsl/materials.glsl); kernels without materials test no alpha, and the macro vanishes.
bool is_opaque_hit(uint triangle_index, vec3 ray_origin, vec3 ray_direction, float t);
// Whether any material uses alpha (the host specializes it; false compiles the test out).
layout(constant_id = SPEC_SCENE_HAS_ALPHA) const bool SCENE_HAS_ALPHA = true;
#define AND_HIT_IS_OPAQUE(index, ray_origin, ray_direction, t) && (!SCENE_HAS_ALPHA || is_opaque_hit(index, ray_origin, ray_direction, t))
#else
#define AND_HIT_IS_OPAQUE(index, ray_origin, ray_direction, t)
#endif

#ifdef USE_BVH
// Defined in bvh.glsl, which kernels built with USE_BVH include.
bool bvh_closest_hit(out float out_t, out uint out_triangle_index, vec3 ray_origin, vec3 ray_direction);
bool bvh_any_hit(vec3 ray_origin, vec3 ray_direction, float t_max);
#endif
#ifdef USE_RAY_QUERY
// Defined in ray_query.glsl, which kernels built with USE_RAY_QUERY include.
bool ray_query_closest_hit(out float out_t, out uint out_triangle_index, vec3 ray_origin, vec3 ray_direction);
bool ray_query_any_hit(vec3 ray_origin, vec3 ray_direction, float t_max);
#endif

#ifndef USER_DEFINES_RAY_MESH_INTERSECTION
// Finds the closest triangle that a ray hits (Part 1): brute force over all triangles, or,
// in kernels built with USE_BVH, by traversing the BVH with the same triangle tests, or, in
// kernels built with USE_RAY_QUERY, with the device's acceleration structure.
// \param out_t Ray parameter of the closest hit
// \param out_triangle The triangle that was hit
// \param ray_origin, ray_direction The ray, world space
// \return true iff any triangle was hit; then g_hit_triangle_index names the triangle
bool ray_mesh_intersection(out float out_t, out triangle_t out_triangle, vec3 ray_origin, vec3 ray_direction) {
    ++g_path.ray_count;
#if defined(USE_RAY_QUERY)
    uint hit_index;
    bool hit = ray_query_closest_hit(out_t, hit_index, ray_origin, ray_direction);
#elif defined(USE_BVH)
    uint hit_index;
    bool hit = bvh_closest_hit(out_t, hit_index, ray_origin, ray_direction);
#else
    out_t = NO_HIT_T;
    uint hit_index = 0u;
    bool hit = false;
    if (CONSTANT_TRIANGLE_COUNT != 0u) {
        // The same loop, unrolled over the constant triangles (of a scene without alpha:
        // Traversal::choose, so no alpha test, whose code would be unrolled too)
#define TEST_CONSTANT_TRIANGLE(i) \
        if (i < CONSTANT_TRIANGLE_COUNT) { \
            float t; \
            if (RAY_HITS_TRIANGLE(t, ray_origin, ray_direction, GET_CONSTANT_TRIANGLE(i)) && t < out_t) { \
                out_t = t; \
                hit_index = i; \
                hit = true; \
            } \
        }
        FOR_EACH_TESTED_CONSTANT_TRIANGLE(TEST_CONSTANT_TRIANGLE)
#undef TEST_CONSTANT_TRIANGLE
    } else {
        uint triangle_count = g_resolution_triangle_count_seed.z;
        for (uint i = 0u; i != triangle_count; ++i) {
            float t;
            if (RAY_HITS_TRIANGLE(t, ray_origin, ray_direction, get_triangle(i)) && t < out_t AND_HIT_IS_OPAQUE(i, ray_origin, ray_direction, t)) {
                out_t = t;
                hit_index = i;
                hit = true;
            }
        }
    }
#endif
    if (hit) {
        out_triangle = get_triangle(hit_index);
        g_path.hit_triangle_index = hit_index;
    }
    return hit;
}
#endif

// Whether a ray hits any triangle at a ray parameter t < t_max (vkpath's addition, for
// shadow rays): it may stop at the first such hit instead of finding the closest.
bool ray_mesh_any_hit(vec3 ray_origin, vec3 ray_direction, float t_max) {
    ++g_path.ray_count;
#if defined(USE_RAY_QUERY)
    return ray_query_any_hit(ray_origin, ray_direction, t_max);
#elif defined(USE_BVH)
    return bvh_any_hit(ray_origin, ray_direction, t_max);
#else
    if (CONSTANT_TRIANGLE_COUNT != 0u) {
#define TEST_CONSTANT_TRIANGLE(i) \
        if (i < CONSTANT_TRIANGLE_COUNT) { \
            float t; \
            if (ray_triangle_intersection(t, ray_origin, ray_direction, GET_CONSTANT_TRIANGLE(i)) && t < t_max) \
                return true; \
        }
        FOR_EACH_TESTED_CONSTANT_TRIANGLE(TEST_CONSTANT_TRIANGLE)
#undef TEST_CONSTANT_TRIANGLE
        return false;
    }
    uint triangle_count = g_resolution_triangle_count_seed.z;
    for (uint i = 0u; i != triangle_count; ++i) {
        float t;
        if (ray_triangle_intersection(t, ray_origin, ray_direction, get_triangle(i)) && t < t_max AND_HIT_IS_OPAQUE(i, ray_origin, ray_direction, t))
            return true;
    }
    return false;
#endif
}

#endif
