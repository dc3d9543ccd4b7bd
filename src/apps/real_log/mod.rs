//! The real-log session behind Map Weaver's real-log mode: a CARMEN log
//! read a few lines at a time, then mapped a few scans at a time with the
//! ray traversal (Table 9.1) and the hand-crafted model (Table 9.2), so
//! that a page shows progress, stays responsive, and can scrub through the
//! build.
//!
//! - `settings`: what a reader chooses ([`LogMapSettings`]), checked once
//!   into [`CheckedSettings`] with its one model; the pose sources
//!   ([`LogPoses`]); the limits the controls keep to ([`SettingLimits`]).
//! - `pane`: one pose source's map ([`LogPane`]): shared scans, its poses,
//!   a tiled grid and the mapper, built towards a target scan count.
//! - `view`: what a pane shows: its view, cursor, readouts, scale legend
//!   and export.
//! - `matched`: the scan-matched pose source inside a pane
//!   ([`MatchView`] what the page draws of its last match), and every
//!   pane's poses as a `poses.tsv` text.
//! - `session`: [`RealLogSession`], the read, the panes (the corrected map,
//!   and the dead-reckoned one beside it when asked for: a further pose
//!   source is one more pane) and the one state a panel renders
//!   ([`SessionState`]).

mod budget;
mod map;
mod matched;
mod pane;
mod session;
mod settings;
mod view;

pub use map::LogGrid;
pub use matched::{match_settings, match_work, MatchView, MATCH_DRIFT_MARGIN};
pub use pane::{BuildProgress, LogPane, DEFAULT_VIEW_SIZE};
pub use session::{
    FailedStep, PaneState, ReadReport, RealLogSession, SessionState, Stage, READ_SHARE,
};
pub use settings::{
    CheckedSettings, LogCellModel, LogMapSettings, LogPoses, SettingLimits, HIT_RATIO, MAX_SEED,
    NO_RETURN_REACH,
};
pub use view::{GeometryReport, ImageCell, ViewLegend, CURSOR_LONG_STEPS, CURSOR_STEP_PX};
