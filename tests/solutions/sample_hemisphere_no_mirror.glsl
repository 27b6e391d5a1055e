// A typical mistake: sample_hemisphere that forgets the mirror step and returns directions
// on the whole sphere. `vkpath check` must reject it and show directions below the
// hemisphere.
vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    return sample_sphere(random_numbers);
}
