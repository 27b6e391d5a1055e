//! The builds of the kernels that are compiled more than once, with different macros. Read
//! by `build.rs` (which compiles every `glsl/*.comp` once without macros and once more for
//! each build listed here) and by `crate::kernels` (which picks a build at run time, and
//! whose `vkpath check` compiles the same macros again): this file is the one place that
//! says how a kernel is built. It uses nothing but `core`, so that `build.rs` can include it.

/// One extra build of a kernel: the GLSL file's stem, the build's name (its SPIR-V is
/// `crate::shaders::<NAME>`, upper-cased) and the macros `#define`d for it.
pub struct KernelBuild {
    /// The kernel's file in `glsl/`, without `.comp`.
    pub source: &'static str,
    /// The build's name.
    pub name: &'static str,
    /// `(name, value)` of each macro defined before the source is read.
    pub macros: &'static [(&'static str, &'static str)],
}

/// The macro that makes the path tracer traverse a BVH (`glsl/bvh.glsl`).
pub const USE_BVH: &str = "USE_BVH";
/// The macro that makes the path tracer find hits with the device's acceleration structures
/// (`glsl/ray_query.glsl`: `VK_KHR_ray_query`), for devices that offer them.
pub const USE_RAY_QUERY: &str = "USE_RAY_QUERY";
/// The macro that gives the path tracer glTF materials (the glTF model of `glsl/surface.glsl`,
/// the environment and punctual lights of `glsl/lights.glsl`).
pub const USE_MATERIALS: &str = "USE_MATERIALS";

/// The macro that leaves the layered lobes (transmission, clear coat, sheen:
/// `glsl/layered_bsdf.glsl`) out of a material kernel, for scenes that use none: the same
/// images as the build with them, from 55 % of its SPIR-V (less for lavapipe to translate at
/// start-up).
pub const WITHOUT_LAYERS: &str = "WITHOUT_LAYERS";

/// The macro that makes the workshop kernels' constant triangles unroll only the first
/// `FEW_CONSTANT_TRIANGLE_CAPACITY` (32) triangles, for scenes that have no more: the same
/// images from half the unrolled code (a shorter start on lavapipe).
pub const FEW_CONSTANT_TRIANGLES: &str = "FEW_CONSTANT_TRIANGLES";

/// The macros of the lean builds, for renders that need neither the light tree, nor path
/// guiding, nor an environment map (most renders of small scenes): each turns a
/// specialization constant into a constant, so that the build's SPIR-V carries none of that
/// code. The same images as the builds with it, and a shorter start on lavapipe, which
/// translates a kernel's whole SPIR-V at every start (docs/performance.md, "Stop 25").
pub const WITHOUT_LIGHT_TREE: &str = "WITHOUT_LIGHT_TREE";
/// See `WITHOUT_LIGHT_TREE`.
pub const WITHOUT_GUIDING: &str = "WITHOUT_GUIDING";
/// See `WITHOUT_LIGHT_TREE` (material kernels only: the others have no environment).
pub const WITHOUT_ENVIRONMENT_MAP: &str = "WITHOUT_ENVIRONMENT_MAP";

/// Every build beyond the plain one of each kernel.
pub const EXTRA_BUILDS: &[KernelBuild] = &[
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_few_triangles",
        macros: &[(FEW_CONSTANT_TRIANGLES, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_bvh",
        macros: &[(USE_BVH, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials",
        macros: &[(USE_MATERIALS, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_without_layers",
        macros: &[(USE_MATERIALS, "1"), (WITHOUT_LAYERS, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_bvh",
        macros: &[(USE_BVH, "1"), (USE_MATERIALS, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_bvh_without_layers",
        macros: &[(USE_BVH, "1"), (USE_MATERIALS, "1"), (WITHOUT_LAYERS, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_few_triangles_lean",
        macros: &[
            (FEW_CONSTANT_TRIANGLES, "1"),
            (WITHOUT_LIGHT_TREE, "1"),
            (WITHOUT_GUIDING, "1"),
        ],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_bvh_lean",
        macros: &[
            (USE_BVH, "1"),
            (WITHOUT_LIGHT_TREE, "1"),
            (WITHOUT_GUIDING, "1"),
        ],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_ray_query",
        macros: &[(USE_RAY_QUERY, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_ray_query_lean",
        macros: &[
            (USE_RAY_QUERY, "1"),
            (WITHOUT_LIGHT_TREE, "1"),
            (WITHOUT_GUIDING, "1"),
        ],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_ray_query",
        macros: &[(USE_RAY_QUERY, "1"), (USE_MATERIALS, "1")],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_ray_query_without_layers",
        macros: &[
            (USE_RAY_QUERY, "1"),
            (USE_MATERIALS, "1"),
            (WITHOUT_LAYERS, "1"),
        ],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_ray_query_lean",
        macros: &[
            (USE_RAY_QUERY, "1"),
            (USE_MATERIALS, "1"),
            (WITHOUT_LAYERS, "1"),
            (WITHOUT_LIGHT_TREE, "1"),
            (WITHOUT_GUIDING, "1"),
            (WITHOUT_ENVIRONMENT_MAP, "1"),
        ],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_lean",
        macros: &[
            (USE_MATERIALS, "1"),
            (WITHOUT_LAYERS, "1"),
            (WITHOUT_LIGHT_TREE, "1"),
            (WITHOUT_GUIDING, "1"),
            (WITHOUT_ENVIRONMENT_MAP, "1"),
        ],
    },
    KernelBuild {
        source: "path_tracer",
        name: "path_tracer_materials_bvh_lean",
        macros: &[
            (USE_BVH, "1"),
            (USE_MATERIALS, "1"),
            (WITHOUT_LAYERS, "1"),
            (WITHOUT_LIGHT_TREE, "1"),
            (WITHOUT_GUIDING, "1"),
            (WITHOUT_ENVIRONMENT_MAP, "1"),
        ],
    },
];
