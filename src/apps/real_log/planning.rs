//! After a read, or new settings, the panes are planned in calls of
//! bounded work ([`PanePlanning`]): each pane's extent, the tiles its
//! beams reach when its box passes the tile budget, and the finest
//! resolution that fits when those pass it (docs/ARCHITECTURE.md, "Real
//! logs").

use super::budget::{
    at_pose, beam_reach, budget_refusal, budget_tiles, check_pose_bound, check_pose_work,
    every_tile_fits, grid_of_extent, no_scans, scan_model, FitSearch,
};
use super::pane::{source_settings, LogPane};
use super::settings::{CheckedSettings, LogCellModel};
use crate::error::{OccError, Result};
use crate::geometry::GridGeometry;
use crate::mapping::reach::{ExtentBox, TileReach};
use crate::poses::{PoseSource, PoseSourceKind, SourceStart};
use crate::sensors::odometry::OdometryParams;
use crate::sensors::ScanLog;
use std::sync::Arc;

/// A start's units ([`SourceStart::step`]: a pose dead-reckoned, or
/// sixteen copied) to a unit of a plan's work, a scan's pass: a pass over
/// a scan's beams (growing a box, counting the tiles they reach) takes 10
/// to 40 µs natively on a 361-beam log, as reading its line does, and a
/// pose dead-reckoned about a tenth of a microsecond. Counted one to one,
/// a start's calls ran a hundred times faster than their budget said, a
/// page sized its next read call from them, and the pass that followed
/// held the main thread 90 to 190 ms (the Freiburg campus).
pub const START_UNITS_PER_PASS: usize = 64;

/// Where one pane's plan stands.
enum Phase {
    /// Starting its pose source: its path made a bounded number of poses
    /// per call ([`SourceStart`]).
    Start(Box<SourceStart>),
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

/// One pane of a plan: its pose source (`None` while it is started, or
/// when it could not start: the phase then says why) and cell model, and
/// its phase.
struct PlannedPane {
    kind: PoseSourceKind,
    source: Option<Box<dyn PoseSource>>,
    model: LogCellModel,
    phase: Phase,
}

/// The panes of a log just read, planned in calls of bounded work (scans
/// walked, poses made), so that no call of the page's read walks every
/// scan or makes every pose (docs/ARCHITECTURE.md, "Real logs"): each
/// pane's pose source, started a bounded number of poses at a time
/// ([`SourceStart`]), its extent (already grown
/// as the lines were read, for the log's own poses), then, when its
/// bounding box passes the tile budget, the tiles its beams reach, and
/// when those pass it, the finest resolution that fits. Panes of one pose
/// source share one walk. The panes it makes, and its refusals, are the
/// ones [`LogPane::plan`] makes, cell for cell and word for word. Once a
/// pane is refused, the panes after it are not planned: the plan's answer
/// is that refusal.
pub(super) struct PanePlanning {
    scans: Arc<ScanLog>,
    settings: CheckedSettings,
    odometry: OdometryParams,
    budget_cells: usize,
    /// The most work finding a pane's poses may cost.
    pose_work: u64,
    /// The box of every scan at its own poses, grown as the log was read:
    /// the extent of a pane whose plan walks those poses.
    read_extent: Option<ExtentBox>,
    panes: Vec<PlannedPane>,
}

impl PanePlanning {
    /// The plan of `settings`' panes over `scans`; `read_extent` the box of
    /// every scan at its own poses when it was grown under these settings
    /// as the lines were read. A pane whose pose source could cost more
    /// than `pose_work` units finding its poses is refused here, before a
    /// walk ([`check_pose_work`]).
    pub(super) fn new(
        scans: Arc<ScanLog>,
        settings: &CheckedSettings,
        odometry: OdometryParams,
        (budget_cells, pose_work): (usize, u64),
        read_extent: Option<ExtentBox>,
    ) -> Self {
        let s = settings.settings();
        let read_extent = read_extent.filter(|e| e.scans() == scans.len());
        let panes = s
            .pane_plan()
            .into_iter()
            // The maps shown beside the chosen one only where their source
            // applies to this log (a bag has no corrected poses); the
            // chosen one is planned whatever, to be refused by name.
            .enumerate()
            .filter(|(i, (kind, _))| *i == 0 || kind.applies(&scans))
            .map(|(_, (kind, model))| {
                // A source whose work is bounded before its path is made
                // (a matcher's) is refused before it is made.
                let start = kind
                    .starting(&scans, &source_settings(settings, odometry))
                    .and_then(|start| {
                        if let Some(bound) = start.work_bound(&scans) {
                            check_pose_bound(&scans, kind, bound, pose_work)?;
                        }
                        Ok(start)
                    });
                PlannedPane {
                    kind,
                    source: None,
                    model,
                    phase: match start {
                        Ok(start) => Phase::Start(Box::new(start)),
                        Err(e) => Phase::Failed(e),
                    },
                }
            })
            .collect();
        Self {
            scans,
            settings: *settings,
            odometry,
            budget_cells,
            pose_work,
            read_extent,
            panes,
        }
    }

    /// Works at most `max_scans` units of the plan: scans walked, and
    /// poses of the panes' sources made ([`SourceStart::step`]'s units; a
    /// pane whose walk is done moves on to its next phase without one);
    /// returns the units worked.
    pub(super) fn step(&mut self, max_scans: usize) -> usize {
        let mut walked = 0;
        for i in 0..self.panes.len() {
            // The plan's answer is the first refusal: nothing after it is
            // planned.
            if self.panes[..i].iter().any(|p| p.phase.is_refusal()) {
                break;
            }
            loop {
                self.take_twin_plan(i);
                match self.advance(i, max_scans.saturating_sub(walked)) {
                    Some(units) => walked += units,
                    None => break,
                }
            }
        }
        walked
    }

