// A correct sample_sphere written differently from the workshop's: z = 1 - 2 u_1 (uniform in
// (-1, 1]), phi = pi (2 u_0 - 1) in [-pi, pi), and the radius clamped before the square
// root. `vkpath check` must accept it (judged by a χ² test, not by equality).
vec3 sample_sphere(vec2 random_numbers) {
    float z = 1.0 - 2.0 * random_numbers.y;
    float radius = sqrt(max(0.0, 1.0 - z * z));
    float phi = M_PI * (2.0 * random_numbers.x - 1.0);
    return vec3(radius * cos(phi), radius * sin(phi), z);
}
