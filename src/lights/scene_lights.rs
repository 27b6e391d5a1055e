//! Every light of a scene as one list of kinds, on the host and on the device: the emissive
//! triangles (with the light tree over them), the environment and the punctual lights. This
//! file (with `mod.rs`'s module lines) is where `crate::lights` lists its kinds:
//!
//! - `SceneLights`: the lights a render uploads, the words of each kind, and what the variant
//!   room (`SceneSummary`, `VariantSettings`) and the loop budget read of them;
//! - `LightsDigest`: the digest of each kind whose buffer a sequence of renders keeps while
//!   it writes the same words (`crate::render::sequence`), and `SameLights`, which kinds
//!   two scenes share;
//! - `LightBuffers`: the lights' own buffers on the device, one per kind, bound where the
//!   kernels' binding table says (`LightBuffers::resource`), kept for the next upload
//!   (`KeptLightBuffers`) and counted when kept (`LightReuse`).
//!
//! The renderer (`crate::render`) holds one `LightBuffers` and names no kind.

use std::sync::Arc;

use super::emissive::EmissiveTriangles;
use super::environment::{Environment, EnvironmentMap};
use super::gpu_emissive::{
    gpu_light_bytes, gpu_light_bytes_with_tree, gpu_light_index_words, gpu_light_selection_words,
};
use super::gpu_environment::gpu_environment_words;
use super::gpu_punctual::gpu_punctual_light_words;
use super::light_tree::{LightKeys, LightTree};
use super::punctual::PunctualLight;
use super::selection::LightSelection;
use crate::digest::Parts;
use crate::kernels::variant::{SceneSummary, VariantSettings};
use crate::kernels::Resource;
use crate::scene::{Scene, Triangle};
use crate::vk::{CommandRunner, Context, TexelBufferView, VkResult};

/// The list of a scene's lights that the renderer uploads.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneLights<'a> {
    /// The emissive triangles, indexed in the order the triangles are uploaded (the BVH's
    /// leaf order when there is one).
    pub emissive: EmissiveTriangles,
    /// The light tree over them (`--light-selection tree`); `None`: the power CDF.
    pub tree: Option<LightTree>,
    /// What rays that leave the scene see; `None`: black.
    pub environment: Option<&'a Environment>,
    /// KHR_lights_punctual's lights.
    pub punctual: &'a [PunctualLight],
}