    /// Pane `i`, once its source is started, takes the plan of a pane of
    /// the same source before it, once that is done.
    fn take_twin_plan(&mut self, i: usize) {
        let (before, rest) = self.panes.split_at_mut(i);
        let pane = &mut rest[0];
        if pane.phase.is_done() || pane.source.is_none() {
            return;
        }
        let twin = before.iter().find(|p| p.kind == pane.kind);
        match twin.map(|p| &p.phase) {
            Some(Phase::Ready(g, n)) => pane.phase = Phase::Ready(*g, *n),
            Some(Phase::Refused(g, n, r)) => pane.phase = Phase::Refused(*g, *n, *r),
            Some(Phase::Failed(e)) => pane.phase = Phase::Failed(e.clone()),
            _ => {}
        }
    }

    /// Pane `i`'s source, started: its phase from here (refused when it
    /// could cost more than the budget finding its poses). A pane whose
    /// plan walks the log's own poses (a scan-matched one too, with room
    /// for drift) takes the box grown as the log was read.
    fn started(&self, start: Box<SourceStart>) -> (Option<Box<dyn PoseSource>>, Phase) {
        let scans = &self.scans;
        let source = start.finish(scans).and_then(|source| {
            check_pose_work(scans, source.as_ref(), self.pose_work)?;
            Ok(source)
        });
        match source {
            Err(e) => (None, Phase::Failed(e)),
            Ok(source) => {
                // (The same poses, not equal ones: no walk to compare them.)
                let own = std::ptr::eq(source.plan_poses(scans).0, scans.poses());
                let extent = match &self.read_extent {
                    Some(e) if own => e.clone(),
                    _ => ExtentBox::new(self.settings.settings().no_return_reach),
                };
                (Some(source), Phase::Extent(extent))
            }
        }
    }

    /// Moves pane `i`'s plan on, within `units` of work: its source's
    /// start a step (or, once its path is made, the source taken), or
    /// through the phases whose walk is done, then one scan of its walk.
    /// The units worked, or `None` when it cannot move on within `units`.
    fn advance(&mut self, i: usize, units: usize) -> Option<usize> {
        if let Phase::Start(start) = &mut self.panes[i].phase {
            if !start.is_done(&self.scans) {
                return (units > 0).then(|| {
                    start
                        .step(&self.scans, units.saturating_mul(START_UNITS_PER_PASS))
                        .div_ceil(START_UNITS_PER_PASS)
                });
            }
            let placeholder = Phase::Extent(ExtentBox::new(0.0));
            let Phase::Start(start) = std::mem::replace(&mut self.panes[i].phase, placeholder)
            else {
                return None;
            };
            let (source, phase) = self.started(start);
            let pane = &mut self.panes[i];
            (pane.source, pane.phase) = (source, phase);
            return Some(0);
        }
        let may_walk = units > 0;
        let (scans, c, budget) = (&self.scans, &self.settings, self.budget_cells);
        let pane = &mut self.panes[i];
        // The poses the walks put the scans at (a scan-matched pane's are
        // the log's own: the matched path stays near them), and the room
        // its grid leaves for drift around them.
        let Some(source) = &pane.source else {
            return None;
        };
        let (poses, drift) = source.plan_poses(scans);
        loop {
            match &mut pane.phase {
                Phase::Extent(e) if e.scans() < scans.len() => {
                    if !may_walk {
                        return None;
                    }
                    let k = e.scans();
                    // (A scan at a pose that is not finite is left out, as
                    // the whole-log extent leaves it out.)
                    match poses.get(k).and_then(|&p| at_pose(scans, k, p)) {
                        Some(scan) => e.add(&scan, &scan_model(c, scans, k)),
                        None => e.skip(),
                    }
                    return Some(1);
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
                        return None;
                    }
                    if let Some(scan) = poses.get(*k).and_then(|&p| at_pose(scans, *k, p)) {
                        tiles.add(&scan, beam_reach(c));
                    }
                    *k += 1;
                    return Some(1);
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
                            return None;
                        }
                        let k = w.scans;
                        if let Some(scan) = poses.get(k).and_then(|&p| at_pose(scans, k, p)) {
                            w.tiles.add(&scan, beam_reach(&w.settings));
                        }
                        w.scans += 1;
                        return Some(1);
                    }
                    Some(w) if w.tiles.count() <= budget_tiles(budget) => {
                        pane.phase = Phase::Refused(*grid, *needed, Some(w.resolution))
                    }
                    Some(_) => *walk = None,
                },
                Phase::Ready(..) | Phase::Refused(..) | Phase::Failed(_) | Phase::Start(_) => {
                    return None
                }
            }
        }
    }

    /// True once every pane's plan is walked, or a pane is refused after
    /// panes whose plans are (the plan's answer is then that refusal).
    pub(super) fn finished(&self) -> bool {
        for pane in &self.panes {
            if !pane.phase.is_done() {
                return false;
            }
            if pane.phase.is_refusal() {
                return true;
            }
        }
        true
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
            ..
        } = self;
        panes
            .into_iter()
            .map(|p| {
                let (grid, refused) = match p.phase {
                    Phase::Failed(e) => return Err(e),
                    Phase::Ready(grid, _) => (grid, None),
                    Phase::Refused(grid, needed, fits) => (grid, Some((needed, fits))),
                    // (Not reached once the plan is finished.)
                    Phase::Start(_)
                    | Phase::Extent(_)
                    | Phase::Tiles(..)
                    | Phase::Search { .. } => {
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

    /// True when the pane is refused (its settings make no map of the log).
    fn is_refusal(&self) -> bool {
        matches!(self, Phase::Refused(..) | Phase::Failed(_))
    }
}
