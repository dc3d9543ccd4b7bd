//! SLAM scan by scan ([`SlamBuilder`]): the local trajectory, matched
//! against submaps, and the pose graph over it, closed at loops and
//! optimised.
//!
//! Two frames, as in Hess et al. 2016: the local frame, where each scan is
//! predicted from the one before by the odometry, matched against the
//! growing submap ([`crate::mapping::scan_match::ScanMatcher`]) and
//! inserted into it, and which no optimisation ever changes; and the
//! global frame of the pose graph's nodes, one per scan, what the source
//! hands out. A scan's node starts at the node before moved by the local
//! motion between them; loop closures and the optimiser move the nodes.
//!
//! Every `LOOP_EVERY`-th scan is searched against the finished submaps
//! near it ([`super::loop_search::LoopGrid::search`]), within a window that grows with the
//! distance travelled since the last closure (the drift the odometry and
//! the local matching may have gathered). A match above the least score
//! is only a candidate: it becomes an edge once a second candidate of a
//! scan shortly before agrees with it (the two scans' placements differ as
//! the local trajectory says: a pairwise consistency check in the spirit
//! of Olson 2009, "Recognizing places using spectrally clustered local
//! matches"). The graph is optimised when closures have been added, every
//! `OPTIMIZE_EVERY` scans and at the last scan; every optimisation raises
//! the revision, which tells a map built at the old poses to rebuild. A
//! scan's insertion into the growing submaps, a loop search and an
//! optimisation may run in slices of bounded work
//! ([`SlamBuilder::locate_scan`], [`SlamBuilder::settle_within`]): a
//! submap's insertion a slice, and a slice stopping inside a submap's
//! search or an optimiser iteration if need be. The next scan waits for
//! them, so the poses are bit for bit those of one call.

use super::loop_search::{LoopScan, LoopWindow, SearchUnderWay};
use super::pose_graph::{Edge, Optimizer, PoseGraph, RobustSettings};
use super::submap::Submap;
use crate::error::Result;
use crate::geometry::{wrap_angle, Pose};
use crate::inverse::HandCraftedParams;
use crate::mapping::insertion::{ScanInserter, ScanInsertion};
use crate::mapping::scan_match::{
    compose, relative_motion, MatchReport, MatchSettings, Prediction, ScanMatcher, ScanPoints,
};
use crate::mapping::walls::WallModel;
use crate::sensors::odometry::OdometryParams;
use crate::sensors::Scan;

