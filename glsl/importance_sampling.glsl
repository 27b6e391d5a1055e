// What the workshop's closing slide names next, as sampling maths: cosine-weighted
// directions (BRDF importance sampling for Lambert), points and directions on light
// triangles (by area, or by solid angle with Arvo's spherical triangles) and the power
// heuristic of multiple importance sampling. Samplers come in pairs sample_x /
// get_x_density, as in Peters' renderers. Their users: the surface seam (glsl/surface.glsl),
// the lights room (glsl/lights.glsl, glsl/emissive_lights.glsl) and the path loop (glsl/path_loop.glsl).
// Rust twins: src/cpu/importance_sampling.rs. Needs LIGHT_SAMPLING defined by the includer.
#ifndef VKPATH_IMPORTANCE_SAMPLING_GLSL
#define VKPATH_IMPORTANCE_SAMPLING_GLSL

#include "integrator.glsl"
#include "shading_basis.glsl"

// Maps two uniform random numbers to a cosine-distributed direction around a normal
// (Malley's method: a uniform point on the unit disk, projected up to the hemisphere).
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param normal Unit normal n, world space
// \return A unit vector omega with density get_hemisphere_cosine_density()
vec3 sample_hemisphere_cosine(vec2 random_numbers, vec3 normal) {
    // The shading basis around n (glsl/shading_basis.glsl)
    mat3 basis = get_shading_basis(normal);
    float radius = sqrt(random_numbers[0]);
    float phi = 2.0 * M_PI * random_numbers[1];
    float x = radius * cos(phi);
    float y = radius * sin(phi);
    float z = sqrt(max(0.0, 1.0 - random_numbers[0]));
    return x * basis[0] + y * basis[1] + z * basis[2];
}

// Density of sample_hemisphere_cosine() w.r.t. solid angle: max(0, n.omega) / pi.
float get_hemisphere_cosine_density(vec3 normal, vec3 direction) {
    return max(0.0, dot(normal, direction)) / M_PI;
}

// Area of a triangle (world space, square metres).
float get_triangle_area(triangle_t triangle) {
    return 0.5 * length(cross(triangle.positions[1] - triangle.positions[0], triangle.positions[2] - triangle.positions[0]));
}

// A uniformly distributed point on a triangle (pbrt-v3 13.6.5: b_0 = 1 - sqrt(u_0),
// b_1 = u_1 sqrt(u_0)); density 1 / area w.r.t. area.
vec3 sample_triangle_point(vec2 random_numbers, triangle_t triangle) {
    float root = sqrt(random_numbers[0]);
    float b_0 = 1.0 - root;
    float b_1 = random_numbers[1] * root;
    return b_0 * triangle.positions[0] + b_1 * triangle.positions[1] + (1.0 - b_0 - b_1) * triangle.positions[2];
}

// A triangle seen from a point: its vertices projected onto the unit sphere around the point
// (a spherical triangle), and the solid angle it covers there.
struct spherical_triangle_t {
    // Unit vectors from the point to the triangle's vertices A, B, C.
    vec3 vertices[3];
    // The area of the spherical triangle, which is the solid angle the triangle subtends
    // (get_solid_angle()).
    float solid_angle;
};

// Solid angle of the spherical triangle with unit vertex vectors a, b, c (Van Oosterom and
// Strackee 1983): tan(omega / 2) = |a.(b x c)| / (1 + a.b + b.c + c.a). Unlike Girard's sum of
// interior angles minus pi, this keeps its digits for small triangles. 0 for a point in the
// triangle's plane outside it.
float get_solid_angle(vec3 a, vec3 b, vec3 c) {
    float numerator = abs(dot(a, cross(b, c)));
    float denominator = 1.0 + dot(a, b) + dot(b, c) + dot(c, a);
    return 2.0 * atan(numerator, denominator);
}

// Projects a triangle onto the unit sphere around `origin`.
spherical_triangle_t get_spherical_triangle(vec3 origin, triangle_t triangle) {
    spherical_triangle_t spherical;
    spherical.vertices[0] = normalize(triangle.positions[0] - origin);
    spherical.vertices[1] = normalize(triangle.positions[1] - origin);
    spherical.vertices[2] = normalize(triangle.positions[2] - origin);
    spherical.solid_angle = get_solid_angle(spherical.vertices[0], spherical.vertices[1], spherical.vertices[2]);
    return spherical;
}

