//! The two panes against each other, for the exercises that compare them:
//! how many cells their exported maps disagree on (exercise 6: ray
//! traversal against the literal sweep), and, when one pane forgets to
//! subtract the model's `l0`, how far it has drifted per update (exercise
//! 8's diagnostic).

use super::settings::PaneSettings;
use super::Weaver;
use crate::grid::LogOddsGrid;
use crate::io::map_server::trinary_gray;

/// Cells on which the two maps' exports disagree (free, occupied or
/// unknown, with the thresholds the export's YAML states).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MapDifference {
    /// Cells exported differently.
    pub cells: usize,
    /// Cells of each map.
    pub of: usize,
    /// Of `cells`, those one pane updated and the other never did.
    pub updated_by_one: usize,
}

/// Exercise 8's diagnostic: one pane adds the model's scores without
/// removing the model's own `l0`, the other is the same in every other
/// knob. Each update then adds `l0` to the forgetting pane's cell on top of
/// what the other pane's cell gets, so a cell updated `n` times has drifted
/// by `n * l0`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct L0Drift {
    /// The pane that forgets (0 left, 1 right).
    pub pane: usize,
    /// The `l0` the other pane removes with every update, log odds.
    pub model_l0: f32,
    /// Measured: the median over `cells` of (the forgetting pane's log
    /// odds - the other's) / updates, log odds per update.
    pub per_update: Option<f64>,
    /// Cells measured: updated in both, strictly inside the clamp in both
    /// (a cell the clamp has cut no longer drifts by `l0` per update).
    pub cells: usize,
}

impl Weaver {
    /// How many cells the two panes' exported maps differ in; `None` when
    /// they map at different resolutions (their cells are not the same).
    pub fn map_difference(&self) -> Option<MapDifference> {
        let (a, b) = (self.panes[0].map.grid(), self.panes[1].map.grid());
        if a.geometry() != b.geometry() {
            return None;
        }
        let (ua, ub) = (a.update_counts(), b.update_counts());
        let mut cells = 0;
        let mut updated_by_one = 0;
        for i in 0..a.cells().len() {
            if trinary_gray(a.model(), a.cells()[i]) != trinary_gray(b.model(), b.cells()[i]) {
                cells += 1;
                if (ua[i] == 0) != (ub[i] == 0) {
                    updated_by_one += 1;
                }
            }
        }
        Some(MapDifference {
            cells,
            of: a.cells().len(),
            updated_by_one,
        })
    }

    /// The drift of a pane that forgets `l0`, measured against the other
    /// pane; `None` unless the two panes differ in that switch alone.
    pub fn l0_drift(&self) -> Option<L0Drift> {
        let [left, right] = [&self.panes[0].settings, &self.panes[1].settings];
        let remembered = |p: &PaneSettings| PaneSettings {
            forget_l0: false,
            ..*p
        };
        if left.forget_l0 == right.forget_l0 || remembered(left) != remembered(right) {
            return None;
        }
        let pane = usize::from(right.forget_l0);
        let (forgets, keeps) = (&self.panes[pane], &self.panes[1 - pane]);
        let ratios = drift_ratios(forgets.map.grid(), keeps.map.grid());
        Some(L0Drift {
            pane,
            model_l0: keeps.model.l0(),
            cells: ratios.len(),
            per_update: median(ratios),
        })
    }
}

/// Per cell updated in both grids and inside both clamps: the difference
/// of their log odds per update.
fn drift_ratios(forgets: &LogOddsGrid, keeps: &LogOddsGrid) -> Vec<f64> {
    let (lf, lk) = (forgets.log_odds(), keeps.log_odds());
    let (uf, uk) = (forgets.update_counts(), keeps.update_counts());
    let inside = |l: f32, g: &LogOddsGrid| l.abs() < g.clamp();
    (0..lf.len())
        .filter(|&i| uf[i] > 0 && uf[i] == uk[i] && inside(lf[i], forgets) && inside(lk[i], keeps))
        .map(|i| f64::from(lf[i] - lk[i]) / f64::from(uf[i]))
        .collect()
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    crate::geometry::order::sort_stable_by_key(&mut v, |&x| x);
    Some(v[v.len() / 2])
}
