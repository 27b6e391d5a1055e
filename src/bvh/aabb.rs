//! Axis-aligned bounding boxes for the BVH builder.

use glam::Vec3;

/// An axis-aligned box, world space. The empty box has `lower = +inf`, `upper = -inf`, so
/// that growing it by any point gives that point's box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub lower: Vec3,
    /// The corner with the largest coordinates.
    pub upper: Vec3,
}

impl Aabb {
    /// The box that contains nothing.
    pub const EMPTY: Aabb = Aabb {
        lower: Vec3::INFINITY,
        upper: Vec3::NEG_INFINITY,
    };

    /// The smallest box containing the three points.
    pub fn of_triangle(positions: &[Vec3; 3]) -> Aabb {
        Aabb {
            lower: positions[0].min(positions[1]).min(positions[2]),
            upper: positions[0].max(positions[1]).max(positions[2]),
        }
    }

    /// The smallest box containing both boxes.
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            lower: self.lower.min(other.lower),
            upper: self.upper.max(other.upper),
        }
    }

    /// The smallest box containing this box and `point`.
    pub fn grow(self, point: Vec3) -> Aabb {
        Aabb {
            lower: self.lower.min(point),
            upper: self.upper.max(point),
        }
    }

    /// The box's edge lengths (negative for the empty box).
    pub fn extent(&self) -> Vec3 {
        self.upper - self.lower
    }

    /// Surface area, 0 for the empty box (and for points, segments and NaN boxes), the
    /// measure of the surface area heuristic: a random ray that hits a convex parent hits a
    /// convex child inside it with probability area(child) / area(parent).
    pub fn surface_area(&self) -> f32 {
        let e = self.extent();
        let area = 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
        if e.min_element() >= 0.0 && area > 0.0 {
            area
        } else {
            0.0
        }
    }

    /// The box's centre.
    pub fn centre(&self) -> Vec3 {
        0.5 * (self.lower + self.upper)
    }

    /// Whether `other` lies inside this box (boundaries included).
    pub fn contains(&self, other: &Aabb) -> bool {
        self.lower.cmple(other.lower).all() && other.upper.cmple(self.upper).all()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_box_grows_to_the_point_and_has_no_area() {
        assert_eq!(Aabb::EMPTY.surface_area(), 0.0);
        let point = Aabb::EMPTY.grow(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(point.lower, point.upper);
        assert_eq!(point.surface_area(), 0.0);
        let unit = point.grow(Vec3::new(2.0, 3.0, 4.0));
        assert_eq!(unit.surface_area(), 6.0);
        assert!(unit.contains(&point));
        assert!(!point.contains(&unit));
        assert_eq!(Aabb::EMPTY.union(unit), unit);
    }
}
