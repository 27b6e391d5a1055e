//! The progressive GPU renderer and what it needs: the settings of a render, how rays find
//! triangles (`traversal`), the scene as the kernel reads it (`gpu_scene`), the structs
//! shared with the path-tracing kernel (`gpu_types`), the kernels kept between runs
//! (`pipeline_cache`) and between the renders of a sequence (`sequence`), the renderer
//! itself, and the session that the command line and Python run a render through
//! (`session`: the job's options, progress, stop and post-processing around a renderer).

pub mod accumulation;
pub mod adaptive;
pub mod aov;
pub mod converged_pixels;
pub mod cryptomatte;
pub mod gpu_materials;
pub mod gpu_motion;
pub mod gpu_scene;
pub mod gpu_textures;
pub mod gpu_types;
pub mod ground_truth;
pub mod guide_buffers;
pub mod job;
pub mod metadata;
pub mod motion_vectors;
pub mod multi;
pub mod pipeline_cache;
pub mod post_process;
pub mod region;
pub mod renderer;
pub mod sequence;
pub mod session;
pub mod settings;
pub mod state_exr;
pub mod tiles;
pub mod traversal;

pub use renderer::{RenderControl, RenderOutcome, Renderer, StopReason};
pub use session::RenderSession;
pub use settings::RenderSettings;
pub use traversal::Traversal;
