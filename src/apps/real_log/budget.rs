//! What a log's map will allocate, known before a cell is: the tiles its
//! beams reach, walked on the grid of tiles (docs/ARCHITECTURE.md, "Real
//! logs"). A resolution too fine for the tile budget is refused when the
//! settings are chosen, naming the finest resolution that fits, instead of
//! a build that stops part way through the log. (After a read, the panes
//! are planned in calls of bounded work: `planning.rs`.)

use super::settings::CheckedSettings;
use crate::error::{invalid, show, OccError, Result};
use crate::geometry::{GridGeometry, Pose};
use crate::grid::storage::{mebibytes, tiles_of, TILE_CELLS, TILE_SIDE};
use crate::inverse::HandCrafted;
use crate::mapping::reach::{covering_grid, tiles_reached, BeamReach};
use crate::poses::{PoseSource, PoseSourceKind};
use crate::sensors::{Scan, ScanLog};

/// Cells visited that cost about one cell update (a verdict gathered, 15
/// instructions natively, against a tile's cell updated, 35): visits per
/// update range from 1.2 (an office) to 3 (a campus's long beams), so a
/// budget of updates alone let a campus call run twice its time slice.
pub const VISITS_PER_UNIT: u64 = 2;

/// Units of work a cell of a newly allocated tile costs (the tile zeroed,
/// its memory first touched, recounted): in the browser a campus call
/// that allocated 100 to 160 tiles took 1.5 to 1.7 times the time of one
/// that allocated none, about two updates' time per new cell.
pub const UNITS_PER_NEW_CELL: u64 = 2;

/// The most work, in the units of a cell update, finding the poses of a
/// log's scans may cost one pane ([`PoseSource::work_bound`]: for scan
/// matching, every scan matched at the most its settings allow). At the
/// 10 to 16 ns a unit of matching takes natively, about five minutes at
/// the most; the largest log of the corpus, the Freiburg campus (2,008
/// scans of 360 beams), is bounded at 2.9e9 at 5 cm, and its matching
/// costs a sixth of that. A log of a million one-beam scans, bounded at
/// 3.5e11, is refused when its panes are planned, not matched for minutes.
/// SLAM's bound adds its submaps and an allowance for its loop search
/// ([`crate::poses::LOOP_SEARCH_ALLOWANCE`]): the campus at 1.9e10 at 5 cm,
/// the Intel log at 7.5e9 (its search and optimisation spent 3.4e9). (A source that knows
/// its poses costs nothing here; what inserting the scans costs is
/// bounded by the scans a log may keep, [`crate::io::LogBudget`].)
pub const MAX_POSE_WORK: u64 = 20_000_000_000;

/// The resolutions offered when one is refused are whole steps of half a
/// centimetre (the finest step a reader sets by hand): steps per metre.
const RESOLUTION_STEPS_PER_METRE: f64 = 200.0;
/// Coarser resolutions tried before giving up on naming one that fits.
const TRIES: usize = 8;

/// Scan `k` of `scans` at `pose`.
pub(super) fn at_pose(scans: &ScanLog, k: usize, pose: Pose) -> Option<Scan> {
    placed_at(scans.scan(k)?, pose)
}

/// `scan` at `pose` (itself when it is there already).
pub(super) fn placed_at(scan: Scan, pose: Pose) -> Option<Scan> {
    if scan.pose() == pose {
        return Some(scan);
    }
    Scan::new(pose, scan.ranges().to_vec(), scan.bearings().to_vec()).ok()
}

/// The tiles the beams of every scan at `poses` reach on `extent`: what
/// the whole log would allocate in a tiled map.
pub(super) fn tiles_needed(
    scans: &ScanLog,
    poses: &[Pose],
    extent: &GridGeometry,
    c: &CheckedSettings,
) -> usize {
    tiles_reached(
        extent,
        (0..scans.len()).filter_map(|k| at_pose(scans, k, *poses.get(k)?)),
        beam_reach(c),
    )
}

