//! Scenes made from code: the furnace box for closed-form tests, and generated meshes.

use glam::Vec3;

use crate::camera::Camera;
use crate::scene::{Scene, Triangle};

/// The 12 triangles of the axis-aligned cube [-1, 1]^3, wound so that every normal points
/// inward, all with the same albedo and emission.
pub fn inward_cube(albedo: Vec3, emission: Vec3) -> Vec<Triangle> {
    let mut triangles = Vec::with_capacity(12);
    // For each face: the inward normal axis and sign; the face lies at -sign on that axis.
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let normal =
                Vec3::from_array(std::array::from_fn(|i| if i == axis { sign } else { 0.0 }));
            let (u_axis, v_axis) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |u: f32, v: f32| {
                let mut p = [0.0f32; 3];
                p[axis] = -sign;
                p[u_axis] = u;
                p[v_axis] = v;
                Vec3::from_array(p)
            };
            let quad = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            for [a, b, c] in [[0, 1, 2], [0, 2, 3]] {
                let mut positions = [quad[a], quad[b], quad[c]];
                let winding = (positions[1] - positions[0]).cross(positions[2] - positions[0]);
                if winding.dot(normal) < 0.0 {
                    positions.swap(1, 2);
                }
                triangles.push(
                    Triangle::new(positions, albedo, emission, false)
                        .expect("cube faces are not degenerate"),
                );
            }
        }
    }
    triangles
}

/// The furnace: a camera at the centre of a closed cube whose inward-facing walls all have
/// albedo `albedo` and emission `emission`. Every path hits a wall at every step, so the
/// expected radiance of every pixel is emission * (1 - a^n) / (1 - a) for maximum path
/// length n (with a uniform albedo a).
pub fn furnace(albedo: f32, emission: f32) -> Scene {
    Scene {
        triangles: inward_cube(Vec3::splat(albedo), Vec3::splat(emission)),
        camera: Some(Camera::look_at(
            Vec3::new(0.1, -0.2, 0.05),
            Vec3::new(1.0, 0.3, 0.2),
            Vec3::Z,
            1.2,
        )),
        warnings: Vec::new(),
        materials: None,
        punctual_lights: Vec::new(),
        environment: None,
        cameras: Vec::new(),
        mesh_instances: Vec::new(),
        motion: None,
    }
}

/// The furnace's closed form: emission * sum_{j<n} a^j.
pub fn furnace_radiance(albedo: f64, emission: f64, max_path_length: u32) -> f64 {
    if albedo == 1.0 {
        return emission * f64::from(max_path_length);
    }
    emission * (1.0 - albedo.powi(max_path_length as i32)) / (1.0 - albedo)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_normals_point_inward() {
        for triangle in inward_cube(Vec3::ONE, Vec3::ZERO) {
            let centroid =
                (triangle.positions[0] + triangle.positions[1] + triangle.positions[2]) / 3.0;
            assert!(triangle.normal.dot(-centroid) > 0.0, "{triangle:?}");
        }
    }

    #[test]
    fn closed_form_sums_the_geometric_series() {
        assert!((furnace_radiance(0.5, 1.0, 3) - 1.75).abs() < 1e-12);
        assert_eq!(furnace_radiance(1.0, 2.0, 4), 8.0);
    }
}
