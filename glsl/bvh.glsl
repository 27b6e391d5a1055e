// Ray traversal of a bounding volume hierarchy over g_triangles (scene.glsl): the closest hit
// and the any-hit query of shadow rays, testing O(log n) triangles instead of all of them.
// The triangle tests read the positions from their own compact buffer
// (g_traversal_triangle_texels); the rest of a triangle is read for the closest hit only.
// The triangle tests are the workshop's ray_triangle_intersection(), so the hits are those of
// the brute-force ray_mesh_intersection() (up to ties at equal t). The nodes are built on the
// CPU (src/bvh/): a binary tree by the SAH, which also reorders g_triangles so that each leaf
// holds a contiguous range, collapsed into a 4-wide tree (src/bvh/wide.rs) whose nodes hold
// the boxes of up to four children, tested together.
// Rust twins: src/bvh/traversal.rs, same names and maths; change both together.
#ifndef VKPATH_BVH_GLSL
#define VKPATH_BVH_GLSL
// textureSize() of a texel buffer declared as a texture (utextureBuffer: the texel buffers
// carry no sampler, which SPIR-V validation asks of buffer images).
#extension GL_EXT_samplerless_texture_functions : require

#include "shared.h"
#include "scene.glsl"

// The nodes of the 4-wide BVH as a texel buffer of RGBA32_UINT, WIDE_BVH_NODE_TEXEL_COUNT
// texels per node (glsl/shared.h: the four children's boxes as lower x, upper x, lower y,
// upper y, lower z, upper z, then their references). Mirrors `vkpath::bvh::GpuWideBvhNode`,
// whose layout test checks it; the root is node 0. On lavapipe a texel fetch is a vector
// gather, where a storage-buffer load is a per-lane loop.
layout(set = 0, binding = BINDING_BVH_NODES) uniform utextureBuffer g_bvh_node_texels;

// The triangles' vertex positions alone, in the leaf order of g_triangle_texels: a texel
// buffer of RGBA32_UINT, TRAVERSAL_TRIANGLE_TEXEL_COUNT texels per triangle (v_0, v_1, v_2 in
// xyz, w unused). Mirrors `vkpath::bvh::GpuTraversalTriangle`. The traversal's triangle
// tests read only these 48 bytes per triangle, so a leaf's triangles lie in contiguous
// 48-byte records instead of 96-byte ones whose second half (normal, albedo, emission) only
// the closest hit needs.
layout(set = 0, binding = BINDING_TRAVERSAL_TRIANGLES) uniform utextureBuffer g_traversal_triangle_texels;

// Triangle i as the traversal's triangle test sees it: its vertex positions, and zeros for
// the members that ray_triangle_intersection() does not read (get_triangle(i) reads all of
// them). A user's own ray_triangle_intersection() may read any member, so kernels built with
// one get get_triangle(i) instead.
triangle_t get_traversal_triangle(uint index) {
#ifdef USER_DEFINES_RAY_TRIANGLE_INTERSECTION
    return get_triangle(index);
#else
    // Motion blur: the compact positions are the still scene's; the keys' are interpolated
    // at the ray's time (as the nodes' boxes are, bvh_enter_moving_children())
    if (MOTION_STEPS != 0u)
        return get_triangle(index);
    int first = int(uint(TRAVERSAL_TRIANGLE_TEXEL_COUNT) * index);
    triangle_t triangle;
    triangle.positions[0] = uintBitsToFloat(texelFetch(g_traversal_triangle_texels, first).xyz);
    triangle.positions[1] = uintBitsToFloat(texelFetch(g_traversal_triangle_texels, first + 1).xyz);
    triangle.positions[2] = uintBitsToFloat(texelFetch(g_traversal_triangle_texels, first + 2).xyz);
    triangle.normal = vec3(0.0);
    triangle.color = vec3(0.0);
    triangle.emission = vec3(0.0);
    return triangle;
#endif
}

// Which tree the bindings hold (the host specializes it with the traversal): BVH_LAYOUT_WIDE,
// the 4-wide tree of this file, or BVH_LAYOUT_COMPRESSED, the compressed wide BVH of
// cwbvh.glsl, which bvh_closest_hit() and bvh_any_hit() then hand the ray to.
layout(constant_id = SPEC_BVH_LAYOUT) const int BVH_LAYOUT = BVH_LAYOUT_WIDE;

