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
pub const MAX_READINGS: usize = 10_000;

/// Refuses a run of `len` readings before anything is allocated for them:
/// callers holding readings in another form (a JavaScript array) check the
/// length before copying.
pub fn check_readings(len: usize) -> Result<()> {
    if len > MAX_READINGS {
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
    /// Saturation `|l| <= clamp`.
    pub clamp: f64,
}

impl CellFilterParams {
    /// The chapter's worked example: an inverse model of 0.7 / 0.3 and a
    /// prior of 0.5.
    pub const WORKED_EXAMPLE: Self = Self {
        p_occ: 0.7,
        p_free: 0.3,
        prior: 0.5,
        clamp: 12.0,
    };

    pub fn validate(&self) -> Result<()> {
        error::open_probability("p_occ", self.p_occ)?;
        error::open_probability("p_free", self.p_free)?;
        error::open_probability("prior", self.prior)?;
        error::positive("clamp", self.clamp)?;
        Ok(())
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
            run(&p, &vec![true; MAX_READINGS], true).unwrap().len(),
            MAX_READINGS
        );
        let e = run(&p, &vec![false; MAX_READINGS + 1], true)
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
}
