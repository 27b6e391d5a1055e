//! `render --region` and tiles through the binary (issue 21): a region's pixels, and a
//! render put on the device in tiles, are bit for bit what the full untiled render gives;
//! the region's EXR records the full image as its display window; bad regions are one line.

use crate::common;

use std::collections::BTreeMap;
use std::path::Path;

use exr::prelude::read_all_flat_layers_from_file;

/// An EXR as read back: the data window's origin and size, the display window's size, and
/// every channel's values as bits (rows top-down over the data window).
struct Exr {
    origin: (i32, i32),
    size: (usize, usize),
    display: (usize, usize),
    channels: BTreeMap<String, Vec<u32>>,
}

fn read(path: &Path) -> Exr {
    let image = read_all_flat_layers_from_file(path).unwrap();
    let layer = &image.layer_data[0];
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let bits = c.sample_data.values_as_f32().map(f32::to_bits).collect();
            (c.name.to_string(), bits)
        })
        .collect();
    let display = image.attributes.display_window;
    Exr {
        origin: (
            layer.attributes.layer_position.x(),
            layer.attributes.layer_position.y(),
        ),
        size: (layer.size.width(), layer.size.height()),
        display: (display.size.width(), display.size.height()),
        channels,
    }
}

/// Runs vkpath, expects success.
fn vkpath_ok(dir: &Path, args: &[&str]) {
    let output = common::vkpath(dir, args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{args:?}: {stderr}");
}

/// A 24x16 render of the built-in box at 8 spp with moments (so that the sums of squares
/// and counts are compared too) and the validation layer (which must stay silent: vkpath
/// fails otherwise), `extra` appended. 3 samples per frame: frames end at
/// other samples than the tiles' batches do.
fn render(dir: &Path, output: &str, extra: &[&str]) {
    let mut args = vec![
        "render",
        "--width",
        "24",
        "--height",
        "16",
        "--spp",
        "8",
        "--samples-per-frame",
        "3",
        "--moments",
        "--validate",
        "-o",
        output,
    ];
    args.extend_from_slice(extra);
    vkpath_ok(dir, &args);
}

/// Asserts that every channel of `part` at data-window pixel (x, y) holds the bits of
/// `full` at (x + x0, y + y0).
fn assert_part_of(part: &Exr, full: &Exr, what: &str) {
    let (x0, y0) = (part.origin.0 as usize, part.origin.1 as usize);
    assert_eq!(
        part.channels.keys().collect::<Vec<_>>(),
        full.channels.keys().collect::<Vec<_>>()
    );
    for (name, values) in &part.channels {
        let whole = &full.channels[name];
        for y in 0..part.size.1 {
            for x in 0..part.size.0 {
                let (a, b) = (
                    values[y * part.size.0 + x],
                    whole[(y + y0) * full.size.0 + x + x0],
                );
                assert_eq!(
                    a,
                    b,
                    "{what}: channel {name}, pixel ({}, {}): {} vs the full render's {}",
                    x + x0,
                    y + y0,
                    f32::from_bits(a),
                    f32::from_bits(b)
                );
            }
        }
    }
}

#[test]
fn region_pixels_equal_the_full_renders_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    // With ground-truth layers beside the colour: a region's are the full image's too
    const TRUTH: [&str; 2] = ["--aov", "material_id,position"];
    render(dir.path(), "full.exr", &TRUTH);
    let full = read(&dir.path().join("full.exr"));
    assert_eq!(
        (full.origin, full.size, full.display),
        ((0, 0), (24, 16), (24, 16))
    );
    assert!(full.channels.contains_key("material_id.Z"));
    // Inside, and along the bottom-right edge (rows run top-down, as in the file).
    for (region, origin, size) in [
        ("5,3,19,11", (5, 3), (14, 8)),
        ("17,9,24,16", (17, 9), (7, 7)),
    ] {
        let name = format!("region-{}.exr", region.replace(',', "-"));
        render(
            dir.path(),
            &name,
            &[&TRUTH[..], &["--region", region]].concat(),
        );
        let part = read(&dir.path().join(&name));
        assert_eq!(
            part.origin, origin,
            "{region}: the data window starts at X0,Y0"
        );
        assert_eq!(part.size, size, "{region}: the data window is the region");
        assert_eq!(
            part.display,
            (24, 16),
            "{region}: the display window is the full image"
        );
        assert_part_of(&part, &full, region);
    }
    // A region in tiles (4x4, not dividing it) is the same again.
    render(
        dir.path(),
        "region-tiled.exr",
        &[&TRUTH[..], &["--region", "3,2,20,13", "--tile-size", "4"]].concat(),
    );
    let part = read(&dir.path().join("region-tiled.exr"));
    assert_eq!((part.origin, part.size), ((3, 2), (17, 11)));
    assert_part_of(&part, &full, "3,2,20,13 in 4x4 tiles");
}

