//! What happens to a finished render before it is saved or returned: outputs beside the
//! colour (AOVs, as EXR layers or Python's `layers`) and denoising with Open Image Denoise,
//! which renders the albedo and normal it needs. `vkpath render` and Python's
//! `vkpath.render` both run it (`RenderSession::post_process`).

use std::sync::Arc;

use crate::camera::Camera;
use crate::error::Result;
use crate::image_io::output::ImageLayer;
use crate::render::aov::{ground_truth_pixels, render_aov, Aov};
use crate::render::ground_truth::render_first_hits;
use crate::render::metadata::{RenderMetadata, AOV_FIELD, DENOISER_NAME, DENOISE_FIELD};
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
        let mut rendered = Vec::new();
        // One render of the pixel centres' first hits serves every ground-truth layer
        let mut first_hits = None;
        for aov in wanted {
            let pixels = if aov.is_ground_truth() {
                let hits = match first_hits.take() {
                    Some(hits) => hits,
                    None => render_first_hits(context, scene, camera, settings)?,
                };
                let pixels = ground_truth_pixels(scene, camera, &hits, aov)?;
                first_hits = Some(hits);
                pixels
            } else {
                render_aov(context, scene, camera, settings, aov)?
            };
            rendered.push((aov, pixels));
        }
        let layer_of = |aov: Aov| rendered.iter().find(|(a, _)| *a == aov).map(|(_, p)| p);
        let mut layers: Vec<ImageLayer> = self
            .aovs
            .iter()
            .filter_map(|&aov| {
                layer_of(aov).map(|pixels| ImageLayer {
                    name: aov.name().to_owned(),
                    pixels: pixels.clone(),
                    single_channel: aov.is_single_channel(),
                })
            })
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
                single_channel: false,
            });
        }
        Ok((result, layers))
    }
}
