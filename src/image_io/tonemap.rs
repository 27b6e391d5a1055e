//! Tone mapping and exposure: how linear scene radiance (linear Rec. 709 / sRGB primaries)
//! becomes display-linear values in [0, 1], before the sRGB transfer function encodes them
//! for a PNG. EXR files never pass through here: they keep the linear radiance.
//!
//! Three curves: `Clamp` (the workshop's display: exposure, then clip), Stephen Hill's fit of
//! the ACES RRT + sRGB ODT, and Troy Sobotka's AgX base transform as Blender 4 ships it (the
//! polynomial fit of its sigmoid that three.js r160+, Filament and Godot use). Exposure is a
//! number of stops, or chosen from the image by `auto_exposure`.

use crate::image_io::data::RenderedImage;

/// How radiance is mapped to the display's [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum ToneMap {
    /// Exposure, then clip each channel to [0, 1]: the workshop's ShaderToy display. Keeps
    /// values below 1 exactly (and images that are not radiance, such as heat maps, as
    /// they are); everything above 1 clips to white.
    #[default]
    #[cfg_attr(
        feature = "cli",
        value(help = "Clip to [0, 1] after exposure (the workshop's display)")
    )]
    Clamp,
    /// Stephen Hill's fit of ACES's reference rendering and sRGB output transforms: a filmic
    /// S-curve that reaches white at about 25.7 (mid grey 0.18 -> 0.106) and shifts hues
    /// of saturated highlights.
    #[cfg_attr(
        feature = "cli",
        value(help = "ACES filmic curve (Stephen Hill's RRT+ODT fit)")
    )]
    Aces,
    /// Troy Sobotka's AgX base transform: a log encoding of 16.5 stops around mid grey
    /// (−10 to +6.5) through a sigmoid, in an inset gamut so that bright saturated colours
    /// roll off towards white instead of clipping or skewing. White at about 16.3.
    #[cfg_attr(
        feature = "cli",
        value(help = "AgX: highlights roll off and desaturate to white (Blender 4's default)")
    )]
    Agx,
    /// AgX with the "Punchy" look (Blender 4 ships it as `AgX - Punchy`): after the sigmoid,
    /// each display-encoded channel to the power 1.35 (deeper shadows and mid-tones, the
    /// highlights' roll-off kept) and saturation 1.4 about the luminance, clipped to [0, 1].
    #[cfg_attr(
        feature = "cli",
        value(
            name = "agx-punchy",
            help = "AgX with Blender's Punchy look: more contrast and colour (render's default)"
        )
    )]
    AgxPunchy,
}

/// The tone map `vkpath render` and `vkpath merge` write PNG files with: AgX, whose highlights
/// roll off and desaturate gracefully where `Clamp` clips (31% of the Cornell box's pixels
/// at 0 EV: its ceiling and upper walls) and ACES skews hues, with the Punchy look: AgX's
/// base transform alone looks hazy and grey next to what people expect of a first picture
/// (the look's power curve restores contrast, its saturation the walls' colours; README,
/// "Output", has the measurements). `exercise` keeps `Clamp`, the workshop's display.
pub const RENDER_PNG_TONE_MAP: ToneMap = ToneMap::AgxPunchy;

impl ToneMap {
    /// How the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Clamp => "clamp",
            ToneMap::Aces => "aces",
            ToneMap::Agx => "agx",
            ToneMap::AgxPunchy => "agx-punchy",
        }
    }
}

/// How bright the image is made before tone mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Exposure {
    /// Radiance is multiplied by 2^stops.
    Stops(f32),
    /// Stops chosen from the image's luminance (`auto_exposure`).
    Auto,
}

impl Default for Exposure {
    fn default() -> Self {
        Exposure::Stops(0.0)
    }
}

impl Exposure {
    /// The linear factor radiance is multiplied by for `image`: 2^stops.
    pub fn scale_for(self, image: &RenderedImage) -> f32 {
        match self {
            Exposure::Stops(stops) => stops.exp2(),
            Exposure::Auto => auto_exposure(image).exp2(),
        }
    }
}

