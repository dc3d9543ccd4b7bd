//! Exact joint posteriors over a few cells: the independence trap (docs/ARCHITECTURE.md, "The independence trap").
//!
//! The occupancy grid of Table 9.1 keeps one binary filter per cell, so its
//! belief is the product of marginals, `p(m) = prod_i p(m_i)`. A wide cone
//! couples the cells inside it: one short reading says "something in here is
//! occupied", not "each of these cells is". This module computes what the
//! factored map cannot hold. For `k <= 16` chosen cells inside one sonar cone
//! (every other cell free) it enumerates all `2^k` configurations, weighs each
//! by its prior times the forward model's likelihood of the readings
//! (Table 6.1, [`crate::sensors::beam_model::BeamModel`]), and normalises. It sits beside
//! the mappers, not in them: the doorway-trap widget and the numbers script
//! ask it for the table, the marginals, and the true versus factored
//! probability of any configuration.
//!
//! A configuration is an integer whose bit `j` is cell `j`'s occupancy: the
//! first cell is the lowest bit, so two cells give `00, 10, 01, 11` in the
//! order `(m_A m_B)` = index 0, 1, 2, 3.

use crate::error::{self, invalid, OccError, Result};
use crate::grid::binary_entropy_bits;
use crate::sensors::beam_model::{BeamModel, BeamModelParams};

/// The most cells a query may enumerate: `2^16 = 65,536` configurations.
pub const MAX_QUERY_CELLS: usize = 16;

/// The most readings a query may hold (all from the same cone and pose).
pub const MAX_QUERY_READINGS: usize = 4096;

/// One chosen cell, as a point in the sensor's frame: range from the sensor
/// (metres) and bearing from the cone's axis (degrees, counter-clockwise).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConeCell {
    pub range: f64,
    pub bearing_deg: f64,
}

/// A joint-posterior question, spelled as the numbers script's
/// `--joint FILE.json` takes it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointQuery {
    /// Prior occupancy of every chosen cell, i.i.d., strictly in (0, 1).
    pub prior: f64,
    /// Full opening angle of the cone, degrees.
    pub beta_deg: f64,
    /// The chosen cells, 1 to 16 of them, all inside the cone.
    pub cells: Vec<ConeCell>,
    /// Range readings (metres) taken along the cone from the same pose,
    /// independent given the map. A reading at or beyond `model.z_max` is a
    /// no-return.
    pub readings: Vec<f64>,
    /// The forward model; a missing object or missing fields take the
    /// chapter's reference setting.
    #[serde(default)]
    pub model: BeamModelParams,
}

impl JointQuery {
    /// The chapter's case (docs/ARCHITECTURE.md, "The independence trap"): cells A and B side by side at 2 m inside
    /// one 22-degree sonar cone, prior 0.5, one reading of 2.0 m, the
    /// reference forward model.
    pub fn chapter_two_cells() -> Self {
        Self {
            prior: 0.5,
            beta_deg: 22.0,
            cells: vec![
                ConeCell {
                    range: 2.0,
                    bearing_deg: -3.0,
                },
                ConeCell {
                    range: 2.0,
                    bearing_deg: 3.0,
                },
            ],
            readings: vec![2.0],
            model: BeamModelParams::CHAPTER,
        }
    }

    /// Checks everything the enumeration relies on, naming the field.
    pub fn validate(&self) -> Result<BeamModel> {
        error::open_probability("prior", self.prior)?;
        error::positive("beta_deg", self.beta_deg)?;
        if self.beta_deg > 360.0 {
            return Err(invalid(
                "beta_deg",
                self.beta_deg,
                "an opening angle of at most 360 degrees",
            ));
        }
        if self.cells.is_empty() || self.cells.len() > MAX_QUERY_CELLS {
            return Err(invalid(
                "cells",
                format!("{} cells", self.cells.len()),
                "between 1 and 16 cells",
            ));
        }
        let half = 0.5 * self.beta_deg;
        for (i, c) in self.cells.iter().enumerate() {
            error::non_negative(&format!("cells[{i}].range"), c.range)?;
            error::finite(&format!("cells[{i}].bearing_deg"), c.bearing_deg)?;
            // A cell outside the cone would never be seen: the question is
            // about cells one reading couples, so say so instead of
            // returning its prior unchanged.
            if c.bearing_deg.abs() > half + 1e-9 {
                return Err(invalid(
                    &format!("cells[{i}].bearing_deg"),
                    c.bearing_deg,
                    "a bearing inside the cone, |bearing_deg| <= beta_deg / 2",
                ));
            }
        }
        if self.readings.is_empty() || self.readings.len() > MAX_QUERY_READINGS {
            return Err(invalid(
                "readings",
                format!("{} readings", self.readings.len()),
                "between 1 and 4096 readings",
            ));
        }
        for (i, &z) in self.readings.iter().enumerate() {
            error::non_negative(&format!("readings[{i}]"), z)?;
        }
        BeamModel::new(self.model)
    }
}