/// Scans per submap.
pub const SUBMAP_SCANS: usize = 20;
/// Every how many scans a loop is searched for.
pub const LOOP_EVERY: usize = 2;
/// Scans after closures were added before the graph is optimised.
pub const OPTIMIZE_EVERY: usize = 20;
/// The least loop-search score (mean probability of a scan's cells) of a
/// candidate closure: 0.55, the least score Cartographer's constraint
/// builder accepts by default. A place seen again scores less than its
/// own scans do on each other: from another pose, parts of it were never
/// in view, and where beams return from foliage, tall grass or people,
/// the cells they end in were as often crossed. On the Freiburg campus
/// true closures score 0.55 to 0.66: at 0.62 it went 250 m without one
/// and ended 0.43 to 0.97 m off (aligned ATE, seeds 1 to 3), at 0.55 0.33
/// to 0.37 m; the office logs moved by at most 2 cm either way, the MIT
/// corridor by 7 cm. A candidate still becomes an edge only beside a
/// second one that agrees with it, and then meets the graph's robust loss
/// and gate.
pub const LOOP_MIN_SCORE: f64 = 0.55;
/// Metres and radians of the loop window with no distance travelled, and
/// what each metre travelled since the last closure adds, and the most.
const WINDOW_BASE: [f64; 2] = [1.0, 0.10];
const WINDOW_PER_METRE: [f64; 2] = [0.05, 0.004];
const WINDOW_MAX: [f64; 2] = [8.0, 0.5];
/// Scans of the same stretch as the scan searched, not searched: their
/// submaps agree with the local trajectory already.
const RECENT_SCANS: usize = 3 * SUBMAP_SCANS;
/// How far apart two candidates' placements may be (metres, radians) and
/// still agree, and how many scans back a partner is looked for.
const AGREEMENT: [f64; 2] = [0.25, 0.05];
const AGREEMENT_SCANS: usize = 12;
/// Spreads of an accepted local match and of a loop closure (metres,
/// metres, radians).
const MATCH_SIGMA: [f64; 3] = [0.02, 0.02, 0.004];
const LOOP_SIGMA: [f64; 3] = [0.05, 0.05, 0.01];
/// The optimiser's multiply–adds to a unit of work (a cell update), and
/// the units a submap's cell update and a finished submap's cell count:
/// so that every kind of SLAM's work takes about as long a unit as the
/// real-log map's cell update (10 to 16 ns natively, budget.rs), and a
/// page's call sized from the calls before it lasts as long whatever work
/// it meets. Measured natively over Intel's SLAM pane: an optimiser's
/// multiply–add 1.1 ns (the nodes in the envelope order, short rows), a
/// submap's cell update 21 to 29 ns (the campus, Intel), a closed
/// submap's cell read on its way to bytes (the box of its scans, then the
/// box of its known cells kept as bytes) about 8 to 16 ns; counted one to
/// a unit (the closed cells a quarter), they made calls of the same budget
/// last 10 to 36 ms. Measured again kind by kind over the Freiburg
/// campus's SLAM pane: the optimiser's multiply–add 1.7 ns, and a call
/// of optimiser slices ran twice as long as the calls before it at ten to
/// a unit; a closed submap's cell 7 ns in the first pass and 23 in the
/// second, which counts two reads a cell ([`Submap::finish_within`]).
const MULTIPLY_ADDS_PER_UNIT: u64 = 6;
pub const SUBMAP_UPDATE_UNITS: u64 = 2;
pub const FINISHED_CELL_UNITS: u64 = 1;
/// The least multiply–adds of the optimiser a settling step runs (about a
/// tenth of a millisecond natively): one Gauss–Newton iteration of a long
/// log is far more, and is run a slice at a time ([`Optimizer::run_within`]).
const OPTIMIZER_STEP_WORK: u64 = 1 << 16;
/// Most bytes the finished submaps' grids for searching may hold together
/// ([`super::loop_search::LoopGrid`] keeps them between searches: its
/// restored bytes and grids of maxima): those searched least recently are
/// dropped first. A submap's grids are eight bytes a cell of its box (a
/// 30 m laser's submap: up to 1,400 cells a side, 16 MB). Intel natively,
/// with the grids of maxima alone: 10.3 s at 32 MB, 8.1 s at 64, 7.6 s at
/// 128, 30 s making them anew for every search; 72 MB keeps as many
/// submaps ready as 64 MB of grids of maxima did.
const LOOP_SEARCH_BYTES: usize = 72 << 20;
/// The least cells of a closed submap a settling step reads on their way
/// to bytes (about a millisecond natively): a page's build steps a source
/// with a budget of nothing, and a step per row of a campus submap made
/// its SLAM pane 40 % slower.
const FINISH_STEP_CELLS: u64 = 1 << 16;
/// Points kept for loop search: one every this many cells.
const LOOP_POINT_SPACING_CELLS: f64 = 2.0;

/// A located scan on its way into the growing submaps.
#[derive(Debug, Clone)]
struct PendingInsertion {
    scan: usize,
    /// The scan at its local pose.
    placed: Scan,
    laser_max: f64,
    /// The submaps before this one have it.
    next: usize,
}

/// A scan being located, its match against a submap run a stage at a
/// time.
#[derive(Debug, Clone)]
struct PendingLocation {
    scan: Scan,
    laser_max: f64,
    prediction: Prediction,
    /// The growing submap it is matched against, if any.
    submap: Option<usize>,
}

/// A loop-search match waiting for a partner.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    scan: usize,
    edge: Edge,
    /// Where the match puts the scan in the global frame.
    placed: Pose,
}

