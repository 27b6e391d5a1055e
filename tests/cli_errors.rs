//! Bad input through the binary: one clear line on stderr naming the problem, a non-zero
//! exit, no panic, and no output file left behind.

use crate::common;

use std::path::Path;

/// Runs vkpath, expects failure, and returns the one error line.
fn expect_error(dir: &Path, args: &[&str], env: &[(&str, &str)], expected_exit: i32) -> String {
    let output = common::vkpath_with_env(dir, args, env);
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert_eq!(
        output.status.code(),
        Some(expected_exit),
        "args {args:?}: {stderr}"
    );
    assert!(
        !stderr.contains("panicked"),
        "args {args:?} panicked: {stderr}"
    );
    let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(
        errors.len(),
        1,
        "args {args:?}: expected one error line, got: {stderr}"
    );
    // Nothing was written: no image and no temporary file.
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(
        leftovers.is_empty(),
        "args {args:?} left files behind: {leftovers:?}"
    );
    errors[0].to_string()
}

fn render_error(args: &[&str], expected_text: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mut full = vec!["render", "-o", "out.png"];
    // Small defaults, unless the test sets the option itself.
    for (option, value) in [("--width", "8"), ("--height", "8"), ("--spp", "1")] {
        if !args.contains(&option) {
            full.extend_from_slice(&[option, value]);
        }
    }
    full.extend_from_slice(args);
    let line = expect_error(dir.path(), &full, &[], 1);
    assert!(
        line.contains(expected_text),
        "args {args:?}: '{line}' does not mention '{expected_text}'"
    );
}

/// A tiny render of the built-in scene with `args` appended and `env` set; its error line.
fn vulkan_error(args: &[&str], env: &[(&str, &str)]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let mut full = vec![
        "render", "-o", "out.png", "--width", "8", "--height", "8", "--spp", "1",
    ];
    full.extend_from_slice(args);
    expect_error(dir.path(), &full, env, 1)
}

#[test]
fn missing_scene_file() {
    render_error(&["/nonexistent/scene.gltf"], "/nonexistent/scene.gltf");
}

#[test]
fn unreadable_scene_file() {
    // A directory cannot be read as a file (chmod would not stop root).
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("dir.obj");
    std::fs::create_dir(&scene).unwrap();
    render_error(&[scene.to_str().unwrap()], "dir.obj");
}

#[test]
fn malformed_gltf() {
    render_error(&[&common::fixture("malformed.gltf")], "malformed.gltf");
}

#[test]
fn non_triangle_primitive() {
    render_error(&[&common::fixture("lines.gltf")], "triangles");
}

#[test]
fn obj_without_camera_is_framed() {
    // No longer an error (issue 13): a scene without a camera is framed, and one line says so.
    let dir = tempfile::tempdir().unwrap();
    let cube = common::fixture("cube.obj");
    let output = common::vkpath(
        dir.path(),
        &[
            "render", "-o", "out.png", "--width", "8", "--height", "8", "--spp", "1", &cube,
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains("the scene has no camera: framing its bounding sphere"),
        "{stderr}"
    );
}

#[test]
fn unsupported_scene_format() {
    render_error(&["scene.stl"], "scene.stl");
}

#[test]
fn zero_and_absurd_sizes_and_sample_counts() {
    render_error(&["--width", "0"], "--width");
    render_error(&["--height", "100000"], "100000");
    render_error(&["--max-path-length", "0"], "--max-path-length");
    render_error(&["--generated", "100000000000"], "--generated");
    // Too large for the device, so in tiles; with a checkpoint they visit every tile each
    // frame, so the whole image's state stays on the host (240 bytes a pixel at most, 60 GiB
    // here), which is checked against the host's memory before anything is allocated, with
    // the sizes (on a machine with less than 60 GiB available). Without one the tiles go one
    // at a time and the host holds 32 bytes a pixel: that image renders (minutes here).
    render_error(
        &[
            "--width",
            "16384",
            "--height",
            "16384",
            "--checkpoint",
            "checkpoint.exr",
        ],
        "MB of host memory for the state of 16384x16384 pixels of the 16384x16384 image",
    );
}

#[test]
fn export_errors() {
    // A file where the output directory should be.
    let dir = tempfile::tempdir().unwrap();
    let blocker = tempfile::NamedTempFile::new().unwrap();
    let target = blocker.path().join("scene");
    let line = expect_error(
        dir.path(),
        &["export", "--output-dir", target.to_str().unwrap()],
        &[],
        1,
    );
    assert!(line.contains("cannot write"), "{line}");
    let line = expect_error(
        dir.path(),
        &["export", "/nonexistent/scene.gltf", "--output-dir", "out"],
        &[],
        1,
    );
    assert!(line.contains("/nonexistent/scene.gltf"), "{line}");
}

#[test]
fn unwritable_output() {
    let dir = tempfile::tempdir().unwrap();
    let line = expect_error(
        dir.path(),
        &["render", "-o", "/nonexistent-dir/out.png"],
        &[],
        1,
    );
    assert!(line.contains("/nonexistent-dir/out.png"), "{line}");
    let line = expect_error(dir.path(), &["render", "-o", "out.jpg"], &[], 1);
    assert!(line.contains(".exr or .png"), "{line}");
}

#[test]
fn malformed_camera_arguments_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let line = expect_error(
        dir.path(),
        &["render", "-o", "x.png", "--camera-position", "1,2"],
        &[],
        2,
    );
    assert!(line.contains("x,y,z"), "{line}");
}

