//! What a sequence of frames of a glTF file (`render --frames`, Python's `render_frames`)
//! decides once for all its frames: the box a file without a camera is framed by (the union
//! of its posed bounds at the sequence's times, so that the view neither zooms nor jumps
//! from frame to frame), and whether its geometry moves (`--accel auto` then keeps one
//! traversal: `SequenceCache::moving_geometry`).

use glam::Vec3;

use super::GltfFile;
use crate::scene::animation::AnimationPick;
use crate::scene::SceneError;

/// How many evenly spread times `GltfFile::animation_bounds` poses, and at most how many of
/// the animations' key times beside them (each pose costs about what a frame's pose does,
/// without its render).
pub const MAX_FRAMING_POSES: usize = 64;

impl GltfFile {
    /// The last key time of the animations `pick` chooses (seconds; 0 without any): from
    /// then on every pose is the same.
    pub fn end_time(&self, pick: &AnimationPick) -> Result<f32, SceneError> {
        Ok(self
            .key_times(pick)?
            .last()
            .copied()
            .unwrap_or(0.0)
            .max(0.0))
    }

    /// Every key time of the animations `pick` chooses, sorted, each once.
    fn key_times(&self, pick: &AnimationPick) -> Result<Vec<f32>, SceneError> {
        let picked = pick
            .select(&self.animations)
            .map_err(|reason| SceneError::Animation {
                path: self.path.clone(),
                reason: reason.to_string(),
            })?;
        let mut times: Vec<f32> = picked
            .iter()
            .flat_map(|animation| {
                let nodes = animation.channels.iter().map(|c| c.sampler.times());
                let weights = animation.weights.iter().map(|c| c.sampler.times.as_slice());
                nodes.chain(weights).flatten().copied()
            })
            .collect();
        times.sort_by(f32::total_cmp);
        times.dedup();
        Ok(times)
    }

    /// The smallest box (lowest, highest corner) that holds the triangles of every pose of
    /// the animations `pick` chooses, from 0 to their end (`end_time`): the union of the
    /// posed bounds at `MAX_FRAMING_POSES` evenly spread times and at the key times (up to
    /// as many again, evenly picked), each posed once. It depends on neither the frames nor
    /// the frame rate, so that every part of a sequence split over a farm's tasks frames it
    /// alike. `None` where no pose has triangles.
    pub fn animation_bounds(
        &mut self,
        pick: &AnimationPick,
    ) -> Result<Option<(Vec3, Vec3)>, SceneError> {
        let end = self.end_time(pick)?;
        let keys = self.key_times(pick)?;
        let mut times: Vec<f32> = spread(keys.len(), MAX_FRAMING_POSES)
            .map(|i| keys[i].clamp(0.0, end))
            .chain(
                spread(MAX_FRAMING_POSES, MAX_FRAMING_POSES)
                    .map(|i| end * i as f32 / (MAX_FRAMING_POSES - 1) as f32),
            )
            .collect();
        times.sort_by(f32::total_cmp);
        times.dedup();
        let mut bounds: Option<(Vec3, Vec3)> = None;
        for time in times {
            let scene = self.pose(time, pick)?;
            if let Some((low, high)) = scene.bounds() {
                bounds = Some(match bounds {
                    Some((l, h)) => (l.min(low), h.max(high)),
                    None => (low, high),
                });
            }
        }
        Ok(bounds)
    }

    /// Whether the animations `pick` chooses may move triangles: they drive morph target
    /// weights, or a node that carries a mesh (or one of its ancestors), or a joint of a
    /// skin that a mesh node uses (or one of its ancestors). Cameras and lights alone do
    /// not move geometry.
    pub fn moves_geometry(&self, pick: &AnimationPick) -> Result<bool, SceneError> {
        let picked = pick
            .select(&self.animations)
            .map_err(|reason| SceneError::Animation {
                path: self.path.clone(),
                reason: reason.to_string(),
            })?;
        if picked.iter().any(|a| !a.weights.is_empty()) {
            return Ok(true);
        }
        let count = self.document.nodes().len();
        let mut animated = vec![false; count];
        for channel in picked.iter().flat_map(|a| &a.channels) {
            if let Some(flag) = animated.get_mut(channel.node) {
                *flag = true;
            }
        }
        if !animated.contains(&true) {
            return Ok(false);
        }
        let moved = moved_nodes(&self.document, &animated);
        let is_moved = |index: usize| moved.get(index).copied().unwrap_or(false);
        Ok(self.document.nodes().any(|node| {
            node.mesh().is_some()
                && match node.skin() {
                    Some(skin) => skin.joints().any(|joint| is_moved(joint.index())),
                    None => is_moved(node.index()),
                }
        }))
    }
}

