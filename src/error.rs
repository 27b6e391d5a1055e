//! The library's error type: what we were doing and what went wrong, in one line.

use crate::image_io::ImageError;
use crate::scene::SceneError;
use crate::vk::VkError;

/// Anything that can go wrong in vkpath.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Vulkan could not be set up or a Vulkan call failed.
    #[error(transparent)]
    Vulkan(#[from] VkError),
    /// A scene could not be loaded.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Render settings out of range.
    #[error("invalid settings: {0}")]
    InvalidSettings(String),
    /// The scene lacks something the render needs.
    #[error("{0}")]
    MissingInput(String),
    /// An image file could not be written or read.
    #[error(transparent)]
    ImageFile(#[from] ImageError),
    /// An image could not be made (a shader program's output, a render's pixels).
    #[error("{0}")]
    Image(String),
    /// A shader could not be compiled.
    #[error("{0}")]
    ShaderCompilation(String),
    /// A kernel's loops ran past their limit (llvmpipe ends loops silently after 65535
    /// iterations; a user's function under `vkpath check` after its own limit), so its
    /// results cannot be trusted.
    #[error("{0}")]
    LoopLimit(String),
    /// Denoising failed (or Open Image Denoise is missing).
    #[error(transparent)]
    Denoise(#[from] crate::denoise::DenoiseError),
    /// A render failed after taking samples, and its device could not give back what it
    /// held (a lost device), so there is no image of them.
    #[error("rendering stopped after {samples} spp: {error}; the device could not give back what it rendered, so no image was written{kept}")]
    RenderLost {
        /// The samples per pixel taken before the failure.
        samples: u32,
        /// The failure.
        error: Box<Error>,
        /// What the caller kept of them (e.g. "; 'ck.exr' holds …"), or empty.
        kept: String,
    },
}

/// Result with vkpath's error.
pub type Result<T, E = Error> = std::result::Result<T, E>;
