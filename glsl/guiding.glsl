// Path guiding's guide: where light arrives from, learned per region of the scene, as a
// distribution of directions to sample (--guiding, after Mueller et al. 2017's "practical
// path guiding", simplified for a compute shader). Space is a uniform grid over the scene's
// box, and each grid position has a cell for each way a surface there can face (the
// normal's dominant axis and sign): each cell holds a histogram over GUIDE_BIN_COUNT bins of
// equal solid angle (the equal-area map z = cos theta, phi, cut GUIDE_DIRECTION_RESOLUTION
// ways each), stored as cumulative probabilities. A fixed layout with no pointers: four
// texel fetches find a cell (the last in a table of grid position and orientation to cell,
// which gives cells only where the scene has surfaces), a binary search of seven fetches
// samples a bin, two give a density, and the memory is cells x 1 KB, known before
// training. A cell that training did not reach often enough holds zeros and is not guided.
//
// Sampling is a one-sample mixture with the BSDF: with probability GUIDE_BSDF_FRACTION the
// BSDF's sampler, else the guide's, and the density of either outcome is the mixture's
// (get_guided_mixture_density()), so the estimator stays unbiased whatever the guide learned.
//
// The words are built by vkpath::guiding (GuideSplats::build()). Rust twins:
// src/cpu/guiding.rs. Needs g_guide_texels (utextureBuffer) and M_PI declared by the
// includer.
#ifndef VKPATH_GUIDING_GLSL
#define VKPATH_GUIDING_GLSL

// What get_guide_cell_index() returns outside the grid, where no surface faces the normal's
// way, and for an empty guide.
#define GUIDE_NO_CELL 0xffffffffu

// The orientation of a unit normal: 2 axis + (1 if it points down that axis), its axis the
// first of its largest components. The two faces of a wall, or a floor and the wall it
// meets, see light from different places, so they learn in different cells.
uint get_guide_orientation(vec3 normal) {
    vec3 a = abs(normal);
    uint axis = (a.x >= a.y && a.x >= a.z) ? 0u : ((a.y >= a.z) ? 1u : 2u);
    return 2u * axis + ((normal[axis] < 0.0) ? 1u : 0u);
}

// The slot of the guide's cell table for a point at `position` with `normal` (orientation
// slowest, then z, y, x fastest), GUIDE_NO_CELL outside the grid and for an empty guide;
// `cell_count` is the guide's number of cells.
uint get_guide_table_slot(vec3 position, vec3 normal, out uint cell_count) {
    uvec4 header = texelFetch(g_guide_texels, 0);
    cell_count = header.w;
    if (header.w == 0u)
        return GUIDE_NO_CELL;
    vec3 bounds_min = uintBitsToFloat(texelFetch(g_guide_texels, 1).xyz);
    vec3 cells_per_unit = uintBitsToFloat(texelFetch(g_guide_texels, 2).xyz);
    vec3 cell = floor((position - bounds_min) * cells_per_unit);
    if (!(all(greaterThanEqual(cell, vec3(0.0))) && all(lessThan(cell, vec3(header.xyz)))))
        return GUIDE_NO_CELL;
    uvec3 coordinates = uvec3(cell);
    return ((get_guide_orientation(normal) * header.z + coordinates.z) * header.y + coordinates.y) * header.x + coordinates.x;
}

// The cell that holds the distribution of a point at `position` whose surface faces
// `normal` (unit, on the side the ray came from): the cell table's entry for its grid
// position and orientation. GUIDE_NO_CELL outside the grid, and where no triangle of the
// scene could face that way (the host gives cells only to those: vkpath::guiding::GuideGrid).
uint get_guide_cell_index(vec3 position, vec3 normal) {
    uint cell_count;
    uint slot = get_guide_table_slot(position, normal, cell_count);
    if (slot == GUIDE_NO_CELL)
        return GUIDE_NO_CELL;
    uint table_texel = GUIDE_HEADER_TEXEL_COUNT + cell_count * GUIDE_CELL_TEXEL_COUNT + slot / 4u;
    return texelFetch(g_guide_texels, int(table_texel))[slot % 4u];
}

// The directional bin of a unit world-space direction: row (cos theta + 1) / 2, column
// phi / (2 pi), each cut into GUIDE_DIRECTION_RESOLUTION; bin = row * resolution + column.
uint get_guide_bin_index(vec3 direction) {
    float resolution = float(GUIDE_DIRECTION_RESOLUTION);
    float z = clamp(direction.z, -1.0, 1.0);
    // GLSL leaves atan(0, 0) undefined: the poles take phi = 0, as Rust's atan2 gives.
    float phi = (direction.x == 0.0 && direction.y == 0.0) ? 0.0 : atan(direction.y, direction.x);
    if (phi < 0.0)
        phi += 2.0 * M_PI;
    uint row = min(uint((z + 1.0) * 0.5 * resolution), uint(GUIDE_DIRECTION_RESOLUTION - 1));
    uint column = min(uint(phi * (resolution / (2.0 * M_PI))), uint(GUIDE_DIRECTION_RESOLUTION - 1));
    return row * uint(GUIDE_DIRECTION_RESOLUTION) + column;
}

