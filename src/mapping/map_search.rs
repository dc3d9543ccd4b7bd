//! MAP occupancy grid mapping by hill climbing (Probabilistic Robotics,
//! §9.4, Table 9.3).
//!
//! Instead of one posterior per cell, look for the single most probable
//! binary map: maximise
//!
//! ```text
//! J(m) = sum_t log p(z_t | x_t, m) + l0 * sum_i m_i
//! ```
//!
//! (the log likelihood of every reading under the forward beam model of
//! Table 6.1, plus the log prior of i.i.d. cells with constants dropped,
//! `l0 = ln(p0 / (1 - p0))`). No inverse model appears, so no cone-shaped
//! smear: a short sonar reading is explained by *one* occupied cell, not by
//! an arc of them. This is the module behind the right half of the
//! doorway-trap widget; its input is a set of cone readings (from
//! [`crate::world::doorway`] or any other scene) and its output a sparse binary
//! map with the history of how it was found.
//!
//! The search starts all-free and flips, one at a time, the cell whose flip
//! raises `J` most (steepest ascent, so the order of flips is legible), until
//! no single flip helps: a local maximum.
//!
//! Two caches make a flip cheap:
//!
//! * **Incidence**, built once on the empty map. Occupancy decides where a
//!   ray stops, never where it goes, so the cells a beam can ever depend on
//!   are exactly those its sub-ray rasters cross, each at the smallest range
//!   at which a sub-ray enters it. The expected range `z*` of a beam is then
//!   the range of its first occupied cell in that list (or `z_max`), which
//!   is what [`crate::world::World::cast_cone`] returns for the same sub-rays.
//!   Since every possible `z*` is one of the list's ranges, the beam's log
//!   likelihood for each is tabulated once too.
//! * **Gains**, kept for every cell and updated incrementally. A flip of
//!   cell `c` can change the gain of a cell `j` only through a beam both lie
//!   on, and only if that beam's first or second occupied cell changed; only
//!   those beams' cells are recomputed.

use crate::error::{self, invalid, OccError, Result};
use crate::geometry::raster::{entry_parameter, raster_work, supercover, MAX_RASTER_WORK};
use crate::geometry::GridGeometry;
use crate::geometry::Pose;
use crate::grid::{logit, FilterSettings, LogOddsGrid};
use crate::sensors::beam_model::{BeamModel, BeamModelParams};
use crate::sensors::scan::ConeBeam;

/// No entry (a beam with no occupied cell).
const NONE: u32 = u32::MAX;

/// A flip must raise the objective by more than this (nats) to be taken:
/// ties and rounding noise do not count as progress, so the climb ends.
pub const MIN_GAIN: f64 = 1e-9;

/// A density the model calls (numerically) impossible is floored here before
/// its logarithm, so that every objective stays finite and comparable.
const MIN_DENSITY: f64 = 1e-300;

/// How the search sees the world: the cone's geometry, the forward model and
/// the prior.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MapSearchSettings {
    /// Prior occupancy `p0` of every cell; the objective's prior term is
    /// `logit(p0)` per occupied cell.
    pub prior: f64,
    /// Half the cone's opening angle, radians.
    pub half_width: f64,
    /// Sub-rays spread evenly across the cone (Table 6.1), edges included.
    pub sub_rays: usize,
    /// The forward beam model; its `z_max` is how far the cone reaches.
    pub model: BeamModelParams,
}

impl MapSearchSettings {
    pub fn validate(&self) -> Result<BeamModel> {
        error::open_probability("prior", self.prior)?;
        error::non_negative("half_width", self.half_width)?;
        if self.half_width >= std::f64::consts::FRAC_PI_2 {
            return Err(invalid(
                "half_width",
                self.half_width,
                "a half opening angle below pi/2 radians",
            ));
        }
        if self.sub_rays == 0 || self.sub_rays > 1024 {
            return Err(invalid(
                "sub_rays",
                self.sub_rays,
                "between 1 and 1024 rays",
            ));
        }
        BeamModel::new(self.model)
    }
}

/// How one beam's log likelihood changed in a flip.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct BeamChange {
    /// Index of the beam in the search's beam list.
    pub beam: usize,
    /// `log p(z | x, m)` before and after the flip, nats.
    pub before: f64,
    pub after: f64,
    /// `after - before`.
    pub delta: f64,
    /// The beam's expected range after the flip, metres.
    pub expected_range: f64,
}

