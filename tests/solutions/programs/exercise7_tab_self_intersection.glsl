// The workshop's Exercise 7 as a whole ShaderToy Buffer A tab, as the slides have it:
// ray_triangle_intersection accepts t >= 0 and the path loop moves the origin to the hit
// point without an offset, so rays hit the surface they leave (self-intersection). Every
// function passes on its own (get_ray_radiance with a self-intersection warning), but the
// program renders darker than the reference: `vkpath check` fails the program and names
// self-intersection.
// Path Tracing Workshop, Buffer A
#define M_PI 3.141592653589793238462643
#define TRIANGLE_COUNT 30
#define MAX_PATH_LENGTH 5
#define SAMPLE_COUNT 8

// A triangle with its shading attributes
struct triangle_t {
    vec3 positions[3];
    vec3 normal;
    vec3 color;
    vec3 emission;
};


// Exercise 1: direction of the primary ray through (x, y) in [0,1]^2
vec3 get_primary_ray_direction(float x, float y, vec3 camera_position, vec3 left_bottom, vec3 right, vec3 up) {
    vec3 point = left_bottom + x * right + y * up;
    return normalize(point - camera_position);
}


// Exercise 2: ray-triangle intersection
bool ray_triangle_intersection(out float out_t, vec3 origin, vec3 direction, triangle_t tri) {
    // origin + t * direction = v0 + b1 * (v1 - v0) + b2 * (v2 - v0)
    // <=> mat3(-direction, v1 - v0, v2 - v0) * (t, b1, b2) = origin - v0
    vec3 v0 = tri.positions[0];
    vec3 v1 = tri.positions[1];
    vec3 v2 = tri.positions[2];
    mat3 mat = mat3(-direction, v1 - v0, v2 - v0);
    vec3 solution = inverse(mat) * (origin - v0);
    float t = solution.x;
    float b1 = solution.y;
    float b2 = solution.z;
    out_t = t;
    return t >= 0.0 && b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0;
}


// Exercise 3: the closest hit with the Cornell box
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
    out_t = 1.0e38;
    bool hit = false;
    for (int i = 0; i != TRIANGLE_COUNT; ++i) {
        float t;
        if (ray_triangle_intersection(t, origin, direction, tris[i]) && t < out_t) {
            out_t = t;
            out_tri = tris[i];
            hit = true;
        }
    }
    return hit;
}


// A pseudo-random number generator
// \param seed Numbers that are different for each invocation. Gets updated so
//           that it can be reused.
// \return Two independent, uniform, pseudo-random numbers in [0,1) (u_0, u_1)
vec2 get_random_numbers(inout uvec2 seed) {
    // This is PCG2D: https://jcgt.org/published/0009/03/02/
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    // Convert to float. The constant here is 2^-32.
    return vec2(seed) * 2.32830643654e-10;
}


// Exercise 4: uniform sphere sampling
vec3 sample_sphere(vec2 random_numbers) {
    float z = 2.0 * random_numbers.y - 1.0;
    float phi = 2.0 * M_PI * random_numbers.x;
    float x = cos(phi) * sqrt(1.0 - z * z);
    float y = sin(phi) * sqrt(1.0 - z * z);
    return vec3(x, y, z);
}


// Exercise 5: uniform hemisphere sampling
vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 direction = sample_sphere(random_numbers);
    // mirror at the tangent plane if it points below the surface
    if (dot(normal, direction) < 0.0)
        direction -= 2.0 * dot(normal, direction) * normal;
    return direction;
}


// Exercise 6: emission plus direct illumination with one sample
vec3 compute_direct_illumination(vec3 shading_position, triangle_t triangle, inout uvec2 seed) {
    vec3 direction = sample_hemisphere(get_random_numbers(seed), triangle.normal);
    float t;
    triangle_t light;
    vec3 incoming = vec3(0.0);
    if (ray_mesh_intersection(t, light, shading_position, direction))
        incoming = light.emission;
    // L_e(x) + a(x) / pi * 2 pi * L_e(y) * dot(n(x), w)
    return triangle.emission + triangle.color / M_PI * 2.0 * M_PI * incoming * dot(triangle.normal, direction);
}


// Exercise 7: path tracing
vec3 get_ray_radiance(vec3 origin, vec3 direction, inout uvec2 seed) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    for (int i = 0; i != MAX_PATH_LENGTH; ++i) {
        float t;
        triangle_t tri;
        if (!ray_mesh_intersection(t, tri, origin, direction))
            break;
        origin += t * direction;
        radiance += throughput * tri.emission;
        direction = sample_hemisphere(get_random_numbers(seed), tri.normal);
        throughput *= tri.color * 2.0 * dot(tri.normal, direction);
    }
    return radiance;
}


void mainImage(out vec4 out_color, in vec2 pixel_coord) {
    // The camera of the Cornell box
    float aspect = iResolution.x / iResolution.y;
    vec3 camera_position = vec3(0.278, 0.8, 0.2744);
    vec3 middle = vec3(0.278, 0.0, 0.2744);
    vec3 right = aspect * vec3(-0.56, 0.0, 0.0);
    vec3 up = vec3(0.0, 0.0, 0.56);
    vec3 left_bottom = middle - 0.5 * right - 0.5 * up;
    vec2 tex_coord = pixel_coord / iResolution.xy;
    vec3 ray_direction = get_primary_ray_direction(tex_coord.x, tex_coord.y, camera_position, left_bottom, right, up);
    // Use a different seed for each pixel and each frame
    uvec2 seed = uvec2(pixel_coord) ^ uvec2(iFrame << 16);
    out_color.rgb = vec3(0.0);
    for (int i = 0; i != SAMPLE_COUNT; ++i)
        out_color.rgb += get_ray_radiance(camera_position, ray_direction, seed);
    out_color.rgb /= float(SAMPLE_COUNT);
    out_color.a = 1.0;
    // Progressive rendering: average with the previous frames (iChannel0 is this buffer)
    vec3 previous = texture(iChannel0, pixel_coord / iResolution.xy).rgb;
    out_color.rgb = mix(previous, out_color.rgb, 1.0 / float(iFrame + 1));
}
