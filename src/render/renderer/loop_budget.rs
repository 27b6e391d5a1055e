//! The lavapipe loop budget: llvmpipe ends a shader invocation's loops silently after a fixed
//! number of iterations, so each dispatch takes only as many samples as stay well below it
//! (`LoopBudget`), and a render the limit may have cut short says what to change
//! (`loop_limit_advice`). On GPUs there is no such limit.

use crate::contract;
use crate::error::{Error, Result};
use crate::kernels::loops::{bvh_iterations_per_ray_at_most, LoopCoefficients, SampleWork};
use crate::kernels::variant::Traversal;
use crate::render::gpu_scene::GpuScene;
use crate::render::settings::{Integrator, RenderSettings};
use crate::scene::Scene;
use crate::vk::Context;

/// A render's loop budget: the device's limit, the coefficients of the kernel's loops, and
/// the samples each dispatch takes.
pub(super) struct LoopBudget {
    limit: LoopLimit,
    loops: LoopCoefficients,
    /// Samples each dispatch adds at most.
    pub(super) samples_per_dispatch: u32,
}

impl LoopBudget {
    /// The budget of rendering `scene` (uploaded as `gpu_scene`, traversed by `traversal`)
    /// with `settings` on `context`'s device; an error when not even one sample fits.
    pub(super) fn of(
        context: &Context,
        settings: &RenderSettings,
        scene: &Scene,
        gpu_scene: &GpuScene,
        traversal: Traversal,
    ) -> Result<LoopBudget> {
        let loops = LoopCoefficients::path_tracer(
            traversal,
            settings.guiding.is_some(),
            gpu_scene.summary.materials,
        );
        let limit = LoopLimit::of(context);
        let work = SampleWork {
            rays: rays_per_sample(settings, gpu_scene.light_samples_per_vertex),
            triangle_count: scene.triangles.len() as u64,
            light_search_iterations: gpu_scene.light_search_iterations,
            bvh_iterations_per_ray: gpu_scene
                .bvh_stats
                .as_ref()
                .map(bvh_iterations_per_ray_at_most),
        };
        let samples_per_dispatch =
            limit.samples_per_dispatch(settings, &loops, &work, traversal)?;
        Ok(LoopBudget {
            limit,
            loops,
            samples_per_dispatch,
        })
    }

    /// The device's loop limit (`SPEC_LOOP_LIMIT`; 0: none) and the kernel's loop
    /// coefficients, as the path tracer's specialization takes them
    /// (`crate::kernels::specialization::SpecializationParts`).
    pub(super) fn limit_and_loops(&self) -> (u32, LoopCoefficients) {
        (self.limit.0, self.loops)
    }
}

/// The loop iterations one invocation may run before the driver may end its loops
/// silently: on CPU devices (lavapipe) llvmpipe's limit per SIMD program divided by its
/// width (see `glsl/shared.h`), none (0) on GPUs.
struct LoopLimit(u32);

impl LoopLimit {
    /// The limit of `context`'s device.
    fn of(context: &Context) -> LoopLimit {
        LoopLimit(if context.info.kind.is_gpu() {
            0
        } else {
            contract::LLVMPIPE_LOOP_LIMIT / contract::LLVMPIPE_SIMD_WIDTH
        })
    }

    /// Samples per dispatch that keep an invocation's loop iterations below the limit by
    /// construction (the kernel still checks, and flags what reaches it): at most
    /// `samples_per_frame`, fewer where a sample loops a lot. A single sample that cannot
    /// fit (long paths, the loop over very many triangles) is refused.
    fn samples_per_dispatch(
        &self,
        settings: &RenderSettings,
        loops: &LoopCoefficients,
        work: &SampleWork,
        traversal: Traversal,
    ) -> Result<u32> {
        if self.0 == 0 {
            return Ok(settings.samples_per_frame);
        }
        let per_sample = loops.iterations_per_sample(work);
        // Keep a margin of 10% for the estimate.
        let budget = u64::from(self.0) * 9 / 10;
        if per_sample > budget {
            return Err(Error::InvalidSettings(format!(
                "one sample of {} path vertices over {} triangles loops about {per_sample} \
                 times, more than llvmpipe safely allows one shader invocation ({} of its {} \
                 per {} lanes): {}",
                settings.max_path_length,
                work.triangle_count,
                self.0,
                contract::LLVMPIPE_LOOP_LIMIT,
                contract::LLVMPIPE_SIMD_WIDTH,
                loop_limit_advice(traversal, false)
            )));
        }
        Ok(((budget / per_sample) as u32).clamp(1, settings.samples_per_frame))
    }
}

/// What to change when the loop limit stops a render: a shorter `--max-path-length`, and
/// `--accel bvh` only where the BVH is not in use already; fewer `--samples-per-frame` too
/// for an image that was rendered (one sample per dispatch can still be too many).
pub(super) fn loop_limit_advice(traversal: Traversal, rendered: bool) -> &'static str {
    let hierarchy = traversal.uses_bvh() || traversal == Traversal::RayQuery;
    match (hierarchy, rendered) {
        (true, false) => "use a shorter --max-path-length",
        (false, false) => "use --accel bvh (or auto) or a shorter --max-path-length",
        (true, true) => "use fewer --samples-per-frame or a shorter --max-path-length",
        (false, true) => {
            "use fewer --samples-per-frame, a shorter --max-path-length or --accel bvh"
        }
    }
}

/// Rays one sample traces at most, for the loop-limit estimate: one closest-hit ray per path
/// vertex (two for direct illumination: the camera ray and its one bounce), and for nee and
/// mis a shadow ray per vertex but the last (the path loop ends there before its light
/// samples) for each of the `light_samples` a vertex draws
/// (`crate::lights::SceneLights::light_samples_per_vertex`).
fn rays_per_sample(settings: &RenderSettings, light_samples: u64) -> u64 {
    let vertices = u64::from(settings.max_path_length);
    match settings.integrator {
        Integrator::DirectIllumination => vertices.max(2),
        Integrator::Nee | Integrator::Mis => vertices + vertices.saturating_sub(1) * light_samples,
        _ => vertices,
    }
}
