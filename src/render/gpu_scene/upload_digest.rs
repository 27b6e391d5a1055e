//! What a scene's upload is made of, as digests of its parts (`UploadDigest`): a sequence
//! of renders (`crate::render::sequence`) keeps the upload while the next scene's digests
//! are the same, without keeping the scene itself (a copy of a scene of 10^6 triangles takes
//! ~200 MB), and where only some parts are the same (a moving scene), their buffers.
//!
//! Each part's digest hashes the words `GpuScene::upload` writes into that part's buffers,
//! or the words it derives them from, made by the functions the upload makes them with, in
//! the scene's order:
//! - the geometry: every `GpuTriangle` (the BVH, the traversal's triangles and the lights
//!   made of triangles are functions of these and of the settings in the sequence's
//!   `UploadKey`), the material kernels' per-triangle shading words, and with ray queries
//!   the acceleration structures' plan;
//! - the materials: the material kernels' material words and texture atlas, or that the
//!   workshop kernels read none;
//! - the lights' own parts, digested by the lights' room (`crate::lights::LightsDigest`,
//!   one digest per kind whose buffer an upload can keep).
//!
//! Two scenes whose part digests are the same get the same words in that part's buffers,
//! whatever else differs in them.

use super::{gpu_materials, kernel_materials};
use crate::accel::plan::StructurePlan;
use crate::digest::Parts;
use crate::kernels::variant::Traversal;
use crate::lights::{LightsDigest, SameLights};
use crate::render::gpu_materials::{material_texel_words, GpuExtraShading, GpuTriangleShading};
use crate::render::gpu_textures::TextureAtlas;
use crate::render::gpu_types::GpuTriangle;
use crate::scene::Scene;

/// The SHA-256 digests of what `GpuScene::upload` writes for a scene, part by part, the
/// render uniforms (camera, image size, seed) aside. SHA-256 is collision resistant: two
/// scenes that upload different words in a part get the same digest with a probability of
/// about 2^-256 (2^-128 among every pair of a sequence of 2^64 scenes), so a sequence that
/// reuses a part by its digest renders the image a fresh upload would.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UploadDigest {
    /// The triangles and everything stored in their (leaf) order.
    geometry: [u8; 32],
    /// The materials' words and texture texels (`MaterialBuffers`).
    materials: [u8; 32],
    /// The lights' own parts, kind by kind.
    lights: LightsDigest,
}

/// Which parts of two uploads write the same words (`UploadDigest::same_parts`), apart from
/// the geometry: the parts a new upload of a moved scene can take from the kept one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SameParts {
    /// The materials' words and texture texels.
    pub materials: bool,
    /// The lights' kinds that are the same (`LightsDigest::same`).
    pub lights: SameLights,
}

impl UploadDigest {
    /// The digests of what `GpuScene::upload` writes for `scene` traced by `traversal`;
    /// `None` where the upload would fail on the scene's own data (textures beyond the 2^32
    /// texels an atlas can index), which is then never kept.
    pub fn of(scene: &Scene, traversal: Traversal) -> Option<UploadDigest> {
        // Every field by name but the lights', which `LightsDigest::of` hashes: it names
        // every field of `Scene`, so a field added to `Scene` does not compile there until it
        // is said to be a light's or this upload's (and then hashed here, or said to be none
        // of the upload's).
        let Scene {
            triangles,
            // The render uniforms, written for every render (`GpuScene::aim`)
            camera: _,
            cameras: _,
            warnings: _,
            // Read as the kernels read them (`kernel_materials`)
            materials: _,
            // Read by the structures' plan
            mesh_instances,
            // Written after the triangles, at the same binding (`motion_texels`)
            motion,
            ..
        } = scene;
        let kernel_materials = kernel_materials(scene);
        let mut geometry = Parts::new();
        geometry.words_of(triangles, GpuTriangle::new);
        if let Some(motion) = motion {
            geometry.part(b"motion");
            geometry.part(&motion.steps().to_le_bytes());
            for key in &motion.triangles {
                geometry.words_of(key, |t| {
                    [t.positions[0], t.positions[1], t.positions[2], t.normal].map(|v| v.to_array())
                });
            }
            // Every field of each key's camera, its lens too (the Debug text prints them all)
            geometry.part(format!("{:?}", motion.cameras).as_bytes());
        }
        let mut materials = Parts::new();
        match &kernel_materials {
            Some(kernel_materials) => {
                geometry.part(b"shading");
                geometry.words_of(&kernel_materials.triangles, GpuTriangleShading::new);
                // The extra vertex attributes, where the kernels read them
                if kernel_materials.vertex_attributes() != 0 {
                    geometry.part(b"extra vertex attributes");
                    let indices: Vec<usize> = (0..kernel_materials.triangles.len()).collect();
                    geometry.words_of(&indices, |&index| {
                        GpuExtraShading::new(&kernel_materials.extra.get(index))
                    });
                }
                materials.part(b"materials");
                let atlas = TextureAtlas::new(&kernel_materials.textures, u64::MAX).ok()?;
                let words = material_texel_words(&gpu_materials(kernel_materials, &atlas));
                materials.part(bytemuck::cast_slice(&words));
                materials.part(bytemuck::cast_slice(&atlas.texels));
            }
            None => materials.part(b"workshop"),
        }
        if traversal == Traversal::RayQuery {
            let plan = StructurePlan::of(triangles, mesh_instances);
            geometry.part(&(plan.bottom_levels.len() as u64).to_le_bytes());
            for level in &plan.bottom_levels {
                geometry.part(bytemuck::cast_slice(&level.positions));
                geometry.words_of(&level.instances, |instance| instance.transform);
                geometry.words_of(&level.instances, |instance| instance.first_triangle);
            }
        }
        Some(UploadDigest {
            geometry: geometry.finish(),
            materials: materials.finish(),
            lights: LightsDigest::of(scene, kernel_materials.is_some()),
        })
    }

