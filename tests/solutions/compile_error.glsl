// Does not compile: a missing semicolon on line 6, which the compiler reports at line 7.
// `vkpath check` must name this file and its line, not user_functions.glsl.
vec3 sample_sphere(vec2 random_numbers) {
    float z = 2.0 * random_numbers.y - 1.0;
    float phi = 2.0 * M_PI * random_numbers.x;
    float radius = sqrt(1.0 - z * z)
    return vec3(radius * cos(phi), radius * sin(phi), z);
}
