// A valid sampler, but not the exercise's: cosine-weighted hemisphere sampling (Malley's
// method in an orthonormal basis around the normal, density cos / pi instead of the uniform
// 1 / (2 pi) that the 2 pi weights of Exercises 6 and 7 assume). `vkpath check` must reject
// sample_hemisphere and name it as cosine-weighted.
vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    // orthonormal basis (t, b, n)
    vec3 helper = (abs(normal.x) > 0.9) ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 tangent = normalize(cross(helper, normal));
    vec3 bitangent = cross(normal, tangent);
    // uniform point on the unit disk, projected up onto the hemisphere
    float r = sqrt(random_numbers.x);
    float phi = 2.0 * M_PI * random_numbers.y;
    float z = sqrt(1.0 - random_numbers.x);
    return r * cos(phi) * tangent + r * sin(phi) * bitangent + z * normal;
}
