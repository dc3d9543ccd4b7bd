//! What a log's map will allocate, known before a cell is: the tiles its
//! beams reach, walked on the grid of tiles (docs/ARCHITECTURE.md, "Real
//! logs"). A resolution too fine for the tile budget is refused when the
//! settings are chosen, naming the finest resolution that fits, instead of
//! a build that stops part way through the log. After a read, the panes
//! are planned in calls of bounded work ([`PanePlanning`]).

use super::pane::{grid_of_extent, no_scans, source_settings, LogPane};
use super::settings::{CheckedSettings, LogCellModel};
use crate::error::{invalid, show, OccError, Result};
use crate::geometry::{GridGeometry, Pose};
use crate::grid::storage::{mebibytes, tiles_of, TILE_CELLS, TILE_SIDE};
use crate::inverse::HandCrafted;
use crate::mapping::reach::{tiles_reached, BeamReach, ExtentBox, TileReach};
use crate::poses::{PoseSource, PoseSourceKind};
use crate::sensors::odometry::OdometryParams;
use crate::sensors::{Scan, ScanLog};
use std::sync::Arc;

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

/// The resolutions offered when one is refused are whole steps of half a
/// centimetre (the finest step a reader sets by hand): steps per metre.
const RESOLUTION_STEPS_PER_METRE: f64 = 200.0;
/// Coarser resolutions tried before giving up on naming one that fits.
const TRIES: usize = 8;