#[test]
fn no_vulkan_loader() {
    let line = vulkan_error(
        &[],
        &[("VKPATH_VULKAN_LOADER", "/nonexistent/libvulkan.so.1")],
    );
    assert!(line.contains("libvulkan1"), "{line}");
}

#[test]
fn no_vulkan_driver() {
    let line = vulkan_error(
        &[],
        &[
            ("VK_DRIVER_FILES", "/nonexistent.json"),
            ("VK_ICD_FILENAMES", "/nonexistent.json"),
        ],
    );
    assert!(line.contains("no Vulkan driver"), "{line}");
    assert!(line.contains("mesa-vulkan-drivers"), "{line}");
}

#[test]
fn cpu_device_when_a_gpu_is_required() {
    // On CI the only device is lavapipe; on a machine with a GPU, ask for the CPU device by
    // name so that the check still has a CPU device to refuse.
    let line = vulkan_error(&["--require-gpu", "--device", "llvmpipe"], &[]);
    assert!(line.contains("GPU was required"), "{line}");
    assert!(line.contains("llvmpipe"), "{line}");
}

#[test]
fn unknown_device() {
    let line = vulkan_error(&["--device", "no-such-gpu"], &[]);
    assert!(line.contains("no-such-gpu"), "{line}");
}

#[test]
fn a_good_render_prints_the_device_and_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let output = common::vkpath(
        dir.path(),
        &[
            "render", "-o", "out.png", "--width", "8", "--height", "8", "--spp", "2",
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("vkpath: device"), "{stderr}");
    let summary = stderr.lines().last().unwrap();
    for part in ["8x8", "2 spp", "samples/s", "["] {
        assert!(summary.contains(part), "summary '{summary}' lacks '{part}'");
    }
    let png = image::open(dir.path().join("out.png")).unwrap();
    assert_eq!((png.width(), png.height()), (8, 8));
}

#[test]
fn zero_samples_are_usage_errors_of_render_bench_and_exercise() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["render", "-o", "out.png", "--spp", "0"][..],
        &["render", "-o", "out.png", "--spp", "4000000000"],
        &["bench", "--spp", "0"],
        &["exercise", "path-tracing", "-o", "out.png", "--spp", "0"],
    ] {
        let line = expect_error(dir.path(), args, &[], 2);
        assert!(
            line.contains("--spp")
                && line.contains("is not a number of samples per pixel in 1..=16777216"),
            "{line}"
        );
    }
}

/// A directory with the files of the tests below: a PNG, a text file named .exr and a
/// truncated Radiance map.
fn wrong_files() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    image::RgbImage::new(2, 2)
        .save(dir.path().join("a.png"))
        .unwrap();
    std::fs::write(dir.path().join("text.exr"), "not an EXR").unwrap();
    std::fs::write(
        dir.path().join("cut.hdr"),
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 8\n\x01\x02",
    )
    .unwrap();
    std::fs::create_dir(dir.path().join("folder.exr")).unwrap();
    dir
}

