//! What a channel's file becomes: a 2D texture (`ChannelSource::File`), rows flipped as
//! ShaderToy flips textures, or a cube map (`ChannelSource::Cube`), six faces in Vulkan's
//! (and OpenGL's) order +X, -X, +Y, -Y, +Z, -Z, each with its image's top row first, as
//! WebGL uploads cube faces (unflipped) for ShaderToy and the VS Code Shader Toy extension.
//!
//! A cube map comes from six images named by a pattern with `{}` (the extension's
//! `#iChannel0 "file://cube_{}.png"` with `#iChannel0::Type "CubeMap"`), or from one
//! equirectangular `.exr`/`.hdr` map as `--environment` reads it, resampled into six faces:
//! a direction sees the texel that `--environment` shows in that direction.

use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::cpu::environment::get_environment_uv;
use crate::error::{Error, Result};
use crate::lights::environment::{load_environment_map, EnvironmentMap};
use crate::shadertoy::runner::MAX_SIDE;

/// Largest face of a cube map made from an equirectangular map (its width / 4, the
/// equator's texel density, up to this).
const MAX_EQUIRECT_FACE: u32 = 2048;

/// The names that the `{}` of a cube map's pattern stands for, set after set (as the VS Code
/// Shader Toy extension tries them), each in the faces' order +X, -X, +Y, -Y, +Z, -Z.
pub const FACE_NAME_SETS: [[&str; 6]; 4] = [
    ["e", "w", "u", "d", "n", "s"],
    ["east", "west", "up", "down", "north", "south"],
    ["px", "nx", "py", "ny", "pz", "nz"],
    ["posx", "negx", "posy", "negy", "posz", "negz"],
];

/// Reads an image file as `rgba32f` texels, rows top-down: PNG and JPEG as their 8-bit (or
/// 16-bit) values scaled to [0, 1], EXR as its floats (alpha 1).
pub fn read_image_texels(path: &Path) -> Result<(u32, u32, Vec<[f32; 4]>)> {
    let is_exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let (width, height, top_down): (u32, u32, Vec<[f32; 4]>) = if is_exr {
        let image = crate::image_io::exr_input::read_exr(path)?.image;
        (image.width, image.height, image.mean)
    } else {
        let image = image::open(path)
            .map_err(|e| {
                Error::Image(format!(
                    "cannot read the channel image '{}': {e}",
                    path.display()
                ))
            })?
            .to_rgba32f();
        let (width, height) = image.dimensions();
        (width, height, image.pixels().map(|p| p.0).collect())
    };
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(Error::Image(format!(
            "the channel image '{}' is {width}x{height}; channels take 1..={MAX_SIDE} texels a side",
            path.display()
        )));
    }
    Ok((width, height, top_down))
}

/// Reads an image file for a 2D channel as `rgba32f` texels, rows bottom-up (ShaderToy
/// flips textures so that (0, 0) is the bottom-left corner).
pub fn read_channel_file(path: &Path) -> Result<(u32, u32, Vec<[f32; 4]>)> {
    let (width, height, top_down) = read_image_texels(path)?;
    Ok((width, height, flip_rows(&top_down, width, height)))
}

/// The rows of a `width` x `height` image in the opposite order.
pub fn flip_rows(texels: &[[f32; 4]], width: u32, height: u32) -> Vec<[f32; 4]> {
    let width = width as usize;
    (0..height as usize)
        .rev()
        .flat_map(|row| texels[row * width..(row + 1) * width].iter().copied())
        .collect()
}

/// Reads a cube map's source: a path with `{}` names six square images of one size; an
/// `.exr` or `.hdr` file is an equirectangular map. Returns the face side and the six faces'
/// texels, face after face (+X, -X, +Y, -Y, +Z, -Z), rows top-down.
pub fn read_cube_channel(path: &Path) -> Result<(u32, Vec<[f32; 4]>)> {
    let text = path.to_string_lossy();
    if text.contains("{}") {
        let faces = face_paths(path)?;
        let mut side = None;
        let mut texels = Vec::new();
        for face in &faces {
            let (width, height, face_texels) = read_image_texels(face)?;
            if width != height || side.is_some_and(|s| s != width) {
                return Err(Error::Image(format!(
                    "the cube map '{}': '{}' is {width}x{height}; its six faces must be square and of one size",
                    path.display(),
                    face.display()
                )));
            }
            side = Some(width);
            texels.extend(face_texels);
        }
        return Ok((side.unwrap_or(1), texels));
    }
    let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
    if !matches!(extension.as_deref(), Some("exr" | "hdr")) {
        return Err(Error::Image(format!(
            "the cube map '{}' is neither six images named with {{}} (e.g. sky_{{}}.png for sky_px.png … sky_nz.png) nor an equirectangular .exr or .hdr map",
            path.display()
        )));
    }
    let map = load_environment_map(path).map_err(|e| Error::Image(e.to_string()))?;
    let side = (map.width / 4).clamp(1, MAX_EQUIRECT_FACE);
    Ok((side, equirect_to_cube(&map, side)))
}

