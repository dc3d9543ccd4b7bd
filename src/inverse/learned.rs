//! The learned inverse sensor model of Probabilistic Robotics §9.3.
//!
//! Instead of Table 9.2's hand-set `alpha`, `beta`, `l_occ` and `l_free`,
//! the model is a logistic regression on a fixed vector of bounded features
//! of a cell's beam-frame geometry: its range `r` (metres), its bearing
//! offset `psi` from the beam axis (radians) and the beam's reading `z`
//! (metres). [`super::training`] fits the weights on triplets sampled from a
//! map prior and the forward model; this module defines the features, turns
//! the weights into an [`InverseModel`] the mappers use, and offers what the
//! workbench widget draws (fields, axis curves, the prior drift).
//!
//! The regression's score `w . phi` is already a posterior log odds (the
//! minimiser of the cross-entropy is the true `p(m | r, psi, z)` when the
//! features can express it), so the evidence handed to the map is
//! `w . phi - l0` with no sigmoid. `l0` is read off the model itself: its
//! score for a cell far beyond a short reading on the axis.
//!
//! # The features
//!
//! With `d = r - z` (metres past the reading), `u = |psi| / h` (`h` the
//! training sensor's cone half-angle) and `m` = "the reading is a no-return
//! (`z >= z_max`)":
//!
//! * `1` — the bias: the score of a cell at the rim of the perceptual
//!   field, where every angular window has fallen to zero.
//! * `(1 - m) G(d)` — "far beyond the reading", at any bearing. The model's
//!   own `l0` is the bias plus this weight: the score of a cell far beyond
//!   a short reading, read off the model. Cells there get exactly zero
//!   evidence, so a mapper may visit them without moving them.
//! * `(1 - m) a_w(u) N_k(d)`, `k = 0..=6` — seven uniform cubic B-splines
//!   in `d` with knots every 0.08 m from -0.3 m to +0.5 m (each lies wholly
//!   inside that span): the shape of the free-to-occupied transition and of
//!   the occupied band.
//! * `(1 - m) F(d) {a_w(u), a_n(u), a_w(u) z / z_max}` — the free plateau
//!   in front of the reading, under the wide and a narrower angular window
//!   (free space may be narrower than the occupied band) and scaled with the
//!   reading's length (confidence may change with range).
//! * `m a_w(u) {1, M(r), H(r)}` — a no-return has its own profile along
//!   the beam (one training reading in twenty is a dropout from a real
//!   obstacle at an unknown range): `H(r)` is a smoothstep from 1 at the
//!   sensor to 0 at 1 m, for the free space the robot stands in, `M(r)` one
//!   from 1 at 1 m to 0 at 4 m, for the room around it, and the constant
//!   for what lies farther.
//!
//! `a_w(u) = (1 - (u/1.5)^2)^2` and `a_n(u) = (1 - u^2)^2` (zero outside)
//! are smooth angular windows; `F(d)` is a cubic smoothstep that is 1 for
//! `d <= -0.3` m and 0 for `d >= 0`, `G(d)` one that is 0 up to 0.2 m and 1
//! from 0.5 m past the reading. Every feature lies in `[0, 1]` and is a
//! polynomial: no transcendental function is evaluated per feature.
//!
//! The bias and `l0` differ on purpose. Cells at the rim of the field in
//! front of a reading lie beside free space and are freer than cells behind
//! an obstacle; one shared weight for both would pull `l0` toward free and
//! make the model claim knowledge about the cells it knows least about.
//!
//! # How far a reading reaches
//!
//! The features let a real return speak about cells up to [`SPLINE_END`]
//! past the reading; how far it *does* is the model's to say. At
//! construction the model finds the depth past the reading beyond which
//! its evidence stays below [`NEGLIGIBLE`] at every bearing and every
//! range ([`LearnedInverse::band_end`]), drops what is left beyond it (at
//! most that much per scan), and reports that depth as its reach: past it
//! every cell gets exactly nothing, so a traversal need not visit it. (With
//! a prior other than its own the cells past the band do get something,
//! the prior's error, and the field then runs [`BEHIND_BAND`] further:
//! [`prior_drift`](crate::mapping::drift::prior_drift).) A model trained on thin walls stops a few decimetres
//! past the reading; one trained on deep blocks paints to the end of the
//! span. The reach is what a ray traversal walks, so it is also what a
//! scan costs.
//!
//! # Evaluating it cheaply
//!
//! Mappers call [`InverseModel::evidence`] once per cell per beam (Map
//! Weaver: 60 beams of about 40 cells per scan). The score of a real return
//! separates into `w0 + w_G G(d) + a_w(u) (T(d) + (z / z_max) w_z F(d)) +
//! a_n(u) w_n F(d)` with `T(d) = sum_k w_k N_k(d) + w_F F(d)`, and that of a
//! no-return into `w0 + a_w(u) (w_m0 + w_m1 M(r) + w_m2 H(r))`. At
//! construction `w_G (G - 1)` (so that it is exactly zero past the span,
//! scores being taken relative to `l0 = w0 + w_G`), `T` and `F` are
//! tabulated on a 5 mm lattice over the spline's span and interpolated
//! linearly (the interpolation error is below 1e-3 in log odds, far below
//! the fit's own uncertainty); in front of the span, where most cells of a
//! beam lie, every part is constant and no table is read. The angular
//! windows are two short polynomials, skipped on the axis (`psi = 0`, all
//! the ray-traversal mapper asks). One call is a handful of multiply-adds
//! and at most two table reads.

