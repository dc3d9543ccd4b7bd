//! The two-cell table (SPEC §6): the exact joint posterior of a few cells in
//! one sonar cone against the product of their marginals, with the gray each
//! cell's marginal is drawn in (the maps' ramp).

use crate::error::Result;
use crate::mapping::joint::{JointPosterior, JointQuery, JointReport};
use crate::render::gray::probability_gray;

/// What the table shows: the joint report and each cell's gray level.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TwoCellReport {
    #[serde(flatten)]
    pub report: JointReport,
    /// Gray level of each marginal on the maps' ramp (white free, black
    /// occupied).
    pub marginal_grays: Vec<u8>,
}

pub fn two_cell_report(query: &JointQuery) -> Result<TwoCellReport> {
    let report = JointPosterior::compute(query)?.report();
    let marginal_grays = report
        .answer
        .marginals
        .iter()
        .map(|&p| probability_gray(p))
        .collect();
    Ok(TwoCellReport {
        report,
        marginal_grays,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chapter's case: both marginals 0.6635, drawn a little darker than
    /// mid-gray, as the maps would draw a cell at that probability.
    #[test]
    fn the_chapter_cells_are_drawn_in_the_maps_gray() {
        let r = two_cell_report(&JointQuery::chapter_two_cells()).unwrap();
        assert_eq!(r.marginal_grays.len(), 2);
        let p = r.report.answer.marginals[0];
        assert!((p - 0.6635).abs() < 1e-4);
        assert_eq!(r.marginal_grays[0], (255.0 * (1.0 - p)).round() as u8);
    }
}