// Motion blur's tree (MOTION_STEPS != 0): texels of one node, MOTION_BVH_KEY_TEXEL_COUNT per
// key (the six box texels of the still node's layout), then the child references
// (glsl/shared.h; src/bvh/motion.rs writes them).
int get_motion_bvh_node_texel_count() {
    return MOTION_BVH_KEY_TEXEL_COUNT * int(MOTION_STEPS) + 1;
}

// Number of nodes in the BVH.
uint get_bvh_node_count() {
    if (MOTION_STEPS != 0u)
        return uint(textureSize(g_bvh_node_texels)) / uint(get_motion_bvh_node_texel_count());
    return uint(textureSize(g_bvh_node_texels)) / uint(WIDE_BVH_NODE_TEXEL_COUNT);
}

// The box of child `slot` (0 .. WIDE_BVH_WIDTH - 1) of node i, world space.
void get_bvh_child_box(uint node_index, int slot, out vec3 out_lower, out vec3 out_upper) {
    int first = WIDE_BVH_NODE_TEXEL_COUNT * int(node_index);
    out_lower = uintBitsToFloat(uvec3(texelFetch(g_bvh_node_texels, first)[slot], texelFetch(g_bvh_node_texels, first + 2)[slot], texelFetch(g_bvh_node_texels, first + 4)[slot]));
    out_upper = uintBitsToFloat(uvec3(texelFetch(g_bvh_node_texels, first + 1)[slot], texelFetch(g_bvh_node_texels, first + 3)[slot], texelFetch(g_bvh_node_texels, first + 5)[slot]));
}

// BVH_SLAB_PADDING, BVH_MIN_DIRECTION and NO_HIT_T, shared with the Rust twins, are in
// glsl/shared.h.

// The per-component inverse of a ray direction for slab tests.
// \param ray_direction The ray direction, world space (need not be normalized)
// \return sign(d_i) / max(|d_i|, BVH_MIN_DIRECTION) per component, +0 counting as positive
vec3 bvh_inverse_direction(vec3 ray_direction) {
    vec3 magnitude = max(abs(ray_direction), vec3(BVH_MIN_DIRECTION));
    vec3 direction_sign = mix(vec3(-1.0), vec3(1.0), greaterThanEqual(ray_direction, vec3(0.0)));
    return direction_sign / magnitude;
}

// The slab test (Kay and Kajiya 1986): whether a ray enters an axis-aligned box before t_max.
// \param out_t_entry Where the ray enters the box (0 if the origin is inside), in units of |ray_direction|
// \param ray_origin The ray origin, world space
// \param inverse_direction bvh_inverse_direction(ray_direction)
// \param box_lower, box_upper The box's corners, world space
// \param t_max Entries past this do not count
// \return true iff the ray's segment [0, t_max] meets the (slightly padded) box
bool bvh_ray_box_intersection(out float out_t_entry, vec3 ray_origin, vec3 inverse_direction, vec3 box_lower, vec3 box_upper, float t_max) {
    vec3 t_lower = (box_lower - ray_origin) * inverse_direction;
    vec3 t_upper = (box_upper - ray_origin) * inverse_direction;
    vec3 t_near = min(t_lower, t_upper);
    vec3 t_far = max(t_lower, t_upper);
    float t_entry = max(max(t_near.x, t_near.y), max(t_near.z, 0.0));
    float t_exit = min(min(t_far.x, t_far.y), t_far.z) * BVH_SLAB_PADDING;
    out_t_entry = t_entry;
    return t_entry <= min(t_exit, t_max);
}

// A child reference's triangle count: at least 1 for a leaf, 0 for an interior node.
uint get_bvh_leaf_triangle_count(uint child) {
    return child >> WIDE_BVH_LEAF_COUNT_SHIFT;
}

// A child reference's node index (interior) or first triangle (leaf).
uint get_bvh_child_index(uint child) {
    return child & uint(WIDE_BVH_INDEX_MASK);
}

// Visits a child reference: its first triangle (a leaf) or its node (an interior node) and its
// triangle count (0 for interior nodes); counts the visit and the leaf loop's iterations (an
// upper bound when that loop stops early) in g_path.traversal_iterations.
void visit_bvh_child(uint child, out uint out_first_index, out uint out_triangle_count) {
    out_first_index = get_bvh_child_index(child);
    out_triangle_count = get_bvh_leaf_triangle_count(child);
    g_path.traversal_iterations += 1u + out_triangle_count;
}

