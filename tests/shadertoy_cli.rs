//! `vkpath shadertoy` through the binary on the programs of tests/solutions/programs/:
//! analytic buffers whose contents after N frames are known exactly (accumulation through a
//! buffer's own previous frame, the same-frame and previous-frame semantics between passes,
//! a Common tab, channel overrides), a page shader, compile errors naming the user's file and
//! line, and stops by signal and time limit that keep what was reached. Every run has the
//! validation layer on (the binary fails if it reports anything). Images are tiny.

use crate::common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use vkpath::image_io::exr_input::read_exr;
use vkpath::RenderedImage;

fn program(name: &str) -> String {
    format!(
        "{}/tests/solutions/programs/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// Runs `vkpath shadertoy` with `--validate`; returns (exit code, stderr).
fn shadertoy(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let mut all = vec!["shadertoy", "--validate"];
    all.extend_from_slice(args);
    let run = common::runs::run(dir, &all, &[]);
    (run.code, run.stderr)
}

/// The EXR's pixel at column x and row y counted from the bottom (as fragCoord counts),
/// with alpha: read_exr gives R, G, B, so alpha is read separately.
fn rgba(path: &Path) -> (RenderedImage, Vec<f32>) {
    let image = read_exr(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .image;
    let layer = exr::prelude::read_first_flat_layer_from_file(path).expect("EXR");
    let alpha = layer
        .layer_data
        .channel_data
        .list
        .iter()
        .find(|c| c.name.eq("A"))
        .map(|c| c.sample_data.values_as_f32().collect())
        .expect("an alpha channel");
    (image, alpha)
}

fn at(image: &(RenderedImage, Vec<f32>), x: u32, y_from_bottom: u32) -> [f32; 4] {
    let (image, alpha) = image;
    let row = image.height - 1 - y_from_bottom;
    let p = image.pixel(x, row);
    [p[0], p[1], p[2], alpha[(row * image.width + x) as usize]]
}

#[test]
fn a_buffer_accumulating_through_its_own_previous_frame_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    let frames = 7u32;
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("count_image.glsl"),
            "--buffer-a",
            &program("count_buffer_a.glsl"),
            "--frames",
            "7",
            "--width",
            "12",
            "--height",
            "5",
            "-o",
            "image.exr",
            "--save-buffer",
            "a=a.exr",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stderr.contains("wrote image.exr") && stderr.contains("wrote a.exr"),
        "{stderr}"
    );
    let n = frames as f32;
    let buffer = rgba(&dir.path().join("a.exr"));
    let image = rgba(&dir.path().join("image.exr"));
    for (x, y) in [(0, 0), (11, 0), (0, 4), (5, 2), (11, 4)] {
        let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
        // Sums of N terms, each exact in float: the buffer is exactly N x (1, x, y) plus
        // the frame indices 0 + ... + (N - 1).
        assert_eq!(
            at(&buffer, x, y),
            [n, n * fx, n * fy, n * (n - 1.0) / 2.0],
            "A at ({x}, {y})"
        );
        // The Image pass sees this frame's A (red exactly 1, not (N - 1) / N).
        assert_eq!(
            at(&image, x, y),
            [1.0, fx, fy, (n - 1.0) / 2.0],
            "Image at ({x}, {y})"
        );
    }
}

#[test]
fn two_buffers_see_this_frame_of_earlier_passes_and_the_previous_of_later_ones() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("chain_image.glsl"),
            "--common",
            &program("chain_common.glsl"),
            "--buffer-a",
            &program("chain_buffer_a.glsl"),
            "--buffer-b",
            &program("chain_buffer_b.glsl"),
            "--channel",
            "buffer-a.1=buffer-b",
            "--channel",
            "buffer-b.1=buffer-a",
            "--channel",
            "image.1=buffer-b",
            "--frames",
            "5",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "image.exr",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    assert_chain_image(&dir.path().join("image.exr"));
}