impl<'a> SceneLights<'a> {
    /// The lights of `scene`, whose triangles are uploaded as `triangles` (the scene's own
    /// or a reordering of them).
    pub fn new(scene: &'a Scene, triangles: &[Triangle]) -> SceneLights<'a> {
        SceneLights {
            emissive: EmissiveTriangles::new(triangles),
            tree: None,
            environment: scene.environment.as_ref(),
            punctual: &scene.punctual_lights,
        }
    }

    /// These lights with a light tree over the emissive triangles (none without them);
    /// `triangles` must be the ones this list was made with, and `keys` motion blur's keys
    /// of them (`LightKeys::STILL` for a still scene), over which the tree bounds each light
    /// (`LightTree::build_over_keys`).
    pub fn with_light_tree(self, triangles: &[Triangle], keys: LightKeys) -> Self {
        let tree = (!self.emissive.triangle_indices.is_empty())
            .then(|| LightTree::build_over_keys(triangles, &self.emissive, keys));
        SceneLights { tree, ..self }
    }

    /// These lights as `selection` chooses among them: with the light tree where it takes
    /// the tree (`LightSelection::uses_tree`); `triangles` and `keys` as `with_light_tree`
    /// takes them.
    pub fn with_selection(
        self,
        selection: LightSelection,
        triangles: &[Triangle],
        keys: LightKeys,
    ) -> Self {
        if self.uses_tree(selection) {
            self.with_light_tree(triangles, keys)
        } else {
            self
        }
    }

    /// Whether `selection` takes the light tree over these lights.
    fn uses_tree(&self, selection: LightSelection) -> bool {
        selection.uses_tree(self.emissive.triangle_indices.len())
    }

    /// What the variant room reads of these lights: `SceneSummary`'s lights' fields (the
    /// rest default, for the caller to fill).
    pub fn summary(&self) -> SceneSummary {
        SceneSummary {
            environment: self.has_environment(),
            samples_environment: self.samples_environment(),
            punctual_lights: !self.punctual.is_empty(),
            emissive_triangles: !self.emissive.triangle_indices.is_empty(),
            ..SceneSummary::default()
        }
    }

    /// What the variant room reads of `selection` over these lights: `VariantSettings`'
    /// lights' field (the rest default, for the caller to fill).
    pub fn variant_settings(&self, selection: LightSelection) -> VariantSettings {
        VariantSettings {
            light_tree: self.uses_tree(selection),
            ..VariantSettings::default()
        }
    }

    /// Light samples next event estimation draws at a path vertex, at most: one per kind
    /// the scene has (`sample_direct_light` in `glsl/lights.glsl`: the emissive triangles,
    /// and in the material kernels the environment and the punctual lights).
    pub fn light_samples_per_vertex(&self) -> u64 {
        1 + u64::from(self.has_environment()) + u64::from(!self.punctual.is_empty())
    }
    /// The words of the selection buffer (`BINDING_LIGHT_SELECTION`), one per triangle this
    /// list was made with, in the same order: what MIS reads of each, its selection
    /// probability, or with a light tree its index in the light list.
    pub fn selection_words(&self) -> Vec<u32> {
        match &self.tree {
            None => gpu_light_selection_words(&self.emissive),
            Some(_) => gpu_light_index_words(&self.emissive),
        }
    }

    /// The bytes of the emissive triangles' texel buffer (`BINDING_LIGHTS`), with the tree's
    /// nodes where there is one.
    pub fn emissive_bytes(&self) -> Vec<u8> {
        match &self.tree {
            None => gpu_light_bytes(&self.emissive),
            Some(tree) => gpu_light_bytes_with_tree(&self.emissive, tree),
        }
    }

    /// The light searches' iterations per ray that the kernel counts (the loop bound,
    /// `get_light_search_iterations()` of `glsl/emissive_lights.glsl`): the power CDF's binary search
    /// (`crate::kernels::loops::light_search_iterations`), or with a tree two walks (a light
    /// sample's and an MIS weight's) of at most depth + 1 trips each.
    pub fn light_search_iterations(&self) -> u64 {
        match &self.tree {
            None => crate::kernels::loops::light_search_iterations(
                self.emissive.triangle_indices.len() as u64,
            ),
            Some(tree) => 2 * (u64::from(tree.depth) + 1),
        }
    }

    /// The words of the environment's texel buffer (`BINDING_ENVIRONMENT`).
    pub fn environment_words(&self) -> Vec<u32> {
        gpu_environment_words(self.environment)
    }

    /// Whether the environment gives light (`SCENE_HAS_ENVIRONMENT`; else its words say
    /// `ENVIRONMENT_NONE`).
    pub fn has_environment(&self) -> bool {
        self.environment.is_some_and(Environment::emits_light)
    }

    /// Whether next event estimation draws light samples from the environment
    /// (`SCENE_SAMPLES_ENVIRONMENT`): where it gives light and is a map. A constant
    /// environment is left to the paths' BSDF-sampled rays (`glsl/shared.h`).
    pub fn samples_environment(&self) -> bool {
        self.has_environment() && self.environment.is_some_and(|e| e.map.is_some())
    }

    /// The words of the punctual lights' texel buffer (`BINDING_PUNCTUAL_LIGHTS`).
    pub fn punctual_words(&self) -> Vec<u32> {
        gpu_punctual_light_words(self.punctual)
    }
}

/// Feeds `update` what a scene's lights add to its hash in a render's metadata
/// (`crate::render::metadata::scene_hash`): the punctual lights and the environment, as
/// described (the emissive triangles are the triangles').
pub fn hash_description(scene: &Scene, update: &mut dyn FnMut(&[u8])) {
    if !scene.punctual_lights.is_empty() {
        update(format!("{:?}", scene.punctual_lights).as_bytes());
    }
    if let Some(environment) = &scene.environment {
        update(
            format!(
                "{:?} {} {}",
                environment.background, environment.strength, environment.rotation_degrees
            )
            .as_bytes(),
        );
        if let Some(map) = &environment.map {
            update(format!("{}x{}", map.width, map.height).as_bytes());
            update(bytemuck::cast_slice::<_, u8>(&map.texels));
        }
    }
}

/// The SHA-256 digests of the words `LightBuffers::upload` writes for each kind of light
/// whose buffer does not follow from the triangles (the environment, the punctual lights),
/// for a sequence of renders that keeps such a buffer while the next scene writes the same
/// words (`crate::render::gpu_scene::UploadDigest` holds one). The emissive triangles, their
/// selection words and light tree are functions of the triangles and the settings, which
/// the upload's geometry digest and key cover.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightsDigest {
    /// The environment's words.
    environment: [u8; 32],
    /// The punctual lights' words.
    punctual: [u8; 32],
}