// Puts two (entry, child) pairs in order of entry: a compare-exchange of a sorting network,
// which swaps only when the second enters strictly earlier.
void order_bvh_children(inout float entry_a, inout uint child_a, inout float entry_b, inout uint child_b) {
    bool swap = entry_b < entry_a;
    float entry = entry_a;
    uint child = child_a;
    entry_a = swap ? entry_b : entry_a;
    child_a = swap ? child_b : child_a;
    entry_b = swap ? entry : entry_b;
    child_b = swap ? child : child_b;
}

// The children of a node whose boxes the ray enters before t_max, nearest first: how many
// (0 .. WIDE_BVH_WIDTH); out_children holds them in its first components, with the
// parameters where the ray enters them in out_entries (the slab test of
// bvh_ray_box_intersection() for four boxes at once, component by component).
// \param lower_x, upper_x, lower_y, upper_y, lower_z, upper_z The four children's boxes, world space
// \param children Their references (WIDE_BVH_EMPTY_CHILD: an unused slot)
uint bvh_enter_boxes(vec4 lower_x, vec4 upper_x, vec4 lower_y, vec4 upper_y, vec4 lower_z, vec4 upper_z, uvec4 children, vec3 ray_origin, vec3 inverse_direction, float t_max, out uvec4 out_children, out vec4 out_entries) {
    vec4 t_lower_x = (lower_x - ray_origin.x) * inverse_direction.x;
    vec4 t_upper_x = (upper_x - ray_origin.x) * inverse_direction.x;
    vec4 t_lower_y = (lower_y - ray_origin.y) * inverse_direction.y;
    vec4 t_upper_y = (upper_y - ray_origin.y) * inverse_direction.y;
    vec4 t_lower_z = (lower_z - ray_origin.z) * inverse_direction.z;
    vec4 t_upper_z = (upper_z - ray_origin.z) * inverse_direction.z;
    vec4 t_entry = max(max(min(t_lower_x, t_upper_x), min(t_lower_y, t_upper_y)), max(min(t_lower_z, t_upper_z), vec4(0.0)));
    vec4 t_exit = min(min(max(t_lower_x, t_upper_x), max(t_lower_y, t_upper_y)), max(t_lower_z, t_upper_z)) * BVH_SLAB_PADDING;
    bvec4 entered = bvec4(uvec4(lessThanEqual(t_entry, min(t_exit, vec4(t_max)))) & uvec4(notEqual(children, uvec4(WIDE_BVH_EMPTY_CHILD))));
    // Boxes not entered sort last
    out_entries = mix(vec4(NO_HIT_T), t_entry, entered);
    out_children = children;
    order_bvh_children(out_entries.x, out_children.x, out_entries.y, out_children.y);
    order_bvh_children(out_entries.z, out_children.z, out_entries.w, out_children.w);
    order_bvh_children(out_entries.x, out_children.x, out_entries.z, out_children.z);
    order_bvh_children(out_entries.y, out_children.y, out_entries.w, out_children.w);
    order_bvh_children(out_entries.y, out_children.y, out_entries.z, out_children.z);
    uvec4 counted = uvec4(entered);
    return counted.x + counted.y + counted.z + counted.w;
}

// Motion blur: bvh_enter_boxes() of interior node i's children's boxes at g_motion_time, each
// lerped between its boxes at the two keys around the time. The lerped box holds the
// children's triangles at that time: a box at key k holds its triangles' vertices at key k,
// the kernel places a vertex at the same lerp of its two keys' positions
// (get_moving_packed_triangle()), and a lerp with one weight keeps the order of corners and
// points; a node's box at a key is the union of its children's at that key (src/bvh/motion.rs).
uint bvh_enter_moving_children(uint node_index, vec3 ray_origin, vec3 inverse_direction, float t_max, out uvec4 out_children, out vec4 out_entries) {
    uint key;
    float fraction = get_motion_segment(g_motion_time, key);
    int first = get_motion_bvh_node_texel_count() * int(node_index);
    int before = first + MOTION_BVH_KEY_TEXEL_COUNT * int(key);
    int after = before + MOTION_BVH_KEY_TEXEL_COUNT;
    vec4 lower_x = mix(uintBitsToFloat(texelFetch(g_bvh_node_texels, before)), uintBitsToFloat(texelFetch(g_bvh_node_texels, after)), fraction);
    vec4 upper_x = mix(uintBitsToFloat(texelFetch(g_bvh_node_texels, before + 1)), uintBitsToFloat(texelFetch(g_bvh_node_texels, after + 1)), fraction);
    vec4 lower_y = mix(uintBitsToFloat(texelFetch(g_bvh_node_texels, before + 2)), uintBitsToFloat(texelFetch(g_bvh_node_texels, after + 2)), fraction);
    vec4 upper_y = mix(uintBitsToFloat(texelFetch(g_bvh_node_texels, before + 3)), uintBitsToFloat(texelFetch(g_bvh_node_texels, after + 3)), fraction);
    vec4 lower_z = mix(uintBitsToFloat(texelFetch(g_bvh_node_texels, before + 4)), uintBitsToFloat(texelFetch(g_bvh_node_texels, after + 4)), fraction);
    vec4 upper_z = mix(uintBitsToFloat(texelFetch(g_bvh_node_texels, before + 5)), uintBitsToFloat(texelFetch(g_bvh_node_texels, after + 5)), fraction);
    uvec4 children = texelFetch(g_bvh_node_texels, first + MOTION_BVH_KEY_TEXEL_COUNT * int(MOTION_STEPS));
    return bvh_enter_boxes(lower_x, upper_x, lower_y, upper_y, lower_z, upper_z, children, ray_origin, inverse_direction, t_max, out_children, out_entries);
}