use super::InverseModel;
use crate::error::{self, invalid, Result};

/// Number of features.
pub const FEATURES: usize = 15;

/// Index of the bias.
pub const BIAS: usize = 0;
/// Index of the far-beyond feature `G`.
pub const BEYOND: usize = 1;
/// Index of the first B-spline feature.
const SPLINE0: usize = 2;
/// Number of B-spline basis functions in `d`.
const SPLINES: usize = 7;
/// Start of the spline's span in `d`, metres (in front of the reading):
/// where the free plateau `F` starts to fall.
pub const SPLINE_START: f64 = -0.3;
/// Knot spacing, metres: a little under a cell of the maps, so that a
/// band one or two cells deep can be drawn, and wide enough that 24,000
/// samples fill it. The span it gives, half a metre past the reading, is
/// a ceiling on the band, not its width: where the band ends is read off
/// the fitted model ([`LearnedInverse::band_end`]).
pub const KNOT_STEP: f64 = 0.08;
/// Where the spline's span ends, metres past the reading: from here on a
/// real return tells the model nothing (`G = 1`).
pub const SPLINE_END: f64 = SPLINE_START + (SPLINES + 3) as f64 * KNOT_STEP;
/// Where `G` starts to rise, metres past the reading.
const BEYOND_START: f64 = SPLINE_END - 0.3;
/// Feature indices of the free plateau under the wide window, the narrow
/// window, and the wide window scaled by the reading's length.
const FREE_WIDE: usize = SPLINE0 + SPLINES;
const FREE_NARROW: usize = FREE_WIDE + 1;
const FREE_RANGE: usize = FREE_WIDE + 2;
/// Index of the first no-return feature.
const NO_RETURN: usize = FREE_WIDE + 3;

/// Support of the wide angular window, in cone half-angles: the perceptual
/// field's half-width.
pub const FIELD: f64 = 1.5;
/// Depth past the end of the model's band ([`LearnedInverse::band_end`])
/// that still belongs to a real return's perceptual field when the model
/// removes a prior other than its own, metres: cells the model knows
/// nothing about, which then drift ([`prior_drift`](crate::mapping::drift::prior_drift)). With its own prior
/// they would get exactly 0, and the field ends with the band.
pub const BEHIND_BAND: f64 = 0.1;
/// Evidence a reading may leave out past the end of its band, log odds:
/// it moves a cell's probability by at most 1.25 points (at p = 1/2),
/// well inside what the fit can tell apart from zero.
pub const NEGLIGIBLE: f64 = 0.05;
/// Reach of the near-sensor feature `H` of a no-return, metres.
const NEAR_SENSOR: f64 = 1.0;
/// Where the room feature `M` of a no-return has fallen to 0, metres.
const ROOM: f64 = 4.0;
/// Width of the free plateau's smooth edge, metres before the reading.
const FRONT_RAMP: f64 = 0.3;
/// Largest magnitude of a weight or a prior, log odds. Every feature lies
/// in `[0, 1]`, so a score stays within `FEATURES * MAX_LOG_ODDS`: finite as
/// an `f32` whatever the weights. (A fitted model's weights are a few log
/// odds; a probability within `e^-10000` of 0 or 1 is past any map's clamp.)
pub const MAX_LOG_ODDS: f64 = 1e4;
/// Lattice step of the tabulated score, metres.
const TABLE_STEP: f64 = KNOT_STEP / TABLE_PER_KNOT as f64;
/// Lattice points per knot interval.
const TABLE_PER_KNOT: usize = 16;
/// Rows of the tabulated score, over the spline's span, both ends included.
const TABLE_ROWS: usize = (SPLINES + 3) * TABLE_PER_KNOT + 1;

