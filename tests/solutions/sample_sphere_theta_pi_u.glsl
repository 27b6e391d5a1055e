// A typical mistake (the slides' cautionary example): spherical coordinates with
// theta = pi u_1, which crowds the samples at the poles. `vkpath check` must reject it.
vec3 sample_sphere(vec2 random_numbers) {
    float theta = M_PI * random_numbers.y;
    float phi = 2.0 * M_PI * random_numbers.x;
    return vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
}
