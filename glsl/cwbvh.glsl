// Ray traversal of the compressed wide BVH (Ylitie, Karras and Laine 2017, "Efficient
// incoherent ray traversal on GPUs through compressed wide BVHs", HPG), the closest hit and
// the any-hit query of shadow rays: nodes of 8 children whose boxes are quantised to a byte
// per plane against the node's grid (80 bytes per node instead of 112 per 4 children), leaves
// of 1 to 3 triangles, triangles packed 36 bytes apiece. Included by bvh.glsl, whose
// bvh_closest_hit() and bvh_any_hit() call these when BVH_LAYOUT is BVH_LAYOUT_COMPRESSED;
// it reads the same bindings (g_bvh_node_texels, g_traversal_triangle_texels) in the layout
// of src/bvh/compressed.rs. The triangle tests are those of bvh.glsl, so the hits are brute
// force's up to ties at equal t.
//
// The stack holds node groups rather than nodes: an interior node's children that the ray
// entered and that are still to visit, as bits 24-31 of a word whose bits 0-7 are the node's
// inner mask, beside the index of its first interior child. On the stack a group is one word,
// the node's index (bits 8-31) and the children still to visit (bits 0-7); a pop fetches the
// node's first interior child and inner mask again (cwbvh_node_group_of_entry()). Half the
// registers of a stack of whole groups: on a GPU the stack's top entries live in registers
// (the deeper ones in shared memory, CWBVH_PUSH), and they bound how many subgroups a SIMD
// keeps in flight. A node's entered leaves form a
// triangle group (bits 0-23: the triangles' offsets from the node's first triangle), tested
// before the next node. Children are visited in slot order xor the ray's octant: the builder
// sorted the slots so that the highest bit is the child nearest along the ray's direction.
// Rust twins: src/bvh/compressed_traversal.rs, same names and maths; change both together.
#ifndef VKPATH_CWBVH_GLSL
#define VKPATH_CWBVH_GLSL
// textureSize() of a texel buffer declared as a texture (utextureBuffer: the texel buffers
// carry no sampler, which SPIR-V validation asks of buffer images).
#extension GL_EXT_samplerless_texture_functions : require

// The four words that start at word `offset` (0 .. 3) of the eight words of texels a then b.
uvec4 shift_texels(uvec4 a, uvec4 b, uint offset) {
    uvec4 one = uvec4(a.yzw, b.x);
    uvec4 two = uvec4(a.zw, b.xy);
    uvec4 three = uvec4(a.w, b.xyz);
    return offset == 0u ? a : (offset == 1u ? one : (offset == 2u ? two : three));
}

// Triangle i of the compressed tree's traversal triangles: PACKED_TRIANGLE_WORD_COUNT words
// from word 9 i of g_traversal_triangle_texels (3 texel fetches), and zeros for the members
// that ray_triangle_intersection() does not read. As in get_traversal_triangle(), kernels
// with a user's own ray_triangle_intersection() get get_triangle(i).
triangle_t get_packed_traversal_triangle(uint index) {
#ifdef USER_DEFINES_RAY_TRIANGLE_INTERSECTION
    return get_triangle(index);
#else
    uint first_word = uint(PACKED_TRIANGLE_WORD_COUNT) * index;
    int texel = int(first_word >> 2u);
    uint offset = first_word & 3u;
    uvec4 a = texelFetch(g_traversal_triangle_texels, texel);
    uvec4 b = texelFetch(g_traversal_triangle_texels, texel + 1);
    uvec4 c = texelFetch(g_traversal_triangle_texels, texel + 2);
    // Words 0-3 start at `offset` in a, b; words 4-7 in b, c; word 8 is c[offset]
    vec4 low = uintBitsToFloat(shift_texels(a, b, offset));
    vec4 high = uintBitsToFloat(shift_texels(b, c, offset));
    float last = uintBitsToFloat(shift_texels(c, c, offset).x);
    triangle_t triangle;
    triangle.positions[0] = low.xyz;
    triangle.positions[1] = vec3(low.w, high.xy);
    triangle.positions[2] = vec3(high.zw, last);
    triangle.normal = vec3(0.0);
    triangle.color = vec3(0.0);
    triangle.emission = vec3(0.0);
    return triangle;
#endif
}

