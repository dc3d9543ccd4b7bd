#![cfg(not(target_arch = "wasm32"))]
//! A cell model need not hold log odds: the two models here state a
//! probability and whether a cell was measured, and nothing else, yet their
//! maps are built, drawn (whole, through a screen view, and incrementally
//! with their scores), counted and exported like the chapter's.
//!
//! * [`BetaCount`] keeps the occupied and free verdicts a cell received
//!   and believes their Beta posterior's mean, `(hits + 1) / (hits +
//!   misses + 2)`.
//! * [`LastReading`] believes the last verdict only.

use occgrid::apps::pane::{MapPane, ScreenView};
use occgrid::geometry::{GridGeometry, Pose};
use occgrid::grid::cell::{Thresholds, Verdict};
use occgrid::grid::readout::readout_at_cell;
use occgrid::grid::stats::{count_states, count_states_between, TileTally};
use occgrid::grid::{
    binary_entropy_bits, logit, CellModel, Dense, FilterSettings, Grid, HitCount, HitCounting,
    Store, StoredCell, Tiled, TiledGrid,
};
use occgrid::inverse::{HandCrafted, HandCraftedParams};
use occgrid::io::map_server::{
    export_counts, map_server_pair, read_pgm, FREE_THRESH, OCCUPIED_THRESH,
};
use occgrid::mapping::traversal::RayMapper;
use occgrid::render::map_view::MapView;
use occgrid::render::viewport::render_grid_rgba;
use occgrid::sensors::Scan;

/// The verdicts a cell received, each count saturating.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Counts {
    hits: u8,
    misses: u8,
}

/// The counts saturate, so the store counts a cell's updates beside it.
impl StoredCell for Counts {
    type Updates = u32;
    fn updates(self, beside: u32) -> u32 {
        beside
    }
}

/// The Beta posterior's mean of a cell's verdicts, from a uniform prior.
#[derive(Debug, Clone, PartialEq)]
struct BetaCount;

impl CellModel for BetaCount {
    type Cell = Counts;
    fn unknown(&self) -> Counts {
        Counts::default()
    }
    fn hit(&self, c: &mut Counts, _: f32) {
        c.hits = c.hits.saturating_add(1);
    }
    fn miss(&self, c: &mut Counts, _: f32) {
        c.misses = c.misses.saturating_add(1);
    }
    fn add(&self, c: &mut Counts, evidence: f32) {
        if evidence > 0.0 {
            self.hit(c, evidence)
        } else if evidence < 0.0 {
            self.miss(c, evidence)
        }
    }
    fn probability(&self, c: Counts) -> f64 {
        (c.hits as f64 + 1.0) / (c.hits as f64 + c.misses as f64 + 2.0)
    }
    fn is_unknown(&self, c: Counts) -> bool {
        c == Counts::default()
    }
}

/// The last verdict: 0 never measured, 1 free, 2 occupied.
#[derive(Debug, Clone, PartialEq)]
struct LastReading;

impl CellModel for LastReading {
    type Cell = u8;
    fn unknown(&self) -> u8 {
        0
    }
    fn hit(&self, c: &mut u8, _: f32) {
        *c = 2
    }
    fn miss(&self, c: &mut u8, _: f32) {
        *c = 1
    }
    fn add(&self, c: &mut u8, evidence: f32) {
        if evidence != 0.0 {
            *c = if evidence > 0.0 { 2 } else { 1 }
        }
    }
    fn probability(&self, c: u8) -> f64 {
        [0.5, 0.1, 0.9][c as usize]
    }
    fn is_unknown(&self, c: u8) -> bool {
        c == 0
    }
}

fn scan(x: f64, theta: f64) -> Scan {
    let bearings: Vec<f64> = (0..72).map(|k| k as f64 * 5f64.to_radians()).collect();
    let ranges = (0..72).map(|k| 1.2 + 0.02 * (k % 9) as f64).collect();
    Scan::new(Pose::new(x, 0.1, theta).unwrap(), ranges, bearings).unwrap()
}

fn laser() -> HandCrafted {
    HandCrafted::new(HandCraftedParams::laser(8.0)).unwrap()
}

/// A map's cells, row-major from the bottom row, read through `cell_at`.
fn cells_of<M: CellModel, S: Store<M::Cell>>(grid: &Grid<M, S>) -> Vec<M::Cell> {
    let g = grid.geometry();
    (0..g.len())
        .map(|i| {
            let (ix, iy) = g.cell_of_index(i);
            grid.cell_at(ix, iy).unwrap()
        })
        .collect()
}

/// What the page would show of a cell, written out from its probability
/// alone: mid-gray unknown, else `round(255 (1 - p))`.
fn expected_gray<M: CellModel>(m: &M, c: M::Cell) -> u8 {
    if m.is_unknown(c) {
        128
    } else {
        (255.0 * (1.0 - m.probability(c)) + 0.5) as u8
    }
}

