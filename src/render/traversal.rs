//! How the path tracer finds the triangle a ray hits, for a loaded scene: the variant room
//! (`crate::kernels::variant`) decides from counts and flags; this file reads them off a
//! `Scene`.

pub use crate::kernels::variant::{constant_triangle_specialization, Traversal};
use crate::render::settings::Accel;
use crate::scene::Scene;

impl Traversal {
    /// `Traversal::choose` for `scene`, as on a device without ray queries (a render asks
    /// `crate::accel::choose_traversal`, which knows the device).
    pub fn for_scene(scene: &Scene, accel: Accel) -> Traversal {
        Traversal::choose(
            scene.triangles.len(),
            accel,
            scene.needs_material_kernels(),
            scene.uses_alpha(),
        )
    }
}
