//! How nee and mis choose the emissive triangle they sample (`--light-selection`): in
//! proportion to power, or by the light tree (`super::light_tree`), and when `auto` takes the
//! tree.

use crate::scene::Triangle;

/// How nee and mis choose the emissive triangle they sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum LightSelection {
    /// The light tree for scenes of more than `LIGHT_TREE_THRESHOLD` emissive triangles,
    /// else power (`LightSelection::uses_tree`).
    #[default]
    #[cfg_attr(
        feature = "cli",
        value(help = "The light tree above 16 emissive triangles, else power")
    )]
    Auto,
    /// In proportion to power, from a CDF: the same choice at every shading point.
    #[cfg_attr(
        feature = "cli",
        value(help = "In proportion to power (a CDF over the emissive triangles)")
    )]
    Power,
    /// By a light tree's bound of each light's contribution to the shading point (distance,
    /// orientation, power; Conty Estevez and Kulla 2018, pbrt-v4's BVHLightSampler).
    #[cfg_attr(
        feature = "cli",
        value(help = "By a light tree's importance to the shading point: for many lights")
    )]
    Tree,
}

/// Scenes with more emissive triangles than this use the light tree under
/// `LightSelection::Auto`. With a few lights the tree cannot tell much apart that the power
/// CDF does not, and costs a walk of its depth at every light sample and every MIS weight;
/// the scenes of the images made before the tree (the Cornell box, `tests/data`, `scenes/`,
/// `scripts/same-images.sh`'s) have fewer, so their images stay bit for bit as they were.
pub const LIGHT_TREE_THRESHOLD: usize = 16;

impl LightSelection {
    /// Whether a scene of `light_count` emissive triangles is rendered with the light tree.
    pub fn uses_tree(self, light_count: usize) -> bool {
        match self {
            LightSelection::Auto => light_count > LIGHT_TREE_THRESHOLD,
            LightSelection::Power => false,
            LightSelection::Tree => light_count > 0,
        }
    }

    /// The name the CLI uses: "auto", "power" or "tree".
    pub fn name(self) -> &'static str {
        match self {
            LightSelection::Auto => "auto",
            LightSelection::Power => "power",
            LightSelection::Tree => "tree",
        }
    }
}

impl LightSelection {
    /// Whether a scene of `triangles` is rendered with the light tree (`uses_tree` of its
    /// emissive triangles' count).
    pub fn uses_tree_over(self, triangles: &[Triangle]) -> bool {
        self.uses_tree(super::emissive::emissive_triangle_count(triangles))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_selection_is_the_tree_only_above_the_threshold() {
        let auto = LightSelection::Auto;
        assert!(!auto.uses_tree(LIGHT_TREE_THRESHOLD) && auto.uses_tree(LIGHT_TREE_THRESHOLD + 1));
        assert!(!LightSelection::Power.uses_tree(1_000_000));
        assert!(LightSelection::Tree.uses_tree(1) && !LightSelection::Tree.uses_tree(0));
        // The built-in box keeps its power CDF (and so its images) by default.
        let scene = crate::scene::Scene::builtin_cornell_box().unwrap();
        assert!(!crate::RenderSettings::default()
            .light_selection
            .uses_tree_over(&scene.triangles));
    }
}
