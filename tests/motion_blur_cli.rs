//! Motion blur through the binary (`--shutter`, `--shutter-position`, `--motion-steps`): a
//! blurred render equals the mean of still renders at times spread evenly across the
//! shutter, for a translating node, a rotating node and a moving camera; a square moving at constant
//! speed has edges whose 10–90 % ramp is 0.8 × its image-space travel during the shutter (a
//! box shutter turns a sharp edge into a linear ramp as wide as the travel); a shutter on a
//! still scene gives the still image bit for bit; bad values are one-line usage errors.

use std::path::Path;

use serde_json::json;

use crate::common::runs::{exr_bits, exr_pixels, run};

/// The image: 48 x 16 pixels, a 30 degree vertical field of view, the camera at the origin
/// looking down -z at the square 4 units away.
const WIDTH: usize = 48;
const HEIGHT: usize = 16;
const FOV_DEGREES: f32 = 30.0;
const DEPTH: f32 = 4.0;
/// The square's half-size (world units), and how fast the moving thing (the square, or the
/// camera the other way) slides along x (units per second).
const HALF_SIZE: f32 = 0.6;
const SPEED: f32 = 2.0;
/// The stills: frames 1..=STILLS at STILL_FPS, the midpoints of STILLS equal parts of the
/// blurred render's shutter [0.5 / STILL_FPS, (STILLS + 0.5) / STILL_FPS].
const STILLS: u32 = 8;
const STILL_FPS: f32 = 16.0;
/// A smaller copy of the square (`SPINNER_SCALE`), centred at `SPINNER_CENTRE` in the image's
/// top rows (right of the sliding square's path), that turns about the view axis: a rotating
/// node, a quarter turn during the shutter.
const SPINNER_CENTRE: [f32; 3] = [2.5, 0.75, -DEPTH];
const SPINNER_SCALE: f32 = 0.6;
const SPIN_DEGREES_PER_SECOND: f32 = 180.0;
/// The rows the spinner covers.
const SPINNER_ROWS: std::ops::Range<usize> = 0..7;
/// Keys across the blurred render's shutter: a rotation moves linearly between two keys
/// (a chord of its arc), so the spinner's quarter turn takes 8 keys (its corners' chords
/// then stray 0.01 px from the arc); the sliding square's linear motion is exact at any number.
const MOTION_STEPS: &str = "8";

/// Pixels per world unit on the square's plane.
fn pixels_per_unit() -> f32 {
    0.5 * HEIGHT as f32 / (0.5 * FOV_DEGREES.to_radians()).tan() / DEPTH
}

/// The shutter's length in seconds, and the square's travel across it in pixels.
fn shutter_seconds() -> f32 {
    STILLS as f32 / STILL_FPS
}

