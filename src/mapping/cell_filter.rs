//! One cell's binary Bayes filter, step by step: the chapter's worked
//! example and its lesson on the prior.
//!
//! Table 9.1, line 4, for a single cell: `l <- l + inverse - l0`. The
//! inverse model's answer is a *posterior*, so the prior `l0` is already in
//! it; the update removes it once, or it would be counted once per reading
//! and the cell would drift toward the prior's side with every scan.

use crate::error::{self, invalid, Result};
use crate::grid::{logit, probability};

/// The most readings one run of the filter takes. The filter is a lesson
/// read row by row: a few dozen readings tell it, and ten thousand is far
/// past what anyone clicks. Every reading becomes a row of 32 bytes in the
/// answer, so without a bound a page could ask for gigabytes.
pub const MAX_FILTER_READINGS: usize = 10_000;

/// Refuses a run of `len` readings before anything is allocated for them:
/// callers holding readings in another form (a JavaScript array) check the
/// length before copying.
pub fn check_readings(len: usize) -> Result<()> {
    if len > MAX_FILTER_READINGS {
        return Err(invalid(
            "readings",
            format!("{len} readings"),
            "at most 10000 readings",
        ));
    }
    Ok(())
}

/// The inverse model and prior of a single-cell filter, as probabilities.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CellFilterParams {
    /// `p(m | z)` after an "occupied" reading.
    pub p_occ: f64,
    /// `p(m | z)` after a "free" reading.
    pub p_free: f64,
    /// The prior `p(m)`.
    pub prior: f64,
    /// Saturation `|l| <= clamp`; `f64::INFINITY` for none (the drift of
    /// a forgotten prior, which a clamp would cut short, in full).
    pub clamp: f64,
}

impl CellFilterParams {
    /// The chapter's worked example: an inverse model of 0.7 / 0.3 and a
    /// prior of 0.5.
    pub const WORKED_EXAMPLE: Self = Self {
        p_occ: 0.7,
        p_free: 0.3,
        prior: 0.5,
        clamp: Self::CLAMP,
    };

    /// The lesson on the prior: a prior of 0.2 and an inverse model whose
    /// two answers sit symmetrically around it in log odds (logit 0.37 and
    /// logit 0.10 are about l0 + 0.85 and l0 - 0.85), so that alternating
    /// readings keep the cell near l0 until the update forgets to remove it.
    pub const L0_LESSON: Self = Self {
        p_occ: 0.37,
        p_free: 0.1,
        prior: 0.2,
        clamp: Self::CLAMP,
    };

    /// The widget's saturation: far enough out that the lesson's drift and
    /// a long run of agreeing readings both show, near enough that a few
    /// contradicting readings still move the cell.
    pub const CLAMP: f64 = 12.0;

    pub fn validate(&self) -> Result<()> {
        error::open_probability("p_occ", self.p_occ)?;
        error::open_probability("p_free", self.p_free)?;
        error::open_probability("prior", self.prior)?;
        // NaN compares false: refused with zero and the negatives.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(self.clamp > 0.0) {
            return Err(invalid(
                "clamp",
                error::show(self.clamp),
                "a number greater than 0, or infinity for no clamp",
            ));
        }
        Ok(())
    }
}

/// A preset of the widget: the model, the readings (1 occupied, 0 free)
/// and whether the update subtracts the prior.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CellFilterPreset {
    pub p_occ: f64,
    pub p_free: f64,
    pub prior: f64,
    pub clamp: f64,
    pub readings: &'static [u8],
    pub subtract_prior: bool,
}

impl CellFilterPreset {
    /// The chapter's worked example: occupied, occupied, free.
    pub const WORKED_EXAMPLE: Self = Self::of(CellFilterParams::WORKED_EXAMPLE, &[1, 1, 0], true);
    /// The lesson on the prior: alternating readings, without subtracting l0.
    pub const L0_LESSON: Self = Self::of(
        CellFilterParams::L0_LESSON,
        &[1, 0, 1, 0, 1, 0, 1, 0],
        false,
    );

