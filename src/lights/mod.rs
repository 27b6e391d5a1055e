//! The scene's lights on the host, in one room: what each kind of light is, the list of all
//! of a scene's lights that the renderer uploads (`SceneLights`), and how each kind is packed
//! into the words the shaders read. One file, one job:
//!
//! - `emissive`: the emissive triangles' power-proportional table (`EmissiveTriangles`) and
//!   the luminance that weights it;
//! - `environment`: the light from infinitely far away (`Environment`: a map or a constant
//!   colour) and reading an equirectangular map;
//! - `light_tree`: the light tree over the emissive triangles (`--light-selection tree`),
//!   built here and traversed by `glsl/light_tree.glsl`;
//! - `alias_table`: the alias table that importance-samples an environment map;
//! - `environment_source`: the environment a user asks for (`--environment`,
//!   `--background`, Python's `environment=`), checked in one place and loaded into an
//!   `Environment` (the scene description's, see `crate::scene::SceneDescription`);
//! - `punctual`: KHR_lights_punctual's point, spot and directional lights;
//! - `selection`: `LightSelection`, how nee and mis choose the emissive triangle they sample
//!   (`--light-selection`);
//! - `scene_lights`: the list of kinds: `SceneLights`, every light of a scene as the renderer
//!   uploads it, and what the variant room reads of them; `LightsDigest`, the digests by
//!   which a sequence keeps a kind's buffer; `LightBuffers`, the lights' own buffers on the
//!   device, one per kind, and the emissive triangles' selection words;
//! - `gpu_emissive`, `gpu_environment`, `gpu_punctual`: each kind's words as
//!   `glsl/emissive_lights.glsl`, `glsl/environment.glsl` and
//!   `glsl/punctual_lights.glsl` read them (the CPU twins in `crate::cpu` read the same
//!   words).
//!
//! A new kind of light is a file for the kind, a file for its words, its rows in
//! `scene_lights` (a field of `SceneLights`, its flag in `SceneLights::summary`, its digest
//! in `LightsDigest` if a sequence may keep it, its buffer in `LightBuffers`: a field, its
//! upload, an arm of `LightBuffers::resource`, a term of `byte_size`), a field of
//! `crate::scene::Scene` (which carries the description) and its binding
//! (`crate::kernels::bindings`, `glsl/shared.h`); the renderer (`crate::render`) holds one
//! `LightBuffers` and names no kind (a test in `crate::house` fails if it does). On the GLSL
//! side, its file and a sampler in `glsl/lights.glsl` (`docs/house.md` counts the files, and
//! `crate::house` holds the count).

pub mod alias_table;
pub mod emissive;
pub mod environment;
pub mod environment_source;
pub mod gpu_emissive;
pub mod gpu_environment;
pub mod gpu_punctual;
pub mod light_tree;
pub mod punctual;
pub mod scene_lights;
pub mod selection;

pub use emissive::{luminance, EmissiveTriangles};
pub use environment::{Environment, EnvironmentMap};
pub use environment_source::EnvironmentSource;
pub use light_tree::LightKeys;
pub use punctual::{PunctualKind, PunctualLight};
pub use scene_lights::{
    hash_description, KeptLightBuffers, LightBuffers, LightReuse, LightsDigest, SameLights,
    SceneLights,
};
pub use selection::LightSelection;
