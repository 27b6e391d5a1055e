//! Rendering in tiles: which tiles an area is split into (`--tile-size`, or automatically
//! when it would not fit the device), the two orders a render takes their samples in
//! (`TileOrder`: every frame visits every tile, or each tile is finished before the next),
//! copying a tile's state between the host and the tile-sized accumulation image, and the
//! host memory each order needs. Every pixel takes the same samples in the same order
//! whatever the tiles and their order, so a tiled image is bit for bit the untiled one.

use crate::contract;
use crate::error::{Error, Result};
use crate::image_io::data::{resolve_pixel, RenderedImage};
use crate::render::region::{automatic_tile_side, PixelRegion, ACCUMULATION_BYTES_PER_PIXEL};
use crate::render::settings::RenderSettings;
use crate::scene::Scene;
use crate::vk::{Buffer, CommandRunner, Context, Recorder, StorageImage};

/// A render in tiles: the device's accumulation image holds one tile at a time.
pub(crate) struct Tiles {
    /// The tiles, row by row; the accumulation image is as large as the first.
    pub(crate) list: Vec<PixelRegion>,
    /// The order the tiles take their samples in, and what the host holds meanwhile.
    pub(crate) order: TileOrder,
}

/// The order in which the tiles of a render take their samples.
pub(crate) enum TileOrder {
    /// Every frame visits every tile (a render in tiles unless told otherwise): the host
    /// holds the whole area's state, so checkpoints, resuming, time limits and previews
    /// work as without tiles.
    EveryFrame(WholeState),
    /// Each tile takes all its samples before the next begins (`Renderer::tile_by_tile`):
    /// the host holds the finished image and one tile's read-back.
    OneAtATime(TileByTile),
}

/// The host's state of the whole area, for `TileOrder::EveryFrame`: each batch uploads
/// each tile's state, adds its samples and reads it back into `next`, which becomes the
/// state once every tile has its samples (the two are swapped, not copied), so that a
/// failure halfway leaves the state as the samples of whole batches say.
pub(crate) struct WholeState {
    /// The state of the whole area, as `Accumulation::texels` lays it out; empty until
    /// first used (`state`), so that a render that goes tile by tile never allocates it.
    state: Vec<[f32; 4]>,
    /// The batch's new state: allocated at the first batch, overwritten tile by tile.
    next: Vec<[f32; 4]>,
    /// A host-visible buffer of the accumulation image's size, to upload a tile's state.
    upload: Buffer,
}

/// A render finishing its tiles one at a time, for `TileOrder::OneAtATime`: the device's
/// image keeps the tile's state from batch to batch, and once the tile has every sample it
/// is read back, its pixels are resolved into `image` and the next tile starts from zero.
pub(crate) struct TileByTile {
    /// The tile taking samples (an index into the list; its length once all are done).
    index: usize,
    /// Samples each pixel of that tile has taken.
    pub(crate) samples: u32,
    /// The image, with the finished tiles' pixels (the others have none); `None` once
    /// handed out (`take_image`).
    image: Option<RenderedImage>,
    /// Rays traced by the finished tiles.
    pub(crate) rays: f64,
    /// Pixels of the finished tiles whose paths the loop limit may have cut short.
    pub(crate) flagged: usize,
}

/// What a batch over the tiles needs of the renderer.
pub(crate) struct TileDevice<'a> {
    /// Runs the batch's submissions.
    pub(crate) commands: &'a CommandRunner,
    /// The (tile-sized) accumulation image.
    pub(crate) image: &'a StorageImage,
    /// A host-visible buffer of the image's size, to read it back.
    pub(crate) readback: &'a Buffer,
    /// The part of the image rendered, which the tiles cover.
    pub(crate) area: PixelRegion,
    /// The render's settings (for the host memory check's message).
    pub(crate) settings: &'a RenderSettings,
}

impl Tiles {
    /// Tiles whose frames visit every tile (`TileOrder::EveryFrame`); `upload` is a
    /// host-visible buffer of the accumulation image's size.
    pub(crate) fn every_frame(list: Vec<PixelRegion>, upload: Buffer) -> Tiles {
        Tiles {
            list,
            order: TileOrder::EveryFrame(WholeState {
                state: Vec::new(),
                next: Vec::new(),
                upload,
            }),
        }
    }

    /// Switches to finishing the tiles one at a time (before any sample is taken), after
    /// checking that the finished image fits the host's memory.
    pub(crate) fn go_tile_by_tile(
        &mut self,
        settings: &RenderSettings,
        area: PixelRegion,
    ) -> Result<()> {
        validate_host_memory(
            settings,
            area,
            host_available_memory(),
            TILE_BY_TILE_HOST_BYTES_PER_PIXEL,
        )?;
        self.order = TileOrder::OneAtATime(TileByTile {
            index: 0,
            samples: 0,
            image: Some(RenderedImage::empty(area.width(), area.height())),
            rays: 0.0,
            flagged: 0,
        });
        Ok(())
    }