    const fn of(p: CellFilterParams, readings: &'static [u8], subtract_prior: bool) -> Self {
        Self {
            p_occ: p.p_occ,
            p_free: p.p_free,
            prior: p.prior,
            clamp: p.clamp,
            readings,
            subtract_prior,
        }
    }

    pub fn params(&self) -> CellFilterParams {
        CellFilterParams {
            p_occ: self.p_occ,
            p_free: self.p_free,
            prior: self.prior,
            clamp: self.clamp,
        }
    }
}

/// One row of the running table.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CellStep {
    /// 1-based step number.
    pub step: usize,
    /// True for an "occupied" reading.
    pub occupied: bool,
    /// Log odds after the reading.
    pub l: f64,
    /// Probability after the reading.
    pub p: f64,
}

/// The log odds of the model's two answers and of the prior.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CellLogOdds {
    pub l_occ: f64,
    pub l_free: f64,
    pub l0: f64,
}

pub fn log_odds_of(params: &CellFilterParams) -> Result<CellLogOdds> {
    params.validate()?;
    Ok(CellLogOdds {
        l_occ: logit(params.p_occ),
        l_free: logit(params.p_free),
        l0: logit(params.prior),
    })
}

/// Runs the filter over `readings` (true = occupied), starting from the
/// prior. With `subtract_prior = false` the update forgets `- l0`: the
/// mistake whose drift the widget shows.
pub fn run(
    params: &CellFilterParams,
    readings: &[bool],
    subtract_prior: bool,
) -> Result<Vec<CellStep>> {
    check_readings(readings.len())?;
    let lo = log_odds_of(params)?;
    let removed = if subtract_prior { lo.l0 } else { 0.0 };
    let mut l = lo.l0;
    Ok(readings
        .iter()
        .enumerate()
        .map(|(i, &occupied)| {
            let inverse = if occupied { lo.l_occ } else { lo.l_free };
            l = (l + inverse - removed).clamp(-params.clamp, params.clamp);
            CellStep {
                step: i + 1,
                occupied,
                l,
                p: probability(l),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_more_readings_than_the_budget_naming_the_count() {
        let p = CellFilterParams::WORKED_EXAMPLE;
        assert_eq!(
            run(&p, &vec![true; MAX_FILTER_READINGS], true)
                .unwrap()
                .len(),
            MAX_FILTER_READINGS
        );
        let e = run(&p, &vec![false; MAX_FILTER_READINGS + 1], true)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("readings") && e.contains("10001 readings") && e.contains("at most 10000"),
            "{e}"
        );
    }

    #[test]
    fn rejects_certain_probabilities_and_zero_clamp() {
        let bad = CellFilterParams {
            p_occ: 1.0,
            ..CellFilterParams::WORKED_EXAMPLE
        };
        assert!(run(&bad, &[true], true)
            .unwrap_err()
            .to_string()
            .contains("p_occ"));
        let bad = CellFilterParams {
            clamp: 0.0,
            ..CellFilterParams::WORKED_EXAMPLE
        };
        assert!(run(&bad, &[true], true)
            .unwrap_err()
            .to_string()
            .contains("clamp"));
    }

    #[test]
    fn the_l0_lesson_stays_near_the_prior_only_when_the_update_removes_it() {
        let lesson = CellFilterPreset::L0_LESSON;
        let readings: Vec<bool> = lesson.readings.iter().map(|&r| r == 1).collect();
        let l0 = logit(lesson.prior);
        let kept = run(&lesson.params(), &readings, true).unwrap();
        assert!((kept.last().unwrap().l - l0).abs() < 0.5, "{kept:?}");
        // The preset itself forgets: every reading adds l0 once more.
        assert!(!lesson.subtract_prior);
        let drifted = run(&lesson.params(), &readings, lesson.subtract_prior).unwrap();
        assert!(drifted.last().unwrap().l < 5.0 * l0, "{drifted:?}");
    }

    #[test]
    fn the_worked_example_preset_is_the_worked_example() {
        let w = CellFilterPreset::WORKED_EXAMPLE;
        assert_eq!(w.params(), CellFilterParams::WORKED_EXAMPLE);
        assert_eq!(w.readings, &[1, 1, 0]);
        assert!(w.subtract_prior);
    }
}