// The children of interior node i whose boxes the ray enters before t_max, nearest first
// (bvh_enter_boxes()); with motion blur, their boxes at the ray's time
// (bvh_enter_moving_children()).
uint bvh_enter_children(uint node_index, vec3 ray_origin, vec3 inverse_direction, float t_max, out uvec4 out_children, out vec4 out_entries) {
    if (MOTION_STEPS != 0u)
        return bvh_enter_moving_children(node_index, ray_origin, inverse_direction, t_max, out_children, out_entries);
    int first = WIDE_BVH_NODE_TEXEL_COUNT * int(node_index);
    vec4 lower_x = uintBitsToFloat(texelFetch(g_bvh_node_texels, first));
    vec4 upper_x = uintBitsToFloat(texelFetch(g_bvh_node_texels, first + 1));
    vec4 lower_y = uintBitsToFloat(texelFetch(g_bvh_node_texels, first + 2));
    vec4 upper_y = uintBitsToFloat(texelFetch(g_bvh_node_texels, first + 3));
    vec4 lower_z = uintBitsToFloat(texelFetch(g_bvh_node_texels, first + 4));
    vec4 upper_z = uintBitsToFloat(texelFetch(g_bvh_node_texels, first + 5));
    uvec4 children = texelFetch(g_bvh_node_texels, first + 6);
    return bvh_enter_boxes(lower_x, upper_x, lower_y, upper_y, lower_z, upper_z, children, ray_origin, inverse_direction, t_max, out_children, out_entries);
}

// Pushes the entered children but the nearest (components 1 .. count - 1 of
// bvh_enter_children()'s), farthest first, so that they pop nearest first. The stack never
// overflows (src/bvh/wide.rs bounds every path's pushes by WIDE_BVH_STACK_SIZE); the test
// only keeps a malformed tree from writing out of bounds.
#define PUSH_BVH_CHILD(child, entry, stack_nodes, stack_entries, stack_size) \
    if (stack_size < WIDE_BVH_STACK_SIZE) { \
        stack_nodes[stack_size] = child; \
        stack_entries[stack_size] = entry; \
        ++stack_size; \
    }
#define PUSH_BVH_CHILDREN(count, children, entries, stack_nodes, stack_entries, stack_size) \
    if (count > 3u) { PUSH_BVH_CHILD(children.w, entries.w, stack_nodes, stack_entries, stack_size) } \
    if (count > 2u) { PUSH_BVH_CHILD(children.z, entries.z, stack_nodes, stack_entries, stack_size) } \
    if (count > 1u) { PUSH_BVH_CHILD(children.y, entries.y, stack_nodes, stack_entries, stack_size) }

#include "cwbvh.glsl"

