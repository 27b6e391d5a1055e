#version 300 es
// The WebGL pattern: the path length is a uniform the page sets (uniform int maxPathLength),
// and the slides' loop is bounded by it. A plain global would be 0 and render black; `vkpath
// check` must give it the workshop's MAX_PATH_LENGTH, say so in a note, and pass
// get_ray_radiance.
precision highp float;
uniform int maxPathLength;
out vec4 fragColor;

vec3 get_ray_radiance(vec3 origin, vec3 direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    for (int i = 0; i < maxPathLength; ++i) {
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

void main() {
    fragColor = vec4(0.0);
}
