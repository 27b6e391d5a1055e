// get_ray_radiance exactly as Exercise 7 on the slides: a for loop with MAX_PATH_LENGTH
// iterations, break on a miss, x_{j+1} = x_j + t_j w_j with no offset, emission weighted by the
// throughput, a uniform hemisphere direction and the throughput times a 2 n.w. `vkpath check`
// must pass it, with a warning that with intersections accepting t >= 0 the next ray starts on
// the surface and can hit it again (self-intersection).
vec3 get_ray_radiance(vec3 origin, vec3 direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    for (int i = 0; i != MAX_PATH_LENGTH; ++i) {
        float t;
        triangle_t tri;
        if (!ray_mesh_intersection(t, tri, origin, direction))
            break;
        origin += t * direction;
        radiance += throughput * tri.emission;
        direction = sample_hemisphere(get_random_numbers(seed), tri.normal);
        throughput *= tri.color * 2.0 * dot(tri.normal, direction);
    }
    return radiance;
}
