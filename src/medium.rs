//! A homogeneous participating medium as a render asks for it (`render --medium
//! sigma_a=R,G,B:sigma_s=R,G,B:g=G`): its coefficients, their checks, and the specialization
//! constants that carry it into the path tracer (`glsl/medium.glsl`'s `g_medium`). The
//! maths lives in the twins `glsl/medium.glsl` / `crate::cpu::medium` and
//! `glsl/phase_function.glsl` / `crate::cpu::phase_function`; docs/media.md says what is
//! supported.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::contract;

/// A medium's coefficients or their text are wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MediumError {
    /// A part of the text is not `key=value`, or names no known key.
    #[error("'{0}' is not one of sigma_a=R,G,B, sigma_s=R,G,B or g=G (parts separated by ':')")]
    UnknownPart(String),
    /// A key is given twice.
    #[error("{0} is given twice")]
    Repeated(String),
    /// A value is not a number, or a coefficient has neither 1 nor 3 of them.
    #[error("{key}={value}: expected {expected}")]
    BadValue {
        /// The key.
        key: String,
        /// Its text.
        value: String,
        /// What it should be.
        expected: &'static str,
    },
    /// A coefficient is negative or not finite.
    #[error("{key} has {value}: coefficients must be finite and at least 0")]
    BadCoefficient {
        /// `sigma_a` or `sigma_s`.
        key: &'static str,
        /// The offending value.
        value: f32,
    },
    /// The anisotropy is outside (-1, 1).
    #[error("g={0}: the Henyey-Greenstein anisotropy must lie strictly between -1 and 1")]
    BadAnisotropy(f32),
}

/// A homogeneous medium: coefficients per scene unit of length, linear RGB. The twin of
/// `medium_t` (`glsl/medium.glsl`): the same fields in the same order.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Medium {
    /// sigma_a: the fraction of light absorbed per unit length, per channel, >= 0.
    pub absorption: Vec3,
    /// sigma_s: the fraction of light scattered per unit length, per channel, >= 0.
    pub scattering: Vec3,
    /// g of the Henyey-Greenstein phase function, in (-1, 1): > 0 forwards, 0 isotropic.
    pub anisotropy: f32,
}

impl Medium {
    /// No medium: every coefficient 0 (a vacuum, transmittance 1 everywhere).
    pub const VACUUM: Medium = Medium {
        absorption: Vec3::ZERO,
        scattering: Vec3::ZERO,
        anisotropy: 0.0,
    };

    /// Checks the coefficients (finite, >= 0) and the anisotropy (in (-1, 1)).
    pub fn validate(&self) -> Result<(), MediumError> {
        for (key, coefficients) in [("sigma_a", self.absorption), ("sigma_s", self.scattering)] {
            for value in coefficients.to_array() {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(MediumError::BadCoefficient { key, value });
                }
            }
        }
        if !(self.anisotropy > -1.0 && self.anisotropy < 1.0) {
            return Err(MediumError::BadAnisotropy(self.anisotropy));
        }
        Ok(())
    }

    /// The path tracer's specialization constants for this medium: `SPEC_MEDIUM` 1 and its
    /// seven coefficients' bits from `SPEC_MEDIUM_COEFFICIENTS` on (sigma_a rgb, sigma_s rgb,
    /// g), as `glsl/medium.glsl` reads them. A render without a medium passes none (the
    /// kernel's defaults: no medium).
    pub fn specialization(&self) -> Vec<(u32, u32)> {
        let mut constants = vec![(contract::SPEC_MEDIUM, 1)];
        let values = self
            .absorption
            .to_array()
            .into_iter()
            .chain(self.scattering.to_array())
            .chain([self.anisotropy]);
        for (k, value) in values.enumerate() {
            constants.push((
                contract::SPEC_MEDIUM_COEFFICIENTS + k as u32,
                value.to_bits(),
            ));
        }
        constants
    }
}

/// One coefficient's text: one value for all three channels, or three.
fn parse_coefficients(key: &str, value: &str) -> Result<Vec3, MediumError> {
    let bad = || MediumError::BadValue {
        key: key.to_string(),
        value: value.to_string(),
        expected: "one number for all channels or three, R,G,B",
    };
    let numbers = value
        .split(',')
        .map(|n| n.trim().parse::<f32>().map_err(|_| bad()))
        .collect::<Result<Vec<f32>, MediumError>>()?;
    match numbers[..] {
        [v] => Ok(Vec3::splat(v)),
        [r, g, b] => Ok(Vec3::new(r, g, b)),
        _ => Err(bad()),
    }
}

