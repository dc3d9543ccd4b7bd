//! The session a real-log panel drives ([`RealLogSession`]): a log (of any
//! format [`crate::io::open_log`] reads) read a few records at a time, then
//! mapped a few scans at a time into one
//! pane per pose source (the corrected map, and beside it the
//! dead-reckoned and scan-matched ones when the reader asks for them),
//! with the one state
//! ([`SessionState`]) the panel renders.

use super::budget::{scan_model, MAX_POSE_WORK};
use super::pane::LogPane;
use super::planning::PanePlanning;
use super::settings::{CheckedSettings, LogMapSettings};
use super::view::GeometryReport;
use super::SessionState;
use crate::error::{invalid, OccError, Result};
use crate::grid::storage::DEFAULT_TILE_BUDGET_CELLS;
use crate::inverse::HandCrafted;
use crate::io::{open_log, LoadProgress, LogBudget, LogSource, TopicChoices};
use crate::mapping::reach::ExtentBox;
use crate::poses::PoseSourceKind;
use crate::sensors::odometry::OdometryParams;
use crate::sensors::ScanLog;
use std::sync::Arc;

/// The share of a load's progress given to reading the file; the rest is
/// mapping it (reading the Intel log takes about a third of its load).
pub const READ_SHARE: f64 = 0.3;

/// What the read of a log reports: its progress and the file's size.
/// `finished` is true once the log is read and its panes are planned.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ReadReport {
    #[serde(flatten)]
    pub progress: LoadProgress,
    pub bytes_total: usize,
    /// The call's work, in scans: the scans it read or placed
    /// ([`crate::io::LogSource::scan_steps`]; each scan's share of
    /// the map's extent is grown as it is read) and the scans its planning
    /// of the panes walked, and the poses it made starting their sources
    /// ([`crate::poses::SourceStart::step`]'s units); at most the call's
    /// `max_scans`, or 1.
    pub work: usize,
}

/// What a call of [`RealLogSession::plan`] did: the planning of the panes
/// after new settings ([`super::Stage::Planning`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct PlanReport {
    /// The call's work, in scans walked: at most its `max_scans`, or 1.
    pub work: usize,
    /// True once the new panes are in place.
    pub finished: bool,
}

/// Scans of planning a call of [`RealLogSession::configure`] walks itself:
/// a small log's panes are in place when it returns; a longer one's
/// planning goes on over [`RealLogSession::plan`] calls of the page's
/// budget, the maps on screen staying until then.
pub const CONFIGURE_SCANS: usize = 256;

/// A finished planning: its scans, its panes (or why the settings make
/// none) and what it was for.
type Planned = (Arc<ScanLog>, Result<Vec<LogPane>>, PlanFor);

/// What a planning under way is for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum PlanFor {
    /// The log just read (the last calls of its read).
    Read,
    /// New settings for the panes on screen, which head for `target`
    /// scans; `previous` their settings, in force again if the new ones
    /// make no map of the log.
    Settings {
        previous: CheckedSettings,
        target: usize,
    },
    /// New settings for scans that awaited them.
    Pending,
}