/// Writes `moving.gltf`: an emissive square (radiance 1, black base) facing the camera at
/// depth `DEPTH` and a camera at the origin; the square's node (`camera_moves`: the camera's)
/// slides LINEAR along x at `SPEED` (the camera at -`SPEED`) from 0 s to 2 s.
fn write_scene(dir: &Path, camera_moves: bool) {
    let h = HALF_SIZE;
    let positions: [f32; 12] = [-h, -h, 0.0, h, -h, 0.0, h, h, 0.0, -h, h, 0.0];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let times: [f32; 2] = [0.0, 2.0];
    let sign = if camera_moves { -1.0 } else { 1.0 };
    let z = if camera_moves { 0.0 } else { -DEPTH };
    let start_x = -0.6 * sign;
    let slide: [f32; 6] = [start_x, 0.0, z, start_x + sign * 2.0 * SPEED, 0.0, z];
    // The spinner turns about the view axis at SPIN_DEGREES_PER_SECOND: keys a quarter turn
    // apart (slerp takes the short way between them)
    let spin_times: [f32; 5] = [0.0, 0.5, 1.0, 1.5, 2.0];
    let spin: Vec<f32> = spin_times
        .iter()
        .flat_map(|t| {
            let half = 0.5 * (SPIN_DEGREES_PER_SECOND * t).to_radians();
            [0.0, 0.0, half.sin(), half.cos()]
        })
        .collect();
    let mut data: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    for blob in [
        bytemuck_bytes(&positions),
        indices.iter().flat_map(|i| i.to_le_bytes()).collect(),
        bytemuck_bytes(&times),
        bytemuck_bytes(&slide),
        bytemuck_bytes(&spin_times),
        bytemuck_bytes(&spin),
    ] {
        views.push(json!({"buffer": 0, "byteOffset": data.len(), "byteLength": blob.len()}));
        data.extend(blob);
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
    }
    let (square_translation, camera_translation) = if camera_moves {
        ([0.0, 0.0, -DEPTH], [start_x, 0.0, 0.0])
    } else {
        ([start_x, 0.0, -DEPTH], [0.0, 0.0, 0.0])
    };
    let moving_node = if camera_moves { 1 } else { 0 };
    let document = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"name": "square", "mesh": 0, "translation": square_translation},
            {"name": "camera", "camera": 0, "translation": camera_translation},
            {"name": "spinner", "mesh": 0, "translation": SPINNER_CENTRE, "scale": [SPINNER_SCALE, SPINNER_SCALE, SPINNER_SCALE]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": FOV_DEGREES.to_radians(), "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}, "emissiveFactor": [1, 1, 1]}],
        "animations": [{
            "channels": [
                {"sampler": 0, "target": {"node": moving_node, "path": "translation"}},
                {"sampler": 1, "target": {"node": 2, "path": "rotation"}},
            ],
            "samplers": [
                {"input": 2, "output": 3, "interpolation": "LINEAR"},
                {"input": 4, "output": 5, "interpolation": "LINEAR"},
            ],
        }],
        "buffers": [{
            "byteLength": data.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64::encode(&data)),
        }],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-h, -h, 0], "max": [h, h, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [2.0]},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 4, "componentType": 5126, "count": 5, "type": "SCALAR", "min": [0.0], "max": [2.0]},
            {"bufferView": 5, "componentType": 5126, "count": 5, "type": "VEC4"},
        ],
    });
    std::fs::write(dir.join("moving.gltf"), document.to_string()).unwrap();
}