/// Which kinds of light two uploads write alike (`LightsDigest::same`): the buffers a new
/// upload takes from the kept one (`LightBuffers::into_kept`). `Default`: none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SameLights {
    environment: bool,
    punctual: bool,
}

impl SameLights {
    /// Every kind alike.
    pub fn all() -> SameLights {
        SameLights {
            environment: true,
            punctual: true,
        }
    }
}

/// Hashes what the environment's words (`gpu_environment_words`) are made of: the
/// environment itself, every field, rather than the words, whose importance table takes
/// longer to make than the map to hash (0.18 s a frame for a 2048 x 1024 map). The same
/// environment makes the same words.
fn hash_environment(part: &mut Parts, environment: Option<&Environment>) {
    let Some(Environment {
        map,
        background,
        strength,
        rotation_degrees,
    }) = environment
    else {
        part.part(b"none");
        return;
    };
    part.part(bytemuck::cast_slice(&[
        background.x,
        background.y,
        background.z,
        *strength,
        *rotation_degrees,
    ]));
    match map {
        Some(EnvironmentMap {
            width,
            height,
            texels,
        }) => {
            part.part(bytemuck::cast_slice(&[*width, *height]));
            part.words_of(texels, |texel| texel.to_array());
        }
        None => part.part(b"constant"),
    }
}

impl LightsDigest {
    /// The digests of `scene`'s lights as an upload for the material kernels
    /// (`material_kernels`) or the workshop's writes them: only the material kernels read
    /// the environment and the punctual lights (`LightBuffers::upload`).
    pub fn of(scene: &Scene, material_kernels: bool) -> LightsDigest {
        // Every field by name: a field added to `Scene` does not compile here until it is
        // said to be a light's (hashed here) or the upload's (`UploadDigest::of` hashes
        // those, and leaves the lights' to this digest).
        let Scene {
            triangles: _,
            camera: _,
            cameras: _,
            warnings: _,
            materials: _,
            mesh_instances: _,
            // The upload's: the keys ride in the triangle buffer (the light buffers are
            // the still triangles')
            motion: _,
            punctual_lights,
            environment,
        } = scene;
        let read = |hash: &dyn Fn(&mut Parts)| {
            let mut part = Parts::new();
            if material_kernels {
                hash(&mut part);
            } else {
                part.part(b"workshop");
            }
            part.finish()
        };
        LightsDigest {
            environment: read(&|part| hash_environment(part, environment.as_ref())),
            punctual: read(&|part| {
                part.part(bytemuck::cast_slice(&gpu_punctual_light_words(
                    punctual_lights,
                )))
            }),
        }
    }

    /// Which kinds `self` and `other` write alike.
    pub fn same(&self, other: &LightsDigest) -> SameLights {
        SameLights {
            environment: self.environment == other.environment,
            punctual: self.punctual == other.punctual,
        }
    }
}

/// A scene's lights on the device: one texel buffer per kind of light, each holding the
/// words that kind's GLSL file reads (`gpu_emissive`, `gpu_environment`, `gpu_punctual`),
/// and the emissive kind's per-triangle selection words. The scene's upload
/// (`crate::render::gpu_scene`) binds each where the kernels' binding table
/// (`crate::kernels::bindings`) says, asking `LightBuffers::resource` which it is, and
/// counts them all in its memory (`LightBuffers::byte_size`).
pub struct LightBuffers {
    /// The emissive triangles' selection table, or their light tree
    /// (`glsl/emissive_lights.glsl`, `glsl/light_tree.glsl`).
    emissive: TexelBufferView,
    /// Every triangle's selection word, for MIS (`g_light_selection_words`, R32_UINT, 4
    /// bytes per triangle): its selection probability, or with the tree its light index.
    selection: TexelBufferView,
    /// The environment (`glsl/environment.glsl`): only the material kernels read it.
    environment: Option<TexelBufferView>,
    /// The punctual lights (`glsl/punctual_lights.glsl`): only the material kernels read
    /// them.
    punctual: Option<TexelBufferView>,
}