/// A log being read and mapped, step by step:
///
/// 1. [`Self::new`] takes the file's bytes (gzip or plain), or
///    [`Self::idle`] none until [`Self::open`];
/// 2. [`Self::read`] reads up to `n` more laser lines per call, then plans
///    one pane per pose source ([`crate::poses::PoseSourceKind::panes`]) in calls of at
///    most `n` scans of work, until finished;
/// 3. [`Self::build_slice`] advances every pane within one budget of cell
///    updates per call;
/// 4. [`Self::seek`] scrubs every pane to `k` scans, and
///    [`Self::configure`] restarts the build with new settings, after a
///    planning of the panes that [`Self::plan`] walks in bounded calls.
///
/// [`Self::state`] says where it stands; the panes answer for their maps.
pub struct RealLogSession {
    /// The reader over the file's bytes (of the format its first bytes
    /// name), dropped (with the bytes) once the whole log is read.
    pub(super) loader: Option<Box<dyn LogSource>>,
    pub(super) budget: LogBudget,
    /// The box of the scans read so far at their own poses, grown as they
    /// are read, under the model and no-return reach it is keyed by (the
    /// settings' when the read began; dropped if they change meanwhile):
    /// the corrected pane's extent, with no walk left for the last read.
    pub(super) read_extent: Option<(HandCrafted, f64, ExtentBox)>,
    /// The panes planned over the calls of the read that follow its last
    /// line, or over [`Self::plan`]'s after new settings.
    pub(super) planning: Option<(PanePlanning, PlanFor)>,
    /// Scans read whose map the current settings cannot make (a grid too
    /// large), and why: kept until `configure` brings settings that fit.
    pub(super) pending: Option<(Arc<ScanLog>, OccError)>,
    /// The read under way, or how the last one ended.
    pub(super) read_report: Option<ReadReport>,
    /// Why the read was refused, once it has been (the file is freed).
    pub(super) read_failure: Option<OccError>,
    pub(super) bytes_total: usize,
    /// The name of the log last opened.
    pub(super) log: Option<String>,
    pub(super) settings: CheckedSettings,
    pub(super) panes: Vec<LogPane>,
    /// True while the build is the one that follows a read (the progress
    /// bar then continues from the read's share).
    pub(super) after_read: bool,
    pub(super) budget_cells: usize,
    /// The most work finding a pane's poses may cost ([`MAX_POSE_WORK`]).
    pub(super) pose_work: u64,
    /// The topics a refused read wanted a choice between (a bag's).
    pub(super) topic_choices: Option<TopicChoices>,
    /// The poses of the log last read, once read, when the reader names
    /// none ([`PoseSourceKind::own_of`]).
    pub(super) read_own_poses: Option<PoseSourceKind>,
}

impl Default for RealLogSession {
    fn default() -> Self {
        Self::idle()
    }
}

impl RealLogSession {
    /// A session without a log: [`Self::open`] gives it one.
    pub fn idle() -> Self {
        Self {
            loader: None,
            budget: LogBudget::default(),
            read_extent: None,
            planning: None,
            pending: None,
            read_report: None,
            read_failure: None,
            bytes_total: 0,
            log: None,
            settings: CheckedSettings::default(),
            panes: Vec::new(),
            after_read: false,
            budget_cells: DEFAULT_TILE_BUDGET_CELLS,
            pose_work: MAX_POSE_WORK,
            topic_choices: None,
            read_own_poses: None,
        }
    }

    /// A session about to read `bytes` (a log of any format
    /// [`open_log`] reads).
    pub fn new(bytes: Vec<u8>) -> Self {
        Self::with_budget(bytes, LogBudget::default())
    }

    /// A session whose reader has its own budget (a test's smaller one).
    pub fn with_budget(bytes: Vec<u8>, budget: LogBudget) -> Self {
        let mut s = Self::idle();
        s.budget = budget;
        s.open(bytes, "log");
        s
    }

    /// A session whose panes' tiles hold at most `budget_cells` cells (a
    /// test's smaller budget; the default is [`DEFAULT_TILE_BUDGET_CELLS`]).
    pub fn with_tile_budget(bytes: Vec<u8>, budget_cells: usize) -> Self {
        let mut s = Self::idle();
        s.budget_cells = budget_cells;
        s.open(bytes, "log");
        s
    }

    /// A session whose panes may cost at most `units` of work finding their
    /// poses (a test's smaller budget, for a shorter log; the default is
    /// [`MAX_POSE_WORK`]).
    pub fn with_pose_work_budget(bytes: Vec<u8>, units: u64) -> Self {
        let mut s = Self::idle();
        s.pose_work = units;
        s.open(bytes, "log");
        s
    }

    /// Starts reading another log, `name` its file's name (what the state
    /// is about from now on). The panes of the log read before stay (on
    /// screen, and operable) until this one is read; a log that waited for
    /// settings is dropped.
    pub fn open(&mut self, bytes: Vec<u8>, name: &str) {
        self.log = Some(name.to_string());
        self.read_own_poses = None;
        self.bytes_total = bytes.len();
        self.planning = None;
        self.pending = None;
        self.read_failure = None;
        self.read_report = None;
        self.topic_choices = None;
        let (model, reach) = self.extent_key();
        self.read_extent = Some((model, reach, ExtentBox::new(reach)));
        match open_log(bytes, self.budget) {
            Ok(loader) => self.loader = Some(loader),
            Err(e) => {
                // A format the core knows but does not read: refused as a
                // malformed file is, at the first read.
                self.loader = None;
                self.read_failure = Some(e);
            }
        }
    }

