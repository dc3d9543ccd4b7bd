//! The SLAM pose source ([`Slam`]): seeded dead reckoning (or the log's
//! own odometry where it has some, as the scan-matched source) corrected
//! by matching each scan against a submap of the scans before it, loops
//! closed against finished submaps, the pose graph optimised
//! ([`crate::slam`]). It keeps its own submaps: the map it is handed is
//! not read. After an optimisation the poses of earlier scans change, and
//! the revision ([`PoseSource::revision`]) rises: a map built at the old
//! poses is built again. An optimisation runs in slices of bounded work
//! ([`PoseSource::settle_within`]), its poses handed out only once it has
//! converged.
//!
//! What finding the poses of a log may cost is stated before its first
//! scan is located ([`work_bound`]): the local matches and the insertion
//! into submaps bounded as the scan-matched source bounds its matches,
//! and the loop search and the optimisation given an allowance per scan
//! that the source keeps: past its bound it locates no more scans and says
//! so ([`PoseSource::refusal`]). A reset, like the start
//! ([`super::SourceStart`]), makes its copies of the path a bounded number
//! of poses per step ([`PoseSource::settle_within`]).

use super::scan_matched::path_work_bound;
use super::{
    PoseSource, PoseSourceKind, SourceInfo, SourceSettings, COPIES_PER_UNIT, MATCH_DRIFT_MARGIN,
};
use crate::error::{OccError, Result};
use crate::geometry::Pose;
use crate::mapping::scan_match::{MatchMap, MatchSettings};
use crate::sensors::{Scan, ScanLog};
use crate::slam::builder::{FINISHED_CELL_UNITS, LOOP_EVERY, SUBMAP_SCANS, SUBMAP_UPDATE_UNITS};
use crate::slam::SlamBuilder;

pub(super) const INFO: SourceInfo = SourceInfo {
    kind: PoseSourceKind::Slam,
    name: "slam",
    menu: "SLAM (scan matching with loop closure)",
    caption: &["SLAM (from dead reckoning, seed ", ")"],
    described: Some(&[
        "slam (seed ",
        "): dead reckoning (or the log's own odometry) matched against submaps, loops closed and the pose graph optimised, not the log's corrected poses",
    ]),
    provenance: &[
        "slam (from odometry simulated with Table 5.6's noise, seed ",
        ", or the log's own odometry where it differs from its corrected poses; submaps matched, loops closed, the pose graph optimised)",
    ],
    export_suffix: Some("slam"),
    beside: &[PoseSourceKind::Corrected, PoseSourceKind::DeadReckoning],
};

/// The loop search's and the optimisation's allowance, in searches of a
/// whole submap per loop search: a search of a finished submap may have
/// to make its seven grids of maxima, 3.5 units a cell
/// ([`crate::slam::loop_search`]), though a submap keeps them between
/// searches while memory allows. At 5 cm, searching and optimising
/// together spend 0.12 of one (Intel) to 0.39 (the Freiburg campus, whose
/// submaps are the largest and are made again most often); before the
/// grids were kept, 1.1 and 0.8.
pub const LOOP_SEARCH_ALLOWANCE: u64 = 1;

/// Units a local match counts, per unit of [`super::match_work`] but its
/// coarse copy ([`local_match_work`]): a match against a submap takes
/// about 21 ns a unit natively (Intel and the campus), twice the real-log
/// map's cell update, which a page's call is sized by.
pub const LOCAL_MATCH_UNITS: u64 = 2;

/// The units a local match of SLAM counts: its coarse copy as
/// [`super::match_work`] counts it, and the rest [`LOCAL_MATCH_UNITS`]
/// times. Measured stage by stage on the Freiburg campus (5 cm, natively),
/// a submap's cells are pooled at 1.5 ns a cell, as fast as the real-log
/// map's: counted twice, the copy took 3.7 ns a unit where the search
/// took 10, and a page's calls sized from steps of copies ran twice as
/// long once they met the other work.
pub fn local_match_work(report: &crate::mapping::scan_match::MatchReport) -> u64 {
    super::match_work(report) * LOCAL_MATCH_UNITS
        - super::pooled_work(report) * (LOCAL_MATCH_UNITS - 1)
}

