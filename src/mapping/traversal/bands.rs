//! The traversal of beams that state their evidence as bands
//! ([`BeamBand`]), with or without the free space between neighbouring
//! beams: the real-log path (docs/ARCHITECTURE.md, "Real logs").

use super::fans::Fans;
use super::{
    between, trace, BandCodes, BeamBand, BeamFrame, Gathered, RayMapper, ScanEvidence, ScanStats,
    MAX_REACH_CELLS,
};
use crate::grid::{CellModel, Grid, Store};
use crate::sensors::Scan;

impl RayMapper {
    /// Integrates one scan whose beams each state their evidence as a
    /// [`BeamBand`] (`bands[i]` for beam `i`, `None` for a beam with nothing
    /// to walk), every beam with the same `free` (< 0) and `occupied` (> 0)
    /// log odds net of `l0`. Cells are gathered and updated once per scan,
    /// occupied winning, as in [`Self::integrate`]; with each band built
    /// from Table 9.2's axis profile (no gap) the map is bit for bit the
    /// one `integrate` makes. On a store that gathers in a window around
    /// the sensor ([`Store::WINDOWED`]), a beam reaching more than
    /// [`MAX_REACH_CELLS`] is not walked (the caller's settings refuse it
    /// first).
    pub fn integrate_bands<C: CellModel, S: Store<C::Cell>>(
        &mut self,
        grid: &mut Grid<C, S>,
        scan: &Scan,
        bands: &[Option<BeamBand>],
        free: f32,
        occupied: f32,
    ) -> ScanStats {
        self.integrate_bands_between(grid, scan, bands, (free, occupied), false)
    }

    /// [`Self::integrate_bands`], and with `between` the free space between
    /// neighbouring beams too: Table 9.2 gives a cell evidence when it lies
    /// within `β/2` of a beam's bearing, and a scanner's beams are as wide
    /// as their spacing `δφ`, so a cell between two beams' axes, nearer than
    /// both their free ranges, is free. The axes of neighbouring beams part
    /// by more than a cell beyond `res / δφ` (2.9 m for 1° at 5 cm), and
    /// the cells a supercover walk leaves between them are the gray
    /// pinholes of thinly covered floor; one more walk along the bisector of
    /// each pair, from there out to twice that range (or the nearer free
    /// range), covers them; each further level doubles the walks (at odd
    /// multiples of a quarter, then an eighth of the angle) and the range:
    /// three levels fill out to eight times it, 23 m for 1° and 46 m for
    /// 0.5° at 5 cm. Their cells join the scan's verdicts, so each cell is
    /// still updated once per scan. (The third level took the Infinite
    /// Corridor's pinholes from 1.21 to 0.82 per 1,000 free cells and the
    /// campus's from 1.48 to 0.92, for 4.4 % more cell updates on the
    /// campus; docs/ARCHITECTURE.md, "Real logs".) Where two neighbouring
    /// beams end on one surface (readings close enough not to be a depth
    /// jump), the arc of the beams' width between the two readings is
    /// occupied too: a wall seen from afar, its readings several cells
    /// apart, is drawn whole instead of in dots.
    pub fn integrate_bands_between<C: CellModel, S: Store<C::Cell>>(
        &mut self,
        grid: &mut Grid<C, S>,
        scan: &Scan,
        bands: &[Option<BeamBand>],
        (free, occupied): (f32, f32),
        between: bool,
    ) -> ScanStats {
        if !(free < 0.0 && occupied > 0.0) {
            // Not this path's kind of evidence (the caller checks its
            // settings): no update rather than a wrong one.
            return ScanStats::default();
        }
        let res = grid.geometry().resolution();
        let walkable = |r: f64| r > 0.0 && (!S::WINDOWED || r / res <= MAX_REACH_CELLS);
        let reach = bands
            .iter()
            .flatten()
            .map(|b| b.reach)
            .filter(|&r| walkable(r))
            .fold(0.0, f64::max);
        let Some(frame) = BeamFrame::new::<C, S>(grid.geometry(), &scan.pose(), reach) else {
            return ScanStats::default();
        };
        // A windowed map gathers by segment (see `Gathered`); a dense one
        // in a touched list, as every other path does.
        let frame = if S::WINDOWED {
            frame.in_segments()
        } else {
            frame
        };
        self.cache_bearing_trig(scan.bearings());
        self.wedges.clear();
        if between {
            between::plan_wedges(bands, scan.bearings(), res, walkable, &mut self.wedges);
        }
        let evidence = ScanEvidence { free, occupied };
        let mut plan = BandsPlan {
            frame: &frame,
            bands,
            bearings: scan.bearings(),
            trig: &self.bearing_trig,
            wedges: &self.wedges,
            fans: &mut self.fans,
            between,
            res,
        };
        // The walk is the same whatever the cell model (compiled once per
        // way of gathering); only settling the verdicts into the map is
        // the model's.
        let (cells_visited, cells_updated) = if S::WINDOWED {
            let gathered = frame.segment_codes(&mut self.codes, &mut self.segments);
            let (visits, gathered) = plan.gather(gathered, true);
            (visits, gathered.settle(grid, &frame.window, evidence))
        } else {
            let gathered = frame.codes(&mut self.codes, &mut self.touched);
            let (visits, gathered) = plan.gather(gathered, false);
            (visits, gathered.settle(grid, &frame.window, evidence))
        };
        ScanStats {
            cells_visited,
            cells_updated,
        }
    }
}