/// A loop search under way: scan `scan`'s points against the finished
/// submaps from `next` on (the one before, `current`, perhaps searched
/// part way), the best match so far.
#[derive(Debug, Clone)]
struct LoopSearch {
    scan: usize,
    window: LoopWindow,
    here: Pose,
    next: usize,
    /// The submap being searched, and how far its search has got.
    current: Option<(usize, SearchUnderWay)>,
    best: Option<(f64, Candidate)>,
}

/// The SLAM state over one log.
#[derive(Debug, Clone)]
pub struct SlamBuilder {
    odometry: Vec<Pose>,
    noise: OdometryParams,
    resolution: f64,
    matcher: ScanMatcher,
    inserter: ScanInserter,
    /// Local-frame pose of each scan located.
    local: Vec<Pose>,
    pub graph: PoseGraph,
    submaps: Vec<Submap>,
    candidates: Vec<Candidate>,
    /// Metres travelled since the last closure.
    since_closure: f64,
    /// Closures added since the last optimisation.
    pending: usize,
    last_optimized: usize,
    /// The loop search under way, when one runs in slices.
    searching: Option<LoopSearch>,
    /// The last scan located, still to be inserted into the growing
    /// submaps a submap a step ([`Self::settle_within`]).
    inserting: Option<PendingInsertion>,
    /// The optimisation under way, when one runs in slices.
    optimizing: Option<Optimizer>,
    /// The scan being located, its match run a stage at a time.
    locating: Option<PendingLocation>,
    revision: u64,
    closures: usize,
    work: u64,
    /// What the last local match found.
    last_match: MatchReport,
    points: ScanPoints,
    /// The scan under loop search, its points thinned.
    loop_scan: LoopScan,
    /// Submaps closed and not yet made into bytes, oldest first.
    closing: Vec<usize>,
    /// Bytes the finished submaps' grids for searching hold, and loop
    /// searches of a submap ended so far.
    search_bytes: usize,
    searches_ended: u64,
}

impl SlamBuilder {
    /// SLAM from `odometry` (one pose per scan) with its `noise`, matching
    /// with `settings` on submaps of `resolution`.
    pub fn new(
        odometry: Vec<Pose>,
        noise: OdometryParams,
        settings: MatchSettings,
        resolution: f64,
    ) -> Result<Self> {
        let insertion = ScanInsertion {
            model: HandCraftedParams::laser(settings.max_range),
            // As the real-log maps clear along a no-return (5 m).
            no_return_reach: 5.0,
            walls: WallModel::Incidence,
            between_beams: false,
        };
        Ok(Self {
            matcher: ScanMatcher::for_resolution(settings, resolution)?,
            inserter: ScanInserter::new(insertion)?,
            odometry,
            noise,
            resolution,
            local: Vec::new(),
            graph: PoseGraph::default(),
            submaps: Vec::new(),
            candidates: Vec::new(),
            since_closure: 0.0,
            pending: 0,
            last_optimized: 0,
            searching: None,
            inserting: None,
            optimizing: None,
            locating: None,
            revision: 0,
            closures: 0,
            work: 0,
            last_match: MatchReport::unmatched(Pose {
                x: 0.0,
                y: 0.0,
                theta: 0.0,
            }),
            points: ScanPoints::default(),
            loop_scan: LoopScan::default(),
            closing: Vec::new(),
            search_bytes: 0,
            searches_ended: 0,
        })
    }

    /// Scans located so far.
    pub fn located(&self) -> usize {
        self.local.len()
    }

    /// The global pose of each scan located.
    pub fn poses(&self) -> &[Pose] {
        &self.graph.nodes
    }

    /// Raised by every optimisation that moved located scans.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Loop closures in the graph (switched off or not).
    pub fn closures(&self) -> usize {
        self.closures
    }

    /// What the last local match found.
    pub fn last_match(&self) -> &MatchReport {
        &self.last_match
    }

    /// Work since the start besides the local matches, in cell updates
    /// (an optimisation under way counted as far as it has got).
    pub fn work(&self) -> u64 {
        let searched = self
            .searching
            .as_ref()
            .and_then(|s| s.current.as_ref())
            .map_or(0, |(_, under_way)| under_way.work / 8);
        self.work
            + searched
            + self
                .optimizing
                .as_ref()
                .map_or(0, |o| o.work() / MULTIPLY_ADDS_PER_UNIT)
    }