/// The chain program's image after N = 5 frames: A's red 5, A's green B's red after frame 3
/// (1+2+3+4 = 10), B's red 1+...+5 = 15, in every pixel.
fn assert_chain_image(path: &Path) {
    let image = rgba(path);
    for (x, y) in [(0, 0), (7, 7), (3, 5)] {
        assert_eq!(at(&image, x, y), [5.0, 10.0, 15.0, 1.0], "({x}, {y})");
    }
}

#[test]
fn vscode_shader_toy_directives_wire_the_channels() {
    // The chain program above as VS Code Shader Toy tabs: #iChannelN "self" /
    // "file://…glsl" instead of --channel, #include of the Common tab given, and an unknown
    // directive (#iKeyboard) dropped with a note: the same image.
    let dir = tempfile::tempdir().unwrap();
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("vscode_image.glsl"),
            "--common",
            &program("vscode_common.glsl"),
            "--buffer-a",
            &program("vscode_buffer_a.glsl"),
            "--buffer-b",
            &program("vscode_buffer_b.glsl"),
            "--frames",
            "5",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "image.exr",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    assert_chain_image(&dir.path().join("image.exr"));
}

#[test]
fn a_page_shader_runs_as_the_image_pass_and_pngs_are_clamped_not_encoded() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("page_shader_gradient.glsl"),
            "--frames",
            "1",
            "--width",
            "4",
            "--height",
            "2",
            "-o",
            "page.png",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let png = image::open(dir.path().join("page.png")).unwrap().to_rgb8();
    assert_eq!(png.dimensions(), (4, 2));
    // x / 4 at centres 0.5 .. 3.5 times 255, rounded; 0.5 -> 128 (no sRGB curve); 2 -> 255.
    let reds: Vec<u8> = (0..4).map(|x| png.get_pixel(x, 0).0[0]).collect();
    assert_eq!(reds, [32, 96, 159, 223]);
    assert_eq!(png.get_pixel(1, 1).0[1..], [128, 255]);
}

#[test]
fn compile_errors_name_the_file_and_line_and_bad_arguments_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let file = program("image_compile_error.glsl");
    let (code, stderr) = shadertoy(dir.path(), &[&file, "--frames", "1", "-o", "x.png"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains(&format!("{file}:4:")), "{stderr}");
    assert!(stderr.contains("undefined_alpha"), "{stderr}");
    assert!(!dir.path().join("x.png").exists());

    let image = program("count_image.glsl");
    for (args, expected) in [
        (
            vec![image.as_str(), "--frames", "1", "-o", "x.jpg"],
            "unsupported image format",
        ),
        (
            vec![
                image.as_str(),
                "--frames",
                "1",
                "-o",
                "x.png",
                "--channel",
                "image.0=buffer-c",
            ],
            "has no buffer-c",
        ),
        (
            vec![
                image.as_str(),
                "--frames",
                "1",
                "-o",
                "x.png",
                "--save-buffer",
                "a=a.exr",
            ],
            "has no buffer-a",
        ),
        (
            vec!["missing.glsl", "--frames", "1", "-o", "x.png"],
            "cannot read 'missing.glsl'",
        ),
        (
            vec![image.as_str(), "--frames", "0", "-o", "x.png"],
            "--frames",
        ),
    ] {
        let (code, stderr) = shadertoy(dir.path(), &args);
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}

#[test]
fn sigint_and_the_time_limit_stop_after_a_frame_and_keep_it() {
    let dir = tempfile::tempdir().unwrap();
    let (a, image) = (program("count_buffer_a.glsl"), program("count_image.glsl"));
    let args = |limit: Option<&'static str>| {
        let mut args = vec![
            "shadertoy".to_string(),
            "--validate".into(),
            image.clone(),
            "--buffer-a".into(),
            a.clone(),
            "--frames".into(),
            "10000000".into(),
            "--width".into(),
            "8".into(),
            "--height".into(),
            "8".into(),
            "-o".into(),
            "image.exr".into(),
            "--save-buffer".into(),
            "a=a.exr".into(),
        ];
        if let Some(limit) = limit {
            args.extend(["--time-limit".to_string(), limit.to_string()]);
        }
        args
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_vkpath"))
        .args(args(None))
        .current_dir(dir.path())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read stderr on a thread; once the run says it started its frames, let it run some.
    let pipe = child.stderr.take().unwrap();
    let (sender, receiver) = std::sync::mpsc::channel::<String>();
    let reader = std::thread::spawn(move || {
        use std::io::BufRead;
        let mut all = String::new();
        for line in std::io::BufReader::new(pipe).lines().map_while(Result::ok) {
            let _ = sender.send(line.clone());
            all.push_str(&line);
            all.push('\n');
        }
        all
    });
    let started = Instant::now();
    while !receiver
        .recv_timeout(Duration::from_secs(60))
        .is_ok_and(|line| line.contains("running"))
    {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "the run never started"
        );
    }
    std::thread::sleep(Duration::from_millis(500));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    let stderr = reader.join().unwrap();
    assert_eq!(status.code(), Some(130), "128 + SIGINT: {stderr}");
    let frames: f32 = stderr
        .split("stopped by SIGINT after ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no frame count: {stderr}"));
    assert!(frames >= 1.0, "{stderr}");
    // The buffer holds exactly the frames reached.
    assert_eq!(at(&rgba(&dir.path().join("a.exr")), 3, 3)[0], frames);

    let started = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_vkpath"))
        .args(args(Some("1")))
        .current_dir(dir.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("stopped by --time-limit"), "{stderr}");
    // Start-up (device, compiling) comes on top of the limit; the frames are short.
    assert!(started.elapsed() < Duration::from_secs(30));
    let image = rgba(&dir.path().join("image.exr"));
    assert_eq!(
        at(&image, 0, 0)[0],
        1.0,
        "the Image pass of the last frame reached"
    );
}

