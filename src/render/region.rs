//! Rectangles of the image: the part a render takes (`--region`) and the tiles it is split
//! into when the whole would not fit the device (`--tile-size`, or automatically). Pixels
//! are counted from the image's top-left corner, as its rows are stored; a rectangle holds
//! columns `x0..x1` and rows `y0..y1` (the ends excluded). A pixel's samples depend only on
//! its place in the full image, so a region or a tile holds exactly the values the full
//! render gives its pixels.

use crate::contract;
use crate::error::{Error, Result};

/// A rectangle of pixels of an image: columns `x0..x1`, rows `y0..y1` from the top-left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PixelRegion {
    /// First column.
    pub x0: u32,
    /// First row (from the top).
    pub y0: u32,
    /// Column past the last.
    pub x1: u32,
    /// Row past the last.
    pub y1: u32,
}

/// A `--region` that is not four whole numbers (`PixelRegion::parse`): the text given.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "'{0}' is not X0,Y0,X1,Y1 (four whole numbers >= 0: columns X0..X1 and rows Y0..Y1 from \
     the top-left, the ends excluded)"
)]
pub struct RegionSyntaxError(pub String);

impl PixelRegion {
    /// The whole of a `width` x `height` image.
    pub fn whole(width: u32, height: u32) -> PixelRegion {
        PixelRegion {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Parses `X0,Y0,X1,Y1` (four integers, the ends excluded), as `--region` takes it.
    pub fn parse(text: &str) -> std::result::Result<PixelRegion, RegionSyntaxError> {
        let parsed: Option<Vec<u32>> = text.split(',').map(|n| n.trim().parse().ok()).collect();
        match parsed.as_deref() {
            Some(&[x0, y0, x1, y1]) => Ok(PixelRegion { x0, y0, x1, y1 }),
            _ => Err(RegionSyntaxError(text.to_string())),
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }

    /// Whether this is the whole of a `width` x `height` image.
    pub fn is_whole(&self, width: u32, height: u32) -> bool {
        *self == PixelRegion::whole(width, height)
    }

    /// Checks that the region is a non-empty part of a `width` x `height` image; the error
    /// is one line naming what is wrong.
    pub fn validate(&self, width: u32, height: u32) -> Result<()> {
        if self.x1 <= self.x0 || self.y1 <= self.y0 {
            return Err(Error::InvalidSettings(format!(
                "--region {self} is empty: it needs X1 > X0 and Y1 > Y0 (the ends are excluded)"
            )));
        }
        if self.x1 > width || self.y1 > height {
            return Err(Error::InvalidSettings(format!(
                "--region {self} reaches outside the {width}x{height} image (X1 at most \
                 {width}, Y1 at most {height})"
            )));
        }
        Ok(())
    }

    /// The tiles of at most `tile_width` x `tile_height` pixels that cover this region, row
    /// by row from the top-left; the last in a row or column may be smaller.
    pub fn tiles(&self, tile_width: u32, tile_height: u32) -> Vec<PixelRegion> {
        let (tile_width, tile_height) = (tile_width.max(1), tile_height.max(1));
        let mut tiles = Vec::new();
        let mut y0 = self.y0;
        while y0 < self.y1 {
            let y1 = self.y1.min(y0.saturating_add(tile_height));
            let mut x0 = self.x0;
            while x0 < self.x1 {
                let x1 = self.x1.min(x0.saturating_add(tile_width));
                tiles.push(PixelRegion { x0, y0, x1, y1 });
                x0 = x1;
            }
            y0 = y1;
        }
        tiles
    }
}

impl std::fmt::Display for PixelRegion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.y0, self.x1, self.y1)
    }
}

/// Bytes one pixel of the accumulation takes in one copy: its `ACCUMULATION_LAYER_COUNT`
/// RGBA32F texels.
pub const ACCUMULATION_BYTES_PER_PIXEL: u64 = 16 * contract::ACCUMULATION_LAYER_COUNT as u64;

/// Copies of the accumulation a renderer holds per pixel of the device's part: the storage
/// image, the buffer it is read back through and, when tiled, the one tiles are uploaded
/// from (counted always, to be safe).
pub const ACCUMULATION_COPIES: u64 = 3;

