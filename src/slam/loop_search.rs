//! Loop closure search: a scan matched against a finished submap over a
//! wide window by branch and bound (Olson 2009, "Real-time correlative
//! scan matching"; Hess et al. 2016, "Real-time loop closure in 2D LIDAR
//! SLAM", Algorithm 3), then refined to a fraction of a cell.
//!
//! The submap's cells are kept as occupancy probabilities in bytes
//! ([`LoopGrid`]: unknown cells score 0, so a scan placed over unexplored
//! space earns nothing). For a search, precomputed grids of depth `h` hold
//! at each cell the highest value of the `2^h x 2^h` cells from it
//! (Hess et al. 2016, eq. 14): a candidate offset covering `2^h` offsets in
//! x and y scores at most what its points read there, an upper bound of
//! every offset below it, and branches whose bound is under the best score
//! found (or the least score accepted) are never scored.
//!
//! A point scores a cell only if their surfaces can be one
//! ([`super::facing`]): a wall's two faces are never matched one on the
//! other.
//!
//! The headings are searched every `δθ`, the step that moves the farthest
//! point by about one cell (Hess et al. 2016, eq. 7); the best candidate is
//! then refined on bilinear reads of the same bytes, a quarter cell and a
//! quarter heading step at a time.

use super::facing::{
    pack_cell, strength, strength_facing, surface_normals, AgreementTable, Facing,
};
use super::packed_rows::PackedRows;
use crate::geometry::Pose;

/// Depth of the coarsest precomputed grid (cells of `2^7` = 128 cells: 6.4 m
/// at 5 cm).
const DEPTH: usize = 7;

/// What a read of the branch and bound and one of the refinement's
/// bilinear reads cost, in reads of a grid of maxima being made (the unit
/// of [`SearchUnderWay::work`]). Natively a read making a grid takes about
/// 0.9 ns, one of the branch and bound 3.6 to 3.8 ns (its reads fall
/// anywhere in the grid, each checked against the grid's edges), and a
/// bilinear read is four of those and its arithmetic.
const BOUND_READ_COST: u64 = 4;
const REFINE_READ_COST: u64 = 16;

/// A scan's points for loop search (sensor frame, in the scan's order)
/// and which way each one's surface faces: worked out once a scan, for
/// every submap it is searched against.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LoopScan {
    points: Vec<[f64; 2]>,
    facings: Vec<Facing>,
}

impl LoopScan {
    pub fn new(points: Vec<[f64; 2]>) -> Self {
        let facings = points
            .iter()
            .zip(surface_normals(&points))
            .map(|(p, normal)| match normal {
                Some(angle) => Facing {
                    angle,
                    by_beam: false,
                },
                None => Facing {
                    angle: (-p[1]).atan2(-p[0]),
                    by_beam: true,
                },
            })
            .collect();
        Self { points, facings }
    }

    pub fn points(&self) -> &[[f64; 2]] {
        &self.points
    }
}

/// A finished submap's cells for loop search: occupancy probabilities and
/// their surfaces' normals as bytes ([`pack_cell`]), unknown cells 0,
/// over the box of its known cells; and its grids of maxima once
/// a search has made them.
///
/// At rest its bytes are kept run-length coded ([`PackedRows`], a
/// quarter of their size on the campus); a search restores them first, a
/// slice of rows at a time (one read a cell).
///
/// A submap is searched again by every scan near it (Intel: a submap
/// about 40 times), and making its grids cost 28 reads a cell, far more
/// than a search's branch and bound: they are made once and kept
/// (Hess et al. 2016 precompute them once a submap is finished), with the
/// restored bytes, until their holder drops them to keep within a memory
/// budget ([`Self::drop_search_grids`]).
#[derive(Debug, Clone, PartialEq)]
pub struct LoopGrid {
    /// World coordinates of the corner of cell `(0, 0)`.
    pub origin: [f64; 2],
    pub resolution: f64,
    pub width: usize,
    pub height: usize,
    /// Bytes as [`pack_cell`] makes them, coded.
    packed: PackedRows,
    /// The same bytes restored, `restored` rows of them so far (all of
    /// them once a search has begun; none at rest).
    cells: Vec<u8>,
    restored: usize,
    /// The grids of depth `1..=levels.len()` made so far.
    levels: Vec<Vec<u8>>,
    /// The next one, while it is made a slice of rows at a time.
    making: Option<Making>,
}

