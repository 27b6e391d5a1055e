//! The lights' own buffers on the device (`LightBuffers`): one texel buffer per kind of
//! light, each holding the words that kind's GLSL file reads (`gpu_emissive`,
//! `gpu_environment`, `gpu_punctual`), and the emissive kind's per-triangle selection words.
//! The scene's upload (`crate::render::gpu_scene`) binds each where the kernels' binding
//! table (`crate::kernels::bindings`) says, asking `LightBuffers::resource` which it is, and
//! counts them all in its memory (`LightBuffers::byte_size`).

use std::sync::Arc;

use crate::kernels::Resource;
use crate::lights::SceneLights;
use crate::vk::{CommandRunner, Context, TexelBufferView, VkResult};

/// A scene's lights on the device.
pub struct LightBuffers {
    /// The emissive triangles' selection table, or their light tree
    /// (`glsl/emissive_lights.glsl`, `glsl/light_tree.glsl`).
    pub emissive: TexelBufferView,
    /// Every triangle's selection word, for MIS (`g_light_selection_words`, R32_UINT, 4
    /// bytes per triangle): its selection probability, or with the tree its light index.
    pub selection: TexelBufferView,
    /// The environment (`glsl/environment.glsl`): only the material kernels read it.
    pub environment: Option<TexelBufferView>,
    /// The punctual lights (`glsl/punctual_lights.glsl`): only the material kernels read
    /// them.
    pub punctual: Option<TexelBufferView>,
}

/// The environment's and punctual lights' buffers of an earlier upload, which an upload
/// takes instead of uploading them again (the caller knows they hold the same words: a
/// sequence of renders compares digests of them). `Default`: none.
#[derive(Default)]
pub struct KeptLightBuffers {
    /// The environment's buffer, if kept.
    pub environment: Option<TexelBufferView>,
    /// The punctual lights' buffer, if kept.
    pub punctual: Option<TexelBufferView>,
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

    /// The environment's buffer (where `environment`) and the punctual lights' (where
    /// `punctual`) for a later upload (`upload`'s `kept`); the rest is freed.
    pub fn into_kept(self, environment: bool, punctual: bool) -> KeptLightBuffers {
        KeptLightBuffers {
            environment: self.environment.filter(|_| environment),
            punctual: self.punctual.filter(|_| punctual),
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