/// Units of work a cell of a submap costs a loop search (the grids of
/// maxima, eq. 14 of Hess et al. 2016: seven depths, four reads a cell, eight
/// reads to a unit), in halves.
const SEARCH_HALF_UNITS_PER_CELL: u64 = 7;

/// Poses a step of a reset copies at least, whatever its budget: steps of
/// a few hundred units, so that a pane's build, a step a call at least,
/// restarts a long log in a few calls.
const RESTART_STEP_POSES: usize = 4096;

/// The most work finding the SLAM poses of every scan of `log` may cost
/// under `settings` on maps of `resolution` metres per cell, in the units
/// of a cell update (what [`PoseSource::work`] counts):
///
/// - every scan but the first matched against a submap, at the most
///   [`super::match_work_bound`] allows (as the scan-matched source),
///   [`LOCAL_MATCH_UNITS`] a unit of it (more than [`local_match_work`]
///   counts);
/// - every scan inserted into the two growing submaps, a beam updating at
///   most the cells of a line twice as long as the matcher's range (and
///   the no-return reach) and a metre more, and the laser's own cell,
///   `SUBMAP_UPDATE_UNITS` a cell update;
/// - a submap started every `SUBMAP_SCANS / 2` scans, each finished once
///   (two passes over at most its grid, the second two reads a cell,
///   `FINISHED_CELL_UNITS` a read, at most `2 (maxRange + 5) / resolution`
///   cells a side);
/// - every `LOOP_EVERY`-th scan searched for a loop and the graph
///   optimised: [`LOOP_SEARCH_ALLOWANCE`] searches of a whole submap each
///   (the loop search's cost grows with the submaps near a scan, which no
///   plan knows before the path is found: an allowance the source keeps,
///   not a bound of the search);
/// - the two copies of the path a reset makes again, [`COPIES_PER_UNIT`]
///   poses to a unit (a step's last unit perhaps not full).
pub(super) fn work_bound(settings: &MatchSettings, resolution: f64, log: &ScanLog) -> u64 {
    let n = log.len() as u64;
    let local = path_work_bound(settings, resolution, log).saturating_mul(LOCAL_MATCH_UNITS);
    let beam_reach = settings.max_range.max(5.0) + 1.0;
    let per_beam = (2.0 * beam_reach / resolution).ceil() as u64 + 2;
    let inserted = (log.beams() as u64)
        .saturating_mul(per_beam)
        .saturating_add(n)
        .saturating_mul(2 * SUBMAP_UPDATE_UNITS);
    // The side of a submap's grid (`Submap::start`: at least 64 cells).
    let side = ((2.0 * (settings.max_range + 5.0) / resolution).ceil() as u64).max(64);
    let cells = side.saturating_mul(side);
    let submaps = n / (SUBMAP_SCANS as u64 / 2) + 1;
    let finished = submaps.saturating_mul(cells.saturating_mul(3 * FINISHED_CELL_UNITS));
    let searches = n.div_ceil(LOOP_EVERY as u64);
    let loops = searches
        .saturating_mul(LOOP_SEARCH_ALLOWANCE)
        .saturating_mul(cells.saturating_mul(SEARCH_HALF_UNITS_PER_CELL) / 2);
    let copies = 2 * (n.div_ceil(COPIES_PER_UNIT as u64) + 1);
    local
        .saturating_add(inserted)
        .saturating_add(finished)
        .saturating_add(loops)
        .saturating_add(copies)
}

/// SLAM as a pose source.
#[derive(Debug, Clone)]
pub struct Slam {
    builder: SlamBuilder,
    /// The graph's poses for the scans located, the odometry's after.
    poses: Vec<Pose>,
    /// The local matches' work ([`super::match_work`]).
    match_work: u64,
    /// The part of that counted for the match under way.
    match_counted: u64,
    /// What a fresh builder is made with.
    settings: SourceSettings,
    /// The most work finding every pose may cost ([`work_bound`]).
    bound: u64,
    /// A reset under way: the builder is the old one until it is done.
    restart: Option<Restart>,
    /// Units spent copying poses since the last reset.
    copy_work: u64,
    /// Revisions of builders reset since the start, so that the revision
    /// only grows.
    revision_base: u64,
    /// Why no more scans are located (the bound passed), once it is so.
    refused: Option<OccError>,
}