    /// Whether a scan's insertion into the submaps, a loop search or an
    /// optimisation is under way ([`Self::settle_within`]).
    pub fn is_settling(&self) -> bool {
        self.inserting.is_some()
            || !self.closing.is_empty()
            || self.searching.is_some()
            || self.optimizing.is_some()
    }

    /// The odometry this builder starts from.
    pub fn odometry(&self) -> &[Pose] {
        &self.odometry
    }

    /// Locates the next scan (`scan`, its own pose ignored; `laser_max`
    /// its laser's maximum range) and runs the optimisation it calls for
    /// to the end: its global pose.
    pub fn add_scan(&mut self, scan: &Scan, laser_max: f64) -> Result<Pose> {
        let k = self.local.len();
        self.locate_scan(scan, laser_max)?;
        self.settle_within(u64::MAX);
        Ok(self.graph.nodes[k])
    }

    /// Locates the next scan as [`Self::add_scan`] does, but only starts
    /// its insertion into the submaps, the loop search and the
    /// optimisation it calls for ([`Self::settle_within`] runs them): its
    /// global pose before that optimisation. Whatever is still under way
    /// is first run to its end.
    pub fn locate_scan(&mut self, scan: &Scan, laser_max: f64) -> Result<Pose> {
        self.begin_locate(scan, laser_max)?;
        loop {
            if let Some(pose) = self.locate_step()? {
                return Ok(pose);
            }
        }
    }

    /// Starts locating the next scan as [`Self::locate_scan`] does, its
    /// match against the submap to be run a stage at a time
    /// ([`Self::locate_step`]; [`ScanMatcher::begin_match`]). Whatever is
    /// under way is first run to its end, and a location begun before is
    /// dropped.
    pub fn begin_locate(&mut self, scan: &Scan, laser_max: f64) -> Result<()> {
        self.locating = None;
        self.settle_within(u64::MAX);
        let k = self.local.len();
        let settings = *self.matcher.settings();
        let prediction = match (k, self.odometry.get(k)) {
            (_, None) => Prediction::at(scan.pose(), &settings),
            (0, Some(o)) => Prediction::at(*o, &settings),
            (_, Some(o)) => Prediction::from_odometry(
                &self.local[k - 1],
                &self.odometry[k - 1],
                o,
                &self.noise,
                &settings,
            ),
        };
        // Matched against the older growing submap.
        let submap = self
            .submaps
            .iter()
            .position(|s| s.grid.is_some() && s.scans > 0)
            .filter(|_| k > 0);
        if let Some(grid) = submap.and_then(|i| self.submaps[i].grid.as_ref()) {
            self.matcher
                .begin_match(grid, scan, laser_max, &prediction)?;
        }
        self.locating = Some(PendingLocation {
            scan: scan.clone(),
            laser_max,
            prediction,
            submap,
        });
        Ok(())
    }

    /// Whether a scan's location is under way ([`Self::begin_locate`]).
    pub fn is_locating(&self) -> bool {
        self.locating.is_some()
    }

    /// The local match under way ([`Self::begin_locate`]): what it has
    /// done so far.
    pub fn match_under_way(&self) -> Option<&MatchReport> {
        self.locating.as_ref()?;
        self.matcher.under_way()
    }

    /// The next stage of the location begun ([`Self::begin_locate`]): the
    /// scan's global pose once located (as [`Self::locate_scan`] returns
    /// it), `None` while stages are left. An error when none was begun.
    pub fn locate_step(&mut self) -> Result<Option<Pose>> {
        let Some(pending) = self.locating.take() else {
            return Err(crate::error::OccError::State(
                "SLAM: no scan is being located".into(),
            ));
        };
        let report = match pending.submap.and_then(|i| self.submaps[i].grid.as_ref()) {
            Some(grid) => match self.matcher.match_step(grid) {
                Some(report) => report,
                None => {
                    self.locating = Some(pending);
                    return Ok(None);
                }
            },
            None => MatchReport::unmatched(pending.prediction.pose),
        };
        self.place_located(&pending, report).map(Some)
    }

