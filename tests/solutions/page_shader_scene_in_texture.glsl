#version 300 es
// A WebGL2 page shader whose scene lives in a texture: uniform sampler2D u_scene holds one
// triangle per row (texels 0-2 the vertices, 3 the normal, 4 the colour, 5 the emission), read
// by the helper fetch_triangle that ray_mesh_intersection calls. Its samplers are correct.
// `vkpath check` must not crash, must judge sample_sphere and sample_hemisphere (PASS), and
// must list ray_mesh_intersection as NOT JUDGED naming u_scene (check has no scene texture).
precision highp float;

uniform sampler2D u_scene;
uniform int u_triangle_count;
uniform vec2 u_resolution;
out vec4 fragColor;

#define M_PI 3.141592653589793

struct triangle_t {
    vec3 positions[3];
    vec3 normal;
    vec3 color;
    vec3 emission;
};

triangle_t fetch_triangle(int index) {
    triangle_t tri;
    for (int i = 0; i < 3; ++i)
        tri.positions[i] = texelFetch(u_scene, ivec2(i, index), 0).xyz;
    tri.normal = texelFetch(u_scene, ivec2(3, index), 0).xyz;
    tri.color = texelFetch(u_scene, ivec2(4, index), 0).xyz;
    tri.emission = texelFetch(u_scene, ivec2(5, index), 0).xyz;
    return tri;
}

bool ray_triangle(out float out_t, vec3 origin, vec3 direction, triangle_t tri) {
    vec3 e1 = tri.positions[1] - tri.positions[0];
    vec3 e2 = tri.positions[2] - tri.positions[0];
    vec3 p = cross(direction, e2);
    float det = dot(e1, p);
    out_t = 0.0;
    if (det == 0.0)
        return false;
    vec3 s = origin - tri.positions[0];
    float u = dot(s, p) / det;
    vec3 q = cross(s, e1);
    float v = dot(direction, q) / det;
    out_t = dot(e2, q) / det;
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && out_t > 0.0;
}

bool ray_mesh_intersection(out float out_t, out triangle_t out_triangle, vec3 ray_origin, vec3 ray_direction) {
    out_t = 1.0e38;
    bool hit = false;
    for (int i = 0; i < u_triangle_count; ++i) {
        triangle_t tri = fetch_triangle(i);
        float t;
        if (ray_triangle(t, ray_origin, ray_direction, tri) && t < out_t) {
            out_t = t;
            out_triangle = tri;
            hit = true;
        }
    }
    return hit;
}

vec3 sample_sphere(vec2 random_numbers) {
    float z = 2.0 * random_numbers.y - 1.0;
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = 2.0 * M_PI * random_numbers.x;
    return vec3(r * cos(phi), r * sin(phi), z);
}

vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 direction = sample_sphere(random_numbers);
    if (dot(direction, normal) < 0.0)
        direction -= 2.0 * dot(direction, normal) * normal;
    return direction;
}

void main() {
    vec2 uv = gl_FragCoord.xy / u_resolution;
    float t;
    triangle_t tri;
    bool hit = ray_mesh_intersection(t, tri, vec3(0.278, 0.8, 0.2744), normalize(vec3(uv - 0.5, -1.0)));
    fragColor = vec4(hit ? tri.color : vec3(0.0), 1.0);
}
