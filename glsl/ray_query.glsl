// Ray traversal by the device's own acceleration structures (VK_KHR_ray_query with
// VK_KHR_acceleration_structure), in the same compute kernel: the closest hit and the any-hit
// query of shadow rays, the hardware twins of bvh_closest_hit() and bvh_any_hit()
// (glsl/bvh.glsl). The host (src/accel/) builds one bottom-level structure per mesh (and
// world-space ones over the triangles no mesh copy covers) and a top-level structure of
// instances above them, each instance's custom index being its first triangle's index in
// g_triangle_texels (the scene's order), so that custom index + primitive index is the
// triangle index the shading code reads: only the traversal differs from the BVH builds, the
// hit's shading data come from the same buffers.
// The software BVH is this file's reference (tests/ray_query_cli.rs compares their images).
#ifndef VKPATH_RAY_QUERY_GLSL
#define VKPATH_RAY_QUERY_GLSL

#include "shared.h"
#include "scene.glsl"

// The scene's top-level acceleration structure (builds with USE_RAY_QUERY).
layout(set = 0, binding = BINDING_ACCELERATION_STRUCTURE) uniform accelerationStructureEXT g_acceleration_structure;

// The ray parameters a query accepts: the workshop's ray_triangle_intersection() accepts
// t >= 0 (the path loop offsets its origins itself), so the hardware query starts at 0 too.
#define RAY_QUERY_T_MIN 0.0

// Whether a ray may start a query: Vulkan leaves queries of rays with a non-finite origin or
// direction undefined (the BVH's slab tests simply find nothing for them, and so do these).
bool is_ray_query_defined(vec3 ray_origin, vec3 ray_direction) {
    bvec3 bad = bvec3(uvec3(isnan(ray_origin)) | uvec3(isinf(ray_origin)) | uvec3(isnan(ray_direction)) | uvec3(isinf(ray_direction)));
    return !any(bad);
}

// The triangle index of a query's candidate (committed: false) or committed (true) hit. A
// macro, as is CONFIRM_OPAQUE_CANDIDATE, so that each query stays a local object of the one
// function that initializes and runs it.
#define GET_RAY_QUERY_TRIANGLE_INDEX(query, committed) \
    (uint(rayQueryGetIntersectionInstanceCustomIndexEXT(query, committed)) \
        + uint(rayQueryGetIntersectionPrimitiveIndexEXT(query, committed)))

// One step of a query's loop (`while (rayQueryProceedEXT(query))`): a candidate on
// non-opaque geometry (alpha-tested materials; the host marks the geometry opaque where no
// material uses alpha, and then none comes) is confirmed where is_opaque_hit() says it counts,
// as the BVH's AND_HIT_IS_OPAQUE() test does. Each step counts one traversal iteration; the
// device's own loop inside a step is not counted (src/kernels/loops.rs estimates it).
#define CONFIRM_OPAQUE_CANDIDATE(query, ray_origin, ray_direction) \
    ++g_path.traversal_iterations; \
    if (rayQueryGetIntersectionTypeEXT(query, false) == gl_RayQueryCandidateIntersectionTriangleEXT) { \
        uint candidate_index = GET_RAY_QUERY_TRIANGLE_INDEX(query, false); \
        float candidate_t = rayQueryGetIntersectionTEXT(query, false); \
        if (true AND_HIT_IS_OPAQUE(candidate_index, ray_origin, ray_direction, candidate_t)) \
            rayQueryConfirmIntersectionEXT(query); \
    }

// Finds the closest triangle that a ray hits with the device's acceleration structure.
// \param out_t Ray parameter of the closest hit (NO_HIT_T if none): the workshop's
//        ray_triangle_intersection() of the hit triangle where it accepts the hit, so that
//        the hit point is computed as the BVH builds compute it, else the device's t
// \param out_triangle_index Index of the hit triangle in g_triangles (0 if none)
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \return true iff a triangle was hit at 0 <= t < NO_HIT_T
bool ray_query_closest_hit(out float out_t, out uint out_triangle_index, vec3 ray_origin, vec3 ray_direction) {
    out_t = NO_HIT_T;
    out_triangle_index = 0u;
    if (!is_ray_query_defined(ray_origin, ray_direction))
        return false;
    rayQueryEXT query;
    rayQueryInitializeEXT(query, g_acceleration_structure, gl_RayFlagsNoneEXT, 0xff, ray_origin, RAY_QUERY_T_MIN, ray_direction, NO_HIT_T);
    while (rayQueryProceedEXT(query)) {
        CONFIRM_OPAQUE_CANDIDATE(query, ray_origin, ray_direction)
    }
    if (rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionTriangleEXT)
        return false;
    out_triangle_index = GET_RAY_QUERY_TRIANGLE_INDEX(query, true);
    out_t = rayQueryGetIntersectionTEXT(query, true);
    float t;
    if (ray_triangle_intersection(t, ray_origin, ray_direction, get_triangle(out_triangle_index)))
        out_t = t;
    return true;
}

// Whether a ray hits any triangle at t < t_max (shadow rays), ending at the first hit found.
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \param t_max Hits at or beyond this ray parameter do not count
// \return true iff some triangle is hit at 0 <= t < t_max
bool ray_query_any_hit(vec3 ray_origin, vec3 ray_direction, float t_max) {
    if (!(t_max > RAY_QUERY_T_MIN) || !is_ray_query_defined(ray_origin, ray_direction))
        return false;
    rayQueryEXT query;
    rayQueryInitializeEXT(query, g_acceleration_structure, gl_RayFlagsTerminateOnFirstHitEXT, 0xff, ray_origin, RAY_QUERY_T_MIN, ray_direction, min(t_max, NO_HIT_T));
    while (rayQueryProceedEXT(query)) {
        CONFIRM_OPAQUE_CANDIDATE(query, ray_origin, ray_direction)
    }
    return rayQueryGetIntersectionTypeEXT(query, true) == gl_RayQueryCommittedIntersectionTriangleEXT;
}

#endif
