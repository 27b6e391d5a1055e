// Ray traversal of a bounding volume hierarchy over g_triangles (scene.glsl): the closest hit
// and the any-hit query of shadow rays, testing O(log n) triangles instead of all of them.
// The triangle tests read the positions from their own compact buffer
// (g_traversal_triangle_texels); the rest of a triangle is read for the closest hit only.
// The triangle tests are the workshop's ray_triangle_intersection(), so the hits are those of
// the brute-force ray_mesh_intersection() (up to ties at equal t). The nodes are built on the
// CPU (src/bvh/), which also reorders g_triangles so that each leaf holds a contiguous range.
// Rust twins: src/bvh/traversal.rs, same names and maths; change both together.
#ifndef VKPATH_BVH_GLSL
#define VKPATH_BVH_GLSL

#include "shared.h"
#include "scene.glsl"

// One node of the BVH, 32 bytes. Mirrors `vkpath::bvh::GpuBvhNode`, whose layout test checks
// these offsets. The root is node 0. An interior node's children are nodes first_index and
// first_index + 1; a leaf holds triangles first_index .. first_index + triangle_count - 1 of
// g_triangles. The integers are stored as float bits (no arithmetic ever touches them).
struct bvh_node_t {
    vec4 lower; // xyz: lower corner of the box (world space), w: first_index as uint bits
    vec4 upper; // xyz: upper corner of the box (world space), w: triangle_count as uint bits, 0 for interior nodes
};

// The nodes as a texel buffer of RGBA32_UINT, two texels per node: on lavapipe a texel fetch
// is a vector gather, where a storage-buffer load is a per-lane loop.
layout(set = 0, binding = BINDING_BVH_NODES) uniform usamplerBuffer g_bvh_node_texels;

// The triangles' vertex positions alone, in the leaf order of g_triangle_texels: a texel
// buffer of RGBA32_UINT, TRAVERSAL_TRIANGLE_TEXEL_COUNT texels per triangle (v_0, v_1, v_2 in
// xyz, w unused). Mirrors `vkpath::bvh::GpuTraversalTriangle`. The traversal's triangle
// tests read only these 48 bytes per triangle, so a leaf's triangles lie in contiguous
// 48-byte records instead of 96-byte ones whose second half (normal, albedo, emission) only
// the closest hit needs.
layout(set = 0, binding = BINDING_TRAVERSAL_TRIANGLES) uniform usamplerBuffer g_traversal_triangle_texels;

