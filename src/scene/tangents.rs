//! Tangents for normal mapping where a file has none: MikkTSpace (the `mikktspace` crate),
//! the tangent space that glTF's normal maps are baked in (glTF 2.0, 3.7.2.1: "When tangents
//! are not specified, client implementations SHOULD calculate tangents using default
//! MikkTSpace algorithms with the specified vertex positions, normals, and texture
//! coordinates").

use glam::{Vec2, Vec3, Vec4};

/// A triangle list with per-corner attributes, as MikkTSpace reads and writes it.
struct Corners<'a> {
    positions: &'a [[Vec3; 3]],
    normals: &'a [[Vec3; 3]],
    tex_coords: &'a [[Vec2; 3]],
    tangents: Vec<[Vec4; 3]>,
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.positions.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[face][vert].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[face][vert].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        // glTF's v runs down the image while a normal map's +Y (green) points up it, as in
        // OpenGL's and Blender's texture space, where MikkTSpace's bitangent follows +v: the
        // algorithm sees v flipped, so that B = cross(N, T) w points to the image's top.
        let uv = self.tex_coords[face][vert];
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.tangents[face][vert] = Vec4::from(tangent);
    }
}

/// MikkTSpace tangents (xyz) with bitangent signs (w) for each corner of each triangle, in
/// the space of the inputs; `None` when the algorithm fails (no triangles). Corners whose
/// texture coordinates are degenerate get whatever MikkTSpace makes of them (it falls back
/// to a tangent perpendicular to the normal).
pub fn generate_tangents(
    positions: &[[Vec3; 3]],
    normals: &[[Vec3; 3]],
    tex_coords: &[[Vec2; 3]],
) -> Option<Vec<[Vec4; 3]>> {
    let mut corners = Corners {
        positions,
        normals,
        tex_coords,
        tangents: vec![[Vec4::ZERO; 3]; positions.len()],
    };
    mikktspace::generate_tangents(&mut corners).then_some(corners.tangents)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_mapped_along_x_gets_tangent_x() {
        // The unit quad in the x-y plane with u along +x and v along -y (glTF's v runs down
        // the image, so the image's top is +y): the tangent is +x and the bitangent, the
        // direction a normal map's green channel points, is +y = (n x t) w with w = +1.
        let positions = [
            [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)],
            [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
        ];
        let normals = [[Vec3::Z; 3]; 2];
        let tex_coords = [
            [
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(1.0, 0.0),
            ],
            [
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(0.0, 0.0),
            ],
        ];
        let tangents = generate_tangents(&positions, &normals, &tex_coords).unwrap();
        for corner in tangents.iter().flatten() {
            assert!((corner.truncate() - Vec3::X).length() < 1e-5, "{corner}");
            let bitangent = Vec3::Z.cross(corner.truncate()) * corner.w;
            assert!((bitangent - Vec3::Y).length() < 1e-5, "{corner}");
        }
    }
}
