//! The occupancy grid: one binary Bayes filter per cell, in log odds.
//!
//! This is the state every mapper writes into and every widget draws
//! (Probabilistic Robotics, §9.2, Table 9.1). A cell holds
//! `l = ln(p / (1 - p))`; a measurement adds the inverse sensor model's
//! evidence *net of the prior* `l0`, because the inverse model returns a
//! posterior and the prior must be counted once, not once per scan.
//!
//! The map's limits are [`GridGeometry`] (geometry layer); [`LogOddsGrid`]
//! is the filter itself, with the map-wide scores a widget reads (entropy,
//! Brier score) and, in [`stats`], the state counts of an exported map.

use crate::error::{self, invalid, OccError, Result};
use crate::geometry::GridGeometry;

pub mod readout;
pub mod stats;
pub mod tiled;

/// Log odds of a probability, `ln(p / (1 - p))`.
pub fn logit(p: f64) -> f64 {
    (p / (1.0 - p)).ln()
}

/// Probability of log odds, `1 - 1 / (1 + exp(l))`, written so that it is
/// exact to rounding for any finite `l` (no `inf / inf` for large `|l|`).
pub fn probability(l: f64) -> f64 {
    if l >= 0.0 {
        1.0 / (1.0 + (-l).exp())
    } else {
        let e = l.exp();
        e / (1.0 + e)
    }
}

/// Binary entropy of a probability, in bits. `H_b(0) = H_b(1) = 0`.
pub fn binary_entropy_bits(p: f64) -> f64 {
    let term = |q: f64| if q > 0.0 { -q * q.log2() } else { 0.0 };
    term(p) + term(1.0 - p)
}

/// Settings of a log-odds map: its prior and its saturation.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FilterSettings {
    /// Prior probability of occupancy of every cell, `p0`.
    pub prior: f64,
    /// Saturation `|l| <= clamp`, in log odds. Keeps every cell revisable.
    pub clamp: f64,
}

impl Default for FilterSettings {
    fn default() -> Self {
        Self {
            prior: 0.5,
            clamp: 12.0,
        }
    }
}

impl FilterSettings {
    pub fn validate(&self) -> Result<()> {
        error::open_probability("prior", self.prior)?;
        error::positive("clamp", self.clamp)?;
        // Cells are stored as f32. A clamp past f32's range would be
        // infinite there (and an infinite cell turns into NaN at the next
        // update of the opposite sign); one below it rounds to a clamp of 0.
        let stored = self.clamp as f32;
        if !(stored.is_finite() && stored > 0.0) {
            return Err(invalid(
                "clamp",
                error::show(self.clamp),
                "a saturation that f32 cells can hold, from 1.5e-45 to 3.4e38 log odds",
            ));
        }
        let l0 = logit(self.prior);
        if l0.abs() > self.clamp {
            return Err(invalid(
                "clamp",
                error::show(self.clamp),
                "at least |l0|, the prior's log odds (or the prior itself would be clamped)",
            ));
        }
        Ok(())
    }
}

/// The cells of a [`LogOddsGrid`], borrowed for a run of updates.
pub struct CellsMut<'a> {
    log_odds: &'a mut [f32],
    updates: &'a mut [u32],
    clamp: f32,
}

impl CellsMut<'_> {
    /// [`LogOddsGrid::apply`].
    #[inline(always)]
    pub fn apply(&mut self, i: usize, evidence: f32) {
        // Comparisons rather than f32::clamp, which re-checks its bounds
        // on every call (the clamp is positive by construction).
        let c = self.clamp;
        let l = &mut self.log_odds[i];
        let v = *l + evidence;
        *l = if v > c {
            c
        } else if v < -c {
            -c
        } else {
            v
        };
        self.updates[i] += 1;
    }

    /// [`LogOddsGrid::apply`] for evidence known to be `>= 0`: only the
    /// upper clamp can bind (the log odds are within the clamp already).
    #[inline(always)]
    pub fn raise(&mut self, i: usize, evidence: f32) {
        debug_assert!(evidence >= 0.0);
        let c = self.clamp;
        let l = &mut self.log_odds[i];
        let v = *l + evidence;
        *l = if v > c { c } else { v };
        self.updates[i] += 1;
    }

    /// [`LogOddsGrid::apply`] for evidence known to be `<= 0`: only the
    /// lower clamp can bind.
    #[inline(always)]
    pub fn lower(&mut self, i: usize, evidence: f32) {
        debug_assert!(evidence <= 0.0);
        let c = -self.clamp;
        let l = &mut self.log_odds[i];
        let v = *l + evidence;
        *l = if v < c { c } else { v };
        self.updates[i] += 1;
    }
}

/// The occupancy grid map: log odds per cell, and how often each cell was
/// updated (for the reader's hover readout).
#[derive(Debug, Clone, PartialEq)]
pub struct LogOddsGrid {
    geometry: GridGeometry,
    log_odds: Vec<f32>,
    updates: Vec<u32>,
    l0: f32,
    clamp: f32,
}