    /// Which parts besides the geometry `self` and `other` write alike.
    pub fn same_parts(&self, other: &UploadDigest) -> SameParts {
        SameParts {
            materials: self.materials == other.materials,
            lights: self.lights.same(&other.lights),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::materials::SceneMaterials;
    use crate::scene::{MeshInstance, Triangle};
    use glam::{Mat4, Vec3};
    use std::sync::Arc;

    fn scene(x: f32) -> Scene {
        let triangle = Triangle::new(
            [Vec3::new(x, 0.0, 0.0), Vec3::X, Vec3::Y],
            Vec3::splat(0.5),
            Vec3::ZERO,
            false,
        )
        .unwrap();
        Scene {
            triangles: vec![triangle],
            ..Scene::default()
        }
    }

    fn digest(scene: &Scene) -> UploadDigest {
        UploadDigest::of(scene, Traversal::Bvh).unwrap()
    }

    #[test]
    fn scenes_are_the_same_only_bit_for_bit() {
        assert_eq!(digest(&scene(0.0)), digest(&scene(0.0)));
        // 0 and -0 compare equal as floats, but are other bits on the device.
        assert_ne!(digest(&scene(0.0)), digest(&scene(-0.0)));
        assert_ne!(digest(&scene(0.0)), digest(&scene(0.25)));
        let mut lit = scene(0.0);
        lit.triangles[0].emission = Vec3::ONE;
        assert_ne!(digest(&scene(0.0)), digest(&lit));
        let mut two_sided = scene(0.0);
        two_sided.triangles[0].double_sided = true;
        assert_ne!(digest(&scene(0.0)), digest(&two_sided));
        let mut shaded = scene(0.0);
        shaded.materials = Some(SceneMaterials::from_plain(&shaded.triangles));
        assert_ne!(digest(&scene(0.0)), digest(&shaded));
        assert_eq!(digest(&shaded), digest(&shaded.clone()));
        let mut smooth = shaded.clone();
        if let Some(materials) = smooth.materials.as_mut() {
            materials.triangles[0].normals[1] = Vec3::Y;
        }
        assert_ne!(digest(&shaded), digest(&smooth));
    }

    #[test]
    fn a_moved_scene_keeps_the_parts_that_did_not_move() {
        let shaded = |x: f32| {
            let mut scene = scene(x);
            scene.materials = Some(SceneMaterials::from_plain(&scene.triangles));
            scene
        };
        let (before, after) = (digest(&shaded(0.0)), digest(&shaded(0.25)));
        assert_ne!(before, after);
        let all = SameParts {
            materials: true,
            lights: SameLights::all(),
        };
        assert_eq!(before.same_parts(&after), all);
        // (`crate::lights::LightsDigest`'s tests change the lights kind by kind.)
        // The workshop kernels read no materials, nor the lights' own parts.
        assert_eq!(
            digest(&scene(0.0)).same_parts(&before),
            SameParts::default()
        );
    }

    #[test]
    fn a_camera_or_a_warning_is_not_uploaded() {
        let mut moved = scene(0.0);
        moved.warnings.push("a camera moved".into());
        let camera = crate::camera::Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y, 40.0);
        moved.cameras = vec![camera];
        moved.camera = Some(camera);
        assert_eq!(digest(&scene(0.0)), digest(&moved));
    }

    #[test]
    fn an_instance_counts_where_the_device_builds_structures() {
        let instanced = |x: f32| {
            let mut scene = scene(0.0);
            scene.mesh_instances = vec![MeshInstance {
                first_triangle: 0,
                object_to_world: Mat4::from_translation(Vec3::new(x, 0.0, 0.0)),
                object_positions: Arc::new(vec![scene.triangles[0].positions]),
                node: None,
            }];
            scene
        };
        let ray_query = |scene: &Scene| UploadDigest::of(scene, Traversal::RayQuery);
        assert_ne!(ray_query(&instanced(0.0)), ray_query(&instanced(1.0)));
        assert_eq!(ray_query(&instanced(1.0)), ray_query(&instanced(1.0)));
        // The BVH's upload reads the world-space triangles alone
        assert_eq!(digest(&instanced(0.0)), digest(&instanced(1.0)));
    }
}
