//! What scripts read (issue 21): one `render --json` schema whatever the devices, `--quiet`
//! silent on success, a warning for each option without effect, several outputs from one
//! render, `wrote PATH` for every file, and the command line's names in EXR metadata.

use crate::common;

use std::collections::BTreeSet;
use std::path::Path;

/// Runs vkpath, expects success, returns (stdout, stderr).
fn vkpath_ok(dir: &Path, args: &[&str]) -> (String, String) {
    let output = common::vkpath(dir, args);
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(output.status.success(), "{args:?}: {stderr}");
    (String::from_utf8_lossy(&output.stdout).to_string(), stderr)
}

/// A tiny render's arguments with `extra` appended.
fn tiny<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["render", "--width", "16", "--height", "8", "--spp", "8"];
    args.extend_from_slice(extra);
    args
}

/// The keys of a JSON object, nested objects' (and the first array element's) as "a.b".
fn keys(value: &serde_json::Value, prefix: &str, out: &mut BTreeSet<String>) {
    match value {
        serde_json::Value::Object(map) => {
            for (key, inner) in map {
                let name = format!("{prefix}{key}");
                out.insert(name.clone());
                keys(inner, &format!("{name}."), out);
            }
        }
        serde_json::Value::Array(items) => {
            if let Some(first) = items.first() {
                keys(first, prefix, out);
            }
        }
        _ => {}
    }
}

#[test]
fn json_has_one_schema_for_one_device_and_for_two() {
    let dir = tempfile::tempdir().unwrap();
    let (one, _) = vkpath_ok(dir.path(), &tiny(&["-o", "one.exr", "--json"]));
    let (two, _) = vkpath_ok(
        dir.path(),
        &tiny(&["-o", "two.exr", "--json", "--device", "0,0"]),
    );
    let one: serde_json::Value = serde_json::from_str(one.trim()).unwrap();
    let two: serde_json::Value = serde_json::from_str(two.trim()).unwrap();
    let (mut a, mut b) = (BTreeSet::new(), BTreeSet::new());
    keys(&one, "", &mut a);
    keys(&two, "", &mut b);
    assert_eq!(a, b, "one device: {one}\ntwo devices: {two}");
    for key in [
        "schema_version",
        "outputs",
        "scene",
        "width",
        "height",
        "integrator",
        "sampler",
        "spp_requested",
        "spp_taken",
        "sample_range",
        "resumed_spp",
        "setup_seconds",
        "render_seconds",
        "samples_per_second",
        "devices.name",
        "devices.type",
        "devices.index",
        "devices.spp",
        "stop",
        "checkpoint",
        "preview",
    ] {
        assert!(a.contains(key), "{key} missing from {one}");
    }
    assert_eq!(one["schema_version"], 1);
    assert_eq!(one["scene"], "builtin:cornell-box");
    assert_eq!(
        (one["width"].as_u64(), one["height"].as_u64()),
        (Some(16), Some(8))
    );
    // The default: mis with Sobol points.
    assert_eq!(
        (one["integrator"].as_str(), one["sampler"].as_str()),
        (Some("mis"), Some("sobol"))
    );
    assert_eq!(one["spp_taken"], 8);
    assert_eq!(one["devices"][0]["type"], "cpu");
    assert_eq!(two["devices"].as_array().unwrap().len(), 2);
    assert_eq!(two["spp_taken"], 8);
}

#[test]
fn a_resumed_finished_checkpoint_counts_no_samples_as_this_runs() {
    let dir = tempfile::tempdir().unwrap();
    vkpath_ok(
        dir.path(),
        &tiny(&["-o", "a.exr", "--quiet", "--checkpoint", "ck.exr"]),
    );
    let (json, _) = vkpath_ok(
        dir.path(),
        &tiny(&["-o", "b.exr", "--json", "--resume", "ck.exr"]),
    );
    let report: serde_json::Value = serde_json::from_str(json.trim()).unwrap();
    assert_eq!(report["resumed_spp"], 8, "{report}");
    assert_eq!(report["spp_taken"], 8, "{report}");
    assert_eq!(report["samples_per_second"], 0.0, "{report}");
    assert_eq!(report["devices"][0]["spp"], 0, "{report}");
}

#[test]
fn quiet_prints_nothing_on_success() {
    let dir = tempfile::tempdir().unwrap();
    let output = common::vkpath(dir.path(), &tiny(&["-o", "out.png", "--quiet"]));
    assert!(output.status.success());
    assert_eq!(String::from_utf8_lossy(&output.stderr), "", "stderr");
    assert_eq!(String::from_utf8_lossy(&output.stdout), "", "stdout");
    assert!(dir.path().join("out.png").is_file());
}

