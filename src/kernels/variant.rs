//! The one room that decides which variant of the path tracer runs: how it finds hits
//! (`Traversal`), which SPIR-V build of `glsl/path_tracer.comp` it takes (`builds`), and the
//! specialization constants that say what the scene has (`SCENE_HAS_*`, the light
//! selection). A pure function of a `SceneSummary` (counts and flags, no data), the
//! `VariantSettings` and the traversal, testable without a GPU: every later scene flag or
//! lean build lands in the tables of this file and nowhere else.
//!
//! The render-wide constants that do not depend on the scene (path length, integrator,
//! sampler: `RenderSettings::specialization`) and those of the loop budget
//! (`crate::kernels::loops`) join the variant's in `crate::kernels::specialization`.

use crate::contract;
use crate::error::Result;
use crate::kernels::builds::{
    FEW_CONSTANT_TRIANGLES, USE_BVH, USE_MATERIALS, USE_RAY_QUERY, WITHOUT_ENVIRONMENT_MAP,
    WITHOUT_GUIDING, WITHOUT_LAYERS, WITHOUT_LIGHT_TREE,
};
use crate::kernels::{Build, PATH_TRACER};
use crate::scene::Triangle;

/// How rays find the closest triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Accel {
    /// A BVH for scenes of more than `BVH_THRESHOLD` triangles and for material scenes that
    /// the constant triangles cannot trace (more than 16 triangles, or alpha), else the loop
    /// compiled into the kernel (`Traversal::choose`); where such a scene would take the
    /// BVH and the device has ray queries, the device's acceleration structures
    /// (`Traversal::choose_on_device`).
    #[default]
    #[cfg_attr(
        feature = "cli",
        value(
            help = "A BVH above 64 triangles (glTF materials: above 16 or with alpha), the device's ray queries instead where it has them, else the linear loop"
        )
    )]
    Auto,
    /// The workshop's loop over all triangles.
    #[cfg_attr(
        feature = "cli",
        value(help = "The workshop's linear loop over all triangles")
    )]
    None,
    /// A bounding volume hierarchy (binned SAH), traversed in the shader.
    #[cfg_attr(feature = "cli", value(help = "Always a BVH"))]
    Bvh,
    /// The device's acceleration structures, traversed by `VK_KHR_ray_query` in the same
    /// kernel (`glsl/ray_query.glsl`); an error on devices without ray queries.
    #[cfg_attr(
        feature = "cli",
        value(help = "Always the device's ray queries (VK_KHR_ray_query); an error without them")
    )]
    Hardware,
    /// The compressed wide BVH (8-wide, quantised boxes: `crate::bvh::CompressedBvh`), for
    /// large scenes: less memory per triangle than `Bvh`'s 4-wide tree.
    #[cfg_attr(
        feature = "cli",
        value(help = "Always the compressed 8-wide BVH (quantised boxes, less memory)")
    )]
    CompressedBvh,
}

/// Scenes with more triangles than this get a BVH under `Accel::Auto`. Measured on lavapipe
/// (`vkpath bench`-style runs): the workshop's 30-triangle box is several times faster with
/// the loop over all triangles compiled into the kernel (`Traversal::ConstantTriangles`), and
/// even the loop over the texel buffer beats the BVH there (2.27 against 1.29 M samples/s
/// with `workshop`); at about 130 triangles the BVH is 1.3x faster than that loop.
pub const BVH_THRESHOLD: usize = 64;

impl Accel {
    /// Whether a scene of `triangle_count` triangles is traced with a BVH.
    pub fn uses_bvh(self, triangle_count: usize) -> bool {
        match self {
            Accel::Auto => triangle_count > BVH_THRESHOLD,
            Accel::None | Accel::Hardware => false,
            Accel::Bvh | Accel::CompressedBvh => true,
        }
    }
}

/// How the kernel finds the triangle a ray hits. The triangles' data are read from a texel
/// buffer (RGBA32_UINT, `TRIANGLE_TEXEL_COUNT` texels per triangle): on lavapipe a texel fetch
/// at a per-lane index is a vector gather, faster than uniform- or storage-buffer loads
/// (docs/performance.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Traversal {
    /// The workshop's loop over all triangles, compiled into the kernel: their positions are
    /// specialization constants (`glsl/constant_triangles.glsl`), so a ray reads no memory
    /// per triangle. For scenes that `constant_triangles_can_trace`.
    ConstantTriangles,
    /// The workshop's loop over all triangles, read from the texel buffer
    /// (`glsl/path_tracer.comp`).
    Linear,
    /// A BVH, with the triangles in its leaf order (`path_tracer.comp` with `USE_BVH`).
    Bvh,
    /// The device's acceleration structures over the triangles in their scene order,
    /// traversed with `VK_KHR_ray_query` (`path_tracer.comp` with `USE_RAY_QUERY`).
    RayQuery,
    /// The compressed wide BVH (`crate::bvh::CompressedBvh`), with the triangles in its leaf
    /// order: the builds of `Bvh`, specialized with `SPEC_BVH_LAYOUT`.
    CompressedBvh,
}

