//! The path tracer's loops, described once, and the bound of an invocation's loop iterations
//! derived from that description for both sides: the kernel counts an upper bound of its
//! iterations with the coefficients the host passes as specialization constants
//! (`SPEC_LOOPS_PER_SAMPLE` ... in `glsl/path_tracer.comp`) and flags a pixel that may have
//! reached llvmpipe's silent loop limit, and the host sizes each dispatch so that none does
//! (`crate::render::renderer`). A test scans the kernel's GLSL (the `.comp` and every file it
//! includes, `crate::kernels::scan`) for loops and fails when one is not described here.
//!
//! The bound is a SUM over all loops, not a maximum per loop: llvmpipe (Mesa 22.3) keeps one
//! loop limiter per SIMD program, which every trip of every loop of the program decrements,
//! the trip that leaves a loop included (measured by `tests/long_paths.rs`: after a first
//! loop of 40 000 iterations a second one runs only 25 534 of its 40 000). A bound per loop
//! statement would let a program's loops together pass the limit and be cut silently.

use crate::bvh::BvhStats;
use crate::contract;
use crate::kernels::variant::Traversal;

/// How many times one loop may iterate, in what the kernel counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoopBound {
    /// At most once per sample that the invocation takes.
    PerSample,
    /// At most once per ray traced (`g_path.ray_count`): each iteration traces a ray.
    PerRay,
    /// A binary search over the lights, at most once per ray: at most the bits of the light
    /// count (`findMSB(count) + 1`), never more than `LIGHT_SEARCH_MAX_ITERATIONS`.
    LightSearchPerRay,
    /// Over all triangles, at most once per ray, in `Traversal::Linear` only (unrolled over
    /// the constant triangles, replaced by the BVH's traversal in the BVH builds).
    TrianglesPerRay,
    /// Counted by the kernel itself, exactly, in `g_path.traversal_iterations` (the BVH).
    CountedByKernel,
    /// The guide's binary search over a cell's texels (`sample_guide_direction`), at most once
    /// per ray (once per guided vertex, each of which traced a ray):
    /// `GUIDE_SEARCH_ITERATIONS` iterations.
    GuideSearchPerRay,
    /// The loop over a material's textured slots (`sample_material_textures`), at most once
    /// per ray (once per surface, each of which a ray found): at most
    /// `MATERIAL_TEXTURE_SLOT_COUNT` iterations and the trip that leaves the loop.
    TextureSlotsPerRay,
}

/// Iterations of the guide's binary search: log2 of `GUIDE_CELL_TEXEL_COUNT` (texels of four
/// bins each).
pub const GUIDE_SEARCH_ITERATIONS: u32 = contract::GUIDE_CELL_TEXEL_COUNT.trailing_zeros();

/// One loop of the kernel's GLSL.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KernelLoop {
    /// The file in `glsl/`.
    pub file: &'static str,
    /// The function it is in.
    pub function: &'static str,
    /// How often it may iterate.
    pub bound: LoopBound,
    /// Loops of one group are alternatives: for the same sample or ray at most one of them
    /// runs (one integrator's path loop, the closest-hit or the any-hit query's triangle
    /// loop), so a group counts once.
    pub group: &'static str,
    /// Whether it runs only with path guiding on (`GUIDING_ON`): the bound of an unguided
    /// kernel leaves it out.
    pub guiding_only: bool,
    /// Whether it exists only in the glTF-material kernels (`USE_MATERIALS`): the bound of
    /// the others leaves it out.
    pub materials_only: bool,
}

const fn described(
    file: &'static str,
    function: &'static str,
    bound: LoopBound,
    group: &'static str,
) -> KernelLoop {
    KernelLoop {
        file,
        function,
        bound,
        group,
        guiding_only: false,
        materials_only: false,
    }
}

/// A loop that runs only with path guiding on.
const fn guiding_loop(
    file: &'static str,
    function: &'static str,
    bound: LoopBound,
    group: &'static str,
) -> KernelLoop {
    KernelLoop {
        guiding_only: true,
        ..described(file, function, bound, group)
    }
}

