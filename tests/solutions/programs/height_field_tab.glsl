// A Buffer A tab that path traces a scene of its own: a height field read from iChannel0 as a
// texture, lit by the sky, averaged over the frames as the workshop's tab does. Its
// get_random_numbers is the workshop's. `vkpath check` must judge that function and list the
// program as NOT JUDGED (it is not the workshop's Cornell box), exit status from the function.
#define M_PI 3.141592653589793

vec2 get_random_numbers(inout uvec2 seed) {
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    return vec2(seed) * 2.32830643654e-10;
}

float terrain_height(vec2 p) {
    return 0.2 * texture(iChannel0, fract(0.25 * p)).r;
}

// March the ray over the height field; the sky's radiance where it escapes.
vec3 get_ray_radiance(vec3 origin, vec3 direction, inout uvec2 seed) {
    float t = get_random_numbers(seed).x * 0.05;
    for (int i = 0; i != 64; ++i) {
        vec3 p = origin + t * direction;
        if (p.y < terrain_height(p.xz))
            return vec3(0.3, 0.25, 0.2);
        t += 0.05;
    }
    return vec3(0.5, 0.7, 1.0);
}

void mainImage(out vec4 out_color, in vec2 pixel_coord) {
    vec2 uv = pixel_coord / iResolution.xy;
    vec3 direction = normalize(vec3(uv.x - 0.5, uv.y - 0.6, 1.0));
    uvec2 seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);
    vec3 color = get_ray_radiance(vec3(0.0, 0.5, 0.0), direction, seed);
    vec3 previous = texture(iChannel0, uv).rgb;
    out_color = vec4(mix(previous, color, 1.0 / float(iFrame + 1)), 1.0);
}