    /// Names the topics of a ROS 2 bag to map (its LaserScan and its
    /// Odometry topic), before its first read: refused for a file without
    /// topics, once reading has begun, or when no log is open.
    pub fn choose_topics(
        &mut self,
        scan_topic: Option<String>,
        odom_topic: Option<String>,
    ) -> Result<()> {
        match self.loader.as_mut() {
            Some(loader) => loader.choose_topics(scan_topic, odom_topic),
            None => Err(OccError::State("no log to read: open one first".into())),
        }
    }

    /// The poses the log is mapped at when the reader names none: while
    /// it is being read, its format's ([`crate::io::LogFormat::own_poses`]);
    /// once read, its own ([`PoseSourceKind::own_of`]: a ROS 2 bag's
    /// corrected poses where it carries a `map → odom` transform, which
    /// only its read finds); `None` without a log.
    pub fn own_poses(&self) -> Option<PoseSourceKind> {
        match &self.loader {
            Some(l) => Some(l.format().own_poses()),
            None => self.read_own_poses,
        }
    }

    /// Reads up to `max_scans` more laser lines (and at most the reader's
    /// budget of lines and bytes per call: [`LogBudget`]). When the log is
    /// finished its panes are set up; a malformed line is an error naming
    /// its line number, and so is a log past the budget or without laser
    /// lines: the file and the scans read are then freed, and every later
    /// call gives the same error (the session stays usable: settings, and
    /// [`Self::open`] for another file). A log cut short is read up to the
    /// cut, with the report's `warning` naming the line. If the settings
    /// make too large a grid for this log, that is an error too, and the
    /// scans wait ([`super::Stage::AwaitingSettings`]) for a [`Self::configure`]
    /// that fits.
    pub fn read(&mut self, max_scans: usize) -> Result<ReadReport> {
        if let Some(e) = &self.read_failure {
            return Err(e.clone());
        }
        if matches!(self.planning, Some((_, PlanFor::Read))) {
            return self.plan_step(max_scans, 0);
        }
        let Some(loader) = self.loader.as_mut() else {
            return Err(OccError::State(if self.read_report.is_some() {
                "the log has been read already".into()
            } else {
                "no log to read: open one first".into()
            }));
        };
        // Counted in passes over scans, not scans kept: a bag keeps none
        // until every message is read.
        let steps_before = loader.scan_steps();
        let progress = match loader.read(max_scans) {
            Ok(p) => p,
            Err(e) => return Err(self.read_failed(e)),
        };
        let read = loader.scan_steps() - steps_before;
        self.grow_read_extent();
        let finished = progress.finished;
        let mut report = ReadReport {
            progress,
            bytes_total: self.bytes_total,
            work: read,
        };
        if !finished {
            self.read_report = Some(report.clone());
            return Ok(report);
        }
        let Some(loader) = self.loader.take() else {
            return Ok(report);
        };
        if loader.scans().is_empty() {
            self.read_report = Some(report.clone());
            let e = loader.no_scans();
            return Err(self.read_failed(e));
        }
        let scans = loader.into_scans();
        self.read_own_poses = Some(PoseSourceKind::own_of(&scans));
        let extent = self.read_extent.take().map(|(_, _, e)| e);
        self.planning = Some((
            PanePlanning::new(
                Arc::new(scans),
                &self.settings,
                OdometryParams::WHEELS,
                (self.budget_cells, self.pose_work),
                extent,
            ),
            PlanFor::Read,
        ));
        // The log is read once its panes are planned too.
        report.progress.finished = false;
        self.read_report = Some(report);
        self.plan_step(max_scans.saturating_sub(read), read)
    }

    /// The model and no-return reach the map's extent depends on.
    fn extent_key(&self) -> (HandCrafted, f64) {
        (
            *self.settings.model(),
            self.settings.settings().no_return_reach,
        )
    }

