//! The real-log session behind Map Weaver's real-log mode: a log (of any
//! format the readers of [`crate::io`] take) read a few records at a time, then mapped a few scans at a time with the
//! ray traversal (Table 9.1) and the hand-crafted model (Table 9.2), so
//! that a page shows progress, stays responsive, and can scrub through the
//! build.
//!
//! - `settings`: what a reader chooses ([`LogMapSettings`]), checked once
//!   into [`CheckedSettings`] with its one model; the limits the controls
//!   keep to ([`SettingLimits`]).
//! - `pane`: one pose source's map ([`LogPane`]): shared scans, its pose
//!   source ([`crate::poses`]), a map and the one scan insertion, built
//!   towards a target scan count.
//! - `map`: the map of whichever cell model, behind one interface
//!   ([`LogGrid`] for its grid).
//! - `view`: what a pane shows: its view, cursor, readouts, scale legend,
//!   counts (kept per tile as the build writes them) and export.
//! - `budget`: what a map will allocate, known before a cell is.
//! - `planning`: the panes planned in calls of bounded work, after a read
//!   and after new settings.
//! - `matched`: what the page draws of a scan-matched pane's last match
//!   ([`MatchView`]), and every pane's poses as a `poses.tsv` text.
//! - `session`: [`RealLogSession`], the read, the panes (the corrected map,
//!   and the dead-reckoned one beside it when asked for: a further pose
//!   source is one more pane); beside the state's types here, the one
//!   state a panel renders ([`SessionState`]).

mod budget;
mod map;
mod matched;
mod pane;
mod planning;
mod provenance;
mod session;
mod settings;
mod slam_view;
mod surface;
mod view;

pub use budget::{MAX_POSE_WORK, VISITS_PER_UNIT};
pub use map::LogGrid;
pub use matched::MatchView;
pub use pane::{BuildProgress, LogPane, DEFAULT_VIEW_SIZE};
pub use planning::START_UNITS_PER_PASS;
pub use session::{PlanReport, ReadReport, RealLogSession, CONFIGURE_SCANS, READ_SHARE};
pub use settings::{
    CheckedSettings, LogCellModel, LogMapSettings, SettingLimits, HIT_RATIO, MAX_SEED,
    NO_RETURN_REACH,
};
pub use slam_view::{PoseErrorView, ERROR_SCANS_PER_CALL, GRAPH_LOCAL_SEGMENTS, GRAPH_NODES_DRAWN};
pub use view::{GeometryReport, ViewLegend, CURSOR_LONG_STEPS, CURSOR_STEP_PX};

use crate::poses::PoseSourceKind;

// The session's state, as a panel renders it (`RealLogSession::state`).

/// Where a session stands: the one state a panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Stage {
    /// No log yet.
    #[serde(rename = "idle")]
    Idle,
    /// A log is being read (the panes of the previous log, if any, stay).
    #[serde(rename = "reading")]
    Reading,
    /// The log is read, but the settings make too large a grid for it: the
    /// scans wait for settings that fit.
    #[serde(rename = "awaiting-settings")]
    AwaitingSettings,
    /// New settings: the panes are being planned at them, in bounded
    /// calls (the maps of the settings before stay on screen until then).
    #[serde(rename = "planning")]
    Planning,
    /// The panes are heading for their target scan count.
    #[serde(rename = "building")]
    Building,
    /// Every pane holds its target scan count.
    #[serde(rename = "done")]
    Done,
    /// The read was refused (a malformed or oversized log), or a pane's map
    /// passed its tile budget; `error` says why.
    #[serde(rename = "failed")]
    Failed,
}

/// What a failed session failed at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FailedStep {
    Read,
    Build,
}

/// One pane as the state reports it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PaneState {
    pub poses: PoseSourceKind,
    pub model: LogCellModel,
    pub caption: String,
    #[serde(flatten)]
    pub progress: BuildProgress,
}