/// One scan's bands on the way to the map: what
/// [`RayMapper::integrate_bands_between`] walks and fills.
struct BandsPlan<'p> {
    frame: &'p BeamFrame,
    bands: &'p [Option<BeamBand>],
    bearings: &'p [f64],
    trig: &'p [(f64, f64)],
    wedges: &'p [Option<between::Wedge>],
    fans: &'p mut Fans,
    between: bool,
    res: f64,
}

impl BandsPlan<'_> {
    /// Walks the beams (the wedges' spans left out), fills the wedges and
    /// draws the walls between: the cells visited and the verdicts
    /// gathered, at most one per cell. On a `windowed` map a beam past the
    /// window's reach is not walked.
    fn gather<'g, const SEGMENTED: bool>(
        &mut self,
        mut gathered: Gathered<'g, u8, SEGMENTED>,
        windowed: bool,
    ) -> (usize, Gathered<'g, u8, SEGMENTED>) {
        let (frame, res) = (self.frame, self.res);
        let walkable = |r: f64| r > 0.0 && (!windowed || r / res <= MAX_REACH_CELLS);
        let mut visits = 0;
        if self.between {
            // The fans near the sensor and far out (`fans`): a beam inside
            // a near fan is then walked only where its cells may leave it,
            // and a wedge inside a far fan filled only beyond it.
            let n;
            (n, gathered) = self
                .fans
                .fill(frame, self.wedges, self.bearings, self.trig, gathered);
            visits += n;
        }
        for (i, (band, &trig)) in self.bands.iter().zip(self.trig).enumerate() {
            let Some(b) = *band else { continue };
            if !walkable(b.reach) {
                continue;
            }
            // Where the wedges on both sides hold the beam's middle cells,
            // only its near part and its tail are walked; where a fan holds
            // part of it (`held`, empty without the space between beams),
            // that part is not walked either.
            let (held_from, held_to) = self.fans.held(i);
            let spans = match between::beam_spans(self.wedges, i, res) {
                // The fan holds the near part out to the wedges' start.
                Some((near, tail)) => [(0.0, near.min(held_from)), (tail, b.reach)],
                None if held_from < held_to => [(0.0, held_from), (held_to, b.reach)],
                None => {
                    let Some((walk, at)) = frame.beam(trig, b.reach) else {
                        continue;
                    };
                    let n;
                    (n, gathered) = trace(walk, at, BandCodes(b), gathered);
                    visits += n;
                    continue;
                }
            };
            for (from, to) in spans {
                let Some((walk, at)) = frame.segment(trig, from, to) else {
                    continue;
                };
                let n;
                (n, gathered) = trace(walk, at, BandCodes(b), gathered);
                visits += n;
            }
        }
        if self.between {
            let n;
            (n, gathered) = between::trace_between(
                frame,
                self.bands,
                self.bearings,
                self.trig,
                self.wedges,
                |k, from| self.fans.wedge_from(k, from),
                walkable,
                gathered,
            );
            visits += n;
        }
        (visits, gathered)
    }
}