    /// Grows the read's extent by the scans read since the last call.
    fn grow_read_extent(&mut self) {
        let (Some(loader), Some((_, _, extent))) = (&self.loader, &mut self.read_extent) else {
            return;
        };
        let scans = loader.scans();
        for k in extent.scans()..scans.len() {
            match scans.scan(k) {
                Some(scan) => extent.add(&scan, &scan_model(&self.settings, scans, k)),
                None => extent.skip(),
            }
        }
    }

    /// Walks up to `max_scans` scans of the panes' planning, in a call that
    /// has read `read` scans already; once the plan is walked, the panes are
    /// set up and the read is finished.
    fn plan_step(&mut self, max_scans: usize, read: usize) -> Result<ReadReport> {
        // A call of its own walks at least one scan; one that has read
        // scans walks what is left of its budget.
        let budget = if read > 0 {
            max_scans
        } else {
            max_scans.max(1)
        };
        let (walked, planned) = self.walk_plan(budget);
        let mut report = self.read_report.clone().ok_or_else(|| self.no_map())?;
        report.work = read + walked;
        report.progress.finished = planned.is_some();
        self.read_report = Some(report.clone());
        match planned {
            Some((scans, Err(e), _)) => {
                self.panes.clear();
                self.pending = Some((scans, e.clone()));
                Err(e)
            }
            Some((_, Ok(panes), _)) => {
                self.after_read = true;
                self.adopt(panes, None)?;
                Ok(report)
            }
            None => Ok(report),
        }
    }

    /// Walks up to `max_scans` scans of the planning under way; once it
    /// is walked, takes it and gives its scans, its panes (or why the
    /// settings make none) and what it was for.
    fn walk_plan(&mut self, max_scans: usize) -> (usize, Option<Planned>) {
        let Some((planning, _)) = self.planning.as_mut() else {
            return (0, None);
        };
        let walked = planning.step(max_scans);
        if !planning.finished() {
            return (walked, None);
        }
        let Some((planning, purpose)) = self.planning.take() else {
            return (walked, None);
        };
        let scans = Arc::clone(planning.scans());
        (walked, Some((scans, planning.into_panes(), purpose)))
    }

    /// Walks up to `max_scans` scans (at least one) of the planning of the
    /// panes after new settings ([`super::Stage::Planning`]); once it is walked,
    /// the new panes replace the ones on screen and head for their target.
    /// An error when the new settings make no map of this log (a grid too
    /// large, beams past the tile budget): the panes on screen and their
    /// settings then stay in force (for scans that awaited settings, they
    /// wait on, with this error).
    pub fn plan(&mut self, max_scans: usize) -> Result<PlanReport> {
        if !matches!(
            self.planning,
            Some((_, PlanFor::Settings { .. } | PlanFor::Pending))
        ) {
            return Err(OccError::State(
                "no panes to plan: new settings start a planning".into(),
            ));
        }
        let (work, planned) = self.walk_plan(max_scans.max(1));
        let finished = planned.is_some();
        match planned {
            None => {}
            Some((_, Ok(panes), PlanFor::Settings { target, .. })) => {
                self.adopt(panes, Some(target))?;
                self.after_read = false;
            }
            Some((_, Ok(panes), _)) => self.adopt(panes, None)?,
            Some((_, Err(e), PlanFor::Settings { previous, .. })) => {
                self.settings = previous;
                return Err(e);
            }
            Some((scans, Err(e), _)) => {
                self.pending = Some((scans, e.clone()));
                return Err(e);
            }
        }
        Ok(PlanReport { work, finished })
    }

    /// Puts newly planned `panes` in place of the ones on screen, heading
    /// for `target` scans (all when `None`): a pane of the same source and
    /// model over the same scans keeps its view where its map's limits
    /// stay; any other starts at the output size of the panes before.
    fn adopt(&mut self, mut panes: Vec<LogPane>, target: Option<usize>) -> Result<()> {
        for pane in &mut panes {
            let same = self.panes.iter().find(|p| {
                p.source() == pane.source()
                    && p.model() == pane.model()
                    && Arc::ptr_eq(p.shared_scans(), pane.shared_scans())
            });
            match same.or(self.panes.first()) {
                Some(old) if same.is_some() => pane.keep_view(old)?,
                Some(old) => {
                    let v = old.view();
                    pane.set_view_size(v.width, v.height)?;
                }
                None => {}
            }
            if let Some(k) = target {
                pane.seek(k)?;
            }
        }
        self.panes = panes;
        self.pending = None;
        Ok(())
    }