/// The sensor geometry the features are expressed in.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FeatureFrame {
    /// Maximum range of the sensor, metres.
    pub z_max: f64,
    /// Half-angle of the training sensor's cone, radians.
    pub half_width: f64,
}

impl FeatureFrame {
    pub fn validate(&self) -> Result<()> {
        error::positive("z_max", self.z_max)?;
        error::positive("half_width", self.half_width)?;
        if self.half_width * FIELD > std::f64::consts::FRAC_PI_2 {
            return Err(invalid(
                "half_width",
                self.half_width,
                "a cone half-angle of at most pi/3 radians",
            ));
        }
        Ok(())
    }

    /// The feature vector of a cell at range `r` and bearing offset `psi`
    /// for a reading `z` (the exact definition; the mappers use the
    /// tabulated form of [`LearnedInverse`]).
    pub fn features(&self, r: f64, psi: f64, z: f64) -> [f64; FEATURES] {
        let mut phi = [0.0; FEATURES];
        phi[BIAS] = 1.0;
        let u = psi.abs() / self.half_width;
        let wide = window(u / FIELD);
        if z >= self.z_max {
            phi[NO_RETURN] = wide;
            phi[NO_RETURN + 1] = wide * room(r);
            phi[NO_RETURN + 2] = wide * near_sensor(r);
            return phi;
        }
        let d = r - z;
        phi[BEYOND] = beyond(d);
        if let Some((i, b)) = spline_basis(d) {
            for (j, &bj) in b.iter().enumerate() {
                // Function k covers knot intervals k-3 ..= k; i is the
                // interval holding d.
                if let Some(k) = (i + j).checked_sub(3).filter(|&k| k < SPLINES) {
                    phi[SPLINE0 + k] = wide * bj;
                }
            }
        }
        let front = front_plateau(d);
        phi[FREE_WIDE] = wide * front;
        phi[FREE_NARROW] = window(u) * front;
        phi[FREE_RANGE] = wide * (z / self.z_max).clamp(0.0, 1.0) * front;
        phi
    }
}

/// `(1 - x^2)^2` on `|x| < 1`, else 0: a smooth bump with flat top and feet.
#[inline]
fn window(x: f64) -> f64 {
    let q = 1.0 - x * x;
    if q > 0.0 {
        q * q
    } else {
        0.0
    }
}

/// Cubic smoothstep: 0 at `x <= 0`, 1 at `x >= 1`.
#[inline]
fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// `F`: 1 for `d <= -0.3` m, 0 for `d >= 0`.
#[inline]
fn front_plateau(d: f64) -> f64 {
    smoothstep(-d / FRONT_RAMP)
}

/// `M`: 1 up to [`NEAR_SENSOR`], 0 from [`ROOM`] metres on.
#[inline]
fn room(r: f64) -> f64 {
    smoothstep((ROOM - r) / (ROOM - NEAR_SENSOR))
}

/// `H`: 1 at the sensor, 0 from [`NEAR_SENSOR`] metres on.
#[inline]
fn near_sensor(r: f64) -> f64 {
    smoothstep(1.0 - r / NEAR_SENSOR)
}

/// `G`: 0 up to 0.2 m past the reading, 1 from 0.5 m.
#[inline]
fn beyond(d: f64) -> f64 {
    smoothstep((d - BEYOND_START) / (SPLINE_END - BEYOND_START))
}

