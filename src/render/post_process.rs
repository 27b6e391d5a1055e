//! What happens to a finished render before it is saved or returned: outputs beside the
//! colour (AOVs, as EXR layers or Python's `layers`) and denoising with Open Image Denoise,
//! which renders the albedo and normal it needs. `vkpath render` and Python's
//! `vkpath.render` both run it (`RenderSession::post_process`).

use std::sync::Arc;

use crate::camera::Camera;
use crate::error::Result;
use crate::image_io::output::ImageLayer;
use crate::render::aov::{ground_truth_pixels, render_aov, Aov};
use crate::render::cryptomatte::{
    check_levels, cryptomatte_layers, cryptomatte_samples, render_hit_samples, CryptomatteOptions,
};
use crate::render::ground_truth::render_first_hits;
use crate::render::metadata::{RenderMetadata, AOV_FIELD, DENOISER_NAME, DENOISE_FIELD};
use crate::render::motion_vectors::{
    motion_pixels, FrameNeighbours, BACKWARD_LAYER, FORWARD_LAYER,
};
use crate::render::settings::RenderSettings;
use crate::scene::Scene;
use crate::vk::Context;
use crate::RenderedImage;

/// What happens to a finished render before it is saved: outputs beside the colour
/// (`--aov`) and denoising (`--denoise`, which renders the albedo and normal it needs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PostProcess {
    /// The outputs to add as EXR layers.
    pub aovs: Vec<Aov>,
    /// Whether to denoise the colour with Open Image Denoise (the EXR keeps the original in a
    /// `noisy` layer).
    pub denoise: bool,
    /// For `Aov::Motion`: the frame's scene one frame before and after (`None`: a still
    /// render, whose motion vectors are 0). Set per frame.
    pub neighbours: Option<Arc<FrameNeighbours>>,
    /// For `Aov::Cryptomatte`: its ranks per pixel and samples.
    pub cryptomatte: CryptomatteOptions,
}

impl PostProcess {
    /// Whether there is anything to do.
    pub fn is_empty(&self) -> bool {
        self.aovs.is_empty() && !self.denoise
    }

    /// Records in `metadata` what this does to an image (`denoise`, `aov`), as the files
    /// it post-processed say.
    pub fn record(&self, metadata: &mut RenderMetadata) {
        if self.denoise {
            metadata.set_image_field(DENOISE_FIELD, DENOISER_NAME.to_string());
        }
        if !self.aovs.is_empty() {
            let names: Vec<&str> = self.aovs.iter().map(|aov| aov.name()).collect();
            metadata.set_image_field(AOV_FIELD, names.join(","));
        }
    }

    /// The image to save and its extra layers: `image`, denoised with `denoise` (the
    /// original then in a last `noisy` layer), and each AOV of `aovs` rendered with
    /// `settings` (whose `spp` should be the samples the image took), in their order.
    pub fn apply(
        &self,
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: &RenderSettings,
        image: &RenderedImage,
    ) -> Result<(RenderedImage, Vec<ImageLayer>)> {
        let mut wanted = self.aovs.clone();
        if self.denoise {
            for aov in [Aov::Albedo, Aov::Normal] {
                if !wanted.contains(&aov) {
                    wanted.push(aov);
                }
            }
        }
        let mut rendered: Vec<(Aov, Vec<ImageLayer>)> = Vec::new();
        let layer = |name: &str, pixels: Vec<[f32; 3]>, single_channel: bool| ImageLayer {
            name: name.to_owned(),
            pixels,
            single_channel,
            ..ImageLayer::default()
        };
        // One render of the pixel centres' first hits serves every ground-truth layer
        let mut first_hits = None;
        for aov in wanted {
            let layers = if aov == Aov::Cryptomatte {
                self.cryptomatte(context, scene, camera, settings)?
            } else if aov.is_ground_truth() {
                let hits = match first_hits.take() {
                    Some(hits) => hits,
                    None => render_first_hits(context, scene, camera, settings)?,
                };
                let layers = if aov == Aov::Motion {
                    let size = (settings.width, settings.height);
                    let neighbours = self.neighbours.as_deref();
                    let [forward, backward] = motion_pixels(scene, camera, &hits, neighbours, size);
                    vec![
                        layer(FORWARD_LAYER, forward, false),
                        layer(BACKWARD_LAYER, backward, false),
                    ]
                } else {
                    let pixels = ground_truth_pixels(scene, camera, &hits, aov)?;
                    vec![layer(aov.name(), pixels, aov.is_single_channel())]
                };
                first_hits = Some(hits);
                layers
            } else {
                let pixels = render_aov(context, scene, camera, settings, aov)?;
                vec![layer(aov.name(), pixels, aov.is_single_channel())]
            };
            rendered.push((aov, layers));
        }
        let layers_of = |aov: Aov| rendered.iter().find(|(a, _)| *a == aov).map(|(_, l)| l);
        let layer_of = |aov: Aov| layers_of(aov).and_then(|l| l.first()).map(|l| &l.pixels);
        let mut layers: Vec<ImageLayer> = self
            .aovs
            .iter()
            .filter_map(|&aov| layers_of(aov).cloned())
            .flatten()
            .collect();
        let mut result = image.clone();
        if self.denoise {
            let noisy: Vec<[f32; 3]> = image.mean.iter().map(|p| [p[0], p[1], p[2]]).collect();
            let denoised = crate::denoise::denoise(
                &noisy,
                layer_of(Aov::Albedo).map(Vec::as_slice),
                layer_of(Aov::Normal).map(Vec::as_slice),
                image.width,
                image.height,
            )?;
            for (pixel, value) in result.mean.iter_mut().zip(&denoised) {
                pixel[..3].copy_from_slice(value);
            }
            layers.push(ImageLayer {
                name: "noisy".to_owned(),
                pixels: noisy,
                ..ImageLayer::default()
            });
        }
        Ok((result, layers))
    }

    /// The Cryptomatte's layers: the first hits of `cryptomatte_samples(settings.spp)`
    /// jittered samples per pixel (or `CryptomatteOptions::samples`), ranked.
    fn cryptomatte(
        &self,
        context: &Arc<Context>,
        scene: &Scene,
        camera: &Camera,
        settings: &RenderSettings,
    ) -> Result<Vec<ImageLayer>> {
        let levels = self.cryptomatte.levels;
        check_levels(levels)?;
        let count = self
            .cryptomatte
            .samples
            .unwrap_or_else(|| cryptomatte_samples(settings.spp));
        let samples = render_hit_samples(context, scene, camera, settings, count)?;
        Ok(cryptomatte_layers(scene, &samples, levels))
    }
}
