//! Nothing already there is lost (issue 21): an output, checkpoint or preview that is (or
//! links to) a device, FIFO or directory is refused before rendering and survives; a stop
//! before the first sample writes nothing and leaves an existing output as it was; a second
//! signal aborts at once without leaving a temporary or a partial file.

use crate::common;

use std::io::{BufRead, BufReader};
use std::os::unix::fs::{symlink, FileTypeExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Whether the tests run as root (CI and containers do): then `mknod` can make a device.
fn is_root() -> bool {
    let output = Command::new("id").arg("-u").output().expect("id runs");
    String::from_utf8_lossy(&output.stdout).trim() == "0"
}

/// Makes a special file at `path`: a character device like /dev/full (1, 7) as root, else
/// a FIFO. Returns what the refusal names.
fn make_special_file(path: &Path) -> &'static str {
    let (program, args, what): (&str, Vec<&str>, &str) = if is_root() {
        ("mknod", vec!["c", "1", "7"], "a character device")
    } else {
        ("mkfifo", vec![], "a FIFO")
    };
    let status = Command::new(program).arg(path).args(args).status().unwrap();
    assert!(status.success(), "{program} {}", path.display());
    what
}

/// Whether `path` is still the special file `make_special_file` made.
fn is_special(path: &Path) -> bool {
    let kind = std::fs::symlink_metadata(path).unwrap().file_type();
    kind.is_char_device() || kind.is_fifo()
}

/// The names in `dir`.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn an_output_linked_to_a_device_is_refused_and_the_device_survives() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let what = make_special_file(&path.join("node"));
    symlink("node", path.join("out.exr")).unwrap();
    symlink("node", path.join("ck.exr")).unwrap();
    symlink("node", path.join("preview.png")).unwrap();
    let small = ["--width", "8", "--height", "8", "--spp", "1"];
    for extra in [
        vec!["-o", "out.exr"],
        vec!["-o", "fine.exr", "--checkpoint", "ck.exr"],
        vec!["-o", "fine.exr", "--preview", "preview.png"],
        vec!["-o", "fine.exr", "-o", "out.exr"],
    ] {
        let mut args = vec!["render"];
        args.extend_from_slice(&small);
        args.extend_from_slice(&extra);
        let output = common::vkpath(path, &args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{extra:?}: {stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
        assert_eq!(errors.len(), 1, "{extra:?}: one line: {stderr}");
        assert!(
            errors[0].contains("symbolic link to") && errors[0].contains(what),
            "{extra:?}: {}",
            errors[0]
        );
        assert!(
            is_special(&path.join("node")),
            "{extra:?}: the node survives"
        );
        assert_eq!(
            names(path),
            ["ck.exr", "node", "out.exr", "preview.png"],
            "{extra:?}: nothing written, nothing renamed"
        );
    }
    // A directory and a FIFO named directly are refused alike.
    std::fs::create_dir(path.join("folder.png")).unwrap();
    let output = common::vkpath(path, &["render", "-o", "folder.png", "--spp", "1"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("it is a directory"), "{stderr}");
}

#[test]
fn a_checkpoint_must_be_an_exr() {
    let dir = tempfile::tempdir().unwrap();
    let output = common::vkpath(
        dir.path(),
        &[
            "render",
            "-o",
            "out.exr",
            "--spp",
            "1",
            "--checkpoint",
            "ck.png",
        ],
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("a checkpoint is an EXR"), "{stderr}");
    assert!(names(dir.path()).is_empty(), "nothing written");
}

/// Starts `vkpath render` with `args` in `dir`, waits until it has printed `marker` on
/// stderr, and returns it with the lines so far and the rest of stderr's reader.
// The caller waits for the child it is given; a child that ends early is waited for here.
#[allow(clippy::zombie_processes)]
fn spawn_until(
    dir: &Path,
    args: &[&str],
    marker: &str,
) -> (
    std::process::Child,
    Vec<String>,
    BufReader<std::process::ChildStderr>,
) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vkpath"))
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_LOG")
        .stderr(Stdio::piped())
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let mut reader = BufReader::new(child.stderr.take().unwrap());
    let mut lines = Vec::new();
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).unwrap_or(0) == 0 {
            let status = child.wait();
            panic!("vkpath ended ({status:?}) before printing '{marker}': {lines:?}");
        }
        let found = line.contains(marker);
        lines.push(line);
        if found {
            return (child, lines, reader);
        }
    }
}

