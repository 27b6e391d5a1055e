// A Buffer A tab whose mainImage traces a ray and then writes a constant colour over it (a
// line left from debugging). Its get_random_numbers is the workshop's; its intersection and
// get_ray_radiance take other parameters than the workshop's. `vkpath check` must judge the
// function and list the program as NOT JUDGED (its image never changes from frame to frame, so
// it is no estimate of the workshop's scene), exit status from the function.
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

bool ray_mesh_intersection(out float out_t, vec3 origin, vec3 direction) {
    // The floor of the Cornell box, z = 0.
    out_t = -origin.z / direction.z;
    return out_t > 0.0;
}

vec3 get_ray_radiance(vec3 origin, vec3 direction, vec2 random_numbers) {
    float t;
    return ray_mesh_intersection(t, origin, direction) ? vec3(random_numbers, 0.5) : vec3(0.0);
}

void mainImage(out vec4 out_color, in vec2 pixel_coord) {
    uvec2 seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);
    vec3 direction = normalize(vec3(pixel_coord / iResolution.xy - 0.5, -1.0));
    out_color.rgb = get_ray_radiance(vec3(0.278, 0.8, 0.2744), direction, get_random_numbers(seed));
    out_color = vec4(0.25, 0.5, 0.75, 1.0);
}