/// One step of the climb, annotated for the widget.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Flip {
    /// 1 for the first flip.
    pub number: usize,
    /// The flipped cell: row-major index and `(ix, iy)`, and where it is
    /// drawn in the north-up image (column, row from the top).
    pub cell: usize,
    pub ix: usize,
    pub iy: usize,
    pub col: usize,
    pub row: usize,
    /// True when the cell became occupied.
    pub to_occupied: bool,
    /// Objective change, nats: the sum of the beams' changes plus the
    /// prior term.
    pub gain: f64,
    /// The prior's share of the gain, `+l0` for a cell set occupied and
    /// `-l0` for one cleared.
    pub prior_term: f64,
    /// The objective after the flip, nats.
    pub objective: f64,
    /// Every beam whose log likelihood the flip changed.
    pub beams: Vec<BeamChange>,
}

/// The beam–cell incidence of Table 9.3's search, in compressed rows.
#[derive(Debug, Clone)]
struct Incidence {
    /// Beam `b`'s entries are `beam_start[b]..beam_start[b + 1]`, sorted by
    /// range.
    beam_start: Vec<u32>,
    entry_cell: Vec<u32>,
    entry_beam: Vec<u32>,
    /// Range (metres) at which the cone first enters the entry's cell.
    entry_range: Vec<f64>,
    /// `log p(z_b | z* = entry_range)`, nats.
    entry_log_lik: Vec<f64>,
    /// `log p(z_b | z* = z_max)`: the beam on an empty cone.
    empty_log_lik: Vec<f64>,
    /// Cell `i`'s entries (global entry indices) are
    /// `cell_entries[cell_start[i]..cell_start[i + 1]]`.
    cell_start: Vec<u32>,
    cell_entries: Vec<u32>,
}

/// The climb: state, caches and history.
#[derive(Debug, Clone)]
pub struct MapSearch {
    geometry: GridGeometry,
    beams: Vec<ConeBeam>,
    settings: MapSearchSettings,
    l0: f64,
    inc: Incidence,
    occupied: Vec<bool>,
    /// Per beam: global entry index of its first and second occupied cell.
    first: Vec<u32>,
    second: Vec<u32>,
    /// Per beam: current log likelihood.
    beam_log_lik: Vec<f64>,
    /// Per cell: objective change if that cell alone were flipped now.
    gains: Vec<f64>,
    occupied_count: usize,
    objective: f64,
    history: Vec<f64>,
    flips: Vec<Flip>,
    converged: bool,
    /// Scratch for the affected-cell set of a flip.
    stamp: Vec<u32>,
    epoch: u32,
    affected: Vec<u32>,
}

impl MapSearch {
    /// Validates the input, builds the incidence cache on the empty map and
    /// puts the climb at its all-free start.
    pub fn new(
        geometry: GridGeometry,
        beams: Vec<ConeBeam>,
        settings: MapSearchSettings,
    ) -> Result<Self> {
        let model = settings.validate()?;
        if beams.is_empty() {
            return Err(invalid("beams", "[]", "at least one beam"));
        }
        for (i, b) in beams.iter().enumerate() {
            Pose::new(b.pose.x, b.pose.y, b.pose.theta).map_err(|e| prefix(i, e))?;
            error::finite(&format!("beams[{i}].bearing"), b.bearing)?;
            error::non_negative(&format!("beams[{i}].range"), b.range)?;
        }
        let work = raster_work(
            beams.len(),
            settings.sub_rays,
            settings.model.z_max,
            geometry.resolution(),
        );
        // Written to refuse a NaN too.
        if !(work <= MAX_RASTER_WORK) {
            return Err(invalid(
                "beams x sub_rays x (z_max / resolution)",
                work,
                "at most 5e7 raster steps",
            ));
        }
        let inc = build_incidence(&geometry, &beams, &settings, &model);
        let n = geometry.len();
        let l0 = logit(settings.prior);
        let mut search = Self {
            geometry,
            settings,
            l0,
            occupied: vec![false; n],
            first: vec![NONE; beams.len()],
            second: vec![NONE; beams.len()],
            beam_log_lik: inc.empty_log_lik.clone(),
            gains: vec![0.0; n],
            occupied_count: 0,
            objective: 0.0,
            history: Vec::new(),
            flips: Vec::new(),
            converged: false,
            stamp: vec![0; n],
            epoch: 0,
            affected: Vec::new(),
            inc,
            beams,
        };
        search.reset();
        Ok(search)
    }

