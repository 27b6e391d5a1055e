//! Keyframe animation of node transforms, as glTF 2.0 defines it (spec section 3.11 and
//! appendix C): samplers that map a time in seconds to a translation, rotation or scale by
//! `STEP`, `LINEAR` (spherical linear for rotations) or `CUBICSPLINE` (cubic Hermite with
//! in and out tangents) interpolation. Pure maths, no file format: `gltf_animation.rs` reads
//! the file's samplers into these types.

use glam::{Quat, Vec3, Vec4};

/// How a sampler interpolates between its keyframes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the last key at or before the time.
    Step,
    /// Linear between the two keys around the time; spherical linear for rotations.
    Linear,
    /// Cubic Hermite between the two keys, with an in tangent, value and out tangent stored
    /// per key (in that order); tangents are per second, scaled by the interval's length.
    CubicSpline,
}

impl Interpolation {
    /// How many output elements a sampler with `keys` input times must have.
    pub fn output_count(self, keys: usize) -> usize {
        match self {
            Interpolation::Step | Interpolation::Linear => keys,
            Interpolation::CubicSpline => 3 * keys,
        }
    }

    /// The glTF name (`STEP`, `LINEAR`, `CUBICSPLINE`).
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Step => "STEP",
            Interpolation::Linear => "LINEAR",
            Interpolation::CubicSpline => "CUBICSPLINE",
        }
    }
}

/// What an animation channel drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// The node's translation (x, y, z, in its parent's space).
    Translation,
    /// The node's rotation, a unit quaternion (x, y, z, w).
    Rotation,
    /// The node's scale (x, y, z).
    Scale,
}

/// Keyframes: strictly increasing times in seconds and their values, 4-wide (a quaternion's
/// x, y, z, w; a vector's x, y, z and 0), with tangents around each value for `CUBICSPLINE`.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    /// Key times in seconds, strictly increasing, at least one.
    pub times: Vec<f32>,
    /// `interpolation.output_count(times.len())` values.
    pub values: Vec<Vec4>,
    /// How values between keys are found.
    pub interpolation: Interpolation,
}

/// Why a sampler's data cannot be used.
#[derive(Clone, Debug, PartialEq)]
pub enum SamplerError {
    /// No key times.
    NoKeys,
    /// A key time that is not finite or not above the one before (its index).
    NotIncreasing(usize),
    /// The number of outputs does not fit the interpolation (found, expected).
    OutputCount(usize, usize),
}

impl std::fmt::Display for SamplerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SamplerError::NoKeys => write!(f, "has no key times"),
            SamplerError::NotIncreasing(i) => {
                write!(
                    f,
                    "key time {i} is not finite or not above the one before it"
                )
            }
            SamplerError::OutputCount(found, expected) => {
                write!(
                    f,
                    "has {found} output values, the interpolation needs {expected}"
                )
            }
        }
    }
}

impl Sampler {
    /// A sampler, checked: times finite and strictly increasing, outputs as many as the
    /// interpolation needs.
    pub fn new(
        times: Vec<f32>,
        values: Vec<Vec4>,
        interpolation: Interpolation,
    ) -> Result<Sampler, SamplerError> {
        check_keys(
            &times,
            values.len(),
            interpolation.output_count(times.len()),
        )?;
        Ok(Sampler {
            times,
            values,
            interpolation,
        })
    }

    /// The key times in seconds, strictly increasing.
    pub fn times(&self) -> &[f32] {
        &self.times
    }

    /// The time span of the keys, first to last, in seconds.
    pub fn span(&self) -> (f32, f32) {
        (self.times[0], self.times[self.times.len() - 1])
    }

    /// The key value `k` (the middle of a cubic spline's triple).
    fn value(&self, k: usize) -> Vec4 {
        match self.interpolation {
            Interpolation::CubicSpline => self.values[3 * k + 1],
            _ => self.values[k],
        }
    }

    /// The value at `time` of a vector channel (translation, scale): x, y, z.
    pub fn sample_vec3(&self, time: f32) -> Vec3 {
        self.sample(time, false).truncate()
    }

    /// The value at `time` of a rotation channel: a unit quaternion.
    pub fn sample_quat(&self, time: f32) -> Quat {
        let v = self.sample(time, true);
        let q = Quat::from_xyzw(v.x, v.y, v.z, v.w);
        // A zero quaternion in a broken file must not become NaN.
        if q.length_squared() > 0.0 {
            q.normalize()
        } else {
            Quat::IDENTITY
        }
    }

