// Correct sample_sphere (theta = acos(1 - 2 u_1), uniform in cos theta) and sample_hemisphere
// (mirroring with reflect()) from the workshop, in one file with code of ANOTHER course that
// reuses workshop names with other types: struct Ray, struct Triangle, a Möller-Trumbore
// ray_triangle_intersection(Ray, Triangle, out float) and get_ray_radiance(Ray, inout uint)
// with its own uint hash RNG. `vkpath check` must pass the two samplers, list
// ray_triangle_intersection and get_ray_radiance as not judged (other parameters), and exit 0.

// ---- Path Tracing Workshop, exercises 4 and 5 ----

vec3 sample_sphere(vec2 random_numbers) {
    // cos(theta) has to be uniform in [-1, 1], not theta itself
    float theta = acos(1.0 - 2.0 * random_numbers.y);
    float phi = 2.0 * M_PI * random_numbers.x;
    return vec3(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
}

vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 w = sample_sphere(random_numbers);
    // reflect(I, N) = I - 2 dot(N, I) N, i.e. the mirror from the slides
    if (dot(normal, w) < 0.0)
        w = reflect(w, normal);
    return w;
}


// ---- Ray tracing course (week 3), kept here for comparison ----

struct Ray {
    vec3 origin;
    vec3 direction;
};

struct Triangle {
    vec3 vertex0, vertex1, vertex2;
    vec3 albedo;
};

const float PI = 3.14159265359;
const int MAX_BOUNCES = 4;
const int NUM_TRIANGLES = 3;
const vec3 SKY_COLOR = vec3(0.6, 0.7, 0.9);

uint pcg_hash(uint state) {
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

float random_float(inout uint rng_state) {
    rng_state = rng_state * 747796405u + 2891336453u;
    return float(pcg_hash(rng_state)) / 4294967296.0;
}

vec3 random_unit_vector(inout uint rng_state) {
    float z = random_float(rng_state) * 2.0 - 1.0;
    float a = random_float(rng_state) * 2.0 * PI;
    float r = sqrt(1.0 - z * z);
    return vec3(r * cos(a), r * sin(a), z);
}

Triangle scene_triangle(int index) {
    if (index == 0)
        return Triangle(vec3(-5.0, -5.0, 0.0), vec3(5.0, -5.0, 0.0), vec3(5.0, 5.0, 0.0), vec3(0.8));
    if (index == 1)
        return Triangle(vec3(-5.0, -5.0, 0.0), vec3(5.0, 5.0, 0.0), vec3(-5.0, 5.0, 0.0), vec3(0.8));
    return Triangle(vec3(-1.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.5), vec3(0.9, 0.2, 0.2));
}

// Möller-Trumbore
bool ray_triangle_intersection(Ray ray, Triangle tri, out float t) {
    const float EPSILON = 1e-7;
    t = 0.0;
    vec3 edge1 = tri.vertex1 - tri.vertex0;
    vec3 edge2 = tri.vertex2 - tri.vertex0;
    vec3 h = cross(ray.direction, edge2);
    float a = dot(edge1, h);
    if (abs(a) < EPSILON)
        return false;  // parallel
    float f = 1.0 / a;
    vec3 s = ray.origin - tri.vertex0;
    float u = f * dot(s, h);
    if (u < 0.0 || u > 1.0)
        return false;
    vec3 q = cross(s, edge1);
    float v = f * dot(ray.direction, q);
    if (v < 0.0 || u + v > 1.0)
        return false;
    t = f * dot(edge2, q);
    return t > EPSILON;
}

vec3 get_ray_radiance(Ray ray, inout uint rng_state) {
    vec3 color = vec3(0.0);
    vec3 attenuation = vec3(1.0);
    for (int bounce = 0; bounce < MAX_BOUNCES; bounce++) {
        float closest = 1e30;
        int hit_index = -1;
        for (int i = 0; i < NUM_TRIANGLES; i++) {
            float t;
            if (ray_triangle_intersection(ray, scene_triangle(i), t) && t < closest) {
                closest = t;
                hit_index = i;
            }
        }
        if (hit_index < 0) {
            color += attenuation * SKY_COLOR;
            break;
        }
        Triangle tri = scene_triangle(hit_index);
        vec3 n = normalize(cross(tri.vertex1 - tri.vertex0, tri.vertex2 - tri.vertex0));
        if (dot(n, ray.direction) > 0.0)
            n = -n;
        // Lambertian: scatter around the normal, albedo is the attenuation
        ray.origin = ray.origin + closest * ray.direction + 1e-4 * n;
        ray.direction = normalize(n + random_unit_vector(rng_state));
        attenuation *= tri.albedo;
    }
    return color;
}