use LoopBound::*;

/// Every loop of `glsl/path_tracer.comp` and the files it includes, in the order of each
/// function's source. A loop added to the kernel must be added here (the test below fails
/// until it is), and if it fits none of the `LoopBound`s, the bound needs a new term.
pub const PATH_TRACER_LOOPS: &[KernelLoop] = &[
    described("path_tracer.comp", "main", PerSample, "sample loop"),
    described("integrator.glsl", "get_ray_radiance", PerRay, "path loop"),
    described("path_loop.glsl", "get_path_radiance", PerRay, "path loop"),
    // The light tree's two walks are the tree builds' light search, which the kernel counts
    // as both of them together (`get_light_search_iterations()`).
    described(
        "light_tree.glsl",
        "sample_light_tree",
        LightSearchPerRay,
        "light search",
    ),
    described(
        "light_tree.glsl",
        "get_light_tree_probability",
        LightSearchPerRay,
        "light search",
    ),
    described(
        "emissive_lights.glsl",
        "sample_light_index",
        LightSearchPerRay,
        "light search",
    ),
    described(
        "scene.glsl",
        "ray_mesh_intersection",
        TrianglesPerRay,
        "triangle loop",
    ),
    described(
        "scene.glsl",
        "ray_mesh_any_hit",
        TrianglesPerRay,
        "triangle loop",
    ),
    described("bvh.glsl", "bvh_closest_hit", CountedByKernel, "BVH"),
    described("bvh.glsl", "bvh_closest_hit", CountedByKernel, "BVH"),
    described("bvh.glsl", "bvh_closest_hit", CountedByKernel, "BVH"),
    described("bvh.glsl", "bvh_any_hit", CountedByKernel, "BVH"),
    described("bvh.glsl", "bvh_any_hit", CountedByKernel, "BVH"),
    // The ray queries' steps (the device's traversal inside each step is estimated by the
    // host as a BVH's: `TYPICAL_BVH_ITERATIONS_PER_RAY`).
    described(
        "ray_query.glsl",
        "ray_query_closest_hit",
        CountedByKernel,
        "ray query",
    ),
    described(
        "ray_query.glsl",
        "ray_query_any_hit",
        CountedByKernel,
        "ray query",
    ),
    // The compressed tree's traversals (`SPEC_BVH_LAYOUT`), counted as the 4-wide tree's
    described("cwbvh.glsl", "cwbvh_closest_hit", CountedByKernel, "BVH"),
    described("cwbvh.glsl", "cwbvh_closest_hit", CountedByKernel, "BVH"),
    described("cwbvh.glsl", "cwbvh_any_hit", CountedByKernel, "BVH"),
    described("cwbvh.glsl", "cwbvh_any_hit", CountedByKernel, "BVH"),
    guiding_loop(
        "guiding.glsl",
        "sample_guide_direction",
        GuideSearchPerRay,
        "guide search",
    ),
    // Only in the glTF-material kernels.
    KernelLoop {
        materials_only: true,
        ..described(
            "materials.glsl",
            "sample_material_textures",
            TextureSlotsPerRay,
            "texture slots",
        )
    },
    // One iteration per recorded vertex, each of which traced a ray.
    guiding_loop(
        "path_guiding.glsl",
        "splat_guide_records",
        PerRay,
        "guide splats",
    ),
];

/// Most iterations of a `LightSearchPerRay` loop (`sample_light_index`: 32 halvings bound a
/// search over any `uint` count).
pub const LIGHT_SEARCH_MAX_ITERATIONS: u64 = 32;
/// The host's estimate of a BVH traversal's iterations per ray, for sizing dispatches (the
/// kernel counts them exactly and flags what exceeds the limit), where the tree's own bound
/// (`bvh_iterations_per_ray_at_most`) is not smaller.
pub const TYPICAL_BVH_ITERATIONS_PER_RAY: u64 = 128;

