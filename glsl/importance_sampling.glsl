// What the workshop's closing slide names next: BRDF importance sampling (cosine-weighted
// directions), light sampling (next event estimation), multiple importance sampling and
// Russian roulette. Samplers come in pairs sample_x / get_x_density, as in Peters' renderers.
// Rust twins: src/cpu/importance_sampling.rs. Needs MAX_PATH_LENGTH, INTEGRATOR,
// RUSSIAN_ROULETTE_START, SAMPLER and LIGHT_SAMPLING defined by the includer. Random numbers come from
// get_path_random_numbers() (glsl/sobol.glsl): PCG2D or scrambled Sobol.
#ifndef VKPATH_IMPORTANCE_SAMPLING_GLSL
#define VKPATH_IMPORTANCE_SAMPLING_GLSL

#include "integrator.glsl"
#include "sobol.glsl"

// Emissive triangles, a texel buffer of RGBA32_UINT (16 bytes a texel). Texel 0 is the header,
// `vkpath::render::gpu_types::GpuLightHeader`: x = number of lights, yzw = 0. Texel 1 + i is
// light i, `vkpath::render::gpu_types::GpuLight`: x = its scene triangle index, y = the
// cumulative probability (float bits) of choosing this light or an earlier one
// (power-proportional; the last is 1), zw = 0. Written by
// `vkpath::render::gpu_types::gpu_light_bytes`, whose layout tests check these offsets. The
// selection probability of each triangle (0 for non-emitters) is stored in its packed
// normal.w, for MIS.
layout(set = 0, binding = BINDING_LIGHTS) uniform usamplerBuffer g_light_texels;

// Number of emissive triangles.
uint get_light_count() {
    return texelFetch(g_light_texels, 0).x;
}

// Scene triangle index of light i.
uint get_light_triangle_index(uint light_index) {
    return texelFetch(g_light_texels, int(light_index) + 1).x;
}

// Probability of choosing light i or an earlier one.
float get_light_cumulative_probability(uint light_index) {
    return uintBitsToFloat(texelFetch(g_light_texels, int(light_index) + 1).y);
}

