// A typical mistake: a loop whose condition never becomes false (the author meant to stop it
// with a break that is missing). On lavapipe the driver would end it silently after 65535
// iterations and the function would return a correct direction; `vkpath check` must fail it
// as an endless loop.
vec3 sample_sphere(vec2 random_numbers) {
    float z = 2.0 * random_numbers[1] - 1.0;
    float steps = 0.0;
    while (steps >= 0.0)
        steps += 1.0;
    float phi = 2.0 * M_PI * random_numbers[0];
    float r = sqrt(1.0 - z * z);
    return vec3(r * cos(phi), r * sin(phi), z);
}
