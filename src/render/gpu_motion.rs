//! Motion blur on the device: the keys of a `SceneMotion` as the kernels read them after the
//! triangles at `BINDING_TRIANGLES` (`glsl/shared.h`: `MOTION_TRIANGLE_TEXEL_COUNT` texels per
//! triangle and key, triangle-major, then `MOTION_CAMERA_TEXEL_COUNT` per key's camera), read by
//! `get_packed_triangle()` and `get_camera_at_time()` of `glsl/scene.glsl`.

use crate::bvh::Aabb;
use crate::contract;
use crate::render::gpu_types::RenderUniforms;
use crate::scene::motion::SceneMotion;

/// The texels (RGBA32, as float bits) of `motion`'s keys, the triangles in `order` (the
/// BVH's leaf order: `order[i]` is the scene's index of stored triangle i; `None`: the
/// scene's order), the cameras' image planes at `aspect` (width / height) with their lens in
/// the w components as `RenderUniforms` holds them.
pub fn motion_texels(motion: &SceneMotion, order: Option<&[u32]>, aspect: f32) -> Vec<[f32; 4]> {
    let count = motion.triangles.first().map_or(0, Vec::len);
    let mut texels = Vec::with_capacity(
        contract::MOTION_TRIANGLE_TEXEL_COUNT as usize * count * motion.triangles.len()
            + contract::MOTION_CAMERA_TEXEL_COUNT as usize * motion.cameras.len(),
    );
    // Triangle-major: the two keys a ray's time lerps are neighbours in memory
    for stored in 0..count {
        let index = order.map_or(stored, |order| order[stored] as usize);
        for key in &motion.triangles {
            let triangle = &key[index];
            let [a, b, c] = triangle.positions.map(|p| p.extend(0.0).to_array());
            texels.extend([a, b, c, triangle.normal.extend(0.0).to_array()]);
        }
    }
    for camera in &motion.cameras {
        // The uniforms' camera vectors, lens included (size, count and seed unused here)
        let uniforms = RenderUniforms::new(&camera.image_plane(aspect), 0, 0, 0, 0);
        texels.extend([
            uniforms.camera_position,
            uniforms.left_bottom,
            uniforms.right,
            uniforms.up,
        ]);
    }
    texels
}

/// Each triangle's box at each of `motion`'s keys (`[k][i]`: triangle i of the scene's order
/// at key k): motion blur's tree is built over these (`MotionBvh::build`), its nodes holding
/// a box per key that the kernels lerp at a ray's time.
pub fn motion_key_boxes(motion: &SceneMotion) -> Vec<Vec<Aabb>> {
    motion
        .triangles
        .iter()
        .map(|key| {
            key.iter()
                .map(|triangle| Aabb::of_triangle(&triangle.positions))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::scene::motion::{KeyTriangle, SceneMotion, Shutter, ShutterPosition};
    use glam::Vec3;

    #[test]
    fn keys_are_triangle_major_in_leaf_order_then_the_cameras() {
        let triangle = |x: f32| KeyTriangle {
            positions: [Vec3::new(x, 0.0, 0.0), Vec3::Y, Vec3::Z],
            normal: Vec3::X,
        };
        let camera = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 1.0);
        let motion = SceneMotion {
            shutter: Shutter::new(1.0, ShutterPosition::Center, 2).unwrap(),
            triangles: vec![
                vec![triangle(0.0), triangle(1.0)],
                vec![triangle(2.0), triangle(3.0)],
            ],
            cameras: vec![camera, camera],
        };
        let texels = motion_texels(&motion, Some(&[1, 0]), 1.0);
        assert_eq!(texels.len(), 4 * 2 * 2 + 4 * 2);
        let first_xs: Vec<f32> = (0..4).map(|record| texels[4 * record][0]).collect();
        // stored triangle 0 is the scene's 1 (x 1 at key 0, 3 at key 1), then the scene's 0
        assert_eq!(first_xs, vec![1.0, 3.0, 0.0, 2.0]);
        assert_eq!(texels[3], [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(texels[16], [0.0, 0.0, 0.0, 0.0]);
    }
}