/// Rec. 709 / sRGB relative luminance of linear RGB (ITU-R BT.709 weights).
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// The middle grey that `auto_exposure` maps the image's log-average luminance to: the
/// photographic "key" of an average scene (Reinhard et al. 2002), and AgX's pivot.
pub const MIDDLE_GREY: f32 = 0.18;

/// The exposure in stops that maps the log-average (geometric mean) luminance of `image`
/// to `MIDDLE_GREY`, as Reinhard et al.'s photographic tone reproduction (SIGGRAPH 2002)
/// does: log2(0.18 / exp(mean(ln L))). The geometric mean follows what the eye adapts to
/// and is not dragged up by a small, very bright light as the arithmetic mean is. Pixels
/// whose luminance is zero, negative, NaN or infinite are left out (a black background or
/// a firefly of inf does not move it); an image with none left gives 0 stops.
pub fn auto_exposure(image: &RenderedImage) -> f32 {
    let (sum, count) = image
        .mean
        .iter()
        .map(|p| luminance([p[0], p[1], p[2]]))
        .filter(|l| l.is_finite() && *l > 0.0)
        .fold((0.0f64, 0usize), |(sum, count), l| {
            (sum + f64::from(l).ln(), count + 1)
        });
    if count == 0 {
        return 0.0;
    }
    let log_average = (sum / count as f64).exp();
    let stops = (f64::from(MIDDLE_GREY) / log_average).log2() as f32;
    // A log-average of 1e-38 would ask for +120 stops; no radiance needs more than this.
    stops.clamp(-64.0, 64.0)
}

/// Display-linear RGB in [0, 1] (before the sRGB OETF) of linear radiance `rgb_linear`
/// multiplied by `exposure_scale` (= 2^EV), through `map`. NaN becomes 0; +inf becomes
/// white under every curve.
pub fn tone_map(rgb_linear: [f32; 3], exposure_scale: f32, map: ToneMap) -> [f32; 3] {
    // Negative radiance is noise below black; NaN is nothing (f32::max drops NaN).
    let exposed = rgb_linear.map(|c| (c * exposure_scale).max(0.0));
    match map {
        ToneMap::Clamp => exposed.map(|c| c.min(1.0)),
        ToneMap::Aces => aces_hill(exposed),
        ToneMap::Agx => agx(exposed, AgxLook::Base),
        ToneMap::AgxPunchy => agx(exposed, AgxLook::Punchy),
    }
}

