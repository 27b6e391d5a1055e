//! Generated meshes for scale tests: an icosphere, a displaced grid, and a Cornell box that
//! holds both, sized to a requested triangle count (10^4 to 10^6 and beyond).

use glam::Vec3;

use crate::scene::{Scene, SceneError, Triangle};

/// The 12 vertices of the regular icosahedron: cyclic permutations of (0, ±1, ±phi), before
/// normalization.
fn icosahedron_vertices() -> [Vec3; 12] {
    let phi = (1.0 + 5.0f32.sqrt()) / 2.0;
    [
        Vec3::new(-1.0, phi, 0.0),
        Vec3::new(1.0, phi, 0.0),
        Vec3::new(-1.0, -phi, 0.0),
        Vec3::new(1.0, -phi, 0.0),
        Vec3::new(0.0, -1.0, phi),
        Vec3::new(0.0, 1.0, phi),
        Vec3::new(0.0, -1.0, -phi),
        Vec3::new(0.0, 1.0, -phi),
        Vec3::new(phi, 0.0, -1.0),
        Vec3::new(phi, 0.0, 1.0),
        Vec3::new(-phi, 0.0, -1.0),
        Vec3::new(-phi, 0.0, 1.0),
    ]
}

/// The 20 faces of the icosahedron, counter-clockwise seen from outside.
const ICOSAHEDRON_FACES: [[usize; 3]; 20] = [
    [0, 11, 5],
    [0, 5, 1],
    [0, 1, 7],
    [0, 7, 10],
    [0, 10, 11],
    [1, 5, 9],
    [5, 11, 4],
    [11, 10, 2],
    [10, 7, 6],
    [7, 1, 8],
    [3, 9, 4],
    [3, 4, 2],
    [3, 2, 6],
    [3, 6, 8],
    [3, 8, 9],
    [4, 9, 5],
    [2, 4, 11],
    [6, 2, 10],
    [8, 6, 7],
    [9, 8, 1],
];

/// Triangles of `subdivided_sphere` for a subdivision level.
pub fn subdivided_sphere_triangle_count(subdivisions: u32) -> usize {
    20usize.saturating_mul(4usize.saturating_pow(subdivisions))
}

/// An icosphere: the icosahedron with each triangle split into four `subdivisions` times,
/// the vertices pushed onto the sphere. 20 * 4^subdivisions triangles (n = 7: 327 680;
/// n = 10: 21 M, about 2 GB on the GPU), watertight (an edge's midpoint is computed the same
/// way from both sides), counter-clockwise seen from outside so that normals point outwards.
/// \param centre, radius The sphere, world space
/// \param albedo, emission The workshop's material of every triangle (single-sided emission)
/// \return The triangles; degenerate ones, which f32 only produces far beyond n = 10, are
///         dropped
pub fn subdivided_sphere(
    subdivisions: u32,
    centre: Vec3,
    radius: f32,
    albedo: Vec3,
    emission: Vec3,
) -> Vec<Triangle> {
    let vertices = icosahedron_vertices().map(Vec3::normalize);
    let mut faces: Vec<[Vec3; 3]> = ICOSAHEDRON_FACES
        .iter()
        .map(|face| face.map(|i| vertices[i]))
        .collect();
    for _ in 0..subdivisions {
        let mut finer = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            // a + b == b + a in floating point, so neighbours share their midpoints exactly
            let ab = (a + b).normalize();
            let bc = (b + c).normalize();
            let ca = (c + a).normalize();
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = finer;
    }
    faces
        .into_iter()
        .filter_map(|face| {
            Triangle::new(face.map(|p| centre + radius * p), albedo, emission, false)
        })
        .collect()
}

/// The displacement of `displaced_grid`, a smooth function of the grid coordinates
/// (s, t) in [0, 1]^2 with values in [-1, 1]: two crossed waves plus a long diagonal swell,
/// 0.6 sin(6 pi s) sin(4 pi t) + 0.4 cos(2 pi (s - t)).
pub fn grid_displacement(s: f32, t: f32) -> f32 {
    use std::f32::consts::PI;
    0.6 * (6.0 * PI * s).sin() * (4.0 * PI * t).sin() + 0.4 * (2.0 * PI * (s - t)).cos()
}

/// A heightfield: a `resolution` x `resolution` grid of quads over the parallelogram
/// `corner + s * edge_s + t * edge_t`, (s, t) in [0, 1]^2, each vertex moved by
/// `amplitude * grid_displacement(s, t)` along the unit normal `edge_s x edge_t`, each quad
/// split into two triangles: 2 * resolution^2 triangles, counter-clockwise seen from the
/// side the normal points to.
/// \param corner, edge_s, edge_t The undisplaced grid, world space (edges not parallel)
/// \param amplitude The largest displacement, world-space length
/// \param albedo The workshop's albedo of every triangle (no emission)
/// \return The triangles; degenerate ones (e.g. from parallel edges) are dropped
pub fn displaced_grid(
    resolution: u32,
    corner: Vec3,
    edge_s: Vec3,
    edge_t: Vec3,
    amplitude: f32,
    albedo: Vec3,
) -> Vec<Triangle> {
    let normal = edge_s.cross(edge_t).normalize_or_zero();
    let n = resolution as usize;
    let vertex = |i: usize, j: usize| {
        let s = i as f32 / resolution as f32;
        let t = j as f32 / resolution as f32;
        corner + s * edge_s + t * edge_t + amplitude * grid_displacement(s, t) * normal
    };
    // One row of vertices at a time, so each vertex is computed once per row pair.
    let row = |j: usize| (0..=n).map(|i| vertex(i, j)).collect::<Vec<_>>();
    let mut triangles = Vec::with_capacity(2 * n * n);
    let mut lower = row(0);
    for j in 0..n {
        let upper = row(j + 1);
        for i in 0..n {
            let (p00, p10, p01, p11) = (lower[i], lower[i + 1], upper[i], upper[i + 1]);
            for positions in [[p00, p10, p11], [p00, p11, p01]] {
                triangles.extend(Triangle::new(positions, albedo, Vec3::ZERO, false));
            }
        }
        lower = upper;
    }
    triangles
}