// Triangle i as the traversal's triangle test sees it: its vertex positions, and zeros for
// the members that ray_triangle_intersection() does not read (get_triangle(i) reads all of
// them). A user's own ray_triangle_intersection() may read any member, so kernels built with
// one get get_triangle(i) instead.
triangle_t get_traversal_triangle(uint index) {
#ifdef USER_DEFINES_RAY_TRIANGLE_INTERSECTION
    return get_triangle(index);
#else
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

// Node i of the BVH.
bvh_node_t get_bvh_node(uint index) {
    bvh_node_t node;
    node.lower = uintBitsToFloat(texelFetch(g_bvh_node_texels, int(2u * index)));
    node.upper = uintBitsToFloat(texelFetch(g_bvh_node_texels, int(2u * index + 1u)));
    return node;
}

// Number of nodes in the BVH.
uint get_bvh_node_count() {
    return uint(textureSize(g_bvh_node_texels)) / 2u;
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

// Whether the ray enters the root's box before t_max; out_node_count: the tree's nodes (0 for
// an empty tree, which nothing enters).
bool bvh_enters_root(out uint out_node_count, vec3 ray_origin, vec3 inverse_direction, float t_max) {
    out_node_count = get_bvh_node_count();
    float t_entry;
    return out_node_count != 0u && bvh_ray_box_intersection(t_entry, ray_origin, inverse_direction, get_bvh_node(0).lower.xyz, get_bvh_node(0).upper.xyz, t_max);
}

// Visits a node: its range, its first triangle (a leaf) or its first child (an interior
// node, the second child follows it), and its triangle count (0 for interior nodes); counts
// the visit and the leaf loop's iterations (an upper bound when that loop stops early) in
// g_path.traversal_iterations.
void visit_bvh_node(uint node_index, out uint out_first_index, out uint out_triangle_count) {
    bvh_node_t node = get_bvh_node(node_index);
    out_first_index = floatBitsToUint(node.lower.w);
    out_triangle_count = floatBitsToUint(node.upper.w);
    g_path.traversal_iterations += 1u + out_triangle_count;
}

// The children of an interior node (first_index and first_index + 1) whose boxes the ray
// enters before t_max, nearer first: how many (0, 1 or 2); out_near is the one to visit
// next, out_far (entered at out_far_entry) the one to push when both are entered.
uint bvh_enter_children(uint first_index, vec3 ray_origin, vec3 inverse_direction, float t_max, out uint out_near, out uint out_far, out float out_far_entry) {
    float t_left, t_right;
    bool hit_left = bvh_ray_box_intersection(t_left, ray_origin, inverse_direction, get_bvh_node(first_index).lower.xyz, get_bvh_node(first_index).upper.xyz, t_max);
    bool hit_right = bvh_ray_box_intersection(t_right, ray_origin, inverse_direction, get_bvh_node(first_index + 1u).lower.xyz, get_bvh_node(first_index + 1u).upper.xyz, t_max);
    bool left_first = !hit_right || (hit_left && t_left <= t_right);
    out_near = left_first ? first_index : first_index + 1u;
    out_far = left_first ? first_index + 1u : first_index;
    out_far_entry = left_first ? t_right : t_left;
    return (hit_left ? 1u : 0u) + (hit_right ? 1u : 0u);
}

// Finds the closest triangle that a ray hits, traversing the BVH: the brute-force
// ray_mesh_intersection() with the same triangle tests, nearer child first, and subtrees
// skipped once they start beyond the closest hit so far.
// \param out_t Ray parameter of the closest hit (NO_HIT_T if none)
// \param out_triangle_index Index of the hit triangle in g_triangles (0 if none)
// \param ray_origin, ray_direction The ray, world space (the direction need not be normalized)
// \return true iff a triangle was hit at 0 <= t < NO_HIT_T
bool bvh_closest_hit(out float out_t, out uint out_triangle_index, vec3 ray_origin, vec3 ray_direction) {
    out_t = NO_HIT_T;
    out_triangle_index = 0u;
    bool hit = false;
    vec3 inverse_direction = bvh_inverse_direction(ray_direction);
    uint node_count;
    if (!bvh_enters_root(node_count, ray_origin, inverse_direction, out_t))
        return false;
    // Nodes still to visit, with the parameter where the ray enters them
    uint stack_nodes[BVH_STACK_SIZE];
    float stack_entries[BVH_STACK_SIZE];
    uint stack_size = 0u;
    uint node_index = 0u;
    // Each iteration visits one node and no node is visited twice, so node_count bounds it.
    for (uint iteration = 0u; iteration != node_count; ++iteration) {
        uint first_index, triangle_count;
        visit_bvh_node(node_index, first_index, triangle_count);
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
            // An interior node: test both children, go to the nearer, push the farther
            uint far_child;
            float far_entry;
            uint entered = bvh_enter_children(first_index, ray_origin, inverse_direction, out_t, node_index, far_child, far_entry);
            // The builder keeps leaves at depth <= BVH_STACK_SIZE, so the stack never
            // overflows; the test only keeps a malformed tree from writing out of bounds.
            if (entered == 2u && stack_size < BVH_STACK_SIZE) {
                stack_nodes[stack_size] = far_child;
                stack_entries[stack_size] = far_entry;
                ++stack_size;
            }
            descend = entered != 0u;
        }
        // Pop the next node that the ray enters before the closest hit so far (the stack
        // shrinks in every iteration, so this loop is bounded by BVH_STACK_SIZE)
        while (!descend && stack_size != 0u) {
            ++g_path.traversal_iterations;
            --stack_size;
            if (stack_entries[stack_size] <= out_t) {
                node_index = stack_nodes[stack_size];
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
    vec3 inverse_direction = bvh_inverse_direction(ray_direction);
    uint node_count;
    if (!bvh_enters_root(node_count, ray_origin, inverse_direction, t_max))
        return false;
    // Entry parameters need no stack here: t_max never shrinks, so popped nodes need no test.
    uint stack_nodes[BVH_STACK_SIZE];
    uint stack_size = 0u;
    uint node_index = 0u;
    // Each iteration visits one node and no node is visited twice, so node_count bounds it.
    for (uint iteration = 0u; iteration != node_count; ++iteration) {
        uint first_index, triangle_count;
        visit_bvh_node(node_index, first_index, triangle_count);
        if (triangle_count != 0u) {
            uint end = first_index + triangle_count;
            for (uint i = first_index; i < end; ++i) {
                float t;
                if (ray_triangle_intersection(t, ray_origin, ray_direction, get_traversal_triangle(i)) && t < t_max AND_HIT_IS_OPAQUE(i, ray_origin, ray_direction, t))
                    return true;
            }
        } else {
            // Nearer first: an occluder near the origin ends the search sooner
            uint far_child;
            float far_entry;
            uint next_node;
            uint entered = bvh_enter_children(first_index, ray_origin, inverse_direction, t_max, next_node, far_child, far_entry);
            if (entered == 2u && stack_size < BVH_STACK_SIZE) {
                stack_nodes[stack_size] = far_child;
                ++stack_size;
            }
            if (entered != 0u) {
                node_index = next_node;
                continue;
            }
        }
        if (stack_size == 0u)
            break;
        --stack_size;
        node_index = stack_nodes[stack_size];
    }
    return false;
}

#endif
