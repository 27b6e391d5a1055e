//! Using vkpath as a library: render the built-in Cornell box and read back linear radiance.
//! Run with `cargo run --release --example library`.

use vkpath::vk::{Context, ContextOptions};
use vkpath::{RenderSettings, Renderer, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let context = Context::new(&ContextOptions::default())?;
    println!("device: {}", context.info);
    let scene = Scene::builtin_cornell_box()?; // or Scene::load(Path::new("scene.gltf"))?
    let camera = scene.camera.expect("the built-in scene has a camera");
    let settings = RenderSettings {
        width: 128,
        height: 128,
        spp: 16,
        ..Default::default()
    };
    let mut renderer = Renderer::new(&context, &scene, &camera, settings)?;
    // Batches of short frames until every sample is taken; the callback reports progress.
    let outcome = renderer.render_to_end(|done| println!("{done} spp"), None)?;
    let image = outcome.image; // linear RGBA f32, rows top-down
    println!("centre pixel: {:?}", image.pixel(64, 64));
    vkpath::image_io::output::save_image(
        std::path::Path::new("library.exr"),
        &image,
        &Default::default(),
    )?;
    Ok(())
}
