//! The environment a user asks for, before it is loaded: a constant colour, or an
//! equirectangular map file with its strength and rotation. The command line (`--background`,
//! `--environment`, `--environment-strength`, `--environment-rotation`) and Python
//! (`background=`, `environment=`, ...) both check their options here, under their own
//! names, and the scene takes the loaded environment in one place,
//! `crate::scene::Scene::with_environment`.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::environment::{load_environment_map, Environment, EnvironmentMapError};

/// What rays that leave the scene should see, as asked for (not yet loaded).
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    /// A constant radiance (linear RGB, finite, non-negative) from every direction.
    Background(Vec3),
    /// An equirectangular map (.exr or .hdr, see `load_environment_map`).
    Map {
        /// The map's file.
        path: PathBuf,
        /// Factor on its radiance, finite and >= 0.
        strength: f32,
        /// Turn about +Y in degrees, finite.
        rotation_degrees: f32,
    },
}

/// Environment options that do not go together or are out of range: one line, naming the
/// option as the front end names it (`EnvironmentOptionNames`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EnvironmentOptionError {
    /// A strength that is negative, infinite or NaN.
    #[error("{option} must be a finite number >= 0, not {strength}")]
    Strength {
        /// The strength's option.
        option: &'static str,
        /// The value given.
        strength: f32,
    },
    /// A rotation that is infinite or NaN.
    #[error("{option} must be finite")]
    Rotation {
        /// The rotation's option.
        option: &'static str,
    },
    /// Both a map and a constant colour.
    #[error("{map} and {background} exclude each other: give one")]
    MapAndBackground {
        /// The map's option.
        map: &'static str,
        /// The constant colour's option.
        background: &'static str,
    },
    /// A constant colour with a negative or non-finite component.
    #[error("{option} must be three finite numbers >= 0")]
    Background {
        /// The constant colour's option.
        option: &'static str,
    },
}

/// How a front end names the environment's options, for its error messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnvironmentOptionNames {
    /// The map's option.
    pub map: &'static str,
    /// The strength's option.
    pub strength: &'static str,
    /// The rotation's option.
    pub rotation: &'static str,
    /// The constant colour's option.
    pub background: &'static str,
}

/// The command line's names.
pub const COMMAND_LINE_NAMES: EnvironmentOptionNames = EnvironmentOptionNames {
    map: "--environment",
    strength: "--environment-strength",
    rotation: "--environment-rotation",
    background: "--background",
};

impl EnvironmentSource {
    /// The environment that the options ask for (`None`: neither a map nor a background),
    /// checked: the strength must be finite and >= 0 and the rotation finite (even without
    /// a map, so that a typo is not silently ignored), at most one of map and background,
    /// the background finite and >= 0. The error is one line naming the option.
    pub fn from_options(
        map: Option<&Path>,
        strength: f32,
        rotation_degrees: f32,
        background: Option<Vec3>,
        names: &EnvironmentOptionNames,
    ) -> Result<Option<EnvironmentSource>, EnvironmentOptionError> {
        if !(strength >= 0.0 && strength.is_finite()) {
            return Err(EnvironmentOptionError::Strength {
                option: names.strength,
                strength,
            });
        }
        if !rotation_degrees.is_finite() {
            return Err(EnvironmentOptionError::Rotation {
                option: names.rotation,
            });
        }
        match (map, background) {
            (Some(_), Some(_)) => Err(EnvironmentOptionError::MapAndBackground {
                map: names.map,
                background: names.background,
            }),
            (None, Some(background)) => {
                if !(background.is_finite() && background.min_element() >= 0.0) {
                    return Err(EnvironmentOptionError::Background {
                        option: names.background,
                    });
                }
                Ok(Some(EnvironmentSource::Background(background)))
            }
            (Some(path), None) => Ok(Some(EnvironmentSource::Map {
                path: path.to_path_buf(),
                strength,
                rotation_degrees,
            })),
            (None, None) => Ok(None),
        }
    }

    /// Loads the environment (reads the map); the error is one line naming the file.
    pub fn load(&self) -> Result<Environment, EnvironmentMapError> {
        match self {
            EnvironmentSource::Background(background) => Ok(Environment::constant(*background)),
            EnvironmentSource::Map {
                path,
                strength,
                rotation_degrees,
            } => Ok(Environment {
                map: Some(load_environment_map(path)?),
                background: Vec3::ZERO,
                strength: *strength,
                rotation_degrees: *rotation_degrees,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(
        map: Option<&str>,
        strength: f32,
        rotation: f32,
        background: Option<Vec3>,
    ) -> Result<Option<EnvironmentSource>, EnvironmentOptionError> {
        EnvironmentSource::from_options(
            map.map(Path::new),
            strength,
            rotation,
            background,
            &COMMAND_LINE_NAMES,
        )
    }

    #[test]
    fn options_are_checked_in_one_place_under_the_front_ends_names() {
        assert_eq!(options(None, 1.0, 0.0, None), Ok(None));
        assert_eq!(
            options(None, 1.0, 0.0, Some(Vec3::ONE)),
            Ok(Some(EnvironmentSource::Background(Vec3::ONE)))
        );
        assert_eq!(
            options(Some("sky.exr"), 2.0, -90.0, None),
            Ok(Some(EnvironmentSource::Map {
                path: "sky.exr".into(),
                strength: 2.0,
                rotation_degrees: -90.0
            }))
        );
        assert_eq!(
            options(None, -1.0, 0.0, None).unwrap_err().to_string(),
            "--environment-strength must be a finite number >= 0, not -1"
        );
        assert_eq!(
            options(None, 1.0, f32::NAN, None).unwrap_err().to_string(),
            "--environment-rotation must be finite"
        );
        assert_eq!(
            options(None, 1.0, 0.0, Some(Vec3::new(1.0, -1.0, 0.0)))
                .unwrap_err()
                .to_string(),
            "--background must be three finite numbers >= 0"
        );
        assert_eq!(
            options(Some("sky.exr"), 1.0, 0.0, Some(Vec3::ONE))
                .unwrap_err()
                .to_string(),
            "--environment and --background exclude each other: give one"
        );
    }

    #[test]
    fn a_background_loads_as_a_constant_and_a_missing_map_is_one_line() {
        let constant = EnvironmentSource::Background(Vec3::splat(0.25)).load();
        assert_eq!(
            constant.ok(),
            Some(Environment::constant(Vec3::splat(0.25)))
        );
        let missing = EnvironmentSource::Map {
            path: "no/such/sky.exr".into(),
            strength: 1.0,
            rotation_degrees: 0.0,
        }
        .load()
        .unwrap_err()
        .to_string();
        assert!(
            missing.contains("no/such/sky.exr") && !missing.contains('\n'),
            "{missing}"
        );
    }
}
