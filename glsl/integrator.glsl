// The workshop's estimators: Exercise 6 (compute_direct_illumination) and Exercise 7
// (get_ray_radiance), plus the two things real scenes need that the workshop's closed,
// inward-facing Cornell box does not (orient_towards_ray, offset_ray_origin).
// Rust twins: src/cpu/integrator.rs. Needs MAX_PATH_LENGTH defined by the includer.
#ifndef VKPATH_INTEGRATOR_GLSL
#define VKPATH_INTEGRATOR_GLSL

#include "scene.glsl"

// Prepares a triangle that a ray hit for shading (vkpath's addition). Triangles of real
// scenes are seen from both sides: the normal is flipped to face the ray's origin, so that
// sampled directions leave on the side the ray came from; emission is one-sided (the side
// the counter-clockwise normal points to) unless the triangle is double-sided, so the
// emission seen from the back is zero. In the workshop's Cornell box every hit is on the
// front, where this changes nothing.
// \param triangle The hit triangle, updated in place
// \param ray_direction Direction of the ray that hit it, world space
// \param double_sided Whether the triangle emits from both sides
void orient_towards_ray(inout triangle_t triangle, vec3 ray_direction, bool double_sided) {
    if (dot(triangle.normal, ray_direction) > 0.0) {
        triangle.normal = -triangle.normal;
        if (!double_sided)
            triangle.emission = vec3(0.0);
    }
}

// Moves the origin of a ray that leaves a surface slightly off it, so that the ray does not
// hit the surface it starts on again through rounding (vkpath's addition: the workshop does
// not guard against self-intersection). The offset is RAY_ORIGIN_OFFSET = 2^-17 relative to
// the largest coordinate (at least 2^-17 absolute): about 64 float ulps, far above the
// rounding error of ray_triangle_intersection() and far below any feature of a sensible scene.
// \param position Point on the surface, world space
// \param normal Unit normal on the side the ray leaves to
vec3 offset_ray_origin(vec3 position, vec3 normal) {
    vec3 magnitude = abs(position);
    float scale = max(1.0, max(magnitude.x, max(magnitude.y, magnitude.z)));
    return position + (scale * RAY_ORIGIN_OFFSET) * normal;
}

#ifndef USER_DEFINES_COMPUTE_DIRECT_ILLUMINATION
// Exercise 6: radiance leaving a point of a triangle towards the camera, estimated with one
// uniform hemisphere sample for direct illumination:
// L_e(x) + a(x)/pi * 2 pi * L_e(y) * n(x).omega   (density 1/(2 pi) w.r.t. solid angle)
// \param shading_position The point x on the triangle, world space
// \param triangle The triangle at x, oriented by orient_towards_ray()
// \param seed The pixel's random state (get_random_numbers())
vec3 compute_direct_illumination(vec3 shading_position, triangle_t triangle, inout uvec2 seed) {
    vec3 ray_direction = sample_hemisphere(get_random_numbers(seed), triangle.normal);
    vec3 incoming_emission = vec3(0.0);
    float t;
    triangle_t light_triangle;
    if (ray_mesh_intersection(t, light_triangle, offset_ray_origin(shading_position, triangle.normal), ray_direction)) {
        orient_towards_ray(light_triangle, ray_direction, is_double_sided(g_hit_triangle_index));
        incoming_emission = light_triangle.emission;
    }
    return triangle.emission + triangle.color / M_PI * 2.0 * M_PI * incoming_emission * dot(triangle.normal, ray_direction);
}
#endif

#ifndef USER_DEFINES_GET_RAY_RADIANCE
// Exercise 7: a Monte Carlo estimate of the radiance L(x_0, omega_0) arriving along a ray,
// with paths of up to MAX_PATH_LENGTH surface hits and uniform hemisphere sampling:
// L_{j+1} = L_j + T_j L_e(x_{j+1}),            L_0 = 0
// T_{j+1} = T_j a(x_{j+1}) 2 n(x_{j+1}).omega_{j+1},   T_0 = 1
// \param ray_origin, ray_direction The camera ray, world space
// \param seed The pixel's random state (get_random_numbers())
vec3 get_ray_radiance(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput_weight = vec3(1.0);
    for (int i = 0; i != MAX_PATH_LENGTH; ++i) {
        float t;
        triangle_t triangle;
        // Trace ray x_j, omega_j, break if it hits nothing
        if (!ray_mesh_intersection(t, triangle, ray_origin, ray_direction))
            break;
        orient_towards_ray(triangle, ray_direction, is_double_sided(g_hit_triangle_index));
        // x_{j+1} = x_j + t_j omega_j
        ray_origin += t * ray_direction;
        // Add T_j L_e(x_{j+1}) to the radiance
        radiance += throughput_weight * triangle.emission;
        // Sample omega_{j+1} in Omega(x_{j+1})
        ray_direction = sample_hemisphere(get_random_numbers(seed), triangle.normal);
        // Multiply the throughput by a(x_{j+1}) 2 n(x_{j+1}).omega_{j+1}
        throughput_weight *= triangle.color * 2.0 * dot(triangle.normal, ray_direction);
        ray_origin = offset_ray_origin(ray_origin, triangle.normal);
    }
    return radiance;
}
#endif

#endif