/// `vkpath check --json` on a program fixture (32 x 32 renders, as tests/check_cli.rs);
/// returns the exit code, the `program` entry and stderr.
fn check_program(name: &str) -> (Option<i32>, serde_json::Value, serde_json::Value) {
    check_program_with(name, &[])
}

/// `check_program` with more arguments.
fn check_program_with(
    name: &str,
    extra: &[&str],
) -> (Option<i32>, serde_json::Value, serde_json::Value) {
    check_program_env(name, extra, &[])
}

/// `check_program_with` with extra environment variables.
fn check_program_env(
    name: &str,
    extra: &[&str],
    env: &[(&str, &str)],
) -> (Option<i32>, serde_json::Value, serde_json::Value) {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec!["--json"];
    args.extend_from_slice(extra);
    let run = common::runs::check(dir.path(), &[program(name)], &args, env);
    let report = run.json();
    let entry = common::runs::verdict(&report, "program")
        .or_else(|| {
            report["lost"]
                .as_array()
                .and_then(|lost| lost.iter().find(|l| l["function"] == "program").cloned())
        })
        .unwrap_or_else(|| panic!("{name}: no program verdict: {}", run.stdout));
    (run.code, entry, report)
}

#[test]
fn check_passes_the_exercise_7_tab_with_a_correct_intersection() {
    let (_, program, report) = check_program("exercise7_tab.glsl");
    assert_eq!(program["passed"], true, "{program:#}");
    assert_eq!(program["method"], "render");
    // Every other function of the tab passes too.
    for function in report["functions"].as_array().unwrap() {
        assert_eq!(function["passed"], true, "{function:#}");
    }
}

#[test]
fn check_fails_the_slides_tab_and_names_self_intersection() {
    // 16 frames (128 samples per pixel) with `--frames`: the slides' tab is about 35% dark,
    // far more than the noise of 16 frames' means (the default 128 frames is for small biases).
    let (code, program, _) =
        check_program_with("exercise7_tab_self_intersection.glsl", &["--frames", "16"]);
    assert_eq!(code, Some(1));
    let detail = program["tolerance"].as_str().unwrap_or_default();
    assert!(detail.contains("after 16 frames"), "{program:#}");
    assert_eq!(program["passed"], false, "{program:#}");
    let hint = program["hint"].as_str().unwrap_or_default();
    assert!(hint.starts_with("self-intersection"), "{program:#}");
    assert!(
        program["measurements"]["your_average"].as_f64()
            < program["measurements"]["reference_average"].as_f64()
    );
}