/// A reset under way: the fresh builder's copy of the odometry, and the
/// poses handed out set back to the odometry, a bounded number a step.
#[derive(Debug, Clone)]
struct Restart {
    odometry: Vec<Pose>,
    /// `poses[..restored]` are the odometry's again.
    restored: usize,
    /// `poses[dirty..]` never left the odometry's.
    dirty: usize,
}

impl Slam {
    /// SLAM from `odometry` (one pose per scan: the log's own, or dead
    /// reckoning, made by the caller) and `poses` a copy of it (the poses
    /// handed out), keeping to `bound` units of work ([`work_bound`]).
    pub(super) fn of_path(
        (odometry, poses): (Vec<Pose>, Vec<Pose>),
        settings: &SourceSettings,
        bound: u64,
    ) -> Result<Self> {
        Ok(Self {
            builder: Self::fresh_builder(odometry, settings)?,
            poses,
            match_work: 0,
            match_counted: 0,
            settings: *settings,
            bound,
            restart: None,
            copy_work: 0,
            revision_base: 0,
            refused: None,
        })
    }

    fn fresh_builder(odometry: Vec<Pose>, s: &SourceSettings) -> Result<SlamBuilder> {
        SlamBuilder::new(odometry, s.noise, s.matching, s.resolution)
    }

    /// The graph's poses handed out (once an optimisation has converged).
    fn take_poses(&mut self) {
        let found = self.builder.poses();
        self.poses[..found.len()].copy_from_slice(found);
    }

    /// The SLAM state: its graph, closures, revision.
    pub fn builder(&self) -> &SlamBuilder {
        &self.builder
    }

    /// Up to `max_units` units (at least [`RESTART_STEP_POSES`] poses) of
    /// the reset under way: the fresh builder's odometry copied, then the
    /// poses handed out set back; once both are done, the fresh builder
    /// takes the old one's place.
    fn restart_step(&mut self, max_units: u64) {
        let Some(r) = self.restart.as_mut() else {
            return;
        };
        let least = RESTART_STEP_POSES.div_ceil(COPIES_PER_UNIT);
        let units = usize::try_from(max_units).unwrap_or(usize::MAX).max(least);
        let odometry = self.builder.odometry();
        // The fresh copy first (room for all of it reserved at once).
        let k0 = r.odometry.len();
        let end = odometry
            .len()
            .min(k0.saturating_add(units.saturating_mul(COPIES_PER_UNIT)));
        r.odometry.reserve_exact(odometry.len() - k0);
        r.odometry.extend_from_slice(&odometry[k0..end]);
        let mut spent = (end - k0).div_ceil(COPIES_PER_UNIT);
        let left = units.saturating_sub(spent);
        if r.odometry.len() == odometry.len() && left > 0 {
            let end = r.dirty.min(
                r.restored
                    .saturating_add(left.saturating_mul(COPIES_PER_UNIT)),
            );
            if r.restored < end {
                self.poses[r.restored..end].copy_from_slice(&odometry[r.restored..end]);
                spent += (end - r.restored).div_ceil(COPIES_PER_UNIT);
                r.restored = end;
            }
        }
        self.copy_work += spent as u64;
        if r.odometry.len() < odometry.len() || r.restored < r.dirty {
            return;
        }
        let odometry = std::mem::take(&mut r.odometry);
        self.restart = None;
        match Self::fresh_builder(odometry, &self.settings) {
            Ok(fresh) => {
                self.revision_base += self.builder.revision();
                self.builder = fresh;
            }
            // (Not reached: the same settings made the builder before.)
            Err(e) => self.refused = Some(e),
        }
    }

    /// Refuses to go on once the work has passed the bound.
    fn check_bound(&mut self, k: usize) -> Result<()> {
        if let Some(e) = &self.refused {
            return Err(e.clone());
        }
        if self.work() <= self.bound {
            return Ok(());
        }
        let e = OccError::State(format!(
            "the pose source slam passed its bound of {} units of work (cell updates) at scan {k} \
             ({} units spent): its loop search and optimisation cost this log more than the \
             {LOOP_SEARCH_ALLOWANCE} searches of a whole submap a search allowed; map it \
             scan-matched, at poses known in advance, or fewer of its scans",
            self.bound,
            self.work()
        ));
        self.refused = Some(e.clone());
        Err(e)
    }
}

impl PoseSource for Slam {
    fn kind(&self) -> PoseSourceKind {
        PoseSourceKind::Slam
    }

