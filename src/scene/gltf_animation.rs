//! A glTF file's `animations` read into [`Animation`]s, and the node transforms they give at
//! a time. Skins and morph targets are not animated yet: a file that has them is rendered in
//! its rest pose, with one warning.

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
use super::SceneError;

/// The warning for files with skins or morph targets.
pub const SKIN_MORPH_WARNING: &str =
    "animation of skins/morph targets is not supported yet; rendering the rest pose";

/// Every animation of the file, checked: each sampler's input scalar floats, strictly
/// increasing, and as many outputs as its interpolation needs. Channels on morph target
/// weights are left out (see [`skin_or_morph_warning`]).
pub fn read_animations(
    path: &Path,
    document: &Document,
    buffers: &[gltf::buffer::Data],
) -> Result<Vec<Animation>, SceneError> {
    let mut animations = Vec::new();
    for animation in document.animations() {
        let name = label(animation.name(), animation.index());
        let mut channels = Vec::new();
        for channel in animation.channels() {
            let property = match channel.target().property() {
                gltf::animation::Property::Translation => Property::Translation,
                gltf::animation::Property::Rotation => Property::Rotation,
                gltf::animation::Property::Scale => Property::Scale,
                gltf::animation::Property::MorphTargetWeights => continue,
            };
            let sampler = channel.sampler();
            let (input, output) = (sampler.input(), sampler.output());
            let bad = |reason: String| {
                malformed(
                    path,
                    format!("animation '{name}' channel {}: {reason}", channel.index()),
                )
            };
            check_accessor(&input, Dimensions::Scalar, &[DataType::F32]).map_err(&bad)?;
            let (dimensions, types): (Dimensions, &[DataType]) = match property {
                Property::Rotation => (
                    Dimensions::Vec4,
                    &[
                        DataType::F32,
                        DataType::I8,
                        DataType::U8,
                        DataType::I16,
                        DataType::U16,
                    ],
                ),
                _ => (Dimensions::Vec3, &[DataType::F32]),
            };
            check_accessor(&output, dimensions, types).map_err(&bad)?;
            let reader = channel.reader(|buffer| buffers.get(buffer.index()).map(|d| &d[..]));
            let cut_off = |accessor: &gltf::Accessor| {
                bad(format!(
                    "accessor '{}' lies outside its buffer",
                    label(accessor.name(), accessor.index())
                ))
            };
            let times: Vec<f32> = reader
                .read_inputs()
                .ok_or_else(|| cut_off(&input))?
                .collect();
            let values: Vec<Vec4> = match reader.read_outputs().ok_or_else(|| cut_off(&output))? {
                ReadOutputs::Translations(t) | ReadOutputs::Scales(t) => {
                    t.map(|v| Vec3::from(v).extend(0.0)).collect()
                }
                ReadOutputs::Rotations(r) => r.into_f32().map(Vec4::from).collect(),
                ReadOutputs::MorphTargetWeights(_) => continue,
            };
            if times.len() != input.count() || values.len() != output.count() {
                return Err(cut_off(&output));
            }
            let interpolation = match sampler.interpolation() {
                gltf::animation::Interpolation::Linear => Interpolation::Linear,
                gltf::animation::Interpolation::Step => Interpolation::Step,
                gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
            };
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
        animations.push(Animation { name, channels });
    }
    Ok(animations)
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

/// The one warning for a file with skins, morph targets or animated morph weights, which
/// are drawn in their rest pose.
pub fn skin_or_morph_warning(document: &Document) -> Option<&'static str> {
    let morph = document.meshes().any(|mesh| {
        mesh.primitives()
            .any(|p| p.morph_targets().next().is_some())
    });
    (document.skins().next().is_some() || morph).then_some(SKIN_MORPH_WARNING)
}

/// Reads the file's animations and picks some (`pick`): the local transforms they give at
/// `time`, and warnings.
pub fn node_transforms_at(
    path: &Path,
    document: &Document,
    buffers: &[gltf::buffer::Data],
    pick: &AnimationPick,
    time: f32,
) -> Result<(HashMap<usize, Mat4>, Vec<String>), SceneError> {
    let animations = read_animations(path, document, buffers)?;
    let picked = pick
        .select(&animations)
        .map_err(|reason| malformed_pick(path, reason))?;
    let mut warnings = Vec::new();
    if let Some(warning) = skin_or_morph_warning(document) {
        warnings.push(warning.to_string());
    }
    Ok((animated_local_transforms(document, &picked, time), warnings))
}

/// The error for an `--animation` that the file does not have.
fn malformed_pick(path: &Path, reason: String) -> SceneError {
    SceneError::Animation {
        path: path.to_owned(),
        reason,
    }
}
