// The phase function of a participating medium: Henyey and Greenstein's (1941), the
// scattering at a point of a medium as the BSDF is at a surface (pbrt-v4's HGPhaseFunction,
// Mitsuba 3's hg). A phase function is a density w.r.t. solid angle over the sphere, so its
// value is its sampler's density: p(l) = get_phase_function_density(), the sample's weight
// p / p = 1, and no cosine and no side rule enter the scattered light.
//
// Directions, as at a surface: `view` points towards where the path came from (minus the
// ray's direction), `direction` towards where light arrives from (the next vertex), both unit,
// world space. Light travels along -direction and leaves along view, so the scattering angle
// theta has cos theta = dot(-direction, view); g > 0 scatters forwards (direction near -view,
// the path goes on straight), g < 0 backwards, g = 0 is isotropic.
//
// Rust twin: src/cpu/phase_function.rs (same names, same maths).
#ifndef VKPATH_PHASE_FUNCTION_GLSL
#define VKPATH_PHASE_FUNCTION_GLSL

#include "workshop.glsl"
#include "shading_basis.glsl"

// Below this |g| the sampler takes the isotropic closed form: the general one divides by 2 g
// and loses all precision to cancellation as g goes to 0 (pbrt-v4 uses the same bound).
#define HENYEY_GREENSTEIN_ISOTROPIC_G 1.0e-3

// Henyey-Greenstein's phase function at scattering angle theta (1/sr):
// p(cos theta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos theta)^(3/2)).
// \param cos_theta Cosine of the angle between the light's direction of travel before and
//        after scattering, in [-1, 1]
// \param g The mean cosine of the scattering angle, in (-1, 1)
float get_henyey_greenstein(float cos_theta, float g) {
    float denominator = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * M_PI * denominator * sqrt(denominator));
}

// The phase function for light arriving from `direction` and leaving towards `view` (both
// unit, world space, away from the point): get_henyey_greenstein(dot(-direction, view), g).
float get_phase_function(vec3 view, vec3 direction, float g) {
    return get_henyey_greenstein(-dot(direction, view), g);
}

// Density w.r.t. solid angle with which sample_phase_function() returns `direction`: the
// phase function itself.
float get_phase_function_density(vec3 view, vec3 direction, float g) {
    return get_phase_function(view, direction, g);
}

// A direction distributed as the phase function, by inverting its CDF in cos theta (pbrt-v4's
// SampleHenyeyGreenstein, with the same sign convention: u_0 = 0 gives theta = 0) and a
// uniform azimuth around -view.
// \param random_numbers (u_0, u_1) in [0, 1)^2: the cosine and the azimuth
// \param view Unit direction towards where the path came from, world space
// \return Unit direction towards where the path goes on, world space
vec3 sample_phase_function(vec2 random_numbers, vec3 view, float g) {
    float cos_theta;
    if (abs(g) < HENYEY_GREENSTEIN_ISOTROPIC_G)
        cos_theta = 1.0 - 2.0 * random_numbers[0];
    else {
        float ratio = (1.0 - g * g) / (1.0 + g - 2.0 * g * random_numbers[0]);
        cos_theta = (1.0 + g * g - ratio * ratio) / (2.0 * g);
    }
    cos_theta = clamp(cos_theta, -1.0, 1.0);
    float sin_theta = sqrt(max(0.0, 1.0 - cos_theta * cos_theta));
    float phi = 2.0 * M_PI * random_numbers[1];
    // The angle is measured from the light's direction of travel, -view
    vec3 local = vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
    return normalize(get_shading_basis(-view) * local);
}

#endif
