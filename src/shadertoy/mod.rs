//! `vkpath shadertoy`: whole ShaderToy programs run headless. The Common tab is prepended to
//! every pass; each frame runs Buffers A, B, C, D and then the Image pass as full-screen
//! compute dispatches of the user's `mainImage(out vec4 fragColor, in vec2 fragCoord)`
//! (fragCoord at pixel centres, origin at the bottom left). Buffers are `rgba32f` images,
//! ping-ponged, with ShaderToy's semantics: a pass reading a buffer that runs before it sees
//! this frame's result, one reading itself or a later buffer the previous frame's (zero
//! before frame 0). `iChannel0`–`3` are sampled with linear filtering and clamp to edge;
//! ShaderToy's inputs advance in fixed steps of 1/60 s from 0, so a run is deterministic.
//!
//! - `program`: the passes, their files and their channels (`--channel`);
//! - `kernel`: the pass kernel (`pass.comp`) compiled with the user's tabs, each prepared by
//!   the intake `vkpath check` uses too (`crate::glsl_intake`, page shaders included), one
//!   compilation per pass with the Common tab first, messages naming their files and lines;
//! - `inputs`: ShaderToy's inputs as the kernel receives them;
//! - `runner`: the pipelines, images and frames on a device;
//! - `display`: PNG as ShaderToy shows it, EXR as the floats.

pub mod display;
pub mod inputs;
pub mod kernel;
pub mod program;
pub mod runner;

pub use program::{ChannelBinding, ChannelSource, Pass, PassKind, Program, ProgramError};
pub use runner::ShadertoyRunner;
