//! How the path tracer finds the triangle a ray hits: the workshop's loop compiled into the
//! kernel (small scenes), the loop over the triangle buffer, or a BVH.

use crate::contract;
use crate::error::Result;
use crate::kernels::builds::{USE_BVH, USE_MATERIALS, WITHOUT_LAYERS};
use crate::kernels::{Build, PATH_TRACER};
use crate::render::settings::Accel;
use crate::scene::Triangle;

/// How the kernel finds the triangle a ray hits. The triangles' data are read from a texel
/// buffer (RGBA32_UINT, `TRIANGLE_TEXEL_COUNT` texels per triangle): on lavapipe a texel fetch
/// at a per-lane index is a vector gather, faster than uniform- or storage-buffer loads
/// (docs/performance.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Traversal {
    /// The workshop's loop over all triangles, compiled into the kernel: their positions are
    /// specialization constants (`glsl/constant_triangles.glsl`), so a ray reads no memory
    /// per triangle. For scenes of at most `CONSTANT_TRIANGLE_CAPACITY` triangles.
    ConstantTriangles,
    /// The workshop's loop over all triangles, read from the texel buffer
    /// (`glsl/path_tracer.comp`).
    Linear,
    /// A BVH, with the triangles in its leaf order (`path_tracer.comp` with `USE_BVH`).
    Bvh,
}

impl Traversal {
    /// What `accel` asks for, for a scene of `triangle_count` triangles traced by the
    /// workshop's kernels (`materials` false) or the glTF-material kernels (true).
    ///
    /// The workshop's kernels compile the loop over all triangles in whenever they fit. The
    /// material kernels take a BVH under `Accel::Auto` however small the scene: their kernel
    /// without one holds the unrolled loop at every intersection call site, which llvmpipe
    /// inlines before it folds the loop away, so building it takes 20-30 times longer (about
    /// 19 s against 0.5-0.6 s on 2 busy cores, for the constant loop and the texel loop
    /// alike), on every run since lavapipe keeps no pipeline cache; that costs more than the
    /// BVH's slower samples save below millions of samples (docs/performance.md, `cargo
    /// bench --bench startup`). `Accel::None` keeps the loop compiled in there too.
    pub fn choose(triangle_count: usize, accel: Accel, materials: bool) -> Traversal {
        let fits = triangle_count <= contract::CONSTANT_TRIANGLE_CAPACITY as usize;
        if accel.uses_bvh(triangle_count) || (accel == Accel::Auto && materials) {
            Traversal::Bvh
        } else if fits {
            Traversal::ConstantTriangles
        } else {
            Traversal::Linear
        }
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
    /// triangles; with the layered lobes (`Scene::needs_layered_kernels`) or, where the BVH
    /// traces glTF materials without them, the build that leaves them out (`WITHOUT_LAYERS`:
    /// the same images, a faster start). The other material build keeps them whatever the
    /// scene, one build fewer to compile for `--accel none`.
    pub fn build(self, materials: bool, layers: bool) -> Result<Build> {
        let mut macros = Vec::new();
        if self == Traversal::Bvh {
            macros.push(USE_BVH);
        }
        if materials {
            macros.push(USE_MATERIALS);
            if self == Traversal::Bvh && !layers {
                macros.push(WITHOUT_LAYERS);
            }
        }
        PATH_TRACER.build_with(&macros)
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
    fn small_scenes_compile_their_triangles_in_only_for_the_workshop_kernels() {
        let capacity = contract::CONSTANT_TRIANGLE_CAPACITY as usize;
        let choose = Traversal::choose;
        assert_eq!(choose(30, Accel::Auto, false), Traversal::ConstantTriangles);
        assert_eq!(choose(30, Accel::Auto, true), Traversal::Bvh);
        assert_eq!(choose(30, Accel::None, true), Traversal::ConstantTriangles);
        assert_eq!(choose(capacity + 1, Accel::None, false), Traversal::Linear);
        assert_eq!(choose(capacity + 1, Accel::Auto, false), Traversal::Bvh);
        assert_eq!(choose(12, Accel::Bvh, false), Traversal::Bvh);
    }
}