/// A grid of maxima being made ([`LoopGrid::make_level_within`]): the
/// sliding maximum along the rows of the grid before it, `y` rows of
/// `rows` done; then (`columns`) along its columns, `y` rows of `out` done.
#[derive(Debug, Clone, PartialEq)]
struct Making {
    rows: Vec<u8>,
    out: Vec<u8>,
    y: usize,
    columns: bool,
}

/// The least reads a slice of a grid of maxima being made takes (about a
/// millisecond natively): a campus submap's grid is up to 2 million cells,
/// 8 million reads a grid, which made in one step held a page's call
/// 50 ms past its budget.
const LEVEL_STEP_READS: u64 = 1 << 20;

/// What a search found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopMatch {
    /// The scan's pose in the submap's frame.
    pub pose: Pose,
    /// Mean probability of its points' cells, 0 to 1.
    pub score: f64,
    /// Candidates scored.
    pub candidates: u64,
}

/// A search under way ([`LoopGrid::begin_search`]): the precomputed grids
/// made so far, the next heading, the best candidate so far.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchUnderWay {
    predicted: Pose,
    min_score: f64,
    /// The heading step, and the steps either way of the prediction.
    dtheta: f64,
    headings: i64,
    /// Cells either way in x and y.
    wxy: i64,
    /// The next heading searched, in steps from the prediction.
    heading: i64,
    /// (sum of the points' bytes, heading, dx, dy) of the best so far.
    best: Option<(f64, i64, i64, i64)>,
    candidates: u64,
    /// Reads so far, each weighed by its cost in reads of a grid of maxima
    /// being made (four a cell for each grid made; `BOUND_READ_COST` a
    /// point of a candidate, `REFINE_READ_COST` a point refined).
    pub work: u64,
    /// Nothing (left) to search: no points, no cells, or refined already.
    empty: bool,
}

/// The search window around a predicted pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopWindow {
    /// Metres either way in x and y.
    pub linear: f64,
    /// Radians either way.
    pub angular: f64,
    /// The least score a match is accepted with.
    pub min_score: f64,
}

impl LoopGrid {
    /// A grid of `width x height` probabilities as bytes (255 certain)
    /// from `origin` (world, metres), rows bottom first, their surfaces'
    /// normals not known; no grids of maxima yet.
    pub fn new(
        origin: [f64; 2],
        resolution: f64,
        width: usize,
        height: usize,
        probabilities: Vec<u8>,
    ) -> Self {
        let cells = probabilities
            .into_iter()
            .map(|p| pack_cell(p as f64 / 255.0, 0))
            .collect();
        Self::from_packed(origin, resolution, width, height, cells)
    }

    /// A grid of bytes as [`pack_cell`] makes them, put to rest.
    pub fn from_packed(
        origin: [f64; 2],
        resolution: f64,
        width: usize,
        height: usize,
        cells: Vec<u8>,
    ) -> Self {
        let (width, height) = if cells.len() == width * height {
            (width, height)
        } else {
            (0, 0)
        };
        Self {
            origin,
            resolution,
            width,
            height,
            packed: PackedRows::pack(&cells, width),
            cells: Vec::new(),
            restored: 0,
            levels: Vec::new(),
            making: None,
        }
    }

    /// Bytes held for searching: the restored bytes and the grids of
    /// maxima made so far.
    pub fn search_bytes(&self) -> usize {
        self.cells.len() + self.levels.iter().map(Vec::len).sum::<usize>()
    }

    /// Drops the restored bytes and the grids of maxima (a later search
    /// makes them again), keeping the coded bytes.
    pub fn drop_search_grids(&mut self) {
        self.cells = Vec::new();
        self.restored = 0;
        self.levels = Vec::new();
        self.making = None;
    }

    /// Every byte, rows bottom first: a copy decoded from the coded bytes.
    #[cfg(test)]
    pub(super) fn unpacked(&self) -> Vec<u8> {
        let w = self.width;
        let mut out = vec![0; w * self.height];
        for (y, row) in out.chunks_exact_mut(w.max(1)).enumerate() {
            self.packed.unpack_row(y, row);
        }
        out
    }

    /// True once every row of the bytes is restored.
    fn is_restored(&self) -> bool {
        self.restored == self.height
    }