#[test]
fn check_fails_the_tab_with_a_missing_factor_2() {
    let (code, program, report) = check_program("exercise7_tab_missing_factor_2.glsl");
    assert_eq!(code, Some(1));
    assert_eq!(program["passed"], false, "{program:#}");
    let radiance = report["functions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["function"] == "get_ray_radiance")
        .unwrap();
    assert_eq!(radiance["passed"], false);
    assert!(
        program["hint"]
            .as_str()
            .unwrap_or_default()
            .contains("get_ray_radiance fails on its own"),
        "{program:#}"
    );
}

#[test]
fn i_resolution_and_i_channel_resolution_are_the_renders_size() {
    // 6 x 3, not square: fragCoord / iResolution.xy is ((x + 0.5) / 6, (y + 0.5) / 3), and
    // iChannelResolution[0] is Buffer A's size; each value is one float division, the same
    // one the test makes.
    let dir = tempfile::tempdir().unwrap();
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("resolution_image.glsl"),
            "--buffer-a",
            &program("count_buffer_a.glsl"),
            "--frames",
            "2",
            "--width",
            "6",
            "--height",
            "3",
            "-o",
            "image.exr",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let image = rgba(&dir.path().join("image.exr"));
    for (x, y) in [(0, 0), (5, 0), (0, 2), (3, 1), (5, 2)] {
        let expected = [(x as f32 + 0.5) / 6.0, (y as f32 + 0.5) / 3.0, 6.0, 3.0];
        assert_eq!(at(&image, x, y), expected, "({x}, {y})");
    }
}

#[test]
fn a_page_shaders_resolution_uniform_is_the_renders_size() {
    // The shared intake gives `uniform vec2 u_resolution` the render's size and drops the
    // page shader's own `uniform float iTime` for vkpath's.
    let dir = tempfile::tempdir().unwrap();
    let file = program("resolution_page_shader.glsl");
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &file, "--frames", "1", "--width", "6", "--height", "3", "-o", "page.exr",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "note: {file}:6: 'uniform vec2 u_resolution' is vec2(6.0, 3.0)"
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!(
            "note: {file}:7: dropped your declaration of iTime"
        )),
        "{stderr}"
    );
    let image = rgba(&dir.path().join("page.exr"));
    for (x, y) in [(0, 0), (5, 2), (2, 1)] {
        let expected = [(x as f32 + 0.5) / 6.0, (y as f32 + 0.5) / 3.0, 6.0, 3.0];
        assert_eq!(at(&image, x, y), expected, "({x}, {y})");
    }
}

#[test]
fn two_passes_may_define_the_same_helper_after_one_common_tab() {
    // Buffer A and the Image pass each define `shade` (with other parameters and bodies) and
    // both call the Common tab's base_value(): one compilation per pass, Common first, as
    // ShaderToy does. Buffer A writes 3, the Image pass 3 + 10.
    let dir = tempfile::tempdir().unwrap();
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("helper_image.glsl"),
            "--common",
            &program("helper_common.glsl"),
            "--buffer-a",
            &program("helper_buffer_a.glsl"),
            "--frames",
            "1",
            "--width",
            "4",
            "--height",
            "4",
            "-o",
            "image.exr",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let image = rgba(&dir.path().join("image.exr"));
    assert_eq!(at(&image, 2, 1), [13.0, 1.0, 0.0, 1.0]);
}

#[test]
fn a_loop_without_end_is_one_error_line_naming_the_pass_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let buffer = program("endless_loop_buffer_a.glsl");
    let started = Instant::now();
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("show_buffer_a.glsl"),
            "--buffer-a",
            &buffer,
            "--frames",
            "3",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "image.png",
        ],
    );
    assert_eq!(code, Some(1), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "one error line: {stderr}");
    assert!(
        errors[0].contains(&format!(
            "frame 0: the loops of {buffer} (buffer-a) ran past"
        )) && errors[0].contains("nothing was written"),
        "{stderr}"
    );
    assert!(!dir.path().join("image.png").exists());
    // The guard ends the loop after a few thousand iterations per pixel: no hang.
    assert!(started.elapsed() < Duration::from_secs(60));
}

