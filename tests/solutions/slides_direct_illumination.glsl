// compute_direct_illumination exactly as Exercise 6 on the slides: one uniform hemisphere
// direction w around the triangle's normal, a ray from the shading point itself (no offset)
// to find L_e(y), and L_e(x) + a(x) / pi * 2 pi * L_e(y) * n(x).w. `vkpath check` must pass it.
vec3 compute_direct_illumination(vec3 shading_position, triangle_t triangle, inout uvec2 seed) {
    vec3 direction = sample_hemisphere(get_random_numbers(seed), triangle.normal);
    vec3 light_emission = vec3(0.0);
    float t;
    triangle_t hit_triangle;
    if (ray_mesh_intersection(t, hit_triangle, shading_position, direction))
        light_emission = hit_triangle.emission;
    return triangle.emission + triangle.color / M_PI * 2.0 * M_PI * light_emission * dot(triangle.normal, direction);
}
