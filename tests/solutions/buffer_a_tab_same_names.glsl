// A ShaderToy Buffer A tab of a three-tab program: common_tab.glsl, this tab, then
// image_tab_needs_common.glsl. Like the Image tab it defines sample_sphere (correct, written
// with z = 1 - 2 u rather than 2 u - 1), which ShaderToy allows because it compiles each pass
// on its own after the Common tab: `vkpath check` must judge both (each naming its tab)
// instead of failing on a redefinition. sample_hemisphere (correct) calls this tab's
// sample_sphere.
vec3 sample_sphere(vec2 random_numbers) {
    return spherical_direction(1.0 - 2.0 * random_numbers.y, 2.0 * M_PI * random_numbers.x);
}

vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 direction = sample_sphere(random_numbers);
    return (dot(direction, normal) < 0.0) ? -direction : direction;
}

void mainImage(out vec4 out_color, in vec2 pixel_coord) {
    uvec2 seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);
    out_color = vec4(sample_hemisphere(get_random_numbers(seed), vec3(0.0, 0.0, 1.0)), 1.0);
}