/// Both a dense and a tiled map of `model`, built from the same scans
/// through panes (a whole-map view with scores, a screen view), are drawn,
/// scored, counted and exported from the model's probability and its
/// unknown cells alone, and agree with each other.
fn a_model_goes_through_every_consumer<M: CellModel>(model: M) {
    let g = GridGeometry::new(60, 50, 0.1, -3.0, -2.5).unwrap();
    let sparse = GridGeometry::sparse(60, 50, 0.1, -3.0, -2.5).unwrap();
    let truth: Vec<bool> = (0..g.len()).map(|i| i % 7 == 0).collect();
    let region: Vec<usize> = (0..g.len()).filter(|i| i % 3 == 0).collect();
    let dense = Grid::<M, Dense<M::Cell>>::with_model(g, model.clone(), 0).unwrap();
    let tiled = Grid::<M, Tiled<M::Cell>>::with_model(sparse, model.clone(), 1 << 20).unwrap();
    let mut dense = MapPane::new(dense, MapView::new(&g, &truth, &region).unwrap());
    let mut tiled = MapPane::new(tiled, ScreenView::new(&sparse, 60, 50).unwrap());
    // A view of the tiled map kept cell by cell too: any storage.
    let mut tiled_view = MapView::new(&sparse, &truth, &region).unwrap();
    let inverse = laser();
    for (k, s) in [scan(0.0, 0.3), scan(0.4, 1.1), scan(-0.3, 2.0)]
        .iter()
        .enumerate()
    {
        assert_eq!(dense.integrate(&inverse, s), tiled.integrate(&inverse, s));
        dense.pixels();
        if k != 1 {
            tiled_view.sync(tiled.grid());
        }
    }
    let (dense_px, tiled_px) = (dense.pixels().to_vec(), tiled.pixels().to_vec());
    let grid = dense.grid();
    let cells = cells_of(grid);
    assert_eq!(cells, cells_of(tiled.grid()));
    let measured = cells.iter().filter(|&&c| !model.is_unknown(c)).count();
    assert!(measured > 200 && measured < g.len(), "{measured}");

    // Drawing: the whole map, the screen view and both incremental views.
    let mut px = vec![0; 4 * g.len()];
    render_grid_rgba(grid, &mut px).unwrap();
    for (i, &c) in cells.iter().enumerate() {
        let (ix, iy) = g.cell_of_index(i);
        let o = 4 * ((g.height() - 1 - iy) * g.width() + ix);
        let gray = expected_gray(&model, c);
        assert_eq!(px[o..o + 4], [gray, gray, gray, 255], "cell {i}");
    }
    assert_eq!(dense_px, px);
    assert_eq!(tiled_px, px);
    tiled_view.sync(tiled.grid());
    assert_eq!(tiled_view.rgba(), &px[..]);

    // Scores: the views' sums are the grid's.
    let view = dense.view();
    let exact_bits: f64 = cells
        .iter()
        .map(|&c| binary_entropy_bits(model.probability(c)))
        .sum();
    assert!((grid.entropy_bits() - exact_bits).abs() < 1e-9);
    for v in [view, &tiled_view] {
        assert!((v.entropy_bits() - exact_bits).abs() < 1e-9);
        let b = grid.brier_score(&truth, Some(&region)).unwrap();
        assert!((v.brier_region() - b).abs() < 1e-12);
        assert!((v.brier_all() - grid.brier_score(&truth, None).unwrap()).abs() < 1e-12);
    }

    // Counts: by the verdict, cell by cell, whatever the storage.
    let w1 = Thresholds::new(0.65, 0.35);
    let by_verdict = |t: &Thresholds| {
        let mut n = [0usize; 4];
        for &c in &cells {
            let v = model.verdict(c, t);
            let p = model.probability(c);
            let expected = match () {
                _ if model.is_unknown(c) => Verdict::Unknown,
                _ if p > t.occupied_above() => Verdict::Occupied,
                _ if p < t.free_below() => Verdict::Free,
                _ => Verdict::Undecided,
            };
            assert_eq!(v, expected, "{c:?}");
            n[v as usize] += 1;
        }
        n
    };
    let n = by_verdict(&w1);
    let counts = count_states(grid);
    assert_eq!(
        (counts.unknown, counts.occupied, counts.free, counts.cells),
        (
            n[Verdict::Unknown as usize],
            n[Verdict::Occupied as usize],
            n[Verdict::Free as usize],
            g.len()
        )
    );
    assert_eq!(count_states(tiled.grid()), counts);
    let mut tally = TileTally::new(0.65, 0.35);
    assert_eq!(tally.counts(tiled.grid()), counts);
    let mut grown = tiled.grid().clone();
    tally.refresh(&mut grown);
    assert_eq!(tally.counts(&grown), counts);

    // Export: the trinary image from the verdict under the YAML's
    // thresholds, and its counts.
    let export = Thresholds::new(OCCUPIED_THRESH, FREE_THRESH);
    let n = by_verdict(&export);
    let pair = map_server_pair(grid, "beta.pgm");
    assert_eq!(pair, map_server_pair(tiled.grid(), "beta.pgm"));
    let pgm = read_pgm(&pair.pgm).unwrap();
    assert_eq!((pgm.width, pgm.height), (g.width(), g.height()));
    for (i, &c) in cells.iter().enumerate() {
        let (ix, iy) = g.cell_of_index(i);
        let expected = match model.verdict(c, &export) {
            Verdict::Occupied => 0,
            Verdict::Free => 254,
            Verdict::Unknown | Verdict::Undecided => 205,
        };
        assert_eq!(pgm.at(ix, g.height() - 1 - iy), Some(expected));
    }
    let e = export_counts(grid);
    assert_eq!(
        (e.occupied, e.free),
        (n[Verdict::Occupied as usize], n[Verdict::Free as usize])
    );
    assert_eq!(
        e.unknown,
        n[Verdict::Unknown as usize] + n[Verdict::Undecided as usize]
    );
    assert_eq!(
        count_states_between(grid, OCCUPIED_THRESH, FREE_THRESH),
        count_states_between(tiled.grid(), OCCUPIED_THRESH, FREE_THRESH)
    );

    // The readout, and the log odds a consumer that wants them derives.
    let (ix, iy) = g.cell_of_index(cells.iter().position(|&c| !model.is_unknown(c)).unwrap());
    let r = readout_at_cell(grid, ix, iy).unwrap();
    let c = grid.cell_at(ix, iy).unwrap();
    assert_eq!(r.p, model.probability(c));
    assert_eq!(r.l, logit(r.p) as f32 as f64);
    assert!(!r.unknown && r.updates > 0);

    // A reset forgets every cell, and the view follows.
    dense.reset();
    assert_eq!(dense.counts().unknown, g.len());
    assert!(dense.pixels().chunks(4).all(|p| p == [128, 128, 128, 255]));
    assert!((dense.view().entropy_bits() - g.len() as f64).abs() < 1e-9);
}