    /// Restores rows of the bytes until `max_reads` reads (at least a
    /// row, one read a cell): the reads made.
    fn restore_within(&mut self, max_reads: u64) -> u64 {
        let w = self.width;
        if self.cells.len() != w * self.height {
            self.cells = vec![0; w * self.height];
            self.restored = 0;
        }
        let mut reads = 0;
        while self.restored < self.height {
            let y = self.restored;
            if let Some(row) = self.cells.get_mut(y * w..(y + 1) * w) {
                self.packed.unpack_row(y, row);
            }
            self.restored += 1;
            reads += w as u64;
            if reads >= max_reads {
                break;
            }
        }
        reads
    }

    /// The byte of a grid at a cell, rows bottom first (0 outside). (A
    /// negative index is a huge unsigned one: one comparison a side.)
    #[inline(always)]
    fn byte(&self, ix: i64, iy: i64, level: &[u8]) -> u8 {
        if ix as u64 >= self.width as u64 || iy as u64 >= self.height as u64 {
            return 0;
        }
        level
            .get(iy as usize * self.width + ix as usize)
            .copied()
            .unwrap_or(0)
    }

    /// Makes the next grid of maxima, of depth `d = levels.len() + 1`,
    /// from the one before (the cells themselves at depth 1), whole rows at
    /// a time until `max_reads` reads (at least a row): each cell the
    /// highest of the `2^d x 2^d` cells from it, by a sliding maximum along
    /// the rows then the columns of the grid before (`2^(d-1)` apart). Once
    /// its last row is made it joins the levels. The reads made (two a
    /// cell a pass: four a cell in all, however it is sliced).
    fn make_level_within(&mut self, max_reads: u64) -> u64 {
        let (w, h) = (self.width, self.height);
        let shift = 1usize << self.levels.len();
        let mut m = self.making.take().unwrap_or_else(|| Making {
            rows: vec![0u8; w * h],
            out: Vec::new(),
            y: 0,
            columns: false,
        });
        let prev: &[u8] = self.levels.last().unwrap_or(&self.cells);
        let mut reads = 0u64;
        loop {
            let y = m.y;
            if !m.columns {
                for x in 0..w {
                    let a = prev[y * w + x];
                    let b = if x + shift < w {
                        prev[y * w + x + shift]
                    } else {
                        0
                    };
                    m.rows[y * w + x] = a.max(b);
                }
            } else {
                for x in 0..w {
                    let a = m.rows[y * w + x];
                    let b = if y + shift < h {
                        m.rows[(y + shift) * w + x]
                    } else {
                        0
                    };
                    m.out[y * w + x] = a.max(b);
                }
            }
            reads += 2 * w as u64;
            m.y += 1;
            if m.y == h {
                if m.columns {
                    self.levels.push(m.out);
                    return reads;
                }
                m = Making {
                    out: vec![0u8; w * h],
                    y: 0,
                    columns: true,
                    ..m
                };
            }
            if reads >= max_reads {
                self.making = Some(m);
                return reads;
            }
        }
    }

    /// Bilinear read of the probabilities at world `(x, y)`, 0 to 1, as a
    /// point agreeing with the normals `agreeing` scores them
    /// ([`codes_agreeing`]).
    fn bilinear(&self, x: f64, y: f64, agreeing: u16) -> f64 {
        let fx = (x - self.origin[0]) / self.resolution - 0.5;
        let fy = (y - self.origin[1]) / self.resolution - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let (ix, iy) = (x0 as i64, y0 as i64);
        let v = |dx: i64, dy: i64| {
            strength_facing(self.byte(ix + dx, iy + dy, &self.cells), agreeing) as f64
        };
        let bottom = v(0, 0) * (1.0 - tx) + v(1, 0) * tx;
        let top = v(0, 1) * (1.0 - tx) + v(1, 1) * tx;
        (bottom * (1.0 - ty) + top * ty) / 255.0
    }

    /// Bytes held: coded, and for searching.
    pub fn bytes(&self) -> usize {
        self.packed.bytes() + self.search_bytes()
    }

    /// Searches `scan`'s points (sensor frame) around `predicted` (in this
    /// submap's frame) within `window`: the best match scoring at least
    /// the window's least score, or `None`; and the work ([`SearchUnderWay::work`]).
    pub fn search(
        &mut self,
        scan: &LoopScan,
        predicted: &Pose,
        window: &LoopWindow,
    ) -> (Option<LoopMatch>, u64) {
        let mut search = self.begin_search(scan, predicted, window);
        loop {
            if let Some(found) = self.continue_search(&mut search, scan, u64::MAX) {
                return (found, search.work);
            }
        }
    }

