// A ShaderToy Image tab for Exercise 6 (direct illumination), as an attendee has it: the
// defines, the struct, ray_triangle_intersection, ray_mesh_intersection, sample_sphere,
// sample_hemisphere, get_random_numbers, get_primary_ray_direction and
// compute_direct_illumination solved, and mainImage(fragColor, fragCoord) that also calls a
// small vignette helper of the attendee's own (it uses iTime and iResolution).
// `vkpath check` must pass every workshop function in it.
#define M_PI 3.141592653589793238462643
#define TRIANGLE_COUNT 30
#define SAMPLE_COUNT 8

struct triangle_t {
    vec3 positions[3];
    vec3 normal;
    vec3 color;
    vec3 emission;
};

// --- Part 1 ---

vec3 get_primary_ray_direction(float x, float y, vec3 camera_position, vec3 left_bottom, vec3 right, vec3 up) {
    return normalize(left_bottom + x * right + y * up - camera_position);
}

bool ray_triangle_intersection(out float out_t, vec3 origin, vec3 direction, triangle_t tri) {
    vec3 v0 = tri.positions[0];
    mat3 m = mat3(-direction, tri.positions[1] - v0, tri.positions[2] - v0);
    vec3 tbb = inverse(m) * (origin - v0);  // (t, b1, b2)
    out_t = tbb.x;
    return tbb.x >= 0.0 && tbb.y >= 0.0 && tbb.z >= 0.0 && tbb.y + tbb.z <= 1.0;
}

