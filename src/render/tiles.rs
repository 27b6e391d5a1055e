//! Rendering in tiles: which tiles an area is split into (`--tile-size`, or automatically
//! when it would not fit the device), the two orders a render takes their samples in
//! (`TileOrder`: every frame visits every tile, or each tile is finished before the next),
//! copying a tile's state between the host and the tile-sized accumulation image, and the
//! host memory each order needs. Every pixel takes the same samples in the same order
//! whatever the tiles and their order, so a tiled image is bit for bit the untiled one.

use crate::contract;
use crate::error::{Error, Result};
use crate::render::region::{automatic_tile_side, PixelRegion, ACCUMULATION_BYTES_PER_PIXEL};
use crate::render::settings::RenderSettings;
use crate::scene::Scene;
use crate::vk::Context;

mod order;

pub(crate) use order::{TileDevice, Tiles, TilesEnd};

/// Device bytes of the scene's buffers: the triangles (96 bytes each), with a BVH their
/// positions again for the traversal (48 bytes each) and at most 1 wide node per triangle
/// (112 bytes each; there are fewer nodes than the binary tree's interior nodes), the lights
/// (16 bytes each and a header) and every triangle's light-selection word (4 bytes each).
pub(crate) fn scene_bytes(scene: &Scene) -> u64 {
    scene.triangles.len() as u64 * (96 + 48 + 112 + 16 + 4) + 16
}

/// Layers of the accumulation.
pub(crate) fn layer_count() -> usize {
    contract::ACCUMULATION_LAYER_COUNT as usize
}

/// Texels of the accumulation of `area`: every layer's pixels.
pub(crate) fn area_texel_count(area: PixelRegion) -> usize {
    area.width() as usize * area.height() as usize * layer_count()
}

/// The tiles the render of `area` is split into (`settings.tile_size`, or automatically
/// when its accumulation would not fit half the device's memory beside the scene, or its
/// image would exceed the device's largest side); empty when it is rendered in one piece.
pub(crate) fn tile_layout(
    context: &Context,
    scene: &Scene,
    settings: &RenderSettings,
    area: PixelRegion,
) -> Vec<PixelRegion> {
    let side = settings.tile_size.or_else(|| {
        let available = context.device_memory_bytes();
        // Half the heap: textures, the driver and other renders need room too.
        let budget = (available / 2).saturating_sub(scene_bytes(scene));
        let budget = if available == 0 { 0 } else { budget.max(1) };
        automatic_tile_side(
            area.width(),
            area.height(),
            budget,
            context.limits.max_image_dimension2_d,
        )
    });
    match side {
        Some(side) if side < area.width() || side < area.height() => area.tiles(side, side),
        _ => Vec::new(),
    }
}

/// Copies the texels of `tile` (every layer) between the state of `area` (`Accumulation`'s
/// layout) and a tile image's texels (each layer `image_width` wide, as many rows as the
/// image has, the tile in its top-left corner): into the image when `to_image`, else back.
pub(crate) fn copy_tile(
    from: &[[f32; 4]],
    area: PixelRegion,
    to: &mut [[f32; 4]],
    image_width: usize,
    tile: PixelRegion,
    to_image: bool,
) {
    let area_width = area.width() as usize;
    let area_pixels = area_width * area.height() as usize;
    let image_layer = if to_image { to.len() } else { from.len() } / layer_count();
    let width = tile.width() as usize;
    for layer in 0..layer_count() {
        for row in 0..tile.height() as usize {
            let area_row = (tile.y0 - area.y0) as usize + row;
            let area_start =
                layer * area_pixels + area_row * area_width + (tile.x0 - area.x0) as usize;
            let image_start = layer * image_layer + row * image_width;
            if to_image {
                to[image_start..image_start + width]
                    .copy_from_slice(&from[area_start..area_start + width]);
            } else {
                to[area_start..area_start + width]
                    .copy_from_slice(&from[image_start..image_start + width]);
            }
        }
    }
}

/// Bytes of host memory a render in tiles that visits every tile each frame holds per
/// pixel of its area at most: its state (`ACCUMULATION_BYTES_PER_PIXEL`), the batch's new
/// state beside it, and at a checkpoint or the end the state handed out, the image made of
/// it and the output's channels (about as much again each).
pub(crate) const TILED_HOST_BYTES_PER_PIXEL: u64 = 5 * ACCUMULATION_BYTES_PER_PIXEL;