// Whether a light sample (sample_light_direction() of glsl/emissive_lights.glsl) is taken by solid
// angle (sample_spherical_triangle()) rather than by area (sample_triangle_point()). Both the
// sampler and get_light_density() ask,
// so that they agree on the density. Lights that subtend less than
// MIN_SPHERICAL_SAMPLING_SOLID_ANGLE or more than MAX_SPHERICAL_SAMPLING_SOLID_ANGLE
// (glsl/shared.h says why) are sampled by area.
bool use_spherical_sampling(spherical_triangle_t spherical) {
    return LIGHT_SAMPLING == LIGHT_SAMPLING_SOLID_ANGLE && spherical.solid_angle >= MIN_SPHERICAL_SAMPLING_SOLID_ANGLE && spherical.solid_angle <= MAX_SPHERICAL_SAMPLING_SOLID_ANGLE;
}

// A direction uniformly distributed in the solid angle of a spherical triangle (Arvo 1995,
// "Stratified sampling of spherical triangles"): u_0 chooses the area of a sub-triangle
// A B C', which fixes C' on arc AC; u_1 a point on arc B C', with the cosine of its arc from B
// uniform (the sub-triangle's area grows linearly in it).
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param spherical The spherical triangle, with a solid angle that use_spherical_sampling()
//        accepts
// \return A unit vector with density 1 / spherical.solid_angle w.r.t. solid angle
vec3 sample_spherical_triangle(vec2 random_numbers, spherical_triangle_t spherical) {
    vec3 a = spherical.vertices[0];
    vec3 b = spherical.vertices[1];
    vec3 c = spherical.vertices[2];
    // The interior angle alpha at A, between the great circles AB and AC.
    vec3 normal_ab = normalize(cross(a, b));
    vec3 normal_ac = normalize(cross(a, c));
    float cos_alpha = dot(normal_ab, normal_ac);
    float sin_alpha = length(cross(normal_ab, normal_ac));
    // phi = sub-triangle area - alpha, by the angle-difference identities.
    float sub_area = random_numbers[0] * spherical.solid_angle;
    float sin_sub_area = sin(sub_area);
    float cos_sub_area = cos(sub_area);
    float sin_phi = sin_sub_area * cos_alpha - cos_sub_area * sin_alpha;
    float cos_phi = cos_sub_area * cos_alpha + sin_sub_area * sin_alpha;
    float u = cos_phi - cos_alpha;
    float v = sin_phi + sin_alpha * dot(a, b);
    // Arvo's q = cos(arc A C') = ((v cos_phi - u sin_phi) cos_alpha - v) / denominator, as
    // 1 - q without cancellation: 2 sin(s/2) (v sin(s/2) - sin(s/2 - alpha) sin s) / denominator
    // for the sub-triangle area s (angle-sum identities). Recovering sin(arc) from q itself
    // would lose half the digits where C' nears A.
    float sin_half_area = sin(0.5 * sub_area);
    float sin_half_area_minus_alpha = sin_half_area * cos_alpha - cos(0.5 * sub_area) * sin_alpha;
    float denominator = (v * sin_phi + u * cos_phi) * sin_alpha;
    float one_minus_q = clamp(2.0 * sin_half_area * (v * sin_half_area - sin_half_area_minus_alpha * sin_sub_area) / denominator, 0.0, 2.0);
    vec3 c_sub = (1.0 - one_minus_q) * a + sqrt(one_minus_q * (2.0 - one_minus_q)) * normalize(c - dot(c, a) * a);
    // z = cos(arc from B to the sample), uniform in [B.C', 1]; 1 - z from the chord, again
    // without cancellation: 1 - B.C' = |C' - B|^2 / 2.
    float one_minus_z = random_numbers[1] * 0.5 * dot(c_sub - b, c_sub - b);
    return (1.0 - one_minus_z) * b + sqrt(one_minus_z * (2.0 - one_minus_z)) * normalize(c_sub - dot(c_sub, b) * b);
}

// The power heuristic with exponent 2 (Veach 1997): weight of a sample from the strategy
// with density `density` against one other strategy with density `other_density`.
float get_power_heuristic_weight(float density, float other_density) {
    float squared = density * density;
    float other_squared = other_density * other_density;
    return (squared + other_squared > 0.0) ? squared / (squared + other_squared) : 0.0;
}

#endif