impl Traversal {
    /// Most triangles that the kernel of these `materials` (the workshop's kernels: false;
    /// the glTF-material kernels: true) compiles in: `CONSTANT_TRIANGLE_CAPACITY`, or
    /// `MATERIAL_CONSTANT_TRIANGLE_CAPACITY` for the material kernels, whose intersection
    /// code stands at more call sites (`glsl/shared.h`).
    pub fn constant_triangle_capacity(materials: bool) -> usize {
        if materials {
            contract::MATERIAL_CONSTANT_TRIANGLE_CAPACITY as usize
        } else {
            contract::CONSTANT_TRIANGLE_CAPACITY as usize
        }
    }

    /// Whether the constant triangles can trace a scene of `triangle_count` triangles for
    /// the workshop's kernels (`materials` false) or the glTF-material kernels (true), with
    /// or without alpha-tested materials: it fits their capacity, and it has no alpha (their
    /// unrolled tests leave the alpha test out, whose code would be unrolled with them).
    pub fn constant_triangles_can_trace(
        triangle_count: usize,
        materials: bool,
        alpha: bool,
    ) -> bool {
        triangle_count <= Traversal::constant_triangle_capacity(materials) && !alpha
    }

    /// What `accel` asks for, for a scene of `triangle_count` triangles traced by the
    /// workshop's kernels (`materials` false) or the glTF-material kernels (true), `alpha`
    /// when some material is alpha-tested.
    ///
    /// Scenes that the constant triangles can trace (`constant_triangles_can_trace`) compile
    /// their triangles in: the fastest samples, and for the material kernels a start within
    /// about 0.02 s of the BVH's (16 triangles unrolled at four call sites, without the
    /// layered lobes where the scene has none; docs/performance.md). Other material scenes
    /// take a BVH under `Accel::Auto` however small (the texel loop's samples are slower);
    /// `Accel::None` keeps the loop, over the texel buffer where the constant triangles
    /// cannot trace the scene.
    ///
    /// `Accel::Hardware` always takes `Traversal::RayQuery` (the caller checks that the
    /// device has ray queries); `Accel::Auto` never does here (`choose_on_device` does).
    pub fn choose(triangle_count: usize, accel: Accel, materials: bool, alpha: bool) -> Traversal {
        let constant = Traversal::constant_triangles_can_trace(triangle_count, materials, alpha);
        if accel == Accel::Hardware {
            Traversal::RayQuery
        } else if accel == Accel::CompressedBvh {
            Traversal::CompressedBvh
        } else if accel == Accel::Bvh {
            Traversal::Bvh
        } else if accel.uses_bvh(triangle_count) || (!constant && accel == Accel::Auto && materials)
        {
            // `auto`'s BVH is the compressed tree: less memory and faster samples (1.6x mis,
            // 1.2x workshop on 10⁶ triangles, docs/performance.md); the 4-wide tree where it
            // cannot hold the scene (`GpuScene::upload`)
            Traversal::CompressedBvh
        } else if constant {
            Traversal::ConstantTriangles
        } else {
            Traversal::Linear
        }
    }