#[test]
fn a_crash_while_the_program_runs_loses_only_the_program_verdict() {
    // The test-only fault switch aborts the worker that runs the program, as a driver crash
    // would: every function verdict is still there, the program is listed as lost with the
    // reason, and the check fails. 8 frames: the program never runs past its start.
    let (code, lost, report) = check_program_env(
        "exercise7_tab.glsl",
        &["--frames", "8"],
        &[("VKPATH_CHECK_FAULT", "program")],
    );
    assert_eq!(code, Some(1), "{report:#}");
    assert!(
        lost["reason"]
            .as_str()
            .unwrap_or_default()
            .contains("the Vulkan driver crashed running your program"),
        "{report:#}"
    );
    assert_eq!(lost["file"], program("exercise7_tab.glsl"), "{lost:#}");
    let functions = report["functions"].as_array().unwrap();
    assert!(functions.len() >= 7, "{report:#}");
    assert!(
        functions
            .iter()
            .all(|f| f["passed"] == true && f["function"] != "program"),
        "{report:#}"
    );
}

#[test]
fn shadertoy_and_check_take_the_same_files_in_the_same_order() {
    // The VS Code Shader Toy tabs as files in check's order (the Common tab given last goes
    // first, then Buffer A, Buffer B and the Image tab as given): the image of --common and
    // --buffer-a/-b, bit for bit.
    let dir = tempfile::tempdir().unwrap();
    let size = ["--frames", "5", "--width", "8", "--height", "8"];
    let (buffer_a, buffer_b, image, common) = (
        program("vscode_buffer_a.glsl"),
        program("vscode_buffer_b.glsl"),
        program("vscode_image.glsl"),
        program("vscode_common.glsl"),
    );
    let mut args: Vec<&str> = vec![&buffer_a, &buffer_b, &image, &common];
    args.extend_from_slice(&size);
    args.extend_from_slice(&["-o", "in_order.exr"]);
    let (code, stderr) = shadertoy(dir.path(), &args);
    assert_eq!(code, Some(0), "{stderr}");
    assert_chain_image(&dir.path().join("in_order.exr"));
    let mut args: Vec<&str> = vec![&image, "--common", &common, "--buffer-a", &buffer_a];
    args.extend_from_slice(&["--buffer-b", &buffer_b, "-o", "flags.exr"]);
    args.extend_from_slice(&size);
    let (code, stderr) = shadertoy(dir.path(), &args);
    assert_eq!(code, Some(0), "{stderr}");
    assert_eq!(
        std::fs::read(dir.path().join("in_order.exr")).unwrap(),
        std::fs::read(dir.path().join("flags.exr")).unwrap()
    );

    // A Common tab and an Image tab of workshop functions, in the wrong order: check judges
    // them as one program (tests/check_cli.rs), and shadertoy runs them.
    let solutions = format!("{}/tests/solutions", env!("CARGO_MANIFEST_DIR"));
    let tabs = [
        format!("{solutions}/image_tab_needs_common.glsl"),
        format!("{solutions}/common_tab.glsl"),
    ];
    let checked = common::runs::check(dir.path(), &tabs, &["--json"], &[]);
    assert_eq!(checked.code, Some(0), "{}", checked.stdout);
    let mut args: Vec<&str> = tabs.iter().map(String::as_str).collect();
    args.extend_from_slice(&size);
    args.extend_from_slice(&["-o", "tabs.png"]);
    let (code, stderr) = shadertoy(dir.path(), &args);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(dir.path().join("tabs.png").exists());

    // Files that cannot make one program: one usage line each.
    let other_common = program("helper_common.glsl");
    for (files, expected) in [
        (
            vec![common.as_str(), other_common.as_str(), image.as_str()],
            "both have no entry point",
        ),
        (
            vec![
                buffer_a.as_str(),
                image.as_str(),
                "--common",
                common.as_str(),
            ],
            "not both",
        ),
    ] {
        let mut args = files.clone();
        args.extend_from_slice(&["--frames", "1", "-o", "bad.png"]);
        let (code, stderr) = shadertoy(dir.path(), &args);
        assert_eq!(code, Some(2), "{stderr}");
        let last = stderr.trim().lines().last().unwrap_or_default();
        assert!(
            last.starts_with("vkpath: error: ") && last.contains(expected),
            "{stderr}"
        );
    }
}

