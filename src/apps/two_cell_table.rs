//! The two-cell table (docs/ARCHITECTURE.md, "The independence trap"): the exact joint posterior of a few cells in
//! one sonar cone against the product of their marginals, with the gray each
//! cell's marginal is drawn in (the maps' ramp).

use crate::error::{invalid, Result};
use crate::mapping::joint::{ConeCell, JointPosterior, JointQuery, JointReport};
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
    /// "All chosen cells occupied": truly, and under the product of the
    /// marginals (the collinear preset's trap: about twice too likely).
    pub all_occupied_true: f64,
    pub all_occupied_factored: f64,
    /// `all_occupied_factored / all_occupied_true`.
    pub all_occupied_ratio: f64,
}

/// What a page's cells and the drag keep to in the chapter's query: ranges
/// up to the sonar's `z_max` (a reading there is no echo), bearings within
/// the cone's half-width, degrees.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TwoCellLimits {
    pub max_range: f64,
    pub half_cone_deg: f64,
}

impl TwoCellLimits {
    pub fn chapter() -> Self {
        let q = JointQuery::chapter_two_cells();
        Self {
            max_range: q.model.z_max,
            half_cone_deg: 0.5 * q.beta_deg,
        }
    }
}

/// The table's presets, by name: the chapter's query with the two cells
/// placed `side` by side (A and B at 2 m, 3 degrees either side of the
/// axis), `collinear` (the chapter's exercise: A at 1 m and B at 2 m on
/// the beam axis, docs/ARCHITECTURE.md, "The independence trap") or `apart` (A at 2 m and B at 1.2 m, 7 degrees
/// either side). The reading is the chapter's 2.0 m in each.
pub fn preset(name: &str) -> Result<JointQuery> {
    let at = |range: f64, bearing_deg: f64| ConeCell { range, bearing_deg };
    let cells = match name {
        "side" => return Ok(JointQuery::chapter_two_cells()),
        "collinear" => vec![at(1.0, 0.0), at(2.0, 0.0)],
        "apart" => vec![at(2.0, -7.0), at(1.2, 7.0)],
        _ => return Err(invalid("preset", name, "one of side, collinear, apart")),
    };
    Ok(JointQuery {
        cells,
        ..JointQuery::chapter_two_cells()
    })
}

pub fn two_cell_report(query: &JointQuery) -> Result<TwoCellReport> {
    let post = JointPosterior::compute(query)?;
    let (all_occupied_true, all_occupied_factored) =
        post.event(&vec![Some(true); query.cells.len()])?;
    let report = post.report();
    let marginal_grays = report
        .answer
        .marginals
        .iter()
        .map(|&p| probability_gray(p))
        .collect();
    Ok(TwoCellReport {
        report,
        marginal_grays,
        all_occupied_ratio: all_occupied_factored / all_occupied_true,
        all_occupied_true,
        all_occupied_factored,
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

    /// docs/ARCHITECTURE.md, "The independence trap": the collinear preset is the chapter's exercise, A at 1 m
    /// and B at 2 m on the axis, and there the factored map overstates
    /// "both occupied" about twofold (against 24-fold for "both free" side
    /// by side).
    #[test]
    fn the_collinear_preset_is_the_chapters_exercise() {
        let q = preset("collinear").unwrap();
        let at: Vec<_> = q.cells.iter().map(|c| (c.range, c.bearing_deg)).collect();
        assert_eq!(at, [(1.0, 0.0), (2.0, 0.0)]);
        assert_eq!(q.readings, [2.0]);
        let r = two_cell_report(&q).unwrap();
        let over = r.all_occupied_ratio;
        assert!((1.5..2.5).contains(&over), "both occupied {over}x");
        let side = two_cell_report(&preset("side").unwrap()).unwrap();
        assert!((side.report.all_free_ratio - 24.0).abs() < 0.5);
        assert!(preset("diagonal")
            .unwrap_err()
            .to_string()
            .contains("preset"));
    }
}