bool ray_mesh_intersection(out float out_t, out triangle_t out_tri, vec3 origin, vec3 direction) {
    triangle_t tris[TRIANGLE_COUNT];
    tris[0] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 0.548799932), vec3(0.555999935, -0.559199989, 4e-08), vec3(1.33e-07, -0.559199989, 4e-08)), vec3(0.0, 1.0, 0.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    tris[1] = triangle_t(vec3[3](vec3(0.313999921, -0.45599997, 0.329999954), vec3(0.313999921, -0.45599997, 4e-08), vec3(0.472000152, -0.406000137, 4e-08)), vec3(0.301707575, -0.953400513, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[2] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(0.555999935, -0.559199989, 4e-08), vec3(0.555999935, -1.19e-07, 4e-08)), vec3(0.0, 0.0, 1.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    tris[3] = triangle_t(vec3[3](vec3(0.264999926, -0.296000093, 0.329999954), vec3(0.264999926, -0.296000093, 4e-08), vec3(0.313999921, -0.45599997, 4e-08)), vec3(-0.956165759, -0.292825958, -0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[4] = triangle_t(vec3[3](vec3(0.423000127, -0.24699989, 4e-08), vec3(0.472000152, -0.406000137, 0.329999954), vec3(0.472000152, -0.406000137, 4e-08)), vec3(0.955649049, 0.294507888, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[5] = triangle_t(vec3[3](vec3(0.264999926, -0.296000093, 0.329999954), vec3(0.313999921, -0.45599997, 4e-08), vec3(0.313999921, -0.45599997, 0.329999954)), vec3(-0.956165759, -0.292825958, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[6] = triangle_t(vec3[3](vec3(0.313999921, -0.45599997, 0.329999954), vec3(0.472000152, -0.406000137, 4e-08), vec3(0.472000152, -0.406000137, 0.329999954)), vec3(0.301707575, -0.953400513, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[7] = triangle_t(vec3[3](vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.082000092, -0.225000143, 0.165000007), vec3(0.082000092, -0.225000143, 4e-08)), vec3(-0.285119946, -0.958491845, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[8] = triangle_t(vec3[3](vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.082000092, -0.225000143, 4e-08), vec3(0.240000039, -0.271999955, 4e-08)), vec3(-0.285119946, -0.958491845, -0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[9] = triangle_t(vec3[3](vec3(0.290000081, -0.113999903, 4e-08), vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.240000039, -0.271999955, 4e-08)), vec3(0.953400053, -0.30170903, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[10] = triangle_t(vec3[3](vec3(0.082000092, -0.225000143, 4e-08), vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.13000007, -0.064999968, 4e-08)), vec3(-0.957826408, 0.287347476, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[11] = triangle_t(vec3[3](vec3(0.082000092, -0.225000143, 4e-08), vec3(0.082000092, -0.225000143, 0.165000007), vec3(0.13000007, -0.064999968, 0.165000007)), vec3(-0.957826408, 0.287347476, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[12] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(0.555999935, -1.19e-07, 4e-08), vec3(1.33e-07, -1.19e-07, 4e-08)), vec3(0.0, 0.0, 1.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    tris[13] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 4e-08), vec3(0.290000081, -0.114000171, 0.165000007), vec3(0.290000081, -0.113999903, 4e-08)), vec3(0.292825408, 0.956165927, 1.554e-06), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[14] = triangle_t(vec3[3](vec3(0.290000081, -0.113999903, 4e-08), vec3(0.290000081, -0.114000171, 0.165000007), vec3(0.240000039, -0.271999955, 0.165000007)), vec3(0.953399906, -0.301709496, -4.9e-07), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[15] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 4e-08), vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.290000081, -0.114000171, 0.165000007)), vec3(0.292826874, 0.956165478, -0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[16] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(1.33e-07, -1.19e-07, 4e-08), vec3(1.33e-07, -1.19e-07, 0.548799932)), vec3(1.0, 0.0, 0.0), vec3(0.289999992, 0.663999975, 0.324999988), vec3(0.0, 0.0, 0.0));
    tris[17] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.082000092, -0.225000143, 0.165000007), vec3(0.240000039, -0.271999955, 0.165000007)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[18] = triangle_t(vec3[3](vec3(0.13000007, -0.064999968, 0.165000007), vec3(0.240000039, -0.271999955, 0.165000007), vec3(0.290000081, -0.114000171, 0.165000007)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[19] = triangle_t(vec3[3](vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.423000127, -0.24699989, 4e-08), vec3(0.264999926, -0.296000093, 4e-08)), vec3(-0.29620985, 0.955122885, 7.76e-07), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[20] = triangle_t(vec3[3](vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.264999926, -0.296000093, 4e-08), vec3(0.264999926, -0.296000093, 0.329999954)), vec3(-0.296208371, 0.955123343, 0.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[21] = triangle_t(vec3[3](vec3(0.423000127, -0.24699989, 4e-08), vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.472000152, -0.406000137, 0.329999954)), vec3(0.955648909, 0.294508341, 2.39e-07), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[22] = triangle_t(vec3[3](vec3(0.555999935, -1.19e-07, 0.548799932), vec3(0.555999935, -1.19e-07, 4e-08), vec3(0.555999935, -0.559199989, 4e-08)), vec3(-1.0, 0.0, -0.0), vec3(0.730000019, 0.246000007, 0.250999987), vec3(0.0, 0.0, 0.0));
    tris[23] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 4e-08), vec3(1.33e-07, -1.19e-07, 0.548799932), vec3(1.33e-07, -0.559199989, 0.548799932)), vec3(1.0, 0.0, 0.0), vec3(0.289999992, 0.663999975, 0.324999988), vec3(0.0, 0.0, 0.0));
    tris[24] = triangle_t(vec3[3](vec3(1.33e-07, -1.19e-07, 0.548799932), vec3(0.555999935, -0.559199989, 0.548799932), vec3(1.33e-07, -0.559199989, 0.548799932)), vec3(0.0, 0.0, -1.0), vec3(0.0, 0.0, 0.0), vec3(3.0, 3.0, 3.0));
    tris[25] = triangle_t(vec3[3](vec3(1.33e-07, -0.559199989, 0.548799932), vec3(0.555999935, -0.559199989, 0.548799932), vec3(0.555999935, -0.559199989, 4e-08)), vec3(-0.0, 1.0, 0.0), vec3(0.874000013, 0.874000013, 0.875), vec3(0.0, 0.0, 0.0));
    tris[26] = triangle_t(vec3[3](vec3(0.472000152, -0.406000137, 0.329999954), vec3(0.264999926, -0.296000093, 0.329999954), vec3(0.313999921, -0.45599997, 0.329999954)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[27] = triangle_t(vec3[3](vec3(0.555999935, -1.19e-07, 0.548799932), vec3(0.555999935, -0.559199989, 4e-08), vec3(0.555999935, -0.559199989, 0.548799932)), vec3(-1.0, -0.0, 0.0), vec3(0.730000019, 0.246000007, 0.250999987), vec3(0.0, 0.0, 0.0));
    tris[28] = triangle_t(vec3[3](vec3(0.472000152, -0.406000137, 0.329999954), vec3(0.423000127, -0.247000158, 0.329999954), vec3(0.264999926, -0.296000093, 0.329999954)), vec3(0.0, 0.0, 1.0), vec3(0.839039981, 0.839039981, 0.839999974), vec3(0.0, 0.0, 0.0));
    tris[29] = triangle_t(vec3[3](vec3(1.33e-07, -1.19e-07, 0.548799932), vec3(0.555999935, -1.19e-07, 0.548799932), vec3(0.555999935, -0.559199989, 0.548799932)), vec3(0.0, 0.0, -1.0), vec3(0.0, 0.0, 0.0), vec3(3.0, 3.0, 3.0));
    bool found = false;
    out_t = 1.0e38;
    for (int i = 0; i != TRIANGLE_COUNT; ++i) {
        float t;
        if (ray_triangle_intersection(t, origin, direction, tris[i])) {
            if (t < out_t) {
                out_t = t;
                out_tri = tris[i];
                found = true;
            }
        }
    }
    return found;
}

// --- Part 2 ---

// PCG2D, from the slides
vec2 get_random_numbers(inout uvec2 seed) {
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    return vec2(seed) * 2.32830643654e-10;
}

// Exercise 4
vec3 sample_sphere(vec2 random_numbers) {
    float phi = 2.0 * M_PI * random_numbers.x;
    float z = 2.0 * random_numbers.y - 1.0;
    float r = sqrt(1.0 - z * z);
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Exercise 5
vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 w = sample_sphere(random_numbers);
    float n_dot_w = dot(normal, w);
    if (n_dot_w < 0.0)
        w -= 2.0 * n_dot_w * normal;
    return w;
}

// Exercise 6
vec3 compute_direct_illumination(vec3 shading_position, triangle_t triangle, inout uvec2 seed) {
    vec3 w = sample_hemisphere(get_random_numbers(seed), triangle.normal);
    float t;
    triangle_t other;
    vec3 L_e_y = vec3(0.0);
    if (ray_mesh_intersection(t, other, shading_position, w))
        L_e_y = other.emission;
    vec3 brdf = triangle.color / M_PI;
    return triangle.emission + brdf * 2.0 * M_PI * L_e_y * dot(triangle.normal, w);
}

// my own: a slowly pulsing vignette, just for looks
float vignette(vec2 uv) {
    vec2 d = uv - 0.5;
    d.x *= iResolution.x / iResolution.y;
    float strength = 0.35 + 0.05 * sin(0.5 * iTime);
    return clamp(1.0 - strength * dot(d, d), 0.0, 1.0);
}

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec2 uv = fragCoord / iResolution.xy;
    float aspect = iResolution.x / iResolution.y;
    vec3 camera_position = vec3(0.278, 0.8, 0.2744);
    vec3 right = aspect * vec3(-0.56, 0.0, 0.0);
    vec3 up = vec3(0.0, 0.0, 0.56);
    vec3 left_bottom = vec3(0.278, 0.0, 0.2744) - 0.5 * right - 0.5 * up;
    vec3 ray_direction = get_primary_ray_direction(uv.x, uv.y, camera_position, left_bottom, right, up);

    uvec2 seed = uvec2(fragCoord) ^ uvec2(iFrame << 16);
    vec3 color = vec3(0.0);
    float t;
    triangle_t tri;
    if (ray_mesh_intersection(t, tri, camera_position, ray_direction)) {
        vec3 shading_position = camera_position + t * ray_direction;
        for (int i = 0; i != SAMPLE_COUNT; ++i)
            color += compute_direct_illumination(shading_position, tri, seed);
        color /= float(SAMPLE_COUNT);
    }
    fragColor = vec4(color * vignette(uv), 1.0);
}