#[test]
fn a_forced_tiling_equals_the_untiled_render_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    render(dir.path(), "untiled.exr", &[]);
    // 5x5 tiles: 5 by 4 of them, the last column and row narrower.
    render(dir.path(), "tiled.exr", &["--tile-size", "5"]);
    let (untiled, tiled) = (
        read(&dir.path().join("untiled.exr")),
        read(&dir.path().join("tiled.exr")),
    );
    assert_eq!(
        (tiled.origin, tiled.size, tiled.display),
        ((0, 0), (24, 16), (24, 16))
    );
    assert_part_of(&tiled, &untiled, "5x5 tiles");
    // The workshop's integrator (PCG2D, another kernel) in tiles of one row.
    let workshop = ["--integrator", "workshop", "--tile-size", "24"];
    render(dir.path(), "workshop-tiled.exr", &workshop);
    render(dir.path(), "workshop.exr", &workshop[..2]);
    let (untiled, tiled) = (
        read(&dir.path().join("workshop.exr")),
        read(&dir.path().join("workshop-tiled.exr")),
    );
    assert_part_of(&tiled, &untiled, "workshop in rows");
}

#[test]
fn bad_regions_and_tiles_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (args, expected) in [
        (&["--region", "5,5,5,9"][..], "is empty"),
        (
            &["--region", "0,0,25,16"][..],
            "reaches outside the 24x16 image",
        ),
        (
            &["--region", "0,0,24,17"][..],
            "reaches outside the 24x16 image",
        ),
        (&["--tile-size", "0"][..], "--tile-size 0"),
    ] {
        let mut all = vec!["render", "--width", "24", "--height", "16", "-o", "x.exr"];
        all.extend_from_slice(args);
        let output = common::vkpath(dir.path(), &all);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!dir.path().join("x.exr").exists());
    }
    let output = common::vkpath(dir.path(), &["render", "--region", "1,2,3", "-o", "x.exr"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "a usage error: {stderr}");
    assert!(stderr.contains("is not X0,Y0,X1,Y1"), "{stderr}");
}

