//! `--accel hardware` (`VK_KHR_ray_query`, `glsl/ray_query.glsl`) through the binary, on Mesa
//! 25's lavapipe, the one driver here with ray queries: its images are statistically those of
//! the software BVH (`vkpath compare`), alpha-tested materials included; `auto` keeps the
//! compressed BVH on this CPU device (its software ray queries are slower) and `render
//! --json` and the summary line say which ran; a scene beyond the structures' limits is
//! refused in one line under `hardware`; the validation layer adds nothing to what it says of the BVH's kernel.
//!
//! Only the `vkpath` processes these tests start see Mesa 25: `scripts/test.sh` fetches it
//! apart (`scripts/mesa25.sh`) and names its ICD in `VKPATH_RAY_QUERY_ICD`, and each run here
//! gives it to its child through `VK_DRIVER_FILES`. Every other test stays on the system's
//! Mesa 22.3. Without the variable (a plain `cargo test`) the Mesa 25 tests say on stderr that
//! they did not run and why; the test of a device without ray queries runs on the default
//! driver, Mesa 22.3 (a default device with ray queries would fail it).

use std::path::Path;

use crate::common;
use crate::common::runs::{run, Run};

/// The variable that names Mesa 25's ICD file (`scripts/test.sh` sets it).
const ICD_VARIABLE: &str = "VKPATH_RAY_QUERY_ICD";

/// Mesa 25's ICD file, or `None` after saying loudly on stderr that `test` did not run.
fn ray_query_icd(test: &str) -> Option<String> {
    match std::env::var(ICD_VARIABLE) {
        Ok(icd) if !icd.is_empty() => Some(icd),
        _ => {
            eprintln!(
                "\n*** {test}: NOT RUN: {ICD_VARIABLE} is unset, so no driver with ray queries is \
                 known. Run scripts/test.sh, or `{ICD_VARIABLE}=$(bash scripts/mesa25.sh) cargo \
                 test --test cli ray_query_cli::` (fetches Mesa 25's lavapipe apart). ***\n"
            );
            None
        }
    }
}