#[test]
fn a_discarded_texel_keeps_what_its_target_held() {
    // tests/solutions/programs/discard_buffer_a.glsl discards the left half from frame 3 on
    // (in a helper that returns a value, called in a loop) and the bottom row from frame 4
    // on (in mainImage). As in ShaderToy, whose buffers are two render targets written in
    // turn and never cleared after frame 0, a discarded texel keeps its target's value: the
    // one of two frames before. The Image pass sees this frame's Buffer A.
    let dir = tempfile::tempdir().unwrap();
    let (code, stderr) = shadertoy(
        dir.path(),
        &[
            &program("show_buffer_a.glsl"),
            "--buffer-a",
            &program("discard_buffer_a.glsl"),
            "--frames",
            "6",
            "--width",
            "4",
            "--height",
            "2",
            "-o",
            "image.exr",
            "--save-buffer",
            "a=a.exr",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let buffer = rgba(&dir.path().join("a.exr"));
    let image = rgba(&dir.path().join("image.exr"));
    for (x, y, expected) in [
        (2, 1, [6.0, 4.0, 0.0, 1.0]),
        (3, 1, [6.0, 4.0, 0.0, 1.0]),
        (3, 0, [4.0, 4.0, 0.0, 1.0]),
        (0, 0, [2.0, 4.0, 0.0, 1.0]),
        (1, 1, [2.0, 4.0, 0.0, 1.0]),
    ] {
        assert_eq!(at(&buffer, x, y), expected, "A at ({x}, {y})");
        assert_eq!(at(&image, x, y), expected, "Image at ({x}, {y})");
    }
}

#[test]
fn a_vscode_file_that_reads_itself_runs_as_a_hidden_buffer() {
    // VS Code Shader Toy's single-file accumulation (#iChannel0 "self", void main(),
    // gl_FragColor): alone, it runs as a hidden buffer that vkpath's Image pass shows; as
    // --buffer-a (a page shader may be a buffer) with an Image tab that shows Buffer A, the
    // same. Five frames: each pixel holds the running mean it computes.
    let dir = tempfile::tempdir().unwrap();
    let file = program("vscode_self_accumulation.glsl");
    let size = ["--frames", "5", "--width", "4", "--height", "2"];
    let mut alone = vec![file.as_str(), "-o", "alone.exr"];
    alone.extend_from_slice(&size);
    let (code, stderr) = shadertoy(dir.path(), &alone);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "note: {file}: reads itself (#iChannel0 \"self\"): it runs as a hidden buffer-a"
        )),
        "{stderr}"
    );
    let shown = program("show_buffer_a.glsl");
    let mut as_buffer = vec![
        shown.as_str(),
        "--buffer-a",
        file.as_str(),
        "-o",
        "buffer.exr",
    ];
    as_buffer.extend_from_slice(&size);
    let (code, stderr) = shadertoy(dir.path(), &as_buffer);
    assert_eq!(code, Some(0), "{stderr}");
    let n = 5.0f32;
    for output in ["alone.exr", "buffer.exr"] {
        let image = rgba(&dir.path().join(output));
        for (x, y) in [(0, 0), (3, 1), (2, 0)] {
            let expected = [
                x as f32 + 0.5 + (n - 1.0) / 2.0,
                (n - 1.0) * (2.0 * n - 1.0) / 6.0,
                1.0,
                1.0,
            ];
            let got = at(&image, x, y);
            // A running mean in float: a few ulps from the exact mean.
            for c in 0..4 {
                assert!(
                    (got[c] - expected[c]).abs() <= 1e-5 * expected[c].abs().max(1.0),
                    "{output} at ({x}, {y}): {got:?} against {expected:?}"
                );
            }
        }
    }
}