/// How the beams under `c` reach: what a walk of the tiles follows.
pub(super) fn beam_reach(c: &CheckedSettings) -> BeamReach<'_> {
    let s = c.settings();
    BeamReach {
        model: c.model(),
        no_return_reach: s.no_return_reach,
        walls: s.walls,
    }
}

/// Refuses settings whose map of `scans` would need more than
/// `budget_cells` cells in tiles. `poses` are where the scans will be put
/// (for a scan-matched pane, the log's own poses: the matched path stays
/// near them, where dead reckoning wanders off); `plan` gives the map's
/// extent at other settings, to find the finest resolution that fits.
pub(super) fn check_tile_budget(
    scans: &ScanLog,
    poses: &[Pose],
    extent: &GridGeometry,
    c: &CheckedSettings,
    budget_cells: usize,
    bytes_per_cell: usize,
    plan: impl Fn(&CheckedSettings) -> Result<GridGeometry>,
) -> Result<()> {
    if every_tile_fits(extent, budget_cells) {
        return Ok(());
    }
    let needed = tiles_needed(scans, poses, extent, c);
    refuse_past_budget(
        needed,
        (scans, poses),
        c,
        budget_cells,
        bytes_per_cell,
        plan,
    )
}

/// True when every tile of `extent` fits `budget_cells`: a map that needs
/// no walk (most logs: only the largest maps pay for counting the tiles
/// their beams reach).
pub(super) fn every_tile_fits(extent: &GridGeometry, budget_cells: usize) -> bool {
    let (tx, ty) = tiles_of(extent);
    tx.saturating_mul(ty) <= budget_tiles(budget_cells)
}

pub(super) fn budget_tiles(budget_cells: usize) -> usize {
    (budget_cells / TILE_CELLS).max(1)
}

/// An error when `needed` tiles pass `budget_cells` (naming the finest
/// resolution that fits, found by walking the scans again at coarser
/// ones: the refusal alone pays for those walks).
pub(super) fn refuse_past_budget(
    needed: usize,
    (scans, poses): (&ScanLog, &[Pose]),
    c: &CheckedSettings,
    budget_cells: usize,
    bytes_per_cell: usize,
    plan: impl Fn(&CheckedSettings) -> Result<GridGeometry>,
) -> Result<()> {
    if needed <= budget_tiles(budget_cells) {
        return Ok(());
    }
    let mut search = FitSearch::new(needed, c, budget_cells);
    let mut fits = None;
    while let Some((candidate, checked)) = search.next(c) {
        let Ok(geometry) = plan(&checked) else { break };
        if tiles_needed(scans, poses, &geometry, &checked) <= budget_tiles(budget_cells) {
            fits = Some(candidate);
            break;
        }
    }
    Err(budget_refusal(
        needed,
        c,
        budget_cells,
        bytes_per_cell,
        fits,
    ))
}

/// The search for the finest resolution that fits the tile budget, a
/// candidate at a time: each candidate costs a walk of the scans, which
/// the planning spreads over calls ([`PanePlanning`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct FitSearch {
    /// The next candidate, in whole steps of [`RESOLUTION_STEPS_PER_METRE`].
    steps: u64,
    tried: usize,
}

impl FitSearch {
    pub(super) fn new(needed: usize, c: &CheckedSettings, budget_cells: usize) -> Self {
        // Tiles grow as the area the beams sweep, with the square of 1 /
        // resolution: start from there and step up until one fits.
        let scale = (needed as f64 / budget_tiles(budget_cells) as f64).sqrt();
        // Counted in whole steps, so that the resolution named reads as typed.
        let r = c.settings().resolution;
        let steps = (r * scale * RESOLUTION_STEPS_PER_METRE).ceil() as u64;
        Self { steps, tried: 0 }
    }

    /// The next resolution to try and the settings at it; `None` once
    /// [`TRIES`] are spent or the settings at it are refused.
    pub(super) fn next(&mut self, c: &CheckedSettings) -> Option<(f64, CheckedSettings)> {
        if self.tried == TRIES {
            return None;
        }
        self.tried += 1;
        let candidate = self.steps as f64 / RESOLUTION_STEPS_PER_METRE;
        self.steps += 1;
        let mut s = *c.settings();
        s.resolution = candidate;
        Some((candidate, s.validate().ok()?))
    }
}

