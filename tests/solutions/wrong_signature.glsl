// sample_sphere with a parameter of the wrong type: GLSL would take it as an overload that
// the workshop's code never calls. `vkpath check` must say so.
vec3 sample_sphere(vec3 random_numbers) {
    return normalize(random_numbers);
}