/// The buffers of an earlier upload that an upload takes instead of uploading them again
/// (the caller knows they hold the same words: `LightsDigest::same`). `Default`: none.
#[derive(Default)]
pub struct KeptLightBuffers {
    environment: Option<TexelBufferView>,
    punctual: Option<TexelBufferView>,
}

impl LightBuffers {
    /// Uploads `lights`: the emissive triangles and their selection words always, the
    /// environment and punctual lights when the kernel reads them (`material_kernels`: the
    /// builds with `USE_MATERIALS`), each taken from `kept` where it holds one.
    pub fn upload(
        context: &Arc<Context>,
        commands: &CommandRunner,
        lights: &SceneLights,
        material_kernels: bool,
        kept: KeptLightBuffers,
    ) -> VkResult<LightBuffers> {
        let upload = |name: &str, bytes: &[u8]| {
            TexelBufferView::upload_rgba32_uint(context, commands, name, bytes)
        };
        let emissive = upload("lights", &lights.emissive_bytes())?;
        let selection = TexelBufferView::upload_r32_uint(
            context,
            commands,
            "light selection words",
            &lights.selection_words(),
        )?;
        let (environment, punctual) = if material_kernels {
            let environment = match kept.environment {
                Some(kept) => kept,
                None => upload(
                    "environment",
                    bytemuck::cast_slice(&lights.environment_words()),
                )?,
            };
            let punctual = match kept.punctual {
                Some(kept) => kept,
                None => upload(
                    "punctual lights",
                    bytemuck::cast_slice(&lights.punctual_words()),
                )?,
            };
            (Some(environment), Some(punctual))
        } else {
            (None, None)
        };
        Ok(LightBuffers {
            emissive,
            selection,
            environment,
            punctual,
        })
    }

    /// The lights' buffer for a binding of the kernels' tables (`crate::kernels::bindings`);
    /// `None` for a resource that is not the lights', or for a kind this upload left out (the
    /// environment and punctual lights without material kernels).
    pub fn resource(&self, resource: Resource) -> Option<&TexelBufferView> {
        match resource {
            Resource::Lights => Some(&self.emissive),
            Resource::LightSelection => Some(&self.selection),
            Resource::Environment => self.environment.as_ref(),
            Resource::PunctualLights => self.punctual.as_ref(),
            _ => None,
        }
    }

    /// The buffers of the kinds `same` says a later upload writes alike, for that upload
    /// (`upload`'s `kept`); the rest is freed.
    pub fn into_kept(self, same: SameLights) -> KeptLightBuffers {
        KeptLightBuffers {
            environment: self.environment.filter(|_| same.environment),
            punctual: self.punctual.filter(|_| same.punctual),
        }
    }

    /// Bytes of all the lights' buffers (`render --json`'s `scene_memory` counts them).
    pub fn byte_size(&self) -> u64 {
        [
            Some(&self.emissive),
            Some(&self.selection),
            self.environment.as_ref(),
            self.punctual.as_ref(),
        ]
        .into_iter()
        .flatten()
        .map(TexelBufferView::byte_size)
        .sum()
    }
}

/// How many renders of a sequence took each kind's buffer from the upload before
/// (`crate::render::sequence::ReuseCounts` holds one).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightReuse {
    /// Renders that took the environment's buffer.
    pub environment: u32,
    /// Renders that took the punctual lights' buffer.
    pub punctual_lights: u32,
}

impl LightReuse {
    /// Counts the buffers a render took (`kept`, passed to `LightBuffers::upload`).
    pub fn count(&mut self, kept: &KeptLightBuffers) {
        self.environment += u32::from(kept.environment.is_some());
        self.punctual_lights += u32::from(kept.punctual.is_some());
    }

    /// The kinds taken since `before`, by the names `render --json` reports them with:
    /// `environment`, `punctual_lights`.
    pub fn since(self, before: LightReuse) -> impl Iterator<Item = &'static str> {
        [
            (self.environment > before.environment, "environment"),
            (
                self.punctual_lights > before.punctual_lights,
                "punctual_lights",
            ),
        ]
        .into_iter()
        .filter_map(|(reused, name)| reused.then_some(name))
    }
}

#[cfg(test)]
#[path = "scene_lights_tests.rs"]
mod tests;