/// The uniform cubic B-spline basis at `d`: the knot interval `i` holding
/// `d` (interval `i` spans `SPLINE_START + [i, i+1) * KNOT_STEP`) and the
/// values of the four functions alive on it, those starting at intervals
/// `i-3 ..= i` in that order. `None` outside the span.
#[inline]
fn spline_basis(d: f64) -> Option<(usize, [f64; 4])> {
    let t = (d - SPLINE_START) / KNOT_STEP;
    if !(t >= 0.0 && t < (SPLINES + 3) as f64) {
        return None;
    }
    let i = t as usize;
    let f = t - i as f64;
    let (f2, f3) = (f * f, f * f * f);
    let g = 1.0 - f;
    Some((
        i,
        [
            g * g * g / 6.0,
            (3.0 * f3 - 6.0 * f2 + 4.0) / 6.0,
            (-3.0 * f3 + 3.0 * f2 + 3.0 * f + 1.0) / 6.0,
            f3 / 6.0,
        ],
    ))
}

/// The trained model: weights, the prior read off them, and the tables
/// that make [`InverseModel::evidence`] cheap.
#[derive(Debug, Clone, PartialEq)]
pub struct LearnedInverse {
    frame: FeatureFrame,
    weights: [f64; FEATURES],
    /// The model's own prior, log odds: its score far beyond a short
    /// reading on the axis.
    own_l0: f64,
    /// The prior removed from every score: `own_l0` unless a caller
    /// overrides it (the drift diagnostic forces 0).
    l0: f64,
    /// `own_l0 - l0`: the evidence of a cell far beyond a reading (0 with
    /// the model's own prior).
    base: f64,
    /// The score's parts on the lattice `d = SPLINE_START + k * TABLE_STEP`.
    /// (Both tables are held inline, a few kilobytes: a model is cloned for
    /// every pane that maps with it, and owns no heap memory.)
    table: [Row; TABLE_ROWS],
    /// The on-axis score of every lattice interval as `(axis, its rise to
    /// the next row, range / z_max, its rise)`: one read and two
    /// multiply-adds per cell. (The last row rises by 0.)
    axis_table: [[f64; 4]; TABLE_ROWS],
    /// On the axis in front of the span, where nothing changes with depth
    /// (the free plateau: most cells of every beam), the evidence is
    /// `plateau_base + z * plateau_slope`.
    plateau_base: f64,
    plateau_slope: f64,
    /// Depth past the reading where the model's band ends, metres
    /// ([`LearnedInverse::band_end`]).
    band_end: f64,
    /// Depth past the reading where the perceptual field of a real return
    /// ends, metres: the band's end, plus [`BEHIND_BAND`] unless `l0` is
    /// the model's own.
    field_end: f64,
    /// A no-return's evidence on the axis from [`ROOM`] metres on, where
    /// it no longer changes with range.
    no_return_far: f64,
    inv_half_width: f64,
    inv_z_max: f64,
}

/// One lattice point of the tabulated score (log odds). Kept in `f64`: the
/// table is a few kilobytes and a conversion per read costs more than the
/// memory.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Row {
    /// `w_G (G(d) - 1)`: exactly 0 from the end of the span on, so that the
    /// cells the model knows nothing about get exactly `own_l0 - l0`.
    g: f64,
    /// `T(d)`, the part under the wide window.
    t: f64,
    /// `F(d)`.
    front: f64,
    /// On the axis (both windows 1), everything but the range-scaled part:
    /// `g + T + w_n F`.
    axis: f64,
    /// On the axis, the range-scaled part per unit of `z / z_max`: `w_z F`.
    range: f64,
}

impl Row {
    #[inline]
    fn lerp(a: &Row, b: &Row, f: f64) -> Row {
        let m = |x: f64, y: f64| x + f * (y - x);
        Row {
            g: m(a.g, b.g),
            t: m(a.t, b.t),
            front: m(a.front, b.front),
            axis: m(a.axis, b.axis),
            range: m(a.range, b.range),
        }
    }
}