    /// Scan `scan` matched as `report` says: its local pose kept, its
    /// insertion into the submaps begun, its node and edge added, and the
    /// loop search or optimisation it calls for started.
    fn place_located(&mut self, pending: &PendingLocation, report: MatchReport) -> Result<Pose> {
        let (scan, laser_max, prediction) = (&pending.scan, pending.laser_max, &pending.prediction);
        let k = self.local.len();
        self.last_match = report;
        let local = report.pose;
        self.local.push(local);
        self.begin_insertion(k, scan, &local, laser_max)?;
        // The node and its edge to the one before.
        if k == 0 {
            self.graph.nodes.push(local);
        } else {
            let motion = relative_motion(&self.local[k - 1], &local);
            self.since_closure += motion[0].hypot(motion[1]);
            let node = compose(&self.graph.nodes[k - 1], motion);
            self.graph.nodes.push(node);
            let sigma = if report.accepted {
                MATCH_SIGMA
            } else {
                [
                    prediction.position_spread,
                    prediction.position_spread,
                    prediction.heading_spread,
                ]
            };
            self.graph
                .edges
                .push(Edge::new(k - 1, k, motion, sigma, false));
        }
        if k.is_multiple_of(LOOP_EVERY) {
            self.start_loop_search(k, scan, laser_max);
        } else {
            self.start_due_optimization(k);
        }
        Ok(self.graph.nodes[k])
    }

    /// Starts the optimisation due after scan `k`, if one is.
    fn start_due_optimization(&mut self, k: usize) {
        let last = k + 1 == self.odometry.len();
        if self.pending > 0 && (k >= self.last_optimized + OPTIMIZE_EVERY || last) {
            self.optimizing = Some(Optimizer::new(RobustSettings::default()));
            self.pending = 0;
            self.last_optimized = self.local.len();
        }
    }

    /// Sets scan `k` at `local` to be inserted into the growing submaps
    /// ([`Self::insert_step`]), starting the next submap halfway through
    /// the newest. A campus scan's beams reach 30 m into two submaps: its
    /// insertion is as much work as its match, and each is a step of its
    /// own, so that no page's call holds both.
    fn begin_insertion(
        &mut self,
        k: usize,
        scan: &Scan,
        local: &Pose,
        laser_max: f64,
    ) -> Result<()> {
        let growing = self.submaps.iter().filter(|s| s.grid.is_some()).count();
        let newest_half = self
            .submaps
            .last()
            .is_none_or(|s| s.scans >= SUBMAP_SCANS / 2);
        if growing < 2 && newest_half {
            let reach = self.matcher.settings().max_range + 5.0;
            self.submaps
                .push(Submap::start(k, local, reach, self.resolution)?);
        }
        self.inserting = Some(PendingInsertion {
            scan: k,
            placed: scan.with_pose(*local)?,
            laser_max,
            next: 0,
        });
        Ok(())
    }

    /// Inserts the located scan into its next growing submap, closing the
    /// submap once full (made into bytes by [`Self::settle_within`], a
    /// slice of rows at a time: a campus submap's grid is up to 1,400
    /// cells a side).
    fn insert_step(&mut self) {
        let Some(mut pending) = self.inserting.take() else {
            return;
        };
        let growing = |submaps: &[Submap], from: usize| {
            (from..submaps.len()).find(|&i| submaps[i].grid.is_some())
        };
        let Some(i) = growing(&self.submaps, pending.next) else {
            return;
        };
        let reach = self.matcher.settings().max_range.min(pending.laser_max);
        let s = &mut self.submaps[i];
        s.cover(&pending.placed, reach);
        if let Some(grid) = s.grid.as_mut() {
            let stats = self
                .inserter
                .insert(grid, &pending.placed, pending.laser_max);
            self.work += stats.cells_updated as u64 * SUBMAP_UPDATE_UNITS;
        }
        s.scans += 1;
        s.last = pending.scan;
        if s.scans >= SUBMAP_SCANS {
            s.close();
            self.closing.push(i);
        }
        pending.next = i + 1;
        if growing(&self.submaps, pending.next).is_some() {
            self.inserting = Some(pending);
        }
    }