/// The refusal of settings whose beams reach `needed` tiles, naming the
/// resolution that fits (`fits`), if one was found.
pub(super) fn budget_refusal(
    needed: usize,
    c: &CheckedSettings,
    budget_cells: usize,
    bytes_per_cell: usize,
    fits: Option<f64>,
) -> OccError {
    let cells = needed as u128 * TILE_CELLS as u128;
    let b = bytes_per_cell as u128;
    let advice = match fits {
        Some(r) => format!("{} m or coarser fits", show(r)),
        None => "a coarser resolution".to_string(),
    };
    invalid(
        "resolution",
        format!("{} m", show(c.settings().resolution)),
        format!(
            "a map this log fits in: its beams would reach {needed} tiles of {TILE_SIDE} x {TILE_SIDE} cells \
             ({cells} cells, {}), over the {budget_cells} cells ({}) a map may hold; {advice}",
            mebibytes(cells * b),
            mebibytes(budget_cells as u128 * b),
        ),
    )
}

/// The model of scan `k`'s laser: the settings' own, or one at the laser's
/// shorter maximum range.
pub(super) fn scan_model(c: &CheckedSettings, scans: &ScanLog, k: usize) -> HandCrafted {
    let laser_max = scans.max_range(k).unwrap_or(f64::INFINITY);
    c.model_for_laser(laser_max).unwrap_or(*c.model())
}

/// The grid over the box `extent` of a log's poses and beams
/// ([`scan_extent`]; `None` for a log without a scan) and `drift` metres
/// more around it, covered on whole cells, under settings whose range
/// cap's reach fits the traversal.
pub(super) fn grid_of_extent(
    extent: Option<[f64; 4]>,
    drift: f64,
    c: &CheckedSettings,
) -> Result<GridGeometry> {
    let s = c.settings();
    let a = extent.ok_or_else(no_scans)?;
    let extent = [a[0] - drift, a[1] - drift, a[2] + drift, a[3] + drift];
    let grid = covering_grid(extent, s.resolution, s.margin)?;
    // A scan is gathered in a window as wide as its longest beam: that
    // window's scratch is what bounds the reach in cells.
    s.check_reach()?;
    Ok(grid)
}

/// Refuses a pane whose `source` could cost more than `budget` units of
/// work finding the poses of `scans` ([`MAX_POSE_WORK`] unless a test
/// says otherwise), naming the source, the figure and the budget.
pub(super) fn check_pose_work(scans: &ScanLog, source: &dyn PoseSource, budget: u64) -> Result<()> {
    check_pose_bound(scans, source.kind(), source.work_bound(scans), budget)
}

/// Refuses a pane of source `kind` whose poses could cost `bound` units of
/// work to find over `scans`, past `budget` ([`check_pose_work`]).
pub(super) fn check_pose_bound(
    scans: &ScanLog,
    kind: PoseSourceKind,
    bound: u64,
    budget: u64,
) -> Result<()> {
    if bound <= budget {
        return Ok(());
    }
    let n = scans.len() as u64;
    // What fits: the bound grows with the scans (a scan's share of it is
    // the same, but for SLAM's finished submaps), and sources that know
    // their poses cost nothing. (A coarser resolution shrinks the share of
    // a scan's search, but at a million scans not by enough to fit.)
    let fit = (budget as u128 * n as u128 / (bound as u128).max(1)) as u64;
    Err(invalid(
        "poses",
        format!("\"{}\" over {n} scans", kind.name()),
        format!(
            "a log whose poses cost at most {budget} units of work (cell updates) to find: \
             these {n} scans could cost up to {bound} ({} a scan); \
             map it at the log's own poses or dead-reckoned ones, or cut it to at most {fit} scans",
            bound / n.max(1)
        ),
    ))
}

pub(super) fn no_scans() -> OccError {
    invalid("log", "no laser scans", "at least one laser scan")
}