impl LearnedInverse {
    /// A model from fitted weights. Rejects non-finite weights.
    pub fn new(frame: FeatureFrame, weights: [f64; FEATURES]) -> Result<Self> {
        frame.validate()?;
        for (i, &w) in weights.iter().enumerate() {
            #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
            if !(w.abs() <= MAX_LOG_ODDS) {
                return Err(invalid(
                    &format!("weights[{i}]"),
                    w,
                    "a finite weight of at most 10000 in magnitude (a log odds)",
                ));
            }
        }
        let mut model = Self {
            frame,
            weights,
            own_l0: 0.0,
            l0: 0.0,
            base: 0.0,
            table: [Row::default(); TABLE_ROWS],
            axis_table: [[0.0; 4]; TABLE_ROWS],
            plateau_base: 0.0,
            plateau_slope: 0.0,
            band_end: 0.0,
            field_end: 0.0,
            no_return_far: 0.0,
            inv_half_width: 1.0 / frame.half_width,
            inv_z_max: 1.0 / frame.z_max,
        };
        // Read the prior off the model: a cell two spline spans beyond a
        // short reading (a quarter of the range), on the axis. (Only the
        // bias and G are non-zero there, at any bearing.)
        let z = 0.25 * frame.z_max;
        let own_l0 = model.score(z + 2.0 * (SPLINE_END - SPLINE_START), 0.0, z);
        for (k, row) in model.table.iter_mut().enumerate() {
            let d = SPLINE_START + k as f64 * TABLE_STEP;
            let front = front_plateau(d);
            let spline: f64 = spline_basis(d).map_or(0.0, |(i, b)| {
                b.iter()
                    .enumerate()
                    .filter_map(|(j, &bj)| {
                        let k = (i + j).checked_sub(3).filter(|&k| k < SPLINES)?;
                        Some(weights[SPLINE0 + k] * bj)
                    })
                    .sum()
            });
            let t = spline + weights[FREE_WIDE] * front;
            let g = weights[BEYOND] * (beyond(d) - 1.0);
            *row = Row {
                g,
                t,
                front,
                axis: g + t + weights[FREE_NARROW] * front,
                range: weights[FREE_RANGE] * front,
            };
        }
        let inv_z_max = model.inv_z_max;
        for (k, out) in model.axis_table.iter_mut().enumerate() {
            let (Some(a), b) = (model.table.get(k), model.table.get(k + 1)) else {
                continue;
            };
            let b = b.unwrap_or(a);
            *out = [
                a.axis,
                b.axis - a.axis,
                a.range * inv_z_max,
                (b.range - a.range) * inv_z_max,
            ];
        }
        model.band_end = band_end(&model.table);
        model.own_l0 = own_l0;
        Ok(model.with_l0(own_l0))
    }

    /// Depth past a reading, metres, beyond which the model's evidence for
    /// a real return stays below [`NEGLIGIBLE`] (net of its own `l0`) at
    /// every bearing and every range: the end of its occupied band, read
    /// off the model. Between 0 and [`SPLINE_END`]. The model drops what
    /// evidence is left beyond it.
    pub fn band_end(&self) -> f64 {
        self.band_end
    }

    /// The same model removing `l0` instead of its own prior from every
    /// score (`with_l0(0.0)` is the mistake [`prior_drift`](crate::mapping::drift::prior_drift) shows). A NaN
    /// keeps the model's own; anything else is held within
    /// `±MAX_LOG_ODDS`, so that every evidence stays a finite `f32`.
    pub fn with_l0(&self, l0: f64) -> Self {
        let l0 = if l0.is_nan() {
            self.own_l0
        } else {
            l0.clamp(-MAX_LOG_ODDS, MAX_LOG_ODDS)
        };
        let base = self.own_l0 - l0;
        let [axis, _, range, _] = self.axis_table[0];
        let behind = if base == 0.0 { 0.0 } else { BEHIND_BAND };
        let w = &self.weights;
        Self {
            l0,
            base,
            plateau_base: base + axis,
            plateau_slope: range,
            field_end: self.band_end + behind,
            no_return_far: base - w[BEYOND] + w[NO_RETURN],
            ..self.clone()
        }
    }

    pub fn frame(&self) -> &FeatureFrame {
        &self.frame
    }
    pub fn weights(&self) -> &[f64; FEATURES] {
        &self.weights
    }
    /// The model's own prior in log odds, read off the model.
    pub fn own_l0(&self) -> f64 {
        self.own_l0
    }