/// `m · v` for a row-major 3×3 matrix.
fn multiply(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

/// Linear sRGB -> ACES AP1 rendering space, with the RRT's saturation adjustment folded in
/// (Hill's `ACESInputMat`; rows sum to 1, so greys stay grey).
const ACES_INPUT: [[f32; 3]; 3] = [
    [0.59719, 0.35458, 0.04823],
    [0.07600, 0.90834, 0.01566],
    [0.02840, 0.13383, 0.83777],
];
/// The ODT's way back to linear sRGB (Hill's `ACESOutputMat`; rows sum to 1).
const ACES_OUTPUT: [[f32; 3]; 3] = [
    [1.60475, -0.53108, -0.07367],
    [-0.10208, 1.10813, -0.00605],
    [-0.00327, -0.07276, 1.07602],
];

/// Stephen Hill's fit of ACES 1.0's RRT + sRGB ODT (BakingLab, 2016): a rational curve per
/// channel between two matrices. Finer than Narkowicz's 2015 single-curve fit, which also
/// skips the matrices and so desaturates nothing. Clipped to [0, 1]: the fit's asymptote is
/// 1/0.983729, reached at about 25.7.
fn aces_hill(rgb: [f32; 3]) -> [f32; 3] {
    let rrt_and_odt = |v: f32| {
        if v.is_infinite() {
            return 1.0;
        }
        let a = v * (v + 0.024_578_6) - 0.000_090_537;
        let b = v * (0.983_729 * v + 0.432_951) + 0.238_081;
        a / b
    };
    let fitted = multiply(&ACES_INPUT, rgb).map(rrt_and_odt);
    multiply(&ACES_OUTPUT, fitted).map(|c| c.clamp(0.0, 1.0))
}

/// Linear sRGB -> linear Rec. 2020 (ITU-R BT.2087), the space Blender's AgX works in.
const SRGB_TO_REC2020: [[f32; 3]; 3] = [
    [0.627_403_9, 0.329_283_04, 0.043_313_07],
    [0.069_097_29, 0.919_540_4, 0.011_362_32],
    [0.016_391_44, 0.088_013_31, 0.895_595_25],
];
/// Linear Rec. 2020 -> linear sRGB, the inverse of `SRGB_TO_REC2020`.
const REC2020_TO_SRGB: [[f32; 3]; 3] = [
    [1.660_491, -0.587_641_1, -0.072_849_86],
    [-0.124_550_5, 1.132_899_9, -0.008_349_42],
    [-0.018_150_76, -0.100_578_9, 1.118_729_6],
];
/// AgX's inset: pulls the primaries towards the achromatic axis so that bright saturated
/// colours reach white through the sigmoid ("path to white"). Rows sum to 1.
const AGX_INSET: [[f32; 3]; 3] = [
    [0.856_627_15, 0.095_121_24, 0.048_251_61],
    [0.137_318_97, 0.761_242, 0.101_439_04],
    [0.111_898_21, 0.076_799_42, 0.811_302_37],
];
/// AgX's outset: restores saturation after the sigmoid (Blender 4's, as three.js r160 has
/// it). Rows sum to 1.
const AGX_OUTSET: [[f32; 3]; 3] = [
    [1.127_100_6, -0.110_606_64, -0.016_493_94],
    [-0.141_329_76, 1.157_823_7, -0.016_493_94],
    [-0.141_329_76, -0.110_606_64, 1.251_936_4],
];
/// The log2 range the sigmoid spans: 10 stops below and 6.5 above mid grey 0.18.
const AGX_MIN_EV: f32 = -12.473_93;
/// See `AGX_MIN_EV`.
const AGX_MAX_EV: f32 = 4.026_069;

/// The sixth-order polynomial fit of AgX's default-contrast sigmoid on [0, 1] (Benjamin
/// Wrensch's "minimal AgX", mean squared error 3.7e-6): log-encoded in, display-encoded
/// (gamma 2.2) out.
fn agx_default_contrast(x: f32) -> f32 {
    let x2 = x * x;
    let x4 = x2 * x2;
    15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
        - 0.00232
}

/// A look applied to AgX's display-encoded values, between the sigmoid and the outset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum AgxLook {
    /// None: the base transform.
    Base,
    /// Blender's "Punchy": an ASC CDL with power 1.35 and saturation 1.4 (the parameters of
    /// Benjamin Wrensch's minimal AgX, which reproduce Blender's look).
    Punchy,
}

/// The Punchy look's power on each display-encoded channel.
const PUNCHY_POWER: f32 = 1.35;
/// The Punchy look's saturation about the (Rec. 709 weighted) luminance.
const PUNCHY_SATURATION: f32 = 1.4;

/// `look` on display-encoded AgX values in [0, 1] (ASC CDL: power, then saturation about
/// the luminance), clipped back to [0, 1].
fn agx_look(encoded: [f32; 3], look: AgxLook) -> [f32; 3] {
    match look {
        AgxLook::Base => encoded,
        AgxLook::Punchy => {
            let powered = encoded.map(|c| c.max(0.0).powf(PUNCHY_POWER));
            let luma = luminance(powered);
            powered.map(|c| (luma + PUNCHY_SATURATION * (c - luma)).clamp(0.0, 1.0))
        }
    }
}

