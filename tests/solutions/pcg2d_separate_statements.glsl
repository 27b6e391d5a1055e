// A correct get_random_numbers written differently from the workshop's: PCG2D (Jarzynski and
// Olano, JCGT 2020) in scalar statements, and the conversion as a division by 2^32 (exact,
// like the multiplication by 2^-32). `vkpath check` must find the very same bits.
vec2 get_random_numbers(inout uvec2 seed) {
    uint x = seed.x * 1664525u + 1013904223u;
    uint y = seed.y * 1664525u + 1013904223u;
    x = x + y * 1664525u;
    y = y + x * 1664525u;
    x = x ^ (x >> 16u);
    y = y ^ (y >> 16u);
    x += y * 1664525u;
    y += x * 1664525u;
    x ^= x >> 16u;
    y ^= y >> 16u;
    seed = uvec2(x, y);
    return vec2(float(x), float(y)) / 4294967296.0;
}