#[test]
fn a_cube_map_channel_is_sampled_by_direction() {
    // tests/solutions/programs/cube_directions.glsl writes texture(iChannel1, direction) for
    // 14 directions. First the VS Code Shader Toy way: #iChannel1 "file://cube_{}.png" with
    // ::Type "CubeMap", six 2 x 2 PNG faces whose texels all differ; each of the first eight
    // directions points at one texel's centre and gets it exactly (value / 255).
    let dir = tempfile::tempdir().unwrap();
    let tab = dir.path().join("cube_directions.glsl");
    std::fs::copy(program("cube_directions.glsl"), &tab).unwrap();
    // Face f's texel (column c, row r from the top): red 40 f + 10 c + 5 r + 10.
    let byte = |f: u32, c: u32, r: u32| (40 * f + 10 * c + 5 * r + 10) as u8;
    for (f, name) in ["px", "nx", "py", "ny", "pz", "nz"].iter().enumerate() {
        let f = f as u32;
        let face = image::RgbImage::from_fn(2, 2, |c, r| image::Rgb([byte(f, c, r), 200, 100]));
        face.save(dir.path().join(format!("cube_{name}.png")))
            .unwrap();
    }
    let tab = tab.to_string_lossy().to_string();
    let size = ["--frames", "1", "--width", "14", "--height", "1"];
    let mut args = vec![tab.as_str(), "-o", "faces.exr"];
    args.extend_from_slice(&size);
    let (code, stderr) = shadertoy(dir.path(), &args);
    assert_eq!(code, Some(0), "{stderr}");
    let image = rgba(&dir.path().join("faces.exr"));
    // (face, column, row) of each of the first eight directions.
    let texels = [
        (0, 0, 0),
        (0, 1, 1),
        (1, 0, 0),
        (2, 0, 0),
        (3, 1, 1),
        (4, 0, 0),
        (5, 0, 0),
        (5, 0, 1),
    ];
    for (x, (f, c, r)) in texels.into_iter().enumerate() {
        let expected = [
            f32::from(byte(f, c, r)) / 255.0,
            200.0 / 255.0,
            100.0 / 255.0,
            1.0,
        ];
        assert_eq!(at(&image, x as u32, 0), expected, "direction {x}");
    }

    // Then an equirectangular EXR as --environment reads it, given on the command line
    // (which wins over the directive): 8 x 4 texels, the top row +Y's code 3, the bottom
    // row -Y's 4, the two middle rows by azimuth (u = 0.5 + atan2(x, -z) / 2 pi): columns
    // 7 and 0 +Z's 5, 1-2 -X's 2, 3-4 -Z's 6, 5-6 +X's 1. Resampled into 2 x 2 faces, every
    // texel around an axis has that axis's code, so each axis direction gets it exactly.
    let code_at = |x: usize, y: usize| -> f32 {
        match (y, x) {
            (0, _) => 3.0,
            (3, _) => 4.0,
            (_, 7 | 0) => 5.0,
            (_, 1 | 2) => 2.0,
            (_, 3 | 4) => 6.0,
            _ => 1.0,
        }
    };
    exr::prelude::write_rgb_file(dir.path().join("sky.exr"), 8, 4, |x, y| {
        (code_at(x, y), 10.0 * code_at(x, y), 0.5)
    })
    .unwrap();
    let mut args = vec![
        tab.as_str(),
        "--channel",
        "image.1=cube:sky.exr",
        "-o",
        "equirect.exr",
    ];
    args.extend_from_slice(&size);
    let (code, stderr) = shadertoy(dir.path(), &args);
    assert_eq!(code, Some(0), "{stderr}");
    let image = rgba(&dir.path().join("equirect.exr"));
    for (x, axis_code) in [
        (8, 1.0),
        (9, 2.0),
        (10, 3.0),
        (11, 4.0),
        (12, 5.0),
        (13, 6.0),
    ] {
        assert_eq!(
            at(&image, x, 0),
            [axis_code, 10.0 * axis_code, 0.5, 1.0],
            "axis direction {x}"
        );
    }
}
