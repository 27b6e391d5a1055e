// The state a kernel invocation keeps beside its functions' arguments: vkpath's additions to
// the workshop's interface, whose signatures stay as its slides write them. One struct, one
// private global per invocation (GLSL's globals are per invocation), written and read only
// where each member says.
#ifndef VKPATH_PATH_STATE_GLSL
#define VKPATH_PATH_STATE_GLSL

struct path_state_t {
    // Index in g_triangles of the triangle that the last successful ray_mesh_intersection()
    // hit: it carries per-triangle flags (is_double_sided()) and materials to the caller.
    // Written by ray_mesh_intersection() (glsl/scene.glsl).
    uint hit_triangle_index;
    // Rays this invocation traced (`vkpath bench`'s rays/s, the loop-limit bound of
    // glsl/path_tracer.comp, the alpha coverage hash). Counted by ray_mesh_intersection() and
    // ray_mesh_any_hit().
    uint ray_count;
    // Iterations of the BVH traversal loops this invocation ran (llvmpipe ends all loops of
    // an invocation after LLVMPIPE_LOOP_LIMIT iterations, see path_tracer.comp). Counted by
    // glsl/bvh.glsl.
    uint traversal_iterations;
    // The current sample (glsl/sobol.glsl's get_path_random_numbers()), set by main() before
    // each sample: its index and the pixel's seed (get_sobol_pixel_seed()).
    uint sample_index;
    uint pixel_seed;
    // The sample's random state for stochastic alpha (ALPHA_MODE_BLEND, glsl/materials.glsl),
    // set by the kernel once per sample: a hit's coverage hashes it with ray_count and the
    // triangle's index.
    uvec2 alpha_seed;
    // Path guiding: the guided cell of the current vertex (GUIDE_NO_CELL, 0xffffffff, where
    // the BSDF samples alone), set by the path loop before its light samples, read by
    // get_path_direction_density() (glsl/path_guiding.glsl).
    uint guide_cell;
};

path_state_t g_path = path_state_t(0u, 0u, 0u, 0u, 0u, uvec2(0u), 0xffffffffu);

// The hit triangle's index under the name the workshop's estimators and exercise files use:
// is_double_sided(g_hit_triangle_index).
#define g_hit_triangle_index g_path.hit_triangle_index

#endif
