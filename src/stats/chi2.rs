//! Pearson's χ² goodness-of-fit test of observed bin counts against expected ones, with
//! Mitsuba's pooling of sparse bins and a Šidák correction, and its use on direction
//! samplers: `chi2_direction_test` bins samples on the sphere (`super::sphere_histogram`)
//! and tests them against a target density.

use glam::Vec3;
use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::stats::sphere_histogram::{
    expected_counts, histogram_directions, SphereFrame, SphereGrid, TargetDensity,
};
use crate::stats::{sidak_alpha, StatsError};

/// Settings of a χ² test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chi2Config {
    /// The bins on the sphere (for `chi2_direction_test`).
    pub grid: SphereGrid,
    /// Bins expecting fewer samples than this are pooled into one. 5 is the usual rule of
    /// thumb (and Mitsuba's) for the χ² approximation of Pearson's statistic to hold.
    pub min_expected_count: f64,
    /// Family-wise significance level: the chance of failing a correct sampler over all
    /// `test_count` tests.
    pub alpha: f64,
    /// Number of tests run together, for the Šidák correction.
    pub test_count: usize,
    /// Simpson intervals per axis and bin for `TargetDensity::SolidAngle`; 6 resolves a
    /// smooth density over bins of 0.13 rad x 0.02 in cos theta far below the statistical
    /// noise of 10^6 samples.
    pub quadrature_resolution: usize,
}

impl Default for Chi2Config {
    /// Mitsuba's grid, pooling below 5, alpha = 1% for a single test.
    fn default() -> Chi2Config {
        Chi2Config {
            grid: SphereGrid::default(),
            min_expected_count: 5.0,
            alpha: 0.01,
            test_count: 1,
            quadrature_resolution: 6,
        }
    }
}

/// The outcome of a χ² test.
#[derive(Clone, Debug, PartialEq)]
pub struct Chi2Result {
    /// Pearson's statistic sum (observed - expected)^2 / expected over the cells that remain
    /// after pooling.
    pub statistic: f64,
    /// Cells after pooling minus 1 (all parameters of the target are known).
    pub degrees_of_freedom: usize,
    /// P(X >= statistic) for X ~ χ²(degrees_of_freedom); 0 when a sample was impossible or
    /// invalid, since the hypothesis is then refuted outright.
    pub p_value: f64,
    /// How many bins were pooled into one cell because they expected too few samples.
    pub pooled_bin_count: usize,
    /// The per-test significance level after the Šidák correction.
    pub significance: f64,
    /// Samples in bins that expected none (e.g. below a hemisphere).
    pub impossible_sample_count: u64,
    /// Samples that are not valid at all (for directions: non-finite or not unit length).
    pub invalid_sample_count: u64,
    /// No impossible or invalid sample, and p_value >= significance.
    pub passed: bool,
}

