//! Images in and out: the rendered image as the host holds it (mean, second moment and
//! sample count per pixel), writing it as EXR or PNG, and reading EXR files back.

pub mod data;
pub mod exr_input;
pub mod output;
pub mod state_exr;
pub mod tonemap;