    /// The loop window after `distance` metres since the last closure.
    fn window(distance: f64) -> LoopWindow {
        let w = |i: usize| (WINDOW_BASE[i] + WINDOW_PER_METRE[i] * distance).min(WINDOW_MAX[i]);
        LoopWindow {
            linear: w(0),
            angular: w(1),
            min_score: LOOP_MIN_SCORE,
        }
    }

    /// Starts the search of scan `k` against the finished submaps near
    /// it ([`Self::search_step`] goes through them).
    fn start_loop_search(&mut self, k: usize, scan: &Scan, laser_max: f64) {
        self.points.fill(scan, laser_max, self.matcher.settings());
        let mut points = Vec::new();
        self.points
            .thinned(LOOP_POINT_SPACING_CELLS * self.resolution, &mut points);
        self.loop_scan = LoopScan::new(points);
        self.searching = Some(LoopSearch {
            scan: k,
            window: Self::window(self.since_closure),
            here: self.graph.nodes[k],
            next: 0,
            current: None,
            best: None,
        });
    }

    /// The search under way against its next finished submap near the
    /// scan, or on with the one part searched, until the search's work in
    /// this call reaches `budget` reads (weighed as
    /// [`super::loop_search::SearchUnderWay::work`] weighs them; a bounded step: a
    /// slice of rows of a grid of maxima, or one heading's branch and bound;
    /// [`super::loop_search::LoopGrid::continue_search`]); once every
    /// submap is searched, its closures kept and the optimisation due
    /// started.
    fn search_step(&mut self, budget: u64) {
        let Some(mut search) = self.searching.take() else {
            return;
        };
        let (k, here, window) = (search.scan, search.here, search.window);
        if search.current.is_none() {
            while let Some(s) = self.submaps.get(search.next) {
                search.next += 1;
                let Some(grid) = &s.finished else { continue };
                if s.last + RECENT_SCANS > k {
                    continue;
                }
                // Near: one of its scans within the window and a few metres.
                let near = (s.anchor..=s.last).any(|j| {
                    let p = &self.graph.nodes[j];
                    (p.x - here.x).hypot(p.y - here.y) <= window.linear + 5.0
                });
                if !near {
                    continue;
                }
                let anchor_local = self.local[s.anchor];
                let anchor_global = self.graph.nodes[s.anchor];
                let predicted = compose(&anchor_local, relative_motion(&anchor_global, &here));
                let begun = grid.begin_search(&self.loop_scan, &predicted, &window);
                search.current = Some((search.next - 1, begun));
                break;
            }
        }
        if let Some((i, mut under_way)) = search.current.take() {
            let s = &mut self.submaps[i];
            // A submap's search begins only once it is finished, and a
            // finished submap stays so: `None` never comes here.
            let (found, made) = match s.finished.as_mut() {
                Some(grid) => {
                    let before = grid.search_bytes();
                    let found = grid.continue_search(&mut under_way, &self.loop_scan, budget);
                    (found, grid.search_bytes() - before)
                }
                None => (Some(None), 0),
            };
            let anchor = s.anchor;
            self.search_bytes += made;
            let Some(found) = found else {
                search.current = Some((i, under_way));
                self.searching = Some(search);
                return;
            };
            self.searches_ended += 1;
            self.submaps[i].searched = self.searches_ended;
            self.keep_search_budget(i);
            // The whole search's work, counted once it is over.
            self.work += under_way.work / 8;
            if let Some(found) = found {
                if search.best.as_ref().is_none_or(|(b, _)| *b < found.score) {
                    let anchor_local = self.local[anchor];
                    let anchor_global = self.graph.nodes[anchor];
                    let measurement = relative_motion(&anchor_local, &found.pose);
                    let placed = compose(&anchor_global, measurement);
                    search.best = Some((
                        found.score,
                        Candidate {
                            scan: k,
                            edge: Edge::new(anchor, k, measurement, LOOP_SIGMA, true),
                            placed,
                        },
                    ));
                }
            }
        }
        if search.next < self.submaps.len() {
            self.searching = Some(search);
            return;
        }
        if let Some((_, candidate)) = search.best {
            self.keep_agreeing(k, candidate);
        }
        self.start_due_optimization(k);
    }