    /// Back to the all-free start: every gain recomputed, history cleared.
    pub fn reset(&mut self) {
        self.occupied.fill(false);
        self.first.fill(NONE);
        self.second.fill(NONE);
        self.beam_log_lik.clone_from(&self.inc.empty_log_lik);
        self.occupied_count = 0;
        for i in 0..self.geometry.len() {
            self.gains[i] = self.gain_of(i);
        }
        self.objective = self.current_objective();
        self.history = vec![self.objective];
        self.flips.clear();
        self.converged = false;
    }

    /// One steepest-ascent step: flips the cell with the largest gain and
    /// returns the annotated flip, or `None` once no flip raises the
    /// objective by more than [`MIN_GAIN`] (a local maximum).
    pub fn step(&mut self) -> Option<&Flip> {
        if self.converged {
            return None;
        }
        // Ties go to the lowest index, so the climb is deterministic.
        let (mut best, mut best_gain) = (usize::MAX, MIN_GAIN);
        for (i, &g) in self.gains.iter().enumerate() {
            if g > best_gain {
                best = i;
                best_gain = g;
            }
        }
        if best == usize::MAX {
            self.converged = true;
            return None;
        }
        self.flip(best);
        self.flips.last()
    }

    /// Steps until convergence or `max_flips` flips; returns the flips made.
    pub fn run(&mut self, max_flips: usize) -> usize {
        let mut n = 0;
        while n < max_flips && self.step().is_some() {
            n += 1;
        }
        n
    }

    /// Flips cell `c`, updates the beams it lies on, the objective, and the
    /// gains of the cells whose gain may have changed.
    fn flip(&mut self, c: usize) {
        let gain = self.gains[c];
        let to_occupied = !self.occupied[c];
        self.occupied[c] = to_occupied;
        if to_occupied {
            self.occupied_count += 1;
        } else {
            self.occupied_count -= 1;
        }

        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        self.affected.clear();
        self.mark(c);

        let mut changes = Vec::new();
        let (s, t) = self.cell_range(c);
        for k in s..t {
            let e = self.inc.cell_entries[k] as usize;
            let b = self.inc.entry_beam[e] as usize;
            let (old_first, old_second) = (self.first[b], self.second[b]);
            self.refresh_beam(b);
            if self.first[b] == old_first && self.second[b] == old_second {
                continue;
            }
            // The beam's first or second occupied cell moved: every cell on
            // it may see another gain through it.
            let (bs, bt) = self.beam_range(b);
            for e2 in bs..bt {
                let j = self.inc.entry_cell[e2] as usize;
                if self.stamp[j] != self.epoch {
                    self.stamp[j] = self.epoch;
                    self.affected.push(j as u32);
                }
            }
            let before = self.beam_log_lik[b];
            let after = self.log_lik_of_first(b);
            self.beam_log_lik[b] = after;
            if after != before {
                changes.push(BeamChange {
                    beam: b,
                    before,
                    after,
                    delta: after - before,
                    expected_range: self.expected_range(b),
                });
            }
        }
        for k in 0..self.affected.len() {
            let j = self.affected[k] as usize;
            self.gains[j] = self.gain_of(j);
        }

        self.objective = self.current_objective();
        self.history.push(self.objective);
        let (ix, iy) = self.geometry.cell_of_index(c);
        let number = self.flips.len() + 1;
        self.flips.push(Flip {
            number,
            cell: c,
            ix,
            iy,
            col: ix,
            row: self.geometry.height() - 1 - iy,
            to_occupied,
            gain,
            prior_term: if to_occupied { self.l0 } else { -self.l0 },
            objective: self.objective,
            beams: changes,
        });
    }

    fn mark(&mut self, j: usize) {
        if self.stamp[j] != self.epoch {
            self.stamp[j] = self.epoch;
            self.affected.push(j as u32);
        }
    }

    fn beam_range(&self, b: usize) -> (usize, usize) {
        (
            self.inc.beam_start[b] as usize,
            self.inc.beam_start[b + 1] as usize,
        )
    }

