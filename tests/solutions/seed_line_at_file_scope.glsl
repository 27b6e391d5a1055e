// Functions only, as pasted from the slides, with the slides' seed line written at file scope
// (in the slides it opens mainImage; here pixel_coord does not exist, so the line cannot
// compile). No workshop function uses it: `vkpath check` must drop it with a note and judge
// all four functions: three correct ones pass, sample_sphere with theta = pi u fails.
#define M_PI 3.141592653589793

uvec2 seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);

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

vec3 sample_sphere(vec2 random_numbers) {
    float theta = M_PI * random_numbers.y;
    float phi = 2.0 * M_PI * random_numbers.x;
    return vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
}

vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 direction = sample_sphere(random_numbers);
    return (dot(direction, normal) < 0.0) ? -direction : direction;
}

vec3 get_primary_ray_direction(float x, float y, vec3 camera_position, vec3 left_bottom, vec3 right, vec3 up) {
    return normalize(left_bottom + x * right + y * up - camera_position);
}
