// Correct get_primary_ray_direction and ray_mesh_intersection written differently from the
// workshop's: the image-plane point summed in another order and normalized with
// inversesqrt; the triangles visited backwards with the closest hit kept.
vec3 get_primary_ray_direction(float x, float y, vec3 camera_position, vec3 left_bottom, vec3 right, vec3 up) {
    vec3 direction = (left_bottom - camera_position) + right * x + up * y;
    return direction * inversesqrt(dot(direction, direction));
}

bool ray_mesh_intersection(out float out_t, out triangle_t out_triangle, vec3 ray_origin, vec3 ray_direction) {
    bool found = false;
    out_t = 0.0;
    uint count = g_resolution_triangle_count_seed.z;
    for (uint i = count; i > 0u; --i) {
        float t;
        triangle_t candidate = get_triangle(i - 1u);
        if (ray_triangle_intersection(t, ray_origin, ray_direction, candidate) && (!found || t < out_t)) {
            out_t = t;
            out_triangle = candidate;
            found = true;
        }
    }
    return found;
}