/// The six files a cube map's pattern names: the first set of `FACE_NAME_SETS` whose six
/// files all exist.
fn face_paths(pattern: &Path) -> Result<[PathBuf; 6]> {
    let text = pattern.to_string_lossy();
    FACE_NAME_SETS
        .iter()
        .map(|names| names.map(|name| PathBuf::from(text.replacen("{}", name, 1))))
        .find(|paths| paths.iter().all(|p| p.is_file()))
        .ok_or_else(|| {
            Error::Image(format!(
                "the cube map '{}': no set of six faces found (its {{}} stands for px, nx, py, ny, pz, nz; posx … negz; e, w, u, d, n, s; or east … south)",
                pattern.display()
            ))
        })
}

/// The direction (not normalized) through the point (s, t) of cube face `face` (0..6: +X,
/// -X, +Y, -Y, +Z, -Z), s and t in [0, 1] with (0, 0) the face image's top-left corner:
/// the inverse of Vulkan's (and OpenGL's) cube-map face selection, where for +X, for
/// example, s = (-z / x + 1) / 2 and t = (-y / x + 1) / 2.
pub fn cube_face_direction(face: usize, s: f32, t: f32) -> Vec3 {
    let (a, b) = (2.0 * s - 1.0, 2.0 * t - 1.0);
    match face {
        0 => Vec3::new(1.0, -b, -a),
        1 => Vec3::new(-1.0, -b, a),
        2 => Vec3::new(a, 1.0, b),
        3 => Vec3::new(a, -1.0, -b),
        4 => Vec3::new(a, -b, 1.0),
        _ => Vec3::new(-a, -b, -1.0),
    }
}

/// The six `side` x `side` faces of an equirectangular map: each texel is the map's texel
/// (nearest, as vkpath reads the map: piecewise constant) in the direction of its centre.
pub fn equirect_to_cube(map: &EnvironmentMap, side: u32) -> Vec<[f32; 4]> {
    let mut texels = Vec::with_capacity(6 * (side * side) as usize);
    for face in 0..6 {
        for row in 0..side {
            for column in 0..side {
                let s = (column as f32 + 0.5) / side as f32;
                let t = (row as f32 + 0.5) / side as f32;
                let uv = get_environment_uv(cube_face_direction(face, s, t).normalize());
                let x = ((uv.x * map.width as f32).max(0.0) as u32).min(map.width - 1);
                let y = ((uv.y * map.height as f32).max(0.0) as u32).min(map.height - 1);
                let texel = map.texels[(y * map.width + x) as usize];
                texels.push([texel.x, texel.y, texel.z, 1.0]);
            }
        }
    }
    texels
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vulkan's face selection and (s, t) for a direction (the specification's table).
    fn select_face(d: Vec3) -> (usize, f32, f32) {
        let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
        let (face, sc, tc, ma) = if ax >= ay && ax >= az {
            if d.x > 0.0 {
                (0, -d.z, -d.y, ax)
            } else {
                (1, d.z, -d.y, ax)
            }
        } else if ay >= az {
            if d.y > 0.0 {
                (2, d.x, d.z, ay)
            } else {
                (3, d.x, -d.z, ay)
            }
        } else if d.z > 0.0 {
            (4, d.x, -d.y, az)
        } else {
            (5, -d.x, -d.y, az)
        };
        (face, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0))
    }

    #[test]
    fn face_directions_invert_the_face_selection() {
        for face in 0..6 {
            for (s, t) in [(0.5, 0.5), (0.2, 0.7), (0.9, 0.1)] {
                let (selected, s2, t2) = select_face(cube_face_direction(face, s, t));
                assert_eq!(selected, face);
                assert!(
                    (s - s2).abs() < 1e-6 && (t - t2).abs() < 1e-6,
                    "{face} {s} {t}"
                );
            }
        }
    }

    #[test]
    fn an_equirect_map_becomes_faces_that_look_the_same_way() {
        // 4 x 2: the top row is the sky (+Y), the bottom row the ground; the columns of the
        // lower row are the azimuths around -X (column 1: u 0.25) and +X (column 3: u 0.75).
        let texel = |v: f32| Vec3::splat(v);
        let map = EnvironmentMap {
            width: 4,
            height: 2,
            texels: [1.0, 1.0, 1.0, 1.0, 2.0, 3.0, 4.0, 5.0].map(texel).to_vec(),
        };
        let faces = equirect_to_cube(&map, 1);
        // Each 1 x 1 face sees its axis: +X column 3 at v 0.5 (the lower row, as v = 0.5
        // rounds down to row 1), -X column 1, +Y the sky.
        assert_eq!(faces[0][0], 5.0);
        assert_eq!(faces[1][0], 3.0);
        assert_eq!(faces[2][0], 1.0);
    }
}