/// Troy Sobotka's AgX base transform with a `look`, the steps of Blender 4's OCIO config as
/// three.js r160 writes them: sRGB -> Rec. 2020, inset, log2 encoding over
/// [AGX_MIN_EV, AGX_MAX_EV], sigmoid, the look, outset, gamma 2.2 back to linear, Rec. 2020
/// -> sRGB.
fn agx(rgb: [f32; 3], look: AgxLook) -> [f32; 3] {
    let inset = multiply(&AGX_INSET, multiply(&SRGB_TO_REC2020, rgb));
    let encoded = inset.map(|c| {
        // 1e-10 keeps log2 finite for black; +inf lands on the top of the range.
        let stops = c.max(1e-10).log2();
        let normalized = (stops - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
        agx_default_contrast(normalized.clamp(0.0, 1.0))
    });
    let encoded = agx_look(encoded, look);
    let display = multiply(&AGX_OUTSET, encoded).map(|c| c.max(0.0).powf(2.2));
    multiply(&REC2020_TO_SRGB, display).map(|c| c.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [ToneMap; 4] = [
        ToneMap::Clamp,
        ToneMap::Aces,
        ToneMap::Agx,
        ToneMap::AgxPunchy,
    ];

    fn grey(value: f32, map: ToneMap) -> f32 {
        tone_map([value; 3], 1.0, map)[1]
    }

    fn uniform(rgb: [f32; 3], pixels: usize) -> RenderedImage {
        RenderedImage {
            width: pixels as u32,
            height: 1,
            mean: vec![[rgb[0], rgb[1], rgb[2], 1.0]; pixels],
            second_moment: vec![[0.0; 3]; pixels],
            sample_count: vec![1.0; pixels],
        }
    }

    #[test]
    fn clamp_is_exposure_then_clip() {
        assert_eq!(
            tone_map([0.5, 0.25, 0.0], 1.0, ToneMap::Clamp),
            [0.5, 0.25, 0.0]
        );
        assert_eq!(tone_map([1.0; 3], 1.0, ToneMap::Clamp), [1.0; 3]);
        assert_eq!(
            tone_map([7.0, -1.0, f32::NAN], 1.0, ToneMap::Clamp),
            [1.0, 0.0, 0.0]
        );
        // One stop down halves the radiance before the clip.
        assert_eq!(tone_map([1.0; 3], 0.5, ToneMap::Clamp), [0.5; 3]);
    }

    #[test]
    fn matrices_keep_white_white_and_invert() {
        for m in [&ACES_INPUT, &ACES_OUTPUT, &AGX_INSET, &AGX_OUTSET] {
            let white = multiply(m, [1.0; 3]);
            assert!(white.iter().all(|c| (c - 1.0).abs() < 1e-4), "{white:?}");
        }
        for basis in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
            let back = multiply(&REC2020_TO_SRGB, multiply(&SRGB_TO_REC2020, basis));
            for c in 0..3 {
                assert!((back[c] - basis[c]).abs() < 1e-5, "{basis:?} -> {back:?}");
            }
        }
    }

    #[test]
    fn curves_map_black_to_black_and_rise_monotonically() {
        for map in ALL {
            let black = tone_map([0.0; 3], 1.0, map);
            assert!(black.iter().all(|&c| c < 1e-3), "{map:?}: {black:?}");
            let mut previous = grey(0.0, map);
            // From 2^-12 to 2^8 in quarter stops.
            for step in -48..=32 {
                let value = grey((step as f32 / 4.0).exp2(), map);
                assert!(
                    value >= previous,
                    "{map:?} falls at 2^{}",
                    step as f32 / 4.0
                );
                previous = value;
            }
        }
    }

    #[test]
    fn filmic_curves_roll_off_instead_of_clipping() {
        for map in [ToneMap::Aces, ToneMap::Agx] {
            // Four stops above 1 (16) is still below white: highlights keep detail
            // (ACES reaches 1 at about 25.7, AgX at 0.18 * 2^6.5 = 16.3).
            let bright = grey(15.0, map);
            assert!(bright < 1.0 && bright > 0.9, "{map:?}: 15 -> {bright}");
            assert!(grey(4.0, map) < grey(8.0, map), "{map:?}");
            // Mid grey lands in the middle, not at the clip.
            let middle = grey(MIDDLE_GREY, map);
            assert!(middle > 0.05 && middle < 0.3, "{map:?}: 0.18 -> {middle}");
            // inf is white, NaN black.
            assert!(grey(f32::INFINITY, map) > 0.99, "{map:?}");
            assert_eq!(
                tone_map([f32::NAN; 3], 1.0, map),
                tone_map([0.0; 3], 1.0, map)
            );
        }
        // Hill's fit: RRTAndODTFit(0.18) = 0.1056 for a grey.
        assert!((grey(MIDDLE_GREY, ToneMap::Aces) - 0.1056).abs() < 1e-3);
    }

    #[test]
    fn agx_desaturates_bright_saturated_colours_towards_white() {
        // A saturated red: AgX brings the other channels up as it brightens (the path to
        // white) and keeps red the largest on the way.
        let red = |scale: f32| tone_map([1.0, 0.05, 0.05], scale, ToneMap::Agx);
        let (dim, bright) = (red(0.25), red(64.0));
        assert!(dim[0] > dim[1] * 4.0, "{dim:?}");
        assert!(bright[1] > 0.5 && bright[2] > 0.5, "{bright:?}");
        assert!(
            bright[0] >= bright[1] && bright[0] >= bright[2],
            "{bright:?}"
        );
    }

    #[test]
    fn the_punchy_look_deepens_mid_tones_and_saturates_keeping_greys_and_white() {
        // Power 1.35 on the display-encoded mid grey (about 0.5): 0.5^1.35 = 0.39, so the
        // grey comes out markedly darker, shadows deeper still.
        let (base, punchy) = (
            grey(MIDDLE_GREY, ToneMap::Agx),
            grey(MIDDLE_GREY, ToneMap::AgxPunchy),
        );
        assert!(
            punchy < 0.9 * base && punchy > 0.5 * base,
            "{base} -> {punchy}"
        );
        assert!(grey(f32::INFINITY, ToneMap::AgxPunchy) > 0.99);
        // Greys stay grey: the saturation pivots about the luminance.
        let g = tone_map([0.3; 3], 1.0, ToneMap::AgxPunchy);
        assert!(
            (g[0] - g[2]).abs() < 1e-5 && (g[0] - g[1]).abs() < 1e-5,
            "{g:?}"
        );
        // A muted red gets more saturated (max - min relative to max).
        let saturation = |rgb: [f32; 3]| {
            let (max, min) = (
                rgb[0].max(rgb[1]).max(rgb[2]),
                rgb[0].min(rgb[1]).min(rgb[2]),
            );
            (max - min) / max
        };
        let red = [0.4, 0.1, 0.1];
        let (plain, punchy) = (
            tone_map(red, 1.0, ToneMap::Agx),
            tone_map(red, 1.0, ToneMap::AgxPunchy),
        );
        assert!(
            saturation(punchy) > saturation(plain),
            "{plain:?} -> {punchy:?}"
        );
    }

    #[test]
    fn auto_exposure_maps_the_log_average_to_middle_grey() {
        for l in [0.01f32, 0.5, 3.0, 1000.0] {
            let stops = auto_exposure(&uniform([l; 3], 16));
            let scale = stops.exp2();
            assert!(
                (scale - MIDDLE_GREY / l).abs() <= 1e-4 * MIDDLE_GREY / l,
                "{l}: {scale}"
            );
        }
        // The geometric mean of 0.02 and 2 is 0.2.
        let mut image = uniform([0.02; 3], 2);
        image.mean[1] = [2.0, 2.0, 2.0, 1.0];
        let scale = auto_exposure(&image).exp2();
        assert!((scale - 0.9).abs() < 1e-4, "{scale}");
        // Black, NaN and inf pixels are left out.
        image.mean.push([0.0, 0.0, 0.0, 1.0]);
        image.mean.push([f32::NAN, 0.0, 0.0, 1.0]);
        image.mean.push([f32::INFINITY, 1.0, 1.0, 1.0]);
        assert!((auto_exposure(&image).exp2() - 0.9).abs() < 1e-4);
        // All black: no exposure change.
        assert_eq!(auto_exposure(&uniform([0.0; 3], 4)), 0.0);
        assert_eq!(Exposure::Auto.scale_for(&uniform([0.0; 3], 4)), 1.0);
        assert_eq!(Exposure::Stops(-1.0).scale_for(&uniform([0.0; 3], 4)), 0.5);
    }
}