    /// The interpolated 4-wide value at `time`; `rotation` selects slerp for `LINEAR`.
    fn sample(&self, time: f32, rotation: bool) -> Vec4 {
        let (k, s) = match key_segment(&self.times, time) {
            Ok(segment) => segment,
            Err(key) => return self.value(key),
        };
        match self.interpolation {
            Interpolation::Step => self.value(k),
            Interpolation::Linear if rotation => {
                Vec4::from(slerp(self.value(k), self.value(k + 1), s))
            }
            Interpolation::Linear => self.value(k).lerp(self.value(k + 1), s),
            Interpolation::CubicSpline => {
                let delta = self.times[k + 1] - self.times[k];
                // glTF appendix C: the out tangent of key k and the in tangent of key k + 1,
                // each times the interval's length.
                let out_tangent = self.values[3 * k + 2] * delta;
                let in_tangent = self.values[3 * (k + 1)] * delta;
                hermite(self.value(k), out_tangent, self.value(k + 1), in_tangent, s)
            }
        }
    }
}

/// Checks keys: at least one time, times finite and strictly increasing, and `found`
/// output elements where the interpolation needs `expected`.
pub(crate) fn check_keys(times: &[f32], found: usize, expected: usize) -> Result<(), SamplerError> {
    if times.is_empty() {
        return Err(SamplerError::NoKeys);
    }
    if let Some(i) =
        (0..times.len()).find(|&i| !times[i].is_finite() || (i > 0 && times[i] <= times[i - 1]))
    {
        return Err(SamplerError::NotIncreasing(i));
    }
    if found != expected {
        return Err(SamplerError::OutputCount(found, expected));
    }
    Ok(())
}

/// The segment of the strictly increasing key `times` around `time`: the key `k` at or
/// before it and the fraction `s` in [0, 1] of the way to key `k + 1`; `Err(key)` when
/// `time` clamps to the first or last key (whose index it gives then).
pub(crate) fn key_segment(times: &[f32], time: f32) -> Result<(usize, f32), usize> {
    let last = times.len() - 1;
    if time.is_nan() || time <= times[0] {
        return Err(0);
    }
    if time >= times[last] {
        return Err(last);
    }
    // The first key after `time`: at least 1 and at most `last` by the checks above.
    let next = times.partition_point(|&t| t <= time);
    let k = next - 1;
    let s = (time - times[k]) / (times[next] - times[k]);
    Ok((k, s.clamp(0.0, 1.0)))
}

/// The cubic Hermite basis at `s` in [0, 1], the weights of p0, m0, p1, m1:
/// 2s³ − 3s² + 1, s³ − 2s² + s, −2s³ + 3s², s³ − s².
pub fn hermite_basis(s: f32) -> [f32; 4] {
    let (s2, s3) = (s * s, s * s * s);
    [
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    ]
}

/// Cubic Hermite spline between `p0` (tangent `m0`) and `p1` (tangent `m1`) at `s` in
/// [0, 1]: (2s³ − 3s² + 1)p0 + (s³ − 2s² + s)m0 + (−2s³ + 3s²)p1 + (s³ − s²)m1.
pub fn hermite(p0: Vec4, m0: Vec4, p1: Vec4, m1: Vec4, s: f32) -> Vec4 {
    let [h00, h10, h01, h11] = hermite_basis(s);
    p0 * h00 + m0 * h10 + p1 * h01 + m1 * h11
}

/// Spherical linear interpolation of two quaternions (x, y, z, w) by `s` in [0, 1], along the
/// shorter arc (glTF appendix C), normalised.
pub fn slerp(a: Vec4, b: Vec4, s: f32) -> Quat {
    let a = Quat::from_vec4(a).normalize();
    let b = Quat::from_vec4(b).normalize();
    // glam's slerp takes the shorter arc and falls back to lerp for nearly equal rotations.
    a.slerp(b, s).normalize()
}

/// One channel: a node's property driven by a sampler.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node's index in the file.
    pub node: usize,
    /// What it drives.
    pub property: Property,
    /// Its keyframes.
    pub sampler: Sampler,
}