impl FromStr for Medium {
    type Err = MediumError;

    /// `sigma_a=R,G,B:sigma_s=R,G,B:g=G`, parts in any order, each at most once; a missing
    /// coefficient is 0, a missing g is 0 (isotropic). The result is validated.
    fn from_str(text: &str) -> Result<Medium, MediumError> {
        let mut medium = Medium::VACUUM;
        let mut seen = Vec::new();
        for part in text.split(':') {
            let (key, value) = part
                .split_once('=')
                .ok_or_else(|| MediumError::UnknownPart(part.to_string()))?;
            let key = key.trim();
            if seen.contains(&key) {
                return Err(MediumError::Repeated(key.to_string()));
            }
            seen.push(key);
            match key {
                "sigma_a" => medium.absorption = parse_coefficients(key, value)?,
                "sigma_s" => medium.scattering = parse_coefficients(key, value)?,
                "g" => {
                    medium.anisotropy = value.trim().parse().map_err(|_| MediumError::BadValue {
                        key: key.to_string(),
                        value: value.to_string(),
                        expected: "a number in (-1, 1)",
                    })?
                }
                _ => return Err(MediumError::UnknownPart(part.to_string())),
            }
        }
        medium.validate()?;
        Ok(medium)
    }
}

impl fmt::Display for Medium {
    /// The text `from_str` reads back (`sigma_a=R,G,B:sigma_s=R,G,B:g=G`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [ar, ag, ab] = self.absorption.to_array();
        let [sr, sg, sb] = self.scattering.to_array();
        write!(
            f,
            "sigma_a={ar},{ag},{ab}:sigma_s={sr},{sg},{sb}:g={}",
            self.anisotropy
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_grey_and_coloured_coefficients_and_round_trips() {
        let medium: Medium = "sigma_a=0.5:sigma_s=0.1,0.2,0.3:g=0.7".parse().unwrap();
        assert_eq!(medium.absorption, Vec3::splat(0.5));
        assert_eq!(medium.scattering, Vec3::new(0.1, 0.2, 0.3));
        assert_eq!(medium.anisotropy, 0.7);
        assert_eq!(medium.to_string().parse::<Medium>().unwrap(), medium);
        // Missing parts are 0
        let absorber: Medium = "sigma_a=1".parse().unwrap();
        assert_eq!(
            (absorber.scattering, absorber.anisotropy),
            (Vec3::ZERO, 0.0)
        );
    }

    #[test]
    fn rejects_bad_coefficients_anisotropy_and_text() {
        for (text, needle) in [
            ("sigma_a=-1", "sigma_a has -1"),
            ("sigma_s=1,nan,1", "sigma_s has NaN"),
            ("sigma_s=inf", "sigma_s has inf"),
            ("g=1", "g=1"),
            ("g=-1.5", "g=-1.5"),
            ("sigma_a=1,2", "expected one number"),
            ("sigma_a=x", "expected one number"),
            ("sigma_t=1", "not one of"),
            ("fog", "not one of"),
            ("sigma_a=1:sigma_a=2", "given twice"),
        ] {
            let error = text.parse::<Medium>().unwrap_err().to_string();
            assert!(error.contains(needle), "{text}: {error}");
            assert!(!error.contains('\n'), "{text}: one line");
        }
    }

    #[test]
    fn specialization_carries_the_coefficients_bits() {
        let medium: Medium = "sigma_a=1,2,3:sigma_s=4,5,6:g=-0.25".parse().unwrap();
        let constants = medium.specialization();
        assert_eq!(constants[0], (contract::SPEC_MEDIUM, 1));
        let values: Vec<f32> = constants[1..]
            .iter()
            .enumerate()
            .map(|(k, (id, bits))| {
                assert_eq!(*id, contract::SPEC_MEDIUM_COEFFICIENTS + k as u32);
                f32::from_bits(*bits)
            })
            .collect();
        assert_eq!(values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, -0.25]);
    }
}
