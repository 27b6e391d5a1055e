//! The pipeline cache through the binary, each test in a cache directory of its own
//! (`VKPATH_CACHE_DIR` in a temp dir, never the user's home): a run writes one cache file,
//! a cached run renders the identical image, a corrupt file is ignored with a warning and
//! rewritten, `--no-cache` touches nothing, and a cache that cannot be written is a warning.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::vkpath_with_env;

/// A tiny render of the built-in box under a white sky (the glTF-material kernels).
const RENDER: &[&str] = &[
    "render",
    "--width",
    "16",
    "--height",
    "16",
    "--spp",
    "4",
    "--background",
    "1,1,1",
    "--integrator",
    "mis",
];

fn render(dir: &Path, cache: &Path, output: &str, extra: &[&str]) -> Output {
    let mut args = RENDER.to_vec();
    args.extend_from_slice(&["-o", output]);
    args.extend_from_slice(extra);
    let cache = cache.to_str().unwrap();
    let out = vkpath_with_env(dir, &args, &[("VKPATH_CACHE_DIR", cache)]);
    assert!(
        out.status.success(),
        "vkpath {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The cache files in `cache`.
fn cache_files(cache: &Path) -> Vec<PathBuf> {
    match std::fs::read_dir(cache) {
        Ok(entries) => entries.map(|entry| entry.unwrap().path()).collect(),
        Err(_) => Vec::new(),
    }
}

fn assert_identical(dir: &Path, a: &str, b: &str) {
    let out = common::vkpath(dir, &["compare", "--exact", a, b]);
    assert!(
        out.status.success(),
        "{a} and {b} differ: {}{}",
        String::from_utf8_lossy(&out.stdout),
        stderr(&out)
    );
}

#[test]
fn a_cached_run_renders_the_same_image_and_a_corrupt_cache_is_ignored_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let (path, cache) = (dir.path(), dir.path().join("cache"));
    // With the validation layer (the command fails if it reports anything): creating,
    // filling and reading back the cache is valid Vulkan.
    let cold = render(path, &cache, "cold.exr", &["--validate"]);
    assert!(!stderr(&cold).contains("warning"), "{}", stderr(&cold));
    let files = cache_files(&cache);
    assert_eq!(files.len(), 1, "one cache file for one device: {files:?}");
    let file = &files[0];
    let name = file.file_name().unwrap().to_string_lossy().into_owned();
    assert!(
        name.starts_with("pipelines-") && name.ends_with(".bin"),
        "{name}"
    );
    let saved = std::fs::read(file).unwrap();
    assert!(saved.starts_with(b"VKPATHPC"));

    let warm = render(path, &cache, "warm.exr", &["--validate"]);
    assert!(!stderr(&warm).contains("warning"), "{}", stderr(&warm));
    // Issue 58: lavapipe keeps nothing in the cache and compiles again for seconds, which
    // printed "building kernels for this scene (first run on this device)" on every warm
    // run. Only a run that found no cache for its device says so (the cold run does when
    // its build passes a second, which depends on the machine's speed).
    assert!(!stderr(&warm).contains("first run"), "{}", stderr(&warm));
    assert_identical(path, "cold.exr", "warm.exr");

    // A damaged file: the magic survives, the rest is garbage of the same length.
    let mut damaged = saved.clone();
    for byte in &mut damaged[8..] {
        *byte ^= 0x5a;
    }
    std::fs::write(file, &damaged).unwrap();
    let after_damage = render(path, &cache, "damaged.exr", &[]);
    let message = stderr(&after_damage);
    assert!(
        message.contains("vkpath: warning: ignoring the pipeline cache"),
        "{message}"
    );
    assert_identical(path, "cold.exr", "damaged.exr");
    // The build replaced the damaged file with a good one: the next run does not warn.
    assert_ne!(std::fs::read(file).unwrap(), damaged);
    let repaired = render(path, &cache, "repaired.exr", &[]);
    assert!(
        !stderr(&repaired).contains("warning"),
        "{}",
        stderr(&repaired)
    );

    // A truncated file (a crash cannot leave one, writes are atomic, but a disk can).
    std::fs::write(file, &saved[..saved.len() / 2]).unwrap();
    let truncated = render(path, &cache, "truncated.exr", &[]);
    assert!(
        stderr(&truncated).contains("ignoring the pipeline cache"),
        "{}",
        stderr(&truncated)
    );
    assert_identical(path, "cold.exr", "truncated.exr");
    assert_eq!(cache_files(&cache).len(), 1, "no temporary files are left");
}

#[test]
fn no_cache_reads_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    render(dir.path(), &cache, "a.exr", &["--no-cache"]);
    assert!(!cache.exists(), "--no-cache created {}", cache.display());
}

#[test]
fn a_cache_that_cannot_be_written_is_a_warning_not_an_error() {
    let dir = tempfile::tempdir().unwrap();
    // A file where the cache directory should be.
    let cache = dir.path().join("not-a-directory");
    std::fs::write(&cache, b"").unwrap();
    let out = render(dir.path(), &cache, "a.exr", &[]);
    let message = stderr(&out);
    assert!(
        message.contains("vkpath: warning: cannot save the pipeline cache"),
        "{message}"
    );
    assert!(dir.path().join("a.exr").exists());
}