/// Up to `most` indices into `0..count`, evenly spread, the first and the last among them.
fn spread(count: usize, most: usize) -> impl Iterator<Item = usize> {
    let picks = count.min(most);
    (0..picks).map(move |i| match picks {
        1 => 0,
        _ => i * (count - 1) / (picks - 1),
    })
}

/// For every node, whether it or one of its ancestors is `animated`: linear in the node
/// count (each node resolved once, however deep), and a cycle in a broken file ends the
/// walk up.
fn moved_nodes(document: &gltf::Document, animated: &[bool]) -> Vec<bool> {
    let count = animated.len();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            if let Some(slot) = parent.get_mut(child.index()) {
                *slot = Some(node.index());
            }
        }
    }
    // None: not resolved yet
    let mut moved: Vec<Option<bool>> = vec![None; count];
    let mut on_path = vec![false; count];
    let mut path = Vec::new();
    for start in 0..count {
        let mut at = Some(start);
        // Up to the first resolved node (or a root, or a cycle)
        let mut above = false;
        while let Some(index) = at {
            if let Some(known) = moved[index] {
                above = known;
                break;
            }
            if on_path[index] {
                break;
            }
            on_path[index] = true;
            path.push(index);
            at = parent[index];
        }
        // Back down, from the top of the path
        while let Some(index) = path.pop() {
            above = above || animated[index];
            moved[index] = Some(above);
            on_path[index] = false;
        }
    }
    moved.into_iter().map(|m| m.unwrap_or(false)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::files::LoadOptions;
    use std::path::Path;

    fn open(name: &str) -> GltfFile {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name);
        GltfFile::open(&path, &LoadOptions::default()).unwrap()
    }

    #[test]
    fn spread_takes_the_ends_and_at_most_its_count() {
        assert_eq!(spread(3, 64).collect::<Vec<_>>(), vec![0, 1, 2]);
        assert_eq!(spread(1, 64).collect::<Vec<_>>(), vec![0]);
        let long: Vec<usize> = spread(1_000_000, 64).collect();
        assert_eq!((long.len(), long[0], long[63]), (64, 0, 999_999));
    }

    #[test]
    fn an_animations_bounds_hold_every_poses_bounds() {
        let mut file = open("BoxAnimated.gltf");
        let pick = AnimationPick::All;
        let (low, high) = file.animation_bounds(&pick).unwrap().unwrap();
        let end = file.end_time(&pick).unwrap();
        assert!(end > 0.0);
        let mut grew = false;
        for time in [0.0, 0.3, 1.1, 2.0, 3.7, end, end + 5.0] {
            let (l, h) = file.pose(time, &pick).unwrap().bounds().unwrap();
            assert!(low.cmple(l).all() && high.cmpge(h).all(), "{time} s");
            grew |= l != low || h != high;
        }
        // The box moves: no single pose's bounds are the animation's
        assert!(grew);
    }

    #[test]
    fn skins_morphs_and_moving_meshes_move_geometry() {
        for name in ["BoxAnimated.gltf", "RiggedSimple.gltf", "SimpleMorph.gltf"] {
            assert!(
                open(name).moves_geometry(&AnimationPick::All).unwrap(),
                "{name}"
            );
        }
        // No animations: nothing moves
        assert!(!open("emissive_quad.gltf")
            .moves_geometry(&AnimationPick::All)
            .unwrap());
    }

    #[test]
    fn moved_nodes_inherit_from_their_ancestors_and_survive_cycles() {
        let json = r#"{"asset":{"version":"2.0"},"nodes":[
            {"children":[1]},{"children":[2]},{},{"children":[4]},{"children":[3]}]}"#;
        let gltf = gltf::Gltf::from_slice_without_validation(json.as_bytes()).unwrap();
        let moved = moved_nodes(&gltf.document, &[false, true, false, false, false]);
        assert_eq!(moved, vec![false, true, true, false, false]);
    }
}
