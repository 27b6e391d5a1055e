// get_ray_radiance as Exercise 7 on the slides, but with the path's vertices counted by hand in
// a while loop and a `continue` where the slides `break` on a miss: a path that leaves the box
// traces the same missing ray again and again, and every iteration traces the whole scene.
// `vkpath check` must fail it as a loop without end within seconds (a small probe render finds
// it before the full renders would spend minutes on the loop guard's 20 000 iterations a path).
vec3 get_ray_radiance(vec3 origin, vec3 direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    int vertex_count = 0;
    while (vertex_count != MAX_PATH_LENGTH) {
        float t;
        triangle_t tri;
        if (!ray_mesh_intersection(t, tri, origin, direction))
            continue;
        origin += t * direction;
        radiance += throughput * tri.emission;
        direction = sample_hemisphere(get_random_numbers(seed), tri.normal);
        throughput *= tri.color * 2.0 * dot(tri.normal, direction);
        ++vertex_count;
    }
    return radiance;
}
