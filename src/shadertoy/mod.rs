//! `vkpath shadertoy`: whole ShaderToy programs run headless. The Common tab is prepended to
//! every pass; each frame runs Buffers A, B, C, D and then the Image pass as full-screen
//! compute dispatches of the user's `mainImage(out vec4 fragColor, in vec2 fragCoord)`
//! (fragCoord at pixel centres, origin at the bottom left). Buffers are `rgba32f` images,
//! ping-ponged, with ShaderToy's semantics: a pass reading a buffer that runs before it sees
//! this frame's result, one reading itself or a later buffer the previous frame's (zero
//! before frame 0). `iChannel0`–`3` are sampled with linear filtering and clamp to edge
//! (a cube-map channel is a `samplerCube`); ShaderToy's inputs advance in fixed steps of
//! 1/60 s from 0, so a run is deterministic.
//!
//! A `discard` leaves the pixel's texel unwritten, as a fragment shader's does: a buffer's
//! texel keeps what that target held, which (ShaderToy renders each buffer into two targets
//! in turn and clears them only before frame 0) is its value of two frames before; the Image
//! pass's keeps the previous frame's. An Image tab that reads itself (VS Code Shader Toy's
//! single-file `#iChannel0 "self"`) runs as a hidden buffer that vkpath's Image pass shows.
//!
//! - `program`: the passes, their files and their channels (`--channel`);
//! - `directives`: the VS Code Shader Toy extension's `#iChannelN` lines;
//! - `kernel`: the pass kernel (`pass.comp`) compiled with the user's tabs, each prepared by
//!   the intake `vkpath check` uses too (`crate::glsl_intake`, page shaders included), one
//!   compilation per pass with the Common tab first, messages naming their files and lines;
//! - `discard`: a fragment shader's `discard` as the kernel runs it (the texel is not written);
//! - `inputs`: ShaderToy's inputs as the kernel receives them;
//! - `runner`: the pipelines, images and frames on a device;
//! - `textures`: channel files as 2D textures and cube maps;
//! - `display`: PNG as ShaderToy shows it, EXR as the floats.

pub mod directives;
pub mod discard;
pub mod display;
pub mod inputs;
pub mod kernel;
pub mod program;
pub mod runner;
pub mod textures;

pub use program::{ChannelBinding, ChannelSource, Pass, PassKind, Program, ProgramError};
pub use runner::ShadertoyRunner;
