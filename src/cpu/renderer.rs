//! The CPU reference renderer: `path_tracer.comp`'s `main()` on the CPU, with rayon over
//! pixel rows. Every pixel takes its samples one at a time in sample order with the same
//! seeds, integrator and Kahan update as the shader, so that its sums equal the GPU's
//! wherever every sample does.

use std::sync::atomic::{AtomicU32, Ordering};

use glam::{UVec2, Vec2, Vec3};
use rayon::prelude::*;

use crate::camera::ImagePlane;
use crate::contract::{LIGHT_SELECTION_TREE, PIXEL_FILTER_BOX};
use crate::cpu::camera::{get_sample_seed, get_sample_tex_coord};
use crate::cpu::guiding::GuideTexels;
use crate::cpu::image::{CpuImage, PixelAccumulator};
use crate::cpu::integrator::get_sample_radiance;
use crate::cpu::integrators::is_importance_sampled;
use crate::cpu::light_tree::LightTexels;
use crate::cpu::lights::LightScene;
use crate::cpu::path_loop::get_path_radiance;
use crate::cpu::sample_dimensions::CAMERA_PAIR_PIXEL;
use crate::cpu::sobol::{get_path_random_numbers, PathSample};
use crate::cpu::thin_lens::{apply_thin_lens, get_lens_random_numbers};
use crate::cpu::workshop::get_primary_ray_direction;
use crate::error::Result;
use crate::guiding::training::{GuideTrainer, GuideTraining, GUIDE_TRAINING_FIRST_SAMPLE};
use crate::guiding::{Guide, GuideGrid, GuideSplats};
use crate::lights::gpu_emissive::gpu_light_bytes_with_tree;
use crate::lights::light_tree::LightTree;
use crate::lights::EmissiveTriangles;
use crate::scene::Triangle;

/// What a CPU render does: the shader's specialization constants and uniforms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CpuRenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximal number of surface hits per path (`MAX_PATH_LENGTH`).
    pub max_path_length: u32,
    /// The user's seed (`get_sample_seed`).
    pub seed: u32,
    /// `PIXEL_FILTER_BOX` or `PIXEL_FILTER_CENTER` of `crate::contract`.
    pub pixel_filter: u32,
    /// `INTEGRATOR_*` of `crate::contract`.
    pub integrator: u32,
    /// `RUSSIAN_ROULETTE_START` (importance-sampled integrators only; 0: off).
    pub russian_roulette_start: u32,
    /// `SAMPLER_PCG` or `SAMPLER_SOBOL` of `crate::contract` (importance-sampled integrators
    /// only; the workshop's draw PCG2D whatever it is).
    pub sampler: u32,
    /// `LIGHT_SAMPLING_*` of `crate::contract` (nee and mis only).
    pub light_sampling: u32,
    /// `LIGHT_SELECTION_*` of `crate::contract` (nee and mis only): the power CDF, or the
    /// light tree the GPU renderer builds over the same lights.
    pub light_selection: u32,
}

/// Renders `settings.spp` samples per pixel into a new image.
/// \param scene_triangles All triangles of the scene
/// \param plane The camera for the image's aspect ratio
/// \param settings Size, samples, path length, seed, pixel filter and integrator
/// \return Sums, sums of squares and counts of every pixel, top-down rows
pub fn render_cpu(
    scene_triangles: &[Triangle],
    plane: &ImagePlane,
    settings: &CpuRenderSettings,
) -> CpuImage {
    let mut image = CpuImage::new(settings.width, settings.height);
    add_cpu_samples(
        scene_triangles,
        plane,
        settings,
        0,
        settings.spp,
        &mut image,
    );
    image
}