    /// The poses found; during a reset, the odometry (where the reset is
    /// heading), which the builder being replaced still holds whole.
    fn poses(&self) -> &[Pose] {
        match self.restart {
            Some(_) => self.builder.odometry(),
            None => &self.poses,
        }
    }

    /// Scan `k` located by SLAM. Scans come in order from the first: a
    /// scan out of order is an error, and nothing changes. A reset under
    /// way is finished first; past the bound, an error.
    fn locate(
        &mut self,
        k: usize,
        scan: &Scan,
        laser_max: f64,
        map: &dyn MatchMap,
    ) -> Result<Pose> {
        loop {
            if let Some(pose) = self.locate_step(k, scan, laser_max, map)? {
                return Ok(pose);
            }
        }
    }

    /// A stage of scan `k`'s location ([`SlamBuilder::locate_step`]): its
    /// match against the submap runs a stage a call, its work counted as
    /// it goes. The first call checks the order and the bound as
    /// [`Self::locate`] does.
    fn locate_step(
        &mut self,
        k: usize,
        scan: &Scan,
        laser_max: f64,
        map: &dyn MatchMap,
    ) -> Result<Option<Pose>> {
        let _ = map;
        while self.restart.is_some() {
            self.restart_step(u64::MAX);
        }
        if k != self.builder.located() {
            return Err(OccError::State(format!(
                "SLAM locates scans in order: scan {k} asked, scan {} next",
                self.builder.located()
            )));
        }
        let revision = self.builder.revision();
        if !self.builder.is_locating() {
            self.check_bound(k)?;
            self.builder.begin_locate(scan, laser_max)?;
            self.match_counted = 0;
        }
        let located = self.builder.locate_step()?;
        let so_far = match located {
            Some(_) => local_match_work(self.builder.last_match()),
            None => self.builder.match_under_way().map_or(0, local_match_work),
        };
        self.match_work += so_far.saturating_sub(self.match_counted);
        self.match_counted = so_far;
        // Beginning the scan settled what the scan before left (an
        // optimisation among it): its revision is taken here, in the
        // stage that saw it, whether or not the match is done.
        if self.builder.revision() != revision {
            self.take_poses();
        } else if let (Some(pose), Some(p)) = (located, self.poses.get_mut(k)) {
            *p = pose;
        }
        Ok(located)
    }

    fn loop_closures(&self) -> Option<usize> {
        Some(self.builder.closures())
    }

    fn pose_graph(&self) -> Option<&crate::slam::PoseGraph> {
        Some(&self.builder.graph)
    }

    fn settling(&self) -> bool {
        self.restart.is_some() || (self.builder.is_settling() && self.refused.is_none())
    }

    fn settle_within(&mut self, budget: u64) -> bool {
        if self.restart.is_some() {
            self.restart_step(budget);
            return !self.settling();
        }
        if self.refused.is_some() || self.check_bound(self.builder.located()).is_err() {
            return true;
        }
        let revision = self.builder.revision();
        let done = self.builder.settle_within(budget);
        if self.builder.revision() != revision {
            self.take_poses();
        }
        done
    }

