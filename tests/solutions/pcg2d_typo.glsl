// A typical mistake: PCG2D with one constant mistyped (1664524u instead of 1664525u in the
// second round). `vkpath check` must reject it and show seeds, expected and actual values.
vec2 get_random_numbers(inout uvec2 seed) {
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664524u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    return vec2(seed) * 2.32830643654e-10;
}
