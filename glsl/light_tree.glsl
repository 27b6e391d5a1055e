// The light tree (--light-selection tree): choosing an emissive triangle by its importance
// to the shading point, from a bounding-volume hierarchy over the lights whose nodes bound
// their positions, emitting normals and power (Conty Estevez and Kulla, "Importance Sampling
// of Many Lights with Adaptive Tree Splitting", HPG 2018; pbrt-v4's BVHLightSampler). One
// random number goes from the root to a leaf, rescaled at each level; the probability of a
// given light is recomputed by walking from the root along its leaf's bit trail (for MIS).
//
// The nodes follow the lights in the lights' texel buffer (g_light_texels of
// glsl/emissive_lights.glsl): header.y is the first node's texel (0: no tree), header.z the deepest
// leaf's depth; light i's texel holds its bit trail in z (bit d: the walk takes the second
// child at depth d). A node is four texels, vkpath::lights::light_tree::GpuLightTreeNode, in
// depth-first order (an interior node's first child follows it). Written by
// vkpath::lights::gpu_emissive::gpu_light_bytes_with_tree, whose tests check the layout.
//
// Rust twins: src/cpu/light_tree.rs. Needs g_light_texels declared by the includer.
#ifndef VKPATH_LIGHT_TREE_GLSL
#define VKPATH_LIGHT_TREE_GLSL

// What sample_light_tree() returns where the tree proves that no light reaches the point.
#define NO_LIGHT 0xffffffffu

// A node of the light tree: the bounds of the lights below it.
struct light_tree_node_t {
    // Corners of the box around the lights, world space
    vec3 bounds_min;
    vec3 bounds_max;
    // Their emitted power (area * pi * luminance of L_e, twice for two-sided emitters)
    float phi;
    // Interior nodes: index of the second child (the first follows the node); leaves: the
    // light's index in the light list
    uint index;
    // Unit axis of a cone that holds every light's emitting normal, and the cosine of its
    // half angle theta_o
    vec3 direction;
    float cos_theta_o;
    // Cosine of the angle theta_e beyond the normals into which light leaves (triangles: 0)
    float cos_theta_e;
    // A single light
    bool is_leaf;
    // Some light below emits from both sides (the cone holds the normals' opposites too)
    bool two_sided;
};

// Texel of the first node (0: the scene has no tree).
uint get_light_tree_first_texel() {
    return texelFetch(g_light_texels, 0).y;
}

// Depth of the deepest leaf (0: the root is the only light).
uint get_light_tree_depth() {
    return texelFetch(g_light_texels, 0).z;
}

// Bit trail of light i's leaf.
uint get_light_bit_trail(uint light_index) {
    return texelFetch(g_light_texels, int(light_index) + 1).z;
}

// Node i of the light tree.
light_tree_node_t get_light_tree_node(uint node_index) {
    int first = int(get_light_tree_first_texel() + 4u * node_index);
    vec4 t0 = uintBitsToFloat(texelFetch(g_light_texels, first));
    uvec4 t1 = texelFetch(g_light_texels, first + 1);
    vec4 t2 = uintBitsToFloat(texelFetch(g_light_texels, first + 2));
    uvec4 t3 = texelFetch(g_light_texels, first + 3);
    light_tree_node_t node;
    node.bounds_min = t0.xyz;
    node.phi = t0.w;
    node.bounds_max = uintBitsToFloat(t1.xyz);
    node.index = t1.w;
    node.direction = t2.xyz;
    node.cos_theta_o = t2.w;
    node.cos_theta_e = uintBitsToFloat(t3.x);
    node.is_leaf = (t3.y & LIGHT_TREE_FLAG_LEAF) != 0u;
    node.two_sided = (t3.y & LIGHT_TREE_FLAG_TWO_SIDED) != 0u;
    return node;
}

// cos(max(0, a - b)) of two angles in [0, pi] given by their sines and cosines.
float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    if (cos_a > cos_b)
        return 1.0;
    return cos_a * cos_b + sin_a * sin_b;
}

// sin(max(0, a - b)), likewise.
float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    if (cos_a > cos_b)
        return 0.0;
    return sin_a * cos_b - cos_a * sin_b;
}

