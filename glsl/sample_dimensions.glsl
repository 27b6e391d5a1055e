// The sample dimensions of the importance-sampled integrators (cosine, nee, mis): which pair of
// random numbers of a sample each decision draws, fixed by what it is and by the path vertex
// it belongs to, not by the order in which the code draws it (pbrt-v4's wavefront
// samples.cpp: each bounce's numbers at a fixed dimension). First the camera's pairs, then one
// block of VERTEX_PAIRS pairs per path vertex (0: the camera ray's hit), so that vertex
// `vertex` draws decision `offset` at pair CAMERA_PAIRS + vertex * VERTEX_PAIRS + offset
// (get_vertex_dimension_pair()). With Sobol each pair is its own scrambled 2D sequence
// (get_sobol_sample_2d()), with PCG a hash of (pixel, sample, pair) (get_pcg_sample_2d()).
// A decision that a path skips draws nothing and moves nobody else's numbers: a light sample,
// a lobe choice or a guide's choice may be taken or not, in any order, and a new decision
// (a lens, a time, a medium's distance) is a row here.
// The workshop's integrators (Exercises 6 and 7) keep drawing the workshop's PCG2D in their
// order (glsl/integrator.glsl, glsl/path_loop.glsl).
// Rust twin: src/cpu/sample_dimensions.rs (a test checks that every constant agrees).
#ifndef VKPATH_SAMPLE_DIMENSIONS_GLSL
#define VKPATH_SAMPLE_DIMENSIONS_GLSL

// ---- The camera's pairs ----
// The pixel jitter of the box filter (main(), glsl/path_tracer.comp)
const uint CAMERA_PAIR_PIXEL = 0u;
// Reserved: the point on the lens (depth of field)
const uint CAMERA_PAIR_LENS = 1u;
// The time within the shutter interval (motion blur, glsl/motion_time.glsl; its first number)
const uint CAMERA_PAIR_TIME = 2u;
// How many pairs the camera has: the first vertex's pairs start here
const uint CAMERA_PAIRS = 3u;

// ---- Each path vertex's pairs, offsets within its block ----
// The emissive triangle's choice (its first number: by power or by the light tree)
const uint VERTEX_PAIR_LIGHT_SELECTION = 0u;
// The point on the chosen emissive triangle (solid angle or area)
const uint VERTEX_PAIR_LIGHT_POINT = 1u;
// The environment map's texel (a constant environment: its direction)
const uint VERTEX_PAIR_ENVIRONMENT_TEXEL = 2u;
// The point within the environment map's texel
const uint VERTEX_PAIR_ENVIRONMENT_POINT = 3u;
// The punctual light's choice (its first number)
const uint VERTEX_PAIR_PUNCTUAL_SELECTION = 4u;
// The BSDF's (or the cosine's) direction
const uint VERTEX_PAIR_DIRECTION = 5u;
// A layered material's lobe choice (its first number)
const uint VERTEX_PAIR_LOBE = 6u;
// Path guiding: BSDF or guide (its first number)
const uint VERTEX_PAIR_GUIDE_CHOICE = 7u;
// Path guiding: the guide's direction
const uint VERTEX_PAIR_GUIDE_DIRECTION = 8u;
// Russian roulette's survival (its first number)
const uint VERTEX_PAIR_RUSSIAN_ROULETTE = 9u;
// The global medium's distance sample on the segment that ends at this vertex: its channel
// (first number) and distance (second) (glsl/path_loop.glsl, glsl/medium.glsl)
const uint VERTEX_PAIR_MEDIUM_DISTANCE = 10u;
// How many pairs each vertex has
const uint VERTEX_PAIRS = 11u;

// The first dimension pair of path vertex `vertex` (0: the camera ray's hit): add a
// VERTEX_PAIR_* offset to it.
uint get_vertex_dimension_pair(int vertex) {
    return CAMERA_PAIRS + uint(vertex) * VERTEX_PAIRS;
}

#endif
