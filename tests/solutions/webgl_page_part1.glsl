#version 300 es
// A whole WebGL2 page fragment shader with Part 1 of the workshop only (camera ray, ray-triangle
// and ray-mesh intersection; main shows the albedo of the first hit), in an attendee's own
// style: a const camera, a Cramer's-rule helper barycentric_solve, other variable names.
// `vkpath check` must pass get_primary_ray_direction, ray_triangle_intersection and
// ray_mesh_intersection. (#version stays on line 1: GLSL ES allows nothing before it, not even
// this comment.)
precision highp float;

uniform vec2 u_resolution;
uniform float u_time;  // not needed for part 1

out vec4 fragColor;

#define TRIANGLE_COUNT 30

struct triangle_t {
    vec3 positions[3];
    vec3 normal;
    vec3 color;
    vec3 emission;
};

// camera (Cornell box, z is up, looking down -y)
const vec3 camera_position = vec3(0.278, 0.8, 0.2744);
const vec3 camera_target = vec3(0.278, 0.0, 0.2744);
const vec3 camera_up = vec3(0.0, 0.0, 0.56);


vec3 get_primary_ray_direction(float x, float y, vec3 eye, vec3 lower_left, vec3 horizontal, vec3 vertical) {
    vec3 pixel_on_plane = lower_left + x * horizontal + y * vertical;
    return normalize(pixel_on_plane - eye);
}


// Solves -dir * t + e1 * b1 + e2 * b2 = ro - p0 with Cramer's rule, returns (t, b1, b2).
// Returns something invalid (t < 0) if the ray is parallel to the triangle.
vec3 barycentric_solve(vec3 ro, vec3 dir, triangle_t tri) {
    vec3 p0 = tri.positions[0];
    vec3 e1 = tri.positions[1] - p0;
    vec3 e2 = tri.positions[2] - p0;
    vec3 rhs = ro - p0;
    vec3 minus_dir = -dir;
    float det = dot(minus_dir, cross(e1, e2));
    if (det == 0.0)
        return vec3(-1.0);
    float inv_det = 1.0 / det;
    float t = dot(rhs, cross(e1, e2)) * inv_det;
    float b1 = dot(minus_dir, cross(rhs, e2)) * inv_det;
    float b2 = dot(minus_dir, cross(e1, rhs)) * inv_det;
    return vec3(t, b1, b2);
}


bool ray_triangle_intersection(out float out_t, vec3 origin, vec3 direction, triangle_t tri) {
    vec3 tbb = barycentric_solve(origin, direction, tri);
    out_t = tbb.x;
    bool inside = tbb.y >= 0.0 && tbb.z >= 0.0 && (tbb.y + tbb.z) <= 1.0;
    return inside && tbb.x >= 0.0;
}