#[test]
fn environment_map_errors_name_the_map_and_the_cause() {
    let files = wrong_files();
    let path = |name: &str| files.path().join(name).display().to_string();
    let missing = path("nope.hdr");
    render_error(
        &["--environment", &missing],
        &format!("cannot read environment map '{missing}': No such file or directory"),
    );
    // The file is named once, and what is wrong with it is said plainly.
    for (name, cause) in [
        ("text.exr", "it is not an OpenEXR file"),
        ("a.png", "must be a .hdr (Radiance) or .exr (OpenEXR) file"),
        ("cut.hdr", "the file is truncated"),
        ("folder.exr", "it is a directory, not a file"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let line = expect_error(
            dir.path(),
            &[
                "render",
                "-o",
                "out.png",
                "--width",
                "8",
                "--height",
                "8",
                "--spp",
                "1",
                "--environment",
                &path(name),
            ],
            &[],
            1,
        );
        assert!(line.contains(cause), "{name}: {line}");
        assert_eq!(line.matches(name).count(), 1, "{name}: {line}");
    }
}

#[test]
fn files_that_are_not_openexr_say_so_and_what_the_command_reads() {
    let files = wrong_files();
    let path = |name: &str| files.path().join(name).display().to_string();
    let dir = tempfile::tempdir().unwrap();
    let png = path("a.png");
    let folder = path("folder.exr");
    let line = expect_error(dir.path(), &["compare", &png, &png], &[], 2);
    assert!(
        line.contains(
            "it is a PNG image, not an OpenEXR file (`vkpath compare` reads OpenEXR images"
        ),
        "{line}"
    );
    let line = expect_error(dir.path(), &["compare", "--exact", &png, &png], &[], 2);
    assert!(
        line.contains("it is a PNG image, not an OpenEXR file"),
        "{line}"
    );
    let line = expect_error(dir.path(), &["compare", &folder, &png], &[], 2);
    assert!(line.contains("it is a directory, not a file"), "{line}");
    let line = expect_error(dir.path(), &["merge", &png, "-o", "m.exr"], &[], 1);
    assert!(
        line.contains(
            "it is a PNG image, not an OpenEXR file (`vkpath merge` reads the OpenEXR shards"
        ),
        "{line}"
    );
    render_error(
        &["--resume", &png],
        "it is a PNG image, not an OpenEXR file (--resume reads the OpenEXR checkpoint",
    );
}

#[test]
fn obj_errors_give_file_and_line() {
    let files = tempfile::tempdir().unwrap();
    let obj = files.path().join("bad.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 2 x\nf 1 2 3\n").unwrap();
    render_error(
        &[obj.to_str().unwrap()],
        &format!("malformed OBJ '{}:4': position parse error", obj.display()),
    );
}

#[test]
fn absurd_frame_ranges_and_bad_tev_addresses_are_usage_errors() {
    // Issue 58: 0..4000000000 aborted allocating 64 GB (exit 134); a bad --tev address was a
    // warning with exit 0.
    let dir = tempfile::tempdir().unwrap();
    let line = expect_error(
        dir.path(),
        &["render", "-o", "f_#.png", "--frames", "0..4000000000"],
        &[],
        2,
    );
    assert!(
        line.contains("'0..4000000000' holds 4000000000 frames; one render takes at most 1000000"),
        "{line}"
    );
    for address in ["localhost", "127.0.0.1:99999", "[::1:14158"] {
        let line = expect_error(
            dir.path(),
            &["render", "-o", "out.png", "--tev", address],
            &[],
            2,
        );
        assert!(
            line.contains(&format!("'{address}' is not HOST:PORT")),
            "{line}"
        );
    }
}

#[test]
fn options_that_exclude_each_other_are_usage_errors() {
    // Issue 58: both exited 1, as a failure would.
    let dir = tempfile::tempdir().unwrap();
    let line = expect_error(
        dir.path(),
        &[
            "render",
            "-o",
            "out.png",
            "--device",
            "all",
            "--tev",
            "127.0.0.1:14158",
        ],
        &[],
        2,
    );
    assert!(line.contains("--tev works with one device"), "{line}");
    let line = expect_error(
        dir.path(),
        &[
            "render",
            "-o",
            "f_#.png",
            "--frames",
            "0..2",
            "--checkpoint",
            "ck.exr",
        ],
        &[],
        2,
    );
    assert!(
        line.contains("--checkpoint and --resume belong to one frame"),
        "{line}"
    );
}

#[test]
fn a_directory_as_scene_is_called_a_directory() {
    // Issue 58: it was "unsupported file extension (expected .gltf, .glb or .obj)".
    let folder = tempfile::tempdir().unwrap();
    let scene = folder.path().join("scenes");
    std::fs::create_dir(&scene).unwrap();
    render_error(&[scene.to_str().unwrap()], "it is a directory, not a file");
}