/// Everything a panel shows about the session's progress, in one object.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SessionState {
    pub state: Stage,
    /// The name of the log last opened (being read, or read): what the
    /// state is about.
    pub log: Option<String>,
    /// Why the session failed, or why it awaits settings.
    pub error: Option<String>,
    /// What failed: `"read"` (the log was refused; the maps of a log read
    /// before, if any, stay) or `"build"` (a map passed its tile budget;
    /// the map so far stays).
    pub failed: Option<FailedStep>,
    /// The whole load's progress, 0 to 1: the read's share
    /// ([`READ_SHARE`]) then the panes' mean, or the panes' mean alone for
    /// a rebuild (new settings, a scrub).
    pub progress: f64,
    /// The read under way, or the last finished read's report.
    pub read: Option<ReadReport>,
    /// The whole build: the scans every pane holds, the target, the
    /// log's scans, and the panes' cell updates and beams together.
    pub scans_done: usize,
    pub scans_target: usize,
    pub scans_total: usize,
    pub cell_updates: u64,
    /// The panes' work together in cell updates (their updates, and the
    /// scan matching's cost in the same units): what `build_slice`'s
    /// budget counts.
    pub work: u64,
    pub beams: u64,
    pub finished: bool,
    /// The panes, the one the reader operates first.
    pub panes: Vec<PaneState>,
    /// The topics a refused read wanted a choice between (a bag with
    /// several LaserScan or Odometry topics and none named), for the page
    /// to offer; `None` otherwise.
    pub topics: Option<crate::io::TopicChoices>,
    /// The settings in force and the limits their controls keep to.
    pub settings: LogMapSettings,
    pub limits: SettingLimits,
}

// The state is built beside the types it fills.
use session::PlanFor;

impl RealLogSession {
    /// Where the session stands.
    pub fn stage(&self) -> Stage {
        if self.loader.is_some() || matches!(self.planning, Some((_, PlanFor::Read))) {
            Stage::Reading
        } else if self.planning.is_some() {
            Stage::Planning
        } else if self.read_failure.is_some() || self.pane_failure().is_some() {
            Stage::Failed
        } else if self.pending.is_some() {
            Stage::AwaitingSettings
        } else if self.panes.is_empty() {
            Stage::Idle
        } else if self.panes.iter().all(|p| p.progress().finished) {
            Stage::Done
        } else {
            Stage::Building
        }
    }

    /// The one state a panel renders.
    pub fn state(&self) -> SessionState {
        let stage = self.stage();
        let error = match stage {
            Stage::Failed => self
                .read_failure
                .as_ref()
                .or_else(|| self.pane_failure())
                .map(|e| e.to_string()),
            Stage::AwaitingSettings => self.pending.as_ref().map(|(_, e)| e.to_string()),
            _ => None,
        };
        let failed = match stage {
            Stage::Failed if self.read_failure.is_some() => Some(FailedStep::Read),
            Stage::Failed => Some(FailedStep::Build),
            _ => None,
        };
        let panes: Vec<PaneState> = self
            .panes
            .iter()
            .map(|p| PaneState {
                poses: p.source(),
                model: p.model(),
                caption: p.caption(),
                progress: p.progress(),
            })
            .collect();
        let fraction = |p: &BuildProgress| {
            if p.scans_target == 0 {
                1.0
            } else {
                p.scans_done as f64 / p.scans_target as f64
            }
        };
        let built = if panes.is_empty() {
            0.0
        } else {
            panes.iter().map(|p| fraction(&p.progress)).sum::<f64>() / panes.len() as f64
        };
        let read_fraction = self.read_report.as_ref().map_or(0.0, |r| {
            if r.progress.finished {
                1.0
            } else {
                r.progress.bytes_read as f64 / r.bytes_total.max(1) as f64
            }
        });
        let progress = match stage {
            Stage::Reading | Stage::AwaitingSettings => READ_SHARE * read_fraction.min(1.0),
            Stage::Planning => 0.0,
            _ if self.after_read => READ_SHARE + (1.0 - READ_SHARE) * built,
            _ => built,
        };
        let first = panes.first().map(|p| p.progress);
        let settings = *self.settings.settings();
        SessionState {
            state: stage,
            log: self.log.clone(),
            error,
            failed,
            progress,
            read: self.read_report.clone(),
            scans_done: panes
                .iter()
                .map(|p| p.progress.scans_done)
                .min()
                .unwrap_or(0),
            scans_target: first.map_or(0, |p| p.scans_target),
            scans_total: first.map_or(0, |p| p.scans_total),
            cell_updates: panes.iter().map(|p| p.progress.cell_updates).sum(),
            work: panes.iter().map(|p| p.progress.work).sum(),
            beams: panes.iter().map(|p| p.progress.beams).sum(),
            finished: !panes.is_empty() && panes.iter().all(|p| p.progress.finished),
            panes,
            topics: self.topic_choices.clone(),
            settings,
            limits: SettingLimits::at(settings.resolution)
                .expect("checked settings have a positive resolution"),
        }
    }
}
