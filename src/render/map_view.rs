//! What a reader sees of a map, kept up to date at the cost of what changed.
//!
//! Between the mapper and the page (docs/ARCHITECTURE.md, "Sessions and panes": "map pixels through a view
//! into wasm memory"): after each scan a [`MapView`] compares the grid's
//! cells with the values it last drew and, for the cells that changed only,
//! redraws the pixel and rescores the cell's entropy (bits) and squared
//! error against the ground truth ([`MapScores`], the map's scores kept
//! cell by cell). A scan of the apartment changes about a tenth of the map,
//! so this costs far less than redrawing and rescoring every cell. A view
//! shows a map of any storage and cell model; for a model that holds log
//! odds ([`CellModel::held_log_odds`]) it needs no exponential or logarithm
//! per cell:
//!
//! * pixels come from [`gray_level`], which finds a cell's gray level by
//!   a binary search over the 255 exact log-odds thresholds of the ramp
//!   (bit for bit what [`super::gray::ramp_gray`] gives);
//! * `p` and `H_b(p)` come from a table over the log odds, linearly
//!   interpolated ([`cell_look`]; error below 1e-6 per cell, see the
//!   test). The same table holds each bin's gray level and the one ramp
//!   threshold inside it, so drawing a cell is one comparison.
//!
//! A model read through its probability is drawn and scored with the
//! exact formulas ([`probability_gray`], [`binary_entropy_bits`]).

use crate::error::Result;
use crate::geometry::GridGeometry;
use crate::grid::stats::MapScores;
use crate::grid::{binary_entropy_bits, probability, CellModel, Grid, Store, StoredCell};
use std::sync::OnceLock;

use super::gray::{gray_level, probability_gray, thresholds, UNKNOWN_GRAY};

/// Log-odds range of the cell table; beyond it cells are drawn and scored
/// with the exact formulas.
const TABLE_RANGE: f32 = 32.0;
/// Table bins per unit of log odds. The ramp falls by at most 255 / 4 gray
/// levels per unit of log odds (its slope at `l = 0`), so a bin a 256th of
/// a unit wide holds at most one gray threshold.
const TABLE_DENSITY: f32 = 256.0;

/// One bin of the cell table, starting at `l = -TABLE_RANGE + k / TABLE_DENSITY`:
/// `p` and `H_b(p)` there (bits), and the bin's gray levels: `gray` below
/// the bin's threshold `step` (if any), one less from `step` on.
#[derive(Debug, Clone, Copy)]
struct Bin {
    p: f32,
    h: f32,
    step: f32,
    gray: u8,
}

fn cell_table() -> &'static [Bin] {
    static T: OnceLock<Vec<Bin>> = OnceLock::new();
    T.get_or_init(|| {
        let n = (2.0 * TABLE_RANGE * TABLE_DENSITY) as usize;
        let t = thresholds();
        (0..=n)
            .map(|k| {
                let start = -TABLE_RANGE + k as f32 / TABLE_DENSITY;
                let end = -TABLE_RANGE + (k + 1) as f32 / TABLE_DENSITY;
                let p = probability(start as f64);
                let gray = gray_level(start);
                // The one threshold in (start, end), where the gray level
                // drops to `gray - 1`; +inf when the bin has none.
                let step = t
                    .iter()
                    .copied()
                    .find(|&x| x > start && x < end)
                    .unwrap_or(f32::INFINITY);
                Bin {
                    p: p as f32,
                    h: binary_entropy_bits(p) as f32,
                    step,
                    gray,
                }
            })
            .collect()
    })
}

/// Gray level, probability and binary entropy (bits) of log odds `l`:
/// the gray level exactly as the grid draws it, `p` and `H_b` linearly
/// interpolated in the table (exact formulas outside its range).
#[inline]
pub fn cell_look(l: f32) -> (u8, f64, f64) {
    let t = (l as f64 + TABLE_RANGE as f64) * TABLE_DENSITY as f64;
    let table = cell_table();
    if t >= 0.0 {
        // An infinite `l` saturates `k` at usize::MAX: look the neighbour
        // up without overflowing.
        let k = t as usize;
        let next = k.checked_add(1).and_then(|j| table.get(j));
        if let (Some(a), Some(b)) = (table.get(k), next) {
            let f = (t - k as f64) as f32;
            let gray = if l >= a.step { a.gray - 1 } else { a.gray };
            return (
                gray,
                (a.p + f * (b.p - a.p)) as f64,
                (a.h + f * (b.h - a.h)) as f64,
            );
        }
    }
    let p = probability(l as f64);
    (gray_level(l), p, binary_entropy_bits(p))
}

/// Probability and binary entropy (bits) of log odds `l`, as the view
/// scores a cell.
pub fn score(l: f32) -> (f64, f64) {
    let (_, p, h) = cell_look(l);
    (p, h)
}