/// Runs `vkpath ARGS` in `dir` on Mesa 25 (`icd`), with `env` besides.
fn run_on(icd: &str, dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Run {
    let mut all = vec![("VK_DRIVER_FILES", icd)];
    all.extend_from_slice(env);
    run(dir, args, &all)
}

/// Renders with `args` into `dir` on Mesa 25 and returns the JSON report; fails the test
/// when the render fails.
fn render_json(icd: &str, dir: &Path, args: &[&str]) -> serde_json::Value {
    let mut full = vec!["render", "--json"];
    full.extend_from_slice(args);
    let run = run_on(icd, dir, &full, &[]);
    assert_eq!(run.code, Some(0), "vkpath {full:?}: {}", run.stderr);
    run.json()
}

/// `vkpath compare A B` in `dir` (with moments in both: each image's noise enters the
/// statistic, so the reference need not be the less noisy one); true when consistent.
fn consistent(dir: &Path, a: &str, b: &str) -> bool {
    let output = common::vkpath(dir, &["compare", a, b]);
    println!(
        "compare {a} {b} -> {:?}\n{}{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    match output.status.code() {
        Some(0) => true,
        Some(1) => false,
        other => panic!("compare {a} {b} could not judge ({other:?})"),
    }
}

/// Renders `scene_args` with each `--accel` of `accels` into `NAME.exr` with moments: PCG
/// samples (independent, as the z-test assumes), a different seed per render so that the
/// images' noise is independent too.
fn render_accels(icd: &str, dir: &Path, scene_args: &[&str], renders: &[(&str, &str, &[&str])]) {
    for (seed, (name, accel, extra)) in renders.iter().enumerate() {
        let seed = (seed + 1).to_string();
        let output = format!("{name}.exr");
        let mut args = vec![
            "--accel",
            accel,
            "--sampler",
            "pcg",
            "--moments",
            "--seed",
            &seed,
            "-o",
            &output,
        ];
        args.extend_from_slice(scene_args);
        args.extend_from_slice(extra);
        let report = render_json(icd, dir, &args);
        assert_eq!(report["accel"], *accel, "{report}");
    }
}

#[test]
fn hardware_renders_are_those_of_the_bvh() {
    let Some(icd) = ray_query_icd("hardware_renders_are_those_of_the_bvh") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // 2 000 random triangles with emitters, 32x32 at 256 spp: 16 blocks of 8x8 pixels, 48
    // z-tests at a family-wise alpha of 1 % (compare's default).
    let scene = [
        "--generated",
        "2000",
        "--width",
        "32",
        "--height",
        "32",
        "--spp",
        "256",
    ];
    render_accels(
        &icd,
        dir.path(),
        &scene,
        &[
            ("hardware", "hardware", &[]),
            ("bvh", "bvh", &[]),
            // A biased image: paths cut after 2 vertices lose the light of longer ones
            ("short", "bvh", &["--max-path-length", "2"]),
        ],
    );
    assert!(
        consistent(dir.path(), "hardware.exr", "bvh.exr"),
        "the hardware render is not the BVH's"
    );
    // The same statistic finds a difference of that size: the test above could fail
    assert!(
        !consistent(dir.path(), "short.exr", "hardware.exr"),
        "compare cannot tell a render that loses the 3rd vertex's light from the hardware's"
    );
}

#[test]
fn alpha_tested_materials_render_as_on_the_bvh() {
    let Some(icd) = ray_query_icd("alpha_tested_materials_render_as_on_the_bvh") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // scenes/materials.gltf has an alpha-masked and an alpha-blended material: the hardware
    // structures hold non-opaque geometry there and the kernel's candidate loop tests alpha.
    let scene_file = format!("{}/scenes/materials.gltf", env!("CARGO_MANIFEST_DIR"));
    let scene = [
        scene_file.as_str(),
        "--width",
        "48",
        "--height",
        "32",
        "--spp",
        "64",
    ];
    render_accels(
        &icd,
        dir.path(),
        &scene,
        &[("hardware", "hardware", &[]), ("bvh", "bvh", &[])],
    );
    assert!(
        consistent(dir.path(), "hardware.exr", "bvh.exr"),
        "the hardware render of alpha-tested materials is not the BVH's"
    );
}

#[test]
fn auto_keeps_the_bvh_on_a_cpu_device_and_hardware_takes_its_ray_queries() {
    let Some(icd) =
        ray_query_icd("auto_keeps_the_bvh_on_a_cpu_device_and_hardware_takes_its_ray_queries")
    else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let small = ["--width", "8", "--height", "8", "--spp", "1", "-o", "a.png"];
    let accel_of = |extra: &[&str]| {
        let mut args = small.to_vec();
        args.extend_from_slice(extra);
        let report = render_json(&icd, dir.path(), &args);
        (report["accel"].clone(), report["scene_memory"].clone())
    };
    // `devices` says the device has ray queries; it is a CPU device
    let devices = run_on(&icd, dir.path(), &["devices", "--json"], &[]).json();
    assert_eq!(devices[0]["ray_queries"], true, "{devices}");
    // 1 000 triangles: the BVH's size. Mesa 25's ray queries run in software, about 4x
    // slower than the compressed BVH (issue 58): `auto` keeps the compressed BVH on a CPU
    // device, and the summary line says so
    let mut args = vec!["render", "--generated", "1000"];
    args.extend_from_slice(&small);
    let auto = run_on(&icd, dir.path(), &args, &[]);
    assert_eq!(auto.code, Some(0), "{}", auto.stderr);
    let summary = auto.stderr.lines().last().unwrap_or_default();
    assert!(summary.contains("traversal compressed BVH"), "{summary}");
    let (accel, memory) = accel_of(&["--generated", "1000"]);
    assert_eq!(accel, "bvh", "{memory}");
    assert_eq!(memory["traversal"], "compressed BVH");
    // --accel hardware takes the device's ray queries
    let (accel, memory) = accel_of(&["--generated", "1000", "--accel", "hardware"]);
    assert_eq!(accel, "hardware", "{memory}");
    assert_eq!(memory["traversal"], "ray queries");
    assert!(
        memory["hardware_structure_bytes"].as_u64().unwrap() > 0,
        "{memory}"
    );
    assert_eq!(memory["bvh_node_bytes"], 0, "{memory}");
    // The Cornell box's 30 triangles stay compiled into the kernel
    assert_eq!(accel_of(&[]).0, "none");
    // --accel bvh is the BVH, and --accel hardware the hardware however small the scene
    assert_eq!(
        accel_of(&["--generated", "1000", "--accel", "bvh"]).0,
        "bvh"
    );
    assert_eq!(accel_of(&["--accel", "hardware"]).0, "hardware");
}

#[test]
fn the_structures_follow_an_animation() {
    let Some(icd) = ray_query_icd("the_structures_follow_an_animation") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // A quad that slides from x = -1 to x = 1 in a second, lit by a white background: every
    // frame loads the scene at its time, so its structures are built again
    crate::frames_cli::write_animated_quad(dir.path());
    for accel in ["hardware", "bvh"] {
        let output = format!("{accel}_##.exr");
        let args = [
            "render",
            "animated.gltf",
            "--frames",
            "0..3",
            "--fps",
            "2",
            "-o",
            &output,
            "--width",
            "32",
            "--height",
            "32",
            "--spp",
            "4",
            "--background",
            "1,1,1",
            "--accel",
            accel,
        ];
        let run = run_on(&icd, dir.path(), &args, &[]);
        assert_eq!(run.code, Some(0), "{}", run.stderr);
    }
    let read = |name: &str| common::runs::exr_bits(dir.path(), name);
    assert_ne!(
        read("hardware_00.exr"),
        read("hardware_02.exr"),
        "the quad did not move"
    );
    // Each frame is the BVH's, bit for bit: the same quad's two triangles found, the same
    // t (the workshop's triangle test of the hit triangle), the same shading
    for frame in ["00", "01", "02"] {
        let (hardware, bvh) = (format!("hardware_{frame}.exr"), format!("bvh_{frame}.exr"));
        let output = common::vkpath(dir.path(), &["compare", "--exact", &hardware, &bvh]);
        assert!(
            output.status.success(),
            "frame {frame}: {}",
            String::from_utf8_lossy(&output.stdout)
        );
    }
}

/// Writes `nodes.gltf` (and `nodes.bin`) into `dir`: one quad mesh drawn by three nodes, the
/// left one moved, the middle one turned 30 degrees about +Z and shrunk, the right one
/// mirrored (scale -1 in x), seen by a camera at z = 3 looking down -Z.
fn write_instanced_quads(dir: &Path) {
    let positions: [f32; 12] = [
        -0.5, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5, 0.5, 0.0, -0.5, 0.5, 0.0,
    ];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let mut bytes: Vec<u8> = positions.iter().flat_map(|x| x.to_le_bytes()).collect();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let document = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"name": "left", "mesh": 0, "translation": [-1.2, 0.1, 0.0]},
            {"name": "middle", "mesh": 0, "rotation": [0.0, 0.0, 0.258819, 0.965926],
             "scale": [0.8, 0.8, 0.8]},
            {"name": "right", "mesh": 0, "translation": [1.2, -0.1, 0.0], "scale": [-1.0, 1.0, 1.0]},
            {"name": "camera", "camera": 0, "translation": [0, 0, 3]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": "nodes.bin", "byteLength": bytes.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 12},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-0.5, -0.5, 0.0], "max": [0.5, 0.5, 0.0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
    });
    std::fs::write(dir.join("nodes.bin"), &bytes).unwrap();
    std::fs::write(dir.join("nodes.gltf"), document.to_string()).unwrap();
}