    /// `choose` on a device (`on.ray_queries`, `on.cpu`) for a render that may be one frame
    /// of a sequence whose geometry moves (`on.moving_geometry`). Under `Accel::Auto`:
    /// - a sequence whose geometry moves takes the BVH where the constant triangles would
    ///   compile its few triangles into the kernel: their positions are specialization
    ///   constants, so every frame would build its kernel again (1.7–2.2 s a frame on
    ///   lavapipe against 0.02–0.08 s with the BVH: SimpleSkin, SimpleMorph), and every
    ///   frame of the sequence takes the same traversal;
    /// - a hardware device's ray queries take the place of the BVH; a CPU device's
    ///   (`VkPhysicalDeviceType::CPU`: Mesa 25's lavapipe) do not: they run in software,
    ///   about 4x slower than the compressed BVH (0.09–0.12 against 0.42 M samples/s,
    ///   `--generated 100000`), and `--accel hardware` still asks for them.
    ///
    /// Scenes traced by the loop over the texel buffer keep it (its kernel does not change
    /// when the triangles move).
    pub fn choose_on_device(
        triangle_count: usize,
        accel: Accel,
        materials: bool,
        alpha: bool,
        on: TraversalContext,
    ) -> Traversal {
        let chosen = match Traversal::choose(triangle_count, accel, materials, alpha) {
            Traversal::ConstantTriangles if accel == Accel::Auto && on.moving_geometry => {
                Traversal::CompressedBvh
            }
            traversal => traversal,
        };
        match chosen {
            Traversal::CompressedBvh if accel == Accel::Auto && on.ray_queries && !on.cpu => {
                Traversal::RayQuery
            }
            traversal => traversal,
        }
    }

    /// A short name for reports: "constant triangles", "linear", "BVH", "compressed BVH" or
    /// "ray queries".
    pub fn name(self) -> &'static str {
        match self {
            Traversal::ConstantTriangles => "constant triangles",
            Traversal::Linear => "linear",
            Traversal::Bvh => "BVH",
            Traversal::CompressedBvh => "compressed BVH",
            Traversal::RayQuery => "ray queries",
        }
    }

    /// What ran, as `render --json`'s `accel` names it: `"hardware"` (the device's ray
    /// queries), `"bvh"` (either tree) or `"none"` (the loop over all triangles, compiled in
    /// or not).
    pub fn accel_name(self) -> &'static str {
        match self {
            Traversal::ConstantTriangles | Traversal::Linear => "none",
            Traversal::Bvh | Traversal::CompressedBvh => "bvh",
            Traversal::RayQuery => "hardware",
        }
    }

    /// Whether rays traverse a BVH (the `USE_BVH` builds), 4-wide or compressed.
    pub fn uses_bvh(self) -> bool {
        matches!(self, Traversal::Bvh | Traversal::CompressedBvh)
    }

    /// `SPEC_BVH_LAYOUT` of the `USE_BVH` builds: which tree the BVH bindings hold.
    pub fn bvh_layout(self) -> u32 {
        if self == Traversal::CompressedBvh {
            contract::BVH_LAYOUT_COMPRESSED
        } else {
            contract::BVH_LAYOUT_WIDE
        }
    }
}

/// What the traversal choice (`Traversal::choose_on_device`) reads beside the scene: the
/// device's ray queries and type, and whether the render is a frame of a sequence whose
/// geometry moves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalContext {
    /// Whether the device's kernels can trace rays with ray queries (`VK_KHR_ray_query`).
    pub ray_queries: bool,
    /// Whether the device is a CPU (`VkPhysicalDeviceType::CPU`, e.g. lavapipe), whose ray
    /// queries are software.
    pub cpu: bool,
    /// Whether the render is one frame of a sequence whose triangles move from frame to
    /// frame (skins, morph targets, animated nodes that carry meshes).
    pub moving_geometry: bool,
}

/// What the variant choice reads of a scene: counts and flags, no data. Made by
/// `crate::render::gpu_scene::GpuScene::upload` from the scene, its materials (the plain
/// ones of a workshop scene that the material kernels render) and its lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneSummary {
    /// Triangles in the scene.
    pub triangle_count: usize,
    /// Whether the scene needs the glTF-material kernels (`Scene::needs_material_kernels`).
    pub materials: bool,
    /// Whether some material has a layered lobe (`SceneMaterials::uses_layers`).
    pub layers: bool,
    /// Whether some material encloses a scattering volume
    /// (`SceneMaterials::uses_volume_scatter`).
    pub volume_scatter: bool,
    /// Whether some material is alpha-tested or blended (`SceneMaterials::uses_alpha`).
    pub alpha: bool,
    /// Whether some material has a specular (GGX) lobe (`SceneMaterials::uses_specular`).
    pub specular: bool,
    /// The extra vertex attributes the kernels read, `VERTEX_ATTRIBUTE_*` bits
    /// (`SceneMaterials::vertex_attributes`).
    pub vertex_attributes: u32,
    /// The texture slots the materials use (`scene_texture_slots`).
    pub texture_slots: u32,
    /// Whether the scene has an environment (`SceneLights::has_environment`).
    pub environment: bool,
    /// Whether light samples are taken of the environment
    /// (`SceneLights::samples_environment`).
    pub samples_environment: bool,
    /// Whether the scene has punctual lights.
    pub punctual_lights: bool,
    /// Whether some triangle emits.
    pub emissive_triangles: bool,
}