/// Gray level, probability and binary entropy (bits) of `cell`, as the
/// view draws and scores it: [`cell_look`] of the log odds the model
/// holds, the exact formulas of its probability otherwise.
#[inline]
fn look<M: CellModel>(model: &M, cell: M::Cell) -> (u8, f64, f64) {
    match model.held_log_odds(cell) {
        Some(l) => cell_look(l),
        None => {
            let p = model.probability(cell);
            (probability_gray(p), p, binary_entropy_bits(p))
        }
    }
}

/// A map as the page shows it: RGBA pixels (north up, the grid's drawing
/// convention), and every cell's entropy and squared error with their sums.
/// `C` is the cell model's cell (log odds for the chapter's maps).
#[derive(Debug, Clone)]
pub struct MapView<C = f32> {
    width: usize,
    height: usize,
    /// The cell each pixel was last drawn from, in the rows drawn (empty
    /// before the first sync).
    shown: Vec<C>,
    /// Per map row, true once drawn since the view was made or cleared.
    row_drawn: Vec<bool>,
    rgba: Vec<u8>,
    scores: MapScores,
    /// Scratch: the cells that changed since the last sync, and their
    /// values now.
    dirty: Vec<(u32, C)>,
}

impl<C: StoredCell> MapView<C> {
    /// A view of maps with `geometry`, scored against `truth`, with a
    /// Brier region of the cells in `region` (indices).
    pub fn new(geometry: &GridGeometry, truth: &[bool], region: &[usize]) -> Result<Self> {
        let n = geometry.len();
        let scores = MapScores::new(n, truth, region)?;
        Ok(Self {
            width: geometry.width(),
            height: geometry.height(),
            shown: Vec::new(),
            row_drawn: vec![false; geometry.height()],
            rgba: vec![0; 4 * n],
            scores,
            dirty: Vec::new(),
        })
    }

    /// Brings the view up to date with `grid` (same geometry as the view),
    /// redrawing and rescoring only the cells that changed since the last
    /// call.
    pub fn sync<M: CellModel<Cell = C>, S: Store<C>>(&mut self, grid: &Grid<M, S>) {
        self.sync_rows(grid, 0..self.height);
    }

    /// [`MapView::sync`] over the rows `rows` of the map only (clipped to
    /// it), returning the cells looked at. Cells are redrawn in index
    /// order, so rows synced in increasing bands that cover the map leave
    /// the view, its sums included, bit for bit as one `sync` does: a
    /// large view is first drawn a band per call this way.
    pub fn sync_rows<M: CellModel<Cell = C>, S: Store<C>>(
        &mut self,
        grid: &Grid<M, S>,
        rows: std::ops::Range<usize>,
    ) -> usize {
        let model = grid.model();
        let unknown = model.unknown();
        let w = self.width;
        let rows = rows.start.min(self.height)..rows.end.min(self.height);
        if self.shown.len() != w * self.height {
            // The first sync: no row is drawn yet.
            self.shown = vec![unknown; w * self.height];
        }
        let mut dirty = std::mem::take(&mut self.dirty);
        dirty.clear();
        for iy in rows.clone() {
            let drawn = self.row_drawn[iy];
            grid.store().row_runs(iy, |run| {
                let start = iy * w + run.x0;
                let Some(shown) = self.shown.get(start..start + run.len) else {
                    return;
                };
                match run.cells {
                    Some((cells, _)) if drawn => changed_cells(cells, shown, start, &mut dirty),
                    Some((cells, _)) => {
                        dirty.extend((start as u32..).zip(cells.iter().copied()));
                    }
                    None => {
                        for (k, &s) in shown.iter().enumerate() {
                            if !drawn || s != unknown {
                                dirty.push(((start + k) as u32, unknown));
                            }
                        }
                    }
                }
            });
            self.row_drawn[iy] = true;
        }
        for &(i, cell) in &dirty {
            self.redraw(model, i as usize, cell);
        }
        // Kept for its room only: a view synced in bands holds what one
        // synced whole holds (the runs' tests compare whole states).
        dirty.clear();
        self.dirty = dirty;
        rows.len() * w
    }

    /// Draws and scores cell `i`, which now holds `cell`.
    #[inline]
    fn redraw<M: CellModel<Cell = C>>(&mut self, model: &M, i: usize, cell: C) {
        self.shown[i] = cell;
        let (gray, p, hb) = look(model, cell);
        // Unknown is mid-gray whatever the prior (`super::gray::cell_gray`).
        let g = if model.is_unknown(cell) {
            UNKNOWN_GRAY
        } else {
            gray
        };
        let w = self.width;
        let (ix, iy) = (i % w, i / w);
        let o = 4 * ((self.height - 1 - iy) * w + ix);
        if let Some(px) = self.rgba.get_mut(o..o + 4) {
            px.copy_from_slice(&[g, g, g, 255]);
        }
        self.scores.rescore(i, p, hb);
    }

    /// Forgets everything drawn and scored, as if new: the next sync
    /// redraws every cell and sums from zero.
    pub fn clear(&mut self) {
        self.row_drawn.fill(false);
        self.scores.clear();
    }