// 7 minus the ray's octant (bit 2: x, bit 1: y, bit 0: z, set for a negative component; -0
// counts as positive, as in bvh_inverse_direction()), as the builder's child order expects.
uint cwbvh_octant_inverse(vec3 ray_direction) {
    return (ray_direction.x < 0.0 ? 0u : 4u) | (ray_direction.y < 0.0 ? 0u : 2u) | (ray_direction.z < 0.0 ? 0u : 1u);
}

// Tests child `slot` (0-7) of a node: the slab test of bvh_ray_box_intersection() on its
// dequantised box, in the node's grid (plane q at t = q * (scale / d) + (origin - o) / d), exit
// padded by BVH_SLAB_PADDING. One child at a time, so that only its six planes' values are
// live beside the node's texels (RDNA3: 144 -> 120 VGPRs for workshop and cosine against two
// vectors of four children, scripts/kernel-statistics.sh; the same arithmetic per child).
// \param planes_x, planes_y, planes_z Per axis the lower planes of slots 0-3, of 4-7, the
//        upper planes of slots 0-3, of 4-7, a byte per child (slot k: bits 8 (k & 3) ..)
// \param meta_words The children's meta bytes, slots 0-3 then 4-7, likewise
// \param scaled_inverse The grid's cell size times bvh_inverse_direction(ray_direction)
// \param shifted_origin (The grid's origin - ray_origin) * bvh_inverse_direction(ray_direction)
// \param octant_inverse cwbvh_octant_inverse(ray_direction)
// \param t_max Entries past this do not count
// \return Its hit bits if entered (else 0): bit 24 + (slot ^ octant_inverse) for an interior
//         child, the offsets of a leaf's triangles from the node's first triangle
uint cwbvh_intersect_child(uint slot, uvec4 planes_x, uvec4 planes_y, uvec4 planes_z, uvec2 meta_words, vec3 scaled_inverse, vec3 shifted_origin, uint octant_inverse, float t_max) {
    uint half_index = slot >> 2u;
    uint shift = 8u * (slot & 3u);
    float t_lower_x = float((planes_x[half_index] >> shift) & 255u) * scaled_inverse.x + shifted_origin.x;
    float t_upper_x = float((planes_x[2u + half_index] >> shift) & 255u) * scaled_inverse.x + shifted_origin.x;
    float t_lower_y = float((planes_y[half_index] >> shift) & 255u) * scaled_inverse.y + shifted_origin.y;
    float t_upper_y = float((planes_y[2u + half_index] >> shift) & 255u) * scaled_inverse.y + shifted_origin.y;
    float t_lower_z = float((planes_z[half_index] >> shift) & 255u) * scaled_inverse.z + shifted_origin.z;
    float t_upper_z = float((planes_z[2u + half_index] >> shift) & 255u) * scaled_inverse.z + shifted_origin.z;
    float t_entry = max(max(min(t_lower_x, t_upper_x), min(t_lower_y, t_upper_y)), max(min(t_lower_z, t_upper_z), 0.0));
    float t_exit = min(min(max(t_lower_x, t_upper_x), max(t_lower_y, t_upper_y)), max(t_lower_z, t_upper_z)) * BVH_SLAB_PADDING;
    uint meta = (meta_words[half_index] >> shift) & 255u;
    // Interior children's meta is 24 + slot (bits 3 and 4 both set, never in a leaf's): one
    // bit at 24 + (slot ^ octant_inverse). A leaf's: its triangles in unary (bits 5-7)
    // shifted to its first triangle's offset (bits 0-4). An empty slot's is 0: no bits.
    bool inner = (meta & (meta << 1u) & 16u) != 0u;
    uint child_bits = inner ? 1u : (meta >> 5u);
    uint bit_index = inner ? ((meta & 31u) ^ octant_inverse) : (meta & 31u);
    return t_entry <= min(t_exit, t_max) ? (child_bits << bit_index) : 0u;
}