/// One row of the joint table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Configuration {
    /// The configuration's index: bit `j` set when cell `j` is occupied.
    pub index: u32,
    /// Occupancy of each cell, first cell first.
    pub occupied: Vec<bool>,
    /// Expected range `z*` of the cone in this configuration: the range of
    /// the nearest occupied cell, or `z_max` when all are free (metres).
    pub expected_range: f64,
    /// `p(z_1..z_n | m)`, the product of the forward densities (a density
    /// in 1/metres^n; a no-return contributes its point mass).
    pub likelihood: f64,
    /// `p(m | z)`, exact.
    pub joint: f64,
    /// `prod_j p(m_j | z)`: what the factored map believes.
    pub factored: f64,
}

/// The exact answer to a [`JointQuery`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct JointPosterior {
    /// `p(m | z)` for every configuration, indexed as [`Configuration::index`].
    pub joint: Vec<f64>,
    /// `p(m_j = 1 | z)` for every cell.
    pub marginals: Vec<f64>,
    /// The configurations' expected ranges (metres), same indexing.
    pub expected_ranges: Vec<f64>,
    /// The readings' likelihood per configuration, same indexing.
    pub likelihoods: Vec<f64>,
}

/// What the numbers script prints for a `--joint` query.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct JointAnswer {
    pub joint: Vec<f64>,
    pub marginals: Vec<f64>,
    /// True probability that every chosen cell is free.
    pub all_free_true: f64,
    /// The same event under the product of marginals.
    pub all_free_factored: f64,
}

/// Everything the two-cell table of the doorway-trap widget prints.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct JointReport {
    #[serde(flatten)]
    pub answer: JointAnswer,
    /// `all_free_factored / all_free_true`: how many times too likely the
    /// factored map finds "all free" (24 in the chapter's case).
    pub all_free_ratio: f64,
    /// Mutual information of the first two cells, bits (0 with one cell).
    pub mutual_information_bits: f64,
    /// Entropy of the exact joint posterior of the chosen cells, bits.
    pub joint_entropy_bits: f64,
    /// The entropy a factored map states for the same cells: the sum of
    /// their own binary entropies, bits. It bounds the joint's from above.
    pub marginal_entropy_sum_bits: f64,
    /// The gap between the two, `marginal_entropy_sum_bits -
    /// joint_entropy_bits`, bits: the information the cells share (with
    /// two cells, their mutual information), never negative. An explorer
    /// that scores information gain on the factored map counts it as
    /// uncertainty left to remove.
    pub shared_information_bits: f64,
    pub table: Vec<Configuration>,
}

impl JointPosterior {
    /// Enumerates every configuration of the query's cells.
    ///
    /// Weights are summed in log space (log prior plus the log densities of
    /// all readings) and normalised with the largest weight factored out, so
    /// hundreds of readings neither underflow nor overflow.
    pub fn compute(query: &JointQuery) -> Result<Self> {
        let model = query.validate()?;
        let k = query.cells.len();
        let n = 1usize << k;
        let z_max = model.params().z_max;
        let (log_p, log_q) = (query.prior.ln(), (1.0 - query.prior).ln());

        // Cells sorted by range, so that a configuration's expected range is
        // the range of its first occupied cell in this order.
        let mut by_range: Vec<usize> = (0..k).collect();
        crate::geometry::order::sort_stable_by_key(&mut by_range, |&cell| query.cells[cell].range);

        // A configuration's expected range is one of k + 1 values (a cell's
        // range, or z_max): the readings' log likelihood is tabulated once
        // per candidate, so the enumeration costs 2^k lookups, not
        // 2^k x readings densities.
        let log_lik_at = |z_star: f64| -> f64 {
            query
                .readings
                .iter()
                .map(|&z| model.density(z, z_star).ln())
                .sum()
        };
        let cell_z: Vec<f64> = query.cells.iter().map(|c| c.range.min(z_max)).collect();
        let cell_log_lik: Vec<f64> = cell_z.iter().map(|&r| log_lik_at(r)).collect();
        let empty_log_lik = log_lik_at(z_max);

        let mut expected_ranges = Vec::with_capacity(n);
        let mut likelihoods = Vec::with_capacity(n);
        let mut log_weights = Vec::with_capacity(n);
        for config in 0..n {
            let (z_star, log_lik) = by_range
                .iter()
                .find(|&&j| config & (1 << j) != 0)
                .map_or((z_max, empty_log_lik), |&j| (cell_z[j], cell_log_lik[j]));
            let ones = config.count_ones() as f64;
            expected_ranges.push(z_star);
            likelihoods.push(log_lik.exp());
            log_weights.push(ones * log_p + (k as f64 - ones) * log_q + log_lik);
        }

        let top = log_weights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        if top == f64::NEG_INFINITY {
            // Possible only with weights of zero on the uniform and short
            // components: every configuration then calls the readings
            // impossible and there is nothing to normalise.
            return Err(invalid(
                "readings",
                format!("{:?}", query.readings),
                "readings with a non-zero likelihood under at least one configuration",
            ));
        }
        let mut joint: Vec<f64> = log_weights.iter().map(|&w| (w - top).exp()).collect();
        let total: f64 = joint.iter().sum();
        for p in &mut joint {
            *p /= total;
        }
        let marginals = (0..k)
            .map(|j| {
                joint
                    .iter()
                    .enumerate()
                    .filter(|(c, _)| c & (1 << j) != 0)
                    .map(|(_, &p)| p)
                    .sum()
            })
            .collect();
        Ok(Self {
            joint,
            marginals,
            expected_ranges,
            likelihoods,
        })
    }

