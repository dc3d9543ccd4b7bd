//! The prior-drift diagnostic of the learned inverse model (§9.3): what
//! happens to a map when the model's own `l0` is not subtracted.

use crate::error::{self, invalid, Result};
use crate::geometry::{GridGeometry, Pose};
use crate::grid::{FilterSettings, LogOddsGrid};
use crate::inverse::learned::LearnedInverse;
use crate::inverse::InverseModel;
use crate::mapping::sweep::sweep_scan;
use crate::sensors::Scan;

/// What [`prior_drift`] measured.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DriftReport {
    /// Identical scans integrated.
    pub scans: usize,
    /// Cells of the perceptual field that no feature of the model reaches.
    pub cells: usize,
    /// Their mean log odds afterwards with the model's own `l0` removed
    /// (they started at 0).
    pub own_l0: f64,
    /// The same with `l0` forced to 0.
    pub zero_l0: f64,
}

/// The prior-drift diagnostic. One beam reading `z` is integrated `scans`
/// times by the literal sweep (Table 9.1), once with the model's own `l0`
/// and once with `l0 = 0`. The cells watched are those of the perceptual
/// field that lie behind the reading by more than the model's band
/// ([`LearnedInverse::band_end`]): the model knows nothing about them (its
/// score there is its prior), yet the mapper visits them. With its own `l0` their evidence is exactly 0 and
/// they stay put; with `l0 = 0` each scan adds the model's prior to each of
/// them, and to every other cell of the field, so every cell of every
/// perceptual field drifts, by `scans * l0` after `scans` scans.
pub fn prior_drift(model: &LearnedInverse, z: f64, scans: usize) -> Result<DriftReport> {
    error::positive("z", z)?;
    if z >= model.z_max() {
        return Err(invalid("z", z, "a real return, shorter than z_max"));
    }
    if !(1..=10_000).contains(&scans) {
        return Err(invalid("scans", scans, "between 1 and 10000 scans"));
    }
    let res = 0.05;
    // The field of the wrong prior, which runs past the model's band.
    let zero_l0 = model.with_l0(0.0);
    let reach = zero_l0.reach(z);
    let half = model.half_width();
    let side = reach * half.sin() + res;
    let geometry = GridGeometry::covering(-res, -side, reach + res, side, res)?;
    let pose = Pose::new(0.0, 0.0, 0.0)?;
    let scan = Scan::new(pose, vec![z], vec![0.0])?;
    let run = |m: &LearnedInverse| -> Result<LogOddsGrid> {
        let mut grid = LogOddsGrid::new(geometry, FilterSettings::default())?;
        for _ in 0..scans {
            sweep_scan(&mut grid, m, &scan);
        }
        Ok(grid)
    };
    let own = run(model)?;
    let zero = run(&zero_l0)?;
    let watched: Vec<usize> = (0..geometry.len())
        .filter(|&i| {
            let (ix, iy) = geometry.cell_of_index(i);
            let (x, y) = geometry.cell_center(ix, iy);
            let (r, psi) = (x.hypot(y), y.atan2(x));
            r <= reach && psi.abs() <= half && r - z > model.band_end()
        })
        .collect();
    if watched.is_empty() {
        return Err(invalid("z", z, "a reading whose field has unreached cells"));
    }
    let mean = |g: &LogOddsGrid| {
        watched.iter().map(|&i| g.log_odds()[i] as f64).sum::<f64>() / watched.len() as f64
    };
    Ok(DriftReport {
        scans,
        cells: watched.len(),
        own_l0: mean(&own),
        zero_l0: mean(&zero),
    })
}
