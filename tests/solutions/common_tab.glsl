// A ShaderToy Common tab: no entry point, shared by every pass. It holds the random numbers and
// a helper that the Image tab (image_tab_needs_common.glsl) calls. Passed first, as ShaderToy
// prepends it: `vkpath check common_tab.glsl image_tab_needs_common.glsl` judges both tabs.
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

vec3 spherical_direction(float cos_theta, float phi) {
    float sin_theta = sqrt(max(0.0, 1.0 - cos_theta * cos_theta));
    return vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}