/// Pearson's χ² test of bin counts, pooling as Mitsuba's `ChiSquare::runTest` does: bins are
/// visited by increasing expected count; bins expecting fewer than `min_expected_count`,
/// and then further bins until the pool expects that many, form one cell.
/// \param observed Count per bin
/// \param expected Expected count per bin, >= 0
/// \param invalid_sample_count Samples that could not be binned (they fail the test)
/// \param config Pooling threshold, alpha and test count (the grid is not read)
pub fn chi2_test(
    observed: &[u64],
    expected: &[f64],
    invalid_sample_count: u64,
    config: &Chi2Config,
) -> Result<Chi2Result, StatsError> {
    if observed.len() != expected.len() {
        return Err(StatsError::SizeMismatch(format!(
            "{} observed bins vs {} expected",
            observed.len(),
            expected.len()
        )));
    }
    if let Some(bad) = expected.iter().find(|e| !(e.is_finite() && **e >= 0.0)) {
        return Err(StatsError::InvalidParameter(format!(
            "expected count {bad} is not finite and >= 0"
        )));
    }
    let significance = sidak_alpha(config.alpha, config.test_count)?;
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));

    let mut statistic = 0.0;
    let mut cell_count = 0usize;
    let mut impossible_sample_count = 0u64;
    let (mut pooled_observed, mut pooled_expected, mut pooled_bin_count) = (0.0, 0.0, 0usize);
    for index in order {
        let (o, e) = (observed[index] as f64, expected[index]);
        if e == 0.0 {
            impossible_sample_count += observed[index];
        } else if e < config.min_expected_count
            || (pooled_expected > 0.0 && pooled_expected < config.min_expected_count)
        {
            pooled_observed += o;
            pooled_expected += e;
            pooled_bin_count += 1;
        } else {
            statistic += (o - e) * (o - e) / e;
            cell_count += 1;
        }
    }
    if pooled_expected > 0.0 {
        statistic += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected)
            / pooled_expected;
        cell_count += 1;
    }
    if cell_count < 2 {
        return Err(StatsError::InvalidParameter(format!(
            "only {cell_count} cell(s) after pooling: too few samples or bins for a χ² test"
        )));
    }
    let degrees_of_freedom = cell_count - 1;
    let distribution = ChiSquared::new(degrees_of_freedom as f64).map_err(|error| {
        StatsError::InvalidParameter(format!(
            "χ² distribution with {degrees_of_freedom} degrees of freedom: {error}"
        ))
    })?;
    let refuted = impossible_sample_count > 0 || invalid_sample_count > 0;
    // The survival function keeps its precision far into the tail, unlike 1 - cdf.
    let p_value = if refuted || !statistic.is_finite() {
        0.0
    } else {
        distribution.sf(statistic)
    };
    Ok(Chi2Result {
        statistic,
        degrees_of_freedom,
        p_value,
        pooled_bin_count,
        significance,
        impossible_sample_count,
        invalid_sample_count,
        passed: !refuted && p_value >= significance,
    })
}

/// The χ² test of a direction sampler: bins the world-space `samples` relative to `frame`
/// and compares them with the counts that `target` predicts for as many samples.
pub fn chi2_direction_test(
    samples: impl IntoIterator<Item = Vec3>,
    target: TargetDensity,
    frame: &SphereFrame,
    config: &Chi2Config,
) -> Result<Chi2Result, StatsError> {
    let histogram = histogram_directions(samples, &config.grid, frame)?;
    // Invalid samples are not binned; the others should follow the target.
    let binned = histogram.sample_count - histogram.invalid_count;
    let expected = expected_counts(
        target,
        &config.grid,
        frame,
        binned,
        config.quadrature_resolution,
    )?;
    chi2_test(
        &histogram.counts,
        &expected,
        histogram.invalid_count,
        config,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistic_pooling_and_p_value_by_hand() {
        let config = Chi2Config::default();
        // Two cells of 50 expected and 40 / 60 observed: chi^2 = 2 * 100 / 50 = 4 with one
        // degree of freedom, p = P(|Z| >= 2) = 0.0455.
        let result = chi2_test(&[40, 60], &[50.0, 50.0], 0, &config).unwrap();
        assert_eq!((result.statistic, result.degrees_of_freedom), (4.0, 1));
        assert!(
            (result.p_value - 0.04550026).abs() < 1e-7,
            "{}",
            result.p_value
        );
        assert!(result.passed);
        // Bins expecting 1, 2 and 3 pool into one cell of 6 (observed 3 + 2 + 1 = 6, adding
        // nothing); the bin expecting 0 with no sample is ignored.
        let result = chi2_test(
            &[40, 60, 3, 2, 1, 0],
            &[50.0, 50.0, 1.0, 2.0, 3.0, 0.0],
            0,
            &config,
        )
        .unwrap();
        assert_eq!(
            (
                result.statistic,
                result.degrees_of_freedom,
                result.pooled_bin_count
            ),
            (4.0, 2, 3)
        );
        // A sample where none is expected refutes the hypothesis outright.
        let result = chi2_test(&[50, 50, 1], &[50.0, 50.0, 0.0], 0, &config).unwrap();
        assert_eq!(
            (
                result.impossible_sample_count,
                result.p_value,
                result.passed
            ),
            (1, 0.0, false)
        );
        let result = chi2_test(&[50, 50], &[50.0, 50.0], 1, &config).unwrap();
        assert!(!result.passed);
        assert!(chi2_test(&[1], &[1.0, 2.0], 0, &config).is_err());
        assert!(
            chi2_test(&[1, 1], &[1.0, 1.0], 0, &config).is_err(),
            "one pooled cell cannot be tested"
        );
    }
}