    /// Frees the file and the scans read, and keeps `e` for later calls.
    fn read_failed(&mut self, e: OccError) -> OccError {
        self.topic_choices = self.loader.take().and_then(|l| l.topic_choices());
        self.read_extent = None;
        self.planning = None;
        self.read_failure = Some(e.clone());
        e
    }

    /// New settings: every pane restarts towards the same scan count (a
    /// pane is added or dropped when the pose source changes), once its
    /// plan is walked: up to [`CONFIGURE_SCANS`] scans here, the rest over
    /// [`Self::plan`] calls ([`super::Stage::Planning`]; the maps on screen stay
    /// until then). Returns the first pane's geometry (`None` while there
    /// is no map yet). Checked once; on error nothing changes.
    pub fn configure(&mut self, settings: LogMapSettings) -> Result<Option<GeometryReport>> {
        let checked = settings.validate()?;
        let (previous, pending_error) = (self.settings, self.pending.clone());
        // What the new settings re-plan: the planning under way (started
        // again), the panes on screen, or scans that awaited settings. (The
        // panes of a log read before the one being read are replaced by
        // that log's.)
        let replan = match (&self.planning, self.panes.first(), &self.pending) {
            (Some((p, purpose)), _, _) => Some((Arc::clone(p.scans()), *purpose)),
            _ if self.loader.is_some() => None,
            (None, Some(first), _) => Some((
                Arc::clone(first.shared_scans()),
                PlanFor::Settings {
                    previous,
                    target: first.progress().scans_target,
                },
            )),
            (None, None, Some((scans, _))) => Some((Arc::clone(scans), PlanFor::Pending)),
            (None, None, None) => None,
        };
        self.settings = checked;
        // The read's extent follows the settings: an extent grown under
        // others is dropped (the planning walks it again, in bounded calls).
        let key = self.extent_key();
        if matches!(&self.read_extent, Some((m, r, _)) if (*m, *r) != key) {
            self.read_extent = None;
        }
        let Some((scans, purpose)) = replan else {
            return Ok(self.geometry(0).ok());
        };
        let planning = PanePlanning::new(
            scans,
            &self.settings,
            OdometryParams::WHEELS,
            (self.budget_cells, self.pose_work),
            None,
        );
        let planning_before = self.planning.replace((planning, purpose));
        if purpose != PlanFor::Read {
            if let Err(e) = self.plan(CONFIGURE_SCANS) {
                // Found within this call: nothing changes (a planning
                // under way goes on).
                (self.settings, self.pending) = (previous, pending_error);
                self.planning = planning_before;
                return Err(e);
            }
            // A read refused since then is the news no longer: the map is.
            self.read_failure = None;
        }
        Ok(self.geometry(0).ok())
    }

    /// Advances every pane towards its target within one budget of
    /// `max_cells` units of work for the whole call (cell updates, visits
    /// and scan matching: [`super::BuildProgress::work`]), the pane furthest
    /// behind first, one scan at a time; the call stops after the scan that
    /// reaches the budget. At least one scan is integrated while any is
    /// left, whatever the budget. An error once a pane's beams reach past
    /// its tile budget (saying how much the log would need); the maps so
    /// far stay. The tiles the call wrote are recounted at its end
    /// ([`LogPane::counts`]).
    pub fn build_slice(&mut self, max_cells: u64) -> Result<SessionState> {
        self.build_slice_until(max_cells, || false)
    }

