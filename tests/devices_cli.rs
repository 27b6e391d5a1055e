//! Issue 41 item 4, the right GPU, through the binary on lavapipe: `vkpath devices --json`
//! gives each device's UUID, `--device UUID` and `VKPATH_DEVICE=UUID` render on it, an
//! unknown UUID is one line, and `CUDA_VISIBLE_DEVICES` is ignored without NVIDIA devices.

use crate::common;

use std::path::Path;

/// Runs vkpath with `env` (`VKPATH_DEVICE` and `CUDA_VISIBLE_DEVICES` empty unless `env`
/// sets them, so that the caller's environment does not choose); returns (status, stdout,
/// stderr).
fn run(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> (Option<i32>, String, String) {
    let mut all = vec![("VKPATH_DEVICE", ""), ("CUDA_VISIBLE_DEVICES", "")];
    all.extend_from_slice(env);
    let output = common::vkpath_with_env(dir, args, &all);
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).to_string(),
        String::from_utf8_lossy(&output.stderr).to_string(),
    )
}

/// The first device's UUID, from `vkpath devices --json`, checked to be NVIDIA's form, and
/// its type as the list names it.
fn first_device(dir: &Path) -> (String, String) {
    let (status, stdout, stderr) = run(dir, &["devices", "--json"], &[]);
    assert_eq!(status, Some(0), "{stderr}");
    let devices: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let kind = devices[0]["type"].as_str().expect("a type").to_string();
    assert!(devices[0].get("kind").is_none(), "{devices}");
    let uuid = devices[0]["uuid"].as_str().expect("a uuid").to_string();
    let groups: Vec<&str> = uuid.split('-').collect();
    assert_eq!(groups[0], "GPU", "{uuid}");
    let lengths: Vec<usize> = groups[1..].iter().map(|g| g.len()).collect();
    assert_eq!(lengths, [8, 4, 4, 4, 12], "{uuid}");
    assert!(
        groups[1..].iter().all(|g| g
            .chars()
            .all(|c| c.is_ascii_hexdigit() && !c.is_ascii_uppercase())),
        "{uuid}"
    );
    (uuid, kind)
}

/// A tiny render's arguments with `extra` appended.
fn tiny<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "render", "--width", "8", "--height", "8", "--spp", "1", "-o", "out.exr",
    ];
    args.extend_from_slice(extra);
    args
}

#[test]
fn device_and_vkpath_device_take_a_uuid_and_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let (uuid, kind) = first_device(dir.path());
    let (status, stdout, stderr) = run(dir.path(), &tiny(&["--device", &uuid, "--json"]), &[]);
    assert_eq!(status, Some(0), "{stderr}");
    let report: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap();
    assert_eq!(report["devices"][0]["uuid"], uuid.as_str(), "{report}");
    // Issue 58: `devices --json` said "kind": "Cpu" where the render said "type": "cpu".
    assert_eq!(report["devices"][0]["type"], kind.as_str(), "{report}");
    assert_eq!(
        report["devices"][0]["chosen_because"],
        format!("--device {uuid}").as_str()
    );
    // A unique prefix, from the environment; the device line says why.
    let prefix = &uuid[..12];
    let (status, _, stderr) = run(dir.path(), &tiny(&[]), &[("VKPATH_DEVICE", prefix)]);
    assert_eq!(status, Some(0), "{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("vkpath: device "))
        .unwrap_or_else(|| panic!("no device line: {stderr}"));
    assert!(
        line.contains(&uuid) && line.ends_with(&format!("(chosen by VKPATH_DEVICE={prefix})")),
        "{line}"
    );
    // --quiet prints no device line.
    let (status, _, stderr) = run(
        dir.path(),
        &tiny(&["--quiet"]),
        &[("VKPATH_DEVICE", prefix)],
    );
    assert_eq!((status, stderr.as_str()), (Some(0), ""));
}

#[test]
fn an_unknown_uuid_is_one_line_and_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    for env in [&[][..], &[("VKPATH_DEVICE", "GPU-00000000-dead")]] {
        let args = if env.is_empty() {
            tiny(&["--device", "GPU-00000000-dead"])
        } else {
            tiny(&[])
        };
        let (status, _, stderr) = run(dir.path(), &args, env);
        assert_eq!(status, Some(1), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        // A wrong VKPATH_DEVICE is named (issue 58): no --device shows on the command line.
        let source = if env.is_empty() {
            ""
        } else {
            "VKPATH_DEVICE=GPU-00000000-dead: "
        };
        assert!(
            stderr.starts_with(&format!(
                "vkpath: error: {source}no Vulkan device matches 'GPU-00000000-dead'"
            )),
            "{stderr}"
        );
    }
}

#[test]
fn cuda_visible_devices_is_ignored_without_nvidia_devices() {
    let dir = tempfile::tempdir().unwrap();
    // lavapipe is no NVIDIA device: a CUDA list cannot apply, and the device line says so.
    let (status, _, stderr) = run(
        dir.path(),
        &tiny(&[]),
        &[(
            "CUDA_VISIBLE_DEVICES",
            "GPU-12345678-1234-1234-1234-123456789abc",
        )],
    );
    assert_eq!(status, Some(0), "{stderr}");
    assert!(
        stderr.contains("CUDA_VISIBLE_DEVICES=GPU-12345678-1234-1234-1234-123456789abc ignored: no NVIDIA device"),
        "{stderr}"
    );
    // An empty value (hiding CUDA GPUs, as Ray does for a task without GPUs) is not worth a word.
    let (status, _, stderr) = run(dir.path(), &tiny(&[]), &[]);
    assert_eq!(status, Some(0), "{stderr}");
    assert!(!stderr.contains("CUDA_VISIBLE_DEVICES"), "{stderr}");
}