#[test]
fn a_mesh_that_several_nodes_draw_is_one_bottom_level_with_instances() {
    let Some(icd) = ray_query_icd("a_mesh_that_several_nodes_draw_is_one_bottom_level") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    write_instanced_quads(dir.path());
    let mut reports = Vec::new();
    for accel in ["hardware", "bvh"] {
        let output = format!("{accel}.exr");
        let args = [
            "nodes.gltf",
            "-o",
            &output,
            "--width",
            "48",
            "--height",
            "32",
            "--spp",
            "4",
            "--background",
            "1,1,1",
            "--accel",
            accel,
        ];
        reports.push(render_json(&icd, dir.path(), &args));
    }
    let memory = &reports[0]["scene_memory"];
    // The left and middle copies share the mesh's structure; the mirrored one (its vertices
    // reordered to keep its front) gets its own
    assert_eq!(memory["hardware_instances"], 3, "{memory}");
    assert_eq!(memory["hardware_bottom_levels"], 2, "{memory}");
    // The BVH's image: each instance's transform puts its triangles where the flattened
    // scene has them (the hit's t is recomputed on the world-space triangle, so rounding in
    // the transform could only move a hit across a triangle's edge: none does here)
    let output = common::vkpath(
        dir.path(),
        &["compare", "--exact", "hardware.exr", "bvh.exr"],
    );
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stdout)
    );
}