// Finds the closest triangle that a ray hits, traversing the BVH: the brute-force
// ray_mesh_intersection() with the same triangle tests, nearest child first, and subtrees
// skipped once they start beyond the closest hit so far.
// \param out_t Ray parameter of the closest hit (NO_HIT_T if none)
// \param out_triangle_index Index of the hit triangle in g_triangles (0 if none)
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \return true iff a triangle was hit at 0 <= t < NO_HIT_T
bool bvh_closest_hit(out float out_t, out uint out_triangle_index, vec3 ray_origin, vec3 ray_direction) {
    if (BVH_LAYOUT == BVH_LAYOUT_COMPRESSED)
        return cwbvh_closest_hit(out_t, out_triangle_index, ray_origin, ray_direction);
    out_t = NO_HIT_T;
    out_triangle_index = 0u;
    bool hit = false;
    vec3 inverse_direction = bvh_inverse_direction(ray_direction);
    uint node_count = get_bvh_node_count();
    if (node_count == 0u)
        return false;
    // Children still to visit, with the parameter where the ray enters them
    uint stack_nodes[WIDE_BVH_STACK_SIZE];
    float stack_entries[WIDE_BVH_STACK_SIZE];
    uint stack_size = 0u;
    // The root, an interior node (a leaf root is the only child of a root node)
    uint child = 0u;
    // Each iteration visits one child reference and none is visited twice: at most the
    // root and every child of every node
    for (uint iteration = 0u; iteration != WIDE_BVH_WIDTH * node_count + 1u; ++iteration) {
        uint first_index, triangle_count;
        visit_bvh_child(child, first_index, triangle_count);
        bool descend = false;
        if (triangle_count != 0u) {
            // A leaf: the brute-force loop over its triangles
            uint end = first_index + triangle_count;
            for (uint i = first_index; i < end; ++i) {
                float t;
                if (ray_triangle_intersection(t, ray_origin, ray_direction, get_traversal_triangle(i)) && t < out_t AND_HIT_IS_OPAQUE(i, ray_origin, ray_direction, t)) {
                    out_t = t;
                    out_triangle_index = i;
                    hit = true;
                }
            }
        } else {
            // An interior node: test its children, go to the nearest, push the others
            uvec4 children;
            vec4 entries;
            uint entered = bvh_enter_children(first_index, ray_origin, inverse_direction, out_t, children, entries);
            PUSH_BVH_CHILDREN(entered, children, entries, stack_nodes, stack_entries, stack_size)
            child = children.x;
            descend = entered != 0u;
        }
        // Pop the next child that the ray enters before the closest hit so far (the stack
        // shrinks in every iteration, so this loop is bounded by WIDE_BVH_STACK_SIZE)
        while (!descend && stack_size != 0u) {
            ++g_path.traversal_iterations;
            --stack_size;
            if (stack_entries[stack_size] <= out_t) {
                child = stack_nodes[stack_size];
                descend = true;
            }
        }
        if (!descend)
            break;
    }
    return hit;
}

// Whether a ray hits any triangle at t < t_max (shadow rays): the traversal of
// bvh_closest_hit() with a fixed t_max, ending at the first hit found.
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \param t_max Hits at or beyond this ray parameter do not count
// \return true iff some triangle is hit at 0 <= t < t_max
bool bvh_any_hit(vec3 ray_origin, vec3 ray_direction, float t_max) {
    if (BVH_LAYOUT == BVH_LAYOUT_COMPRESSED)
        return cwbvh_any_hit(ray_origin, ray_direction, t_max);
    vec3 inverse_direction = bvh_inverse_direction(ray_direction);
    uint node_count = get_bvh_node_count();
    if (node_count == 0u)
        return false;
    // Entry parameters need no test when popped: t_max never shrinks. They are kept for
    // PUSH_BVH_CHILDREN's sake.
    uint stack_nodes[WIDE_BVH_STACK_SIZE];
    float stack_entries[WIDE_BVH_STACK_SIZE];
    uint stack_size = 0u;
    uint child = 0u;
    for (uint iteration = 0u; iteration != WIDE_BVH_WIDTH * node_count + 1u; ++iteration) {
        uint first_index, triangle_count;
        visit_bvh_child(child, first_index, triangle_count);
        if (triangle_count != 0u) {
            uint end = first_index + triangle_count;
            for (uint i = first_index; i < end; ++i) {
                float t;
                if (ray_triangle_intersection(t, ray_origin, ray_direction, get_traversal_triangle(i)) && t < t_max AND_HIT_IS_OPAQUE(i, ray_origin, ray_direction, t))
                    return true;
            }
        } else {
            // Nearest first: an occluder near the origin ends the search sooner
            uvec4 children;
            vec4 entries;
            uint entered = bvh_enter_children(first_index, ray_origin, inverse_direction, t_max, children, entries);
            PUSH_BVH_CHILDREN(entered, children, entries, stack_nodes, stack_entries, stack_size)
            if (entered != 0u) {
                child = children.x;
                continue;
            }
        }
        if (stack_size == 0u)
            break;
        ++g_path.traversal_iterations;
        --stack_size;
        child = stack_nodes[stack_size];
    }
    return false;
}

#endif
