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
//! [`crate::scenes::doorway`] or any other scene) and its output a sparse binary
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
use crate::geometry::raster::{raster_work, MAX_RASTER_WORK};
use crate::geometry::GridGeometry;
use crate::geometry::Pose;
use crate::grid::{logit, FilterSettings, LogOddsGrid};
use crate::sensors::beam_model::{BeamModel, BeamModelParams};
use crate::sensors::scan::ConeBeam;

use super::search_incidence::{Cone, Incidence, IncidenceBuild};

/// No entry (a beam with no occupied cell).
const NONE: u32 = u32::MAX;

/// A flip must raise the objective by more than this (nats) to be taken:
/// ties and rounding noise do not count as progress, so the climb ends.
pub const MIN_GAIN: f64 = 1e-9;

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
    /// puts the climb at its all-free start: a [`MapSearchSetup`] worked to
    /// its end in one call.
    pub fn new(
        geometry: GridGeometry,
        beams: Vec<ConeBeam>,
        settings: MapSearchSettings,
    ) -> Result<Self> {
        MapSearchSetup::new(geometry, beams, settings)?.finish()
    }

    /// Back to the all-free start: every gain recomputed, history cleared.
    pub fn reset(&mut self) {
        self.reset_start();
        self.reset_gains(0..self.geometry.len());
        self.reset_end();
    }

    /// The start of [`MapSearch::reset`]: every cell free, every beam on
    /// its empty cone.
    fn reset_start(&mut self) {
        self.occupied.fill(false);
        self.first.fill(NONE);
        self.second.fill(NONE);
        self.beam_log_lik.clone_from(&self.inc.empty_log_lik);
        self.occupied_count = 0;
    }

    /// The gains of `cells` recomputed; returns their units of work (a
    /// cell and each of its entries, [`GAIN_VISITS_PER_UNIT`] to a unit).
    fn reset_gains(&mut self, cells: std::ops::Range<usize>) -> u64 {
        let mut visits = 0u64;
        for i in cells {
            self.gains[i] = self.gain_of(i);
            let (s, t) = self.cell_range(i);
            visits += 1 + (t - s) as u64;
        }
        visits.div_ceil(GAIN_VISITS_PER_UNIT)
    }

    /// The end of [`MapSearch::reset`]: the objective and a fresh history.
    fn reset_end(&mut self) {
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

/// Table 9.3's search being set up in pieces of bounded work, so that a
/// page's call on a fine map (the doorway at 1 cm: 200,000 cells) stops
/// within one piece of its budget (docs/ARCHITECTURE.md, "Sessions and
/// panes"): each beam's incidence (`search_incidence.rs`), its
/// transpose, the search's arrays, then every cell's gain a band of cells
/// at a time. The pieces compute what [`MapSearch::new`] computes, in the
/// same order: the search is the same bit for bit.
///
/// The unit of work is a raster step of a beam's sub-rays
/// ([`raster_work`]); the cheaper visits of the other pieces count a
/// fraction of a unit each, so that a page's budget learned from one
/// piece's time fits the next.
#[derive(Debug, Clone)]
pub struct MapSearchSetup {
    geometry: GridGeometry,
    settings: MapSearchSettings,
    beams: Vec<ConeBeam>,
    incidence: Option<IncidenceBuild>,
    search: Option<MapSearch>,
    /// Cells whose gain is computed.
    next_cell: usize,
}

/// A cell's gain visits the cell and each of its entries: this many
/// visits count as a unit.
const GAIN_VISITS_PER_UNIT: u64 = 2;
/// The search's arrays made (three of the map's size): this many cells
/// count as a unit.
const ARRAY_CELLS_PER_UNIT: u64 = 8;

impl MapSearchSetup {
    /// Validates the input (a refusal names the field and value, before
    /// anything is built).
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
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(work <= MAX_RASTER_WORK) {
            return Err(invalid(
                "beams x sub_rays x (z_max / resolution)",
                work,
                "at most 5e7 raster steps",
            ));
        }
        let cone = Cone {
            half_width: settings.half_width,
            sub_rays: settings.sub_rays,
        };
        Ok(Self {
            geometry,
            settings,
            beams,
            incidence: Some(IncidenceBuild::new(geometry, cone, model)),
            search: None,
            next_cell: 0,
        })
    }

    /// True once every piece is done: [`MapSearchSetup::finish`] then only
    /// sums the objective.
    pub fn done(&self) -> bool {
        self.search.is_some() && self.next_cell >= self.geometry.len()
    }

    /// Works pieces while the call has spent less than `budget` units (a
    /// budget of 0 counts as 1): at least one piece while there is one, and
    /// past the budget by at most one piece (a beam's raster, the
    /// transpose, the arrays made, or one cell's gain). Returns the units
    /// spent.
    pub fn work(&mut self, budget: u64) -> u64 {
        let budget = budget.max(1);
        let mut spent = 0u64;
        while spent < budget && !self.done() {
            spent = spent.saturating_add(self.piece(budget - spent));
        }
        spent
    }

    /// One piece of at most about `budget` units (at least one cell's
    /// gain); returns its units.
    fn piece(&mut self, budget: u64) -> u64 {
        if let Some(build) = &mut self.incidence {
            if !build.done() {
                return build.piece(&self.beams);
            }
        }
        let Some(search) = &mut self.search else {
            let Some(build) = self.incidence.take() else {
                return 0;
            };
            let inc = build.into_incidence();
            let n = self.geometry.len();
            let beams = self.beams.len();
            let mut search = MapSearch {
                geometry: self.geometry,
                settings: self.settings,
                l0: logit(self.settings.prior),
                occupied: vec![false; n],
                first: vec![NONE; beams],
                second: vec![NONE; beams],
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
                beams: std::mem::take(&mut self.beams),
            };
            search.reset_start();
            self.search = Some(search);
            return (n as u64).div_ceil(ARRAY_CELLS_PER_UNIT);
        };
        // A band of cells whose visits fit the budget, at least one.
        let (start, n) = (self.next_cell, self.geometry.len());
        let limit = budget.saturating_mul(GAIN_VISITS_PER_UNIT);
        let mut visits = 0u64;
        while self.next_cell < n && (self.next_cell == start || visits < limit) {
            let (s, t) = search.cell_range(self.next_cell);
            visits += 1 + (t - s) as u64;
            self.next_cell += 1;
        }
        search.reset_gains(start..self.next_cell)
    }

    /// The search at its all-free start, what is left of the setup done
    /// first.
    pub fn finish(mut self) -> Result<MapSearch> {
        self.work(u64::MAX);
        let Some(mut search) = self.search.take() else {
            return Err(invalid(
                "search",
                "unfinished",
                "a search set up to its end",
            ));
        };
        search.reset_end();
        Ok(search)
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