/// Most iterations that one ray's traversal of a BVH of this shape (the builder's binary tree,
/// whose statistics these are) adds to `g_path.traversal_iterations` (`glsl/bvh.glsl`, which
/// traverses the tree collapsed 4 wide): no child reference is visited twice, a visit counts
/// 1 plus the leaf's triangles, and each pop counts 1, at most one per push, at most one per
/// child reference. The wide tree's references (its root and its nodes' children) number at
/// most the binary tree's nodes, so: `2 nodes + triangles`.
pub fn bvh_iterations_per_ray_at_most(stats: &BvhStats) -> u64 {
    (2 * stats.node_count + stats.triangle_count) as u64
}

/// Iterations of the light search (`sample_light_index`) over `light_count` lights, as the
/// kernel bounds them: the bits of the count (`findMSB(max(count, 1)) + 1`).
pub fn light_search_iterations(light_count: u64) -> u64 {
    let count = light_count.clamp(1, u64::from(u32::MAX));
    (u64::from(u64::BITS - count.leading_zeros())).min(LIGHT_SEARCH_MAX_ITERATIONS)
}

/// What one sample of a render loops over, as far as the host knows before rendering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleWork {
    /// Rays one sample traces at most (`g_path.ray_count`): closest-hit and shadow rays.
    pub rays: u64,
    /// Triangles of the scene (the linear traversal's loop).
    pub triangle_count: u64,
    /// Iterations of one light search (`crate::lights::SceneLights::light_search_iterations`:
    /// the power CDF's binary search over the lights, `light_search_iterations`, or the light
    /// tree's walks).
    pub light_search_iterations: u64,
    /// Most traversal iterations one ray can count in the scene's BVH
    /// (`bvh_iterations_per_ray_at_most`); `None` without a BVH or bound.
    pub bvh_iterations_per_ray: Option<u64>,
}

/// The coefficients of the bound, as the kernel receives them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoopCoefficients {
    /// Iterations per sample (`SPEC_LOOPS_PER_SAMPLE`).
    pub per_sample: u32,
    /// Iterations per ray (`SPEC_LOOPS_PER_RAY`).
    pub per_ray: u32,
    /// Light searches per ray, each of the light count's bits (`SPEC_LIGHT_SEARCHES_PER_RAY`).
    pub light_searches_per_ray: u32,
    /// Loops over all triangles per ray (`SPEC_TRIANGLE_LOOPS_PER_RAY`).
    pub triangle_loops_per_ray: u32,
    /// Whether the kernel counts a traversal's iterations itself (the BVH builds).
    pub counted_by_kernel: bool,
}

/// Groups of `loops` with this bound (those of guiding only with `guiding`, those of the
/// material kernels only with `materials`): each group runs once per unit.
fn groups(loops: &[KernelLoop], bound: LoopBound, guiding: bool, materials: bool) -> u32 {
    let mut seen: Vec<&str> = Vec::new();
    for kernel_loop in loops.iter().filter(|l| {
        l.bound == bound && (guiding || !l.guiding_only) && (materials || !l.materials_only)
    }) {
        if !seen.contains(&kernel_loop.group) {
            seen.push(kernel_loop.group);
        }
    }
    seen.len() as u32
}

impl LoopCoefficients {
    /// The coefficients of `loops` for a kernel built for `traversal`, specialized with
    /// path guiding on or off, with the glTF-material kernels' code (`materials`) or not.
    pub fn of(
        loops: &[KernelLoop],
        traversal: Traversal,
        guiding: bool,
        materials: bool,
    ) -> LoopCoefficients {
        let count = |bound| groups(loops, bound, guiding, materials);
        LoopCoefficients {
            per_sample: count(PerSample),
            per_ray: count(PerRay)
                + GUIDE_SEARCH_ITERATIONS * count(GuideSearchPerRay)
                + (contract::MATERIAL_TEXTURE_SLOT_COUNT + 1) * count(TextureSlotsPerRay),
            light_searches_per_ray: count(LightSearchPerRay),
            triangle_loops_per_ray: match traversal {
                Traversal::Linear => count(TrianglesPerRay),
                Traversal::ConstantTriangles
                | Traversal::Bvh
                | Traversal::CompressedBvh
                | Traversal::RayQuery => 0,
            },
            counted_by_kernel: (traversal.uses_bvh() || traversal == Traversal::RayQuery)
                && count(CountedByKernel) > 0,
        }
    }