    /// The regression's score `w . phi` (a posterior log odds), exactly.
    pub fn score(&self, r: f64, psi: f64, z: f64) -> f64 {
        let phi = self.frame.features(r, psi, z);
        phi.iter().zip(&self.weights).map(|(p, w)| p * w).sum()
    }

    /// The tabulated score's parts at `d` metres past the reading,
    /// linearly interpolated, and held at the ends (in front of the span
    /// at the first row, past it at the last, where every part is 0).
    #[inline]
    fn lookup(&self, d: f64) -> Row {
        let (k, f) = self.lattice_point(d);
        match (self.table.get(k), self.table.get(k + 1)) {
            (Some(a), Some(b)) => Row::lerp(a, b, f),
            _ => Row::default(),
        }
    }

    /// `axis + (z / z_max) range` at `d >= SPLINE_START`, interpolated:
    /// the on-axis score relative to `own_l0` (past the span the last row
    /// holds: it rises by 0).
    #[inline(always)]
    fn lookup_axis(&self, d: f64, z: f64) -> f64 {
        let t = (d - SPLINE_START) * (1.0 / TABLE_STEP);
        let k = (t as usize).min(TABLE_ROWS - 1);
        let f = t - k as f64;
        let row = &self.axis_table[k];
        row[0] + f * row[1] + z * (row[2] + f * row[3])
    }

    /// The lattice interval holding `d` and the position within it, held
    /// at the ends.
    #[inline]
    fn lattice_point(&self, d: f64) -> (usize, f64) {
        // Comparisons rather than f64::max/min, which are library calls in
        // wasm (this runs once per cell per beam).
        let mut t = (d - SPLINE_START) * (1.0 / TABLE_STEP);
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: clamped to 0
        if !(t > 0.0) {
            t = 0.0;
        }
        let k = (t as usize).min(self.table.len().saturating_sub(2));
        let f = t - k as f64;
        (k, if f > 1.0 { 1.0 } else { f })
    }
}

/// [`LearnedInverse::band_end`] of a model tabulated as `table` (rows
/// from `SPLINE_START`, `TABLE_STEP` apart). Past the reading the free
/// plateau is 0, so the evidence of a row at bearing window `a_w` is
/// `g + a_w T`: its largest magnitude over all bearings is at `a_w = 0` or
/// `a_w = 1`. Between two rows it is interpolated, so it stays below the
/// larger of theirs; past the last row it is exactly 0.
fn band_end(table: &[Row]) -> f64 {
    let first = ((0.0 - SPLINE_START) / TABLE_STEP).round() as usize;
    let last_significant = table
        .iter()
        .enumerate()
        .skip(first)
        .rev()
        .find(|(_, row)| row.g.abs().max((row.g + row.t).abs()) >= NEGLIGIBLE)
        .map(|(k, _)| k);
    match last_significant {
        // The band ends at the next row: from there on every row, and so
        // everything between them, is below NEGLIGIBLE.
        Some(k) => (SPLINE_START + (k + 1) as f64 * TABLE_STEP).min(SPLINE_END),
        None => 0.0,
    }
}

