// Path guiding in the path loop (--guiding; glsl/guiding.glsl is the guide itself): at
// every vertex where nee and mis take light samples and the guide has learned its cell,
// the direction comes from the one-sample mixture of BSDF and guide sampling, and every
// density that MIS weighs against (the found emission's, the light samples') is the
// mixture's. In training frames (GUIDING_TRAINING) the loop also records its first
// GUIDE_TRAINING_VERTEX_COUNT such vertices, guided or not, and at the end of the path
// splats each one's estimate of the radiance that arrived along its direction, divided by
// the direction's density (Mueller et al. 2017), into the training buffer with integer
// atomics: the host builds the next guide from those sums (vkpath::guiding).
//
// With GUIDING_OFF all of it is compiled out: get_path_direction_density() is
// get_bsdf_density(), no random number is drawn, nothing is recorded, and images keep
// every bit.
//
// Random numbers at a guided vertex (glsl/sample_dimensions.glsl): the first number of its
// VERTEX_PAIR_GUIDE_CHOICE pair chooses BSDF (below GUIDE_BSDF_FRACTION) or guide; then the
// BSDF's pairs as sample_path_direction() draws them, or the VERTEX_PAIR_GUIDE_DIRECTION pair
// for sample_guide_direction(). Unguided vertices draw neither.
//
// Every function here takes the path's scattering vertex (glsl/scattering_vertex.glsl), not
// the surface: a point in a medium would be guided (and train) through the same functions.
//
// Needs GUIDING (SPEC_GUIDING) declared by the includer, and glsl/scattering_vertex.glsl's
// and glsl/sobol.glsl's functions.
#ifndef VKPATH_PATH_GUIDING_GLSL
#define VKPATH_PATH_GUIDING_GLSL

#include "scattering_vertex.glsl"
#include "sobol.glsl"

layout(set = 0, binding = BINDING_GUIDE) uniform utextureBuffer g_guide_texels;
layout(set = 0, binding = BINDING_GUIDE_SPLATS, std430) buffer guide_splats {
    uint g_guide_splat_words[];
};

#include "guiding.glsl"

// Whether this frame records training splats.
bool is_guide_training() {
    return GUIDING == GUIDING_TRAINING;
}

// The cell of a vertex that takes light samples (what guides and what trains): at its
// position, facing the surface's geometric normal on the ray's side; GUIDE_NO_CELL without
// guiding, where the guide has no cell or no light samples are taken.
uint get_path_guide_grid_cell(scattering_vertex_t vertex, bool light_sampled) {
    if (GUIDING == GUIDING_OFF || !light_sampled)
        return GUIDE_NO_CELL;
    return get_guide_cell_index(vertex.position, vertex.surface.geometric_normal);
}

// Whether the guide may sample directions at `surface`: Lambert always; glTF materials unless
// glossy (a metal smoother than GUIDE_MIN_ROUGHNESS) or layered (a clear coat, sheen):
// there half of the samples would leave the BSDF's narrow lobe for the guide, which
// measurably raised the showcase's error (docs/guiding.md). Such vertices still train.
// (A surface rule: is_guided_vertex() asks it of a surface vertex.)
bool is_guided_surface(surface_t surface) {
#ifdef USE_MATERIALS
    if (has_layers(surface))
        return false;
    return surface.material.metallic < 0.5 || surface.material.roughness >= GUIDE_MIN_ROUGHNESS;
#else
    return true;
#endif
}

// Whether the guide may sample directions at `vertex` (a surface vertex: is_guided_surface()).
bool is_guided_vertex(scattering_vertex_t vertex) {
    return is_guided_surface(vertex.surface);
}

// The cell that guides `vertex` in grid cell `grid_cell`: itself where the guide learned it
// and the vertex is guided, else GUIDE_NO_CELL (the BSDF samples alone).
uint get_path_guide_cell(uint grid_cell, scattering_vertex_t vertex) {
    if (GUIDING == GUIDING_OFF)
        return GUIDE_NO_CELL;
    return (is_guided_cell(grid_cell) && is_guided_vertex(vertex)) ? grid_cell : GUIDE_NO_CELL;
}

