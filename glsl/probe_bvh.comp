#version 460
// Probe of the BVH traversal (glsl/bvh.glsl): for each ray, bvh_closest_hit(), bvh_any_hit(),
// bvh_inverse_direction() and bvh_ray_box_intersection() with the root's box, and, for
// comparison on the GPU itself, the brute-force ray_mesh_intersection() of scene.glsl. Host
// side: tests/bvh_gpu.rs, which compares with the Rust twins.
//
// Descriptor set 0, as the BVH path tracer binds it: BINDING_TRIANGLES (texel buffer,
// reordered by the BVH builder), BINDING_RENDER_UNIFORMS (.z: triangle count, for the brute
// force), BINDING_BVH_NODES and BINDING_TRAVERSAL_TRIANGLES (texel buffers, the latter in the
// same order as the triangles), then BVH_PROBE_BINDING_RAYS and
// BVH_PROBE_BINDING_RESULTS (storage buffers).

#include "shared.h"

layout(local_size_x = PROBE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

#include "scene.glsl"
// Two stack entries of the compressed tree's traversal in registers, not the path tracer's 8:
// the test trees are shallow, and the rest of the stack, in shared memory, is tested too.
#define CWBVH_REGISTER_STACK_SIZE 2
#include "bvh.glsl"

// Whether to run the brute-force ray_mesh_intersection() too (0 or 1): it costs a test of
// every triangle per ray, too slow on lavapipe for large scenes.
layout(constant_id = BVH_PROBE_SPEC_BRUTE_FORCE) const int BVH_PROBE_BRUTE_FORCE = 1;

struct bvh_probe_ray_t {
    vec4 origin_t_max; // xyz: ray origin (world space), w: t_max of the bvh_any_hit() query
    vec4 direction;    // xyz: ray direction (world space), w: unused
};

struct bvh_probe_result_t {
    // bvh_closest_hit(): x: out_t as float bits, y: out_triangle_index, z: 1 iff hit,
    // w: bvh_any_hit() 1 iff hit
    uvec4 bvh;
    // ray_mesh_intersection(): x: out_t as float bits, y: g_hit_triangle_index, z: 1 iff hit,
    // w: 0 (all 0 when BVH_PROBE_BRUTE_FORCE is 0)
    uvec4 brute_force;
    // xyz: bvh_inverse_direction(), w: out_t_entry of bvh_ray_box_intersection() with the
    // box of the root's first child and t_max (0 when there are no nodes)
    vec4 inverse_direction_root_entry;
    // x: 1 iff that box test hit; yzw: 0
    uvec4 root_hit;
};

layout(std430, set = 0, binding = BVH_PROBE_BINDING_RAYS) readonly buffer bvh_probe_rays {
    bvh_probe_ray_t g_probe_rays[];
};
layout(std430, set = 0, binding = BVH_PROBE_BINDING_RESULTS) writeonly buffer bvh_probe_results {
    bvh_probe_result_t g_probe_results[];
};

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(g_probe_rays.length()))
        return;
    vec3 origin = g_probe_rays[index].origin_t_max.xyz;
    float t_max = g_probe_rays[index].origin_t_max.w;
    vec3 direction = g_probe_rays[index].direction.xyz;

    vec3 inverse_direction = bvh_inverse_direction(direction);
    float root_entry = 0.0;
    bool root_hit = false;
    // (The 4-wide tree's box; the compressed tree has no such box to test.)
    if (BVH_LAYOUT == BVH_LAYOUT_WIDE && get_bvh_node_count() > 0u) {
        vec3 lower, upper;
        get_bvh_child_box(0u, 0, lower, upper);
        root_hit = bvh_ray_box_intersection(root_entry, origin, inverse_direction, lower, upper, t_max);
    }
    g_probe_results[index].inverse_direction_root_entry = vec4(inverse_direction, root_entry);
    g_probe_results[index].root_hit = uvec4(root_hit ? 1u : 0u, 0u, 0u, 0u);

    float t;
    uint triangle_index;
    bool hit = bvh_closest_hit(t, triangle_index, origin, direction);
    bool any_hit = bvh_any_hit(origin, direction, t_max);
    g_probe_results[index].bvh = uvec4(floatBitsToUint(t), triangle_index, hit ? 1u : 0u, any_hit ? 1u : 0u);

    uvec4 brute_force = uvec4(0u);
    if (BVH_PROBE_BRUTE_FORCE != 0) {
        float brute_force_t;
        triangle_t triangle;
        bool brute_force_hit = ray_mesh_intersection(brute_force_t, triangle, origin, direction);
        brute_force = uvec4(floatBitsToUint(brute_force_t), g_hit_triangle_index, brute_force_hit ? 1u : 0u, 0u);
    }
    g_probe_results[index].brute_force = brute_force;
}