#[test]
fn a_scene_beyond_the_limits_is_refused_under_hardware() {
    let Some(icd) = ray_query_icd("a_scene_beyond_the_limits_is_refused_under_hardware") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // The structures may hold 500 triangles; the scene has about 1 000
    let limit = [("VKPATH_RAY_QUERY_MAX_PRIMITIVES", "500")];
    let args = |accel| {
        vec![
            "render",
            "--generated",
            "1000",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
            "-o",
            "a.png",
            "--accel",
            accel,
            "--json",
        ]
    };
    // `auto` on this CPU device takes the BVH without asking the structures (on a
    // hardware device it falls back to the BVH with one warning: not testable here)
    let auto = run_on(&icd, dir.path(), &args("auto"), &limit);
    assert_eq!(auto.code, Some(0), "{}", auto.stderr);
    assert_eq!(auto.json()["accel"], "bvh");
    assert!(!auto.stderr.contains("WARN"), "{}", auto.stderr);
    let hardware = run_on(&icd, dir.path(), &args("hardware"), &limit);
    assert_eq!(hardware.code, Some(1), "{}", hardware.stderr);
    let errors: Vec<&str> = hardware
        .stderr
        .lines()
        .filter(|line| line.starts_with("vkpath: error:"))
        .collect();
    assert_eq!(errors.len(), 1, "{}", hardware.stderr);
    assert!(
        errors[0].contains("--accel hardware cannot hold the scene") && errors[0].contains("500"),
        "{}",
        errors[0]
    );
}

/// The validation layer's messages of a `--validate` render on Mesa 25 (a Vulkan 1.4 device,
/// whose SPIR-V rules the layer applies) with `accel`: how many message headers it printed.
/// The command fails when the layer reported anything.
fn validation_messages(icd: &str, dir: &Path, accel: &str) -> (usize, Option<i32>) {
    let args = [
        "render",
        "--generated",
        "1000",
        "--width",
        "8",
        "--height",
        "8",
        "--spp",
        "2",
        "-o",
        "a.png",
        "--validate",
        "--accel",
        accel,
    ];
    let run = run_on(icd, dir, &args, &[]);
    println!("{accel}: {}", run.stderr);
    let headers = run
        .stderr
        .lines()
        .filter(|line| line.contains("vkpath::vk::validation"))
        .count();
    (headers, run.code)
}

#[test]
fn the_validation_layer_says_nothing_of_the_ray_queries() {
    let Some(icd) = ray_query_icd("the_validation_layer_says_nothing_of_the_ray_queries") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    // Silent for the device features, the structures' builds, their descriptor and the
    // queries, and for the BVH's kernel on the same device (the texel buffers are
    // `utextureBuffer`s: a sampled image of a buffer, `usamplerBuffer`, drew a SPIR-V
    // warning from the layer on Vulkan 1.4 devices)
    for accel in ["hardware", "bvh"] {
        assert_eq!(
            validation_messages(&icd, dir.path(), accel),
            (0, Some(0)),
            "{accel}"
        );
    }
}

#[test]
fn hardware_without_ray_queries_is_one_line_naming_the_device() {
    // The default driver (Mesa 22.3's lavapipe) has no ray queries
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render", "--width", "8", "--height", "8", "--spp", "1", "-o", "a.png", "--accel",
        "hardware",
    ];
    let run = run(dir.path(), &args, &[]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    let devices = common::runs::run(dir.path(), &["devices", "--json"], &[]).json();
    assert_eq!(devices[0]["ray_queries"], false, "{devices}");
    let errors: Vec<&str> = run
        .stderr
        .lines()
        .filter(|line| line.starts_with("vkpath: error:"))
        .collect();
    assert_eq!(errors.len(), 1, "{}", run.stderr);
    assert!(
        errors[0].contains("--accel hardware needs ray queries")
            && errors[0].contains("llvmpipe")
            && errors[0].contains("lacks VK_KHR_acceleration_structure"),
        "{}",
        errors[0]
    );
}
