//! The path tracer's whole specialization, assembled in one place from its parts: the
//! render settings' constants (`RenderSettings::specialization`, passed in: the kernels
//! import nothing from `render/`), the constant triangles' (`constant_triangle_specialization`),
//! the variant room's (`path_tracer_variant`), the loop budget's (`crate::kernels::loops`)
//! and path guiding's mode. The renderer and `examples/kernel_statistics.rs` both take it.

use crate::contract;
use crate::kernels::loops::LoopCoefficients;
use crate::kernels::variant::{constant_triangle_specialization, Traversal, Variant};
use crate::scene::Triangle;

/// What the path tracer's specialization is made of, but path guiding's mode (which a
/// guided render's training pipeline sets apart: `path_tracer_specialization`).
#[derive(Clone, Copy, Debug)]
pub struct SpecializationParts<'a> {
    /// The render settings' constants (`RenderSettings::specialization`: samples per frame,
    /// path length, pixel filter, integrator, Russian roulette, sampler, light sampling).
    pub settings: &'a [(u32, u32)],
    /// How rays find hits: `Traversal::ConstantTriangles` passes `triangles` as constants.
    pub traversal: Traversal,
    /// The scene's triangles.
    pub triangles: &'a [Triangle],
    /// The variant room's choice for the scene.
    pub variant: &'a Variant,
    /// The device's loop limit (`SPEC_LOOP_LIMIT`: iterations per invocation on lavapipe, 0
    /// for none, as on GPUs).
    pub loop_limit: u32,
    /// The coefficients of the kernel's loop bound (`LoopCoefficients::path_tracer`).
    pub loops: LoopCoefficients,
}

/// The path tracer's specialization constants (`SPEC_*` id, value) of `parts` with path
/// guiding's mode `guiding` (`SPEC_GUIDING`: `GUIDING_OFF`, `GUIDING_ON` or
/// `GUIDING_TRAINING`), in this order: settings, constant triangles, variant, loop limit,
/// loop coefficients, guiding.
pub fn path_tracer_specialization(parts: &SpecializationParts, guiding: u32) -> Vec<(u32, u32)> {
    let mut specialization = parts.settings.to_vec();
    specialization.extend(constant_triangle_specialization(
        parts.traversal,
        parts.triangles,
    ));
    specialization.extend_from_slice(&parts.variant.specialization);
    specialization.push((contract::SPEC_LOOP_LIMIT, parts.loop_limit));
    specialization.extend_from_slice(&parts.loops.specialization());
    specialization.push((contract::SPEC_GUIDING, guiding));
    specialization
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::PATH_TRACER;
    use glam::Vec3;

    #[test]
    fn every_part_is_passed_once_in_order() {
        let triangle =
            Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], Vec3::ONE, Vec3::ZERO, false).unwrap();
        let variant = Variant {
            build: PATH_TRACER.builds()[0],
            specialization: vec![(900, 9)],
        };
        let loops = LoopCoefficients::path_tracer(Traversal::ConstantTriangles, false, false);
        let parts = SpecializationParts {
            settings: &[(800, 8)],
            traversal: Traversal::ConstantTriangles,
            triangles: &[triangle],
            variant: &variant,
            loop_limit: 7,
            loops,
        };
        let all = path_tracer_specialization(&parts, contract::GUIDING_TRAINING);
        let constant_triangles =
            constant_triangle_specialization(Traversal::ConstantTriangles, &[triangle]);
        let mut expected = vec![(800, 8)];
        expected.extend(constant_triangles);
        expected.push((900, 9));
        expected.push((contract::SPEC_LOOP_LIMIT, 7));
        expected.extend(loops.specialization());
        expected.push((contract::SPEC_GUIDING, contract::GUIDING_TRAINING));
        assert_eq!(all, expected);
        // Another traversal passes no triangles.
        let bvh = SpecializationParts {
            traversal: Traversal::Bvh,
            ..parts
        };
        assert_eq!(
            path_tracer_specialization(&bvh, contract::GUIDING_OFF).len(),
            1 + 1 + 1 + 4 + 1
        );
    }
}