/// One named animation: channels that play together.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// Its name in the file, or `#index`.
    pub name: String,
    /// Its channels on node transforms.
    pub channels: Vec<Channel>,
    /// Its channels on nodes' morph target weights.
    pub weights: Vec<super::morph_targets::WeightsChannel>,
}

/// A node's local transform as translation, rotation and scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodePose {
    /// Translation in the parent's space.
    pub translation: Vec3,
    /// Rotation, a unit quaternion.
    pub rotation: Quat,
    /// Scale along the node's axes.
    pub scale: Vec3,
}

impl NodePose {
    /// This pose with `channel` evaluated at `time` in place of its property.
    pub fn with_channel(mut self, channel: &Channel, time: f32) -> NodePose {
        match channel.property {
            Property::Translation => self.translation = channel.sampler.sample_vec3(time),
            Property::Rotation => self.rotation = channel.sampler.sample_quat(time),
            Property::Scale => self.scale = channel.sampler.sample_vec3(time),
        }
        self
    }

    /// The local-to-parent matrix: translation * rotation * scale.
    pub fn matrix(&self) -> glam::Mat4 {
        glam::Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// An `--animation` that names none of the file's animations: one line, naming what there is.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum AnimationPickError {
    /// The file has no animations at all.
    #[error("--animation {wanted}: the scene has no animations")]
    NoAnimations {
        /// The name or index asked for.
        wanted: String,
    },
    /// No animation has that name, and it is no index of one.
    #[error(
        "--animation {wanted}: no animation of that name or index; the scene has {} ({}), numbered from 0",
        names.len(),
        names.join(", ")
    )]
    NotFound {
        /// The name or index asked for.
        wanted: String,
        /// The file's animations' names, in order.
        names: Vec<String>,
    },
}

/// Which of a file's animations play.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum AnimationPick {
    /// All of them at once (the default).
    #[default]
    All,
    /// The one of this name, or if none has it and it is a number, the one at this index.
    One(String),
}