// Density w.r.t. solid angle with which the path loop samples `direction` at the current
// vertex (g_path.guide_cell): the BSDF's, or in a guided cell the mixture's. What MIS
// weighs light samples and found emission against.
float get_path_direction_density(scattering_vertex_t vertex, vec3 direction) {
    float bsdf_density = get_vertex_scattering_density(vertex, direction);
    if (GUIDING == GUIDING_OFF || g_path.guide_cell == GUIDE_NO_CELL)
        return bsdf_density;
    return get_guided_mixture_density(bsdf_density, get_guide_density(g_path.guide_cell, direction));
}

// A direction from the one-sample mixture at a guided vertex (cell `guide_cell`): with
// probability GUIDE_BSDF_FRACTION the BSDF's sample (`bsdf_sample`, drawn by the caller
// only when chosen), else the guide's. Its density (for MIS) is the mixture's as
// get_path_direction_density() evaluates it, p~ = c p_bsdf + (1 - c) p~_guide, with the
// guide's density looked up by the direction's bin; its weight is get_bsdf() / p~, and for
// a guide sample also p~_guide / p_guide, p_guide the density of the bin the sampler chose.
// That is the one-sample balance heuristic over the two techniques, whose weights sum to 1
// whatever p~_guide is: unbiased even where the GPU's arctangent (Vulkan allows it 4096
// ulps) puts a sample near a bin edge in the neighbouring bin, which a plain
// get_bsdf() / p~ would not be (tests/guiding.rs counts those samples). A BSDF sample of a
// delta lobe (BSDF_LOBE_DELTA) bypasses the mixture: the guide never finds its peak, so its
// weight is its own f / p over the chance GUIDE_BSDF_FRACTION of the BSDF's turn, and its
// density stays 0.
bsdf_sample_t get_guided_direction(scattering_vertex_t vertex, uint guide_cell, bsdf_sample_t bsdf_sample, bool bsdf_chosen, vec2 guide_random_numbers) {
    if (bsdf_chosen && (bsdf_sample.lobes & BSDF_LOBE_DELTA) != 0u) {
        bsdf_sample_t delta = bsdf_sample;
        delta.weight = bsdf_sample.weight / GUIDE_BSDF_FRACTION;
        return delta;
    }
    bsdf_sample_t guided = bsdf_sample;
    // The guide's density of the bin its sampler chose (p_guide; only for a guide sample).
    float sampled = 0.0;
    if (!bsdf_chosen) {
        uint bin;
        float bin_probability;
        guided.direction = sample_guide_direction(guide_cell, guide_random_numbers, bin, bin_probability);
        guided.lobes = BSDF_LOBE_REFLECT;
        guided.eta = 1.0;
        sampled = bin_probability * (float(GUIDE_BIN_COUNT) / (4.0 * M_PI));
    }
    // One lookup for either technique's direction (on lavapipe both sides of an `if` run).
    float looked_up = get_guide_density(guide_cell, guided.direction);
    if (bsdf_chosen) {
        // get_bsdf() / p~ from the BSDF sample's own weight get_bsdf() / p_bsdf (0 where
        // p_bsdf is), without evaluating the BSDF again.
        guided.density = get_guided_mixture_density(bsdf_sample.density, looked_up);
        guided.weight = (guided.density > 0.0) ? bsdf_sample.weight * (bsdf_sample.density / guided.density) : vec3(0.0);
        return guided;
    }
    guided.density = get_guided_mixture_density(get_vertex_scattering_density(vertex, guided.direction), looked_up);
    guided.weight = (guided.density > 0.0) ? get_vertex_scattering(vertex, guided.direction) * (looked_up / (sampled * guided.density)) : vec3(0.0);
    return guided;
}

// ---- Training ----