    /// [`Self::build_slice`], stopping early too after the first step for
    /// which `due()` is true (asked after each step): the page's clock, so
    /// that a call ends within one step of its time whatever a unit of
    /// each kind of work costs on the reader's machine (the units are
    /// weighed natively; in wasm a unit of SLAM's matching costs two to
    /// three times a cell update's, docs/BENCHMARKS.md, W8). Where the
    /// build stops does not change what it builds: the maps are the same
    /// however the work is sliced.
    pub fn build_slice_until(
        &mut self,
        max_cells: u64,
        mut due: impl FnMut() -> bool,
    ) -> Result<SessionState> {
        if self.panes.is_empty() {
            return Err(self.no_map());
        }
        if let Some(e) = self.pane_failure() {
            return Err(e.clone());
        }
        let mut spent = 0u64;
        loop {
            let behind = self
                .panes
                .iter_mut()
                .filter(|p| !p.progress().finished)
                .min_by_key(|p| p.progress().scans_done);
            let Some(pane) = behind else { break };
            let before = pane.progress().work;
            pane.integrate_next();
            spent += pane.progress().work - before;
            if let Some(e) = pane.failure() {
                let e = e.clone();
                self.panes.iter_mut().for_each(|p| _ = p.refresh_counts());
                return Err(e);
            }
            if spent >= max_cells || due() {
                break;
            }
        }
        // The tiles the call wrote are recounted once, at its end (on the
        // campus at 5 cm, half a recounted cell per cell update: a cell
        // recounted takes a seventh of an update's time).
        self.panes.iter_mut().for_each(|p| _ = p.refresh_counts());
        Ok(self.state())
    }

    /// Integrates up to `max_scans` more scans into every pane (a test's
    /// and a script's whole build: [`Self::build_slice`] is the page's).
    pub fn build_chunk(&mut self, max_scans: usize) -> Result<SessionState> {
        if self.panes.is_empty() {
            return Err(self.no_map());
        }
        for pane in &mut self.panes {
            pane.advance(max_scans);
            if let Some(e) = pane.failure() {
                return Err(e.clone());
            }
        }
        Ok(self.state())
    }

    /// Scrubs every pane to `scans` integrated scans; the build then does
    /// the work (going back restarts from the first scan).
    pub fn seek(&mut self, scans: usize) -> Result<()> {
        let Some(first) = self.panes.first() else {
            return Err(self.no_map());
        };
        if scans > first.scans().len() {
            return Err(invalid(
                "scan",
                scans,
                "at most the number of scans in the log",
            ));
        }
        for pane in &mut self.panes {
            pane.seek(scans)?;
        }
        // Panes being planned head there too.
        if let Some((_, PlanFor::Settings { target, .. })) = &mut self.planning {
            *target = scans;
        }
        self.after_read = false;
        self.read_failure = None;
        Ok(())
    }

    fn no_map(&self) -> OccError {
        OccError::State("the log has not been read yet".into())
    }

    pub(super) fn pane_failure(&self) -> Option<&OccError> {
        self.panes.iter().find_map(|p| p.failure())
    }

    /// How the last read ended (also when setting up the map failed), or
    /// `None` before a read has finished.
    pub fn read_summary(&self) -> Option<ReadReport> {
        self.read_report
            .clone()
            .filter(|r| r.progress.finished && self.loader.is_none())
    }

    /// True when the whole log has been read but the settings made too large
    /// a grid for it.
    pub fn awaiting_settings(&self) -> bool {
        self.pending.is_some()
    }

    /// The panes, the one the reader operates first.
    pub fn panes(&self) -> &[LogPane] {
        &self.panes
    }

    /// Pane `k`, or an error naming it.
    pub fn pane(&self, k: usize) -> Result<&LogPane> {
        let n = self.panes.len();
        match self.panes.get(k) {
            Some(p) => Ok(p),
            None if n == 0 => Err(self.no_map()),
            None => Err(invalid(
                "pane",
                format!("{k} (of {n} panes)"),
                "a pane of the session, counted from 0",
            )),
        }
    }

    /// Pane `k` to operate (its view and cursor), or an error naming it.
    pub fn pane_mut(&mut self, k: usize) -> Result<&mut LogPane> {
        self.pane(k)?;
        Ok(&mut self.panes[k])
    }

    /// Pane `k`'s limits.
    pub fn geometry(&self, k: usize) -> Result<GeometryReport> {
        Ok(self.pane(k)?.geometry())
    }
}
