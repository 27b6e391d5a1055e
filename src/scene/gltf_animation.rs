//! A glTF file's `animations` read into [`Animation`]s, and the pose they give at a time:
//! node transforms (which move meshes, cameras, lights and skins' joints) and morph target
//! weights.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat4, Quat, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::util::ReadOutputs;
use gltf::Document;

use super::animation::{
    Animation, AnimationPick, Channel, Interpolation, NodePose, Property, Sampler,
};
use super::gltf_loader::{check_accessor, label, malformed};
use super::morph_targets::{WeightsChannel, WeightsSampler};
use super::SceneError;

/// Every animation of the file, checked: each sampler's input scalar floats, strictly
/// increasing, and as many outputs as its interpolation needs (for morph target weights,
/// times the number of targets of the node's mesh); with the warning about rotation keys
/// that are no rotations (`RotationKeys`), if any.
pub fn read_animations(
    path: &Path,
    document: &Document,
    buffers: &[gltf::buffer::Data],
) -> Result<(Vec<Animation>, Option<String>), SceneError> {
    check_channels(path, document)?;
    let mut animations = Vec::new();
    let mut rotation_keys = RotationKeys::default();
    for animation in document.animations() {
        let name = label(animation.name(), animation.index());
        let mut channels = Vec::new();
        let mut weights = Vec::new();
        for channel in animation.channels() {
            let property = match channel.target().property() {
                gltf::animation::Property::Translation => Property::Translation,
                gltf::animation::Property::Rotation => Property::Rotation,
                gltf::animation::Property::Scale => Property::Scale,
                gltf::animation::Property::MorphTargetWeights => {
                    weights.push(read_weights_channel(path, &name, &channel, buffers)?);
                    continue;
                }
            };
            let sampler = channel.sampler();
            let (input, output) = (sampler.input(), sampler.output());
            let bad = |reason: String| {
                malformed(
                    path,
                    format!("animation '{name}' channel {}: {reason}", channel.index()),
                )
            };
            check_accessor(&input, Dimensions::Scalar, &[DataType::F32])
                .map_err(|reason| bad(reason.to_string()))?;
            let (dimensions, types): (Dimensions, &[DataType]) = match property {
                Property::Rotation => (Dimensions::Vec4, &FLOAT_OR_NORMALISED),
                _ => (Dimensions::Vec3, &[DataType::F32]),
            };
            check_accessor(&output, dimensions, types).map_err(|reason| bad(reason.to_string()))?;
            let reader = channel.reader(|buffer| buffers.get(buffer.index()).map(|d| &d[..]));
            let cut_off = |accessor: &gltf::Accessor| bad(outside_its_buffer(accessor));
            let times: Vec<f32> = reader
                .read_inputs()
                .ok_or_else(|| cut_off(&input))?
                .collect();
            let mut values: Vec<Vec4> =
                match reader.read_outputs().ok_or_else(|| cut_off(&output))? {
                    ReadOutputs::Translations(t) | ReadOutputs::Scales(t) => {
                        t.map(|v| Vec3::from(v).extend(0.0)).collect()
                    }
                    ReadOutputs::Rotations(r) => r.into_f32().map(Vec4::from).collect(),
                    ReadOutputs::MorphTargetWeights(_) => continue,
                };
            if property == Property::Rotation {
                let keys = rotation_keys.mend(&mut values, interpolation_of(&sampler));
                if keys > 0 && rotation_keys.first.is_none() {
                    rotation_keys.first =
                        Some(format!("animation '{name}' channel {}", channel.index()));
                }
            }
            if times.len() != input.count() || values.len() != output.count() {
                return Err(cut_off(&output));
            }
            let interpolation = interpolation_of(&sampler);
            let sampler = Sampler::new(times, values, interpolation).map_err(|error| {
                let accessor = match error {
                    super::animation::SamplerError::OutputCount(..) => &output,
                    _ => &input,
                };
                bad(format!(
                    "{} sampler: accessor '{}' {error}",
                    interpolation.name(),
                    label(accessor.name(), accessor.index())
                ))
            })?;
            channels.push(Channel {
                node: channel.target().node().index(),
                property,
                sampler,
            });
        }
        animations.push(Animation {
            name,
            channels,
            weights,
        });
    }
    Ok((animations, rotation_keys.warning()))
}