    /// A search of `scan` as [`Self::search`] makes it, not yet begun:
    /// [`Self::continue_search`] runs it a bounded step at a time.
    pub fn begin_search(
        &self,
        scan: &LoopScan,
        predicted: &Pose,
        window: &LoopWindow,
    ) -> SearchUnderWay {
        let points = scan.points();
        let res = self.resolution;
        let reach = points
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(0.0, f64::max)
            .max(res);
        // The heading step that moves the farthest point by a cell.
        let dtheta = (1.0 - res * res / (2.0 * reach * reach))
            .clamp(-1.0, 1.0)
            .acos()
            .max(1e-4);
        let headings = (window.angular / dtheta).ceil() as i64;
        SearchUnderWay {
            predicted: *predicted,
            min_score: window.min_score,
            dtheta,
            headings,
            wxy: (window.linear / res).ceil() as i64,
            heading: -headings,
            best: None,
            candidates: 0,
            work: 0,
            empty: points.is_empty() || self.width * self.height == 0,
        }
    }

    /// Goes on with `search` (begun by [`Self::begin_search`] on this grid
    /// and this `scan`) until its work in this call reaches `budget`, a
    /// step at a time: rows of a grid of maxima not yet kept (at least
    /// `LEVEL_STEP_READS` reads, or what is left of the budget; four reads
    /// a cell in all), or the branch and bound of one heading. The match
    /// (or `None`) once the
    /// search is over, `search.work` then its whole work; the steps are the
    /// ones [`Self::search`] takes in one call, in the same order, so the
    /// match is the same bit for bit.
    pub fn continue_search(
        &mut self,
        search: &mut SearchUnderWay,
        scan: &LoopScan,
        budget: u64,
    ) -> Option<Option<LoopMatch>> {
        if search.empty {
            return Some(None);
        }
        let limit = search.work.saturating_add(budget);
        loop {
            let left = limit.saturating_sub(search.work).max(LEVEL_STEP_READS);
            if !self.is_restored() {
                search.work += self.restore_within(left);
            } else if self.levels.len() < DEPTH {
                search.work += self.make_level_within(left);
            } else if search.heading <= search.headings {
                let hi = search.heading;
                search.heading += 1;
                let candidates = self.search_heading(search, scan, hi);
                search.candidates += candidates;
                search.work += candidates * scan.points.len() as u64 * BOUND_READ_COST;
            } else {
                return Some(self.finish_search(search, scan));
            }
            if search.work >= limit {
                return None;
            }
        }
    }

