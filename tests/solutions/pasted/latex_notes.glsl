// Notes with the slides' formulas pasted as LaTeX (written for vkpath's tests).
Monte Carlo: $$L \approx 2{\pi}\frac{1}{N}\sum_{i=1}^{N} f(\omega_i)$$
The estimator {divides by the density} of the samples
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