/// What the variant choice reads of the render's settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VariantSettings {
    /// Whether the render is guided (`RenderSettings::guiding`).
    pub guiding: bool,
    /// Whether the light selection is the light tree
    /// (`LightSelection::uses_tree` of the emissive triangles' count).
    pub light_tree: bool,
    /// Whether the camera has a thin lens (`Lens::is_pinhole` is false): `SPEC_THIN_LENS`;
    /// a pinhole's kernel compiles the lens out.
    pub thin_lens: bool,
}

/// Where the kernel's SPIR-V comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelSource {
    /// One of the builds embedded in the binary: the variant may take the few-triangle and
    /// the lean builds.
    Embedded,
    /// `glsl/path_tracer.comp` compiled at run time (e.g. with a user's functions by `vkpath
    /// check`), with the macros of the plain builds only.
    Given,
}

/// The chosen variant: the build and the scene's specialization constants, as (`SPEC_*` id,
/// value).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variant {
    /// The build of `PATH_TRACER`.
    pub build: Build,
    /// The light selection and, for the material kernels, what the scene has.
    pub specialization: Vec<(u32, u32)>,
}

/// What a build macro's rule reads.
struct Choice<'a> {
    scene: &'a SceneSummary,
    traversal: Traversal,
    /// The embedded builds may be taken (`KernelSource::Embedded`).
    embedded: bool,
    /// The render needs no light tree, guiding or environment map (`fits_lean_builds`).
    lean: bool,
}

/// One macro of the path tracer's builds and when a variant defines it.
struct BuildMacro {
    name: &'static str,
    /// Whether the macro belongs to the lean builds, which not every build has: the variant
    /// falls back to the build without them.
    lean: bool,
    wanted: fn(&Choice) -> bool,
}

/// The path tracer's build macros (`crate::kernels::builds`) and when each is defined.
const PATH_TRACER_MACROS: &[BuildMacro] = &[
    BuildMacro {
        name: USE_BVH,
        lean: false,
        wanted: |c| c.traversal.uses_bvh(),
    },
    BuildMacro {
        name: USE_RAY_QUERY,
        lean: false,
        wanted: |c| c.traversal == Traversal::RayQuery,
    },
    // The workshop kernels' constant triangles of a scene of at most
    // FEW_CONSTANT_TRIANGLE_CAPACITY triangles: the build that unrolls only that many.
    BuildMacro {
        name: FEW_CONSTANT_TRIANGLES,
        lean: false,
        wanted: |c| {
            c.embedded
                && c.traversal == Traversal::ConstantTriangles
                && !c.scene.materials
                && c.scene.triangle_count <= contract::FEW_CONSTANT_TRIANGLE_CAPACITY as usize
        },
    },
    BuildMacro {
        name: USE_MATERIALS,
        lean: false,
        wanted: |c| c.scene.materials,
    },
    // glTF materials without layered lobes: the same images, a faster start.
    BuildMacro {
        name: WITHOUT_LAYERS,
        lean: false,
        wanted: |c| c.scene.materials && !c.scene.layers,
    },
    BuildMacro {
        name: WITHOUT_LIGHT_TREE,
        lean: true,
        wanted: |c| c.embedded && c.lean,
    },
    BuildMacro {
        name: WITHOUT_GUIDING,
        lean: true,
        wanted: |c| c.embedded && c.lean,
    },
    BuildMacro {
        name: WITHOUT_ENVIRONMENT_MAP,
        lean: true,
        wanted: |c| c.embedded && c.lean && c.scene.materials,
    },
];

/// A specialization constant's id and its value for a scene.
type SceneFlag = (u32, fn(&SceneSummary) -> u32);