/// Scan `k` of `scans` at `pose`.
pub(super) fn at_pose(scans: &ScanLog, k: usize, pose: Pose) -> Option<Scan> {
    let scan = scans.scan(k)?;
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
fn beam_reach(c: &CheckedSettings) -> BeamReach<'_> {
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

fn budget_tiles(budget_cells: usize) -> usize {
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
struct FitSearch {
    /// The next candidate, in whole steps of [`RESOLUTION_STEPS_PER_METRE`].
    steps: u64,
    tried: usize,
}

impl FitSearch {
    fn new(needed: usize, c: &CheckedSettings, budget_cells: usize) -> Self {
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
    fn next(&mut self, c: &CheckedSettings) -> Option<(f64, CheckedSettings)> {
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
fn budget_refusal(
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

/// Where one pane's plan stands.
enum Phase {
    /// Growing the box of its poses and beams, a scan at a time.
    Extent(ExtentBox),
    /// Its bounding box passes the tile budget: counting the tiles its
    /// beams reach, a scan at a time (the box of the scans kept for the
    /// search that may follow).
    Tiles([f64; 4], GridGeometry, TileReach, usize),
    /// Its beams pass the tile budget (`needed` tiles): searching for the
    /// finest resolution that fits over the box `bounds`, a candidate at a
    /// time and a scan of its walk at a time.
    Search {
        bounds: [f64; 4],
        grid: GridGeometry,
        needed: usize,
        search: FitSearch,
        walk: Option<CandidateWalk>,
    },
    /// Its grid, and the tiles its beams reach when they were counted.
    Ready(GridGeometry, Option<usize>),
    /// Its beams reach `needed` tiles of its grid, past the budget; the
    /// resolution that fits, if the search found one.
    Refused(GridGeometry, usize, Option<f64>),
    /// The settings make no map of this log (a grid too large).
    Failed(OccError),
}

/// One candidate of a search: its resolution and settings, its grid, and
/// the tiles the scans walked so far reach on it.
struct CandidateWalk {
    resolution: f64,
    settings: CheckedSettings,
    tiles: TileReach,
    scans: usize,
}

/// One pane of a plan: its pose source (`None` when it could not start:
/// the phase then says why) and cell model, and its phase.
struct PlannedPane {
    kind: PoseSourceKind,
    source: Option<Box<dyn PoseSource>>,
    model: LogCellModel,
    phase: Phase,
}

/// The panes of a log just read, planned in calls of bounded work (scans
/// walked), so that no call of the page's read walks every scan
/// (docs/ARCHITECTURE.md, "Real logs"): each pane's extent (already grown
/// as the lines were read, for the log's own poses), then, when its
/// bounding box passes the tile budget, the tiles its beams reach, and
/// when those pass it, the finest resolution that fits. Panes of one pose
/// source share one walk. The panes it makes, and its refusals, are the
/// ones [`LogPane::plan`] makes, cell for cell and word for word.
pub(super) struct PanePlanning {
    scans: Arc<ScanLog>,
    settings: CheckedSettings,
    odometry: OdometryParams,
    budget_cells: usize,
    panes: Vec<PlannedPane>,
}

impl PanePlanning {
    /// The plan of `settings`' panes over `scans`; `read_extent` the box of
    /// every scan at its own poses when it was grown under these settings
    /// as the lines were read.
    pub(super) fn new(
        scans: Arc<ScanLog>,
        settings: &CheckedSettings,
        odometry: OdometryParams,
        budget_cells: usize,
        read_extent: Option<ExtentBox>,
    ) -> Self {
        let s = settings.settings();
        let read_extent = read_extent.filter(|e| e.scans() == scans.len());
        let panes = s
            .pane_plan()
            .into_iter()
            .map(|(kind, model)| {
                let source = kind.start(&scans, &source_settings(settings, odometry));
                // A pane whose plan walks the log's own poses (a
                // scan-matched one too, with room for drift) takes the box
                // grown as the log was read.
                let phase = match (&source, &read_extent) {
                    (Err(e), _) => Phase::Failed(e.clone()),
                    (Ok(source), Some(e)) if source.plan_poses(&scans).0 == scans.poses() => {
                        Phase::Extent(e.clone())
                    }
                    _ => Phase::Extent(ExtentBox::new(s.no_return_reach)),
                };
                PlannedPane {
                    kind,
                    source: source.ok(),
                    model,
                    phase,
                }
            })
            .collect();
        Self {
            scans,
            settings: *settings,
            odometry,
            budget_cells,
            panes,
        }
    }

    /// Walks at most `max_scans` scans of the plan (a pane whose walk is
    /// done moves on to its next phase without one); returns the scans
    /// walked.
    pub(super) fn step(&mut self, max_scans: usize) -> usize {
        let mut walked = 0;
        for i in 0..self.panes.len() {
            // A pane of a source planned before it takes that plan.
            let (before, rest) = self.panes.split_at_mut(i);
            let pane = &mut rest[0];
            if !pane.phase.is_done() {
                let twin = before.iter().find(|p| p.kind == pane.kind);
                match twin.map(|p| &p.phase) {
                    Some(Phase::Ready(g, n)) => pane.phase = Phase::Ready(*g, *n),
                    Some(Phase::Refused(g, n, r)) => pane.phase = Phase::Refused(*g, *n, *r),
                    Some(Phase::Failed(e)) => pane.phase = Phase::Failed(e.clone()),
                    _ => {}
                }
            }
            while self.advance(i, walked < max_scans) {
                walked += 1;
            }
        }
        walked
    }

    /// Moves pane `i`'s plan on: through the phases whose walk is done,
    /// then, if `may_walk`, one scan of its walk. True when a scan was
    /// walked.
    fn advance(&mut self, i: usize, may_walk: bool) -> bool {
        let (scans, c, budget) = (&self.scans, &self.settings, self.budget_cells);
        let pane = &mut self.panes[i];
        // The poses the walks put the scans at (a scan-matched pane's are
        // the log's own: the matched path stays near them), and the room
        // its grid leaves for drift around them.
        let Some(source) = &pane.source else {
            return false;
        };
        let (poses, drift) = source.plan_poses(scans);
        loop {
            match &mut pane.phase {
                Phase::Extent(e) if e.scans() < scans.len() => {
                    if !may_walk {
                        return false;
                    }
                    let k = e.scans();
                    // (A scan at a pose that is not finite is left out, as
                    // the whole-log extent leaves it out.)
                    match poses.get(k).and_then(|&p| at_pose(scans, k, p)) {
                        Some(scan) => e.add(&scan, &scan_model(c, scans, k)),
                        None => e.skip(),
                    }
                    return true;
                }
                Phase::Extent(e) => {
                    let bounds = e.bounds();
                    pane.phase = match (grid_of_extent(bounds, drift, c), bounds) {
                        (Ok(g), _) if every_tile_fits(&g, budget) => Phase::Ready(g, None),
                        (Ok(g), Some(b)) => Phase::Tiles(b, g, TileReach::new(&g), 0),
                        (Ok(_), None) => Phase::Failed(no_scans()),
                        (Err(e), _) => Phase::Failed(e),
                    };
                }
                Phase::Tiles(_, _, tiles, k) if *k < scans.len() => {
                    if !may_walk {
                        return false;
                    }
                    if let Some(scan) = poses.get(*k).and_then(|&p| at_pose(scans, *k, p)) {
                        tiles.add(&scan, beam_reach(c));
                    }
                    *k += 1;
                    return true;
                }
                Phase::Tiles(_, g, tiles, _) if tiles.count() <= budget_tiles(budget) => {
                    pane.phase = Phase::Ready(*g, Some(tiles.count()))
                }
                Phase::Tiles(bounds, g, tiles, _) => {
                    // The box of the scans is the same at any resolution:
                    // each candidate's grid is found without a walk.
                    let needed = tiles.count();
                    pane.phase = Phase::Search {
                        bounds: *bounds,
                        grid: *g,
                        needed,
                        search: FitSearch::new(needed, c, budget),
                        walk: None,
                    };
                }
                Phase::Search {
                    bounds,
                    grid,
                    needed,
                    search,
                    walk,
                } => match walk {
                    None => {
                        let next = search.next(c).and_then(|(r, checked)| {
                            let g = grid_of_extent(Some(*bounds), drift, &checked).ok()?;
                            Some(CandidateWalk {
                                resolution: r,
                                settings: checked,
                                tiles: TileReach::new(&g),
                                scans: 0,
                            })
                        });
                        match next {
                            Some(w) => *walk = Some(w),
                            None => pane.phase = Phase::Refused(*grid, *needed, None),
                        }
                    }
                    Some(w) if w.scans < scans.len() => {
                        if !may_walk {
                            return false;
                        }
                        let k = w.scans;
                        if let Some(scan) = poses.get(k).and_then(|&p| at_pose(scans, k, p)) {
                            w.tiles.add(&scan, beam_reach(&w.settings));
                        }
                        w.scans += 1;
                        return true;
                    }
                    Some(w) if w.tiles.count() <= budget_tiles(budget) => {
                        pane.phase = Phase::Refused(*grid, *needed, Some(w.resolution))
                    }
                    Some(_) => *walk = None,
                },
                Phase::Ready(..) | Phase::Refused(..) | Phase::Failed(_) => return false,
            }
        }
    }

    /// True once every pane's plan is walked.
    pub(super) fn finished(&self) -> bool {
        self.panes.iter().all(|p| p.phase.is_done())
    }

    /// The scans the log has.
    pub(super) fn scans(&self) -> &Arc<ScanLog> {
        &self.scans
    }

    /// The panes, once [`Self::finished`]: an error when the settings make
    /// no map of this log (a grid too large, beams past the tile budget).
    pub(super) fn into_panes(self) -> Result<Vec<LogPane>> {
        let Self {
            scans,
            settings: c,
            odometry,
            budget_cells,
            panes,
        } = self;
        panes
            .into_iter()
            .map(|p| {
                let (grid, refused) = match p.phase {
                    Phase::Failed(e) => return Err(e),
                    Phase::Ready(grid, _) => (grid, None),
                    Phase::Refused(grid, needed, fits) => (grid, Some((needed, fits))),
                    // (Not reached once the plan is finished.)
                    Phase::Extent(_) | Phase::Tiles(..) | Phase::Search { .. } => {
                        return LogPane::plan(
                            Arc::clone(&scans),
                            (p.kind, p.model),
                            &c,
                            odometry,
                            budget_cells,
                        )
                    }
                };
                let source = match p.source {
                    Some(source) => source,
                    None => p.kind.start(&scans, &source_settings(&c, odometry))?,
                };
                let pane = LogPane::planned(
                    Arc::clone(&scans),
                    (source, p.model),
                    &c,
                    odometry,
                    budget_cells,
                    grid,
                )?;
                match refused {
                    // The refusal names the bytes of this pane's cells.
                    Some((needed, fits)) => Err(budget_refusal(
                        needed,
                        &c,
                        budget_cells,
                        pane.grid().bytes_per_cell(),
                        fits,
                    )),
                    None => Ok(pane),
                }
            })
            .collect()
    }
}

impl Phase {
    /// True once the pane's plan needs no more walking.
    fn is_done(&self) -> bool {
        matches!(
            self,
            Phase::Ready(..) | Phase::Refused(..) | Phase::Failed(_)
        )
    }
}