impl AnimationPick {
    /// The animations of `animations` this pick selects, or an error line naming what there is.
    pub fn select<'a>(
        &self,
        animations: &'a [Animation],
    ) -> Result<Vec<&'a Animation>, AnimationPickError> {
        let AnimationPick::One(wanted) = self else {
            return Ok(animations.iter().collect());
        };
        if let Some(found) = animations.iter().find(|a| &a.name == wanted) {
            return Ok(vec![found]);
        }
        if let Some(found) = wanted.parse::<usize>().ok().and_then(|i| animations.get(i)) {
            return Ok(vec![found]);
        }
        let wanted = wanted.clone();
        Err(if animations.is_empty() {
            AnimationPickError::NoAnimations { wanted }
        } else {
            AnimationPickError::NotFound {
                wanted,
                names: animations.iter().map(|a| a.name.clone()).collect(),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vec(x: f32) -> Vec4 {
        Vec4::new(x, 2.0 * x, -x, 0.0)
    }

    #[test]
    fn linear_matches_the_straight_line_and_clamps_outside_the_keys() {
        let sampler = Sampler::new(
            vec![1.0, 3.0],
            vec![vec(0.0), vec(4.0)],
            Interpolation::Linear,
        )
        .unwrap();
        assert_eq!(sampler.sample_vec3(2.0), vec(2.0).truncate());
        assert_eq!(sampler.sample_vec3(2.5), vec(3.0).truncate());
        assert_eq!(sampler.sample_vec3(-5.0), vec(0.0).truncate());
        assert_eq!(sampler.sample_vec3(0.0), vec(0.0).truncate());
        assert_eq!(sampler.sample_vec3(9.0), vec(4.0).truncate());
        assert_eq!(sampler.sample_vec3(f32::NAN), vec(0.0).truncate());
    }

    #[test]
    fn step_holds_the_key_at_or_before() {
        let sampler = Sampler::new(
            vec![0.0, 1.0, 2.0],
            vec![vec(0.0), vec(5.0), vec(7.0)],
            Interpolation::Step,
        )
        .unwrap();
        assert_eq!(sampler.sample_vec3(0.99), vec(0.0).truncate());
        assert_eq!(sampler.sample_vec3(1.0), vec(5.0).truncate());
        assert_eq!(sampler.sample_vec3(1.5), vec(5.0).truncate());
        assert_eq!(sampler.sample_vec3(2.5), vec(7.0).truncate());
    }

    #[test]
    fn cubic_spline_reproduces_a_cubic_polynomial() {
        // x(t) = t³ − t on keys 0, 1, 3: Hermite interpolation with exact derivatives
        // (3t² − 1) reproduces a cubic exactly.
        let f = |t: f32| t * t * t - t;
        let df = |t: f32| 3.0 * t * t - 1.0;
        let times = vec![0.0, 1.0, 3.0];
        let values = times
            .iter()
            .flat_map(|&t| [Vec4::splat(df(t)), Vec4::splat(f(t)), Vec4::splat(df(t))])
            .collect();
        let sampler = Sampler::new(times, values, Interpolation::CubicSpline).unwrap();
        for t in [0.0, 0.25, 0.5, 1.0, 1.7, 2.9, 3.0] {
            let got = sampler.sample_vec3(t).x;
            assert!((got - f(t)).abs() < 1e-4, "t {t}: {got} vs {}", f(t));
        }
        assert_eq!(sampler.sample_vec3(10.0).x, f(3.0));
    }

    #[test]
    fn rotations_slerp_at_constant_angular_speed() {
        // About +Y from 0 to 120 degrees: at s the angle is 120 s degrees.
        let a = Quat::IDENTITY;
        let b = Quat::from_rotation_y(120f32.to_radians());
        let sampler = Sampler::new(
            vec![0.0, 1.0],
            vec![Vec4::from(a), Vec4::from(b)],
            Interpolation::Linear,
        )
        .unwrap();
        for s in [0.0f32, 0.25, 0.5, 0.9] {
            let expected = Quat::from_rotation_y((120.0 * s).to_radians());
            let got = sampler.sample_quat(s);
            assert!(got.dot(expected).abs() > 1.0 - 1e-5, "s {s}: {got:?}");
        }
        // The shorter arc: from 0 to 350 degrees passes through 355, not 175.
        let c = Quat::from_rotation_y(350f32.to_radians());
        let half = slerp(Vec4::from(a), Vec4::from(c), 0.5);
        let expected = Quat::from_rotation_y((-5f32).to_radians());
        assert!(half.dot(expected).abs() > 1.0 - 1e-5);
    }

    #[test]
    fn cubic_spline_rotations_come_out_normalised() {
        let a = Vec4::from(Quat::IDENTITY);
        let b = Vec4::from(Quat::from_rotation_x(1.0));
        let tangent = Vec4::new(0.3, 0.1, 0.0, 0.2);
        let sampler = Sampler::new(
            vec![0.0, 2.0],
            vec![tangent, a, tangent, tangent, b, tangent],
            Interpolation::CubicSpline,
        )
        .unwrap();
        for t in [0.3, 1.0, 1.9] {
            assert!((sampler.sample_quat(t).length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn bad_samplers_are_refused() {
        let four = vec![Vec4::ZERO; 4];
        assert_eq!(
            Sampler::new(
                vec![0.0, 1.0, 1.0, 2.0],
                four.clone(),
                Interpolation::Linear
            ),
            Err(SamplerError::NotIncreasing(2))
        );
        assert_eq!(
            Sampler::new(vec![0.0, 1.0], four.clone(), Interpolation::Linear),
            Err(SamplerError::OutputCount(4, 2))
        );
        assert_eq!(
            Sampler::new(vec![0.0, 1.0], four, Interpolation::CubicSpline),
            Err(SamplerError::OutputCount(4, 6))
        );
        assert_eq!(
            Sampler::new(vec![], vec![], Interpolation::Step),
            Err(SamplerError::NoKeys)
        );
    }

    #[test]
    fn a_pick_by_name_or_index() {
        let animation = |name: &str| Animation {
            name: name.into(),
            channels: vec![],
            weights: vec![],
        };
        let all = [animation("walk"), animation("run")];
        assert_eq!(AnimationPick::All.select(&all).unwrap().len(), 2);
        let pick = |s: &str| AnimationPick::One(s.into()).select(&all);
        assert_eq!(pick("run").unwrap()[0].name, "run");
        assert_eq!(pick("0").unwrap()[0].name, "walk");
        let error = pick("jump").unwrap_err().to_string();
        assert!(error.contains("walk, run"), "{error}");
    }
}