    /// The path tracer's, with path guiding on or off, in a material kernel or not.
    pub fn path_tracer(traversal: Traversal, guiding: bool, materials: bool) -> LoopCoefficients {
        LoopCoefficients::of(PATH_TRACER_LOOPS, traversal, guiding, materials)
    }

    /// The specialization constants that pass them to the kernel.
    pub fn specialization(&self) -> [(u32, u32); 4] {
        [
            (contract::SPEC_LOOPS_PER_SAMPLE, self.per_sample),
            (contract::SPEC_LOOPS_PER_RAY, self.per_ray),
            (
                contract::SPEC_LIGHT_SEARCHES_PER_RAY,
                self.light_searches_per_ray,
            ),
            (
                contract::SPEC_TRIANGLE_LOOPS_PER_RAY,
                self.triangle_loops_per_ray,
            ),
        ]
    }

    /// The host's upper estimate of one sample's iterations: the kernel's bound (a sum over
    /// all loops, as llvmpipe counts them) with the light search over `work`'s lights and a
    /// BVH traversal at its typical length, or at the tree's own bound where that is
    /// smaller (a small scene's tree cannot be traversed for longer).
    pub fn iterations_per_sample(&self, work: &SampleWork) -> u64 {
        let traversal = if self.counted_by_kernel {
            work.bvh_iterations_per_ray
                .map_or(TYPICAL_BVH_ITERATIONS_PER_RAY, |bound| {
                    bound.min(TYPICAL_BVH_ITERATIONS_PER_RAY)
                })
        } else {
            0
        };
        let per_ray = u64::from(self.per_ray)
            + u64::from(self.light_searches_per_ray) * work.light_search_iterations
            + u64::from(self.triangle_loops_per_ray) * work.triangle_count
            + traversal;
        u64::from(self.per_sample) + work.rays * per_ray
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::scan::{find_loops, kernel_files, FoundLoop};

    /// (file, function, number of loops) of `loops`, sorted.
    fn tally<'a>(loops: impl Iterator<Item = (&'a str, &'a str)>) -> Vec<(String, String, usize)> {
        let mut counts: Vec<(String, String, usize)> = Vec::new();
        for (file, function) in loops {
            match counts
                .iter_mut()
                .find(|(f, g, _)| f == file && g == function)
            {
                Some(entry) => entry.2 += 1,
                None => counts.push((file.to_string(), function.to_string(), 1)),
            }
        }
        counts.sort();
        counts
    }

    #[test]
    fn every_loop_of_the_path_tracer_is_described() {
        let found: Vec<FoundLoop> = kernel_files(crate::kernels::PATH_TRACER.source)
            .into_iter()
            .flat_map(|file| {
                let text = crate::shaders::GLSL_SOURCES
                    .iter()
                    .find(|(name, _)| *name == file)
                    .map(|(_, text)| *text)
                    .unwrap_or_default();
                find_loops(file, text)
            })
            .collect();
        assert!(
            found.len() >= 10,
            "the scan finds the kernel's loops: {found:?}"
        );
        let found = tally(found.iter().map(|l| (l.file.as_str(), l.function.as_str())));
        let described = tally(PATH_TRACER_LOOPS.iter().map(|l| (l.file, l.function)));
        assert_eq!(
            found, described,
            "(file, function, loops) found in the kernel's GLSL, then as described in \
             PATH_TRACER_LOOPS: describe every loop there"
        );
    }

