//! What a sequence of renders on one device keeps from one render to the next
//! (`render --frames`, Python's `render_frames`): the path tracer's pipelines, keyed by
//! their build and specialization constants (a frame whose variant is unchanged takes the
//! same pipeline; a flag that flips builds the other one, once), the accumulation image
//! with its read-back and tile-upload buffers (cleared by every render), and the uploaded
//! scene when the next scene uploads the same data (a static scene, or a camera flight):
//! then only the render uniforms (the camera) are written again. A scene whose geometry
//! moved is uploaded afresh, BVH built anew: a refitted BVH would have other bounds and
//! another leaf order than the rebuilt one (the triangles, shading data and light indices
//! are stored in that order), so its images would not be those of a render of that frame
//! alone.

use std::sync::Arc;

use crate::kernels::variant::Traversal;
use crate::kernels::{Build, KernelPipeline};
use crate::lights::gpu_punctual::gpu_punctual_light_words;
use crate::render::gpu_scene::GpuScene;
use crate::render::settings::{Accel, LightSelection, RenderSettings};
use crate::scene::materials::SceneMaterials;
use crate::scene::{Scene, Triangle};
use crate::vk::{Buffer, StorageImage};

/// Pipelines a sequence keeps at most (the most recently used): a sequence whose variant
/// flips back and forth between two or three builds never builds one twice.
const KEPT_PIPELINES: usize = 4;

/// What renders on one device keep for the next; `Default` is empty. Pass the same one to
/// `Renderer::in_sequence` for every render, and give each renderer back with
/// `Renderer::keep_for_next`.
#[derive(Default)]
pub struct SequenceCache {
    /// Embedded path-tracer pipelines, least recently used first.
    pipelines: Vec<CachedPipeline>,
    /// The last render's accumulation image and buffers, while no renderer holds them.
    images: Option<AccumulationImages>,
    /// What the last render's scene uploaded, and the upload itself while no renderer holds
    /// it.
    scene: Option<UploadedScene>,
    /// How often each part was reused (for tests and reports).
    pub reused: ReuseCounts,
}

impl std::fmt::Debug for SequenceCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SequenceCache")
            .field("pipelines", &self.pipelines.len())
            .field("images", &self.images.is_some())
            .field("scene", &self.scene.is_some())
            .field("reused", &self.reused)
            .finish()
    }
}

/// How many renders of a sequence took a part from the previous ones instead of building
/// it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReuseCounts {
    /// Renders whose pipeline was already built.
    pub pipelines: u32,
    /// Renders whose accumulation image was reused.
    pub images: u32,
    /// Renders whose scene upload was reused (only the camera written again).
    pub scenes: u32,
}

impl ReuseCounts {
    /// What was reused since `before` (for one render: what it took from the ones before
    /// it), by name: `kernel`, `accumulation`, `scene`.
    pub fn since(self, before: ReuseCounts) -> Vec<&'static str> {
        [
            (self.pipelines > before.pipelines, "kernel"),
            (self.images > before.images, "accumulation"),
            (self.scenes > before.scenes, "scene"),
        ]
        .into_iter()
        .filter_map(|(reused, name)| reused.then_some(name))
        .collect()
    }
}

/// A pipeline and what it was built from.
struct CachedPipeline {
    build: Build,
    specialization: Vec<(u32, u32)>,
    pipeline: Arc<KernelPipeline>,
}

/// The accumulation image of one size, its read-back buffer and (in tiles) its upload
/// buffer.
pub(crate) struct AccumulationImages {
    /// The image (`ACCUMULATION_LAYER_COUNT` layers).
    pub accumulation: StorageImage,
    /// Host-visible, the image's size.
    pub readback: Buffer,
    /// Host-visible, the image's size: a tiled render's upload of a tile's state.
    pub tile_upload: Option<Buffer>,
}

/// A scene upload and what decides it: the scene's data (camera aside) and the settings
/// that `GpuScene::upload` reads besides the camera's image plane.
struct UploadedScene {
    scene: Scene,
    key: UploadKey,
    /// `None` while a renderer holds it (or after a render that failed).
    gpu: Option<GpuScene>,
}

