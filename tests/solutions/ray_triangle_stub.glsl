// The exercise as handed out: ray_triangle_intersection is still the TODO stub
// (`return false;`), beside a correct sample_sphere. `vkpath check` must fail the stub and
// name it as the exercise's stub, not as a wrong formula.
// TODO: Implement ray_triangle_intersection
bool ray_triangle_intersection(out float out_t, vec3 ray_origin, vec3 ray_direction, triangle_t triangle) {
    return false;
}

vec3 sample_sphere(vec2 random_numbers) {
    float z = 2.0 * random_numbers.y - 1.0;
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = 2.0 * M_PI * random_numbers.x;
    return vec3(r * cos(phi), r * sin(phi), z);
}
