// The Path Tracing Workshop's building blocks, kept as close to the slides as possible: same
// names, signatures and maths. Each function has a Rust twin of the same name in
// src/cpu/workshop.rs; change both together.
#ifndef VKPATH_WORKSHOP_GLSL
#define VKPATH_WORKSHOP_GLSL

#define M_PI 3.141592653589793

// A triangle along with some shading parameters (slide "Mesh representation").
struct triangle_t {
    // The positions of the three vertices (v_0, v_1, v_2), world space
    vec3 positions[3];
    // A vector of length 1, orthogonal to the triangle (n). Points to the side that the
    // vertices are counter-clockwise from.
    vec3 normal;
    // The albedo of the triangle (i.e. the fraction of red/green/blue light that gets
    // reflected) (a), linear RGB in [0, 1]
    vec3 color;
    // The radiance emitted by the triangle (for light sources) (L_e), linear RGB
    vec3 emission;
};

// Prototypes of every workshop function, so that definitions may come in any order: a
// user's file (see user_functions.glsl) can replace any of them, and the reference versions
// of the others still call the user's. Each reference definition is skipped when the macro
// USER_DEFINES_<NAME> is defined.
vec2 get_random_numbers(inout uvec2 seed);
vec3 sample_sphere(vec2 random_numbers);
vec3 sample_hemisphere(vec2 random_numbers, vec3 normal);
bool ray_triangle_intersection(out float out_t, vec3 ray_origin, vec3 ray_direction, triangle_t triangle);
bool ray_mesh_intersection(out float out_t, out triangle_t out_triangle, vec3 ray_origin, vec3 ray_direction);
vec3 get_primary_ray_direction(float x, float y, vec3 camera_position, vec3 left_bottom, vec3 right, vec3 up);
vec3 compute_direct_illumination(vec3 shading_position, triangle_t triangle, inout uvec2 seed);
vec3 get_ray_radiance(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed);

#ifndef USER_DEFINES_GET_RANDOM_NUMBERS
// A pseudo-random number generator
// \param seed Numbers that are different for each invocation. Gets updated so
//           that it can be reused.
// \return Two independent, uniform, pseudo-random numbers in [0,1) (u_0, u_1)
vec2 get_random_numbers(inout uvec2 seed) {
    // This is PCG2D: https://jcgt.org/published/0009/03/02/
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    // Convert to float. The constant here is 2^-32.
    return vec2(seed) * 2.32830643654e-10;
}
#endif

#ifndef USER_DEFINES_SAMPLE_SPHERE
// Maps two uniform random numbers to a uniformly distributed direction on the unit sphere
// (slide "Uniform sphere sampling", derivation in pbr-book.org 13.6.1).
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \return A unit vector, density 1/(4 pi) w.r.t. solid angle
vec3 sample_sphere(vec2 random_numbers) {
    // omega_z = 2 u_1 - 1 is uniform in [-1, 1)
    float z = 2.0 * random_numbers[1] - 1.0;
    // phi = 2 pi u_0
    float phi = 2.0 * M_PI * random_numbers[0];
    // omega_x = cos(phi) sqrt(1 - omega_z^2), omega_y = sin(phi) sqrt(1 - omega_z^2)
    float x = cos(phi) * sqrt(1.0 - z * z);
    float y = sin(phi) * sqrt(1.0 - z * z);
    return vec3(x, y, z);
}
#endif

#ifndef USER_DEFINES_SAMPLE_HEMISPHERE
// Maps two uniform random numbers to a uniformly distributed direction on the hemisphere
// around the given normal (slide "Uniform hemisphere sampling").
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param normal Unit vector n, world space
// \return A unit vector omega with dot(n, omega) >= 0, density 1/(2 pi) w.r.t. solid angle
vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 direction = sample_sphere(random_numbers);
    // Mirror if n . omega < 0: omega' = omega - 2 (n . omega) n
    if (dot(normal, direction) < 0.0)
        direction -= 2.0 * dot(normal, direction) * normal;
    return direction;
}
#endif

#ifndef USER_DEFINES_RAY_TRIANGLE_INTERSECTION
// Intersects a ray with a triangle (Part 1). Solves
// ray_origin + t * ray_direction = v_0 + u (v_1 - v_0) + v (v_2 - v_0)
// for (t, u, v) with Cramer's rule: the workshop's 3x3 linear system, spelled out so that the
// Rust twin performs the same operations.
// \param out_t Ray parameter of the hit (distance in units of |ray_direction|)
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \param triangle The triangle to intersect
// \return true iff the ray hits the triangle at t >= 0 (edges and vertices included)
bool ray_triangle_intersection(out float out_t, vec3 ray_origin, vec3 ray_direction, triangle_t triangle) {
    vec3 edge_1 = triangle.positions[1] - triangle.positions[0];
    vec3 edge_2 = triangle.positions[2] - triangle.positions[0];
    vec3 origin_offset = ray_origin - triangle.positions[0];
    // The columns of the system's matrix are (-ray_direction, edge_1, edge_2); its determinant
    // is the scalar triple product det = dot(-ray_direction, cross(edge_1, edge_2)).
    vec3 normal_unscaled = cross(edge_1, edge_2);
    float determinant = -dot(ray_direction, normal_unscaled);
    vec3 direction_cross_offset = cross(ray_direction, origin_offset);
    float inverse_determinant = 1.0 / determinant;
    float t = dot(origin_offset, normal_unscaled) * inverse_determinant;
    float u = -dot(edge_2, direction_cross_offset) * inverse_determinant;
    float v = dot(edge_1, direction_cross_offset) * inverse_determinant;
    out_t = t;
    // A ray parallel to the triangle gives an infinite or NaN determinant inverse, which fails
    // these comparisons.
    return t >= 0.0 && u >= 0.0 && v >= 0.0 && u + v <= 1.0;
}
#endif

#ifndef USER_DEFINES_GET_PRIMARY_RAY_DIRECTION
// The pinhole camera of Part 1: the direction of the primary ray through a point of the
// image plane.
// \param x, y Point of the image in [0,1]^2, (0,0) at the left bottom, y up (ShaderToy's
//        pixel_coord / iResolution)
// \param camera_position The pinhole, world space
// \param left_bottom The image plane's left-bottom corner, world space
// \param right, up The image plane's edge vectors (full width and height), world space
// \return The normalized ray direction, world space
vec3 get_primary_ray_direction(float x, float y, vec3 camera_position, vec3 left_bottom, vec3 right, vec3 up) {
    vec3 image_plane_point = left_bottom + x * right + y * up;
    return normalize(image_plane_point - camera_position);
}
#endif

#endif