/// Adds the samples with index in `first_sample_index..sample_end` to every pixel, as one
/// frame of the shader does with its push constants `g_first_sample_index` and
/// `g_sample_end`; rendering in several such calls gives bit-identical results to one.
/// The image's own width and height are the resolution; `settings.width`,
/// `settings.height` and `settings.spp` are not read.
pub fn add_cpu_samples(
    scene_triangles: &[Triangle],
    plane: &ImagePlane,
    settings: &CpuRenderSettings,
    first_sample_index: u32,
    sample_end: u32,
    image: &mut CpuImage,
) {
    add_cpu_guided_samples(
        scene_triangles,
        plane,
        settings,
        CpuGuiding::default(),
        first_sample_index..sample_end,
        image,
    );
}

/// What a guided CPU render (`--guiding`, the shader's `GUIDING_ON`) reads and writes: the
/// guide it samples with and, in a training frame, the words its splats go to.
#[derive(Clone, Copy, Debug, Default)]
pub struct CpuGuiding<'a> {
    /// The guide's words (`None`: `GUIDING_OFF`).
    pub guide: Option<GuideTexels<'a>>,
    /// A training frame's splat words, `GuideGrid::splat_word_count` of them in the
    /// device's layout (`None`: not training).
    pub splats: Option<&'a [AtomicU32]>,
}

/// `add_cpu_samples` of a guided render: the importance-sampled integrators sample with
/// `guiding.guide` and, given `guiding.splats`, record and splat as a training frame does.
pub fn add_cpu_guided_samples(
    scene_triangles: &[Triangle],
    plane: &ImagePlane,
    settings: &CpuRenderSettings,
    guiding: CpuGuiding,
    samples: std::ops::Range<u32>,
    image: &mut CpuImage,
) {
    let width = image.width;
    let height = image.height;
    if width == 0 {
        return;
    }
    // The light table of the renderer's light_buffer, for the importance-sampled integrators,
    // and with LIGHT_SELECTION_TREE its words with the tree (crate::lights::SceneLights').
    let lights = EmissiveTriangles::new(scene_triangles);
    let light_tree_words: Option<Vec<u32>> = (settings.light_selection == LIGHT_SELECTION_TREE)
        .then(|| {
            let tree = LightTree::build(scene_triangles, &lights);
            bytemuck::pod_collect_to_vec(&gpu_light_bytes_with_tree(&lights, &tree))
        });
    let light_tree = light_tree_words
        .as_deref()
        .map(|words| LightTexels { words });
    image
        .pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .for_each(|(row, pixels)| {
            // Image rows run top-down; ShaderToy counts pixels from the bottom-left.
            let pixel_y = height - 1 - row as u32;
            for (x, accumulator) in pixels.iter_mut().enumerate() {
                let pixel = UVec2::new(x as u32, pixel_y);
                add_pixel_samples(
                    scene_triangles,
                    &lights,
                    plane,
                    settings,
                    pixel,
                    UVec2::new(width, height),
                    light_tree,
                    guiding,
                    samples.clone(),
                    accumulator,
                );
            }
        });
}

/// The camera ray of a sample through the image point `tex_coord`, as `main()` in
/// `path_tracer.comp` makes it: the pinhole's (`get_primary_ray_direction`), or with a lens
/// (`plane.lens`) the thin lens's, whose numbers are `get_lens_random_numbers`' (the fixed pair
/// `CAMERA_PAIR_LENS` of `sample` for the importance-sampled integrators, a PCG2D stream of
/// `sample_seed`, the sample's `get_sample_seed`, for the workshop's). Returns (origin,
/// direction).
pub fn get_camera_ray(
    plane: &ImagePlane,
    sample_seed: UVec2,
    sample: &PathSample,
    importance_sampled: bool,
    tex_coord: Vec2,
) -> (Vec3, Vec3) {
    let direction = get_primary_ray_direction(
        tex_coord.x,
        tex_coord.y,
        plane.camera_position,
        plane.left_bottom,
        plane.right,
        plane.up,
    );
    if plane.lens.is_pinhole() {
        return (plane.camera_position, direction);
    }
    let random_numbers = get_lens_random_numbers(sample_seed, sample, importance_sampled);
    apply_thin_lens(plane.camera_position, direction, plane, random_numbers)
}

