//! Long paths on lavapipe: what llvmpipe's loop limit counts (measured here, since the
//! kernel's loop bound, `vkpath::kernels::loops`, relies on it), and a render with long
//! paths (mis, BVH) that is neither refused nor cut short.

use crate::common;

use ash::vk;
use gpu_allocator::MemoryLocation;
use vkpath::scene::cornell::workshop_cornell_box;
use vkpath::vk::{Buffer, CommandRunner, ComputePipeline, Context};
use vkpath::{Accel, Integrator, RenderSettings, RenderedImage, Renderer};

/// Iterations one loop statement of a SIMD program may run before llvmpipe ends it.
const LIMIT: u32 = vkpath::contract::LLVMPIPE_LOOP_LIMIT;

/// Two loops one after the other, and a loop nested in another, with iteration counts from
/// push constants (so that nothing is unrolled); each counts how often its body ran.
const LOOPS_SHADER: &str = r#"
#version 460
layout(local_size_x = 1) in;
layout(push_constant) uniform Counts { uint first; uint second; uint outer; uint inner; } counts;
layout(std430, binding = 0) buffer Ran { uint ran[4]; };
void main() {
    uint x = 1u;
    uint first = 0u;
    for (uint i = 0u; i < counts.first; ++i) { x = x * 1664525u + 1013904223u; ++first; }
    uint second = 0u;
    for (uint i = 0u; i < counts.second; ++i) { x = x * 22695477u + 1u; ++second; }
    uint inner = 0u;
    for (uint j = 0u; j < counts.outer; ++j)
        for (uint i = 0u; i < counts.inner; ++i) { x ^= x << 13u; ++inner; }
    ran[0] = first; ran[1] = second; ran[2] = inner; ran[3] = x;
}
"#;

/// How often the bodies of `LOOPS_SHADER` ran (first, second, nested inner) in one
/// invocation with these counts.
fn run_loops(context: &std::sync::Arc<Context>, counts: [u32; 4]) -> [u32; 3] {
    let spirv = vkpath::shader_compiler::compile_compute_shader(
        LOOPS_SHADER,
        "loops.comp",
        &|_| None,
        &[],
        true,
    )
    .expect("the loop shader compiles")
    .spirv;
    let pipeline = ComputePipeline::new(
        context,
        &spirv,
        &[(0, vk::DescriptorType::STORAGE_BUFFER)],
        16,
        &[],
    )
    .unwrap();
    let ran = Buffer::new(
        context,
        "ran",
        16,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )
    .unwrap();
    let set = pipeline.allocate_descriptor_set().unwrap();
    set.write_buffer(0, vk::DescriptorType::STORAGE_BUFFER, &ran);
    let commands = CommandRunner::new(context).unwrap();
    commands
        .run(|recorder| {
            recorder.bind(&pipeline, &set);
            recorder.push_constants(&pipeline, &counts);
            recorder.dispatch(&pipeline, [1, 1, 1]);
            recorder.host_read_barrier();
        })
        .unwrap();
    let ran: Vec<u32> = ran.read();
    [ran[0], ran[1], ran[2]]
}

/// The longest `--max-path-length` that mis with the BVH renders on the Cornell box on
/// lavapipe: the host's estimate (`LoopCoefficients::iterations_per_sample`) of
/// 1 + (48 closest-hit + 47 shadow rays) * (1 + 2 + the tree's bound) stays within 90% of
/// 65535 / 8.
const LONG_PATH: u32 = 48;

#[test]
fn llvmpipe_counts_all_loops_of_an_invocation_together() {
    let context = common::validated_context();
    assert!(
        !context.info.kind.is_gpu(),
        "this test measures lavapipe's loop limit; run it on lavapipe"
    );
    // One loop past the limit is cut at it, and a second loop after it runs once: the
    // limiter is shared, not per loop.
    assert_eq!(
        run_loops(&context, [LIMIT + 5000, 1000, 0, 0]),
        [LIMIT, 1, 0]
    );
    // Two loops each below the limit but above it together: the second stops where their
    // sum reaches it; the trip that leaves the first loop counts too (40 001).
    assert_eq!(
        run_loops(&context, [40000, 40000, 0, 0]),
        [40000, LIMIT - 40001, 0]
    );
    // A loop entered twice counts over both entries: 1 + 1 for the empty loops before it,
    // 40 000 + 1 in the first entry and 1 outer trip leave 25 531 for the second entry.
    assert_eq!(run_loops(&context, [0, 0, 2, 40000]), [0, 0, 40000 + 25531]);
    // Short inner loops: every entry costs its iterations, its leaving trip and the outer
    // trip (2 + 1 + 1); of the 65 533 trips the empty loops leave, 16 383 outer trips take
    // 65 532 and the last one leaves one inner iteration.
    assert_eq!(run_loops(&context, [0, 0, 40000, 2]), [0, 0, 2 * 16383 + 1]);
    common::assert_validation_silent(&context);
}

/// The Cornell box rendered with mis and the BVH at `LONG_PATH` vertices, Russian roulette
/// off (every path runs to its end unless it leaves the box), `samples_per_frame` per
/// frame.
fn render_long_paths(context: &std::sync::Arc<Context>, samples_per_frame: u32) -> RenderedImage {
    let scene = workshop_cornell_box().unwrap();
    let settings = RenderSettings {
        width: 16,
        height: 16,
        spp: 4,
        seed: 3,
        max_path_length: LONG_PATH,
        samples_per_frame,
        integrator: Integrator::Mis,
        accel: Accel::Bvh,
        russian_roulette_start: 0,
        ..Default::default()
    };
    let mut renderer = Renderer::new(context, &scene, &scene.camera.unwrap(), settings)
        .unwrap_or_else(|error| panic!("mis at {LONG_PATH} vertices is refused: {error}"));
    renderer
        .render_all()
        .unwrap_or_else(|error| panic!("mis at {LONG_PATH} vertices fails: {error}"))
}

#[test]
fn mis_with_the_bvh_renders_long_paths_in_full() {
    let context = common::validated_context();
    // Neither refused nor flagged (render_all fails on a flagged pixel) ...
    let batched = render_long_paths(&context, 4);
    let single = render_long_paths(&context, 1);
    // ... and no loop was cut: the kernel sums each pixel's samples in the same order
    // however many a dispatch takes (Kahan sums carried in the accumulation image), so a
    // cut path would show as a difference to the render of one sample per dispatch.
    assert!(batched.mean.iter().any(|m| m[0] > 0.0), "the image is lit");
    assert_eq!(batched.sample_count, single.sample_count);
    assert!(
        batched.mean == single.mean && batched.second_moment == single.second_moment,
        "the image depends on the samples per dispatch"
    );
    common::assert_validation_silent(&context);
}
