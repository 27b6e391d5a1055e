//! Images in and out: the rendered image as the host holds it (mean, second moment and
//! sample count per pixel), writing it as EXR or PNG, and reading EXR files back, with one error type (`ImageError`). The checkpoint state
//! (the accumulation in an EXR) is `crate::render::state_exr`.

pub mod data;
pub mod error;
pub mod exr_input;
pub mod output;
pub mod tonemap;

pub use error::{ImageError, ImageResult};