    #[test]
    fn coefficients_count_each_group_once() {
        let linear = LoopCoefficients::path_tracer(Traversal::Linear, false, false);
        // One sample loop; three path loops of which one runs; one light search; the
        // closest-hit or the any-hit query's loop over the triangles.
        assert_eq!(
            (
                linear.per_sample,
                linear.per_ray,
                linear.light_searches_per_ray,
                linear.triangle_loops_per_ray
            ),
            (1, 1, 1, 1)
        );
        assert!(!linear.counted_by_kernel);
        let bvh = LoopCoefficients::path_tracer(Traversal::Bvh, false, false);
        assert_eq!(bvh.triangle_loops_per_ray, 0);
        assert!(bvh.counted_by_kernel);
        let constant = LoopCoefficients::path_tracer(Traversal::ConstantTriangles, false, false);
        assert_eq!(constant.triangle_loops_per_ray, 0);
        // With guiding, per ray: the path loop, the splat loop and the guide's 6-step search.
        let guided = LoopCoefficients::path_tracer(Traversal::Linear, true, false);
        assert_eq!(guided.per_ray, 1 + 1 + 6);
        assert_eq!(guided.per_sample, 1);
        // A material kernel: the path loop and each surface's 13 texture slots plus the
        // trip that leaves their loop.
        let materials = LoopCoefficients::path_tracer(Traversal::Bvh, false, true);
        assert_eq!(materials.per_ray, 1 + 14);
        assert_eq!(
            LoopCoefficients::path_tracer(Traversal::Bvh, true, true).per_ray,
            1 + 1 + 6 + 14
        );
        // 1 + 10 rays * (1 + 32 + 100 triangles), with 2^32 - 1 lights (32 bits)
        let work = SampleWork {
            rays: 10,
            triangle_count: 100,
            light_search_iterations: light_search_iterations(u64::from(u32::MAX)),
            bvh_iterations_per_ray: None,
        };
        assert_eq!(linear.iterations_per_sample(&work), 1 + 10 * 133);
        assert_eq!(bvh.iterations_per_sample(&work), 1 + 10 * (33 + 128));
    }

    #[test]
    fn light_search_counts_the_bits_of_the_light_count() {
        // findMSB(max(count, 1)) + 1, as glsl/path_tracer.comp
        let bits: Vec<u64> = [0, 1, 2, 3, 4, 7, 8, 1 << 20, u64::from(u32::MAX)]
            .into_iter()
            .map(light_search_iterations)
            .collect();
        assert_eq!(bits, [1, 1, 2, 2, 3, 3, 4, 21, 32]);
    }

    #[test]
    fn a_small_tree_bounds_the_traversal_estimate() {
        // A binary tree of 7 nodes, 4 leaves of 30 triangles in all: collapsed 4 wide, a ray
        // visits each of its at most 7 references once (7), tests each triangle at most once
        // (30) and pops at most once per reference (7): 44 iterations, below the typical 128.
        let stats = BvhStats {
            node_count: 7,
            leaf_count: 4,
            triangle_count: 30,
            ..BvhStats::default()
        };
        assert_eq!(bvh_iterations_per_ray_at_most(&stats), 44);
        let bvh = LoopCoefficients::path_tracer(Traversal::Bvh, false, false);
        // mis at 48 vertices over 2 lights: 48 closest-hit rays and 47 shadow rays, each
        // 1 (path loop) + 2 (light search over 2 lights) + 44 (the tree): 1 + 95 * 47.
        let work = SampleWork {
            rays: 95,
            triangle_count: 30,
            light_search_iterations: light_search_iterations(2),
            bvh_iterations_per_ray: Some(44),
        };
        assert_eq!(bvh.iterations_per_sample(&work), 1 + 95 * 47);
        // A large tree's bound is above the typical traversal, which the estimate keeps.
        let large = SampleWork {
            bvh_iterations_per_ray: Some(10_000),
            ..work
        };
        assert_eq!(bvh.iterations_per_sample(&large), 1 + 95 * (1 + 2 + 128));
    }
}