// An upper bound of the light that the lights of `node` bring to `position` (pbrt-v4's
// LightBounds::Importance): phi |cos theta'| / d^2 with d^2 the squared distance to the box's
// centre (at least half its diagonal) and theta' the smallest angle between any of the
// lights' normals and any direction from the box to the point: the angle to the cone's axis
// theta_w, minus theta_o, minus the angle theta_b of the box's bounding sphere seen from the
// point; 0 beyond theta_e (no light can leave towards the point). With a `normal`, also
// times the largest cosine between it and a direction into the box's bounding sphere, and 0
// where the whole box lies below the surface's plane (no light reaches its front); normal =
// 0 leaves that out.
// \param position The shading point, world space
// \param normal Unit normal of the side that receives light there, or 0
float get_light_bounds_importance(light_tree_node_t node, vec3 position, vec3 normal) {
    vec3 center = 0.5 * (node.bounds_min + node.bounds_max);
    vec3 to_point = position - center;
    float center_distance_squared = dot(to_point, to_point);
    vec3 diagonal = node.bounds_max - node.bounds_min;
    float d2 = max(center_distance_squared, 0.5 * length(diagonal));
    // The direction from the box towards the point (0 at its very centre)
    vec3 wi = (center_distance_squared > 0.0) ? to_point / sqrt(center_distance_squared) : vec3(0.0);
    float cos_theta_w = dot(node.direction, wi);
    if (node.two_sided)
        cos_theta_w = abs(cos_theta_w);
    float sin_theta_w = sqrt(max(0.0, 1.0 - cos_theta_w * cos_theta_w));
    // theta_b: the cone of directions from the point that holds the box's bounding sphere
    // (all of them inside it)
    float radius_squared = 0.25 * dot(diagonal, diagonal);
    float cos_theta_b = -1.0;
    if (center_distance_squared > radius_squared)
        cos_theta_b = sqrt(max(0.0, 1.0 - radius_squared / center_distance_squared));
    float sin_theta_b = sqrt(max(0.0, 1.0 - cos_theta_b * cos_theta_b));
    // theta' = theta_w - theta_o - theta_b, clamped at 0
    float sin_theta_o = sqrt(max(0.0, 1.0 - node.cos_theta_o * node.cos_theta_o));
    float cos_theta_x = cos_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, node.cos_theta_o);
    float sin_theta_x = sin_sub_clamped(sin_theta_w, cos_theta_w, sin_theta_o, node.cos_theta_o);
    float cos_theta_p = cos_sub_clamped(sin_theta_x, cos_theta_x, sin_theta_b, cos_theta_b);
    if (cos_theta_p <= node.cos_theta_e)
        return 0.0;
    float importance = node.phi * cos_theta_p / d2;
    if (normal != vec3(0.0)) {
        // The whole box below the surface's plane (its support along the normal, the
        // largest n . (corner - position) of its corners, at most 0): no light reaches the
        // front. Tighter than the bounding sphere's angle for the flat boxes of lights
        // along a floor or ceiling.
        if (dot(normal, center - position) + dot(abs(normal), 0.5 * diagonal) <= 0.0)
            return 0.0;
        // The angle between the normal and the direction towards the box, less theta_b
        float cos_theta_i = -dot(wi, normal);
        float sin_theta_i = sqrt(max(0.0, 1.0 - cos_theta_i * cos_theta_i));
        importance *= cos_sub_clamped(sin_theta_i, cos_theta_i, sin_theta_b, cos_theta_b);
    }
    return max(importance, 0.0);
}

// The probability of the first child at an interior node, from the children's importance
// (1 where only the first can matter, 0 where only the second); -1 where neither can.
float get_light_tree_first_child_probability(light_tree_node_t node, uint node_index, vec3 position, vec3 normal) {
    float first = get_light_bounds_importance(get_light_tree_node(node_index + 1u), position, normal);
    float second = get_light_bounds_importance(get_light_tree_node(node.index), position, normal);
    if (!(first + second > 0.0))
        return -1.0;
    return first / (first + second);
}

// Chooses an emissive triangle by walking the tree from the root, each child with
// probability proportional to its importance, the random number rescaled to [0, 1) at each
// level.
// \param random_number Uniform in [0,1)
// \param position, normal The shading point and its normal (get_light_bounds_importance())
// \param out_probability The probability of the light returned (0 with NO_LIGHT)
// \return Index of a light in the light list, or NO_LIGHT where no light can reach the point
uint sample_light_tree(float random_number, vec3 position, vec3 normal, out float out_probability) {
    out_probability = 0.0;
    if (get_light_tree_first_texel() == 0u)
        return NO_LIGHT;
    float u = random_number;
    float probability = 1.0;
    uint node_index = 0u;
    // Each trip goes one level down: at most LIGHT_TREE_MAX_DEPTH + 1 trips.
    for (uint depth = 0u; depth <= LIGHT_TREE_MAX_DEPTH; ++depth) {
        light_tree_node_t node = get_light_tree_node(node_index);
        if (node.is_leaf) {
            if (node_index > 0u || get_light_bounds_importance(node, position, normal) > 0.0) {
                out_probability = probability;
                return node.index;
            }
            return NO_LIGHT;
        }
        float first = get_light_tree_first_child_probability(node, node_index, position, normal);
        if (first < 0.0)
            return NO_LIGHT;
        if (u < first) {
            u = min(u / first, ONE_MINUS_EPSILON);
            probability *= first;
            node_index += 1u;
        } else {
            u = min((u - first) / (1.0 - first), ONE_MINUS_EPSILON);
            probability *= 1.0 - first;
            node_index = node.index;
        }
    }
    return NO_LIGHT;
}

// The probability that sample_light_tree() at `position` with `normal` chooses light i: the
// product of the same choices along the light's bit trail.
float get_light_tree_probability(uint light_index, vec3 position, vec3 normal) {
    if (get_light_tree_first_texel() == 0u)
        return 0.0;
    uint trail = get_light_bit_trail(light_index);
    float probability = 1.0;
    uint node_index = 0u;
    for (uint depth = 0u; depth <= LIGHT_TREE_MAX_DEPTH; ++depth) {
        light_tree_node_t node = get_light_tree_node(node_index);
        if (node.is_leaf) {
            if (node_index > 0u || get_light_bounds_importance(node, position, normal) > 0.0)
                return probability;
            return 0.0;
        }
        float first = get_light_tree_first_child_probability(node, node_index, position, normal);
        if (first < 0.0)
            return 0.0;
        if ((trail & 1u) == 0u) {
            probability *= first;
            node_index += 1u;
        } else {
            probability *= 1.0 - first;
            node_index = node.index;
        }
        trail >>= 1u;
    }
    return 0.0;
}

#endif