/// The side of the square tiles that an area of `width` x `height` pixels is rendered in, or
/// `None` when it fits in one piece: it is tiled when its accumulation
/// (`ACCUMULATION_COPIES * ACCUMULATION_BYTES_PER_PIXEL` per pixel) would take more than
/// `budget_bytes` (0: unknown, no limit), or a side exceeds `max_side` (the device's largest
/// image side). The tile is the largest power of two that fits both, at least 64 pixels a
/// side.
pub fn automatic_tile_side(
    width: u32,
    height: u32,
    budget_bytes: u64,
    max_side: u32,
) -> Option<u32> {
    let fits = |w: u32, h: u32| {
        let bytes =
            u64::from(w) * u64::from(h) * ACCUMULATION_COPIES * ACCUMULATION_BYTES_PER_PIXEL;
        (budget_bytes == 0 || bytes <= budget_bytes) && w <= max_side && h <= max_side
    };
    if fits(width, height) {
        return None;
    }
    let mut side = 1u32 << 14;
    while side > 64 && !fits(side.min(width), side.min(height)) {
        side /= 2;
    }
    Some(side)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_parse_and_validate_with_one_line_errors() {
        let region = PixelRegion::parse("2, 1,10,5").unwrap();
        let expected = PixelRegion {
            x0: 2,
            y0: 1,
            x1: 10,
            y1: 5,
        };
        assert_eq!(region, expected);
        assert_eq!((region.width(), region.height()), (8, 4));
        assert!(region.validate(10, 5).is_ok());
        assert!(!region.is_whole(10, 5) && PixelRegion::whole(10, 5).is_whole(10, 5));
        for bad in ["1,2,3", "a,b,c,d", "-1,0,4,4", "1,2,3,4,5", ""] {
            assert!(PixelRegion::parse(bad).is_err(), "{bad}");
        }
        let outside = region.validate(9, 5).unwrap_err().to_string();
        assert!(outside.contains("outside the 9x5 image"), "{outside}");
        let empty = PixelRegion::parse("3,1,3,5").unwrap().validate(10, 5);
        let empty = empty.unwrap_err().to_string();
        assert!(
            empty.contains("is empty") && !empty.contains('\n'),
            "{empty}"
        );
    }

    #[test]
    fn tiles_cover_the_region_once_in_row_order() {
        let region = PixelRegion::parse("3,2,20,9").unwrap();
        let tiles = region.tiles(8, 4);
        assert_eq!(tiles.len(), 3 * 2);
        assert_eq!(tiles[0], PixelRegion::parse("3,2,11,6").unwrap());
        assert_eq!(tiles[2], PixelRegion::parse("19,2,20,6").unwrap());
        assert_eq!(tiles[5], PixelRegion::parse("19,6,20,9").unwrap());
        let mut covered = vec![0u32; 20 * 9];
        for tile in &tiles {
            for y in tile.y0..tile.y1 {
                for x in tile.x0..tile.x1 {
                    covered[(y * 20 + x) as usize] += 1;
                }
            }
        }
        for y in 0..9 {
            for x in 0..20 {
                let inside = (3..20).contains(&x) && (2..9).contains(&y);
                assert_eq!(covered[(y * 20 + x) as usize], u32::from(inside), "{x},{y}");
            }
        }
    }

    #[test]
    fn automatic_tiles_only_when_the_area_does_not_fit() {
        let per_pixel = ACCUMULATION_COPIES * ACCUMULATION_BYTES_PER_PIXEL;
        assert_eq!(automatic_tile_side(512, 512, 0, 16384), None);
        assert_eq!(
            automatic_tile_side(512, 512, 512 * 512 * per_pixel, 16384),
            None
        );
        // A quarter of the memory: 256 x 256 tiles fit, 512 x 512 do not.
        assert_eq!(
            automatic_tile_side(512, 512, 256 * 256 * per_pixel, 16384),
            Some(256)
        );
        // Wider than the device's images: tiles of its largest power-of-two side.
        assert_eq!(automatic_tile_side(20000, 100, 0, 16384), Some(16384));
        assert_eq!(automatic_tile_side(20000, 100, 0, 10000), Some(8192));
    }
}