    /// The pixels as of the last [`MapView::sync`], `4 * width * height`
    /// bytes, north up.
    pub fn rgba(&self) -> &[u8] {
        &self.rgba
    }
    /// The map's size, cells (= pixels): width, height.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }
    /// The scores as of the last sync.
    pub fn scores(&self) -> &MapScores {
        &self.scores
    }
    /// Map entropy, bits.
    pub fn entropy_bits(&self) -> f64 {
        self.scores.entropy_bits()
    }
    /// Brier score over the region.
    pub fn brier_region(&self) -> f64 {
        self.scores.brier_region()
    }
    /// Brier score over every cell.
    pub fn brier_all(&self) -> f64 {
        self.scores.brier_all()
    }
}

/// Pushes onto `dirty` the cells of `now` (the map's cells from index
/// `start` on) that differ from the ones `shown`, in order. Most cells
/// did not change, so eight are tested at a time with one branch.
#[inline]
fn changed_cells<C: Copy + PartialEq>(
    now: &[C],
    shown: &[C],
    start: usize,
    dirty: &mut Vec<(u32, C)>,
) {
    const LANES: usize = 8;
    let mut push_changed = |base: usize, a: &[C], s: &[C]| {
        for (j, (&x, &y)) in a.iter().zip(s).enumerate() {
            if x != y {
                dirty.push(((start + base + j) as u32, x));
            }
        }
    };
    let blocks = now.chunks_exact(LANES).zip(shown.chunks_exact(LANES));
    for (b, (a, s)) in blocks.enumerate() {
        let changed = a.iter().zip(s).fold(false, |acc, (&x, &y)| acc | (x != y));
        if changed {
            push_changed(b * LANES, a, s);
        }
    }
    let tail = now.len() - now.len() % LANES;
    push_changed(tail, &now[tail..], &shown[tail.min(shown.len())..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::LogOddsGrid;
    use crate::render::gray::{key, ramp_gray, unkey};

    #[test]
    fn gray_level_is_the_renderers_ramp_bit_for_bit() {
        // Every threshold and its neighbours, and a dense sweep.
        for &t in thresholds() {
            for f in [unkey(key(t) - 1), t, unkey(key(t) + 1)] {
                assert_eq!(gray_level(f), ramp_gray(f), "l = {f}");
            }
        }
        let mut l = -40.0f32;
        while l < 40.0 {
            assert_eq!(gray_level(l), ramp_gray(l), "l = {l}");
            l += 0.000_77;
        }
        assert_eq!(gray_level(-1e30), 255);
        assert_eq!(gray_level(1e30), 0);
    }

    #[test]
    fn table_gray_levels_are_exact() {
        for &t in thresholds() {
            for f in [unkey(key(t) - 1), t, unkey(key(t) + 1)] {
                assert_eq!(cell_look(f).0, ramp_gray(f), "l = {f}");
            }
        }
        let mut l = -40.0f32;
        while l < 40.0 {
            assert_eq!(cell_look(l).0, ramp_gray(l), "l = {l}");
            l += 0.000_77;
        }
    }

    #[test]
    fn table_scores_are_within_a_millionth_of_exact() {
        let mut worst = (0.0f64, 0.0f64);
        let mut l = -45.0f32;
        while l < 45.0 {
            let (p, h) = score(l);
            let p_exact = probability(l as f64);
            worst.0 = worst.0.max((p - p_exact).abs());
            worst.1 = worst.1.max((h - binary_entropy_bits(p_exact)).abs());
            l += 0.001_3;
        }
        assert!(worst.0 < 3e-7 && worst.1 < 1e-6, "{worst:?}");
        assert_eq!(score(0.0), (0.5, 1.0));
    }

    #[test]
    fn view_matches_a_full_render_and_full_scores() {
        let g = GridGeometry::new(7, 5, 0.1, 0.0, 0.0).unwrap();
        let mut grid = LogOddsGrid::new(g, Default::default()).unwrap();
        let truth: Vec<bool> = (0..g.len()).map(|i| i % 3 == 0).collect();
        let mut view = MapView::new(&g, &truth, &[0, 1, 2]).unwrap();
        view.sync(&grid);
        assert_eq!(view.entropy_bits(), 35.0);
        for (i, e) in [(0, 2.3f32), (4, -0.7), (9, 11.9), (33, -5.0), (4, 0.7)] {
            grid.apply(i, e);
            view.sync(&grid);
        }
        let mut px = vec![0; g.len() * 4];
        crate::render::viewport::render_grid_rgba(&grid, &mut px).unwrap();
        assert_eq!(view.rgba(), &px[..]);
        assert!((view.entropy_bits() - grid.entropy_bits()).abs() < 1e-5);
        let b = grid.brier_score(&truth, Some(&[0, 1, 2])).unwrap();
        assert!((view.brier_region() - b).abs() < 1e-6);
        assert!(MapView::<f32>::new(&g, &truth[1..], &[0]).is_err());
        assert!(MapView::<f32>::new(&g, &truth, &[]).is_err());
        assert!(MapView::<f32>::new(&g, &truth, &[35]).is_err());
    }
}