    fn cell_range(&self, i: usize) -> (usize, usize) {
        (
            self.inc.cell_start[i] as usize,
            self.inc.cell_start[i + 1] as usize,
        )
    }

    /// Finds beam `b`'s first and second occupied cells by walking its
    /// entries in range order.
    fn refresh_beam(&mut self, b: usize) {
        let (s, t) = self.beam_range(b);
        let (mut first, mut second) = (NONE, NONE);
        for e in s..t {
            if self.occupied[self.inc.entry_cell[e] as usize] {
                if first == NONE {
                    first = e as u32;
                } else {
                    second = e as u32;
                    break;
                }
            }
        }
        self.first[b] = first;
        self.second[b] = second;
    }

    fn log_lik_of_first(&self, b: usize) -> f64 {
        self.log_lik_at(b, self.first[b])
    }

    fn log_lik_at(&self, b: usize, e: u32) -> f64 {
        if e == NONE {
            self.inc.empty_log_lik[b]
        } else {
            self.inc.entry_log_lik[e as usize]
        }
    }

    /// The objective change if cell `j` alone were flipped, from the beams'
    /// cached first and second occupied cells.
    fn gain_of(&self, j: usize) -> f64 {
        let occupied = self.occupied[j];
        let mut gain = if occupied { -self.l0 } else { self.l0 };
        let (s, t) = self.cell_range(j);
        for k in s..t {
            let e = self.inc.cell_entries[k];
            let b = self.inc.entry_beam[e as usize] as usize;
            let first = self.first[b];
            if occupied {
                // Clearing j matters only if it is the beam's first hit; the
                // beam then stops at its second.
                if first == e {
                    gain += self.log_lik_at(b, self.second[b]) - self.beam_log_lik[b];
                }
            } else if first == NONE
                || self.inc.entry_range[e as usize] < self.inc.entry_range[first as usize]
            {
                // Setting j stops the beam earlier.
                gain += self.inc.entry_log_lik[e as usize] - self.beam_log_lik[b];
            }
        }
        gain
    }

    fn current_objective(&self) -> f64 {
        self.beam_log_lik.iter().sum::<f64>() + self.l0 * self.occupied_count as f64
    }

    // ---- Read-outs ----

    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    pub fn beams(&self) -> &[ConeBeam] {
        &self.beams
    }
    pub fn settings(&self) -> &MapSearchSettings {
        &self.settings
    }
    /// The prior's log odds, the objective's price (or reward) per occupied
    /// cell.
    pub fn l0(&self) -> f64 {
        self.l0
    }
    /// The current binary map, row-major from the bottom row.
    pub fn occupied(&self) -> &[bool] {
        &self.occupied
    }
    pub fn occupied_count(&self) -> usize {
        self.occupied_count
    }
    /// `J(m)` of the current map, nats.
    pub fn objective(&self) -> f64 {
        self.objective
    }
    /// The objective at the start and after every flip.
    pub fn history(&self) -> &[f64] {
        &self.history
    }
    pub fn flips(&self) -> &[Flip] {
        &self.flips
    }
    pub fn is_converged(&self) -> bool {
        self.converged
    }
    /// Per-cell sensitivity: the objective change (nats) if that cell alone
    /// were flipped now. At a local maximum every entry is at most
    /// [`MIN_GAIN`]; an occupied cell's entry is what removing it would
    /// cost, a free cell's what adding it would.
    pub fn sensitivity(&self) -> &[f64] {
        &self.gains
    }
    /// Each beam's current log likelihood, nats.
    pub fn beam_log_likelihoods(&self) -> &[f64] {
        &self.beam_log_lik
    }
    /// Beam `b`'s current expected range `z*`, metres.
    pub fn expected_range(&self, b: usize) -> f64 {
        match self.first.get(b) {
            Some(&e) if e != NONE => self.inc.entry_range[e as usize],
            _ => self.settings.model.z_max,
        }
    }
    /// How many beams can see cell `i` (0 for a cell outside every cone).
    pub fn beams_through(&self, i: usize) -> usize {
        if i >= self.geometry.len() {
            return 0;
        }
        let (s, t) = self.cell_range(i);
        t - s
    }
    /// The cells beam `b`'s cone crosses, nearest first, with the range
    /// (metres) at which the cone enters each.
    pub fn beam_cells(&self, b: usize) -> Vec<(usize, f64)> {
        if b >= self.beams.len() {
            return Vec::new();
        }
        let (s, t) = self.beam_range(b);
        (s..t)
            .map(|e| (self.inc.entry_cell[e] as usize, self.inc.entry_range[e]))
            .collect()
    }
    /// Size of the incidence cache: (beam, cell) pairs.
    pub fn incidence_len(&self) -> usize {
        self.inc.entry_cell.len()
    }