/// A scene of about `target_triangles` triangles for scale tests: the workshop's Cornell box
/// (its 30 triangles, ceiling light and camera) holding an icosphere on the floor and a
/// displaced grid in front of the back wall. The sphere takes the largest subdivision level
/// with at most half of the budget, the grid the rest; the total is within 1% of the target
/// for targets from 10^4 up (at least 30 + 20 + 2 triangles for tiny targets).
pub fn scale_test_scene(target_triangles: usize) -> Result<Scene, SceneError> {
    let mut scene = Scene::builtin_cornell_box()?;
    let budget = target_triangles.saturating_sub(scene.triangles.len());
    let mut subdivisions = 0;
    while subdivided_sphere_triangle_count(subdivisions + 1) <= budget / 2 {
        subdivisions += 1;
    }
    // The box spans x in [0, 0.556], y in [-0.559, 0] (open towards the camera at y > 0),
    // z in [0, 0.549] (z up). The sphere rests on the floor in front of the tall block.
    let sphere = subdivided_sphere(
        subdivisions,
        Vec3::new(0.42, -0.12, 0.09),
        0.09,
        Vec3::new(0.8, 0.8, 0.8),
        Vec3::ZERO,
    );
    let grid_budget = budget.saturating_sub(sphere.len());
    let resolution = ((grid_budget as f64 / 2.0).sqrt().round() as u32).max(1);
    // A relief on the back wall (y = -0.559), facing the camera (+y = z x x).
    let grid = displaced_grid(
        resolution,
        Vec3::new(0.02, -0.53, 0.02),
        Vec3::new(0.0, 0.0, 0.5),
        Vec3::new(0.516, 0.0, 0.0),
        0.02,
        Vec3::new(0.6, 0.7, 0.8),
    );
    scene.triangles.extend(sphere);
    scene.triangles.extend(grid);
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_has_20_times_4_to_the_n_outward_triangles_on_the_sphere() {
        let centre = Vec3::new(1.0, 2.0, 3.0);
        for subdivisions in 0..4 {
            let sphere = subdivided_sphere(subdivisions, centre, 2.0, Vec3::ONE, Vec3::ZERO);
            assert_eq!(sphere.len(), subdivided_sphere_triangle_count(subdivisions));
            for triangle in &sphere {
                let middle =
                    (triangle.positions[0] + triangle.positions[1] + triangle.positions[2]) / 3.0;
                assert!(
                    triangle.normal.dot(middle - centre) > 0.0,
                    "normals point outwards"
                );
                for p in triangle.positions {
                    // f32 normalize is exact to a few ulps of the radius
                    assert!(((p - centre).length() - 2.0).abs() < 1e-5);
                }
            }
        }
    }

    #[test]
    fn icosphere_is_watertight() {
        // Every edge appears exactly twice, once in each direction, with bit-identical
        // endpoints.
        let sphere = subdivided_sphere(3, Vec3::ZERO, 1.0, Vec3::ONE, Vec3::ZERO);
        let key = |p: Vec3| p.to_array().map(f32::to_bits);
        let mut edges = std::collections::HashMap::new();
        for triangle in &sphere {
            for k in 0..3 {
                let edge = (
                    key(triangle.positions[k]),
                    key(triangle.positions[(k + 1) % 3]),
                );
                *edges.entry(edge).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "directed edge used once");
            assert_eq!(edges.get(&(b, a)), Some(&1), "and its reverse once");
        }
    }

    #[test]
    fn displaced_grid_has_two_triangles_per_quad_facing_the_normal() {
        let grid = displaced_grid(10, Vec3::ZERO, Vec3::X, Vec3::Y, 0.05, Vec3::ONE);
        assert_eq!(grid.len(), 200);
        for triangle in &grid {
            // The displacement's slope is at most 0.05 * 2 pi * (0.6 * 6 + 0.4 * 2) < 1.4,
            // but on a 10 x 10 grid a triangle's normal still leans less than 90 degrees.
            assert!(triangle.normal.z > 0.0);
            for p in triangle.positions {
                assert!((p.z - 0.05 * grid_displacement(p.x, p.y)).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn scale_test_scenes_reach_their_target_within_one_percent() {
        for target in [10_000usize, 100_000] {
            let scene = scale_test_scene(target).unwrap();
            let count = scene.triangles.len();
            assert!(
                count.abs_diff(target) * 100 <= target,
                "{count} triangles for a target of {target}"
            );
            assert!(scene.camera.is_some());
            assert!(scene
                .triangles
                .iter()
                .any(|t| t.emission.max_element() > 0.0));
        }
    }
}