/// The scene's flags as specialization constants of the material kernels (what they compile
/// out where the scene lacks it).
const SCENE_FLAGS: &[SceneFlag] = &[
    (contract::SPEC_SCENE_HAS_ALPHA, |s| u32::from(s.alpha)),
    (contract::SPEC_SCENE_TEXTURE_SLOTS, |s| s.texture_slots),
    (contract::SPEC_SCENE_HAS_LAYERS, |s| u32::from(s.layers)),
    (contract::SPEC_SCENE_HAS_VOLUME_SCATTER, |s| {
        u32::from(s.volume_scatter)
    }),
    (contract::SPEC_SCENE_HAS_ENVIRONMENT, |s| {
        u32::from(s.environment)
    }),
    (contract::SPEC_SCENE_HAS_PUNCTUAL_LIGHTS, |s| {
        u32::from(s.punctual_lights)
    }),
    (contract::SPEC_SCENE_SAMPLES_ENVIRONMENT, |s| {
        u32::from(s.samples_environment)
    }),
    (contract::SPEC_SCENE_HAS_SPECULAR, |s| u32::from(s.specular)),
    (contract::SPEC_SCENE_VERTEX_ATTRIBUTES, |s| {
        s.vertex_attributes
    }),
    (contract::SPEC_SCENE_HAS_EMISSIVE_TRIANGLES, |s| {
        u32::from(s.emissive_triangles)
    }),
];

/// Whether a render can take the lean builds (`WITHOUT_LIGHT_TREE`, `WITHOUT_GUIDING`,
/// `WITHOUT_ENVIRONMENT_MAP`): no guiding, no light tree, no environment map to sample.
pub fn fits_lean_builds(scene: &SceneSummary, settings: &VariantSettings) -> bool {
    !settings.guiding && !settings.light_tree && !scene.samples_environment
}

/// The variant of the path tracer for `scene` rendered with `settings` by `traversal`, from
/// `source`: the build that the macro table picks (the lean build where the render fits it
/// and one exists, else the full one) and the scene's specialization constants.
pub fn path_tracer_variant(
    scene: &SceneSummary,
    settings: &VariantSettings,
    traversal: Traversal,
    source: KernelSource,
) -> Result<Variant> {
    let choice = Choice {
        scene,
        traversal,
        embedded: source == KernelSource::Embedded,
        lean: fits_lean_builds(scene, settings),
    };
    let wanted = |lean: bool| -> Vec<&str> {
        PATH_TRACER_MACROS
            .iter()
            .filter(|m| (lean || !m.lean) && (m.wanted)(&choice))
            .map(|m| m.name)
            .collect()
    };
    let full = PATH_TRACER.build_with(&wanted(false))?;
    let build = PATH_TRACER.build_with(&wanted(true)).unwrap_or(full);
    let mut specialization = vec![(
        contract::SPEC_LIGHT_SELECTION,
        if settings.light_tree {
            contract::LIGHT_SELECTION_TREE
        } else {
            contract::LIGHT_SELECTION_POWER
        },
    )];
    // The kernels' default is the pinhole
    if settings.thin_lens {
        specialization.push((contract::SPEC_THIN_LENS, 1));
    }
    // The kernels' default is the 4-wide tree
    if traversal == Traversal::CompressedBvh {
        specialization.push((contract::SPEC_BVH_LAYOUT, traversal.bvh_layout()));
    }
    if scene.materials {
        specialization.extend(SCENE_FLAGS.iter().map(|(id, value)| (*id, value(scene))));
    }
    Ok(Variant {
        build,
        specialization,
    })
}