    /// Drops the grids for searching of the submaps searched least
    /// recently (never those of submap `keep`, just searched) until they
    /// hold at most [`LOOP_SEARCH_BYTES`].
    fn keep_search_budget(&mut self, keep: usize) {
        while self.search_bytes > LOOP_SEARCH_BYTES {
            let oldest = self
                .submaps
                .iter_mut()
                .enumerate()
                .filter(|(j, s)| {
                    *j != keep && s.finished.as_ref().is_some_and(|g| g.search_bytes() > 0)
                })
                .min_by_key(|(_, s)| s.searched);
            let Some((_, s)) = oldest else { break };
            if let Some(grid) = s.finished.as_mut() {
                self.search_bytes -= grid.search_bytes();
                grid.drop_search_grids();
            }
        }
    }

    /// Scan `k`'s best loop match: an edge with its partner, an earlier
    /// candidate whose placement agrees with this one's as the local
    /// trajectory says, or a candidate waiting for one.
    fn keep_agreeing(&mut self, k: usize, candidate: Candidate) {
        self.candidates.retain(|c| c.scan + AGREEMENT_SCANS >= k);
        let partner = self.candidates.iter().rposition(|c| {
            let by_matches = relative_motion(&c.placed, &candidate.placed);
            let by_local = relative_motion(&self.local[c.scan], &self.local[k]);
            (by_matches[0] - by_local[0]).hypot(by_matches[1] - by_local[1]) <= AGREEMENT[0]
                && wrap_angle(by_matches[2] - by_local[2]).abs() <= AGREEMENT[1]
        });
        match partner {
            Some(i) => {
                let first = self.candidates.remove(i);
                for c in [first, candidate] {
                    self.graph.edges.push(c.edge);
                    self.closures += 1;
                    self.pending += 1;
                }
                self.since_closure = 0.0;
            }
            None => self.candidates.push(candidate),
        }
    }

    /// Inserts the located scan into the growing submaps a submap at a
    /// time, makes the closed submaps into bytes a slice of rows at a time,
    /// runs the loop search under way a slice of a submap's search at a
    /// time, then the optimisation a slice of an iteration at a time
    /// ([`Optimizer::run_within`]), until this call's work reaches `budget`
    /// (in cell updates; at least one step); once the optimisation has
    /// converged the revision rises.
    /// True when none is left under way.
    pub fn settle_within(&mut self, budget: u64) -> bool {
        let start = self.work();
        loop {
            let spent = self.work() - start;
            if self.inserting.is_some() {
                self.insert_step();
            } else if let Some(&i) = self.closing.first() {
                // A closed submap made into bytes, whole rows at a time,
                // at least FINISH_STEP_CELLS a step.
                let left =
                    (budget.saturating_sub(spent) / FINISHED_CELL_UNITS).max(FINISH_STEP_CELLS);
                let (read, done) = self.submaps[i].finish_within(left);
                self.work += read * FINISHED_CELL_UNITS;
                if done {
                    self.closing.remove(0);
                }
            } else if self.searching.is_some() {
                // The search counts reads of a grid of maxima being made
                // (and others by their cost in those), eight to a cell
                // update; a step of at least a slice of a grid made, or one heading.
                let left = budget.saturating_sub(spent).saturating_mul(8);
                self.search_step(left);
            } else if let Some(optimizer) = self.optimizing.as_mut() {
                // The optimiser counts multiply–adds; a step of at least
                // OPTIMIZER_STEP_WORK, so that a caller asking for a step
                // at a time (a budget of 0) gets one worth the asking.
                let left = budget
                    .saturating_sub(spent)
                    .saturating_mul(MULTIPLY_ADDS_PER_UNIT)
                    .max(OPTIMIZER_STEP_WORK);
                if optimizer.run_within(&mut self.graph, left) {
                    self.work += optimizer.work() / MULTIPLY_ADDS_PER_UNIT;
                    self.optimizing = None;
                    self.revision += 1;
                }
            } else {
                return true;
            }
            if self.work() - start >= budget {
                return !self.is_settling();
            }
        }
    }
}