impl LogOddsGrid {
    /// A fresh map: every cell at the prior's log odds `l0`.
    pub fn new(geometry: GridGeometry, settings: FilterSettings) -> Result<Self> {
        settings.validate()?;
        let l0 = logit(settings.prior) as f32;
        Ok(Self {
            geometry,
            log_odds: vec![l0; geometry.len()],
            updates: vec![0; geometry.len()],
            l0,
            clamp: settings.clamp as f32,
        })
    }

    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    /// The prior's log odds.
    pub fn l0(&self) -> f32 {
        self.l0
    }
    pub fn clamp(&self) -> f32 {
        self.clamp
    }
    /// Changes the saturation. Cells beyond the new clamp are pulled in, as
    /// the next update would do anyway.
    pub fn set_clamp(&mut self, clamp: f64) -> Result<()> {
        FilterSettings {
            prior: probability(self.l0 as f64),
            clamp,
        }
        .validate()?;
        self.clamp = clamp as f32;
        let c = self.clamp;
        for l in &mut self.log_odds {
            *l = l.clamp(-c, c);
        }
        Ok(())
    }

    /// Log odds of every cell, row-major from the bottom row.
    pub fn log_odds(&self) -> &[f32] {
        &self.log_odds
    }
    /// How many updates each cell has received.
    pub fn update_counts(&self) -> &[u32] {
        &self.updates
    }
    pub fn probability_at(&self, i: usize) -> f64 {
        probability(self.log_odds[i] as f64)
    }
    /// True when the cell holds exactly the prior: the third state, neither
    /// free nor occupied.
    pub fn is_unknown(&self, i: usize) -> bool {
        self.log_odds[i] == self.l0
    }

    /// One step of the cell's binary Bayes filter (Table 9.1, line 4):
    /// `l <- clamp(l + evidence)`, where `evidence` is the inverse model's
    /// log odds already net of its `l0`. The caller has validated `evidence`.
    #[inline(always)]
    pub fn apply(&mut self, i: usize, evidence: f32) {
        self.cells_mut().apply(i, evidence);
    }

    /// The cells, for a caller that updates many of them in a row.
    pub fn cells_mut(&mut self) -> CellsMut<'_> {
        let n = self.log_odds.len();
        CellsMut {
            log_odds: &mut self.log_odds,
            // The same length as the log odds, and the compiler sees it: a
            // cell's index is then checked once for both.
            updates: &mut self.updates[..n],
            clamp: self.clamp,
        }
    }

    /// Puts every cell back to the prior.
    pub fn reset(&mut self) {
        self.log_odds.fill(self.l0);
        self.updates.fill(0);
    }

    /// Entropy of the map, `sum_i H_b(p_i)`, in bits. A fresh map with
    /// `p0 = 0.5` holds exactly one bit per cell.
    pub fn entropy_bits(&self) -> f64 {
        self.log_odds
            .iter()
            .map(|&l| binary_entropy_bits(probability(l as f64)))
            .sum()
    }

    /// Brier score `mean_i (p_i - m_i)^2` against a ground-truth binary map
    /// (`true` = occupied), over every cell or over the cells listed in
    /// `region`.
    pub fn brier_score(&self, truth: &[bool], region: Option<&[usize]>) -> Result<f64> {
        if truth.len() != self.log_odds.len() {
            return Err(OccError::LengthMismatch {
                field: "truth".into(),
                expected: self.log_odds.len(),
                found: truth.len(),
            });
        }
        let sq = |i: usize| {
            let m = if truth[i] { 1.0 } else { 0.0 };
            (self.probability_at(i) - m).powi(2)
        };
        match region {
            None => Ok((0..truth.len()).map(sq).sum::<f64>() / truth.len() as f64),
            Some(cells) => {
                if cells.is_empty() {
                    return Err(invalid("region", "[]", "at least one cell"));
                }
                if let Some(&bad) = cells.iter().find(|&&i| i >= truth.len()) {
                    return Err(invalid("region", bad, "cell indices inside the map"));
                }
                Ok(cells.iter().map(|&i| sq(i)).sum::<f64>() / cells.len() as f64)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn probability_is_stable_for_extreme_log_odds() {
        assert_eq!(probability(800.0), 1.0);
        assert_eq!(probability(-800.0), 0.0);
        assert_abs_diff_eq!(probability(logit(0.7)), 0.7, epsilon = 1e-12);
    }

    #[test]
    fn binary_entropy_is_one_bit_at_one_half_and_zero_at_certainty() {
        assert_eq!(binary_entropy_bits(0.5), 1.0);
        assert_eq!(binary_entropy_bits(0.0), 0.0);
        assert_eq!(binary_entropy_bits(1.0), 0.0);
    }
}