/// The specialization constants that pass the triangles' positions into the kernel for
/// `Traversal::ConstantTriangles` (`glsl/constant_triangles.glsl`); none for the others.
pub fn constant_triangle_specialization(
    traversal: Traversal,
    triangles: &[Triangle],
) -> Vec<(u32, u32)> {
    if traversal != Traversal::ConstantTriangles {
        return Vec::new();
    }
    let mut constants = vec![(
        contract::SPEC_CONSTANT_TRIANGLE_COUNT,
        triangles.len() as u32,
    )];
    let coordinates = triangles
        .iter()
        .flat_map(|triangle| triangle.positions)
        .flat_map(|position| position.to_array());
    for (k, coordinate) in coordinates.enumerate() {
        constants.push((
            contract::SPEC_CONSTANT_TRIANGLES + k as u32,
            coordinate.to_bits(),
        ));
    }
    constants
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_scenes_without_alpha_compile_their_triangles_in() {
        let capacity = contract::CONSTANT_TRIANGLE_CAPACITY as usize;
        let material_capacity = contract::MATERIAL_CONSTANT_TRIANGLE_CAPACITY as usize;
        let choose = Traversal::choose;
        use Traversal::{Bvh, CompressedBvh, ConstantTriangles as Constant, Linear};
        // The workshop's kernels: up to 64 triangles compiled in; above, auto's BVH is the
        // compressed tree, --accel bvh the 4-wide one
        assert_eq!(choose(30, Accel::Auto, false, false), Constant);
        assert_eq!(choose(capacity, Accel::Auto, false, false), Constant);
        assert_eq!(choose(capacity + 1, Accel::None, false, false), Linear);
        assert_eq!(
            choose(capacity + 1, Accel::Auto, false, false),
            CompressedBvh
        );
        assert_eq!(choose(capacity + 1, Accel::Bvh, false, false), Bvh);
        assert_eq!(choose(12, Accel::Bvh, false, false), Bvh);
        // The material kernels: up to 16, and only without alpha
        assert_eq!(choose(12, Accel::Auto, true, false), Constant);
        assert_eq!(
            choose(material_capacity, Accel::Auto, true, false),
            Constant
        );
        assert_eq!(
            choose(material_capacity + 1, Accel::Auto, true, false),
            CompressedBvh
        );
        assert_eq!(
            choose(material_capacity + 1, Accel::None, true, false),
            Linear
        );
        assert_eq!(choose(12, Accel::Auto, true, true), CompressedBvh);
        assert_eq!(choose(12, Accel::None, true, true), Linear);
        assert_eq!(choose(12, Accel::Bvh, true, false), Bvh);
        // Hardware always takes the ray queries
        assert_eq!(
            choose(12, Accel::Hardware, false, false),
            Traversal::RayQuery
        );
    }

    #[test]
    fn auto_takes_ray_queries_where_it_would_take_the_bvh() {
        let gpu = TraversalContext {
            ray_queries: true,
            ..TraversalContext::default()
        };
        let on_device = |count, accel, materials, alpha, ray_queries: bool| {
            let on = TraversalContext { ray_queries, ..gpu };
            Traversal::choose_on_device(count, accel, materials, alpha, on)
        };
        let capacity = contract::CONSTANT_TRIANGLE_CAPACITY as usize;
        use Traversal::{Bvh, ConstantTriangles as Constant, Linear, RayQuery};
        // A device with ray queries: the BVH's scenes take them, the others keep their path
        assert_eq!(
            on_device(capacity + 1, Accel::Auto, false, false, true),
            RayQuery
        );
        assert_eq!(on_device(12, Accel::Auto, true, true, true), RayQuery);
        assert_eq!(on_device(30, Accel::Auto, false, false, true), Constant);
        assert_eq!(
            on_device(capacity + 1, Accel::None, false, false, true),
            Linear
        );
        assert_eq!(on_device(capacity + 1, Accel::Bvh, false, false, true), Bvh);
        assert_eq!(on_device(30, Accel::Hardware, false, false, true), RayQuery);
        // One without: the (compressed) BVH
        assert_eq!(
            on_device(capacity + 1, Accel::Auto, false, false, false),
            Traversal::CompressedBvh
        );
        assert_eq!(Traversal::RayQuery.accel_name(), "hardware");
        assert_eq!(Traversal::Bvh.accel_name(), "bvh");
        assert_eq!(Traversal::CompressedBvh.accel_name(), "bvh");
        assert_eq!(Constant.accel_name(), "none");
    }

    #[test]
    fn auto_leaves_a_cpu_devices_ray_queries_to_accel_hardware() {
        // Mesa 25's lavapipe: ray queries, on a CPU device (issue 58: 4x slower than the
        // compressed BVH)
        let lavapipe = TraversalContext {
            ray_queries: true,
            cpu: true,
            moving_geometry: false,
        };
        let capacity = contract::CONSTANT_TRIANGLE_CAPACITY as usize;
        for (count, materials, alpha) in [(capacity + 1, false, false), (12, true, true)] {
            let on = |accel| Traversal::choose_on_device(count, accel, materials, alpha, lavapipe);
            assert_eq!(on(Accel::Auto), Traversal::CompressedBvh, "{count}");
            assert_eq!(on(Accel::Hardware), Traversal::RayQuery, "{count}");
        }
    }

    #[test]
    fn a_sequence_whose_geometry_moves_takes_the_bvh_for_every_frame() {
        let moving = TraversalContext {
            moving_geometry: true,
            ..TraversalContext::default()
        };
        // A small mesh that the constant triangles would compile in, frame after frame
        for materials in [false, true] {
            let auto =
                |count| Traversal::choose_on_device(count, Accel::Auto, materials, false, moving);
            assert_eq!(auto(3), Traversal::CompressedBvh);
            assert_eq!(auto(12), Traversal::CompressedBvh);
            // still: the constant triangles
            let still = Traversal::choose_on_device(
                12,
                Accel::Auto,
                materials,
                false,
                TraversalContext::default(),
            );
            assert_eq!(still, Traversal::ConstantTriangles);
            // asked for: kept
            let none = Traversal::choose_on_device(12, Accel::None, materials, false, moving);
            assert_eq!(none, Traversal::ConstantTriangles);
        }
        // A hardware device's ray queries take the BVH's place
        let gpu = TraversalContext {
            ray_queries: true,
            ..moving
        };
        assert_eq!(
            Traversal::choose_on_device(12, Accel::Auto, true, false, gpu),
            Traversal::RayQuery
        );
    }

    /// The build a render of `triangles` triangles takes.
    fn build_name(
        traversal: Traversal,
        triangles: usize,
        materials: bool,
        layers: bool,
        settings: VariantSettings,
        source: KernelSource,
    ) -> &'static str {
        let scene = SceneSummary {
            triangle_count: triangles,
            materials,
            layers,
            ..SceneSummary::default()
        };
        path_tracer_variant(&scene, &settings, traversal, source)
            .unwrap()
            .build
            .name
    }

    #[test]
    fn the_macro_table_picks_every_build() {
        let few = contract::FEW_CONSTANT_TRIANGLE_CAPACITY as usize;
        let lean = VariantSettings::default();
        let guided = VariantSettings {
            guiding: true,
            ..lean
        };
        let tree = VariantSettings {
            light_tree: true,
            ..lean
        };
        use KernelSource::{Embedded, Given};
        use Traversal::{Bvh, ConstantTriangles as Constant, Linear, RayQuery};
        // (traversal, triangles, materials, layers, settings, source): the build
        let cases = [
            // The lean builds, where the render needs no light tree, guiding or map
            (
                (Constant, few, false, false, lean, Embedded),
                "path_tracer_few_triangles_lean",
            ),
            (
                (Bvh, 100, false, false, lean, Embedded),
                "path_tracer_bvh_lean",
            ),
            (
                (Constant, 12, true, false, lean, Embedded),
                "path_tracer_materials_lean",
            ),
            (
                (Linear, 100, true, false, lean, Embedded),
                "path_tracer_materials_lean",
            ),
            (
                (Bvh, 100, true, false, lean, Embedded),
                "path_tracer_materials_bvh_lean",
            ),
            (
                (RayQuery, 100, false, false, lean, Embedded),
                "path_tracer_ray_query_lean",
            ),
            (
                (RayQuery, 100, true, false, lean, Embedded),
                "path_tracer_materials_ray_query_lean",
            ),
            (
                (RayQuery, 100, false, false, guided, Embedded),
                "path_tracer_ray_query",
            ),
            (
                (RayQuery, 100, true, true, lean, Embedded),
                "path_tracer_materials_ray_query",
            ),
            (
                (RayQuery, 100, true, false, tree, Embedded),
                "path_tracer_materials_ray_query_without_layers",
            ),
            // ... and the full build where none is lean
            ((Linear, 100, false, false, lean, Embedded), "path_tracer"),
            (
                (Bvh, 100, true, true, lean, Embedded),
                "path_tracer_materials_bvh",
            ),
            // The few-triangle build, and the full ones without lean
            (
                (Constant, few, false, false, guided, Embedded),
                "path_tracer_few_triangles",
            ),
            (
                (Constant, few, false, false, tree, Embedded),
                "path_tracer_few_triangles",
            ),
            (
                (Constant, few + 1, false, false, guided, Embedded),
                "path_tracer",
            ),
            ((Linear, 12, false, false, guided, Embedded), "path_tracer"),
            (
                (Constant, 12, true, false, tree, Embedded),
                "path_tracer_materials_without_layers",
            ),
            (
                (Linear, 12, true, true, guided, Embedded),
                "path_tracer_materials",
            ),
            (
                (Bvh, 100, true, false, guided, Embedded),
                "path_tracer_materials_bvh_without_layers",
            ),
            (
                (Bvh, 100, false, false, guided, Embedded),
                "path_tracer_bvh",
            ),
            // A given kernel: the plain macros only
            ((Constant, few, false, false, lean, Given), "path_tracer"),
            ((Bvh, 100, false, false, lean, Given), "path_tracer_bvh"),
            (
                (Constant, 12, true, false, lean, Given),
                "path_tracer_materials_without_layers",
            ),
            (
                (Bvh, 100, true, true, lean, Given),
                "path_tracer_materials_bvh",
            ),
        ];
        for ((traversal, count, materials, layers, settings, source), expected) in cases {
            let picked = build_name(traversal, count, materials, layers, settings, source);
            assert_eq!(
                picked, expected,
                "{traversal:?}, {count} triangles, materials {materials}, layers {layers}, {settings:?}, {source:?}"
            );
        }
    }

    #[test]
    fn the_scene_flags_are_set_for_material_kernels_only() {
        let settings = VariantSettings {
            light_tree: true,
            ..VariantSettings::default()
        };
        let workshop = SceneSummary {
            triangle_count: 30,
            emissive_triangles: true,
            ..SceneSummary::default()
        };
        let variant =
            path_tracer_variant(&workshop, &settings, Traversal::Bvh, KernelSource::Embedded)
                .unwrap();
        assert_eq!(
            variant.specialization,
            [(
                contract::SPEC_LIGHT_SELECTION,
                contract::LIGHT_SELECTION_TREE
            )]
        );
        let gltf = SceneSummary {
            materials: true,
            alpha: true,
            texture_slots: 3,
            specular: true,
            ..workshop
        };
        let variant = path_tracer_variant(
            &gltf,
            &VariantSettings::default(),
            Traversal::Bvh,
            KernelSource::Embedded,
        )
        .unwrap();
        let value = |id| {
            variant
                .specialization
                .iter()
                .find(|(i, _)| *i == id)
                .map(|(_, v)| *v)
        };
        assert_eq!(
            value(contract::SPEC_LIGHT_SELECTION),
            Some(contract::LIGHT_SELECTION_POWER)
        );
        assert_eq!(value(contract::SPEC_SCENE_HAS_ALPHA), Some(1));
        assert_eq!(value(contract::SPEC_SCENE_TEXTURE_SLOTS), Some(3));
        assert_eq!(value(contract::SPEC_SCENE_HAS_SPECULAR), Some(1));
        assert_eq!(value(contract::SPEC_SCENE_HAS_LAYERS), Some(0));
        assert_eq!(value(contract::SPEC_SCENE_HAS_EMISSIVE_TRIANGLES), Some(1));
        assert_eq!(variant.specialization.len(), 1 + SCENE_FLAGS.len());
        // Every flag is a constant the path tracer declares
        for (id, _) in SCENE_FLAGS {
            assert!(PATH_TRACER.declares_spec_constant(*id), "{id}");
        }
    }

    #[test]
    fn the_compressed_bvh_takes_the_bvh_builds_with_its_layout() {
        for (triangles, materials, alpha) in [(12, false, false), (100, true, true)] {
            assert_eq!(
                Traversal::choose(triangles, Accel::CompressedBvh, materials, alpha),
                Traversal::CompressedBvh
            );
        }
        let scene = SceneSummary {
            triangle_count: 100,
            ..SceneSummary::default()
        };
        let settings = VariantSettings::default();
        let variant = |traversal| {
            path_tracer_variant(&scene, &settings, traversal, KernelSource::Embedded).unwrap()
        };
        let (wide, compressed) = (variant(Traversal::Bvh), variant(Traversal::CompressedBvh));
        assert_eq!(wide.build, compressed.build);
        let layout = |v: &Variant| {
            v.specialization
                .iter()
                .find(|(id, _)| *id == contract::SPEC_BVH_LAYOUT)
                .map(|(_, value)| *value)
        };
        // The 4-wide tree is the kernels' default
        assert_eq!(layout(&wide), None);
        assert_eq!(layout(&compressed), Some(contract::BVH_LAYOUT_COMPRESSED));
        assert!(Traversal::CompressedBvh.uses_bvh() && Traversal::Bvh.uses_bvh());
    }

    #[test]
    fn only_a_thin_lens_camera_specializes_the_lens_in() {
        let scene = SceneSummary {
            triangle_count: 30,
            ..SceneSummary::default()
        };
        let lens = |thin_lens| {
            let settings = VariantSettings {
                thin_lens,
                ..VariantSettings::default()
            };
            let variant =
                path_tracer_variant(&scene, &settings, Traversal::Bvh, KernelSource::Embedded)
                    .unwrap();
            variant
                .specialization
                .iter()
                .find(|(id, _)| *id == contract::SPEC_THIN_LENS)
                .map(|(_, value)| *value)
        };
        // The pinhole is the kernels' default: its specialization (and so a sequence's cached
        // pipeline) is what it was before the lens had a constant
        assert_eq!(lens(false), None);
        assert_eq!(lens(true), Some(1));
        assert!(PATH_TRACER.declares_spec_constant(contract::SPEC_THIN_LENS));
    }
}
