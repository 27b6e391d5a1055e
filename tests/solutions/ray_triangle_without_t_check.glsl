// A typical mistake: Möller-Trumbore without the t >= 0 test, so that triangles behind the
// ray's origin count as hits. `vkpath check` must reject it and show such a ray.
bool ray_triangle_intersection(out float out_t, vec3 ray_origin, vec3 ray_direction, triangle_t triangle) {
    vec3 edge_1 = triangle.positions[1] - triangle.positions[0];
    vec3 edge_2 = triangle.positions[2] - triangle.positions[0];
    vec3 p = cross(ray_direction, edge_2);
    float determinant = dot(edge_1, p);
    out_t = 0.0;
    if (determinant == 0.0)
        return false;
    float inverse_determinant = 1.0 / determinant;
    vec3 s = ray_origin - triangle.positions[0];
    float u = dot(s, p) * inverse_determinant;
    if (u < 0.0 || u > 1.0)
        return false;
    vec3 q = cross(s, edge_1);
    float v = dot(ray_direction, q) * inverse_determinant;
    if (v < 0.0 || u + v > 1.0)
        return false;
    out_t = dot(edge_2, q) * inverse_determinant;
    return true;
}
