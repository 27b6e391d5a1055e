#version 460
// A Vulkan compute shader that traces with ray queries against an acceleration structure it
// binds itself, with a correct PCG2D. vkpath cannot run ray queries here: `vkpath check` must
// list ray_mesh_intersection (which uses them) as NOT JUDGED with that reason, keep the
// extension's code out of everything else, and pass get_random_numbers (exit 0).
#extension GL_EXT_ray_query : require

layout(set = 0, binding = 0) uniform accelerationStructureEXT g_bvh;
layout(set = 0, binding = 1, rgba32f) uniform image2D g_output;
layout(local_size_x = 8, local_size_y = 8) in;

struct triangle_t {
    vec3 positions[3];
    vec3 normal;
    vec3 color;
    vec3 emission;
};

vec2 get_random_numbers(inout uvec2 seed) {
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    return vec2(seed) * 2.32830643654e-10;
}

bool ray_mesh_intersection(out float out_t, out triangle_t out_triangle, vec3 ray_origin, vec3 ray_direction) {
    rayQueryEXT query;
    rayQueryInitializeEXT(query, g_bvh, gl_RayFlagsOpaqueEXT, 0xFF, ray_origin, 0.0, ray_direction, 1.0e30);
    while (rayQueryProceedEXT(query)) {
    }
    out_t = rayQueryGetIntersectionTEXT(query, true);
    out_triangle.normal = vec3(0.0, 0.0, 1.0);
    return rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}

void main() {
    uvec2 seed = gl_GlobalInvocationID.xy;
    imageStore(g_output, ivec2(gl_GlobalInvocationID.xy), vec4(get_random_numbers(seed), 0.0, 1.0));
}