/// Sends `signal` (e.g. "-INT") to `child`.
fn kill(child: &std::process::Child, signal: &str) {
    let status = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

#[test]
fn a_sigint_before_the_first_sample_leaves_the_existing_output_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let before = b"an image from yesterday".to_vec();
    std::fs::write(path.join("out.png"), &before).unwrap();
    // The materials scene: its kernels take seconds to build on lavapipe, and the device
    // line comes just before they are built, so the signal arrives during set-up.
    let scene = format!("{}/scenes/materials.gltf", env!("CARGO_MANIFEST_DIR"));
    let (mut child, _, mut reader) = spawn_until(
        path,
        &[
            "render", &scene, "-o", "out.png", "--width", "16", "--height", "16", "--spp", "4",
        ],
        "vkpath: device",
    );
    let sent = Instant::now();
    kill(&child, "-INT");
    let status = child.wait().unwrap();
    let stopped_after = sent.elapsed();
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut reader, &mut rest).unwrap();
    assert_eq!(status.code(), Some(130), "128 + SIGINT: {rest}");
    assert!(
        rest.contains("stopped by SIGINT before the first sample: nothing written"),
        "{rest}"
    );
    assert_eq!(rest.lines().count(), 1, "one line: {rest}");
    // The bar is "within a second"; the command exits at once, so even a loaded CI
    // machine stays far below 5 s, where the kernels alone take longer than that.
    assert!(
        stopped_after < Duration::from_secs(5),
        "stopped {stopped_after:?} after the signal"
    );
    assert_eq!(std::fs::read(path.join("out.png")).unwrap(), before);
    assert_eq!(names(path), ["out.png"], "no temporary file is left");
}

#[test]
fn a_second_sigint_aborts_at_once_leaving_only_whole_files() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    // A render long enough to be interrupted mid-way (about 3 s on lavapipe, 2 cores).
    let args = [
        "render",
        "-o",
        "out.exr",
        "--width",
        "96",
        "--height",
        "96",
        "--spp",
        "2048",
        "--integrator",
        "workshop",
        "--checkpoint",
        "ck.exr",
        "--checkpoint-interval",
        "0.2",
    ];
    let (child, _, mut reader) = spawn_until(path, &args, "vkpath: device");
    let started = Instant::now();
    while !path.join("ck.exr").exists() {
        assert!(started.elapsed() < Duration::from_secs(60), "no checkpoint");
        std::thread::sleep(Duration::from_millis(20));
    }
    kill(&child, "-INT");
    kill(&child, "-INT");
    let output = child.wait_with_output().unwrap();
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut reader, &mut rest).unwrap();
    assert_eq!(output.status.code(), Some(130), "{rest}");
    // The second signal may come before or after the first one's writes finished: either
    // way every file there is whole and no temporary is left.
    // (A Ctrl-C's image goes to out.partial.exr, never over out.exr.)
    let left = names(path);
    assert!(
        left.iter().all(|n| n == "ck.exr" || n == "out.partial.exr"),
        "only whole files: {left:?}"
    );
    vkpath::render::state_exr::read_state(&path.join("ck.exr")).expect("a whole checkpoint");
    if path.join("out.partial.exr").exists() {
        vkpath::image_io::exr_input::read_exr(&path.join("out.partial.exr"))
            .expect("a whole image");
    }
}

/// A render of the built-in box long enough to be stopped mid-way (seconds on lavapipe),
/// writing `outputs`, with a checkpoint every 0.2 s so that a test knows it has samples.
fn long_render_args<'a>(outputs: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "render",
        "--width",
        "96",
        "--height",
        "96",
        "--spp",
        "4096",
        "--integrator",
        "workshop",
        "--checkpoint",
        "ck.exr",
        "--checkpoint-interval",
        "0.2",
    ];
    for output in outputs {
        args.extend(["-o", output]);
    }
    args
}

/// Starts a long render, waits for its first checkpoint (so it has samples), sends
/// `signal` and returns its exit status and the rest of its stderr.
fn stop_after_first_samples(dir: &Path, outputs: &[&str], signal: &str) -> (i32, String) {
    let (child, _, mut reader) = spawn_until(dir, &long_render_args(outputs), "vkpath: device");
    let started = Instant::now();
    while !dir.join("ck.exr").exists() {
        assert!(started.elapsed() < Duration::from_secs(60), "no checkpoint");
        std::thread::sleep(Duration::from_millis(20));
    }
    kill(&child, signal);
    let output = child.wait_with_output().unwrap();
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut reader, &mut rest).unwrap();
    (output.status.code().unwrap_or(-1), rest)
}

/// The `vkpath` metadata text of an image (EXR header attribute or PNG tEXt chunk).
fn metadata_text(path: &Path) -> String {
    let metadata = vkpath::render::state_exr::read_image_metadata(path)
        .unwrap()
        .expect("vkpath metadata");
    metadata
        .fields()
        .iter()
        .map(|(name, value)| format!("{name}={value}"))
        .collect::<Vec<_>>()
        .join("; ")
}

