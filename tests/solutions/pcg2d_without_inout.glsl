// The slides' PCG2D with `inout` missing from the seed parameter: each call computes the
// right numbers from the seed it is given, but the caller's seed never advances, so every
// call returns the same pair. `vkpath check` must judge it (not "unusable") and fail it,
// naming the missing inout.
vec2 get_random_numbers(uvec2 seed) {
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    return vec2(seed) * 2.32830643654e-10;
}