// The vertices this path recorded (the first GUIDE_TRAINING_VERTEX_COUNT that take light
// samples inside the grid): cell, directional bin, the path's radiance after the vertex's
// light samples, and |cos theta| / (throughput after the vertex times the direction's
// density), theta the direction's angle to the shading normal.
uint g_guide_record_count = 0u;
uint g_guide_record_cells[GUIDE_TRAINING_VERTEX_COUNT];
uint g_guide_record_bins[GUIDE_TRAINING_VERTEX_COUNT];
vec3 g_guide_record_radiance[GUIDE_TRAINING_VERTEX_COUNT];
vec3 g_guide_record_scale[GUIDE_TRAINING_VERTEX_COUNT];

// Records `vertex` in grid cell `grid_cell` (theta measured from its shading normal), whose path went on
// along `direction`, sampled with `density`, with `throughput_weight` after it, `radiance`
// having been gathered up to and including its light samples. Only in training frames.
// The cosine makes the guide learn incident radiance times |cos theta|, the product that a
// diffuse BSDF's ideal sampler follows: the opening scene's guided relMSE fell from 0.00097
// to 0.00080, the Cornell box's (256^2, 256 spp) from 0.00174 to 0.00151 (docs/guiding.md).
void record_guide_vertex(uint grid_cell, scattering_vertex_t vertex, vec3 direction, float density, vec3 throughput_weight, vec3 radiance) {
    if (!is_guide_training() || grid_cell == GUIDE_NO_CELL || g_guide_record_count >= uint(GUIDE_TRAINING_VERTEX_COUNT) || !(density > 0.0))
        return;
    uint k = g_guide_record_count++;
    g_guide_record_cells[k] = grid_cell;
    g_guide_record_bins[k] = get_guide_bin_index(direction);
    g_guide_record_radiance[k] = radiance;
    float cosine = abs(dot(vertex.surface.shading_normal, direction));
    g_guide_record_scale[k] = vec3(throughput_weight.r > 0.0 ? cosine / (throughput_weight.r * density) : 0.0,
                                   throughput_weight.g > 0.0 ? cosine / (throughput_weight.g * density) : 0.0,
                                   throughput_weight.b > 0.0 ? cosine / (throughput_weight.b * density) : 0.0);
}

// A splat's value in fixed point, as (low, high) words of the integer floor(min(value
// GUIDE_FIXED_POINT_SCALE, GUIDE_MAX_SPLAT_UNITS)) (exact: a float at or above 2^32 is a
// multiple of 2^9). Rust twin: vkpath::cpu::guiding::get_guide_splat_units.
uvec2 get_guide_splat_units(float value) {
    float units = floor(min(value * GUIDE_FIXED_POINT_SCALE, GUIDE_MAX_SPLAT_UNITS));
    float high = floor(units / 4294967296.0);
    return uvec2(uint(units - high * 4294967296.0), uint(high));
}

// Adds one splat of `value` (>= 0 and finite, else nothing) to the bin's 64-bit sum, with
// the carry of its low word, and counts it for the cell.
void add_guide_splat(uint cell, uint bin, float value) {
    if (!(value >= 0.0) || isinf(value))
        return;
    uvec2 units = get_guide_splat_units(value);
    uint slot = 2u * (cell * uint(GUIDE_BIN_COUNT) + bin);
    if (units.x != 0u) {
        uint before = atomicAdd(g_guide_splat_words[slot], units.x);
        units.y += (before + units.x < before) ? 1u : 0u;
    }
    if (units.y != 0u)
        atomicAdd(g_guide_splat_words[slot + 1u], units.y);
    uint cell_count = texelFetch(g_guide_texels, 0).w;
    atomicAdd(g_guide_splat_words[2u * cell_count * uint(GUIDE_BIN_COUNT) + cell], 1u);
}

// At the end of a training path with total `radiance`: each recorded vertex's estimate of
// the radiance that arrived along its direction, (radiance - its radiance) / its
// throughput, as luminance times |cos theta| over the direction's density.
void splat_guide_records(vec3 radiance) {
    for (uint k = 0u; k < g_guide_record_count; ++k) {
        vec3 incident = (radiance - g_guide_record_radiance[k]) * g_guide_record_scale[k];
        add_guide_splat(g_guide_record_cells[k], g_guide_record_bins[k], get_luminance(incident));
    }
    g_guide_record_count = 0u;
}

#endif