// The cell's cumulative probability up to and including `bin`.
float get_guide_cumulative(uint cell_index, uint bin) {
    uint texel = GUIDE_HEADER_TEXEL_COUNT + cell_index * GUIDE_CELL_TEXEL_COUNT + bin / 4u;
    return uintBitsToFloat(texelFetch(g_guide_texels, int(texel))[bin % 4u]);
}

// Whether the cell holds a learned distribution (its last cumulative probability is 1).
bool is_guided_cell(uint cell_index) {
    return cell_index != GUIDE_NO_CELL && get_guide_cumulative(cell_index, GUIDE_BIN_COUNT - 1u) > 0.0;
}

// The probability of one bin of a guided cell.
float get_guide_bin_probability(uint cell_index, uint bin) {
    float before = (bin == 0u) ? 0.0 : get_guide_cumulative(cell_index, bin - 1u);
    return get_guide_cumulative(cell_index, bin) - before;
}

// The guide's density w.r.t. solid angle of a unit direction in a guided cell: the bin's
// probability over its solid angle 4 pi / GUIDE_BIN_COUNT.
float get_guide_density(uint cell_index, vec3 direction) {
    return get_guide_bin_probability(cell_index, get_guide_bin_index(direction)) * (float(GUIDE_BIN_COUNT) / (4.0 * M_PI));
}

// The cell's cumulative probabilities of bins 4 texel .. 4 texel + 3 (one texel of its words).
vec4 get_guide_cumulative_texel(uint cell_index, uint texel) {
    return uintBitsToFloat(texelFetch(g_guide_texels, int(GUIDE_HEADER_TEXEL_COUNT + cell_index * GUIDE_CELL_TEXEL_COUNT + texel)));
}

// A unit direction distributed as get_guide_density() in a guided cell: the bin by binary
// search of the cumulative probabilities with random_numbers[0], which is then rescaled
// within the bin to place cos theta; random_numbers[1] places phi. `out_bin` is the bin
// chosen and `out_bin_probability` its probability: the sample's density is that bin's,
// whereas get_guide_bin_index() of the direction may put a sample within the arctangent's
// error of a bin edge in the neighbouring bin.
// The search runs over the cell's texels of four bins each (GUIDE_CELL_TEXEL_COUNT of
// them), then among the four bins of the texel found: seven fetches, where a search over
// single bins takes ten, with the same bin, the same probabilities and so the same bits.
vec3 sample_guide_direction(uint cell_index, vec2 random_numbers, out uint out_bin, out float out_bin_probability) {
    float u = random_numbers[0];
    // The first texel whose last cumulative probability exceeds u (or the last texel): every
    // texel before `texel` ends at or below u, and `before` is where the one before it ends.
    uint texel = 0u;
    float before = 0.0;
    for (uint step = GUIDE_CELL_TEXEL_COUNT / 2u; step != 0u; step /= 2u) {
        float end = get_guide_cumulative_texel(cell_index, texel + step - 1u).w;
        if (end <= u) {
            texel += step;
            before = end;
        }
    }
    vec4 cumulative = get_guide_cumulative_texel(cell_index, texel);
    // The first of its bins whose cumulative probability exceeds u (or its last): those at
    // or below u are a prefix, the probabilities being non-decreasing.
    uint within_texel = uint(cumulative.x <= u) + uint(cumulative.y <= u) + uint(cumulative.z <= u);
    if (within_texel != 0u)
        before = cumulative[within_texel - 1u];
    uint first = 4u * texel + within_texel;
    float probability = cumulative[within_texel] - before;
    float within = min((u - before) / probability, ONE_MINUS_EPSILON);
    float resolution = float(GUIDE_DIRECTION_RESOLUTION);
    float row = float(first / uint(GUIDE_DIRECTION_RESOLUTION));
    float column = float(first % uint(GUIDE_DIRECTION_RESOLUTION));
    float z = -1.0 + 2.0 * (row + within) / resolution;
    float phi = 2.0 * M_PI * (column + random_numbers[1]) / resolution;
    float radius = sqrt(max(0.0, 1.0 - z * z));
    out_bin = first;
    out_bin_probability = probability;
    return vec3(radius * cos(phi), radius * sin(phi), z);
}

// The density of the one-sample mixture of BSDF and guide sampling at a guided vertex.
float get_guided_mixture_density(float bsdf_density, float guide_density) {
    return GUIDE_BSDF_FRACTION * bsdf_density + (1.0 - GUIDE_BSDF_FRACTION) * guide_density;
}

#endif