    /// `J(m)` of any binary map, from scratch: each beam's first occupied
    /// cell is searched anew. The check on the incremental bookkeeping.
    pub fn evaluate(&self, occupied: &[bool]) -> Result<f64> {
        if occupied.len() != self.geometry.len() {
            return Err(OccError::LengthMismatch {
                field: "occupied".into(),
                expected: self.geometry.len(),
                found: occupied.len(),
            });
        }
        let mut total = 0.0;
        for b in 0..self.beams.len() {
            let (s, t) = self.beam_range(b);
            let hit = (s..t).find(|&e| occupied[self.inc.entry_cell[e] as usize]);
            total += match hit {
                Some(e) => self.inc.entry_log_lik[e],
                None => self.inc.empty_log_lik[b],
            };
        }
        let count = occupied.iter().filter(|&&o| o).count();
        Ok(total + self.l0 * count as f64)
    }

    /// Every cell's gain recomputed by brute force: flip, evaluate from
    /// scratch, flip back. Quadratic; for tests and small maps.
    pub fn gains_from_scratch(&self) -> Vec<f64> {
        let mut map = self.occupied.clone();
        let base = self.evaluate(&map).unwrap_or(f64::NAN);
        (0..map.len())
            .map(|i| {
                map[i] = !map[i];
                let v = self.evaluate(&map).unwrap_or(f64::NAN);
                map[i] = !map[i];
                v - base
            })
            .collect()
    }

    /// The binary map as a log-odds grid (for export): occupied cells at
    /// `+clamp`, free cells some beam crossed at `-clamp`, and cells no cone
    /// ever reached left at the prior, unknown — the search decided nothing
    /// about them.
    pub fn to_grid(&self, clamp: f64) -> Result<LogOddsGrid> {
        let mut grid = LogOddsGrid::new(
            self.geometry,
            FilterSettings {
                prior: self.settings.prior,
                clamp,
            },
        )?;
        let c = clamp as f32;
        for (i, &o) in self.occupied.iter().enumerate() {
            if o {
                grid.apply(i, 2.0 * c);
            } else if self.beams_through(i) > 0 {
                grid.apply(i, -2.0 * c);
            }
        }
        Ok(grid)
    }
}

fn prefix(i: usize, e: OccError) -> OccError {
    match e {
        OccError::InvalidParameter {
            field,
            value,
            expected,
        } => OccError::InvalidParameter {
            field: format!("beams[{i}].{field}"),
            value,
            expected,
        },
        other => other,
    }
}

