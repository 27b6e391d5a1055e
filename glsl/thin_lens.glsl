// Depth of field: a thin lens in front of the workshop's pinhole camera, as Mitsuba's
// `thinlens` and pbrt's perspective camera model it. The pinhole's ray through a point of the
// image (get_primary_ray_direction(), unchanged) meets the plane in focus, parallel to the
// image plane at `focus_distance` from the pinhole; the lens's ray leaves from a point of the
// aperture, a disc or a regular polygon of radius `aperture_radius` centred on the pinhole,
// towards that point. Points on the focus plane stay sharp; a point at depth Z images to the
// aperture's shape scaled by aperture_radius |Z - focus_distance| / Z on the focus plane.
// An aperture of radius 0 is not applied at all: the pinhole's image, bit for bit.
// Rust twins: src/cpu/thin_lens.rs. Needs SAMPLER defined and glsl/integrators.glsl included
// by the includer.
#ifndef VKPATH_THIN_LENS_GLSL
#define VKPATH_THIN_LENS_GLSL

#include "workshop.glsl"
#include "sobol.glsl"
#include "sample_dimensions.glsl"

// XORed into a sample's PCG2D seed to give the workshop integrators' lens sample a stream of
// its own.
const uvec2 LENS_SEED_MASK = uvec2(0x6c656e73u, 0x44f3a5c1u);

// The two random numbers of a sample's point on the aperture, at a dimension of their own:
// for the importance-sampled integrators, the fixed pair CAMERA_PAIR_LENS
// (glsl/sample_dimensions.glsl: Sobol, or hashed PCG); for the workshop's, PCG2D of the
// sample's seed XOR LENS_SEED_MASK, which leaves the sample's own PCG2D stream (and so the
// workshop's draws) as it was.
// \param sample_seed get_sample_seed() of the sample
vec2 get_lens_random_numbers(uvec2 sample_seed) {
    if (is_importance_sampled())
        return get_path_random_numbers(CAMERA_PAIR_LENS);
    uvec2 lens_seed = sample_seed ^ LENS_SEED_MASK;
    return get_random_numbers(lens_seed);
}

// A point of the unit aperture, uniform in its area: the unit disc (blades == 0) by Shirley
// and Chiu's concentric map, which keeps the strata of Sobol points; otherwise the regular
// polygon with `blades` corners on the unit circle, one of them at angle pi/2 + rotation: the
// first number chooses one of its triangles (centre, corner k, corner k + 1), all of equal
// area, and the rest of it and the second number a uniform point of that triangle.
// \param random_numbers Two uniform numbers in [0,1)
// \param blades 0 (a disc) or the polygon's number of corners, at least 3
// \param rotation The polygon's rotation about the view axis, radians
// \return The point, in units of the aperture radius (x right, y up)
vec2 sample_aperture(vec2 random_numbers, uint blades, float rotation) {
    if (blades == 0u) {
        vec2 offset = 2.0 * random_numbers - vec2(1.0);
        if (offset.x == 0.0 && offset.y == 0.0)
            return vec2(0.0);
        float radius;
        float angle;
        if (abs(offset.x) > abs(offset.y)) {
            radius = offset.x;
            angle = 0.25 * M_PI * (offset.y / offset.x);
        } else {
            radius = offset.y;
            angle = 0.5 * M_PI - 0.25 * M_PI * (offset.x / offset.y);
        }
        return radius * vec2(cos(angle), sin(angle));
    }
    float scaled = random_numbers[0] * float(blades);
    float corner = min(floor(scaled), float(blades - 1u));
    float along = sqrt(scaled - corner);
    float corner_angle = 2.0 * M_PI / float(blades);
    float first_angle = 0.5 * M_PI + rotation + corner * corner_angle;
    vec2 first_corner = vec2(cos(first_angle), sin(first_angle));
    vec2 second_corner = vec2(cos(first_angle + corner_angle), sin(first_angle + corner_angle));
    return along * mix(first_corner, second_corner, random_numbers[1]);
}

// Turns the pinhole's ray into the thin lens's: from a point of the aperture towards where the
// pinhole's ray meets the plane in focus.
// \param ray_origin The pinhole on input; the point of the aperture on output
// \param ray_direction The pinhole's normalized ray direction on input; the lens's on output
// \param right, up The image plane's edge vectors (see get_primary_ray_direction())
// \param image_plane_middle The image plane's centre, world space
// \param aperture_radius, focus_distance, blades, rotation The lens (see sample_aperture())
// \param random_numbers get_lens_random_numbers() of the sample
void apply_thin_lens(inout vec3 ray_origin, inout vec3 ray_direction, vec3 right, vec3 up, vec3 image_plane_middle, float aperture_radius, float focus_distance, uint blades, float rotation, vec2 random_numbers) {
    vec3 right_direction = normalize(right);
    vec3 up_direction = normalize(up);
    // The image plane's normal, pointing from the pinhole towards the image plane
    vec3 view_axis = normalize(cross(right, up));
    if (dot(view_axis, image_plane_middle - ray_origin) < 0.0)
        view_axis = -view_axis;
    vec3 focus_point = ray_origin + (focus_distance / dot(ray_direction, view_axis)) * ray_direction;
    vec2 aperture_point = aperture_radius * sample_aperture(random_numbers, blades, rotation);
    ray_origin += aperture_point.x * right_direction + aperture_point.y * up_direction;
    ray_direction = normalize(focus_point - ray_origin);
}

#endif