#[test]
fn a_beta_count_cell_is_drawn_counted_and_exported_from_its_probability() {
    a_model_goes_through_every_consumer(BetaCount);
}

#[test]
fn a_last_reading_cell_is_drawn_counted_and_exported_from_its_probability() {
    a_model_goes_through_every_consumer(LastReading);
}

/// A counting cell's visits are its updates: a tiled map of hit counting
/// keeps nothing beside its cells (4 bytes a cell, where log odds take 8),
/// yet every cell reads the same update count as the log-odds map built
/// from the same scans, and the readout says so.
#[test]
fn a_counting_map_counts_updates_in_its_cells_and_takes_half_the_bytes() {
    let sparse = GridGeometry::sparse(60, 50, 0.1, -3.0, -2.5).unwrap();
    let model = HitCounting {
        occupied_ratio: 0.25,
    };
    let mut counting =
        Grid::<HitCounting, Tiled<HitCount>>::with_model(sparse, model, 1 << 20).unwrap();
    let mut log_odds = TiledGrid::new(sparse, FilterSettings::default(), 1 << 20).unwrap();
    let (inverse, mut mapper) = (laser(), RayMapper::new());
    for s in [
        scan(0.0, 0.3),
        scan(0.4, 1.1),
        scan(-0.3, 2.0),
        scan(0.0, 0.3),
    ] {
        mapper.integrate(&mut counting, &inverse, &s);
        mapper.integrate(&mut log_odds, &inverse, &s);
    }
    assert_eq!(counting.bytes_per_cell(), 4);
    assert_eq!(log_odds.bytes_per_cell(), 8);
    assert_eq!(
        counting.bytes_allocated(),
        4 * counting.cells_allocated(),
        "nothing beside the cells"
    );
    let mut seen_by = [0usize; 5];
    for i in 0..sparse.len() {
        let (ix, iy) = sparse.cell_of_index(i);
        let n = log_odds.updates_at(ix, iy).unwrap();
        assert_eq!(counting.updates_at(ix, iy), Some(n), "cell {i}");
        assert_eq!(readout_at_cell(&counting, ix, iy).unwrap().updates, n);
        seen_by[n as usize] += 1;
    }
    // Cells seen by one scan, and by all four (the first pose twice).
    assert!(seen_by[1] > 50 && seen_by[4] > 10, "{seen_by:?}");
}
