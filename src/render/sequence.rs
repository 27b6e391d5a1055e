//! What a sequence of renders on one device keeps from one render to the next
//! (`render --frames`, Python's `render_frames`): the path tracer's pipelines, keyed by
//! their build and specialization constants (a frame whose variant is unchanged takes the
//! same pipeline; a flag that flips builds the other one, once), the accumulation image
//! with its read-back and tile-upload buffers (cleared by every render), and the uploaded
//! scene. Where the next scene's upload would write the same words (the same
//! `UploadDigest`: a static scene, or a camera flight; the scene itself is not kept), only
//! the render uniforms (the camera) are written again. A scene whose geometry moved is
//! uploaded afresh, BVH built anew (a refitted BVH would have other bounds and another leaf
//! order than the rebuilt one; the triangles, shading data and light indices are stored in
//! that order, so its images would not be those of a render of that frame alone), but the
//! parts whose words did not change (`UploadDigest::same_parts`: the materials and texture
//! texels, and the lights' buffers that `crate::lights::LightsDigest` finds the same) are
//! taken from the kept upload.

use std::sync::Arc;

use crate::kernels::variant::Traversal;
use crate::kernels::{Build, KernelPipeline};
use crate::lights::LightReuse;
use crate::render::gpu_scene::{GpuScene, KeptParts, UploadDigest};
use crate::render::settings::{Accel, LightSelection, RenderSettings};
use crate::scene::Scene;
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
    /// Whether the sequence's geometry moves from frame to frame (set by its caller before
    /// the first render, e.g. `GltfFile::moves_geometry`): `--accel auto` then takes one
    /// traversal for every frame, never the constant triangles, whose kernel each frame
    /// would build again (`Traversal::choose_on_device`).
    pub moving_geometry: bool,
}

impl std::fmt::Debug for SequenceCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SequenceCache")
            .field("pipelines", &self.pipelines.len())
            .field("images", &self.images.is_some())
            .field("scene", &self.scene.is_some())
            .field("reused", &self.reused)
            .field("moving_geometry", &self.moving_geometry)
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
    /// Renders that uploaded their scene's geometry again but took the materials' words and
    /// texture texels from the upload before.
    pub materials: u32,
    /// Likewise the lights' buffers, kind by kind.
    pub lights: LightReuse,
}

impl ReuseCounts {
    /// What was reused since `before` (for one render: what it took from the ones before
    /// it), by name: `kernel`, `accumulation`, `scene`, or where the scene moved the parts
    /// of its upload that did not: `materials`, then the lights' kinds by their names
    /// (`LightReuse::since`).
    pub fn since(self, before: ReuseCounts) -> Vec<&'static str> {
        [
            (self.pipelines > before.pipelines, "kernel"),
            (self.images > before.images, "accumulation"),
            (self.scenes > before.scenes, "scene"),
            (self.materials > before.materials, "materials"),
        ]
        .into_iter()
        .filter_map(|(reused, name)| reused.then_some(name))
        .chain(self.lights.since(before.lights))
        .collect()
    }

    /// Counts the parts a render took from the upload before.
    fn count_parts(&mut self, parts: &KeptParts) {
        self.materials += u32::from(parts.materials());
        self.lights.count(parts.lights());
    }
}

/// What a render takes of the upload before: all of it (the scene's data are the same; only
/// the camera is written again), or some of its parts for a new upload (none where nothing
/// is kept).
// One value per render, moved once: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
pub(crate) enum KeptUpload {
    /// The whole upload.
    Whole(GpuScene),
    /// The parts that did not change, for `GpuScene::upload`.
    Parts(KeptParts),
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

/// A scene upload and what decides it: the digest of the words it wrote
/// (`UploadDigest`: the scene's data, camera aside) and the settings that `GpuScene::upload`
/// reads besides the camera's image plane.
struct UploadedScene {
    digest: UploadDigest,
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

    /// What the render of `scene` for `key` takes of the kept upload: all of it where its
    /// upload writes the same words (the same `UploadDigest`), else the parts that write the
    /// same words (`UploadDigest::same_parts`; the rest of the kept upload is freed).
    /// Remembers the digest and `key` for the upload the caller makes.
    pub(crate) fn take_scene(&mut self, scene: &Scene, key: UploadKey) -> KeptUpload {
        let started = std::time::Instant::now();
        let digest = UploadDigest::of(scene, key.traversal);
        log::debug!(
            "scene upload: digests made in {:.3} s",
            started.elapsed().as_secs_f64()
        );
        let kept = self.scene.take();
        self.scene = digest.map(|digest| UploadedScene {
            digest,
            key,
            gpu: None,
        });
        let (Some(kept), Some(digest)) = (kept, digest) else {
            return KeptUpload::Parts(KeptParts::default());
        };
        let Some(gpu) = kept.gpu else {
            return KeptUpload::Parts(KeptParts::default());
        };
        if kept.key == key && kept.digest == digest {
            self.reused.scenes += 1;
            return KeptUpload::Whole(gpu);
        }
        let parts = gpu.into_kept(kept.digest.same_parts(&digest));
        self.reused.count_parts(&parts);
        KeptUpload::Parts(parts)
    }

    /// Keeps what a finished renderer held for the next render.
    pub(crate) fn keep(&mut self, images: AccumulationImages, gpu: GpuScene) {
        self.images = Some(images);
        if let Some(kept) = self.scene.as_mut() {
            kept.gpu = Some(gpu);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_traversal_or_a_setting_changes_the_upload_key() {
        let settings = RenderSettings::default();
        let key = UploadKey::new(&settings, Traversal::Bvh);
        assert_eq!(key, UploadKey::new(&settings, Traversal::Bvh));
        assert_ne!(key, UploadKey::new(&settings, Traversal::Linear));
        let guided = RenderSettings {
            guiding: Some(crate::guiding::training::GuideTraining { samples: 8 }),
            ..settings.clone()
        };
        assert_ne!(key, UploadKey::new(&guided, Traversal::Bvh));
    }
}