#[test]
fn a_tiled_render_stopped_by_a_fault_resumes_bit_for_bit() {
    // 12x12 tiles: four per frame, each its own submission; submission 10 (in the second
    // batch, after its first tiles took their samples) fails. The checkpoint must hold only
    // the samples of whole batches, so that resuming it gives the uninterrupted render.
    for adaptive in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path();
        let mut args = vec![
            "render",
            "--width",
            "24",
            "--height",
            "16",
            "--spp",
            "32",
            "--samples-per-frame",
            "1",
            "--moments",
            "--tile-size",
            "12",
            "--checkpoint",
            "ck.exr",
            "--checkpoint-interval",
            "0.001",
            "-o",
            "resumed.exr",
        ];
        if adaptive {
            args.extend_from_slice(&["--noise-threshold", "0.2", "--noise-min-spp", "4"]);
        }
        let output =
            common::vkpath_with_env(path, &args, &[("VKPATH_INJECT_FAULT", "device-lost:10")]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        let (state, _) = vkpath::render::state_exr::read_state(&path.join("ck.exr")).unwrap();
        let taken = state.samples.len();
        assert!((1..32).contains(&taken), "the checkpoint holds {taken} spp");
        let mut resume = args.clone();
        resume.extend_from_slice(&["--resume", "ck.exr"]);
        vkpath_ok(path, &resume);
        // The uninterrupted render, untiled.
        let mut whole: Vec<&str> = args[..10].to_vec();
        whole.extend_from_slice(&args[16..]);
        let output_index = whole.iter().position(|a| *a == "resumed.exr").unwrap();
        whole[output_index] = "whole.exr";
        vkpath_ok(path, &whole);
        let (resumed, whole) = (
            read(&path.join("resumed.exr")),
            read(&path.join("whole.exr")),
        );
        assert_part_of(
            &resumed,
            &whole,
            if adaptive { "adaptive" } else { "uniform" },
        );
    }
}

#[test]
fn tiles_finished_one_at_a_time_equal_the_untiled_render_bit_for_bit() {
    // Light samples (nee) with PCG2D, and the albedo and normal layers beside the colour
    // (and the ground truth's material_id and position, from the pixel centres' first hits):
    // untiled, in 7x7 tiles finished one at a time (a plain render in tiles: 4 by 3 of
    // them, the last column 3 wide and the last row 2 high), and in the same tiles visited
    // every frame (a checkpoint keeps the whole state), every channel is the same bits.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let settings = [
        "--integrator",
        "nee",
        "--sampler",
        "pcg",
        "--aov",
        "albedo,normal,material_id,position",
    ];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut args = settings.to_vec();
        args.extend_from_slice(extra);
        args
    };
    render(path, "untiled.exr", &settings);
    render(path, "one-at-a-time.exr", &with(&["--tile-size", "7"]));
    render(
        path,
        "every-frame.exr",
        &with(&["--tile-size", "7", "--checkpoint", "ck.exr"]),
    );
    let untiled = read(&path.join("untiled.exr"));
    assert!(
        untiled.channels.contains_key("albedo.R")
            && untiled.channels.contains_key("material_id.Z")
            && untiled.channels.contains_key("position.R"),
        "the layers are there"
    );
    for name in ["one-at-a-time.exr", "every-frame.exr"] {
        let tiled = read(&path.join(name));
        assert_eq!((tiled.origin, tiled.size), ((0, 0), (24, 16)));
        assert_part_of(&tiled, &untiled, name);
        let output = common::vkpath(path, &["compare", "--exact", "untiled.exr", name]);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(output.status.success(), "{name}: {stdout}");
    }
    // The render that visited every tile each frame kept the whole state: its checkpoint.
    let (state, _) = vkpath::render::state_exr::read_state(&path.join("ck.exr")).unwrap();
    assert_eq!(state.samples, 0..8);
}

#[test]
fn tiles_finished_one_at_a_time_write_nothing_when_a_fault_stops_them() {
    // 4x4 tiles: 24 of them, each at least one submission of its own, so submission 10
    // (after set-up, as in the test above) fails before the last tile is done. The tiles
    // finished by then are not an image of the samples asked for, and the others have
    // none: the command fails with one line and writes nothing.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let args = [
        "render",
        "--width",
        "24",
        "--height",
        "16",
        "--spp",
        "8",
        "--samples-per-frame",
        "1",
        "--tile-size",
        "4",
        "-o",
        "out.exr",
    ];
    let output = common::vkpath_with_env(path, &args, &[("VKPATH_INJECT_FAULT", "device-lost:10")]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "one line: {stderr}");
    assert!(!path.join("out.exr").exists(), "{stderr}");
    assert!(!path.join("out.partial.exr").exists(), "{stderr}");
}
