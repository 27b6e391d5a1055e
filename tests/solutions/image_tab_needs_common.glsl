// A ShaderToy Image tab that calls spherical_direction from its Common tab (common_tab.glsl).
// Alone it cannot compile: `vkpath check` must say in one line that spherical_direction is not
// defined and that a Common tab goes first. After the Common tab, sample_sphere passes.
vec3 sample_sphere(vec2 random_numbers) {
    return spherical_direction(2.0 * random_numbers.y - 1.0, 2.0 * M_PI * random_numbers.x);
}

void mainImage(out vec4 out_color, in vec2 pixel_coord) {
    uvec2 seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);
    out_color = vec4(sample_sphere(get_random_numbers(seed)) * 0.5 + 0.5, 1.0);
}