// Maps two uniform random numbers to a cosine-distributed direction around a normal
// (Malley's method: a uniform point on the unit disk, projected up to the hemisphere).
// \param random_numbers Uniform (u_0, u_1) in [0,1)^2
// \param normal Unit normal n, world space
// \return A unit vector omega with density get_hemisphere_cosine_density()
vec3 sample_hemisphere_cosine(vec2 random_numbers, vec3 normal) {
    // An orthonormal basis around n (Duff et al. 2017, "Building an Orthonormal Basis,
    // Revisited", JCGT 6(1)).
    float sign_z = (normal.z >= 0.0) ? 1.0 : -1.0;
    float a = -1.0 / (sign_z + normal.z);
    float b = normal.x * normal.y * a;
    vec3 tangent = vec3(1.0 + sign_z * normal.x * normal.x * a, sign_z * b, -sign_z * normal.x);
    vec3 bitangent = vec3(b, sign_z + normal.y * normal.y * a, -normal.y);
    float radius = sqrt(random_numbers[0]);
    float phi = 2.0 * M_PI * random_numbers[1];
    float x = radius * cos(phi);
    float y = radius * sin(phi);
    float z = sqrt(max(0.0, 1.0 - random_numbers[0]));
    return x * tangent + y * bitangent + z * normal;
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

// Whether sample_direct_light() samples a light by solid angle (sample_spherical_triangle())
// rather than by area (sample_triangle_point()). Both the sampler and get_light_density() ask,
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

// Chooses an emissive triangle in proportion to its power by binary search in the CDF.
// \param random_number Uniform in [0,1)
// \return Index of a light; only valid when get_light_count() > 0
uint sample_light_index(float random_number) {
    uint low = 0u;
    uint high = get_light_count() - 1u;
    // At most 32 halvings for any uint count.
    for (int i = 0; i != 32 && low < high; ++i) {
        uint middle = (low + high) / 2u;
        if (random_number < get_light_cumulative_probability(middle))
            high = middle;
        else
            low = middle + 1u;
    }
    return low;
}

// Probability that sample_light_index() picks the given scene triangle (0 for non-emitters).
float get_light_selection_probability(uint triangle_index) {
    return get_packed_triangle(triangle_index).normal.w;
}

// Density w.r.t. solid angle, at the origin of `spherical` (the light as seen from there), of
// a light sample that lands on the emitter at `distance` along `direction`: p_select / solid
// angle for lights sampled by solid angle, else p_select / area * distance^2 / |n_light.omega|.
float get_light_density(float selection_probability, triangle_t light, spherical_triangle_t spherical, vec3 direction, float distance) {
    if (use_spherical_sampling(spherical))
        return selection_probability / spherical.solid_angle;
    float cosine = abs(dot(light.normal, direction));
    return selection_probability * distance * distance / (get_triangle_area(light) * max(cosine, MIN_LIGHT_COSINE));
}

// Whether anything blocks the segment from `origin` to distance `distance` along `direction`
// (the emitter at its end excluded by a relative margin of SHADOW_RAY_MARGIN = 2^-14).
bool is_occluded(vec3 origin, vec3 direction, float distance) {
    return ray_mesh_any_hit(origin, direction, distance * (1.0 - SHADOW_RAY_MARGIN));
}

// The power heuristic with exponent 2 (Veach 1997): weight of a sample from the strategy
// with density `density` against one other strategy with density `other_density`.
float get_power_heuristic_weight(float density, float other_density) {
    float squared = density * density;
    float other_squared = other_density * other_density;
    return (squared + other_squared > 0.0) ? squared / (squared + other_squared) : 0.0;
}

// A direction from `origin` towards a point of a light triangle and the distance to it
// along that direction: by solid angle or by area, as use_spherical_sampling() says.
// \param spherical The light as seen from `origin` (get_spherical_triangle())
void sample_light_direction(vec2 point_randoms, triangle_t light, vec3 origin, spherical_triangle_t spherical, out vec3 out_direction, out float out_distance) {
    if (use_spherical_sampling(spherical)) {
        out_direction = sample_spherical_triangle(point_randoms, spherical);
        // The distance from the triangle test that shadow rays run, so that is_occluded()'s
        // margin excludes exactly this triangle; where rounding put the direction just
        // outside the triangle, the distance to its plane.
        if (!ray_triangle_intersection(out_distance, origin, out_direction, light))
            out_distance = dot(light.normal, light.positions[0] - origin) / dot(light.normal, out_direction);
    } else {
        vec3 to_light = sample_triangle_point(point_randoms, light) - origin;
        out_distance = length(to_light);
        out_direction = to_light / out_distance;
    }
}

// One light sample at a diffuse surface point (next event estimation), MIS-weighted
// against cosine sampling when INTEGRATOR == INTEGRATOR_MIS:
// a(x)/pi * L_e(y) * (n.omega) / p_light(omega) * w_light
// \param shading_position Point x, world space
// \param triangle The triangle at x, oriented towards the incoming ray
// \param seed The pixel's PCG2D random state (see get_path_random_numbers())
vec3 sample_direct_light(vec3 shading_position, triangle_t triangle, inout uvec2 seed) {
    vec2 selection = get_path_random_numbers(seed);
    vec2 point_randoms = get_path_random_numbers(seed);
    if (get_light_count() == 0u)
        return vec3(0.0);
    uint light_triangle_index = get_light_triangle_index(sample_light_index(selection[0]));
    triangle_t light = get_triangle(light_triangle_index);
    vec3 origin = offset_ray_origin(shading_position, triangle.normal);
    vec3 direction;
    float distance;
    spherical_triangle_t spherical = get_spherical_triangle(origin, light);
    sample_light_direction(point_randoms, light, origin, spherical, direction, distance);
    float cosine = dot(triangle.normal, direction);
    // One-sided emitters shine only towards their normal.
    bool front = dot(light.normal, direction) < 0.0;
    if (cosine <= 0.0 || !(distance > 0.0) || (!front && !is_double_sided(light_triangle_index)))
        return vec3(0.0);
    if (is_occluded(origin, direction, distance))
        return vec3(0.0);
    float light_density = get_light_density(get_light_selection_probability(light_triangle_index), light, spherical, direction, distance);
    float weight = (INTEGRATOR == INTEGRATOR_MIS) ? get_power_heuristic_weight(light_density, get_hemisphere_cosine_density(triangle.normal, direction)) : 1.0;
    return triangle.color / M_PI * light.emission * cosine / light_density * weight;
}

// Path tracing with importance sampling (INTEGRATOR_COSINE, _NEE or _MIS): the workshop's
// loop of get_ray_radiance() with cosine-weighted directions, so the throughput update
// a 2 (n.omega) becomes a (n.omega) / pi / p(omega) = a; light samples at each vertex for NEE
// and MIS; and Russian roulette after RUSSIAN_ROULETTE_START vertices. MAX_PATH_LENGTH
// bounds the number of surface hits as in the workshop: a light sample at vertex j stands
// for a hit j + 1, so it is taken only while j < MAX_PATH_LENGTH.
//
// Random numbers, in the order drawn (each a pair from get_path_random_numbers(); the order
// decides every output bit, with PCG2D and with Sobol's dimension pairs alike, so keep it):
// the pixel jitter (main(), box filter only); then at each vertex that is not the last:
// nee and mis: the light's selection pair and its point pair (sample_direct_light(), drawn
// even without lights); all three: the cosine direction; past RUSSIAN_ROULETTE_START: the
// survival pair (its first number).
vec3 get_ray_radiance_importance_sampled(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput_weight = vec3(1.0);
    // Density of the cosine sample that produced ray_direction (0: the camera ray).
    float direction_density = 0.0;
    // Origin of the current ray: where MIS weights see a light found by it (get_light_density()).
    vec3 previous_position = ray_origin;
    for (int i = 0; i != MAX_PATH_LENGTH; ++i) {
        float t;
        triangle_t triangle;
        if (!ray_mesh_intersection(t, triangle, ray_origin, ray_direction))
            break;
        uint triangle_index = g_hit_triangle_index;
        orient_towards_ray(triangle, ray_direction, is_double_sided(triangle_index));
        ray_origin += t * ray_direction;
        // Emission found by following the path: all of it for cosine sampling and for the
        // camera ray; none for NEE (light samples account for it); MIS-weighted for MIS.
        if (i == 0 || INTEGRATOR == INTEGRATOR_COSINE) {
            radiance += throughput_weight * triangle.emission;
        } else if (INTEGRATOR == INTEGRATOR_MIS && triangle.emission != vec3(0.0)) {
            float light_density = get_light_density(get_light_selection_probability(triangle_index), triangle, get_spherical_triangle(previous_position, triangle), ray_direction, t);
            radiance += throughput_weight * triangle.emission * get_power_heuristic_weight(direction_density, light_density);
        }
        if (i + 1 == MAX_PATH_LENGTH)
            break;
        if (INTEGRATOR != INTEGRATOR_COSINE)
            radiance += throughput_weight * sample_direct_light(ray_origin, triangle, seed);
        // Continue with a cosine sample: weight a(x) (n.omega) / pi / p(omega) = a(x).
        ray_direction = sample_hemisphere_cosine(get_path_random_numbers(seed), triangle.normal);
        direction_density = get_hemisphere_cosine_density(triangle.normal, ray_direction);
        if (direction_density <= 0.0)
            break;
        throughput_weight *= triangle.color;
        ray_origin = offset_ray_origin(ray_origin, triangle.normal);
        previous_position = ray_origin;
        // Russian roulette: continue with probability q = min(1, max throughput component)
        // and divide by q, which keeps the estimate unbiased.
        if (RUSSIAN_ROULETTE_START > 0 && i + 1 >= RUSSIAN_ROULETTE_START) {
            float survival = min(1.0, max(throughput_weight.r, max(throughput_weight.g, throughput_weight.b)));
            if (get_path_random_numbers(seed)[0] >= survival)
                break;
            throughput_weight /= survival;
        }
    }
    return radiance;
}

#endif
