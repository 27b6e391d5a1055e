// Adaptive sampling (--noise-threshold): whether a pixel's estimate is good enough to stop
// taking samples. Rust twin: `vkpath::render::adaptive::is_pixel_converged`.
#ifndef ADAPTIVE_SAMPLING_GLSL
#define ADAPTIVE_SAMPLING_GLSL

// Whether a pixel that holds `count` samples is judged now: every `min_samples` samples
// (at min_samples, 2 min_samples, ...). Judging after every sample would stop pixels at
// every chance dip of their noise estimate (each look is another chance to stop early, the
// bias of optional stopping), and the counts it stops at keep Sobol points' strata whole.
bool is_noise_check_due(float count, uint min_samples) {
    uint n = uint(count);
    return n >= min_samples && n % min_samples == 0u;
}

// Whether the relative standard error of a pixel's mean is at most `threshold`: for every
// channel, the standard error of its mean, estimated from the `count` samples' sum `sum`
// (the Kahan sum less its compensation) and sum of squares `sum_of_squares`, is at most
// `threshold` times the mean of the pixel's brightest channel. Squared, so that no square
// root rounds differently from the Rust twin:
//   s_c^2 = (sum_of_squares_c - count mean_c^2) / (count - 1)   (the sample variance)
//   converged  <=>  max_c s_c^2 / count <= (threshold max_c mean_c)^2.
// A pixel whose samples were all equal (black background: all 0) has s = 0 and is
// converged. Needs count >= 2.
bool is_pixel_converged(vec3 sum, float count, vec3 sum_of_squares, float threshold) {
    // `precise` keeps the compiler from fusing or reordering, as the twin computes.
    precise vec3 mean = sum / count;
    precise vec3 deviation = sum_of_squares - count * (mean * mean);
    precise vec3 variance_of_mean = max(deviation, vec3(0.0)) / ((count - 1.0) * count);
    float largest_variance = max(variance_of_mean.r, max(variance_of_mean.g, variance_of_mean.b));
    precise float limit = threshold * max(mean.r, max(mean.g, mean.b));
    precise float limit_squared = limit * limit;
    return largest_variance <= limit_squared;
}

#endif