/// Rotation keys that are no rotations: NaN or infinite components, or length zero (a
/// quaternion that cannot be normalised), which are taken as no rotation (the identity)
/// and said in one warning for the file; and keys whose squared length overflows (or
/// underflows) a float, which are scaled to a normalisable length first (they are
/// rotations). Before, all of these became the identity in silence (issue 58).
#[derive(Debug, Default)]
struct RotationKeys {
    /// Keys taken as no rotation.
    unusable: usize,
    /// Keys scaled to a normalisable length.
    rescaled: usize,
    /// The first channel with such a key ("animation 'walk' channel 3").
    first: Option<String>,
}

impl RotationKeys {
    /// Mends the keys of one rotation sampler's outputs in place (a cubic spline's middle
    /// values; its tangents are no rotations), counting them; returns how many it mended.
    fn mend(&mut self, values: &mut [Vec4], interpolation: Interpolation) -> usize {
        let (first, step) = match interpolation {
            Interpolation::CubicSpline => (1, 3),
            _ => (0, 1),
        };
        let mut mended = 0;
        for key in values.iter_mut().skip(first).step_by(step) {
            let largest = key.abs().max_element();
            if !key.is_finite() || largest == 0.0 {
                *key = Vec4::W;
                self.unusable += 1;
            } else if !(key.length_squared().is_normal()) {
                // Dividing by the largest component brings the length into [1, 2].
                *key /= largest;
                self.rescaled += 1;
            } else {
                continue;
            }
            mended += 1;
        }
        mended
    }

    /// The one warning for the file, if a key was mended.
    fn warning(&self) -> Option<String> {
        let first = self.first.as_ref()?;
        let mut parts = Vec::new();
        if self.unusable > 0 {
            parts.push(format!(
                "{} are NaN, infinite or of length 0 and are taken as no rotation",
                self.unusable
            ));
        }
        if self.rescaled > 0 {
            parts.push(format!(
                "{} are too long or too short to normalise in floats and were scaled first",
                self.rescaled
            ));
        }
        Some(format!(
            "rotation keys that are not unit quaternions (the first in {first}): {}",
            parts.join("; ")
        ))
    }
}

/// The component types an animation output may have: floats, or normalised integers
/// (rotations and morph weights, glTF 2.0 § 5.5.5).
const FLOAT_OR_NORMALISED: [DataType; 5] = [
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];

/// The reason given for an accessor whose data the buffers do not hold.
fn outside_its_buffer(accessor: &gltf::Accessor) -> String {
    format!(
        "accessor '{}' lies outside its buffer",
        label(accessor.name(), accessor.index())
    )
}

/// A sampler's interpolation, as the animation module names it.
fn interpolation_of(sampler: &gltf::animation::Sampler) -> Interpolation {
    match sampler.interpolation() {
        gltf::animation::Interpolation::Linear => Interpolation::Linear,
        gltf::animation::Interpolation::Step => Interpolation::Step,
        gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
    }
}

/// The local-to-parent matrix at `time` (seconds) of every node that the picked animations
/// drive; nodes not in the map keep their file transform.
pub fn animated_local_transforms(
    document: &Document,
    animations: &[&Animation],
    time: f32,
) -> HashMap<usize, Mat4> {
    let mut poses: HashMap<usize, NodePose> = HashMap::new();
    for animation in animations {
        for channel in &animation.channels {
            let Some(node) = document.nodes().nth(channel.node) else {
                continue;
            };
            let pose = poses.entry(channel.node).or_insert_with(|| {
                let (translation, rotation, scale) = node.transform().decomposed();
                NodePose {
                    translation: Vec3::from(translation),
                    rotation: Quat::from_array(rotation),
                    scale: Vec3::from(scale),
                }
            });
            *pose = pose.with_channel(channel, time);
        }
    }
    poses
        .into_iter()
        .map(|(node, pose)| (node, pose.matrix()))
        .collect()
}

