//! Rust twin of `glsl/shading_basis.glsl`: the one orthonormal frame around a normal that the
//! BSDFs (`crate::cpu::brdf`, `crate::cpu::layered_bsdf`) and the cosine sampler
//! (`crate::cpu::importance_sampling::sample_hemisphere_cosine`) work in.

use glam::{Mat3, Vec3};

/// Twin of `get_shading_basis`: columns tangent, bitangent, normal around a unit normal
/// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1)).
pub fn get_shading_basis(normal: Vec3) -> Mat3 {
    // sign_z keeps a = -1 / (sign_z + n_z) away from a division by zero at n_z = -1.
    let sign_z = if normal.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign_z + normal.z);
    let b = normal.x * normal.y * a;
    let tangent = Vec3::new(
        1.0 + sign_z * normal.x * normal.x * a,
        sign_z * b,
        -sign_z * normal.x,
    );
    let bitangent = Vec3::new(b, sign_z + normal.y * normal.y * a, -normal.y);
    Mat3::from_cols(tangent, bitangent, normal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::importance_sampling::sample_hemisphere_cosine;
    use crate::cpu::workshop::M_PI;
    use glam::Vec2;

    /// Unit normals all over the sphere, the poles and the seam at n_z = 0 included.
    fn normals() -> Vec<Vec3> {
        let mut normals = vec![Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::Y];
        for i in 0..64 {
            let z = -1.0 + 2.0 * (i as f32 + 0.5) / 64.0;
            let phi = 2.399_963 * i as f32;
            let r = (1.0 - z * z).sqrt();
            normals.push(Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize());
        }
        normals
    }

    #[test]
    fn the_basis_is_orthonormal_right_handed_and_ends_in_the_normal() {
        // Duff et al. report errors of a few ulps; 1e-6 is about 8 ulps of one.
        for normal in normals() {
            let basis = get_shading_basis(normal);
            assert_eq!(basis.z_axis, normal);
            for (u, v) in [(0, 1), (1, 2), (0, 2)] {
                assert!(basis.col(u).dot(basis.col(v)).abs() < 1e-6, "{normal}");
            }
            for k in 0..3 {
                assert!((basis.col(k).length() - 1.0).abs() < 1e-6, "{normal}");
            }
            assert!((basis.x_axis.cross(basis.y_axis) - normal).length() < 1e-6);
        }
    }

    #[test]
    fn the_cosine_sampler_works_in_the_shading_basis() {
        // sample_hemisphere_cosine() is Malley's disk point lifted in this very basis, bit
        // for bit (the same products and sums in the same order).
        for normal in normals() {
            let basis = get_shading_basis(normal);
            for random in [Vec2::new(0.3, 0.7), Vec2::new(0.9, 0.1), Vec2::ZERO] {
                let radius = random[0].sqrt();
                let phi = 2.0 * M_PI * random[1];
                let (x, y) = (radius * phi.cos(), radius * phi.sin());
                let z = (1.0 - random[0]).max(0.0).sqrt();
                let expected = x * basis.x_axis + y * basis.y_axis + z * basis.z_axis;
                assert_eq!(sample_hemisphere_cosine(random, normal), expected);
            }
        }
    }
}