/// Bytes of host memory a render finished tile by tile holds per pixel of its area at
/// most: the finished image (`RenderedImage`: mean 16, second moment 12, sample count 4)
/// and the channels an EXR output copies out of it (16, 32 with --moments).
pub(crate) const TILE_BY_TILE_HOST_BYTES_PER_PIXEL: u64 = 32 + 32;

/// Refuses a tiled render whose host memory (`bytes_per_pixel` of its area) would not fit
/// in `available` bytes (`None`: unknown, not checked): tiles spare the device, not always
/// the host.
pub(crate) fn validate_host_memory(
    settings: &RenderSettings,
    area: PixelRegion,
    available: Option<u64>,
    bytes_per_pixel: u64,
) -> Result<()> {
    let needed = u64::from(area.width()) * u64::from(area.height()) * bytes_per_pixel;
    let (what, advice) = match bytes_per_pixel {
        TILE_BY_TILE_HOST_BYTES_PER_PIXEL => ("the finished image", "use a smaller image"),
        _ => (
            "the state",
            "use a smaller image, or go tile by tile (--tile-size without --checkpoint, \
             --resume, --time-limit, --preview, --tev or --guiding)",
        ),
    };
    match available {
        Some(available) if needed > available => Err(Error::InvalidSettings(format!(
            "the render needs about {} MB of host memory for {what} of {}x{} pixels of the \
             {}x{} image ({bytes_per_pixel} bytes a pixel, rendered in tiles), more than the \
             {} MB available: {advice} or a --region",
            needed >> 20,
            area.width(),
            area.height(),
            settings.width,
            settings.height,
            available >> 20
        ))),
        _ => Ok(()),
    }
}

/// The host memory available to a new allocation (Linux's `MemAvailable`), if known.
pub(crate) fn host_available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiled_renders_must_fit_the_hosts_memory() {
        let settings = RenderSettings {
            width: 1000,
            height: 800,
            ..RenderSettings::default()
        };
        let area = PixelRegion::parse("0,0,1000,500").unwrap();
        for per_pixel in [
            TILED_HOST_BYTES_PER_PIXEL,
            TILE_BY_TILE_HOST_BYTES_PER_PIXEL,
        ] {
            let needed = 1000 * 500 * per_pixel;
            assert!(validate_host_memory(&settings, area, Some(needed), per_pixel).is_ok());
            assert!(validate_host_memory(&settings, area, None, per_pixel).is_ok());
            let message = validate_host_memory(&settings, area, Some(needed - 1), per_pixel)
                .unwrap_err()
                .to_string();
            assert!(
                message.contains("of 1000x500 pixels of the 1000x800 image"),
                "{message}"
            );
            let tile_by_tile = per_pixel == TILE_BY_TILE_HOST_BYTES_PER_PIXEL;
            assert_eq!(
                message.contains("go tile by tile"),
                !tile_by_tile,
                "{message}"
            );
        }
        assert!(host_available_memory().is_some_and(|bytes| bytes > 0));
    }

    #[test]
    fn tiles_copy_into_the_tile_image_and_back() {
        // A 5x3 area (3 layers), a 2x2 tile at (2, 1) in a 3x2 tile image.
        let area = PixelRegion::parse("10,20,15,23").unwrap();
        let layers = layer_count();
        let state: Vec<[f32; 4]> = (0..15 * layers).map(|i| [i as f32; 4]).collect();
        let tile = PixelRegion::parse("12,21,14,23").unwrap();
        let mut image = vec![[-1.0f32; 4]; 3 * 2 * layers];
        copy_tile(&state, area, &mut image, 3, tile, true);
        for layer in 0..layers {
            let at = |x: usize, y: usize| image[layer * 6 + y * 3 + x][0];
            let area_value = |x: usize, y: usize| (layer * 15 + y * 5 + x) as f32;
            assert_eq!(at(0, 0), area_value(2, 1));
            assert_eq!(at(1, 1), area_value(3, 2));
            assert_eq!(at(2, 0), -1.0, "outside the tile: untouched");
        }
        let mut back = vec![[0.0f32; 4]; 15 * layers];
        copy_tile(&image, area, &mut back, 3, tile, false);
        for (i, (a, b)) in back.iter().zip(&state).enumerate() {
            let (x, y) = ((i % 15) % 5, (i % 15) / 5);
            let inside = (2..4).contains(&x) && (1..3).contains(&y);
            assert_eq!(a[0], if inside { b[0] } else { 0.0 }, "texel {i}");
        }
    }
}