#[test]
fn options_without_effect_are_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    for (extra, expected) in [
        (
            vec!["-o", "a.png", "--aov", "albedo"],
            "--aov has no effect",
        ),
        (vec!["-o", "a.png", "--moments"], "--moments has no effect"),
        (
            vec!["-o", "a.exr", "--tonemap", "aces"],
            "--tonemap has no effect",
        ),
        (
            vec!["-o", "a.exr", "--exposure", "1"],
            "--exposure has no effect",
        ),
        (
            vec![
                "-o",
                "a.exr",
                "--integrator",
                "workshop",
                "--sampler",
                "sobol",
            ],
            "--sampler sobol has no effect with --integrator workshop",
        ),
        (
            vec!["-o", "a.exr", "--environment-strength", "2"],
            "--environment-strength has no effect without --environment",
        ),
    ] {
        let (_, stderr) = vkpath_ok(dir.path(), &tiny(&extra));
        let warnings: Vec<&str> = stderr.lines().filter(|l| l.contains("warning")).collect();
        assert_eq!(warnings.len(), 1, "{extra:?}: {stderr}");
        assert!(warnings[0].contains(expected), "{extra:?}: {stderr}");
    }
    // The same options where they do something: no warning.
    let (_, stderr) = vkpath_ok(
        dir.path(),
        &tiny(&[
            "-o",
            "b.png",
            "-o",
            "b.exr",
            "--moments",
            "--tonemap",
            "aces",
            "--aov",
            "depth",
        ]),
    );
    assert!(!stderr.contains("warning"), "{stderr}");
}

#[test]
fn several_outputs_come_from_one_render() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let (_, stderr) = vkpath_ok(path, &tiny(&["-o", "both.exr", "-o", "both.png"]));
    for file in ["both.exr", "both.png"] {
        assert!(
            stderr.contains(&format!("vkpath: wrote {file}")),
            "{stderr}"
        );
    }
    vkpath_ok(path, &tiny(&["-o", "alone.exr", "--quiet"]));
    vkpath_ok(path, &tiny(&["-o", "alone.png", "--quiet"]));
    let output = common::vkpath(path, &["compare", "--exact", "both.exr", "alone.exr"]);
    assert!(output.status.success(), "the EXR is the single render's");
    assert_eq!(
        std::fs::read(path.join("both.png")).unwrap(),
        std::fs::read(path.join("alone.png")).unwrap(),
        "the PNG is the single render's"
    );
    // One name twice is refused before rendering.
    let output = common::vkpath(path, &tiny(&["-o", "x.exr", "-o", "x.exr"]));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("given twice"), "{stderr}");
}

#[test]
fn every_file_written_is_named_and_metadata_uses_command_line_names() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let (_, stderr) = vkpath_ok(
        path,
        &tiny(&[
            "-o",
            "w.exr",
            "--integrator",
            "workshop",
            "--pixel-filter",
            "center",
        ]),
    );
    assert!(stderr.contains("vkpath: wrote w.exr"), "{stderr}");
    // The header's `vkpath` attribute is plain text in the file.
    let bytes = std::fs::read(path.join("w.exr")).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    for field in [
        "integrator=workshop",
        "sampler=pcg",
        "light_sampling=solid-angle",
        "pixel_filter=center",
    ] {
        assert!(text.contains(field), "{text} lacks {field}");
    }
    // A resume of other settings names the difference as the command line does.
    vkpath_ok(
        path,
        &tiny(&["-o", "m.exr", "--quiet", "--checkpoint", "ck.exr"]),
    );
    let output = common::vkpath(
        path,
        &tiny(&["-o", "r.exr", "--integrator", "nee", "--resume", "ck.exr"]),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("integrator: mis vs nee"), "{stderr}");
    // The sample displays, a heat map and an export say what they wrote.
    let (_, stderr) = vkpath_ok(path, &["exercise", "sample-sphere", "-o", "s.png"]);
    assert!(stderr.contains("vkpath: wrote s.png"), "{stderr}");
    let (_, stderr) = vkpath_ok(path, &["compare", "w.exr", "w.exr", "--heatmap", "h.png"]);
    assert!(stderr.contains("vkpath: wrote h.png"), "{stderr}");
    let (_, stderr) = vkpath_ok(path, &["export", "--output-dir", "box"]);
    let written = stderr
        .lines()
        .filter(|l| l.starts_with("vkpath: wrote box/"))
        .count();
    let files = std::fs::read_dir(path.join("box")).unwrap().count();
    assert_eq!(written, files, "{stderr}");
    assert!(
        !stderr.contains("note"),
        "plain materials need no note: {stderr}"
    );
    // Glass is not exported as opaque plastic in silence: its transmission factors are in
    // the manifest, and one note names the layered materials.
    let glass = format!("{}/scenes/glass.gltf", env!("CARGO_MANIFEST_DIR"));
    let (_, stderr) = vkpath_ok(path, &["export", &glass, "--output-dir", "glass"]);
    let notes: Vec<&str> = stderr.lines().filter(|l| l.contains("note")).collect();
    assert_eq!(notes.len(), 1, "{stderr}");
    assert!(notes[0].contains(": transmission"), "{}", notes[0]);
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(path.join("glass/scene.json")).unwrap()).unwrap();
    let transmitting = manifest["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|mesh| mesh["material"]["transmission"]["factor"].as_f64() > Some(0.0))
        .count();
    assert!(transmitting > 0, "{manifest}");
    // Issue 58: an animated file's export was silent about its animations; one note says
    // which were dropped and which pose the meshes hold.
    let animated = common::fixture("BoxAnimated.gltf");
    let (_, stderr) = vkpath_ok(path, &["export", &animated, "--output-dir", "animated"]);
    let notes: Vec<&str> = stderr.lines().filter(|l| l.contains("note")).collect();
    assert_eq!(notes.len(), 1, "{stderr}");
    assert!(
        notes[0].contains("2 animations are ('#0', '#1') not exported")
            && notes[0].contains("time 0 s"),
        "{}",
        notes[0]
    );
}

