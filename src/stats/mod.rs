//! Statistical tests for the renderer: a χ² goodness-of-fit test for direction samplers on
//! the sphere (Mitsuba / pbrt style) and z-tests that compare two Monte Carlo estimates, each
//! with a Šidák correction when many tests run at once.

pub mod chi2;
pub mod sphere_histogram;
pub mod ztest;

#[cfg(test)]
mod sampler_tests;

/// Why a statistical test could not run.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StatsError {
    /// A parameter is outside its valid range.
    #[error("invalid parameter for a statistical test: {0}")]
    InvalidParameter(String),
    /// Two inputs that must have the same size do not.
    #[error("size mismatch in a statistical test: {0}")]
    SizeMismatch(String),
}

/// The Šidák-corrected significance level of each of `test_count` independent tests, so that
/// the chance that any of them rejects a true hypothesis is `alpha`:
/// alpha_1 = 1 - (1 - alpha)^(1 / k), evaluated as -expm1(ln(1 - alpha) / k), which keeps its
/// precision for small alpha and large k.
/// \param alpha Family-wise significance level in (0, 1)
/// \param test_count Number of tests k >= 1
pub fn sidak_alpha(alpha: f64, test_count: usize) -> Result<f64, StatsError> {
    if !(alpha > 0.0 && alpha < 1.0) {
        return Err(StatsError::InvalidParameter(format!(
            "significance level {alpha} is not in (0, 1)"
        )));
    }
    if test_count == 0 {
        return Err(StatsError::InvalidParameter(
            "the Šidák correction needs at least one test".into(),
        ));
    }
    Ok(-((-alpha).ln_1p() / test_count as f64).exp_m1())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sidak_alpha_values() {
        assert!((sidak_alpha(0.01, 1).unwrap() - 0.01).abs() < 1e-15);
        let alpha_3 = sidak_alpha(0.01, 3).unwrap();
        assert!((alpha_3 - (1.0 - 0.99f64.powf(1.0 / 3.0))).abs() < 1e-15);
        // (1 - alpha_1)^k = 1 - alpha
        assert!(((1.0 - alpha_3).powi(3) - 0.99).abs() < 1e-14);
        assert!(
            sidak_alpha(0.0, 3).is_err()
                && sidak_alpha(1.0, 3).is_err()
                && sidak_alpha(0.5, 0).is_err()
        );
    }
}