/// Rasters every beam's sub-rays on the empty map and tabulates the log
/// likelihood of each possible expected range.
fn build_incidence(
    geometry: &GridGeometry,
    beams: &[ConeBeam],
    settings: &MapSearchSettings,
    model: &BeamModel,
) -> Incidence {
    let (w, h) = (geometry.width(), geometry.height());
    let res = geometry.resolution();
    let z_max = settings.model.z_max;
    let n_rays = settings.sub_rays;
    let log_density = |z: f64, z_star: f64| model.density(z, z_star).max(MIN_DENSITY).ln();

    let mut beam_start = Vec::with_capacity(beams.len() + 1);
    let mut entry_cell: Vec<u32> = Vec::new();
    let mut entry_beam: Vec<u32> = Vec::new();
    let mut entry_range_v: Vec<f64> = Vec::new();
    let mut entry_log_lik = Vec::new();
    let mut empty_log_lik = Vec::with_capacity(beams.len());
    // Per cell, the smallest entry range seen for the current beam.
    let mut best: Vec<f64> = vec![f64::INFINITY; geometry.len()];
    let mut touched: Vec<usize> = Vec::new();

    for (b, beam) in beams.iter().enumerate() {
        beam_start.push(entry_cell.len() as u32);
        let (su, sv) = geometry.world_to_grid(beam.pose.x, beam.pose.y);
        let axis = beam.pose.theta + beam.bearing;
        for k in 0..n_rays {
            // The same spread of sub-rays as World::cast_cone.
            let f = if n_rays == 1 {
                0.0
            } else {
                -1.0 + 2.0 * k as f64 / (n_rays - 1) as f64
            };
            let (s, c) = (axis + f * settings.half_width).sin_cos();
            let end = (su + z_max * c / res, sv + z_max * s / res);
            supercover(w, h, (su, sv), end, |ix, iy| {
                // The same entry as World::cast's, so that a beam's z*
                // here equals the cone cast of the same map bit for bit.
                let r = entry_parameter(ix, iy, (su, sv), (c, s)) * res;
                // A cell entered at z_max or beyond leaves z* at z_max.
                if r >= z_max {
                    return;
                }
                let i = iy * w + ix;
                if best[i] == f64::INFINITY {
                    touched.push(i);
                }
                if r < best[i] {
                    best[i] = r;
                }
            });
        }
        let mut cells: Vec<(f64, usize)> = touched.drain(..).map(|i| (best[i], i)).collect();
        // Nearest first; equal ranges by cell index, so the order (and the
        // tie between two cells entered at the same range) is fixed.
        cells.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for &(r, i) in &cells {
            best[i] = f64::INFINITY;
            entry_cell.push(i as u32);
            entry_beam.push(b as u32);
            entry_range_v.push(r);
            entry_log_lik.push(log_density(beam.range, r));
        }
        empty_log_lik.push(log_density(beam.range, z_max));
    }
    beam_start.push(entry_cell.len() as u32);

    // The transpose: for every cell, the entries (beam, range) it has.
    let n = geometry.len();
    let mut cell_start = vec![0u32; n + 1];
    for &i in &entry_cell {
        cell_start[i as usize + 1] += 1;
    }
    for i in 0..n {
        cell_start[i + 1] += cell_start[i];
    }
    let mut fill = cell_start.clone();
    let mut cell_entries = vec![0u32; entry_cell.len()];
    for (e, &i) in entry_cell.iter().enumerate() {
        let slot = &mut fill[i as usize];
        cell_entries[*slot as usize] = e as u32;
        *slot += 1;
    }

    Incidence {
        beam_start,
        entry_cell,
        entry_beam,
        entry_range: entry_range_v,
        entry_log_lik,
        empty_log_lik,
        cell_start,
        cell_entries,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> MapSearchSettings {
        MapSearchSettings {
            prior: 0.3,
            half_width: 0.1,
            sub_rays: 5,
            model: BeamModelParams::CHAPTER,
        }
    }

    #[test]
    fn one_short_reading_is_explained_by_one_cell() {
        let g = GridGeometry::new(40, 20, 0.1, 0.0, 0.0).unwrap();
        let beam = ConeBeam {
            pose: Pose::new(0.55, 1.05, 0.0).unwrap(),
            bearing: 0.0,
            range: 1.5,
        };
        let mut s = MapSearch::new(g, vec![beam], settings()).unwrap();
        let flips = s.run(100);
        assert_eq!(
            flips, 1,
            "one cell explains the reading; more only cost prior"
        );
        assert!(s.is_converged());
        assert!((s.expected_range(0) - 1.5).abs() < 0.1);
        assert_eq!(s.history().len(), 2);
        assert!(s.history()[1] > s.history()[0]);
    }

    #[test]
    fn rejects_bad_settings_and_beams() {
        let g = GridGeometry::new(10, 10, 0.1, 0.0, 0.0).unwrap();
        let beam = ConeBeam {
            pose: Pose::default(),
            bearing: 0.0,
            range: 1.0,
        };
        let bad = MapSearchSettings {
            prior: 1.0,
            ..settings()
        };
        assert!(MapSearch::new(g, vec![beam], bad)
            .unwrap_err()
            .to_string()
            .contains("prior"));
        let e = MapSearch::new(
            g,
            vec![ConeBeam {
                range: f64::NAN,
                ..beam
            }],
            settings(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("beams[0].range"), "{e}");
        assert!(MapSearch::new(g, vec![], settings()).is_err());
        let e = MapSearch::new(
            g,
            vec![ConeBeam {
                pose: Pose {
                    x: f64::INFINITY,
                    y: 0.0,
                    theta: 0.0,
                },
                ..beam
            }],
            settings(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("beams[0].pose.x"), "{e}");
    }
}
