//! How the path tracer finds the triangle a ray hits: the workshop's loop compiled into the
//! kernel (small scenes), the loop over the triangle buffer, or a BVH.

use crate::contract;
use crate::error::Result;
use crate::kernels::builds::{
    FEW_CONSTANT_TRIANGLES, USE_BVH, USE_MATERIALS, WITHOUT_ENVIRONMENT_MAP, WITHOUT_GUIDING,
    WITHOUT_LAYERS, WITHOUT_LIGHT_TREE,
};
use crate::kernels::{Build, PATH_TRACER};
use crate::render::settings::Accel;
use crate::scene::{Scene, Triangle};

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
    pub fn choose(triangle_count: usize, accel: Accel, materials: bool, alpha: bool) -> Traversal {
        let constant = Traversal::constant_triangles_can_trace(triangle_count, materials, alpha);
        if accel.uses_bvh(triangle_count) {
            Traversal::Bvh
        } else if constant {
            Traversal::ConstantTriangles
        } else if accel == Accel::Auto && materials {
            Traversal::Bvh
        } else {
            Traversal::Linear
        }
    }

    /// `choose` for `scene`.
    pub fn for_scene(scene: &Scene, accel: Accel) -> Traversal {
        Traversal::choose(
            scene.triangles.len(),
            accel,
            scene.needs_material_kernels(),
            scene.uses_alpha(),
        )
    }

    /// A short name for reports: "constant triangles", "linear" or "BVH".
    pub fn name(self) -> &'static str {
        match self {
            Traversal::ConstantTriangles => "constant triangles",
            Traversal::Linear => "linear",
            Traversal::Bvh => "BVH",
        }
    }

    /// The build of the path tracer (`crate::kernels::PATH_TRACER`) for this traversal,
    /// with glTF materials (the glTF model of `glsl/surface.glsl`) or the workshop's diffuse
    /// triangles; with the layered lobes (`Scene::needs_layered_kernels`) or, for glTF
    /// materials without them, the build that leaves them out (`WITHOUT_LAYERS`: the same
    /// images, a faster start).
    pub fn build(self, materials: bool, layers: bool) -> Result<Build> {
        let mut macros = Vec::new();
        if self == Traversal::Bvh {
            macros.push(USE_BVH);
        }
        if materials {
            macros.push(USE_MATERIALS);
            if !layers {
                macros.push(WITHOUT_LAYERS);
            }
        }
        PATH_TRACER.build_with(&macros)
    }

    /// `build`, but for the workshop kernels' constant triangles of a scene of at most
    /// `FEW_CONSTANT_TRIANGLE_CAPACITY` triangles the build that unrolls only that many
    /// (`FEW_CONSTANT_TRIANGLES`), and where `lean` (the render needs no light tree, guiding
    /// or environment map: `crate::render::gpu_scene::fits_lean_builds`) the lean build of
    /// that build where there is one (`WITHOUT_LIGHT_TREE`): the same images, a shorter start.
    pub fn build_for(
        self,
        triangle_count: usize,
        materials: bool,
        layers: bool,
        lean: bool,
    ) -> Result<Build> {
        let few = triangle_count <= contract::FEW_CONSTANT_TRIANGLE_CAPACITY as usize;
        let full = if self == Traversal::ConstantTriangles && !materials && few {
            PATH_TRACER.build_with(&[FEW_CONSTANT_TRIANGLES])?
        } else {
            self.build(materials, layers)?
        };
        if !lean {
            return Ok(full);
        }
        let mut macros: Vec<&str> = full.macros.iter().map(|(name, _)| *name).collect();
        macros.extend([WITHOUT_LIGHT_TREE, WITHOUT_GUIDING]);
        if materials {
            macros.push(WITHOUT_ENVIRONMENT_MAP);
        }
        Ok(PATH_TRACER.build_with(&macros).unwrap_or(full))
    }
}

/// The specialization constants that pass the triangles' positions into the kernel for
/// `Traversal::ConstantTriangles` (`glsl/constant_triangles.glsl`); none for the others.
pub(crate) fn constant_triangle_specialization(
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
        use Traversal::{Bvh, ConstantTriangles as Constant, Linear};
        // The workshop's kernels: up to 64 triangles compiled in
        assert_eq!(choose(30, Accel::Auto, false, false), Constant);
        assert_eq!(choose(capacity, Accel::Auto, false, false), Constant);
        assert_eq!(choose(capacity + 1, Accel::None, false, false), Linear);
        assert_eq!(choose(capacity + 1, Accel::Auto, false, false), Bvh);
        assert_eq!(choose(12, Accel::Bvh, false, false), Bvh);
        // The material kernels: up to 16, and only without alpha
        assert_eq!(choose(12, Accel::Auto, true, false), Constant);
        assert_eq!(
            choose(material_capacity, Accel::Auto, true, false),
            Constant
        );
        assert_eq!(choose(material_capacity + 1, Accel::Auto, true, false), Bvh);
        assert_eq!(
            choose(material_capacity + 1, Accel::None, true, false),
            Linear
        );
        assert_eq!(choose(12, Accel::Auto, true, true), Bvh);
        assert_eq!(choose(12, Accel::None, true, true), Linear);
        assert_eq!(choose(12, Accel::Bvh, true, false), Bvh);
    }
}
