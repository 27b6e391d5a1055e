// The random numbers of the importance-sampled integrators (cosine, nee, mis), one pair per
// sample dimension pair of glsl/sample_dimensions.glsl, whichever order the path loop draws
// them in: with SAMPLER_SOBOL the first two dimensions of the Sobol sequence with hash-based
// Owen scrambling and index shuffling, after Brent Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4), https://jcgt.org/published/0009/04/01/ (each dimension pair is its
// own scrambled 2D Sobol sequence, decorrelated from the others and from other pixels by
// seeds); with SAMPLER_PCG independent numbers hashed from the pixel, the sample index and the
// dimension pair (get_pcg_sample_2d()). The workshop's integrators draw the workshop's PCG2D
// stream instead (get_random_numbers(), glsl/workshop.glsl).
// Rust twins: src/cpu/sobol.rs. Needs SAMPLER defined by the includer (SAMPLER_PCG or
// SAMPLER_SOBOL).
#ifndef VKPATH_SOBOL_GLSL
#define VKPATH_SOBOL_GLSL

#include "shared.h"
#include "sample_dimensions.glsl"

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
// \param dimension_pair Which pair of random numbers of the sample (glsl/sample_dimensions.glsl)
// \param pixel_seed get_sobol_pixel_seed() of the pixel
// \return Two numbers in [0,1); for sample indices 0..2^k-1 they form a (0,k,2)-net
vec2 get_sobol_sample_2d(uint sample_index, uint dimension_pair, uint pixel_seed) {
    uint seed = sobol_hash(sobol_hash_combine(pixel_seed, dimension_pair));
    uint index = nested_uniform_scramble(sample_index, seed);
    uint x = nested_uniform_scramble(sobol_dimension_0(index), sobol_hash_combine(seed, 0u));
    uint y = nested_uniform_scramble(sobol_dimension_1(index), sobol_hash_combine(seed, 1u));
    return vec2(sobol_to_float(x), sobol_to_float(y));
}

// PCG2D (Jarzynski and Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3)) as a hash
// of two words: the workshop's get_random_numbers() state update, a bijection of uvec2 whose
// every output bit depends on every input bit. Written out here so that a user's
// get_random_numbers() (vkpath check) cannot change the importance-sampled integrators.
uvec2 pcg2d_hash(uvec2 v) {
    v = 1664525u * v + 1013904223u;
    v.x += 1664525u * v.y;
    v.y += 1664525u * v.x;
    v ^= (v >> 16u);
    v.x += 1664525u * v.y;
    v.y += 1664525u * v.x;
    v ^= (v >> 16u);
    return v;
}

// Independent uniform numbers for one sample and dimension pair of one pixel, as
// get_sobol_sample_2d() is called: the pair's seed (a hash of the pixel's seed and the pair,
// as Sobol's), then the sample index hashed with it, both words through PCG2D. Unlike the
// workshop's per-sample seeds (get_sample_seed(), which differ from sample to sample only in
// their high bits), both input words are full 32-bit hashes, so that samples, pixels and pairs
// are independent (src/cpu/sobol.rs tests it).
// \param sample_index Index of the sample within the pixel, from 0
// \param dimension_pair Which pair of random numbers of the sample (glsl/sample_dimensions.glsl)
// \param pixel_seed get_sobol_pixel_seed() of the pixel
// \return Two numbers in [0,1) (24 bits each, sobol_to_float())
vec2 get_pcg_sample_2d(uint sample_index, uint dimension_pair, uint pixel_seed) {
    uint pair_seed = sobol_hash(sobol_hash_combine(pixel_seed, dimension_pair));
    uvec2 hashed = pcg2d_hash(uvec2(pair_seed, sobol_hash(sobol_hash_combine(pair_seed, sample_index))));
    return vec2(sobol_to_float(hashed.x), sobol_to_float(hashed.y));
}

// The current sample: g_path.sample_index, .pixel_seed
#include "path_state.glsl"

// The random numbers of the importance-sampled integrators at dimension pair `dimension_pair`
// of the current sample (glsl/sample_dimensions.glsl): Sobol's with SAMPLER_SOBOL, hashed PCG
// otherwise. The same numbers however many others the path drew before, and in which order.
// \return Two uniform numbers in [0,1)
vec2 get_path_random_numbers(uint dimension_pair) {
    if (SAMPLER == SAMPLER_SOBOL)
        return get_sobol_sample_2d(g_path.sample_index, dimension_pair, g_path.pixel_seed);
    return get_pcg_sample_2d(g_path.sample_index, dimension_pair, g_path.pixel_seed);
}

#endif
