//! The validation layer stays silent during a render, and the counter that says so works.

use crate::common;

use ash::vk;
use vkpath::{RenderSettings, Renderer, Scene};

#[test]
fn a_render_produces_no_validation_messages() {
    // Creating a validated context asserts that the layer is present: it fails otherwise.
    let context = common::validated_context();
    let scene = Scene::builtin_cornell_box().unwrap();
    let settings = RenderSettings {
        width: 24,
        height: 16,
        spp: 3,
        samples_per_frame: 2,
        ..Default::default()
    };
    let camera = scene.camera.unwrap();
    let mut renderer = Renderer::new(&context, &scene, &camera, settings.clone()).unwrap();
    let image = renderer.render_all().unwrap();
    assert!(
        image.average()[0] > 0.0,
        "the Cornell box should not render black"
    );
    drop(renderer);
    // The warm-up dispatch over no pixels (render jobs compile the kernel with it during
    // set-up) is valid and leaves the image bit for bit as it was.
    let mut warmed = Renderer::new(&context, &scene, &camera, settings).unwrap();
    warmed.warm_up().unwrap();
    let warmed_image = warmed.render_all().unwrap();
    assert!(
        warmed_image.mean == image.mean,
        "the warm-up changed the image"
    );
    drop(warmed);
    common::assert_validation_silent(&context);
}

#[test]
fn the_message_counter_sees_a_deliberate_misuse() {
    let context = common::validated_context();
    let before = context.validation_messages().unwrap().errors();
    // A buffer of size 0 violates VUID-VkBufferCreateInfo-size-00912.
    let info = vk::BufferCreateInfo::default()
        .size(0)
        .usage(vk::BufferUsageFlags::STORAGE_BUFFER)
        .sharing_mode(vk::SharingMode::EXCLUSIVE);
    // SAFETY: deliberately invalid create info; the driver may still create a buffer, which
    // is destroyed right away.
    unsafe {
        if let Ok(buffer) = context.device.create_buffer(&info, None) {
            context.device.destroy_buffer(buffer, None);
        }
    }
    let after = context.validation_messages().unwrap().errors();
    assert!(
        after > before,
        "the deliberate misuse was not counted ({before} -> {after})"
    );
}
