//! The heat map of `vkpath compare --heatmap`: where the failing blocks are.

use super::CompareReport;
use crate::image_io::data::RenderedImage;

/// Linear RGB of a block from its smallest p-value. The evidence is measured as
/// s = ln p / ln(per-test significance): 0 for p = 1, 1 exactly at the threshold. Passing
/// blocks (s < 1) are grey, brighter as they approach the threshold (at most 0.25 linear,
/// sRGB 137); failing blocks are red, turning yellow as s grows to 5 (p = significance^5).
pub fn heat_color(p_value: f64, significance: f64) -> [f32; 3] {
    let evidence = if p_value <= 0.0 {
        f64::INFINITY
    } else {
        p_value.ln() / significance.ln()
    };
    if evidence < 1.0 {
        let grey = (0.25 * evidence.max(0.0)) as f32;
        [grey, grey, grey]
    } else {
        let yellow = ((evidence - 1.0) / 4.0).min(1.0) as f32;
        [1.0, yellow, 0.0]
    }
}

/// The heat map's legend in one line: what each colour of `heat_color` says about a
/// block's smallest p-value, with the thresholds that `significance` (the per-test level)
/// puts on them.
pub fn heat_legend(significance: f64) -> String {
    format!(
        "black: p = 1; grey, brighter as p falls towards {significance:.2e}: passes; \
         red: p = {significance:.2e}, fails; red to yellow: p from {significance:.2e} \
         down to {:.2e} and below",
        significance.powi(5)
    )
}

/// An image of the compared images' size in which every pixel has its block's
/// `heat_color`.
pub fn heat_map(report: &CompareReport, width: u32, height: u32) -> RenderedImage {
    let block = report.block_size;
    let mean: Vec<[f32; 4]> = (0..height as usize)
        .flat_map(|y| (0..width as usize).map(move |x| (x, y)))
        .map(|(x, y)| {
            let index = (y / block) * report.blocks_x + x / block;
            let p_value = report.block_p_values.get(index).copied().unwrap_or(1.0);
            let [r, g, b] = heat_color(p_value, report.per_test_significance);
            [r, g, b, 1.0]
        })
        .collect();
    RenderedImage {
        width,
        height,
        second_moment: mean
            .iter()
            .map(|c| [c[0] * c[0], c[1] * c[1], c[2] * c[2]])
            .collect(),
        sample_count: vec![1.0; mean.len()],
        mean,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_separate_passing_from_failing_blocks() {
        let significance = 1e-4;
        assert_eq!(heat_color(1.0, significance), [0.0; 3]);
        let near = heat_color(2e-4, significance);
        assert!(near[0] == near[1] && near[0] > 0.2 && near[0] < 0.25);
        assert_eq!(heat_color(1e-4, significance), [1.0, 0.0, 0.0]);
        assert_eq!(heat_color(0.0, significance), [1.0, 1.0, 0.0]);
        assert_eq!(heat_color(1e-20, significance), [1.0, 1.0, 0.0]);
    }

    #[test]
    fn the_legend_names_the_thresholds_where_the_colours_change() {
        let significance = 1e-4;
        let legend = heat_legend(significance);
        assert_eq!(
            legend,
            "black: p = 1; grey, brighter as p falls towards 1.00e-4: passes; \
             red: p = 1.00e-4, fails; red to yellow: p from 1.00e-4 down to 1.00e-20 and below"
        );
        // The colours it names are `heat_color`'s at those p-values.
        assert_eq!(heat_color(1.0, significance), [0.0; 3]);
        assert_eq!(heat_color(1e-4, significance), [1.0, 0.0, 0.0]);
        assert_eq!(heat_color(1e-20, significance), [1.0, 1.0, 0.0]);
    }
}