    /// Branch and bound over the offsets of heading `hi` (steps of
    /// `dtheta` from the prediction), the best so far kept in `search`:
    /// the candidates scored.
    fn search_heading(&self, search: &mut SearchUnderWay, scan: &LoopScan, hi: i64) -> u64 {
        let points = scan.points();
        let agreement = AgreementTable::get();
        let res = self.resolution;
        let predicted = search.predicted;
        let wxy = search.wxy;
        let levels = &self.levels;
        let top = 1i64 << DEPTH;
        let mut candidates = 0u64;
        let n = points.len() as f64;
        let min_total = search.min_score * 255.0 * n;
        let mut best = search.best;
        let theta = predicted.theta + hi as f64 * search.dtheta;
        let (s, c) = theta.sin_cos();
        // Each point's cell, and its place among the scan's points. A
        // point that no offset of the window brings within reach of the
        // grid reads 0 at every depth and is left out: the sums are the
        // same, and on the campus a search's points fall outside the
        // submap's box as often as in it.
        let (w, h) = (self.width as i64, self.height as i64);
        let near = |v: i64, side: i64| v > -top - wxy && v < side + wxy;
        let cells: Vec<(i64, i64, usize)> = points
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let x = predicted.x + c * p[0] - s * p[1];
                let y = predicted.y + s * p[0] + c * p[1];
                (
                    ((x - self.origin[0]) / res).floor() as i64,
                    ((y - self.origin[1]) / res).floor() as i64,
                    k,
                )
            })
            .filter(|&(x, y, _)| near(x, w) && near(y, h))
            .collect();
        // The normal codes each point may score against, worked out only
        // if a candidate of this heading gets down to single offsets: most
        // headings are cut off higher.
        let agreeing = std::cell::OnceCell::new();
        let score = |depth: usize, dx: i64, dy: i64| -> u64 {
            if depth == 0 {
                let agreeing: &Vec<u16> = agreeing.get_or_init(|| {
                    cells
                        .iter()
                        .map(|&(_, _, k)| agreement.at(&scan.facings[k], theta))
                        .collect()
                });
                return cells
                    .iter()
                    .zip(agreeing)
                    .map(|(&(x, y, _), &agreeing)| {
                        strength_facing(self.byte(x + dx, y + dy, &self.cells), agreeing) as u64
                    })
                    .sum();
            }
            let level: &[u8] = &levels[depth - 1];
            // A window starting left of (below) the grid but reaching
            // into it is bounded by the grid's first column (row),
            // whose window holds its part.
            let reach = 1i64 << depth;
            let pull = |v: i64| if v < 0 && v > -reach { 0 } else { v };
            // The bytes' probabilities summed in sixteenths, then scaled
            // once ([`strength`]).
            let sixteenths: u64 = cells
                .iter()
                .map(|&(x, y, _)| (self.byte(pull(x + dx), pull(y + dy), level) >> 4) as u64)
                .sum();
            sixteenths * strength(1 << 4) as u64
        };
        // Roots: offsets every 2^DEPTH cells over the window.
        let mut stack: Vec<(u64, usize, i64, i64)> = Vec::new();
        let mut roots = Vec::new();
        let mut y = -wxy;
        while y <= wxy {
            let mut x = -wxy;
            while x <= wxy {
                roots.push((score(DEPTH, x, y), DEPTH, x, y));
                candidates += 1;
                x += top;
            }
            y += top;
        }
        // Lowest first on the stack, so the best is taken first.
        roots.sort_by(|a, b| a.0.cmp(&b.0).then((a.2, a.3).cmp(&(b.2, b.3))));
        stack.extend(roots);
        while let Some((bound, depth, x, y)) = stack.pop() {
            let beaten = best.is_some_and(|b: (f64, i64, i64, i64)| bound as f64 <= b.0);
            if beaten || (bound as f64) < min_total {
                continue;
            }
            if depth == 0 {
                best = Some((bound as f64, hi, x, y));
                continue;
            }
            let half = 1i64 << (depth - 1);
            let mut children = Vec::with_capacity(4);
            for (cx, cy) in [(x, y), (x + half, y), (x, y + half), (x + half, y + half)] {
                if cx > wxy || cy > wxy {
                    continue;
                }
                children.push((score(depth - 1, cx, cy), depth - 1, cx, cy));
                candidates += 1;
            }
            children.sort_by(|a, b| a.0.cmp(&b.0).then((a.2, a.3).cmp(&(b.2, b.3))));
            stack.extend(children);
        }
        search.best = best;
        candidates
    }

    /// The best candidate of every heading refined: the match, if any.
    fn finish_search(&self, search: &mut SearchUnderWay, scan: &LoopScan) -> Option<LoopMatch> {
        let (_, hi, dx, dy) = search.best?;
        let res = self.resolution;
        let predicted = search.predicted;
        let coarse = Pose {
            x: predicted.x + dx as f64 * res,
            y: predicted.y + dy as f64 * res,
            theta: predicted.theta + hi as f64 * search.dtheta,
        };
        let (pose, score, refined) = self.refine(scan, coarse, res, search.dtheta);
        search.work += refined * scan.points.len() as u64 * REFINE_READ_COST;
        // Refined once: a later call finds the search over.
        search.best = None;
        search.empty = true;
        Some(LoopMatch {
            pose,
            score,
            candidates: search.candidates + refined,
        })
    }

    /// The best of the poses a quarter cell and a quarter heading step
    /// apart around `start`, twice, on bilinear reads.
    fn refine(&self, scan: &LoopScan, start: Pose, res: f64, dtheta: f64) -> (Pose, f64, u64) {
        let (points, facings) = (scan.points(), &scan.facings);
        let agreement = AgreementTable::get();
        let mean = |pose: &Pose| {
            let (s, c) = pose.theta.sin_cos();
            points
                .iter()
                .zip(facings)
                .map(|(p, facing)| {
                    let (x, y) = (pose.x + c * p[0] - s * p[1], pose.y + s * p[0] + c * p[1]);
                    self.bilinear(x, y, agreement.at(facing, pose.theta))
                })
                .sum::<f64>()
                / points.len() as f64
        };
        let mut best = (start, mean(&start));
        let mut scored = 1u64;
        let (mut step, mut turn) = (0.5 * res, 0.5 * dtheta);
        for _ in 0..3 {
            let centre = best.0;
            for i in -1i32..=1 {
                for j in -1i32..=1 {
                    for k in -1i32..=1 {
                        if i == 0 && j == 0 && k == 0 {
                            continue;
                        }
                        let pose = Pose {
                            x: centre.x + i as f64 * step,
                            y: centre.y + j as f64 * step,
                            theta: centre.theta + k as f64 * turn,
                        };
                        let v = mean(&pose);
                        scored += 1;
                        if v > best.1 {
                            best = (pose, v);
                        }
                    }
                }
            }
            step *= 0.5;
            turn *= 0.5;
        }
        (best.0, best.1, scored)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An L of walls found again 0.4 m and 3° off.
    #[test]
    fn branch_and_bound_finds_an_offset_corner() {
        let (w, h, res) = (200usize, 200usize, 0.05);
        let mut cells = vec![0u8; w * h];
        for i in 20..180 {
            cells[20 * w + i] = 250;
            cells[i * w + 20] = 250;
        }
        let mut grid = LoopGrid::new([0.0, 0.0], res, w, h, cells);
        // Points of the two walls seen from (5, 5), heading 0.
        let mut points = Vec::new();
        for i in 0..60 {
            let t = 1.025 + i as f64 * 0.1;
            points.push([t - 5.0, 1.025 - 5.0]);
            points.push([1.025 - 5.0, t - 5.0]);
        }
        let scan = LoopScan::new(points);
        let predicted = Pose {
            x: 5.4,
            y: 4.7,
            theta: 0.05,
        };
        let window = LoopWindow {
            linear: 1.0,
            angular: 0.1,
            min_score: 0.5,
        };
        let (found, whole_work) = grid.search(&scan, &predicted, &window);
        let found = found.expect("a match");
        assert!(
            (found.pose.x - 5.0).abs() < 0.03 && (found.pose.y - 5.0).abs() < 0.03,
            "{found:?}"
        );
        assert!(found.pose.theta.abs() < 0.01, "{found:?}");
        // The same search a bounded step at a time: the same match, bit
        // for bit, and the same work; no call past its budget by more than
        // one step (a slice of a grid of maxima, or one heading).
        let budget = 30_000;
        let step = (w * h * 4) as u64;
        grid.drop_search_grids();
        let mut sliced = grid.begin_search(&scan, &predicted, &window);
        let (mut calls, mut before) = (0, 0);
        let again = loop {
            let done = grid.continue_search(&mut sliced, &scan, budget);
            calls += 1;
            assert!(
                sliced.work - before < budget + step,
                "{} in a call",
                sliced.work - before
            );
            before = sliced.work;
            if let Some(again) = done {
                break again;
            }
        };
        assert!(calls > DEPTH, "{calls} calls");
        let again = again.expect("the same match");
        assert_eq!(
            [again.pose.x, again.pose.y, again.pose.theta, again.score].map(f64::to_bits),
            [found.pose.x, found.pose.y, found.pose.theta, found.score].map(f64::to_bits)
        );
        assert_eq!(again.candidates, found.candidates);
        assert_eq!(sliced.work, whole_work);
    }

    /// A grid of maxima made a row at a time is the one made at once, and
    /// costs the same reads: four a cell, however it is sliced.
    #[test]
    fn a_grid_of_maxima_made_in_slices_is_the_one_made_at_once() {
        let (w, h) = (97usize, 61usize);
        let cells: Vec<u8> = (0..w * h)
            .map(|i| ((i * 7919 + (i / w) * 104_729) % 251) as u8)
            .collect();
        let mut whole = LoopGrid::new([0.0, 0.0], 0.05, w, h, cells.clone());
        let mut sliced = LoopGrid::new([0.0, 0.0], 0.05, w, h, cells);
        assert_eq!(whole.restore_within(u64::MAX), (w * h) as u64);
        let (mut reads, mut slices) = (0, 0);
        while !sliced.is_restored() {
            reads += sliced.restore_within(1);
            slices += 1;
        }
        assert_eq!((reads, slices), ((w * h) as u64, h));
        assert_eq!(sliced.cells, whole.cells);
        for depth in 1..=DEPTH {
            assert_eq!(whole.make_level_within(u64::MAX), (4 * w * h) as u64);
            let (mut reads, mut slices) = (0, 0);
            while sliced.levels.len() < depth {
                reads += sliced.make_level_within(1);
                slices += 1;
            }
            assert_eq!((reads, slices), ((4 * w * h) as u64, 2 * h));
            assert_eq!(sliced.levels, whole.levels);
        }
        // A cell of depth 2 is the highest of the 4 x 4 cells from it.
        let at = |x: usize, y: usize| whole.cells[y * w + x];
        let highest = (0..4)
            .flat_map(|dy| (0..4).map(move |dx| (dx, dy)))
            .map(|(dx, dy)| at(10 + dx, 20 + dy))
            .max()
            .unwrap();
        assert_eq!(whole.levels[1][20 * w + 10], highest);
    }

    /// At rest a grid keeps its bytes coded: a room's walls in a box of
    /// unknown take a small share of its cells. A search restores them
    /// (and makes its grids of maxima); dropping those leaves the coded
    /// bytes, from which the next search restores the same cells.
    #[test]
    fn a_grid_at_rest_keeps_its_bytes_coded_and_a_search_restores_them() {
        let (w, h) = (400usize, 300usize);
        let mut cells = vec![0u8; w * h];
        for i in 100..300 {
            cells[120 * w + i] = 250;
            cells[(i - 50) * w + 100] = 250;
        }
        for y in 121..250 {
            cells[y * w + 101..y * w + 300].fill(12);
        }
        let mut grid = LoopGrid::new([0.0, 0.0], 0.05, w, h, cells.clone());
        let at_rest = grid.bytes();
        assert!(at_rest < w * h / 20, "{at_rest} bytes of {}", w * h);
        assert_eq!(grid.search_bytes(), 0);
        let restored = (w * h) as u64;
        assert_eq!(grid.restore_within(u64::MAX), restored);
        let packed = |v: u8| pack_cell(v as f64 / 255.0, 0);
        assert!(grid.cells.iter().zip(&cells).all(|(&c, &v)| c == packed(v)));
        assert_eq!(grid.cells, grid.unpacked());
        grid.drop_search_grids();
        assert_eq!(grid.bytes(), at_rest);
    }

    /// made: the same match bit for bit, at the work of the branch and
    /// bound alone; once dropped, they are made again.
    #[test]
    fn a_second_search_reuses_the_grids_of_maxima() {
        let (w, h, res) = (160usize, 120usize, 0.05);
        let mut cells = vec![0u8; w * h];
        for i in 10..150 {
            cells[10 * w + i] = 240;
        }
        for j in 10..110 {
            cells[j * w + 10] = 240;
            cells[j * w + 120] = 200;
        }
        let mut grid = LoopGrid::new([0.0, 0.0], res, w, h, cells);
        let points: Vec<[f64; 2]> = (0..50)
            .flat_map(|i| {
                let t = 0.6 + i as f64 * 0.1;
                [
                    [t - 3.0, 0.525 - 3.0],
                    [0.525 - 3.0, 0.6 + i as f64 * 0.08 - 3.0],
                ]
            })
            .collect();
        let scan = LoopScan::new(points);
        let predicted = Pose {
            x: 3.2,
            y: 2.9,
            theta: -0.03,
        };
        let window = LoopWindow {
            linear: 0.8,
            angular: 0.08,
            min_score: 0.4,
        };
        assert_eq!(grid.search_bytes(), 0);
        let (first, first_work) = grid.search(&scan, &predicted, &window);
        // The bytes restored (a read a cell), the grids made (four a cell).
        let made = ((1 + 4 * DEPTH) * w * h) as u64;
        assert_eq!(grid.search_bytes(), (1 + DEPTH) * w * h);
        let (second, second_work) = grid.search(&scan, &predicted, &window);
        let (first, second) = (first.expect("a match"), second.expect("a match"));
        assert_eq!(
            [
                second.pose.x,
                second.pose.y,
                second.pose.theta,
                second.score
            ]
            .map(f64::to_bits),
            [first.pose.x, first.pose.y, first.pose.theta, first.score].map(f64::to_bits)
        );
        assert_eq!(
            second_work,
            first_work - made,
            "the second search made no grid"
        );
        grid.drop_search_grids();
        assert_eq!(grid.search_bytes(), 0);
        assert_eq!(grid.search(&scan, &predicted, &window).1, first_work);
    }
}