/// Little-endian bytes of floats.
fn bytemuck_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// The options every render here shares: size, PCG (independent samples), quiet.
fn common_options() -> Vec<String> {
    [
        "--width",
        &WIDTH.to_string(),
        "--height",
        &HEIGHT.to_string(),
        "--sampler",
        "pcg",
        "--quiet",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// Runs `vkpath render moving.gltf` with `extra` and asserts it succeeded.
fn render(dir: &Path, extra: &[&str]) {
    let mut args = vec!["render", "moving.gltf"];
    let common = common_options();
    args.extend(common.iter().map(String::as_str));
    args.extend_from_slice(extra);
    let result = run(dir, &args, &[]);
    assert_eq!(result.code, Some(0), "{args:?}: {}", result.stderr);
}

/// The mean over the square's middle rows of each column's red value.
fn column_profile(pixels: &[[f32; 4]]) -> Vec<f32> {
    let rows = HEIGHT / 2 - 3..HEIGHT / 2 + 3;
    (0..WIDTH)
        .map(|x| rows.clone().map(|y| pixels[y * WIDTH + x][0]).sum::<f32>() / rows.len() as f32)
        .collect()
}

/// Where a profile first rises through `level` (linear between column centres), in pixels
/// from the image's left edge.
fn rising_crossing(profile: &[f32], level: f32) -> f32 {
    let x = (1..profile.len())
        .find(|&x| profile[x - 1] < level && profile[x] >= level)
        .expect("the profile rises through the level");
    let (a, b) = (profile[x - 1], profile[x]);
    (x - 1) as f32 + 0.5 + (level - a) / (b - a)
}

/// Renders the blurred frame (256 spp) and the stills (32 spp each) of `moving.gltf`, and
/// checks that the blur is the stills' mean and that its left edge ramps over 0.8 × travel.
fn blur_equals_the_mean_of_stills(dir: &Path) {
    let time = (0.5 / STILL_FPS).to_string();
    let blur_fps = (1.0 / shutter_seconds()).to_string();
    render(
        dir,
        &[
            "-o",
            "blurred.exr",
            "--spp",
            "256",
            "--time",
            &time,
            "--shutter",
            "1",
            "--shutter-position",
            "start",
            "--fps",
            &blur_fps,
            "--motion-steps",
            MOTION_STEPS,
        ],
    );
    let frames = format!("1..{}", STILLS + 1);
    let still_fps = STILL_FPS.to_string();
    render(
        dir,
        &[
            "-o",
            "still_##.exr",
            "--spp",
            "32",
            "--frames",
            &frames,
            "--fps",
            &still_fps,
        ],
    );
    let blurred_pixels = exr_pixels(dir, "blurred.exr");
    let blurred = column_profile(&blurred_pixels);
    let stills: Vec<Vec<[f32; 4]>> = (1..=STILLS)
        .map(|frame| exr_pixels(dir, &format!("still_{frame:02}.exr")))
        .collect();
    let mut mean = vec![0.0; WIDTH];
    for still in &stills {
        for (m, s) in mean.iter_mut().zip(column_profile(still)) {
            *m += s / STILLS as f32;
        }
    }
    spinner_blurs_as_the_mean_of_stills(&blurred_pixels, &stills);
    // Each column mean of 6 rows: the blur's noise is at most sqrt(0.25 / (256 * 6)) = 0.013,
    // the stills' mean's the same (8 x 32 samples); the stills' midpoint rule in time is
    // exact for a linear ramp but at its two kinks, where it errs by at most 1/16 of a
    // stratum's travel. 0.08 is 4.3 standard deviations of the difference plus that; without
    // blur the edges differ by up to 0.5.
    for (x, (b, m)) in blurred.iter().zip(&mean).enumerate() {
        assert!(
            (b - m).abs() < 0.08,
            "column {x}: blurred {b}, stills' mean {m}\n{blurred:?}\n{mean:?}"
        );
    }
    // The left edge's 10-90 % ramp: 0.8 × the travel (the pixel's box filter leaves the
    // ramp's middle linear). 0.5 px: the noise moves a crossing by about 0.013 / slope
    // (0.13 px) and the column centres' interpolation a little more.
    let travel = SPEED * shutter_seconds() * pixels_per_unit();
    let ramp = rising_crossing(&blurred, 0.9) - rising_crossing(&blurred, 0.1);
    assert!(
        (ramp - 0.8 * travel).abs() < 0.5,
        "ramp {ramp} px, travel {travel} px: {blurred:?}"
    );
}

/// The rotating node: the blurred render's spinner rows, pixel by pixel, against the stills'
/// mean.
fn spinner_blurs_as_the_mean_of_stills(blurred: &[[f32; 4]], stills: &[Vec<[f32; 4]>]) {
    let pixels = SPINNER_ROWS.start * WIDTH..SPINNER_ROWS.end * WIDTH;
    let mean = |i: usize| stills.iter().map(|s| s[i][0]).sum::<f32>() / stills.len() as f32;
    // A pixel's coverage has a standard deviation of at most sqrt(0.25 / 256) = 0.031 in the
    // blur and in the stills' mean (8 x 32 samples), 0.044 in their difference: 0.2 is 4.5 of
    // them, with room for the
    // midpoint rule in time (over 336 pixels, a false alarm about once in 400 runs)
    for i in pixels.clone() {
        let (b, m) = (blurred[i][0], mean(i));
        assert!(
            (b - m).abs() < 0.2,
            "spinner pixel {i}: blurred {b}, stills' mean {m}"
        );
    }
    // The test has teeth: the first still (an unblurred spinner) is far from the mean where
    // it covers a pixel wholly or not at all (exactly 1 or 0: no noise) and the turn covers
    // it part of the time (a corner's sweep)
    let swept = pixels
        .filter(|&i| {
            let first = stills[0][i][0];
            (first == 0.0 || first == 1.0) && (first - mean(i)).abs() > 0.25
        })
        .count();
    assert!(swept >= 1, "the spinner hardly turns");
}

#[test]
fn a_translating_node_blurs_as_the_mean_of_stills_with_a_ramp_of_its_travel() {
    let dir = tempfile::tempdir().unwrap();
    write_scene(dir.path(), false);
    blur_equals_the_mean_of_stills(dir.path());
}

#[test]
fn a_moving_camera_blurs_as_the_mean_of_stills_with_a_ramp_of_its_travel() {
    let dir = tempfile::tempdir().unwrap();
    write_scene(dir.path(), true);
    blur_equals_the_mean_of_stills(dir.path());
}

#[test]
fn a_shutter_on_a_still_scene_is_the_still_image_and_bad_shutters_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path();
    let small = ["--width", "16", "--height", "16", "--spp", "4"];
    let mut plain = vec!["render", "-o", "plain.exr", "--quiet"];
    plain.extend(small);
    assert_eq!(run(path, &plain, &[]).code, Some(0));
    let mut shutter = vec!["render", "-o", "shutter.exr", "--shutter", "1"];
    shutter.extend(small);
    let result = run(path, &shutter, &[]);
    assert_eq!(result.code, Some(0), "{}", result.stderr);
    let notes: Vec<&str> = result
        .stderr
        .lines()
        .filter(|l| l.contains("--shutter"))
        .collect();
    assert_eq!(notes.len(), 1, "{}", result.stderr);
    assert!(notes[0].contains("no animation"), "{}", notes[0]);
    assert_eq!(exr_bits(path, "plain.exr"), exr_bits(path, "shutter.exr"));
    for (bad, expected) in [
        (vec!["--shutter", "-0.5"], "not a shutter"),
        (vec!["--shutter", "2.5"], "not a shutter"),
        (vec!["--shutter", "1", "--motion-steps", "1"], "motion keys"),
        (
            vec!["--shutter", "1", "--motion-steps", "65"],
            "motion keys",
        ),
        (
            vec!["--shutter", "1", "--shutter-position", "middle"],
            "middle",
        ),
    ] {
        let mut args = vec!["render", "-o", "bad.exr"];
        args.extend(small);
        args.extend(&bad);
        let result = run(path, &args, &[]);
        assert_eq!(result.code, Some(2), "{bad:?}: {}", result.stderr);
        assert!(
            result.stderr.contains(expected),
            "{bad:?}: {}",
            result.stderr
        );
    }
    // Above one frame interval: a warning, and the render goes on
    let mut long = vec!["render", "-o", "long.exr", "--shutter", "1.5"];
    long.extend(small);
    let result = run(path, &long, &[]);
    assert_eq!(result.code, Some(0), "{}", result.stderr);
    assert!(
        result.stderr.contains("longer than a frame interval"),
        "{}",
        result.stderr
    );
}

/// The `depth.Z` layer (`--aov depth`: the first hit's distance, averaged over the pixel's
/// samples, 0 where rays escape) of an EXR.
fn depth_layer(dir: &Path, name: &str) -> Vec<f32> {
    let exr = vkpath::image_io::exr_input::read_exr_channels(&dir.join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    exr.channels
        .into_iter()
        .find(|(channel, _)| channel == "depth.Z")
        .map(|(_, values)| values)
        .unwrap_or_else(|| panic!("{name} has no depth.Z"))
}

/// The means of the 4 x 4 blocks of a `side` x `side` layer.
fn block_means(layer: &[f32], side: usize) -> Vec<f32> {
    let blocks = side / 4;
    (0..blocks * blocks)
        .map(|b| {
            let (bx, by) = (4 * (b % blocks), 4 * (b / blocks));
            let sum: f32 = (0..16)
                .map(|i| layer[(by + i / 4) * side + bx + i % 4])
                .sum();
            sum / 16.0
        })
        .collect()
}

/// Deformation blur of glTF file `scene` seen by `camera`: the first hit's depth of a blurred
/// render (shutter [1/8 s, 9/8 s], 8 keys, traced through the motion BVH) against the mean of
/// 4 stills at the midpoints of its quarters, in 4 x 4 blocks.
fn deformation_blurs_as_the_mean_of_stills(scene: &str, camera: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let common = [
        "--width",
        "32",
        "--height",
        "32",
        "--aov",
        "depth",
        "--background",
        "1,1,1",
        "--sampler",
        "pcg",
        "--max-path-length",
        "1",
        "--quiet",
    ];
    let mut blurred = vec![
        "render",
        scene,
        "-o",
        "blurred.exr",
        "--spp",
        "128",
        "--time",
        "0.125",
        "--shutter",
        "2",
        "--shutter-position",
        "start",
        "--fps",
        "2",
        "--motion-steps",
        "8",
        "--accel",
        "bvh",
    ];
    blurred.extend(common);
    blurred.extend(camera);
    let result = run(d, &blurred, &[]);
    assert_eq!(result.code, Some(0), "{}", result.stderr);
    let mut stills = vec![
        "render",
        scene,
        "-o",
        "still_#.exr",
        "--spp",
        "32",
        "--frames",
        "1..5",
        "--fps",
        "4",
    ];
    stills.extend(common);
    stills.extend(camera);
    let result = run(d, &stills, &[]);
    assert_eq!(result.code, Some(0), "{}", result.stderr);
    let blurred = block_means(&depth_layer(d, "blurred.exr"), 32);
    let stills: Vec<Vec<f32>> = (1..5)
        .map(|frame| block_means(&depth_layer(d, &format!("still_{frame}.exr")), 32))
        .collect();
    let mean: Vec<f32> = (0..blurred.len())
        .map(|b| stills.iter().map(|s| s[b]).sum::<f32>() / stills.len() as f32)
        .collect();
    let far = blurred.iter().chain(&mean).fold(0.0f32, |m, &v| m.max(v));
    // A block's mean depth is a coverage average of values in [0, far]: its standard
    // deviation at most far sqrt(0.25 / (16 x 128)), for the blur and for the stills' mean
    // alike (4 x 32 samples), 0.0156 far for their difference; 0.1 far is 6.4 of them, with
    // room for the linear interpolation between keys 1/7 s apart and the stills' midpoint
    // rule in time.
    let tolerance = 0.1 * far;
    for (b, (blur, still_mean)) in blurred.iter().zip(&mean).enumerate() {
        assert!(
            (blur - still_mean).abs() < tolerance,
            "block {b}: blurred {blur}, stills' mean {still_mean} (far {far})"
        );
    }
    // The test has teeth: the first still (what an unblurred render sees) is far from the mean
    let first_off = stills[0]
        .iter()
        .zip(&mean)
        .fold(0.0f32, |m, (s, a)| m.max((s - a).abs()));
    assert!(
        first_off > 2.0 * tolerance,
        "the scene hardly moves: {first_off} (far {far})"
    );
}

#[test]
fn a_skinned_joint_and_a_morph_target_blur_as_the_mean_of_stills() {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");
    deformation_blurs_as_the_mean_of_stills(
        &format!("{data}RiggedSimple.gltf"),
        &["--camera-position", "18,0,0", "--look-at", "0,0,0"],
    );
    deformation_blurs_as_the_mean_of_stills(
        &format!("{data}SimpleMorph.gltf"),
        &["--camera-position", "0.5,0.5,3", "--look-at", "0.5,0.5,0"],
    );
}

#[test]
fn skip_existing_takes_a_still_frame_for_unfinished_and_a_blurred_one_for_finished() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write_scene(d, false);
    let frame = |shutter: &[&str]| {
        let mut args = vec![
            "render",
            "moving.gltf",
            "--frames",
            "1..2",
            "-o",
            "f_#.exr",
            "--skip-existing",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "2",
        ];
        args.extend_from_slice(shutter);
        let result = run(d, &args, &[]);
        assert_eq!(result.code, Some(0), "{args:?}: {}", result.stderr);
        result.stderr
    };
    frame(&[]);
    let blurred = frame(&["--shutter", "1"]);
    assert!(blurred.contains("rendering it again"), "{blurred}");
    let again = frame(&["--shutter", "1"]);
    assert!(again.contains("already finished, skipped"), "{again}");
    let longer = frame(&["--shutter", "1", "--motion-steps", "3"]);
    assert!(longer.contains("rendering it again"), "{longer}");
}