impl LearnedInverse {
    /// [`InverseModel::evidence`] off the free plateau's axis.
    #[inline(never)]
    fn evidence_elsewhere(&self, r: f64, phi: f64, z: f64) -> f32 {
        let w = &self.weights;
        if z < self.frame.z_max {
            let d = r - z;
            let zt = z * self.inv_z_max;
            let behind = self.field_end;
            if phi == 0.0 {
                #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN r gives no evidence
                if !(r > -1.0) {
                    return 0.0;
                }
                if d >= SPLINE_START && d <= self.band_end {
                    return (self.base + self.lookup_axis(d, z)) as f32;
                }
                // Past the band: the prior (0 with the model's own l0), then
                // past the reach (or not a number) nothing.
                return if d > self.band_end && d <= behind {
                    self.base as f32
                } else {
                    0.0
                };
            }
            let u = phi.abs() * self.inv_half_width;
            if !(u <= FIELD && d <= behind && r > -1.0) {
                return 0.0;
            }
            if d > self.band_end {
                return self.base as f32;
            }
            let row = self.lookup(d);
            let (wide, narrow) = (window(u * (1.0 / FIELD)), window(u));
            let e = self.base
                + row.g
                + wide * (row.t + zt * w[FREE_RANGE] * row.front)
                + narrow * w[FREE_NARROW] * row.front;
            return e as f32;
        }
        // A no-return (a NaN reading fails both tests). On the axis from
        // ROOM metres on it is a constant: half of every such beam.
        if phi == 0.0 && r >= ROOM && r <= self.frame.z_max && z >= self.frame.z_max {
            return self.no_return_far as f32;
        }
        let u = phi.abs() * self.inv_half_width;
        if !(z >= self.frame.z_max && r <= self.frame.z_max && r > -1.0 && u <= FIELD) {
            return 0.0;
        }
        let wide = window(u * (1.0 / FIELD));
        // Scores are taken relative to `own_l0 = w0 + w_G`.
        let e = self.base - w[BEYOND]
            + wide
                * (w[NO_RETURN] + room(r) * w[NO_RETURN + 1] + near_sensor(r) * w[NO_RETURN + 2]);
        e as f32
    }
}

impl InverseModel for LearnedInverse {
    #[inline(always)]
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32 {
        // The free plateau on the axis: most cells of every beam, and there
        // all the ray-traversal mapper asks. (A NaN fails a test and goes
        // the long way, which returns 0.)
        if phi == 0.0 && z < self.frame.z_max && r - z < SPLINE_START && r > -1.0 {
            return (self.plateau_base + z * self.plateau_slope) as f32;
        }
        self.evidence_elsewhere(r, phi, z)
    }

    /// A real return: the end of the model's band past the reading
    /// ([`LearnedInverse::band_end`]), and with a prior other than its own
    /// [`BEHIND_BAND`] further. A no-return: `z_max`.
    #[inline]
    fn reach(&self, z: f64) -> f64 {
        if z >= self.frame.z_max {
            self.frame.z_max
        } else {
            z + self.field_end
        }
    }

    fn half_width(&self) -> f64 {
        FIELD * self.frame.half_width
    }

    fn z_max(&self) -> f64 {
        self.frame.z_max
    }

    fn l0(&self) -> f32 {
        self.l0 as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> FeatureFrame {
        FeatureFrame {
            z_max: 8.0,
            half_width: 0.05,
        }
    }

    #[test]
    fn spline_basis_sums_to_one_inside_and_vanishes_outside() {
        // Away from the span's ends all four live functions are features.
        for k in 0..100 {
            let d = SPLINE_START + 3.0 * KNOT_STEP + k as f64 * 0.004;
            if d >= SPLINE_END - 3.0 * KNOT_STEP {
                break;
            }
            let phi = frame().features(2.0 + d, 0.0, 2.0);
            let sum: f64 = phi[SPLINE0..SPLINE0 + SPLINES].iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "{d}: {sum}");
        }
        assert!(spline_basis(SPLINE_END).is_none());
        assert!(spline_basis(SPLINE_START - 1e-9).is_none());
    }

    #[test]
    fn features_are_bounded_and_only_the_prior_is_left_where_nothing_is_known() {
        let f = frame();
        for (r, psi, z) in [(0.3, 0.0, 2.0), (2.05, 0.04, 2.0), (9.0, -0.02, 8.0)] {
            let phi = f.features(r, psi, z);
            assert!(phi.iter().all(|p| (0.0..=1.0).contains(p)), "{phi:?}");
        }
        let only = |phi: [f64; FEATURES], live: &[usize]| {
            phi.iter()
                .enumerate()
                .all(|(i, &p)| p == if live.contains(&i) { 1.0 } else { 0.0 })
        };
        // Far beyond the reading: the bias and G, whatever the bearing.
        assert!(only(
            f.features(2.0 + SPLINE_END + 0.01, 0.0, 2.0),
            &[BIAS, BEYOND]
        ));
        assert!(only(
            f.features(2.0 + SPLINE_END, 0.06, 2.0),
            &[BIAS, BEYOND]
        ));
        // At the rim of the field: the bias alone.
        assert!(only(f.features(1.0, 0.05 * FIELD, 2.0), &[BIAS]));
        assert!(only(f.features(1.0, 0.05 * FIELD, 8.0), &[BIAS]));
    }

