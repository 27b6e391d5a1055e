//! Rust twins of the pure functions of `glsl/materials.glsl`: barycentric coordinates of a
//! hit and normal mapping. (The rest of that file reads texel buffers; its results are
//! compared with these through renders, `tests/materials_render.rs`.)

use glam::{Vec3, Vec4};

use crate::scene::Triangle;

/// Twin of `get_barycentrics`: (b_0, b_1, b_2) of a point in a triangle's plane.
pub fn get_barycentrics(position: Vec3, triangle: &Triangle) -> Vec3 {
    let edge_1 = triangle.positions[1] - triangle.positions[0];
    let edge_2 = triangle.positions[2] - triangle.positions[0];
    let offset = position - triangle.positions[0];
    let normal = edge_1.cross(edge_2);
    let inverse_squared_area = 1.0 / normal.dot(normal);
    let b_1 = offset.cross(edge_2).dot(normal) * inverse_squared_area;
    let b_2 = edge_1.cross(offset).dot(normal) * inverse_squared_area;
    Vec3::new(1.0 - b_1 - b_2, b_1, b_2)
}

/// Twin of `apply_normal_map`: a normal perturbed by a tangent-space normal map texel.
pub fn apply_normal_map(normal: Vec3, tangent: Vec4, texel: Vec3, scale: f32) -> Vec3 {
    let mut orthogonal = tangent.truncate() - tangent.truncate().dot(normal) * normal;
    if !(orthogonal.dot(orthogonal) > 1.0e-12) {
        return normal;
    }
    orthogonal = orthogonal.normalize();
    let sign = if tangent.w < 0.0 { -1.0 } else { 1.0 };
    let bitangent = normal.cross(orthogonal) * sign;
    let direction = 2.0 * texel - Vec3::ONE;
    let mapped =
        direction.x * scale * orthogonal + direction.y * scale * bitangent + direction.z * normal;
    if mapped.dot(mapped) > 1.0e-12 {
        mapped.normalize()
    } else {
        normal
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_texel_keeps_the_normal_and_a_tilted_one_tilts_towards_the_tangent() {
        let tangent = Vec4::new(1.0, 0.0, 0.2, 1.0);
        let flat = apply_normal_map(Vec3::Z, tangent, Vec3::new(0.5, 0.5, 1.0), 1.0);
        assert!((flat - Vec3::Z).length() < 1e-6);
        // (1, 0.5, 1) -> direction (1, 0, 1): 45 degrees towards +x.
        let tilted = apply_normal_map(Vec3::Z, tangent, Vec3::new(1.0, 0.5, 1.0), 1.0);
        assert!((tilted - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6);
        // Green up is the bitangent cross(N, T) w = +y; w = -1 flips it.
        let up = apply_normal_map(Vec3::Z, tangent, Vec3::new(0.5, 1.0, 1.0), 1.0);
        assert!(up.y > 0.7);
        let down = apply_normal_map(
            Vec3::Z,
            Vec4::new(1.0, 0.0, 0.0, -1.0),
            Vec3::new(0.5, 1.0, 1.0),
            1.0,
        );
        assert!(down.y < -0.7);
        // A tangent along the normal has no frame: the normal stays.
        assert_eq!(
            apply_normal_map(Vec3::Z, Vec4::new(0.0, 0.0, 1.0, 1.0), Vec3::ONE, 1.0),
            Vec3::Z
        );
    }

    #[test]
    fn barycentrics_of_the_corners_and_the_centroid() {
        let triangle =
            Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], Vec3::ONE, Vec3::ZERO, false).unwrap();
        assert_eq!(
            get_barycentrics(Vec3::X, &triangle),
            Vec3::new(0.0, 1.0, 0.0)
        );
        let centroid = get_barycentrics(Vec3::new(1.0 / 3.0, 1.0 / 3.0, 0.0), &triangle);
        assert!((centroid - Vec3::splat(1.0 / 3.0)).length() < 1e-6);
    }
}