#[test]
fn ctrl_c_after_the_first_samples_keeps_the_finished_image_and_writes_a_partial_one_beside() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    // A finished image from an earlier render: a Ctrl-C must not replace it.
    let before = b"a finished image from yesterday".to_vec();
    std::fs::write(path.join("out.png"), &before).unwrap();
    let (status, rest) = stop_after_first_samples(path, &["out.png", "out.exr"], "-INT");
    assert_eq!(status, 130, "128 + SIGINT: {rest}");
    assert_eq!(std::fs::read(path.join("out.png")).unwrap(), before);
    assert!(!path.join("out.exr").exists(), "{rest}");
    let stopped: Vec<&str> = rest.lines().filter(|l| l.contains("stopped by")).collect();
    assert_eq!(stopped.len(), 1, "{rest}");
    assert!(
        stopped[0].contains("saved to 'out.partial.png', 'out.partial.exr' and 'ck.exr'")
            // Issue 58: out.exr never existed, so it was not "left as it was".
            && stopped[0].contains("('out.png' left as it was; 'out.exr' not written)"),
        "{}",
        stopped[0]
    );
    // Both partial files say what they hold, that a signal stopped them and what was asked.
    for name in ["out.partial.png", "out.partial.exr"] {
        let text = metadata_text(&path.join(name));
        assert!(
            text.contains("spp_requested=4096; stop=signal"),
            "{name}: {text}"
        );
        assert!(!text.starts_with("spp=4096;"), "{name}: partial: {text}");
    }
}

#[test]
fn sigterm_and_the_time_limit_write_the_outputs_and_say_how_they_stopped() {
    // A scheduler's stop (SIGTERM) writes the outputs themselves, as before.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let (status, rest) = stop_after_first_samples(path, &["out.png"], "-TERM");
    assert_eq!(status, 143, "128 + SIGTERM: {rest}");
    let text = metadata_text(&path.join("out.png"));
    assert!(text.contains("stop=signal"), "{text}");
    assert!(!path.join("out.partial.png").exists());
    // The time limit too, recording it; a finished render records done.
    let mut args = long_render_args(&["limited.png"]);
    args.extend(["--time-limit", "0.5"]);
    let output = common::vkpath(path, &args);
    assert_eq!(output.status.code(), Some(0));
    let text = metadata_text(&path.join("limited.png"));
    assert!(
        text.contains("spp_requested=4096; stop=time-limit"),
        "{text}"
    );
    let output = common::vkpath(
        path,
        &[
            "render", "--width", "8", "--height", "8", "--spp", "2", "-o", "done.png",
        ],
    );
    assert_eq!(output.status.code(), Some(0));
    let text = metadata_text(&path.join("done.png"));
    assert!(
        text.starts_with("spp=2; sample_range=0..2; spp_requested=2; stop=done; version="),
        "{text}"
    );
}

#[test]
fn a_device_fault_keeps_the_finished_image_and_says_what_is_left() {
    // Submission 9 comes after the first batches of a 1-spp-per-frame render of 64 spp
    // (see production::device_faults_name_the_device_and_keep_the_checkpoint).
    let base = [
        "render",
        "--integrator",
        "workshop",
        "-o",
        "out.png",
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "64",
        "--samples-per-frame",
        "1",
    ];
    let with_checkpoint = ["--checkpoint", "ck.exr", "--checkpoint-interval", "0.001"];
    for (fault, checkpoint) in [
        ("fence-timeout:9", false),
        ("device-lost:9", false),
        ("device-lost:9", true),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path();
        let before = b"a finished image from yesterday".to_vec();
        std::fs::write(path.join("out.png"), &before).unwrap();
        let mut args = base.to_vec();
        if checkpoint {
            args.extend_from_slice(&with_checkpoint);
        }
        let output = common::vkpath_with_env(path, &args, &[("VKPATH_INJECT_FAULT", fault)]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{fault}: {stderr}");
        assert_eq!(
            std::fs::read(path.join("out.png")).unwrap(),
            before,
            "{fault}"
        );
        let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
        assert_eq!(errors.len(), 1, "{fault}: one line: {stderr}");
        let line = errors[0];
        if fault.starts_with("fence-timeout") {
            // The device still answers: what it took goes beside the finished image.
            let text = metadata_text(&path.join("out.partial.png"));
            assert!(text.contains("stop=failed"), "{text}");
            assert!(
                line.contains("in 'out.partial.png' ('out.png' left as it was)")
                    && line.contains("starts over")
                    && !line.contains("--resume"),
                "{line}"
            );
            continue;
        }
        // A lost device gives nothing back (fault injection keeps it lost, as a real one
        // stays): no image, and the line says what is left.
        assert!(!path.join("out.partial.png").exists(), "{line}");
        assert!(line.contains("no image was written"), "{line}");
        match (checkpoint, path.join("ck.exr").exists()) {
            (false, _) => assert!(line.contains("without --checkpoint nothing"), "{line}"),
            (true, true) => {
                let (state, _) =
                    vkpath::render::state_exr::read_state(&path.join("ck.exr")).unwrap();
                let held = format!("holds the first {} spp", state.samples.len());
                assert!(
                    line.contains(&held) && line.contains("--resume 'ck.exr'"),
                    "{line}"
                );
            }
            (true, false) => assert!(line.contains("no checkpoint had been written"), "{line}"),
        }
    }
}