    /// Samples each pixel being rendered holds: every pixel's (`every_pixel`, what a render
    /// in tiles visited each frame holds), or the current tile's when finished one by one.
    pub(crate) fn samples_of_current_pixels(&self, every_pixel: u32) -> u32 {
        match &self.order {
            TileOrder::EveryFrame(_) => every_pixel,
            TileOrder::OneAtATime(order) => order.samples,
        }
    }

    /// Samples per pixel over the whole area so far, as a count of whole samples (rounded
    /// down): for a render finished tile by tile, the finished tiles' and the current
    /// one's samples spread over the area (for progress reports).
    pub(crate) fn progress(&self, every_pixel: u32, spp: u32) -> u32 {
        let TileOrder::OneAtATime(order) = &self.order else {
            return every_pixel;
        };
        let pixels = |tile: &PixelRegion| u64::from(tile.width()) * u64::from(tile.height());
        let finished: u64 = self.list[..order.index].iter().map(pixels).sum();
        let current = self.list.get(order.index).map_or(0, pixels);
        let total: u64 = self.list.iter().map(pixels).sum();
        let samples = finished * u64::from(spp) + current * u64::from(order.samples);
        (samples / total.max(1)) as u32
    }

    /// Runs one batch of frames (`record` records them over a tile, from the samples each
    /// of its pixels holds to `samples_after`) over every tile, or over the current tile
    /// when finishing them one at a time; returns the samples every pixel of the area
    /// then holds (with tiles finished one at a time: `spp` after the last tile, else 0).
    pub(crate) fn run_batch(
        &mut self,
        device: &TileDevice,
        record: &dyn Fn(&mut Recorder, PixelRegion),
        samples_after: u32,
        spp: u32,
    ) -> Result<u32> {
        match &mut self.order {
            TileOrder::EveryFrame(whole) => {
                whole.run_batch(device, &self.list, record)?;
                Ok(samples_after)
            }
            TileOrder::OneAtATime(order) => {
                order.run_batch(device, &self.list, record, samples_after, spp)?;
                Ok(if order.index == self.list.len() {
                    spp
                } else {
                    0
                })
            }
        }
    }
}

impl WholeState {
    /// The state of the whole area, allocated (zero) at first use after checking that it
    /// fits the host's memory.
    pub(crate) fn state(
        &mut self,
        settings: &RenderSettings,
        area: PixelRegion,
    ) -> Result<&mut Vec<[f32; 4]>> {
        if self.state.is_empty() {
            validate_host_memory(
                settings,
                area,
                host_available_memory(),
                TILED_HOST_BYTES_PER_PIXEL,
            )?;
            self.state = vec![[0.0; 4]; area_texel_count(area)];
        }
        Ok(&mut self.state)
    }

    /// One batch over every tile: the tile's state up, its frames, its new state back.
    fn run_batch(
        &mut self,
        device: &TileDevice,
        list: &[PixelRegion],
        record: &dyn Fn(&mut Recorder, PixelRegion),
    ) -> Result<()> {
        let area = device.area;
        self.state(device.settings, area)?;
        if self.next.len() != self.state.len() {
            self.next = vec![[0.0; 4]; self.state.len()];
        }
        let (image, readback) = (device.image, device.readback);
        let image_width = image.width as usize;
        let image_pixels = image_width * image.height as usize;
        // The tile's state, laid out as the image is (texels outside a smaller edge tile
        // are left from the tile before: no frame reads or writes them).
        let mut texels = vec![[0.0f32; 4]; image_pixels * layer_count()];
        for &tile in list {
            copy_tile(&self.state, area, &mut texels, image_width, tile, true);
            self.upload.write(bytemuck::cast_slice(&texels));
            let upload = &self.upload;
            device.commands.run(|recorder| {
                recorder.copy_buffer_to_image(upload, image);
                record(recorder, tile);
                recorder.copy_image_to_buffer(image, readback);
            })?;
            let back: Vec<[f32; 4]> = readback.read();
            copy_tile(&back, area, &mut self.next, image_width, tile, false);
        }
        // Every texel of `next` belongs to one tile, so all of it is new.
        std::mem::swap(&mut self.state, &mut self.next);
        Ok(())
    }

    /// Frees the batch's new state (after the last batch: it is allocated again if another
    /// comes).
    pub(crate) fn drop_next(&mut self) {
        self.next = Vec::new();
    }
}

impl TileByTile {
    /// One batch over the current tile: cleared first when it has no samples yet, read
    /// back and resolved into the image once it has all `spp`.
    fn run_batch(
        &mut self,
        device: &TileDevice,
        list: &[PixelRegion],
        record: &dyn Fn(&mut Recorder, PixelRegion),
        samples_after: u32,
        spp: u32,
    ) -> Result<()> {
        let Some(&tile) = list.get(self.index) else {
            return Ok(());
        };
        if self.image.is_none() {
            return Err(Error::InvalidSettings(
                "the render's image was already handed out".into(),
            ));
        }
        let (image, readback) = (device.image, device.readback);
        let (fresh, last) = (self.samples == 0, samples_after >= spp);
        device.commands.run(|recorder| {
            if fresh {
                recorder.clear_storage_image(image);
            }
            record(recorder, tile);
            if last {
                recorder.copy_image_to_buffer(image, readback);
            }
        })?;
        self.samples = samples_after;
        if last {
            let texels: Vec<[f32; 4]> = readback.read();
            self.resolve(&texels, image.width as usize, device.area, tile);
            self.index += 1;
            self.samples = 0;
        }
        Ok(())
    }