    #[test]
    fn tabulated_evidence_matches_the_exact_score() {
        let mut w = [0.0; FEATURES];
        for (i, x) in w.iter_mut().enumerate() {
            *x = ((i * 7 % 5) as f64 - 2.0) * 0.8;
        }
        let m = LearnedInverse::new(frame(), w).unwrap();
        for k in 0..4000 {
            let z = if k % 10 == 0 {
                8.0
            } else {
                0.5 + (k % 37) as f64 * 0.2
            };
            let r = (k % 101) as f64 * 0.09;
            let psi = ((k % 13) as f64 - 6.0) * 0.012;
            if r > m.reach(z) {
                continue;
            }
            let exact = m.score(r, psi, z) - m.own_l0();
            let fast = m.evidence(r, psi, z) as f64;
            if z < 8.0 && r - z > m.band_end() {
                // Past the band: what is dropped is negligible.
                assert_eq!(fast, 0.0, "({r}, {psi}, {z})");
                assert!(
                    exact.abs() < NEGLIGIBLE + 2e-3,
                    "({r}, {psi}, {z}): {exact}"
                );
                continue;
            }
            assert!(
                (exact - fast).abs() < 2e-3,
                "({r}, {psi}, {z}): {exact} vs {fast}"
            );
        }
    }

    #[test]
    fn the_band_ends_where_the_weights_stop_speaking() {
        let frame = frame();
        // Only the bias and the free plateau: nothing to say past the
        // reading.
        let mut w = [0.0; FEATURES];
        w[BIAS] = -1.0;
        w[FREE_WIDE] = -2.0;
        let m = LearnedInverse::new(frame, w).unwrap();
        assert_eq!(m.band_end(), 0.0);
        assert_eq!(m.reach(2.0), 2.0);
        assert_eq!(m.with_l0(0.0).reach(2.0), 2.0 + BEHIND_BAND);
        assert!(m.evidence(1.0, 0.0, 2.0) < -1.0);
        // G alone: cells short of its rise differ from those far beyond
        // by w_G, so the band lasts until G has nearly reached 1.
        w[BEYOND] = 0.5;
        let m = LearnedInverse::new(frame, w).unwrap();
        assert!(m.band_end() > BEYOND_START && m.band_end() < SPLINE_END);
        // One spline weight on the k-th function: it speaks up to the end
        // of that function's support (where it falls below NEGLIGIBLE).
        for k in 3..SPLINES {
            let mut w = [0.0; FEATURES];
            w[SPLINE0 + k] = 2.0;
            let m = LearnedInverse::new(frame, w).unwrap();
            let support_end = SPLINE_START + (k + 4) as f64 * KNOT_STEP;
            assert!(m.band_end() <= support_end + 1e-9, "{k}: {}", m.band_end());
            assert!(
                m.band_end() > support_end - KNOT_STEP,
                "{k}: {}",
                m.band_end()
            );
            // Just short of the end it still speaks, just past it not.
            assert!(m.evidence(2.0 + m.band_end() - 0.006, 0.0, 2.0) > 0.04);
            assert!(m.evidence(2.0 + m.band_end() - 0.2, 0.0, 2.0) > 0.05);
            assert_eq!(m.evidence(2.0 + m.band_end() + 0.01, 0.0, 2.0), 0.0);
            assert_eq!(m.reach(2.0), 2.0 + m.band_end());
        }
        // With l0 forced to 0 the field runs on past the band, where the
        // cells get the model's prior; with its own l0 they get nothing.
        let zero = m.with_l0(0.0);
        let r = 2.0 + m.band_end() + 0.5 * BEHIND_BAND;
        assert_eq!(zero.reach(2.0), 2.0 + m.band_end() + BEHIND_BAND);
        assert_eq!(zero.evidence(r, 0.0, 2.0), m.own_l0() as f32);
        assert_eq!(zero.evidence(r, 0.01, 2.0), m.own_l0() as f32);
        assert_eq!(m.evidence(r, 0.0, 2.0), 0.0);
        assert_eq!(zero.evidence(r + BEHIND_BAND, 0.0, 2.0), 0.0);
    }
}
