//! Path guiding in renders (`--guiding`): guided images agree with unguided ones by `vkpath
//! compare` (block z-tests with both images' moments) on the Cornell box, the opening scene
//! and the glossy showcase; the same seed gives the same bits however frames are split;
//! resumed and sharded guided renders equal the single render; a signal or the time limit
//! stops training, after which it starts afresh to the same guide; a guided render reports
//! its guide; and the options that cannot work say so in one line. The validation layer stays
//! silent throughout (`--validate`, `assert_validation_silent`).

use crate::common;

use std::cell::Cell;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use vkpath::guiding::training::GuideTraining;
use vkpath::render::accumulation::Accumulation;
use vkpath::render::{RenderControl, StopReason};
use vkpath::scene::Scene;
use vkpath::{Integrator, RenderSettings, Renderer};

/// `vkpath render` in `dir` with `args`, checked for success; its `--json` report.
fn render(dir: &Path, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["render", "--validate", "--json"];
    all.extend_from_slice(args);
    let output = common::vkpath(dir, &all);
    assert!(
        output.status.success(),
        "vkpath {all:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).unwrap()
}

#[test]
fn guided_renders_agree_with_unguided_ones() {
    // Each case renders unguided (seed 1) and guided (seed 2, its default training: a quarter
    // of --spp) with moments; `vkpath compare` (8x8 blocks, family-wise alpha 0.01, so a
    // false failure has probability 0.01 per case) must find them consistent. A guide that
    // biased the estimate (a density that is not the sampler's, a mixture weight lost in an
    // MIS weight) moves the brightest blocks by many standard errors at these sample counts.
    let opening = format!("{}/scenes/opening.gltf", env!("CARGO_MANIFEST_DIR"));
    let materials = format!("{}/scenes/materials.gltf", env!("CARGO_MANIFEST_DIR"));
    let cases: [(&str, &[&str]); 4] = [
        (
            "cornell-mis",
            &[
                "--integrator",
                "mis",
                "--width",
                "32",
                "--height",
                "32",
                "--spp",
                "128",
            ],
        ),
        (
            "cornell-nee",
            &[
                "--integrator",
                "nee",
                "--width",
                "32",
                "--height",
                "32",
                "--spp",
                "128",
            ],
        ),
        (
            "opening-mis",
            &[
                &opening,
                "--integrator",
                "mis",
                "--max-path-length",
                "8",
                "--width",
                "40",
                "--height",
                "30",
                "--spp",
                "128",
            ],
        ),
        (
            "materials-mis",
            &[
                &materials,
                "--integrator",
                "mis",
                "--width",
                "32",
                "--height",
                "24",
                "--spp",
                "64",
            ],
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (name, args) in cases {
        let plain = format!("{name}.exr");
        let guided = format!("{name}-guided.exr");
        let mut unguided_args = args.to_vec();
        unguided_args.extend_from_slice(&["--seed", "1", "--moments", "-o", &plain]);
        let report = render(dir.path(), &unguided_args);
        assert!(report["guide"].is_null(), "{name}: {report}");
        let mut guided_args = args.to_vec();
        guided_args.extend_from_slice(&["--guiding", "--seed", "2", "--moments", "-o", &guided]);
        let report = render(dir.path(), &guided_args);
        let guide = &report["guide"];
        assert!(
            guide["guided_cells"].as_u64().unwrap() > 0,
            "{name}: {report}"
        );
        assert!(
            guide["memory_bytes"].as_u64().unwrap() > 0,
            "{name}: {report}"
        );
        // Where training's seconds went: three non-negative parts that add up to them (the
        // host's part is the remainder, so up to rounding in the JSON).
        let part = |key: &str| guide[key].as_f64().unwrap();
        let parts = [
            part("training_pipeline_seconds"),
            part("training_frames_seconds"),
            part("training_host_seconds"),
        ];
        assert!(parts.iter().all(|&p| p >= 0.0), "{name}: {report}");
        assert!(
            (parts.iter().sum::<f64>() - part("training_seconds")).abs() < 1e-6,
            "{name}: {report}"
        );
        assert!(part("training_frames_seconds") > 0.0, "{name}: {report}");
        let output = common::vkpath(dir.path(), &["compare", &guided, &plain]);
        assert!(
            output.status.success(),
            "{name}: guided and unguided renders differ: {}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

#[test]
fn same_seed_same_bits_with_guiding_whatever_the_frames() {
    // The training splats are integer sums (order-independent), the build is sequential and
    // the render adds samples in sample order: two guided renders with the same seed, one
    // sample per frame and seven, write identical files.
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for samples_per_frame in ["1", "7"] {
        let name = format!("spf{samples_per_frame}.exr");
        render(
            dir.path(),
            &[
                "--integrator",
                "mis",
                "--guiding",
                "--guide-training-spp",
                "15",
                "--width",
                "24",
                "--height",
                "16",
                "--spp",
                "9",
                "--seed",
                "5",
                "--samples-per-frame",
                samples_per_frame,
                "--moments",
                "-o",
                &name,
            ],
        );
        files.push(std::fs::read(dir.path().join(&name)).unwrap());
    }
    assert!(
        files[0] == files[1],
        "guided renders differ between frame splits"
    );
}

/// Settings of the resume and shard test: the Cornell box with mis, guided.
fn guided_settings(spp: u32) -> RenderSettings {
    RenderSettings {
        width: 24,
        height: 20,
        spp,
        integrator: Integrator::Mis,
        seed: 3,
        guiding: Some(GuideTraining { samples: 12 }),
        ..RenderSettings::default()
    }
}

#[test]
fn resume_and_merge_equal_the_single_guided_render() {
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let camera = scene.camera.unwrap();
    let single = {
        let mut renderer = Renderer::new(&context, &scene, &camera, guided_settings(16)).unwrap();
        renderer.render_all().unwrap();
        assert!(renderer.guide_report().unwrap().guided_cell_count > 0);
        renderer.accumulation().unwrap()
    };
    // Resume: 4 samples, saved, then a new renderer (which trains the same guide) goes on.
    let partial = {
        let settings = RenderSettings {
            samples_per_frame: 1,
            ..guided_settings(16)
        };
        let mut renderer = Renderer::new(&context, &scene, &camera, settings).unwrap();
        for _ in 0..4 {
            renderer.render_frame().unwrap();
        }
        renderer.accumulation().unwrap()
    };
    assert_eq!(partial.samples, 0..4);
    // The guide is frozen into the state, and a resumed render samples with it.
    assert!(partial.guide.is_some());
    assert_eq!(partial.guide, single.guide);
    let resume = |state: &Accumulation| {
        let mut renderer = Renderer::new(&context, &scene, &camera, guided_settings(16)).unwrap();
        renderer.resume(state).unwrap();
        renderer.render_all().unwrap();
        assert!(renderer.guide_report().unwrap().from_checkpoint);
        renderer.accumulation().unwrap()
    };
    let resumed = resume(&partial);
    assert_eq!(
        resumed.texels, single.texels,
        "resumed guided render differs"
    );
    // With another guide frozen in (one trained on 2 spp), the resumed samples follow that
    // guide, not one trained anew: the image differs from the single render's.
    let other_guide = {
        let settings = RenderSettings {
            guiding: Some(GuideTraining { samples: 2 }),
            ..guided_settings(16)
        };
        let mut renderer = Renderer::new(&context, &scene, &camera, settings).unwrap();
        renderer.train_guide().unwrap();
        renderer.accumulation().unwrap().guide
    };
    assert_ne!(other_guide, single.guide);
    let with_other_guide = resume(&Accumulation {
        guide: other_guide.clone(),
        ..partial.clone()
    });
    assert_eq!(with_other_guide.guide, other_guide);
    assert_ne!(with_other_guide.texels, single.texels);
    // Shards: samples 0..10 and 10..16, each training the same guide, merged.
    let shard = |range: std::ops::Range<u32>| {
        let mut renderer = Renderer::new(
            &context,
            &scene,
            &camera,
            guided_settings(range.len() as u32),
        )
        .unwrap();
        renderer.start_at_sample(range.start).unwrap();
        renderer.render_all().unwrap();
        renderer.accumulation().unwrap()
    };
    let merged = Accumulation::merge(&[shard(0..10), shard(10..16)]).unwrap();
    assert_eq!(merged.samples, 0..16);
    // Both shards trained the single render's guide, which the merge keeps.
    assert_eq!(merged.guide, single.guide);
    // Within the 4 ulps that `Accumulation::merge` documents for any merge (its float64 sum
    // against the single render's float32 Kahan sum); a shard with another guide would
    // differ by its noise, thousands of ulps.
    let (a, b) = (merged.image(), single.image());
    let worst = common::worst_ulps_apart(&a, &b);
    assert!(
        worst <= 4,
        "merged guided shards are {worst} ulps from the single render"
    );
    common::assert_validation_silent(&context);
}

#[test]
fn the_command_line_resumes_with_the_checkpoints_guide() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let common_args = [
        "--width",
        "24",
        "--height",
        "16",
        "--integrator",
        "mis",
        "--guiding",
        "--guide-training-spp",
        "6",
        "--seed",
        "5",
    ];
    let run = |extra: &[&str]| {
        let mut args = common_args.to_vec();
        args.extend_from_slice(extra);
        render(path, &args)
    };
    let single = run(&["--spp", "8", "-o", "single.exr"]);
    assert_eq!(single["guide"]["from_checkpoint"], false, "{single}");
    run(&["--spp", "3", "--checkpoint", "ck.exr", "-o", "part.exr"]);
    let resumed = run(&["--spp", "8", "--resume", "ck.exr", "-o", "resumed.exr"]);
    // No training: the guide comes from the checkpoint, and with it the single render's bits.
    assert_eq!(resumed["guide"]["from_checkpoint"], true, "{resumed}");
    assert_eq!(resumed["guide"]["training_seconds"], 0.0, "{resumed}");
    assert_eq!(
        resumed["guide"]["guided_cells"],
        single["guide"]["guided_cells"]
    );
    let same = common::vkpath(path, &["compare", "--exact", "resumed.exr", "single.exr"]);
    assert!(
        same.status.success(),
        "{}",
        String::from_utf8_lossy(&same.stdout)
    );
}

#[test]
fn guiding_options_that_cannot_work_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (args, expected) in [
        (
            &[
                "render",
                "--integrator",
                "cosine",
                "--guiding",
                "-o",
                "a.png",
            ][..],
            "--guiding guides nee and mis",
        ),
        (
            &[
                "render",
                "--integrator",
                "mis",
                "--guiding",
                "--guide-training-spp",
                "0",
                "-o",
                "a.png",
            ][..],
            "--guide-training-spp 0 is outside",
        ),
        (
            &[
                "render",
                "--integrator",
                "mis",
                "--guiding",
                "--sample-range",
                "0..8",
                "-o",
                "a.exr",
            ][..],
            "needs --guide-training-spp",
        ),
    ] {
        let output = common::vkpath(dir.path(), args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

#[test]
fn a_signal_or_the_time_limit_stops_training_and_a_restart_trains_the_same_guide() {
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let camera = scene.camera.unwrap();
    let single = {
        let mut renderer = Renderer::new(&context, &scene, &camera, guided_settings(8)).unwrap();
        renderer.render_all().unwrap();
        renderer.accumulation().unwrap()
    };
    let settings = RenderSettings {
        samples_per_frame: 1,
        ..guided_settings(8)
    };
    let mut renderer = Renderer::new(&context, &scene, &camera, settings).unwrap();
    // A signal before training: the render stops with nothing taken and nothing trained.
    let flag = AtomicBool::new(true);
    let control = RenderControl {
        cancel: Some(&flag),
        ..RenderControl::default()
    };
    let outcome = renderer.render_with(|_| {}, control).unwrap();
    assert_eq!((outcome.stop, outcome.samples), (StopReason::Cancelled, 0));
    assert!(outcome.guide.is_none() && renderer.guide_report().is_none());
    // A time limit already past does the same.
    let control = RenderControl {
        deadline: Some(Instant::now()),
        ..RenderControl::default()
    };
    let outcome = renderer.render_with(|_| {}, control).unwrap();
    assert_eq!((outcome.stop, outcome.samples), (StopReason::TimeLimit, 0));
    // Abandoned in its last iteration (12 spp train as 1 + 2 + 9, one submission each, so
    // the third question stops it with the guide of the first two bound), training starts
    // afresh and the render equals the uninterrupted one bit for bit.
    let asked = Cell::new(0);
    let trained = renderer
        .train_guide_until(&|| {
            asked.set(asked.get() + 1);
            asked.get() > 2
        })
        .unwrap();
    assert_eq!(asked.get(), 3);
    assert!(!trained && renderer.guide_report().is_none());
    renderer.render_all().unwrap();
    assert_eq!(renderer.accumulation().unwrap().texels, single.texels);
    common::assert_validation_silent(&context);
}

#[test]
fn guided_renders_default_to_no_russian_roulette_and_keep_a_given_start() {
    // Roulette kills the paths a guide sends towards the light (docs/guiding.md), so
    // `--guiding` without --russian-roulette-start renders without it; unguided renders
    // keep the default start of 3, and a start given on the command line is kept.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let roulette_start = |name: &str, extra: &[&str]| {
        let mut args = vec![
            "render",
            "--width",
            "12",
            "--height",
            "8",
            "--spp",
            "2",
            "--integrator",
            "mis",
            "--seed",
            "3",
            "-o",
            name,
        ];
        args.extend_from_slice(extra);
        let out = common::vkpath(path, &args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        vkpath::render::state_exr::read_metadata(&path.join(name))
            .expect("the EXR records its settings")
            .setting("russian_roulette_start")
            .expect("the settings hold russian_roulette_start")
            .to_string()
    };
    let guided = ["--guiding", "--guide-training-spp", "2"];
    assert_eq!(roulette_start("plain.exr", &[]), "3");
    assert_eq!(roulette_start("guided.exr", &guided), "0");
    let given = [&guided[..], &["--russian-roulette-start", "4"]].concat();
    assert_eq!(roulette_start("given.exr", &given), "4");
}