/// The body of `main()` in `path_tracer.comp` for one pixel (counted from the bottom-left).
#[allow(clippy::too_many_arguments)]
fn add_pixel_samples(
    scene_triangles: &[Triangle],
    lights: &EmissiveTriangles,
    plane: &ImagePlane,
    settings: &CpuRenderSettings,
    pixel: UVec2,
    resolution: UVec2,
    light_tree: Option<LightTexels>,
    guiding: CpuGuiding,
    samples: std::ops::Range<u32>,
    accumulator: &mut PixelAccumulator,
) {
    for sample_index in samples {
        let mut seed = get_sample_seed(pixel, sample_index, settings.seed);
        let sample = PathSample::new(settings.sampler, pixel, sample_index, settings.seed);
        let importance_sampled = is_importance_sampled(settings.integrator);
        // The importance-sampled integrators' jitter at its dimension pair, the workshop's
        // from PCG2D.
        let tex_coord = if importance_sampled && settings.pixel_filter == PIXEL_FILTER_BOX {
            (pixel.as_vec2() + get_path_random_numbers(&sample, CAMERA_PAIR_PIXEL))
                / resolution.as_vec2()
        } else {
            get_sample_tex_coord(pixel, resolution, settings.pixel_filter, &mut seed)
        };
        let sample_seed = get_sample_seed(pixel, sample_index, settings.seed);
        let (camera_position, ray_direction) =
            get_camera_ray(plane, sample_seed, &sample, importance_sampled, tex_coord);
        let radiance = if is_importance_sampled(settings.integrator) {
            let scene = LightScene {
                scene_triangles,
                lights,
                integrator: settings.integrator,
                light_sampling: settings.light_sampling,
                guide: guiding.guide,
                light_tree,
            };
            get_path_radiance(
                &scene,
                camera_position,
                ray_direction,
                &sample,
                &mut seed,
                settings.max_path_length,
                settings.russian_roulette_start,
                guiding.splats,
            )
        } else {
            get_sample_radiance(
                scene_triangles,
                camera_position,
                ray_direction,
                &mut seed,
                settings.integrator,
                settings.max_path_length,
            )
        };
        accumulator.add_sample(radiance);
    }
}

/// Twin of `Renderer::train_guide` on the CPU: the iterations of `training` over the whole
/// image, each taking training samples from `GUIDE_TRAINING_FIRST_SAMPLE` on with the guide
/// built so far, their splats added up by the host's `GuideTrainer` as the GPU's are.
/// \param grid The guide's grid (the GPU render's: `GuideGrid::around_triangles` of the
///        scene's triangles)
/// \return The final guide
pub fn train_cpu_guide(
    scene_triangles: &[Triangle],
    plane: &ImagePlane,
    settings: &CpuRenderSettings,
    grid: GuideGrid,
    training: GuideTraining,
) -> Result<Guide> {
    let mut trainer = GuideTrainer::new(grid.clone());
    let mut taken = 0u32;
    for samples in training.iterations() {
        let words: Vec<AtomicU32> = (0..grid.splat_word_count())
            .map(|_| AtomicU32::new(0))
            .collect();
        let mut image = CpuImage::new(settings.width, settings.height);
        let first = GUIDE_TRAINING_FIRST_SAMPLE + taken;
        add_cpu_guided_samples(
            scene_triangles,
            plane,
            settings,
            CpuGuiding {
                guide: Some(trainer.guide().texels()),
                splats: Some(&words),
            },
            first..first + samples,
            &mut image,
        );
        let words: Vec<u32> = words.iter().map(|w| w.load(Ordering::Relaxed)).collect();
        trainer.add_iteration(&GuideSplats::from_device_words(&grid, &words)?);
        taken += samples;
    }
    Ok(trainer.into_guide())
}