    /// Number of chosen cells.
    pub fn cells(&self) -> usize {
        self.marginals.len()
    }

    /// True and factored probability of an event that fixes some cells and
    /// leaves the others open: `pattern[j]` is `Some(occupied)` or `None`.
    /// The true probability sums the joint over every matching
    /// configuration; the factored one multiplies the fixed cells' marginals.
    pub fn event(&self, pattern: &[Option<bool>]) -> Result<(f64, f64)> {
        if pattern.len() != self.cells() {
            return Err(OccError::LengthMismatch {
                field: "pattern".into(),
                expected: self.cells(),
                found: pattern.len(),
            });
        }
        let matches = |config: usize| {
            pattern.iter().enumerate().all(|(j, want)| match want {
                Some(occ) => (config & (1 << j) != 0) == *occ,
                None => true,
            })
        };
        let truth = self
            .joint
            .iter()
            .enumerate()
            .filter(|(c, _)| matches(*c))
            .map(|(_, &p)| p)
            .sum();
        let factored = pattern
            .iter()
            .zip(&self.marginals)
            .map(|(want, &m)| match want {
                Some(true) => m,
                Some(false) => 1.0 - m,
                None => 1.0,
            })
            .product();
        Ok((truth, factored))
    }

    /// True and factored probability of one full configuration (by index).
    pub fn configuration(&self, index: usize) -> Result<(f64, f64)> {
        if index >= self.joint.len() {
            return Err(invalid(
                "configuration",
                index,
                "an index below 2^(number of cells)",
            ));
        }
        let pattern: Vec<Option<bool>> = (0..self.cells())
            .map(|j| Some(index & (1 << j) != 0))
            .collect();
        self.event(&pattern)
    }

    /// "Every chosen cell free": the event the factored map gets most wrong
    /// next to a short reading.
    pub fn all_free(&self) -> (f64, f64) {
        let factored = self.marginals.iter().map(|m| 1.0 - m).product();
        (self.joint[0], factored)
    }

    /// Every configuration as a table row.
    pub fn table(&self) -> Vec<Configuration> {
        let k = self.cells();
        (0..self.joint.len())
            .map(|c| {
                let occupied: Vec<bool> = (0..k).map(|j| c & (1 << j) != 0).collect();
                let factored = occupied
                    .iter()
                    .zip(&self.marginals)
                    .map(|(&o, &m)| if o { m } else { 1.0 - m })
                    .product();
                Configuration {
                    index: c as u32,
                    occupied,
                    expected_range: self.expected_ranges[c],
                    likelihood: self.likelihoods[c],
                    joint: self.joint[c],
                    factored,
                }
            })
            .collect()
    }

    /// The summary the numbers script prints.
    pub fn answer(&self) -> JointAnswer {
        let (all_free_true, all_free_factored) = self.all_free();
        JointAnswer {
            joint: self.joint.clone(),
            marginals: self.marginals.clone(),
            all_free_true,
            all_free_factored,
        }
    }

    /// The answer, the configuration table, the first two cells' mutual
    /// information and the entropies of the joint and of the factored map,
    /// for the widget.
    pub fn report(&self) -> JointReport {
        let answer = self.answer();
        JointReport {
            all_free_ratio: answer.all_free_factored / answer.all_free_true,
            mutual_information_bits: self.pair_mutual_information_bits(0, 1).unwrap_or(0.0),
            joint_entropy_bits: self.joint_entropy_bits(),
            marginal_entropy_sum_bits: self.marginal_entropy_sum_bits(),
            shared_information_bits: self.shared_information_bits(),
            table: self.table(),
            answer,
        }
    }

