//! The beam–cell incidence of Table 9.3's MAP search
//! (`map_search`), built on the empty map in bounded pieces.
//!
//! Occupancy decides where a ray stops, never where it goes, so the cells a
//! beam can ever depend on are those its sub-ray rasters cross, each at the
//! smallest range at which a sub-ray enters it; every possible expected
//! range `z*` is one of those ranges, so the beam's log likelihood is
//! tabulated once for each. A fine map has many such cells (the doorway at
//! 1 cm: 63 beams, 290,000 entries), so the build goes a beam per piece,
//! then the transpose (each cell's entries) in one piece: a page's call
//! stops within one piece of its budget (docs/ARCHITECTURE.md, "Sessions
//! and panes"), and the pieces give the incidence one call gives.

use crate::geometry::raster::{entry_parameter, raster_work, supercover};
use crate::geometry::GridGeometry;
use crate::sensors::beam_model::BeamModel;
use crate::sensors::scan::ConeBeam;

/// A density the model calls (numerically) impossible is floored here before
/// its logarithm, so that every objective stays finite and comparable.
const MIN_DENSITY: f64 = 1e-300;

/// The transpose visits every cell and every entry once, each far cheaper
/// than a raster step (the unit of a beam's piece): this many of them count
/// as one unit.
const TRANSPOSE_VISITS_PER_UNIT: u64 = 8;

/// The cone each beam covers (the search's settings): half its opening
/// angle, radians, and the sub-rays spread evenly across it, edges
/// included (Table 6.1). It reaches the forward model's `z_max`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Cone {
    pub half_width: f64,
    pub sub_rays: usize,
}

/// The beam–cell incidence of Table 9.3's search, in compressed rows.
#[derive(Debug, Clone)]
pub(super) struct Incidence {
    /// Beam `b`'s entries are `beam_start[b]..beam_start[b + 1]`, sorted by
    /// range.
    pub beam_start: Vec<u32>,
    pub entry_cell: Vec<u32>,
    pub entry_beam: Vec<u32>,
    /// Range (metres) at which the cone first enters the entry's cell.
    pub entry_range: Vec<f64>,
    /// `log p(z_b | z* = entry_range)`, nats.
    pub entry_log_lik: Vec<f64>,
    /// `log p(z_b | z* = z_max)`: the beam on an empty cone.
    pub empty_log_lik: Vec<f64>,
    /// Cell `i`'s entries (global entry indices) are
    /// `cell_entries[cell_start[i]..cell_start[i + 1]]`.
    pub cell_start: Vec<u32>,
    pub cell_entries: Vec<u32>,
}

/// The incidence being built: the beams rastered so far, then the
/// transpose.
#[derive(Debug, Clone)]
pub(super) struct IncidenceBuild {
    geometry: GridGeometry,
    cone: Cone,
    model: BeamModel,
    /// Beams rastered so far.
    next_beam: usize,
    inc: Incidence,
    /// Per cell, the smallest entry range seen for the current beam.
    best: Vec<f64>,
    touched: Vec<usize>,
    transposed: bool,
}

impl IncidenceBuild {
    /// Cone, model, beams and geometry already checked by the search.
    pub fn new(geometry: GridGeometry, cone: Cone, model: BeamModel) -> Self {
        Self {
            geometry,
            cone,
            model,
            next_beam: 0,
            inc: Incidence {
                beam_start: Vec::new(),
                entry_cell: Vec::new(),
                entry_beam: Vec::new(),
                entry_range: Vec::new(),
                entry_log_lik: Vec::new(),
                empty_log_lik: Vec::new(),
                cell_start: Vec::new(),
                cell_entries: Vec::new(),
            },
            best: Vec::new(),
            touched: Vec::new(),
            transposed: false,
        }
    }

    pub fn done(&self) -> bool {
        self.transposed
    }

    /// The units of rastering one beam (its sub-rays' raster steps).
    pub fn beam_units(&self) -> u64 {
        let z_max = self.model.params().z_max;
        raster_work(1, self.cone.sub_rays, z_max, self.geometry.resolution()).ceil() as u64
    }

    /// One piece: the next beam of `beams` rastered, or, once every beam
    /// is, the transpose. Returns its units.
    pub fn piece(&mut self, beams: &[ConeBeam]) -> u64 {
        if let Some(beam) = beams.get(self.next_beam) {
            self.raster_beam(beam);
            self.next_beam += 1;
            return self.beam_units();
        }
        if self.transposed {
            return 0;
        }
        self.inc.beam_start.push(self.inc.entry_cell.len() as u32);
        self.transpose();
        self.transposed = true;
        self.best = Vec::new();
        ((self.geometry.len() + self.inc.entry_cell.len()) as u64)
            .div_ceil(TRANSPOSE_VISITS_PER_UNIT)
    }

    /// The incidence, once [`IncidenceBuild::done`].
    pub fn into_incidence(self) -> Incidence {
        self.inc
    }

    /// Rasters `beam`'s sub-rays on the empty map and tabulates the log
    /// likelihood of each possible expected range.
    fn raster_beam(&mut self, beam: &ConeBeam) {
        let geometry = &self.geometry;
        let (w, h) = (geometry.width(), geometry.height());
        let res = geometry.resolution();
        let z_max = self.model.params().z_max;
        let n_rays = self.cone.sub_rays;
        let model = &self.model;
        let log_density = |z: f64, z_star: f64| model.density(z, z_star).max(MIN_DENSITY).ln();
        if self.best.is_empty() {
            self.best = vec![f64::INFINITY; geometry.len()];
        }
        let b = self.next_beam;
        let inc = &mut self.inc;
        let (best, touched) = (&mut self.best, &mut self.touched);
        inc.beam_start.push(inc.entry_cell.len() as u32);
        let (su, sv) = geometry.world_to_grid(beam.pose.x, beam.pose.y);
        let axis = beam.pose.theta + beam.bearing;
        for k in 0..n_rays {
            // The same spread of sub-rays as World::cast_cone.
            let f = if n_rays == 1 {
                0.0
            } else {
                -1.0 + 2.0 * k as f64 / (n_rays - 1) as f64
            };
            let (s, c) = (axis + f * self.cone.half_width).sin_cos();
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
        crate::geometry::order::sort_keyed(&mut cells);
        for &(r, i) in &cells {
            best[i] = f64::INFINITY;
            inc.entry_cell.push(i as u32);
            inc.entry_beam.push(b as u32);
            inc.entry_range.push(r);
            inc.entry_log_lik.push(log_density(beam.range, r));
        }
        inc.empty_log_lik.push(log_density(beam.range, z_max));
    }

    /// The transpose: for every cell, the entries (beam, range) it has.
    fn transpose(&mut self) {
        let inc = &mut self.inc;
        let n = self.geometry.len();
        let mut cell_start = vec![0u32; n + 1];
        for &i in &inc.entry_cell {
            cell_start[i as usize + 1] += 1;
        }
        for i in 0..n {
            cell_start[i + 1] += cell_start[i];
        }
        let mut fill = cell_start.clone();
        let mut cell_entries = vec![0u32; inc.entry_cell.len()];
        for (e, &i) in inc.entry_cell.iter().enumerate() {
            let slot = &mut fill[i as usize];
            cell_entries[*slot as usize] = e as u32;
            *slot += 1;
        }
        inc.cell_start = cell_start;
        inc.cell_entries = cell_entries;
    }
}
