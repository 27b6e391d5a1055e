//! What is wrong with a command-line value: the error of the CLI's `value_parser`s, which
//! clap prints after "invalid value 'X' for '--option'".

use glam::Vec3;

use crate::render::settings::MAX_SPP;

/// A command-line value that does not parse, in one line that quotes it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ValueError {
    /// Not a number, where seconds are asked for.
    #[error("'{text}' is not a number of seconds")]
    NotSeconds {
        /// The value as given.
        text: String,
    },
    /// A number of seconds that is not positive and finite (under 1e9).
    #[error("{text} is not a positive number of seconds")]
    NotPositiveSeconds {
        /// The value as given.
        text: String,
    },
    /// Not a sample count per pixel in 1..=`MAX_SPP`.
    #[error("'{text}' is not a number of samples per pixel in 1..={MAX_SPP}")]
    NotSpp {
        /// The value as given.
        text: String,
    },
    /// Not START..END with START < END.
    #[error("'{text}' is not START..END with START < END")]
    NotSampleRange {
        /// The value as given.
        text: String,
    },
    /// Not INDEX/COUNT with INDEX < COUNT.
    #[error("'{text}' is not INDEX/COUNT with 0 <= INDEX < COUNT")]
    NotShard {
        /// The value as given.
        text: String,
    },
    /// Neither `auto` nor a finite number of stops.
    #[error("'{text}' is neither 'auto' nor a finite number of stops")]
    NotExposure {
        /// The value as given.
        text: String,
    },
    /// Not two numbers X,Y.
    #[error("'{text}' is not X,Y")]
    NotPixel {
        /// The value as given.
        text: String,
    },
    /// A coordinate of a pixel that is not a whole number >= 0.
    #[error("'{text}' is not a pixel index")]
    NotPixelIndex {
        /// The coordinate as given.
        text: String,
    },
    /// Not a number (or a part of a vector that is not).
    #[error("'{text}' is not a number")]
    NotNumber {
        /// The value (or part) as given.
        text: String,
    },
    /// A part of a vector that is infinite or NaN.
    #[error("'{text}' is not finite")]
    NotFinite {
        /// The part as given.
        text: String,
    },
    /// Not three comma-separated parts.
    #[error("expected three comma-separated numbers x,y,z, got '{text}'")]
    NotThreeNumbers {
        /// The value as given.
        text: String,
    },
    /// A number outside [0, 1].
    #[error("{value} is outside [0, 1]")]
    OutsideUnitInterval {
        /// The number.
        value: f32,
    },
    /// A view angle outside [0, 90) degrees.
    #[error("{value} is outside [0, 90) degrees: the view must be above the surface")]
    ViewBelowSurface {
        /// The angle in degrees.
        value: f32,
    },
    /// A colour with a component outside [0, 1].
    #[error("{color} has a component outside [0, 1]")]
    ColorOutsideUnitInterval {
        /// The colour.
        color: Vec3,
    },
    /// Not a whole number.
    #[error("'{text}' is not a whole number")]
    NotWholeNumber {
        /// The value as given.
        text: String,
    },
    /// An image size that is not a multiple of 8 in 8..=1024.
    #[error("{size} is not a multiple of 8 in 8..=1024")]
    NotBlockSize {
        /// The size.
        size: u32,
    },
    /// Not BUFFER=FILE.exr.
    #[error("'{text}': expected BUFFER=FILE.exr, e.g. a=A.exr")]
    NotBufferFile {
        /// The value as given.
        text: String,
    },
    /// BUFFER=FILE where BUFFER names no buffer.
    #[error("'{text}': '{name}' is not a buffer (a, b, c, d or buffer-a … buffer-d)")]
    NotABuffer {
        /// The value as given.
        text: String,
        /// Its BUFFER part.
        name: String,
    },
    /// BUFFER=FILE where FILE is not an EXR.
    #[error("'{text}': buffers are saved as .exr")]
    BufferNotExr {
        /// The value as given.
        text: String,
    },
    /// Not a time in seconds at or after 0 (`--time`).
    #[error("'{text}' is not a time in seconds at or after 0")]
    NotTime {
        /// The value as given.
        text: String,
    },
    /// Not a shutter of 0 to 2 frame intervals (`--shutter`).
    #[error("'{text}' is not a shutter of 0 to 2 frame intervals")]
    NotShutter {
        /// The value as given.
        text: String,
    },
    /// Not a number of motion keys from 2 to 64 (`--motion-steps`).
    #[error("'{text}' is not a number of motion keys from 2 to 64")]
    NotMotionSteps {
        /// The value as given.
        text: String,
    },
    /// Not a frame rate above 0 (`--fps`).
    #[error("'{text}' is not a frame rate above 0")]
    NotFrameRate {
        /// The value as given.
        text: String,
    },
    /// Not START..END with START < END (`--frames`).
    #[error("'{text}' is not START..END with START < END (END excluded)")]
    NotFrameRange {
        /// The value as given.
        text: String,
    },
    /// Not HOST:PORT (`--tev`).
    #[error("'{text}' is not HOST:PORT (e.g. 127.0.0.1:14158): {why}")]
    NotHostPort {
        /// The value as given.
        text: String,
        /// What is wrong with it.
        why: &'static str,
    },
    /// Not a finite number at or above 0.
    #[error("'{text}' is not a finite number at or above 0")]
    NotNonNegative {
        /// The value as given.
        text: String,
    },
    /// Not a finite number above 0.
    #[error("'{text}' is not a finite number above 0")]
    NotPositive {
        /// The value as given.
        text: String,
    },
    /// Not a number of aperture blades: 0 (round) or 3..=64.
    #[error("'{text}' is not a number of aperture blades: 0 (round) or 3 to 64")]
    NotBlades {
        /// The value as given.
        text: String,
    },
    /// A `--frames` range longer than `MAX_FRAMES`.
    #[error("'{text}' holds {count} frames; one render takes at most {max} (split the range over several tasks)", max = crate::cli::frames::MAX_FRAMES)]
    TooManyFrames {
        /// The value as given.
        text: String,
        /// How many frames it holds.
        count: u64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_quote_the_value() {
        let text = "x".to_string();
        assert_eq!(
            ValueError::NotSpp { text }.to_string(),
            format!("'x' is not a number of samples per pixel in 1..={MAX_SPP}")
        );
        assert_eq!(
            ValueError::ColorOutsideUnitInterval {
                color: Vec3::new(2.0, 0.5, 0.0)
            }
            .to_string(),
            "[2, 0.5, 0] has a component outside [0, 1]"
        );
    }
}