/// What `GpuScene::upload` reads of the settings and the traversal (the render uniforms
/// aside, which are written for every render).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct UploadKey {
    traversal: Traversal,
    accel: Accel,
    light_selection: LightSelection,
    guiding: bool,
}

impl UploadKey {
    /// The key of an upload for `traversal` with `settings`.
    pub(crate) fn new(settings: &RenderSettings, traversal: Traversal) -> UploadKey {
        UploadKey {
            traversal,
            accel: settings.accel,
            light_selection: settings.light_selection,
            guiding: settings.guiding.is_some(),
        }
    }
}

impl SequenceCache {
    /// The pipeline of `build` with `specialization`: the one built before, or `build_it`'s
    /// (then kept, dropping the least recently used beyond `KEPT_PIPELINES`).
    pub(crate) fn pipeline(
        &mut self,
        build: &Build,
        specialization: &[(u32, u32)],
        build_it: impl FnOnce() -> crate::Result<KernelPipeline>,
    ) -> crate::Result<Arc<KernelPipeline>> {
        let found = self
            .pipelines
            .iter()
            .position(|p| p.build == *build && p.specialization == specialization);
        if let Some(index) = found {
            let cached = self.pipelines.remove(index);
            let pipeline = cached.pipeline.clone();
            self.pipelines.push(cached);
            self.reused.pipelines += 1;
            return Ok(pipeline);
        }
        let pipeline = Arc::new(build_it()?);
        if self.pipelines.len() >= KEPT_PIPELINES {
            self.pipelines.remove(0);
        }
        self.pipelines.push(CachedPipeline {
            build: *build,
            specialization: specialization.to_vec(),
            pipeline: pipeline.clone(),
        });
        Ok(pipeline)
    }

    /// The kept accumulation image and buffers if they are `width` x `height` and have an
    /// upload buffer exactly when `tiled`; `None` otherwise (and the kept ones are freed).
    pub(crate) fn take_images(
        &mut self,
        width: u32,
        height: u32,
        tiled: bool,
    ) -> Option<AccumulationImages> {
        let images = self.images.take()?;
        let image = &images.accumulation;
        let fits =
            (image.width, image.height) == (width, height) && images.tile_upload.is_some() == tiled;
        if fits {
            self.reused.images += 1;
        }
        fits.then_some(images)
    }

    /// The kept upload of a scene with the same data as `scene` for `key`, if there is one;
    /// otherwise remembers `scene` and `key` for the upload the caller makes (and frees the
    /// kept one).
    pub(crate) fn take_scene(&mut self, scene: &Scene, key: UploadKey) -> Option<GpuScene> {
        if let Some(kept) = self.scene.as_mut() {
            if kept.key == key && same_scene_data(&kept.scene, scene) {
                let gpu = kept.gpu.take();
                if gpu.is_some() {
                    self.reused.scenes += 1;
                }
                return gpu;
            }
        }
        self.scene = Some(UploadedScene {
            scene: scene_data(scene),
            key,
            gpu: None,
        });
        None
    }

    /// Keeps what a finished renderer held for the next render.
    pub(crate) fn keep(&mut self, images: AccumulationImages, gpu: GpuScene) {
        self.images = Some(images);
        if let Some(kept) = self.scene.as_mut() {
            kept.gpu = Some(gpu);
        }
    }
}

/// What of `scene` an upload reads (`GpuScene::upload`): all of it but its cameras and
/// warnings.
fn scene_data(scene: &Scene) -> Scene {
    Scene {
        camera: None,
        cameras: Vec::new(),
        warnings: Vec::new(),
        ..scene.clone()
    }
}