    /// Resolves a finished tile's texels (laid out as the image is, the tile in its top-left
    /// corner) into its pixels of the image, as `RenderedImage::from_accumulation` would.
    fn resolve(
        &mut self,
        texels: &[[f32; 4]],
        image_width: usize,
        area: PixelRegion,
        tile: PixelRegion,
    ) {
        let Some(image) = self.image.as_mut() else {
            return;
        };
        let layer = texels.len() / layer_count();
        let sums = contract::LAYER_SUM as usize * layer;
        let compensations = contract::LAYER_COMPENSATION as usize * layer;
        let squares = contract::LAYER_SUM_OF_SQUARES as usize * layer;
        let area_width = area.width() as usize;
        for row in 0..tile.height() as usize {
            let area_row = (tile.y0 - area.y0) as usize + row;
            let area_start = area_row * area_width + (tile.x0 - area.x0) as usize;
            for column in 0..tile.width() as usize {
                let texel = row * image_width + column;
                let (sum, compensation, square) = (
                    &texels[sums + texel],
                    &texels[compensations + texel],
                    &texels[squares + texel],
                );
                let (mean, second_moment, count) = resolve_pixel(sum, compensation, square);
                let pixel = area_start + column;
                image.mean[pixel] = mean;
                image.second_moment[pixel] = second_moment;
                image.sample_count[pixel] = count;
                self.rays += f64::from(compensation[3]);
                self.flagged += usize::from(square[3] != 0.0);
            }
        }
    }

    /// The image (once: the render holds none after it).
    pub(crate) fn take_image(&mut self) -> Result<RenderedImage> {
        self.image.take().ok_or_else(|| {
            Error::InvalidSettings("the render's image was already handed out".into())
        })
    }
}

/// Device bytes of the scene's buffers: the triangles (96 bytes each), with a BVH their
/// positions again for the traversal (48 bytes each) and at most 1 wide node per triangle
/// (112 bytes each; there are fewer nodes than the binary tree's interior nodes), the lights
/// (16 bytes each and a header).
pub(crate) fn scene_bytes(scene: &Scene) -> u64 {
    scene.triangles.len() as u64 * (96 + 48 + 112 + 16) + 16
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
    fn finished_tiles_resolve_as_the_whole_state_does() {
        // A 5x3 area at (10, 20) in a 3x3 tile and a 2x3 one, each read back from a 3x3
        // image (texels outside the tile -1): the image made tile by tile is the one
        // made of the whole state, the rays add up, and one flagged pixel is counted.
        let area = PixelRegion::parse("10,20,15,23").unwrap();
        let layers = layer_count();
        let squares = contract::LAYER_SUM_OF_SQUARES as usize * 15;
        let state: Vec<[f32; 4]> = (0..15 * layers)
            .map(|i| {
                let v = i as f32;
                let flag = if i == squares + 7 { 1.0 } else { 0.0 };
                let alpha = if i >= squares {
                    flag
                } else {
                    (i % 15) as f32 + 1.0
                };
                [v * 0.5, v + 1.0, v * 2.0, alpha]
            })
            .collect();
        let whole = RenderedImage::from_accumulation(5, 3, &state);
        let mut order = TileByTile {
            index: 0,
            samples: 0,
            image: Some(RenderedImage::empty(5, 3)),
            rays: 0.0,
            flagged: 0,
        };
        for tile in area.tiles(3, 3) {
            let mut texels = vec![[-1.0f32; 4]; 9 * layers];
            copy_tile(&state, area, &mut texels, 3, tile, true);
            order.resolve(&texels, 3, area, tile);
        }
        assert_eq!(order.rays, (1..=15).sum::<usize>() as f64);
        assert_eq!(order.flagged, 1);
        assert_eq!(order.take_image().unwrap(), whole);
        assert!(order.take_image().is_err(), "handed out once");
    }

    #[test]
    fn progress_spreads_the_finished_tiles_over_the_area() {
        // A 10x10 area in four 5x5 tiles: one finished, the second at 4 of 8 samples.
        let area = PixelRegion::parse("0,0,10,10").unwrap();
        let mut tiles = Tiles {
            list: area.tiles(5, 5),
            order: TileOrder::OneAtATime(TileByTile {
                index: 1,
                samples: 4,
                image: None,
                rays: 0.0,
                flagged: 0,
            }),
        };
        // (25 * 8 + 25 * 4) / 100 samples a pixel, rounded down.
        assert_eq!(tiles.progress(0, 8), 3);
        assert_eq!(tiles.samples_of_current_pixels(0), 4);
        if let TileOrder::OneAtATime(order) = &mut tiles.order {
            order.index = 4;
            order.samples = 0;
        }
        assert_eq!(tiles.progress(8, 8), 8);
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
