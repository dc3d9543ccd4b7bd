//! What a cell believes, and how one scan's verdict changes it: the cell
//! model, separate from where cells live ([`super::storage`]).
//!
//! The traversal decides, per scan, at most one verdict per cell: occupied
//! (a *hit*: the beam ended in it) or free (a *miss*: the beam passed
//! through), hits winning (Table 9.1 applied once per cell per scan). A
//! cell model turns a verdict into a new cell value and a cell value into
//! a probability. [`LogOdds`] is the chapter's binary Bayes filter
//! (Table 9.1: `l <- l + evidence - l0`, clamped); a model that
//! counts hits and visits, or one that steps through tables of odds,
//! implements the same trait and every consumer of a map works with it.

use super::{logit, probability};

/// A cell model: the value a cell holds and what a verdict does to it.
pub trait CellModel: Clone + std::fmt::Debug + PartialEq {
    /// What one cell holds.
    type Cell: Copy + PartialEq + std::fmt::Debug;

    /// The cell nothing has measured: the third state, neither free nor
    /// occupied.
    fn unknown(&self) -> Self::Cell;

    /// An occupied verdict. `evidence` is the scan's occupied log odds net
    /// of the prior (`> 0`); a model that does not weigh evidence ignores it.
    fn hit(&self, cell: &mut Self::Cell, evidence: f32);

    /// A free verdict; `evidence` the scan's free log odds net of the prior
    /// (`< 0`).
    fn miss(&self, cell: &mut Self::Cell, evidence: f32);

    /// A verdict of any inverse model as log odds net of the prior, of
    /// either sign (Table 9.1 with a model whose evidence varies per cell,
    /// such as the learned model of §9.3).
    fn add(&self, cell: &mut Self::Cell, evidence: f32);

    /// The cell's log odds of occupancy.
    fn log_odds(&self, cell: Self::Cell) -> f32;

    /// True while the cell holds exactly the unknown value.
    fn is_unknown(&self, cell: Self::Cell) -> bool;

    /// The cell's probability of occupancy.
    #[inline]
    fn probability(&self, cell: Self::Cell) -> f64 {
        probability(self.log_odds(cell) as f64)
    }
}

/// The chapter's cell: log odds `l = ln(p / (1 - p))`, one binary Bayes
/// filter per cell (Table 9.1), saturated at `|l| <= clamp` so that a cell
/// stays revisable (a ghost fades after as many contradicting scans as the
/// clamp allows, not as many as confirmed it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogOdds {
    /// The prior's log odds: the unknown cell.
    pub l0: f32,
    /// The saturation, `> 0`.
    pub clamp: f32,
}

impl LogOdds {
    /// From a validated prior probability and clamp.
    pub fn new(prior: f64, clamp: f64) -> Self {
        Self {
            l0: logit(prior) as f32,
            clamp: clamp as f32,
        }
    }
}

impl CellModel for LogOdds {
    type Cell = f32;

    #[inline(always)]
    fn unknown(&self) -> f32 {
        self.l0
    }

    /// (Comparisons rather than `f32::clamp`, which re-checks its bounds on
    /// every call; the evidence is positive, so only the upper clamp can
    /// bind.)
    #[inline(always)]
    fn hit(&self, l: &mut f32, evidence: f32) {
        debug_assert!(evidence >= 0.0);
        let c = self.clamp;
        let v = *l + evidence;
        *l = if v > c { c } else { v };
    }

    #[inline(always)]
    fn miss(&self, l: &mut f32, evidence: f32) {
        debug_assert!(evidence <= 0.0);
        let c = -self.clamp;
        let v = *l + evidence;
        *l = if v < c { c } else { v };
    }

    #[inline(always)]
    fn add(&self, l: &mut f32, evidence: f32) {
        let c = self.clamp;
        let v = *l + evidence;
        *l = if v > c {
            c
        } else if v < -c {
            -c
        } else {
            v
        };
    }

    #[inline(always)]
    fn log_odds(&self, l: f32) -> f32 {
        l
    }

    #[inline(always)]
    fn is_unknown(&self, l: f32) -> bool {
        l == self.l0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_odds_cell_clamps_on_the_side_its_verdict_moves() {
        let m = LogOdds::new(0.5, 2.0);
        let mut l = m.unknown();
        assert!(m.is_unknown(l));
        m.hit(&mut l, 1.5);
        m.hit(&mut l, 1.5);
        assert_eq!(l, 2.0);
        m.miss(&mut l, -5.0);
        assert_eq!(l, -2.0);
        m.add(&mut l, 0.5);
        assert_eq!(l, -1.5);
        m.add(&mut l, 9.0);
        assert_eq!(l, 2.0);
        assert!(!m.is_unknown(l));
        assert!((m.probability(l) - probability(2.0)).abs() < 1e-12);
    }
}