/// Whether `GpuScene::upload` uploads the same bytes for `a` as for `b`: their triangles and
/// per-vertex shading data are the same bit for bit (what moves with a skin, a morph target
/// or a node), and their materials, textures, lights, environment and mesh copies compare
/// equal (`PartialEq`: they do not depend on the time, and a sequence reads them from the
/// same file with the same bits); punctual lights, which nodes move, by the words their
/// upload writes (`gpu_punctual_light_words`).
pub(crate) fn same_scene_data(a: &Scene, b: &Scene) -> bool {
    same_triangles(&a.triangles, &b.triangles)
        && same_materials(a.materials.as_ref(), b.materials.as_ref())
        && gpu_punctual_light_words(&a.punctual_lights)
            == gpu_punctual_light_words(&b.punctual_lights)
        && a.environment == b.environment
        && a.mesh_instances.len() == b.mesh_instances.len()
        && a.mesh_instances
            .iter()
            .zip(&b.mesh_instances)
            .all(|(x, y)| {
                x.first_triangle == y.first_triangle
                    && bits(x.object_to_world.to_cols_array())
                        == bits(y.object_to_world.to_cols_array())
                    && (Arc::ptr_eq(&x.object_positions, &y.object_positions)
                        || x.object_positions.len() == y.object_positions.len()
                            && x.object_positions
                                .iter()
                                .zip(y.object_positions.iter())
                                .all(|(p, q)| {
                                    p.iter()
                                        .zip(q)
                                        .all(|(u, v)| bits(u.to_array()) == bits(v.to_array()))
                                }))
            })
}

/// The bits of some floats (so that 0 and -0 differ, and a NaN equals itself).
fn bits<const N: usize>(values: [f32; N]) -> [u32; N] {
    values.map(f32::to_bits)
}

/// Whether two triangle lists are the same bit for bit.
fn same_triangles(a: &[Triangle], b: &[Triangle]) -> bool {
    let key = |t: &Triangle| {
        let p = t.positions;
        (
            [
                bits(p[0].to_array()),
                bits(p[1].to_array()),
                bits(p[2].to_array()),
                bits(t.normal.to_array()),
                bits(t.color.to_array()),
                bits(t.emission.to_array()),
            ],
            t.double_sided,
        )
    };
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| key(x) == key(y))
}

/// Whether two scenes' materials are the same: per-vertex shading data bit for bit,
/// materials and textures equal.
fn same_materials(a: Option<&SceneMaterials>, b: Option<&SceneMaterials>) -> bool {
    let (a, b) = match (a, b) {
        (None, None) => return true,
        (Some(a), Some(b)) => (a, b),
        _ => return false,
    };
    let shading_bits = |s: &crate::scene::materials::TriangleShading| {
        let mut words = vec![s.material];
        for i in 0..3 {
            words.extend(bits(s.normals[i].to_array()));
            words.extend(bits(s.tex_coords[i].to_array()));
            words.extend(bits(s.tangents[i].to_array()));
        }
        words
    };
    a.materials == b.materials
        && a.textures == b.textures
        && a.triangles.len() == b.triangles.len()
        && a.triangles
            .iter()
            .zip(&b.triangles)
            .all(|(x, y)| shading_bits(x) == shading_bits(y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

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

    #[test]
    fn scenes_are_the_same_only_bit_for_bit() {
        assert!(same_scene_data(&scene(0.0), &scene(0.0)));
        // 0 and -0 compare equal as floats, but are other bits on the device.
        assert!(!same_scene_data(&scene(0.0), &scene(-0.0)));
        assert!(!same_scene_data(&scene(0.0), &scene(0.25)));
        let mut lit = scene(0.0);
        lit.triangles[0].emission = Vec3::ONE;
        assert!(!same_scene_data(&scene(0.0), &lit));
        let mut shaded = scene(0.0);
        shaded.materials = Some(SceneMaterials::from_plain(&shaded.triangles));
        assert!(!same_scene_data(&scene(0.0), &shaded));
        assert!(same_scene_data(&shaded, &shaded.clone()));
    }

    #[test]
    fn a_camera_alone_keeps_the_upload_key() {
        let mut moved = scene(0.0);
        moved.warnings.push("a camera moved".into());
        assert!(same_scene_data(&scene_data(&scene(0.0)), &moved));
        let settings = RenderSettings::default();
        let key = UploadKey::new(&settings, Traversal::Bvh);
        assert_eq!(key, UploadKey::new(&settings, Traversal::Bvh));
        assert_ne!(key, UploadKey::new(&settings, Traversal::Linear));
    }
}
