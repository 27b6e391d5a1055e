// A typical mistake: the path loop adds the emission of every vertex but never multiplies
// the throughput by a 2 cos, so light is not attenuated at bounces. `vkpath check` must
// reject it: the render is far too bright.
vec3 get_ray_radiance(vec3 ray_origin, vec3 ray_direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    for (int i = 0; i != MAX_PATH_LENGTH; ++i) {
        float t;
        triangle_t triangle;
        if (!ray_mesh_intersection(t, triangle, ray_origin, ray_direction))
            break;
        orient_towards_ray(triangle, ray_direction, is_double_sided(g_hit_triangle_index));
        ray_origin += t * ray_direction;
        radiance += triangle.emission;
        ray_direction = sample_hemisphere(get_random_numbers(seed), triangle.normal);
        ray_origin = offset_ray_origin(ray_origin, triangle.normal);
    }
    return radiance;
}
