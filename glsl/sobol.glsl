// Low-discrepancy samples for the importance-sampled integrators: the first two dimensions of
// the Sobol sequence with hash-based Owen scrambling and index shuffling, after Brent Burley
// 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4), https://jcgt.org/published/0009/04/01/
// Each pair of random numbers of a path (a "dimension pair": the pixel jitter, then the light
// sample, the cosine direction, Russian roulette, ... in the order they are drawn) is its own
// scrambled 2D Sobol sequence, decorrelated from the others and from other pixels by seeds.
// Rust twins: src/cpu/sobol.rs. Needs SAMPLER defined by the includer (SAMPLER_PCG or
// SAMPLER_SOBOL), and get_random_numbers() (workshop.glsl) for SAMPLER_PCG.
#ifndef VKPATH_SOBOL_GLSL
#define VKPATH_SOBOL_GLSL

#include "shared.h"

// The bits of x in reverse order (bit 0 becomes bit 31).
uint sobol_reverse_bits(uint x) {
    return bitfieldReverse(x);
}

// Burley's improved Laine-Karras hash: a permutation of the uints in which each bit depends
// only on the bits below it, so that (applied to bit-reversed numbers) it permutes the
// elementary intervals of [0,1) recursively, as an Owen scramble does.
// \param x The value to permute
// \param seed Selects the permutation
uint laine_karras_permutation(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// An Owen scramble of a 32-bit fixed-point number in [0,1): reverse the bits so that the most
// significant bit is lowest, permute with laine_karras_permutation(), reverse back.
// \param x Fixed-point number (value x * 2^-32)
// \param seed Selects the scramble
uint nested_uniform_scramble(uint x, uint seed) {
    x = sobol_reverse_bits(x);
    x = laine_karras_permutation(x, seed);
    x = sobol_reverse_bits(x);
    return x;
}

// Dimension 0 of the Sobol sequence (the van der Corput sequence), 32-bit fixed point: the
// direction numbers are 2^-1, 2^-2, ..., so the point is the bit-reversed index.
uint sobol_dimension_0(uint index) {
    return sobol_reverse_bits(index);
}

// Dimension 1 of the Sobol sequence, 32-bit fixed point: the XOR of the direction numbers
// v_j of the index's set bits j, with v_0 = 2^-1 and v_j = v_{j-1} ^ (v_{j-1} >> 1) (the
// primitive polynomial x + 1), i.e. 0x80000000, 0xc0000000, 0xa0000000, 0xf0000000, ...
// In closed form: v_j has bit 31 - k set iff C(j, k) is odd, i.e. iff the bits of k are a
// subset of those of j (Lucas), so bit 31 - k of the result is the XOR of the index bits j
// over all supersets j of k: five shift-XOR steps (one per bit of k), then a bit reversal.
// A loop over the index's bits would run 32 times for the shuffled indices of
// get_sobol_sample_2d(), which made Sobol samples 1.45x as slow as PCG2D on lavapipe.
uint sobol_dimension_1(uint index) {
    uint superset_xor = index;
    superset_xor ^= (superset_xor >> 1u) & 0x55555555u;
    superset_xor ^= (superset_xor >> 2u) & 0x33333333u;
    superset_xor ^= (superset_xor >> 4u) & 0x0f0f0f0fu;
    superset_xor ^= (superset_xor >> 8u) & 0x00ff00ffu;
    superset_xor ^= (superset_xor >> 16u) & 0x0000ffffu;
    return sobol_reverse_bits(superset_xor);
}

// A well-mixed 32-bit hash (the PCG hash of Jarzynski and Olano 2020, "Hash Functions for GPU
// Rendering", JCGT 9(3)), to turn structured numbers into scramble seeds.
uint sobol_hash(uint value) {
    uint state = value * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Combines a seed with a value (boost's hash_combine, as Burley's paper uses it).
uint sobol_hash_combine(uint seed, uint value) {
    return seed ^ (value + 0x9e3779b9u + (seed << 6u) + (seed >> 2u));
}

// The seed of a pixel's Sobol sequences: a hash of the pixel and the user's --seed.
// \param pixel Pixel index from the bottom-left
// \param user_seed The --seed option
uint get_sobol_pixel_seed(uvec2 pixel, uint user_seed) {
    return sobol_hash(sobol_hash_combine(sobol_hash_combine(sobol_hash(user_seed), pixel.x), pixel.y));
}

// Converts a 32-bit fixed-point number to a float in [0,1). Only the top 24 bits are kept:
// float(x) * 2^-32 as in PCG2D rounds x >= 2^32 - 2^7 up to exactly 1.0, which samplers that
// expect [0,1) must not see; (x >> 8) * 2^-24 is exact and at most 1 - 2^-24.
float sobol_to_float(uint x) {
    return float(x >> 8u) * 5.9604644775390625e-08;
}

// Sample `sample_index` of the 2D Owen-scrambled Sobol sequence of one dimension pair of one
// pixel (Burley 2020, listing 3): the index is shuffled by a nested uniform scramble, so that
// each pixel and dimension pair visits the points in a different order (decorrelating the
// pairs of one path), and each output dimension gets its own Owen scramble.
// \param sample_index Index of the sample within the pixel, from 0
// \param dimension_pair Which pair of random numbers of the path (0: the first drawn)
// \param pixel_seed get_sobol_pixel_seed() of the pixel
// \return Two numbers in [0,1); for sample indices 0..2^k-1 they form a (0,k,2)-net
vec2 get_sobol_sample_2d(uint sample_index, uint dimension_pair, uint pixel_seed) {
    uint seed = sobol_hash(sobol_hash_combine(pixel_seed, dimension_pair));
    uint index = nested_uniform_scramble(sample_index, seed);
    uint x = nested_uniform_scramble(sobol_dimension_0(index), sobol_hash_combine(seed, 0u));
    uint y = nested_uniform_scramble(sobol_dimension_1(index), sobol_hash_combine(seed, 1u));
    return vec2(sobol_to_float(x), sobol_to_float(y));
}

// The current sample's Sobol state: g_path.sample_index, .pixel_seed, .dimension_pair
#include "path_state.glsl"

// The random numbers of the importance-sampled integrators: the next dimension pair of the
// sample's scrambled Sobol sequence with SAMPLER_SOBOL, the workshop's PCG2D otherwise.
// \param seed The PCG2D state of the sample (untouched with SAMPLER_SOBOL)
// \return Two uniform numbers in [0,1)
vec2 get_path_random_numbers(inout uvec2 seed) {
    if (SAMPLER == SAMPLER_SOBOL)
        return get_sobol_sample_2d(g_path.sample_index, g_path.dimension_pair++, g_path.pixel_seed);
    return get_random_numbers(seed);
}

#endif
