//! The command-line tests: each runs the `vkpath` binary (with `common::vkpath`) on small
//! scenes and checks its outputs, messages and exit codes. One test binary for all of them, so
//! that the crate is linked once (issue 40: 42 binaries took 5 min 44 s of CI to build); each
//! file below is a module, run alone with `cargo test --test cli <module>::`.

mod common;

#[path = "bench_cli.rs"]
mod bench_cli;
#[path = "check_cli.rs"]
mod check_cli;
#[path = "check_pasted_cli.rs"]
mod check_pasted_cli;
#[path = "cli_errors.rs"]
mod cli_errors;
#[path = "compare_cli.rs"]
mod compare_cli;
#[path = "cryptomatte_cli.rs"]
mod cryptomatte_cli;
#[path = "depth_of_field_cli.rs"]
mod depth_of_field_cli;
#[path = "determinism.rs"]
mod determinism;
#[path = "devices_cli.rs"]
mod devices_cli;
#[path = "exercise_cli.rs"]
mod exercise_cli;
#[path = "farm_cli.rs"]
mod farm_cli;
#[path = "frames_cli.rs"]
mod frames_cli;
#[path = "gltf_fidelity_cli.rs"]
mod gltf_fidelity_cli;
#[path = "ground_truth_cli.rs"]
mod ground_truth_cli;
#[path = "hostile_input.rs"]
mod hostile_input;
#[path = "khronos_animation_cli.rs"]
mod khronos_animation_cli;
#[path = "look_cli.rs"]
mod look_cli;
#[path = "materials_cli.rs"]
mod materials_cli;
#[path = "medium_cli.rs"]
mod medium_cli;
#[path = "messages_cli.rs"]
mod messages_cli;
#[path = "motion_blur_cli.rs"]
mod motion_blur_cli;
#[path = "noise_threshold.rs"]
mod noise_threshold;
#[path = "nothing_lost.rs"]
mod nothing_lost;
#[path = "pipeline_cache.rs"]
mod pipeline_cache;
#[path = "production.rs"]
mod production;
#[path = "ray_query_cli.rs"]
mod ray_query_cli;
#[path = "region_tiles.rs"]
mod region_tiles;
#[path = "scripting_cli.rs"]
mod scripting_cli;
#[path = "sequence_cli.rs"]
mod sequence_cli;
#[path = "shadertoy_cli.rs"]
mod shadertoy_cli;
#[path = "skin_morph_cli.rs"]
mod skin_morph_cli;
#[path = "tev_live.rs"]
mod tev_live;
