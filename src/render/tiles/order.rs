//! The two orders in which the tiles of a render take their samples (`TileOrder`), and
//! what the host holds meanwhile: the whole area's state when every frame visits every
//! tile, the finished image when each tile is finished before the next.

use super::{
    area_texel_count, copy_tile, host_available_memory, layer_count, validate_host_memory,
    TILED_HOST_BYTES_PER_PIXEL, TILE_BY_TILE_HOST_BYTES_PER_PIXEL,
};
use crate::contract;
use crate::error::{Error, Result};
use crate::image_io::data::{resolve_pixel, RenderedImage};
use crate::render::region::PixelRegion;
use crate::render::settings::RenderSettings;
use crate::vk::{Buffer, CommandRunner, Recorder, StorageImage};

/// A render in tiles: the device's accumulation image holds one tile at a time. The
/// renderer asks it, and names no order.
pub(crate) struct Tiles {
    /// The tiles, row by row; the accumulation image is as large as the first.
    list: Vec<PixelRegion>,
    /// The order the tiles take their samples in, and what the host holds meanwhile.
    order: TileOrder,
}

/// What a render in tiles holds at its end (`Tiles::end`).
pub(crate) enum TilesEnd {
    /// The tiles were finished one at a time: the image (handed out, the tiles hold none
    /// after) and the rays they traced.
    Image {
        /// The finished tiles' pixels.
        image: RenderedImage,
        /// Rays traced by the finished tiles.
        rays: f64,
    },
    /// The tiles were finished one at a time, but the loop limit may have cut paths short
    /// in this many pixels.
    CutPaths(usize),
    /// The frames visited every tile: the whole area's state (`Tiles::whole_state`) holds
    /// the samples.
    WholeState,
}

/// The order in which the tiles of a render take their samples.
enum TileOrder {
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
struct WholeState {
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
struct TileByTile {
    /// The tile taking samples (an index into the list; its length once all are done).
    index: usize,
    /// Samples each pixel of that tile has taken.
    samples: u32,
    /// The image, with the finished tiles' pixels (the others have none); `None` once
    /// handed out (`take_image`).
    image: Option<RenderedImage>,
    /// Rays traced by the finished tiles.
    rays: f64,
    /// Pixels of the finished tiles whose paths the loop limit may have cut short.
    flagged: usize,
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

    /// The upload buffer, for the next render of a sequence (`Renderer::keep_for_next`);
    /// `None` once the tiles went one at a time, which needs none.
    pub(crate) fn into_upload(self) -> Option<Buffer> {
        match self.order {
            TileOrder::EveryFrame(whole) => Some(whole.upload),
            TileOrder::OneAtATime(_) => None,
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

    /// The state of the whole area (allocated, zero, at first use after checking that it
    /// fits the host's memory); an error for tiles finished one at a time, which hold none
    /// (`doing`: what the caller would do with it, for the message).
    pub(crate) fn whole_state(
        &mut self,
        settings: &RenderSettings,
        area: PixelRegion,
        doing: &str,
    ) -> Result<&mut Vec<[f32; 4]>> {
        match &mut self.order {
            TileOrder::EveryFrame(whole) => whole.state(settings, area),
            TileOrder::OneAtATime(_) => Err(no_whole_state(doing)),
        }
    }

    /// Zeroes what the host holds of the samples: the whole area's state, or the finished
    /// image and the current tile when finished one at a time (which start again at the
    /// first tile).
    pub(crate) fn clear(&mut self, settings: &RenderSettings, area: PixelRegion) -> Result<()> {
        match &mut self.order {
            TileOrder::EveryFrame(whole) => {
                whole.state(settings, area)?.fill([0.0; 4]);
                Ok(())
            }
            TileOrder::OneAtATime(_) => self.go_tile_by_tile(settings, area),
        }
    }

    /// What the tiles hold at the render's end: tiles finished one at a time hand out
    /// their image; tiles whose frames visited every tile free the last batch's new state
    /// (the state is what a render hands out).
    pub(crate) fn end(&mut self) -> Result<TilesEnd> {
        match &mut self.order {
            TileOrder::OneAtATime(order) if order.flagged > 0 => {
                Ok(TilesEnd::CutPaths(order.flagged))
            }
            TileOrder::OneAtATime(order) => {
                let rays = order.rays;
                let image = order.take_image()?;
                Ok(TilesEnd::Image { image, rays })
            }
            TileOrder::EveryFrame(whole) => {
                whole.drop_next();
                Ok(TilesEnd::WholeState)
            }
        }
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
    fn state(
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
    fn drop_next(&mut self) {
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
    fn take_image(&mut self) -> Result<RenderedImage> {
        self.image.take().ok_or_else(|| {
            Error::InvalidSettings("the render's image was already handed out".into())
        })
    }
}

/// The error of a render finished tile by tile asked for the whole image's state, to do
/// `what` with it.
fn no_whole_state(what: &str) -> Error {
    Error::InvalidSettings(format!(
        "a render finished tile by tile holds no state of the whole image to {what}: render \
         without Renderer::tile_by_tile"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
