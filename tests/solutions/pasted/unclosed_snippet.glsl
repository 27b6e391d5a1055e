// Snippets first, then my functions (written for vkpath's tests, shaped like attendees'
// notes: the slides' mainImage loop pasted half, its brace never closed).
for (int i = 0; i != SAMPLE_COUNT; ++i) {
    if (ray_mesh_intersection(t, tri, origin, direction)) {
        // ... shade the hit

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