/// A `weights` channel, checked: input as for node channels, output scalars (floats or
/// normalised integers), as many as the interpolation needs times the number of morph targets
/// of the node's mesh.
fn read_weights_channel(
    path: &Path,
    name: &str,
    channel: &gltf::animation::Channel,
    buffers: &[gltf::buffer::Data],
) -> Result<WeightsChannel, SceneError> {
    let sampler = channel.sampler();
    let (input, output) = (sampler.input(), sampler.output());
    let bad = |reason: String| {
        malformed(
            path,
            format!("animation '{name}' channel {}: {reason}", channel.index()),
        )
    };
    let node = channel.target().node();
    let target_count = node
        .mesh()
        .and_then(|mesh| mesh.primitives().map(|p| p.morph_targets().len()).max())
        .unwrap_or(0);
    if target_count == 0 {
        return Err(bad(format!(
            "animates the morph weights of node '{}', whose mesh has no morph targets",
            label(node.name(), node.index())
        )));
    }
    check_accessor(&input, Dimensions::Scalar, &[DataType::F32])
        .map_err(|reason| bad(reason.to_string()))?;
    check_accessor(&output, Dimensions::Scalar, &FLOAT_OR_NORMALISED)
        .map_err(|reason| bad(reason.to_string()))?;
    let reader = channel.reader(|buffer| buffers.get(buffer.index()).map(|d| &d[..]));
    let cut_off = |accessor: &gltf::Accessor| bad(outside_its_buffer(accessor));
    let times: Vec<f32> = reader
        .read_inputs()
        .ok_or_else(|| cut_off(&input))?
        .collect();
    let values: Vec<f32> = match reader.read_outputs().ok_or_else(|| cut_off(&output))? {
        ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
        _ => return Err(cut_off(&output)),
    };
    if times.len() != input.count() || values.len() != output.count() {
        return Err(cut_off(&output));
    }
    let interpolation = interpolation_of(&sampler);
    let sampler =
        WeightsSampler::new(times, values, target_count, interpolation).map_err(|error| {
            let (accessor, more) = match error {
                super::animation::SamplerError::OutputCount(..) => {
                    (&output, format!(" ({target_count} morph targets per key)"))
                }
                _ => (&input, String::new()),
            };
            bad(format!(
                "{} weights sampler: accessor '{}' {error}{more}",
                interpolation.name(),
                label(accessor.name(), accessor.index())
            ))
        })?;
    Ok(WeightsChannel {
        node: node.index(),
        sampler,
    })
}

/// Checks what the `gltf` crate's validation leaves out of animations and its accessors
/// unwrap: each channel's target node exists, its path is known, and each sampler's
/// interpolation is known.
fn check_channels(path: &Path, document: &Document) -> Result<(), SceneError> {
    use gltf::json::validation::Checked;
    let root = document.as_json();
    for (index, animation) in root.animations.iter().enumerate() {
        let name = label(animation.name.as_deref(), index);
        let bad = |reason: String| malformed(path, format!("animation '{name}' {reason}"));
        for (c, channel) in animation.channels.iter().enumerate() {
            if channel.target.node.value() >= root.nodes.len() {
                return Err(bad(format!(
                    "channel {c} targets node {}, which does not exist",
                    channel.target.node.value()
                )));
            }
            if !matches!(channel.target.path, Checked::Valid(_)) {
                return Err(bad(format!("channel {c} has an unknown target path")));
            }
        }
        for (s, sampler) in animation.samplers.iter().enumerate() {
            if !matches!(sampler.interpolation, Checked::Valid(_)) {
                return Err(bad(format!("sampler {s} has an unknown interpolation")));
            }
        }
    }
    Ok(())
}

/// What the picked animations make of the file at one time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pose {
    /// The local-to-parent matrix of every node they drive; other nodes keep the file's.
    pub local_transforms: HashMap<usize, Mat4>,
    /// The morph target weights of every node whose weights they drive.
    pub morph_weights: HashMap<usize, Vec<f32>>,
}

/// Picks some (`pick`) of the file's animations (`read_animations`): the pose they give at
/// `time`.
pub fn pose_at(
    path: &Path,
    document: &Document,
    animations: &[Animation],
    pick: &AnimationPick,
    time: f32,
) -> Result<Pose, SceneError> {
    let picked = pick
        .select(animations)
        .map_err(|reason| malformed_pick(path, reason.to_string()))?;
    let mut morph_weights = HashMap::new();
    for channel in picked.iter().flat_map(|a| &a.weights) {
        morph_weights.insert(channel.node, channel.sampler.sample(time));
    }
    Ok(Pose {
        local_transforms: animated_local_transforms(document, &picked, time),
        morph_weights,
    })
}

/// The error for an `--animation` that the file does not have.
fn malformed_pick(path: &Path, reason: String) -> SceneError {
    SceneError::Animation {
        path: path.to_owned(),
        reason,
    }
}
