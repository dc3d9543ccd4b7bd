//! Probes of an inverse model, what the workbench draws: its evidence over a
//! beam's neighbourhood (range × bearing), its posterior along the beam
//! axis, two models side by side on one colour scale, and the mean free
//! evidence in front of a reading (the learned model's skepticism of
//! max-range readings, §9.3).

use super::InverseModel;
use crate::error::{self, invalid, Result};

/// The range-by-bearing lattice over which a model is drawn: `ranges`
/// samples of the range from `min_range` to `max_range` (metres, both
/// included) and `bearings` samples of the bearing offset from
/// `-max_bearing` to `+max_bearing` (radians, both included).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct BeamLattice {
    pub min_range: f64,
    pub max_range: f64,
    pub ranges: usize,
    pub max_bearing: f64,
    pub bearings: usize,
}

impl BeamLattice {
    pub fn validate(&self) -> Result<()> {
        error::non_negative("min_range", self.min_range)?;
        error::finite("max_range", self.max_range)?;
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(self.max_range > self.min_range) {
            return Err(invalid(
                "max_range",
                self.max_range,
                "a range greater than min_range",
            ));
        }
        error::non_negative("max_bearing", self.max_bearing)?;
        if self.max_bearing > std::f64::consts::PI {
            return Err(invalid(
                "max_bearing",
                self.max_bearing,
                "a bearing of at most pi radians",
            ));
        }
        lattice_size("ranges", self.ranges)?;
        lattice_size("bearings", self.bearings)?;
        Ok(())
    }

    /// Range of column `i`, metres.
    pub fn range(&self, i: usize) -> f64 {
        lattice(self.min_range, self.max_range, i, self.ranges)
    }

    /// Bearing offset of row `j`, radians.
    pub fn bearing(&self, j: usize) -> f64 {
        lattice(-self.max_bearing, self.max_bearing, j, self.bearings)
    }
}

/// A model's evidence (log odds, net of its `l0`) for reading `z` over a
/// beam's neighbourhood, row-major with one row per bearing (the first row
/// at `-max_bearing`): what the workbench draws as an image.
pub fn evidence_field<M: InverseModel + ?Sized>(
    model: &M,
    z: f64,
    lattice: &BeamLattice,
) -> Result<Vec<f32>> {
    error::non_negative("z", z)?;
    lattice.validate()?;
    let mut out = Vec::with_capacity(lattice.ranges * lattice.bearings);
    for j in 0..lattice.bearings {
        let psi = lattice.bearing(j);
        out.extend((0..lattice.ranges).map(|i| model.evidence(lattice.range(i), psi, z)));
    }
    Ok(out)
}

/// A model's posterior log odds along the beam axis for reading `z`
/// (evidence plus the model's `l0`: the inverse model's own answer before
/// the prior is removed), at the lattice's ranges: what the workbench draws
/// as a curve beside the `l0` line. Cells the model says nothing about sit
/// on `l0`.
pub fn axis_log_odds<M: InverseModel + ?Sized>(
    model: &M,
    z: f64,
    lattice: &BeamLattice,
) -> Result<Vec<f32>> {
    error::non_negative("z", z)?;
    lattice.validate()?;
    let l0 = model.l0();
    Ok((0..lattice.ranges)
        .map(|i| model.evidence(lattice.range(i), 0.0, z) + l0)
        .collect())
}

/// Two models for the same reading over the same lattice, on one colour
/// scale: what the workbench draws side by side.
#[derive(Debug, Clone, PartialEq)]
pub struct SideBySide {
    /// Evidence images ([`evidence_field`]) of the first and second model.
    pub fields: [Vec<f32>; 2],
    /// Log odds along the axis ([`axis_log_odds`]) of both.
    pub axes: [Vec<f32>; 2],
    /// The largest `|evidence|` over both images: one shared log-odds scale,
    /// so that equal colours mean equal evidence in both.
    pub scale: f32,
}

/// Evaluates `a` and `b` for reading `z` over `lattice`.
pub fn side_by_side<A: InverseModel + ?Sized, B: InverseModel + ?Sized>(
    a: &A,
    b: &B,
    z: f64,
    lattice: &BeamLattice,
) -> Result<SideBySide> {
    let fields = [
        evidence_field(a, z, lattice)?,
        evidence_field(b, z, lattice)?,
    ];
    let axes = [axis_log_odds(a, z, lattice)?, axis_log_odds(b, z, lattice)?];
    let scale = fields.iter().flatten().fold(0.0f32, |m, &e| m.max(e.abs()));
    Ok(SideBySide {
        fields,
        axes,
        scale,
    })
}

/// Mean evidence (log odds, net of `l0`) on the beam axis over the free
/// space in front of reading `z`: ranges from 0 to `z - margin` metres,
/// sampled every centimetre (a no-return: up to `z_max - margin`). The
/// chapter compares it for a short and for a max-range reading.
pub fn mean_free_evidence<M: InverseModel + ?Sized>(model: &M, z: f64, margin: f64) -> Result<f64> {
    error::non_negative("z", z)?;
    error::non_negative("margin", margin)?;
    let end = z.min(model.z_max()) - margin;
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
    if !(end > 0.0) {
        return Err(invalid(
            "z",
            z,
            "a reading longer than the margin in front of it",
        ));
    }
    // One sample per centimetre, at most 100,000 (a 1 km reading).
    let n = (end / 0.01).ceil().clamp(1.0, 100_000.0) as usize;
    let sum: f64 = (0..n)
        .map(|i| model.evidence((i as f64 + 0.5) * end / n as f64, 0.0, z) as f64)
        .sum();
    Ok(sum / n as f64)
}

fn lattice_size(field: &str, n: usize) -> Result<()> {
    if (2..=4096).contains(&n) {
        Ok(())
    } else {
        Err(invalid(field, n, "between 2 and 4096 samples"))
    }
}

/// Sample `i` of `n` evenly spaced from `a` to `b` inclusive.
#[inline]
fn lattice(a: f64, b: f64, i: usize, n: usize) -> f64 {
    a + (b - a) * i as f64 / (n - 1) as f64
}
