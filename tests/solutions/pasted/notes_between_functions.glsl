// My notes from the path tracing workshop (written for vkpath's tests, shaped like attendees'
// notes files: the functions with what the slides said between them, snippets pasted at
// file scope, half-finished lines).

Exercise 1
The random numbers come from PCG2D
seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);
vec2 random_numbers = get_random_numbers(seed);
get_random_numbers(seed);
color += radiance;
out_color = vec4(color, 1.0);

vec2 get_random_numbers(inout uvec2 seed) {
    // PCG2D, as on the slides (Jarzynski and Olano 2020)
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    return vec2(seed) * 2.32830643654e-10;
}

Exercise 2
ray = origin + t * direction
t = dot(normal, v0 - origin) / dot(normal, direction);
mat3 system = mat3(-direction, v1 - v0, v2 - v0);
vec3 solution = inverse(system) * (origin - v0);
if (solution.x < 0.0) { return false; }
for (int i = 0; i != TRIANGLE_COUNT; ++i) { hit = hit || ray_triangle_intersection(t, origin, direction, tris[i]); }
return hit;
vec3 v0 = tri.positions[0];
vec3 normal = normalize(cross(v1 - v0, v2 - v0));
float t_max = 1.0e38;
hit_color = tri.color;
TODO
=> closest hit wins

bool ray_triangle_intersection(out float out_t, vec3 origin, vec3 direction, triangle_t tri) {
    vec3 v0 = tri.positions[0];
    mat3 system = mat3(-direction, tri.positions[1] - v0, tri.positions[2] - v0);
    vec3 solution = inverse(system) * (origin - v0);
    out_t = solution.x;
    return solution.x >= 0.0 && solution.y >= 0.0 && solution.z >= 0.0
        && solution.y + solution.z <= 1.0;
}