#[test]
fn exercise_help_lists_general_options_before_the_brdf_ones() {
    let dir = tempfile::tempdir().unwrap();
    let (help, _) = vkpath_ok(dir.path(), &["exercise", "--help"]);
    let lines: Vec<&str> = help.lines().collect();
    // The line that defines an option (not a mention of it in another's help).
    let defined = |flag: &str| {
        lines
            .iter()
            .position(|l| l.trim_start().starts_with(flag))
            .unwrap_or_else(|| panic!("{flag} in {help}"))
    };
    let heading = lines
        .iter()
        .position(|l| l.starts_with("brdf-samples:"))
        .expect("a brdf-samples heading");
    for general in ["--tonemap", "--device", "--validate"] {
        assert!(
            defined(general) < heading,
            "{general} is listed under brdf-samples:\n{help}"
        );
    }
    assert!(defined("--metallic") > heading, "{help}");
}

/// `render --json`'s `scene_memory` (issue 39): the acceleration structure's bytes are the
/// BVH's 112-byte nodes plus 48 bytes of positions per triangle for its triangle tests (the
/// compressed BVH's 80-byte nodes plus 36 bytes), and
/// every scene buffer is counted in `scene_bytes` (at least the 96-byte triangles besides);
/// the box compiled into the kernel has no acceleration structure.
#[test]
fn json_reports_what_the_scene_takes_on_the_device() {
    let dir = tempfile::tempdir().unwrap();
    let memory = |accel: &str, output: &str| {
        let (stdout, _) = vkpath_ok(
            dir.path(),
            &tiny(&["--accel", accel, "-o", output, "--json"]),
        );
        let report: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        report["scene_memory"].clone()
    };
    let bvh = memory("bvh", "bvh.exr");
    assert_eq!(bvh["traversal"], "BVH", "{bvh}");
    assert_eq!(bvh["triangle_count"], 30, "{bvh}");
    let nodes = bvh["bvh_node_bytes"].as_u64().unwrap();
    let positions = bvh["traversal_triangle_bytes"].as_u64().unwrap();
    assert!(nodes > 0 && nodes % 112 == 0, "{bvh}");
    assert_eq!(positions, 48 * 30, "{bvh}");
    let per_triangle = bvh["acceleration_bytes_per_triangle"].as_f64().unwrap();
    assert!(
        (per_triangle - (nodes + positions) as f64 / 30.0).abs() < 1e-9,
        "{bvh}"
    );
    let scene = bvh["scene_bytes"].as_u64().unwrap();
    assert!(scene >= nodes + positions + 96 * 30, "{bvh}");
    let scene_per_triangle = bvh["scene_bytes_per_triangle"].as_f64().unwrap();
    assert!(
        (scene_per_triangle - scene as f64 / 30.0).abs() < 1e-9,
        "{bvh}"
    );

    // The compressed tree: 80-byte nodes, positions packed 36 bytes apiece (whole texels)
    let compressed = memory("compressed-bvh", "compressed.exr");
    assert_eq!(compressed["traversal"], "compressed BVH", "{compressed}");
    let compressed_nodes = compressed["bvh_node_bytes"].as_u64().unwrap();
    assert!(
        compressed_nodes > 0 && compressed_nodes % 80 == 0,
        "{compressed}"
    );
    assert_eq!(
        compressed["traversal_triangle_bytes"],
        (36 * 30u64).div_ceil(16) * 16,
        "{compressed}"
    );
    assert!(
        compressed["acceleration_bytes_per_triangle"]
            .as_f64()
            .unwrap()
            < per_triangle,
        "{compressed}"
    );

    let constant = memory("none", "none.exr");
    assert_eq!(constant["traversal"], "constant triangles", "{constant}");
    assert_eq!(constant["bvh_node_bytes"], 0, "{constant}");
    assert_eq!(constant["traversal_triangle_bytes"], 0, "{constant}");
    assert_eq!(
        constant["acceleration_bytes_per_triangle"], 0.0,
        "{constant}"
    );
    // The box's triangles without the BVH's buffers.
    assert!(
        constant["scene_bytes"].as_u64().unwrap() < scene - nodes - positions + 1,
        "{constant}"
    );
}