bool ray_mesh_intersection(out float out_t, out triangle_t out_tri, vec3 origin, vec3 direction) {
    // Cornell box, copied from the ShaderToy exercise
    triangle_t scene[TRIANGLE_COUNT];
    scene[0] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 0.548799932), vec3(0.555999935, -0.559199989, 4e-08), vec3(1.33e-07, -0.559199989, 4e-08)), vec3(0.0, 1.0, 0.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    scene[1] = triangle_t(vec3[3](vec3(0.313999921, -0.45599997, 0.329999954), vec3(0.313999921, -0.45599997, 4e-08), vec3(0.472000152, -0.406000137, 4e-08)), vec3(0.301707575, -0.953400513, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[2] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(0.555999935, -0.559199989, 4e-08), vec3(0.555999935, -1.19e-07, 4e-08)), vec3(0.0, 0.0, 1.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    scene[3] = triangle_t(vec3[3](vec3(0.264999926, -0.296000093, 0.329999954), vec3(0.264999926, -0.296000093, 4e-08), vec3(0.313999921, -0.45599997, 4e-08)), vec3(-0.956165759, -0.292825958, -0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[4] = triangle_t(vec3[3](vec3(0.423000127, -0.24699989, 4e-08), vec3(0.472000152, -0.406000137, 0.329999954), vec3(0.472000152, -0.406000137, 4e-08)), vec3(0.955649049, 0.294507888, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[5] = triangle_t(vec3[3](vec3(0.264999926, -0.296000093, 0.329999954), vec3(0.313999921, -0.45599997, 4e-08), vec3(0.313999921, -0.45599997, 0.329999954)), vec3(-0.956165759, -0.292825958, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[6] = triangle_t(vec3[3](vec3(0.313999921, -0.45599997, 0.329999954), vec3(0.472000152, -0.406000137, 4e-08), vec3(0.472000152, -0.406000137, 0.329999954)), vec3(0.301707575, -0.953400513, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[7] = triangle_t(vec3[3](vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.082000092, -0.225000143, 0.165000007), vec3(0.082000092, -0.225000143, 4e-08)), vec3(-0.285119946, -0.958491845, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[8] = triangle_t(vec3[3](vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.082000092, -0.225000143, 4e-08), vec3(0.240000039, -0.271999955, 4e-08)), vec3(-0.285119946, -0.958491845, -0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[9] = triangle_t(vec3[3](vec3(0.290000081, -0.113999903, 4e-08), vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.240000039, -0.271999955, 4e-08)), vec3(0.953400053, -0.30170903, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[10] = triangle_t(vec3[3](vec3(0.082000092, -0.225000143, 4e-08), vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.13000007, -0.064999968, 4e-08)), vec3(-0.957826408, 0.287347476, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[11] = triangle_t(vec3[3](vec3(0.082000092, -0.225000143, 4e-08), vec3(0.082000092, -0.225000143, 0.165000007), vec3(0.13000007, -0.064999968, 0.165000007)), vec3(-0.957826408, 0.287347476, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[12] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(0.555999935, -1.19e-07, 4e-08), vec3(1.33e-07, -1.19e-07, 4e-08)), vec3(0.0, 0.0, 1.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    scene[13] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 4e-08), vec3(0.290000081, -0.114000171, 0.165000007), vec3(0.290000081, -0.113999903, 4e-08)), vec3(0.292825408, 0.956165927, 1.554e-06), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[14] = triangle_t(vec3[3](vec3(0.290000081, -0.113999903, 4e-08), vec3(0.290000081, -0.114000171, 0.165000007), vec3(0.240000039, -0.271999955, 0.165000007)), vec3(0.953399906, -0.301709496, -4.9e-07), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[15] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 4e-08), vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.290000081, -0.114000171, 0.165000007)), vec3(0.292826874, 0.956165478, -0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[16] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(1.33e-07, -1.19e-07, 4e-08), vec3(1.33e-07, -1.19e-07, 0.548799932)), vec3(1.0, 0.0, 0.0), vec3(0.289999992, 0.663999975, 0.324999988), vec3(0.0, 0.0, 0.0));
    scene[17] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.082000092, -0.225000143, 0.165000007), vec3(0.240000039, -0.271999955, 0.165000007)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[18] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.290000081, -0.114000171, 0.165000007)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[19] = triangle_t(vec3[3](vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.423000127, -0.24699989, 4e-08), vec3(0.264999926, -0.296000093, 4e-08)), vec3(-0.29620985, 0.955122885, 7.76e-07), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[20] = triangle_t(vec3[3](vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.264999926, -0.296000093, 4e-08), vec3(0.264999926, -0.296000093, 0.329999954)), vec3(-0.296208371, 0.955123343, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[21] = triangle_t(vec3[3](vec3(0.423000127, -0.24699989, 4e-08), vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.472000152, -0.406000137, 0.329999954)), vec3(0.955648909, 0.294508341, 2.39e-07), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[22] = triangle_t(vec3[3](vec3(0.555999935, -1.19e-07, 0.548799932), vec3(0.555999935, -1.19e-07, 4e-08), vec3(0.555999935, -0.559199989, 4e-08)), vec3(-1.0, 0.0, -0.0), vec3(0.730000019, 0.246000007, 0.250999987), vec3(0.0, 0.0, 0.0));
    scene[23] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(1.33e-07, -1.19e-07, 0.548799932), vec3(1.33e-07, -0.559199989, 0.548799932)), vec3(1.0, 0.0, 0.0), vec3(0.289999992, 0.663999975, 0.324999988), vec3(0.0, 0.0, 0.0));
    scene[24] = triangle_t(vec3[3](vec3(1.33e-07, -1.19e-07, 0.548799932), vec3(0.555999935, -0.559199989, 0.548799932), vec3(1.33e-07, -0.559199989, 0.548799932)), vec3(0.0, 0.0, -1.0), vec3(0.0, 0.0, 0.0), vec3(3.0, 3.0, 3.0));
    scene[25] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 0.548799932), vec3(0.555999935, -0.559199989, 0.548799932), vec3(0.555999935, -0.559199989, 4e-08)), vec3(-0.0, 1.0, 0.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    scene[26] = triangle_t(vec3[3](vec3(0.472000152, -0.406000137, 0.329999954), vec3(0.264999926, -0.296000093, 0.329999954), vec3(0.313999921, -0.45599997, 0.329999954)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[27] = triangle_t(vec3[3](vec3(0.555999935, -1.19e-07, 0.548799932), vec3(0.555999935, -0.559199989, 4e-08), vec3(0.555999935, -0.559199989, 0.548799932)), vec3(-1.0, -0.0, 0.0), vec3(0.730000019, 0.246000007, 0.250999987), vec3(0.0, 0.0, 0.0));
    scene[28] = triangle_t(vec3[3](vec3(0.472000152, -0.406000137, 0.329999954), vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.264999926, -0.296000093, 0.329999954)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    scene[29] = triangle_t(vec3[3](vec3(1.33e-07, -1.19e-07, 0.548799932), vec3(0.555999935, -1.19e-07, 0.548799932), vec3(0.555999935, -0.559199989, 0.548799932)), vec3(0.0, 0.0, -1.0), vec3(0.0, 0.0, 0.0), vec3(3.0, 3.0, 3.0));
    float closest_t = 1.0e38;
    int closest_index = -1;
    for (int i = 0; i < TRIANGLE_COUNT; i++) {
        float t_i;
        if (ray_triangle_intersection(t_i, origin, direction, scene[i]) && t_i < closest_t) {
            closest_t = t_i;
            closest_index = i;
        }
    }
    out_t = closest_t;
    if (closest_index < 0)
        return false;
    out_tri = scene[closest_index];
    return true;
}


void main() {
    vec2 uv = gl_FragCoord.xy / u_resolution;
    float aspect = u_resolution.x / u_resolution.y;
    vec3 horizontal = aspect * vec3(-0.56, 0.0, 0.0);
    vec3 lower_left = camera_target - 0.5 * horizontal - 0.5 * camera_up;
    vec3 dir = get_primary_ray_direction(uv.x, uv.y, camera_position, lower_left, horizontal, camera_up);

    float t;
    triangle_t hit_tri;
    vec3 col = vec3(0.0);
    if (ray_mesh_intersection(t, hit_tri, camera_position, dir))
        col = hit_tri.color;  // albedo of the first hit
    fragColor = vec4(col, 1.0);
}