// Tests the children of node i (cwbvh_intersect_child() for slots 0-7).
// \param out_node_group x: the node's first interior child, y: bit 24 + (slot ^
//        octant_inverse) for each interior child entered | the node's inner mask
// \param out_triangle_group x: the node's first triangle, y: the offsets of the triangles of
//        the leaves entered
// \param inverse_direction bvh_inverse_direction(ray_direction)
// \param octant_inverse cwbvh_octant_inverse(ray_direction)
// \param t_max Entries past this do not count
void cwbvh_intersect_node(out uvec2 out_node_group, out uvec2 out_triangle_group, uint node_index, vec3 ray_origin, vec3 inverse_direction, uint octant_inverse, float t_max) {
    int first = CWBVH_NODE_TEXEL_COUNT * int(node_index);
    // x, y, z: the grid's origin; w: the cell sizes' biased exponents (bytes 0-2), inner mask
    uvec4 header = texelFetch(g_bvh_node_texels, first);
    // x: first interior child, y: first triangle, z, w: the children's meta bytes (slots 0-7)
    uvec4 indices = texelFetch(g_bvh_node_texels, first + 1);
    // Per axis: lower planes of slots 0-3, of 4-7, upper planes of slots 0-3, of 4-7
    uvec4 planes_x = texelFetch(g_bvh_node_texels, first + 2);
    uvec4 planes_y = texelFetch(g_bvh_node_texels, first + 3);
    uvec4 planes_z = texelFetch(g_bvh_node_texels, first + 4);
    vec3 scale = uintBitsToFloat(((uvec3(header.w) >> uvec3(0u, 8u, 16u)) & 255u) << 23u);
    vec3 scaled_inverse = scale * inverse_direction;
    vec3 shifted_origin = (uintBitsToFloat(header.xyz) - ray_origin) * inverse_direction;
    // The slots one after another, written out rather than looped over: a loop here would
    // add nine trips per node visit to llvmpipe's loop limiter (src/kernels/loops.rs), and
    // one child's plane values are dead before the next child's are loaded.
    uint hits = cwbvh_intersect_child(0u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    hits |= cwbvh_intersect_child(1u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    hits |= cwbvh_intersect_child(2u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    hits |= cwbvh_intersect_child(3u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    hits |= cwbvh_intersect_child(4u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    hits |= cwbvh_intersect_child(5u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    hits |= cwbvh_intersect_child(6u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    hits |= cwbvh_intersect_child(7u, planes_x, planes_y, planes_z, indices.zw, scaled_inverse, shifted_origin, octant_inverse, t_max);
    out_node_group = uvec2(indices.x, (hits & 0xFF000000u) | (header.w >> 24u));
    out_triangle_group = uvec2(indices.y, hits & 0x00FFFFFFu);
}

// A node group as the stack holds it: the index of the node whose group it is (bits 8-31;
// src/bvh/compressed.rs refuses trees of CWBVH_MAX_NODE_COUNT nodes or more) and the
// children still to visit (bits 0-7: bits 24-31 of node_group.y).
uint cwbvh_stack_entry(uint group_node_index, uvec2 node_group) {
    return (group_node_index << 8u) | (node_group.y >> 24u);
}

// The node group of a stack entry (cwbvh_stack_entry()): its node's first interior child and
// inner mask fetched again, beside the children still to visit.
uvec2 cwbvh_node_group_of_entry(uint entry) {
    int first = CWBVH_NODE_TEXEL_COUNT * int(entry >> 8u);
    uint inner_mask = texelFetch(g_bvh_node_texels, first).w >> 24u;
    uint first_interior_child = texelFetch(g_bvh_node_texels, first + 1).x;
    return uvec2(first_interior_child, (entry << 24u) | inner_mask);
}

// Most steps of one traversal: every node visited once, every triangle tested once, and a
// pop for at most every node visit.
uint cwbvh_step_bound() {
    uint node_count = uint(textureSize(g_bvh_node_texels)) / uint(CWBVH_NODE_TEXEL_COUNT);
    uint triangle_count = 4u * uint(textureSize(g_traversal_triangle_texels)) / uint(PACKED_TRIANGLE_WORD_COUNT);
    return 2u * node_count + triangle_count + 1u;
}

// The stack's first CWBVH_REGISTER_STACK_SIZE entries are an array of the traversal's (in
// registers on a GPU); the rest, to CWBVH_STACK_SIZE, are g_cwbvh_stack_overflow, this
// invocation's column of workgroup-shared memory. Registers bound how many subgroups a GPU
// keeps in flight, shared memory too (RDNA3, scripts/kernel-statistics.sh: 8 entries in
// registers and 24 shared, 6 KB per workgroup of 64, keep 12 subgroups per SIMD for every
// integrator, where 32 in registers kept 8 to 10; docs/performance.md). Shallow traversals
// never touch the shared part. A kernel may define CWBVH_REGISTER_STACK_SIZE before it
// includes this file (probe_bvh.comp takes 2, so that its tests reach the shared part).
#ifndef CWBVH_REGISTER_STACK_SIZE
#define CWBVH_REGISTER_STACK_SIZE 8
#endif
#define CWBVH_WORKGROUP_INVOCATIONS (gl_WorkGroupSize.x * gl_WorkGroupSize.y * gl_WorkGroupSize.z)
shared uint g_cwbvh_stack_overflow[(CWBVH_STACK_SIZE - CWBVH_REGISTER_STACK_SIZE) * CWBVH_WORKGROUP_INVOCATIONS];

// Where stack entry `entry_index` (CWBVH_REGISTER_STACK_SIZE or more) lies in
// g_cwbvh_stack_overflow: entries in rows, invocations in columns.
uint cwbvh_overflow_index(uint entry_index) {
    return (entry_index - uint(CWBVH_REGISTER_STACK_SIZE)) * CWBVH_WORKGROUP_INVOCATIONS + gl_LocalInvocationIndex;
}

// Pushes `entry` (stack_size < CWBVH_STACK_SIZE) onto the stack of registers and shared memory.
#define CWBVH_PUSH(stack, stack_size, entry) { \
    if (stack_size < uint(CWBVH_REGISTER_STACK_SIZE)) \
        stack[stack_size] = entry; \
    else \
        g_cwbvh_stack_overflow[cwbvh_overflow_index(stack_size)] = entry; \
    ++stack_size; \
}

// Pops the top entry (stack_size > 0) into out_entry.
#define CWBVH_POP(stack, stack_size, out_entry) { \
    --stack_size; \
    if (stack_size < uint(CWBVH_REGISTER_STACK_SIZE)) \
        out_entry = stack[stack_size]; \
    else \
        out_entry = g_cwbvh_stack_overflow[cwbvh_overflow_index(stack_size)]; \
}

// The next node of a node group (node group_node_index's) whose bits 24-31 are not all 0:
// clears its bit, pushes what is left of the group (the stack cannot overflow: it holds one
// group per interior level below the root, and src/bvh/compressed.rs refuses trees deeper
// than CWBVH_STACK_SIZE; the test only keeps a malformed tree from writing out of bounds),
// and returns its node index.
#define CWBVH_NEXT_NODE(node_group, group_node_index, octant_inverse, stack, stack_size, out_node_index) { \
    uint hits_inner = node_group.y; \
    uint bit = uint(findMSB(hits_inner)); \
    node_group.y &= ~(1u << bit); \
    if ((node_group.y & 0xFF000000u) != 0u && stack_size < uint(CWBVH_STACK_SIZE)) { \
        CWBVH_PUSH(stack, stack_size, cwbvh_stack_entry(group_node_index, node_group)) \
    } \
    uint slot = (bit - 24u) ^ octant_inverse; \
    out_node_index = node_group.x + uint(bitCount(hits_inner & ((1u << slot) - 1u))); \
}

// Finds the closest triangle that a ray hits, traversing the compressed BVH: brute force's
// triangle tests, children in octant order, nodes culled by the closest hit so far. Each step
// (a triangle test, a node visit or a pop) counts 1 in g_path.traversal_iterations.
// \param out_t Ray parameter of the closest hit (NO_HIT_T if none)
// \param out_triangle_index Index of the hit triangle in g_triangles (0 if none)
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \return true iff a triangle was hit at 0 <= t < NO_HIT_T
bool cwbvh_closest_hit(out float out_t, out uint out_triangle_index, vec3 ray_origin, vec3 ray_direction) {
    out_t = NO_HIT_T;
    out_triangle_index = 0u;
    bool hit = false;
    if (textureSize(g_bvh_node_texels) < CWBVH_NODE_TEXEL_COUNT)
        return false;
    vec3 inverse_direction = bvh_inverse_direction(ray_direction);
    uint octant_inverse = cwbvh_octant_inverse(ray_direction);
    // The root: node 0 as the only, interior, child of a group at base 0
    uvec2 node_group = uvec2(0u, 0x80000000u);
    // The node whose group node_group is (the root's group has none: it is never pushed)
    uint group_node_index = 0u;
    uvec2 triangle_group = uvec2(0u);
    uint stack[CWBVH_REGISTER_STACK_SIZE];
    uint stack_size = 0u;
    uint step_bound = cwbvh_step_bound();
    for (uint step = 0u; step != step_bound; ++step) {
        // The triangles of the leaves just entered, lowest offset first as brute force's
        // loop goes, all before the next node: in a loop of their own rather than one per
        // step, so that on a SIMD CPU (lavapipe) lanes testing triangles and lanes visiting
        // nodes do not make every step cost both (the same tests in the same order)
        while (triangle_group.y != 0u) {
            ++g_path.traversal_iterations;
            uint local = uint(findLSB(triangle_group.y));
            triangle_group.y &= ~(1u << local);
            uint i = triangle_group.x + local;
            float t;
            if (ray_triangle_intersection(t, ray_origin, ray_direction, get_packed_traversal_triangle(i)) && t < out_t AND_HIT_IS_OPAQUE(i, ray_origin, ray_direction, t)) {
                out_t = t;
                out_triangle_index = i;
                hit = true;
            }
        }
        // A node group with nodes left, popped where the one in hand has none (the stack
        // holds only such groups): in the same step as the node's visit, so that a step
        // is a visit (on lavapipe, a step whose lanes pop costs a visit all the same)
        if ((node_group.y & 0xFF000000u) == 0u) {
            if (stack_size == 0u)
                break;
            ++g_path.traversal_iterations;
            uint entry;
            CWBVH_POP(stack, stack_size, entry)
            group_node_index = entry >> 8u;
            node_group = cwbvh_node_group_of_entry(entry);
        }
        ++g_path.traversal_iterations;
        uint node_index;
        CWBVH_NEXT_NODE(node_group, group_node_index, octant_inverse, stack, stack_size, node_index)
        group_node_index = node_index;
        cwbvh_intersect_node(node_group, triangle_group, node_index, ray_origin, inverse_direction, octant_inverse, out_t);
    }
    return hit;
}

// Whether a ray hits any triangle at t < t_max (shadow rays): the traversal of
// cwbvh_closest_hit() with a fixed t_max, ending at the first hit found.
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \param t_max Hits at or beyond this ray parameter do not count
// \return true iff some triangle is hit at 0 <= t < t_max
bool cwbvh_any_hit(vec3 ray_origin, vec3 ray_direction, float t_max) {
    if (textureSize(g_bvh_node_texels) < CWBVH_NODE_TEXEL_COUNT)
        return false;
    vec3 inverse_direction = bvh_inverse_direction(ray_direction);
    uint octant_inverse = cwbvh_octant_inverse(ray_direction);
    uvec2 node_group = uvec2(0u, 0x80000000u);
    // The node whose group node_group is (the root's group has none: it is never pushed)
    uint group_node_index = 0u;
    uvec2 triangle_group = uvec2(0u);
    uint stack[CWBVH_REGISTER_STACK_SIZE];
    uint stack_size = 0u;
    uint step_bound = cwbvh_step_bound();
    for (uint step = 0u; step != step_bound; ++step) {
        while (triangle_group.y != 0u) {
            ++g_path.traversal_iterations;
            uint local = uint(findLSB(triangle_group.y));
            triangle_group.y &= ~(1u << local);
            uint i = triangle_group.x + local;
            float t;
            if (ray_triangle_intersection(t, ray_origin, ray_direction, get_packed_traversal_triangle(i)) && t < t_max AND_HIT_IS_OPAQUE(i, ray_origin, ray_direction, t))
                return true;
        }
        // A node group with nodes left, popped where the one in hand has none (the stack
        // holds only such groups): in the same step as the node's visit, so that a step
        // is a visit (on lavapipe, a step whose lanes pop costs a visit all the same)
        if ((node_group.y & 0xFF000000u) == 0u) {
            if (stack_size == 0u)
                break;
            ++g_path.traversal_iterations;
            uint entry;
            CWBVH_POP(stack, stack_size, entry)
            group_node_index = entry >> 8u;
            node_group = cwbvh_node_group_of_entry(entry);
        }
        ++g_path.traversal_iterations;
        uint node_index;
        CWBVH_NEXT_NODE(node_group, group_node_index, octant_inverse, stack, stack_size, node_index)
        group_node_index = node_index;
        cwbvh_intersect_node(node_group, triangle_group, node_index, ray_origin, inverse_direction, octant_inverse, t_max);
    }
    return false;
}

#endif