    fn plan_poses<'a>(&'a self, log: &'a ScanLog) -> (&'a [Pose], f64) {
        (log.poses(), MATCH_DRIFT_MARGIN)
    }

    /// The work since the last reset: during one, its copies alone.
    fn work(&self) -> u64 {
        match self.restart {
            Some(_) => self.copy_work,
            None => self.builder.work() + self.match_work + self.copy_work,
        }
    }

    fn work_bound(&self, log: &ScanLog) -> u64 {
        work_bound(&self.settings.matching, self.settings.resolution, log)
    }

    /// Back to before the first scan, in steps ([`Self::settle_within`]):
    /// here only marked.
    fn reset(&mut self) {
        self.match_work = 0;
        self.match_counted = 0;
        self.copy_work = 0;
        self.refused = None;
        // (A builder that has located nothing is as fresh as a new one.)
        let fresh = self.builder.located() == 0
            && !self.builder.is_settling()
            && !self.builder.is_locating();
        if self.restart.is_none() && !fresh {
            self.restart = Some(Restart {
                odometry: Vec::new(),
                restored: 0,
                dirty: self.builder.located(),
            });
        }
    }

    fn revision(&self) -> u64 {
        self.revision_base + self.builder.revision()
    }

    fn revises(&self) -> bool {
        true
    }

    fn refusal(&self) -> Option<&OccError> {
        self.refused.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mapping::scan_match::MatchSettings;
    use crate::sensors::odometry::OdometryParams;

    /// Scans of four beams, 5 cm apart along a line, and their poses.
    struct Log(Vec<Scan>);

    impl Log {
        fn poses(&self) -> Vec<Pose> {
            self.0.iter().map(|s| s.pose()).collect()
        }
        fn len(&self) -> usize {
            self.0.len()
        }
        fn scan(&self, k: usize) -> Option<Scan> {
            self.0.get(k).cloned()
        }
    }

    fn log(scans: usize) -> Log {
        let bearings = vec![-0.6, -0.2, 0.2, 0.6];
        Log((0..scans)
            .map(|k| {
                let pose = Pose {
                    x: k as f64 * 0.05,
                    y: 0.0,
                    theta: 0.3,
                };
                Scan::new(pose, vec![1.0, 1.5, 2.0, 2.5], bearings.clone()).unwrap()
            })
            .collect())
    }

    fn slam(log: &Log, bound: u64) -> Slam {
        let settings = SourceSettings {
            seed: 1,
            noise: OdometryParams::WHEELS,
            matching: MatchSettings::default(),
            resolution: 0.05,
        };
        let path = log.poses();
        Slam::of_path((path.clone(), path), &settings, bound).unwrap()
    }

    fn locate(source: &mut Slam, log: &Log, k: usize) -> Result<Pose> {
        let scan = log.scan(k).unwrap();
        let none = crate::grid::TiledGrid::new(
            crate::geometry::GridGeometry::new(8, 8, 0.05, 0.0, 0.0).unwrap(),
            crate::grid::FilterSettings {
                prior: 0.5,
                clamp: 3.5,
            },
            64,
        )
        .unwrap();
        source.locate(k, &scan, f64::INFINITY, &none)
    }

    /// Past its bound the source locates no more scans, and says so by
    /// name, with the bound; a reset starts it afresh.
    #[test]
    fn past_its_bound_slam_refuses_by_name_and_figure() {
        let log = log(6);
        // Scan 0 located, and inserted into its submaps as the source
        // settles.
        let first = |source: &mut Slam| {
            locate(source, &log, 0).unwrap();
            while source.settling() {
                source.settle_within(u64::MAX);
            }
        };
        let mut unbounded = slam(&log, u64::MAX);
        first(&mut unbounded);
        // A bound scan 0's insertion passes.
        let bound = unbounded.work() - 1;
        assert!(bound > 4, "scan 0's insertion is work");
        let mut source = slam(&log, bound);
        first(&mut source);
        let e = locate(&mut source, &log, 1).unwrap_err().to_string();
        assert!(
            e.contains(&format!(
                "the pose source slam passed its bound of {bound} units of work"
            )) && e.contains("at scan 1"),
            "{e}"
        );
        assert_eq!(source.refusal().map(|r| r.to_string()), Some(e.clone()));
        assert_eq!(locate(&mut source, &log, 1).unwrap_err().to_string(), e);
        source.reset();
        assert!(source.refusal().is_none());
        assert!(locate(&mut source, &log, 0).is_ok());
    }

    /// A reset hands out the odometry at once, and makes its copies in
    /// steps; the poses found again are the same, bit for bit.
    #[test]
    fn a_reset_restarts_in_steps_to_the_same_poses() {
        let log = log(30);
        let mut source = slam(&log, u64::MAX);
        let mut first = Vec::new();
        for k in 0..log.len() {
            first.push(locate(&mut source, &log, k).unwrap());
            while source.settling() {
                source.settle_within(0);
            }
        }
        let found = source.poses().to_vec();
        source.reset();
        assert!(source.settling());
        assert_eq!(source.poses(), &log.poses()[..]);
        assert_eq!(source.work(), 0);
        while source.settling() {
            source.settle_within(0);
        }
        assert!(source.work() > 0, "the copies are counted");
        assert_eq!(source.poses(), &log.poses()[..]);
        for (k, pose) in first.iter().enumerate() {
            assert_eq!(locate(&mut source, &log, k).unwrap(), *pose);
            while source.settling() {
                source.settle_within(0);
            }
        }
        assert_eq!(source.poses(), &found[..]);
    }
}