    /// Entropy of the exact joint posterior, `-sum_m p(m | z) log2 p(m | z)`
    /// over every configuration, bits.
    pub fn joint_entropy_bits(&self) -> f64 {
        self.joint
            .iter()
            .filter(|&&p| p > 0.0)
            .map(|&p| -p * p.log2())
            .sum()
    }

    /// The entropy of the same cells in a factored map, which keeps one
    /// marginal per cell: `sum_j H_b(p(m_j | z))`, bits.
    pub fn marginal_entropy_sum_bits(&self) -> f64 {
        self.marginals.iter().map(|&m| binary_entropy_bits(m)).sum()
    }

    /// How far the factored map's entropy overstates the joint's, bits:
    /// the divergence of the joint from the product of its marginals,
    /// `sum_m p(m | z) log2(p(m | z) / prod_j p(m_j | z))`, which equals
    /// `marginal_entropy_sum_bits - joint_entropy_bits` and, as a
    /// divergence, is never negative. Summed term by term rather than
    /// subtracted, so that a gap of a thousandth of a bit is not lost to
    /// the rounding of two sums near 2 bits.
    pub fn shared_information_bits(&self) -> f64 {
        let k = self.cells();
        // Each cell's "free" marginal summed from the joint too, not as
        // 1 - p: a configuration of probability 1e-20 keeps a non-zero
        // factored probability beside a marginal that rounds to 1.
        let free: Vec<f64> = (0..k)
            .map(|j| {
                self.joint
                    .iter()
                    .enumerate()
                    .filter(|(c, _)| c & (1 << j) == 0)
                    .map(|(_, &p)| p)
                    .sum()
            })
            .collect();
        let gap: f64 = self
            .joint
            .iter()
            .enumerate()
            .map(|(c, &p)| {
                let factored: f64 = (0..k)
                    .map(|j| {
                        if c & (1 << j) != 0 {
                            self.marginals[j]
                        } else {
                            free[j]
                        }
                    })
                    .product();
                if p > 0.0 && factored > 0.0 {
                    p * (p / factored).log2()
                } else {
                    0.0
                }
            })
            .sum();
        gap.max(0.0)
    }

    /// Mutual information between cells `a` and `b`, in bits: zero when
    /// the factored map loses nothing about the pair, and what a reader can
    /// watch rise as the cells move side by side in one cone.
    pub fn pair_mutual_information_bits(&self, a: usize, b: usize) -> Result<f64> {
        for (field, j) in [("a", a), ("b", b)] {
            if j >= self.cells() {
                return Err(invalid(field, j, "the index of a chosen cell"));
            }
        }
        if a == b {
            return Err(invalid("b", b, "a cell other than a"));
        }
        let mut pair = [[0.0f64; 2]; 2];
        for (c, &p) in self.joint.iter().enumerate() {
            pair[(c >> a) & 1][(c >> b) & 1] += p;
        }
        let (ma, mb) = (self.marginals[a], self.marginals[b]);
        let mut mi = 0.0;
        for (ia, row) in pair.iter().enumerate() {
            for (ib, &p) in row.iter().enumerate() {
                let pa = if ia == 1 { ma } else { 1.0 - ma };
                let pb = if ib == 1 { mb } else { 1.0 - mb };
                if p > 0.0 && pa > 0.0 && pb > 0.0 {
                    mi += p * (p / (pa * pb)).log2();
                }
            }
        }
        Ok(mi.max(0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_cell_with_a_matching_reading_is_bayes_rule() {
        let q = JointQuery {
            cells: vec![ConeCell {
                range: 2.0,
                bearing_deg: 0.0,
            }],
            ..JointQuery::chapter_two_cells()
        };
        let post = JointPosterior::compute(&q).unwrap();
        let m = BeamModel::chapter();
        let (hit, miss) = (m.density(2.0, 2.0), m.density(2.0, 3.0));
        assert!((post.marginals[0] - hit / (hit + miss)).abs() < 1e-12);
    }

    #[test]
    fn event_with_open_cells_marginalises() {
        let post = JointPosterior::compute(&JointQuery::chapter_two_cells()).unwrap();
        let (truth, factored) = post.event(&[Some(true), None]).unwrap();
        assert!((truth - post.marginals[0]).abs() < 1e-12);
        assert!((factored - post.marginals[0]).abs() < 1e-12);
        assert!(post.event(&[None]).is_err());
        assert!(post.configuration(4).is_err());
    }
}
