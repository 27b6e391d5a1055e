//! KHR_lights_punctual's lights, placed by their nodes. Units (README): a point or spot
//! light's `intensity` is its radiant intensity in the units in which emissive surfaces give
//! radiance, so a surface facing it at distance d receives intensity / d^2; a directional
//! light's `intensity` is the irradiance it gives a surface facing it; `range` is ignored.

use glam::{Mat4, Vec3};

/// What kind of punctual light, with a spot's cone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PunctualKind {
    /// Shines equally in all directions from its position.
    Point,
    /// A point light limited to a cone around its direction, with the extension's smooth
    /// falloff between the inner and outer cone angles (radians).
    Spot {
        /// Full intensity inside this angle from the direction.
        inner_cone_angle: f32,
        /// No light beyond this angle.
        outer_cone_angle: f32,
    },
    /// Parallel light from infinitely far away, along its direction.
    Directional,
}

/// A punctual light in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PunctualLight {
    /// Point, spot or directional.
    pub kind: PunctualKind,
    /// Position (point and spot), world space.
    pub position: Vec3,
    /// Unit direction the light shines along (spot and directional): its node's -Z.
    pub direction: Vec3,
    /// `color` times `intensity`: radiant intensity (point, spot) or irradiance
    /// (directional), linear RGB.
    pub intensity: Vec3,
}

impl PunctualLight {
    /// The light of a glTF node with `local_to_world`; `None` (to be reported) when the
    /// transform or the values are unusable.
    pub fn new(
        kind: PunctualKind,
        color: Vec3,
        intensity: f32,
        local_to_world: Mat4,
    ) -> Option<PunctualLight> {
        let position = local_to_world.transform_point3(Vec3::ZERO);
        let direction = local_to_world
            .transform_vector3(Vec3::NEG_Z)
            .try_normalize()?;
        let intensity = color.max(Vec3::ZERO) * intensity.max(0.0);
        (position.is_finite() && intensity.is_finite()).then_some(PunctualLight {
            kind,
            position,
            direction,
            intensity,
        })
    }

    /// The spot cone's (scale, offset): attenuation = clamp(cos * scale + offset, 0, 1)^2
    /// with cos the angle's cosine from the direction (the extension's formula, the
    /// difference of cosines kept at least 0.001); (0, 1) for other lights.
    pub fn cone_scale_offset(&self) -> (f32, f32) {
        match self.kind {
            PunctualKind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let scale = 1.0 / (inner_cone_angle.cos() - outer_cone_angle.cos()).max(0.001);
                (scale, -outer_cone_angle.cos() * scale)
            }
            _ => (0.0, 1.0),
        }
    }

    /// Whether it gives any light.
    pub fn emits_light(&self) -> bool {
        self.intensity.max_element() > 0.0
    }
}
