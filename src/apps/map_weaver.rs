//! Map Weaver's state: one simulated lap feeding two maps side by side.
//!
//! This is the core behind `<occgrid-map-weaver>` (SPEC §10.1), kept out of
//! the bindings so that it is tested natively. Data flow per scan:
//!
//! 1. [`ApartmentSim`] produces the next [`SimScan`] (true pose,
//!    dead-reckoned pose, LiDAR ranges).
//! 2. Each of the two panes turns it into a [`Scan`] at the pose its
//!    settings ask for (the oracle's or dead reckoning's) and integrates it
//!    with its own inverse model, evidence strength and clamp
//!    ([`RayMapper`], Table 9.1 by ray traversal).
//! 3. Each pane's [`MapView`] brings its pixels, its entropy and its Brier
//!    score up to date by looking only at the cells whose log odds changed,
//!    so a frame costs what the scan touched, not the map.
//!
//! Every scan is kept, so that switching a pane's model or pose source
//! rebuilds that pane over the same scans (the two panes stay comparable).
//! The clamp and strength sliders act on the run as it goes, as a reader
//! turning them mid-lap would expect: a lower clamp pulls saturated cells in
//! at once, a new strength weighs the scans still to come.

use crate::error::{self, invalid, Result};
use crate::geometry::GridGeometry;
use crate::geometry::Pose;
use crate::grid::readout::{readout_at_pixel, CellReadout};
use crate::grid::{FilterSettings, LogOddsGrid};
use crate::inverse::training::{self, TrainingConfig};
use crate::inverse::{HandCrafted, HandCraftedParams, InverseModel, LearnedInverse};
use crate::mapping::sweep::sweep_scan;
use crate::mapping::traversal::{RayMapper, ScanStats};
use crate::render::map_view::MapView;
use crate::render::overlay::{ImageCell, ImagePoint, RobotMark};
use crate::scenes::apartment::{ApartmentScene, ApartmentSim, SimScan};
use crate::sensors::Scan;

/// At most this many laps per run: every scan is kept for rebuilding a
/// pane, and a run must not grow without bound in a forgotten tab.
pub const MAX_LAPS: usize = 20;
/// The most range readings a run may keep (laps x scans x beams): every
/// scan is kept for rebuilding a pane, 8 bytes a reading.
pub const MAX_READINGS: usize = 10_000_000;
/// The most work one request for scans before the first frame may ask for
/// (a link's `scans`): cell visits, counted as scans x 2 panes x beams x the
/// cells along a beam at the LiDAR's range ([`Weaver::work_per_scan`]).
/// 250 million is a few seconds of mapping at the chapter's 0.1 m, where all
/// 20 laps fit, and a few thousand scans at 0.0125 m; the widget does the
/// work in time slices, this bounds how long the reader waits for it.
pub const MAX_FAST_FORWARD_WORK: u64 = 250_000_000;
/// The strongest evidence the strength slider may ask for.
pub const MAX_STRENGTH: f64 = 10.0;
/// The most SGD updates (triplets x epochs) a run's training may ask for:
/// about 26 times the default 24,000 x 8, a couple of seconds of fitting as
/// wasm. The training's own bounds (a million triplets, 200 epochs) are
/// each fine alone, but together they would hold the widget for a minute.
pub const MAX_TRAINING_UPDATES: u64 = crate::inverse::training::MAX_UPDATES;
/// How many recent frame times the "ms per frame" readout is the median of.
const FRAME_WINDOW: usize = 31;

/// Length of the robot's heading tick over the map, metres.
const HEADING_TICK: f64 = 0.3;

/// Which inverse sensor model a pane maps with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// Table 9.2.
    HandCrafted,
    /// The model learned from simulated data (§9.3).
    Learned,
}

/// Where a pane takes the robot's pose from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PoseSource {
    /// The true pose: what mapping with known poses assumes.
    Oracle,
    /// The start pose plus the noisy odometry increments.
    DeadReckoning,
}

/// How a pane applies Table 9.1 to a scan (SPEC §3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MapperKind {
    /// Each beam's raster only ([`RayMapper`]): the production path.
    Traversal,
    /// Every cell of the map against its nearest beam
    /// ([`crate::mapping::sweep::sweep_scan`]), as Table 9.1 is printed.
    Sweep,
}

/// The sensor a pane reads each range as: the opening angle `beta` of
/// Table 9.2. The readings are the simulated LiDAR's either way; a cone
/// pane interprets each one as a sonar would (evidence over the whole
/// cone), which is what makes the two mappers part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SensorKind {
    /// Thin beams: Table 9.2's `beta` as the hand-crafted parameters set
    /// it (one degree).
    Lidar,
    /// A cone of opening [`PaneSettings::beta_deg`].
    Cone,
}

/// The resolutions a pane may map at, metres per cell (exercise 6).
pub const PANE_RESOLUTIONS: [f64; 2] = [0.10, 0.05];
/// The cone's opening angle range, degrees.
pub const CONE_BETA_DEG: (f64, f64) = (1.0, 30.0);
/// How many recent scans a pane's "core time per scan" is the mean of.
const SCAN_TIME_WINDOW: usize = 31;

/// One pane's knobs.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, rename_all = "camelCase")]
pub struct PaneSettings {
    pub model: ModelKind,
    pub pose: PoseSource,
    /// Saturation `|l| <= clamp`, log odds.
    pub clamp: f64,
    /// Factor on the model's evidence (1 = as designed or learned).
    pub strength: f64,
    pub mapper: MapperKind,
    pub sensor: SensorKind,
    /// The cone's opening angle `beta`, degrees (1 to 30); used by the
    /// hand-crafted model when `sensor` is the cone (the learned model
    /// has the width it learned).
    pub beta_deg: f64,
    /// Beams of each scan the pane uses, evenly spaced: a divisor of the
    /// LiDAR's beam count. `None`: every beam.
    pub beams: Option<usize>,
    /// Metres per cell: 0.10 or 0.05. `None`: the scene's own.
    pub resolution: Option<f64>,
    /// The mistake of exercise 8: the learned model's scores are added
    /// without removing its `l0` (the hand-crafted model's `l0` is 0, so
    /// there it changes nothing).
    pub forget_l0: bool,
}

impl Default for PaneSettings {
    fn default() -> Self {
        Self {
            model: ModelKind::HandCrafted,
            pose: PoseSource::Oracle,
            clamp: FilterSettings::default().clamp,
            strength: 1.0,
            mapper: MapperKind::Traversal,
            sensor: SensorKind::Lidar,
            beta_deg: 22.0,
            beams: None,
            resolution: None,
            forget_l0: false,
        }
    }
}

impl PaneSettings {
    /// True when going from `self` to `other` changes how scans are turned
    /// into evidence, so the pane must be built again over the scans so
    /// far (clamp and strength act on the run as it goes).
    fn needs_rebuild(&self, other: &Self) -> bool {
        let live = |p: &Self| Self {
            clamp: 0.0,
            strength: 0.0,
            ..*p
        };
        live(self) != live(other)
    }
}

/// Everything a Map Weaver run is built from. Defaults: the chapter's
/// apartment, seed 1, the person walking, both panes on the oracle with
/// the hand-crafted model on the left and the learned one on the right.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, rename_all = "camelCase")]
pub struct WeaverSettings {
    pub seed: u64,
    pub person: bool,
    pub panes: [PaneSettings; 2],
    /// Table 9.2 at strength 1. The default is a thin LiDAR beam whose
    /// obstacle band `alpha` is one cell (0.10 m): a wider band paints the
    /// free cell in front of every wall occupied too.
    pub hand_crafted: HandCraftedParams,
    /// How the learned model is trained (once per run, when a pane first
    /// needs it; the default matches this LiDAR).
    pub training: TrainingConfig,
    /// The run stops after this many laps.
    pub laps: usize,
    pub scene: ApartmentScene,
}

impl Default for WeaverSettings {
    fn default() -> Self {
        Self {
            seed: 1,
            person: true,
            panes: [
                PaneSettings::default(),
                PaneSettings {
                    model: default_right_model(),
                    ..PaneSettings::default()
                },
            ],
            hand_crafted: HandCraftedParams::laser(8.0),
            training: TrainingConfig::default(),
            laps: 3,
            scene: ApartmentScene::default(),
        }
    }
}

impl WeaverSettings {
    /// Checks every knob, naming the first one that is wrong.
    pub fn validate(&self) -> Result<()> {
        if self.laps == 0 || self.laps > MAX_LAPS {
            return Err(invalid("laps", self.laps, "1 to 20 laps"));
        }
        self.hand_crafted.validate()?;
        for (k, p) in self.panes.iter().enumerate() {
            validate_pane(k, p, self.scene.lidar.beams)?;
        }
        // Checked before the training's own rules so that the message
        // names the fields as this settings object spells them.
        let updates = self.training.triplets as u64 * self.training.epochs as u64;
        if updates > MAX_TRAINING_UPDATES {
            return Err(invalid(
                "training.triplets x training.epochs",
                format!(
                    "{} x {} = {updates}",
                    self.training.triplets, self.training.epochs
                ),
                "at most 5000000 updates: fewer triplets or epochs",
            ));
        }
        self.training.validate()?;
        self.scene.validate()?;
        let readings = self
            .laps
            .saturating_mul(self.scene.scans_per_lap())
            .saturating_mul(self.scene.lidar.beams);
        if readings > MAX_READINGS {
            return Err(invalid(
                "laps",
                self.laps,
                "few enough laps that laps x scans per lap x beams stays within 10000000 readings",
            ));
        }
        Ok(())
    }
}

/// The right pane's model by default: the learned one, so the two models
/// meet the same scans side by side.
fn default_right_model() -> ModelKind {
    ModelKind::Learned
}

fn validate_pane(k: usize, p: &PaneSettings, lidar_beams: usize) -> Result<()> {
    // The pane's grid (prior 0.5) must accept the clamp; say so under the
    // pane's own name.
    FilterSettings {
        prior: 0.5,
        clamp: p.clamp,
    }
    .validate()
    .map_err(|e| pane_clamp_error(k, e))?;
    check_strength(k, p.strength)?;
    if !(p.beta_deg >= CONE_BETA_DEG.0 && p.beta_deg <= CONE_BETA_DEG.1) {
        return Err(invalid(
            &format!("panes[{k}].betaDeg"),
            error::show(p.beta_deg),
            "an opening angle of 1 to 30 degrees",
        ));
    }
    if let Some(r) = p.resolution.filter(|r| !PANE_RESOLUTIONS.contains(r)) {
        return Err(invalid(
            &format!("panes[{k}].resolution"),
            error::show(r),
            "0.1 or 0.05 metres per cell",
        ));
    }
    if let Some(b) = p.beams {
        if b == 0 || b > lidar_beams || lidar_beams % b != 0 {
            return Err(invalid(
                &format!("panes[{k}].beams"),
                b,
                "a divisor of the LiDAR's beam count (60: 1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30 or 60)",
            ));
        }
    }
    Ok(())
}

/// A grid's clamp error, renamed to pane `k`'s field.
fn pane_clamp_error(k: usize, e: crate::OccError) -> crate::OccError {
    match e {
        crate::OccError::InvalidParameter {
            value, expected, ..
        } => crate::OccError::InvalidParameter {
            field: format!("panes[{k}].clamp"),
            value,
            expected,
        },
        other => other,
    }
}

fn check_strength(k: usize, s: f64) -> Result<()> {
    error::non_negative(&format!("panes[{k}].strength"), s)?;
    if s > MAX_STRENGTH {
        return Err(invalid(
            &format!("panes[{k}].strength"),
            s,
            "a factor of at most 10",
        ));
    }
    Ok(())
}

/// An inverse model whose evidence is scaled by a constant: the evidence
/// strength slider for a model that has no `l_occ` / `l_free` to scale.
#[derive(Debug, Clone)]
pub struct Scaled<M> {
    pub model: M,
    pub factor: f32,
}

impl<M: InverseModel> InverseModel for Scaled<M> {
    #[inline]
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32 {
        self.factor * self.model.evidence(r, phi, z)
    }
    #[inline]
    fn reach(&self, z: f64) -> f64 {
        self.model.reach(z)
    }
    fn half_width(&self) -> f64 {
        self.model.half_width()
    }
    fn z_max(&self) -> f64 {
        self.model.z_max()
    }
    fn l0(&self) -> f32 {
        self.model.l0()
    }
}

/// A pane's inverse model, with the strength applied. An enum rather than
/// a trait object so that the traversal's inner loop is monomorphic.
#[derive(Debug, Clone)]
enum PaneModel {
    HandCrafted(HandCrafted),
    Learned(Scaled<LearnedInverse>),
}

impl PaneModel {
    /// The model pane settings `p` ask for: the kind, its strength, the
    /// cone's opening for Table 9.2, and `l0` forgotten or not.
    fn build(p: &PaneSettings, base: &HandCraftedParams, learned: &LearnedInverse) -> Result<Self> {
        Ok(match p.model {
            ModelKind::HandCrafted => {
                let mut params = *base;
                if p.sensor == SensorKind::Cone {
                    params.beta = p.beta_deg.to_radians();
                }
                if p.forget_l0 {
                    // Evidence l - 0 instead of l - l0.
                    let l0 = params.l0;
                    params.l_occ -= l0;
                    params.l_free -= l0;
                }
                Self::HandCrafted(HandCrafted::with_strength(params, p.strength)?)
            }
            ModelKind::Learned => Self::Learned(Scaled {
                model: if p.forget_l0 {
                    learned.with_l0(0.0)
                } else {
                    learned.clone()
                },
                factor: p.strength as f32,
            }),
        })
    }

    fn integrate(
        &self,
        kind: MapperKind,
        mapper: &mut RayMapper,
        grid: &mut LogOddsGrid,
        scan: &Scan,
    ) -> ScanStats {
        match (self, kind) {
            (Self::HandCrafted(m), MapperKind::Traversal) => mapper.integrate(grid, m, scan),
            (Self::Learned(m), MapperKind::Traversal) => mapper.integrate(grid, m, scan),
            (Self::HandCrafted(m), MapperKind::Sweep) => sweep_scan(grid, m, scan),
            (Self::Learned(m), MapperKind::Sweep) => sweep_scan(grid, m, scan),
        }
    }

    /// The prior the model removes from its scores (0 when `l0` is
    /// forgotten).
    fn l0(&self) -> f32 {
        match self {
            Self::HandCrafted(m) => m.l0(),
            Self::Learned(m) => m.l0(),
        }
    }
}

/// The ghost of exercise 5, per pane: cells the person stood on that were
/// above p = 0.5 when they left, and how many scans each took to fall
/// back below p = 0.5.
#[derive(Debug, Clone, Default)]
struct GhostTracker {
    /// The cells under the person after the last scan, and whether each
    /// was above p = 0.5 then.
    under: Vec<(usize, bool)>,
    /// Ghost cells not yet faded: (cell, the last scan that saw the
    /// person on it, counted from 1).
    pending: Vec<(usize, usize)>,
    /// Scans each completed fade took, in the order they completed.
    fades: Vec<usize>,
}

impl GhostTracker {
    /// After scan `scan` (counted from 1) was integrated, with the person
    /// over `now` (sorted cell indices) and the map's log odds `l`.
    fn observe(&mut self, scan: usize, now: &[usize], l: &[f32]) {
        let under_now = |c: usize| now.binary_search(&c).is_ok();
        for &(c, ghost) in &self.under {
            if ghost && !under_now(c) {
                self.pending.push((c, scan - 1));
            }
        }
        let fades = &mut self.fades;
        self.pending.retain(|&(c, left)| {
            if under_now(c) {
                // Back under the person: the ghost is refreshed, not faded.
                return false;
            }
            if l[c] < 0.0 {
                fades.push(scan - left);
                return false;
            }
            true
        });
        self.under = now.iter().map(|&c| (c, l[c] > 0.0)).collect();
    }

    fn clear(&mut self) {
        *self = Self::default();
    }
}

/// Exercise 5's readout: how long the person's ghost took to fade.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GhostReadout {
    /// Ghost cells that have faded so far.
    pub faded: usize,
    /// Ghost cells still at p >= 0.5 since the person left them.
    pub lingering: usize,
    /// Scans and seconds the most recent fade took.
    pub last_scans: Option<usize>,
    pub last_seconds: Option<f64>,
    /// The slowest fade so far.
    pub longest_scans: Option<usize>,
    pub longest_seconds: Option<f64>,
}

/// One map and everything the widget shows about it.
#[derive(Debug, Clone)]
struct Pane {
    settings: PaneSettings,
    model: PaneModel,
    /// The pane's own grid limits (its resolution may differ from the
    /// other pane's), the ground truth at them and the tracked cells.
    geometry: GridGeometry,
    truth: Vec<bool>,
    tracked_cells: [usize; 3],
    grid: LogOddsGrid,
    mapper: RayMapper,
    view: MapView,
    /// Entropy (bits) after each scan; entry 0 is the empty map.
    entropy_curve: Vec<f64>,
    /// Brier score over the surveyed region after each scan; entry 0 is
    /// the empty map.
    brier_curve: Vec<f64>,
    /// The tracked cells' log odds after each scan; entry 0 is the empty
    /// map.
    tracked: Vec<[f32; 3]>,
    last: ScanStats,
    /// The pose the last scan was integrated at.
    pose: Pose,
    ghost: GhostTracker,
    /// Core milliseconds of the pane's recent scans (mapping and view).
    scan_ms: Vec<f64>,
}

/// The apartment scene rastered at `resolution` metres per cell (same
/// extent, same boxes).
fn scene_at(scene: &ApartmentScene, resolution: f64) -> ApartmentScene {
    if resolution == scene.resolution {
        return scene.clone();
    }
    let scale = scene.resolution / resolution;
    ApartmentScene {
        width: (scene.width as f64 * scale).round() as usize,
        height: (scene.height as f64 * scale).round() as usize,
        resolution,
        ..scene.clone()
    }
}

/// The cells of `g` whose centres lie in `r`, in increasing order (the
/// same rule as [`ApartmentScene::cells_in`], over the box's cells only).
fn cells_under(g: &GridGeometry, r: &crate::world::Rect) -> Vec<usize> {
    let [ox, oy] = g.origin();
    let res = g.resolution();
    let span = |lo: f64, hi: f64, o: f64, n: usize| {
        let a = ((lo - o) / res).floor().max(0.0) as usize;
        let b = (((hi - o) / res).ceil().max(0.0) as usize).min(n);
        a..b
    };
    let mut out = Vec::new();
    for iy in span(r.min_y, r.max_y, oy, g.height()) {
        for ix in span(r.min_x, r.max_x, ox, g.width()) {
            let (x, y) = g.cell_center(ix, iy);
            if r.contains(x, y) {
                out.push(g.index(ix, iy));
            }
        }
    }
    out
}

/// Median of a few numbers, if any.
fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    Some(v[v.len() / 2])
}

/// A monotonic clock in milliseconds. Natively the standard library's;
/// in the browser the bindings hand in `performance.now`.
pub type Clock = fn() -> f64;

#[cfg(not(target_arch = "wasm32"))]
fn native_clock() -> f64 {
    use std::sync::OnceLock;
    use std::time::Instant;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64() * 1e3
}

/// A tracked cell: its name, the world point it was chosen by (metres), its
/// grid cell and its cell in the north-up image.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TrackedCell {
    pub name: String,
    pub at: [f64; 2],
    pub ix: usize,
    pub iy: usize,
    pub col: usize,
    pub row: usize,
}

/// The readout of one pane (plain numbers for the page).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct PaneReadout {
    pub model: ModelKind,
    pub pose: PoseSource,
    pub clamp: f64,
    pub strength: f64,
    pub mapper: MapperKind,
    pub sensor: SensorKind,
    pub beta_deg: f64,
    /// Beams of each scan the pane uses.
    pub beams: usize,
    pub resolution: f64,
    pub forget_l0: bool,
    /// The pane's map size, cells (= its image's pixels).
    pub width: usize,
    pub height: usize,
    /// Mean core milliseconds per scan for this pane over its recent scans
    /// (its mapper and view), when a clock is set.
    pub scan_ms: Option<f64>,
    pub ghost: GhostReadout,
    /// The map's prior, log odds (the chart's reference line).
    pub l0: f32,
    /// The model's own prior, log odds.
    pub model_l0: f32,
    pub entropy_bits: f64,
    /// Brier score over the surveyed rooms.
    pub brier: f64,
    /// Brier score over the whole map.
    pub brier_all: f64,
    pub cells_visited: usize,
    pub cells_updated: usize,
    /// The tracked cells' current log odds.
    pub tracked: [f32; 3],
}

/// The readout of the whole widget.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Readout {
    /// Scans integrated so far.
    pub scans: usize,
    pub scans_per_lap: usize,
    /// Laps in the run.
    pub laps: usize,
    /// The lap under way, from 1.
    pub lap: usize,
    /// Simulated seconds since the start.
    pub time: f64,
    /// True once the run's laps are done.
    pub done: bool,
    pub person: bool,
    /// Median milliseconds per frame over the last frames, if any were
    /// timed.
    pub frame_ms: Option<f64>,
    pub panes: [PaneReadout; 2],
}

/// One cell as the hover readout shows it: the pane's cell and the ground
/// truth under it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CellInfo {
    #[serde(flatten)]
    pub cell: CellReadout,
    /// Ground truth.
    pub occupied: bool,
}

/// What is drawn over a pane's map, in the map image's own units: `u`
/// columns from the left edge, `v` rows from the top edge (north up), one
/// unit per cell.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Overlay {
    /// The robot where this pane believes it is, and its heading.
    pub robot: RobotMark,
    /// Length of the robot's heading tick, cells (0.3 m).
    pub tick: f64,
    /// The robot's true position (differs under dead reckoning).
    pub truth: ImagePoint,
    /// Beam end points, `[u0, v0, u1, v1, ...]`, at the pane's pose.
    pub beams: Vec<f64>,
    /// Per beam: did it return (false: a no-return drawn to `z_max`).
    pub hits: Vec<bool>,
    /// The person's footprint, `[u_min, v_min, u_max, v_max]`, if present.
    pub person: Option<[f64; 4]>,
}

/// One simulated scan as a mapper's [`Scan`], at the true pose, and at the
/// dead-reckoned pose when a pane asks for it (validated once, whichever
/// panes use it).
struct PoseScans {
    oracle: Scan,
    odometry: Pose,
    dead_reckoning: std::cell::OnceCell<Scan>,
}

impl PoseScans {
    fn new(scan: &SimScan, bearings: &[f64]) -> Result<Self> {
        Ok(Self {
            oracle: Scan::new(scan.truth, scan.ranges.clone(), bearings.to_vec())?,
            odometry: scan.odometry,
            dead_reckoning: std::cell::OnceCell::new(),
        })
    }

    fn at(&self, pose: PoseSource) -> Result<&Scan> {
        match pose {
            PoseSource::Oracle => Ok(&self.oracle),
            PoseSource::DeadReckoning => {
                if let Some(s) = self.dead_reckoning.get() {
                    return Ok(s);
                }
                let s = self.oracle.with_pose(self.odometry)?;
                Ok(self.dead_reckoning.get_or_init(|| s))
            }
        }
    }
}

/// Every `stride`-th beam of `scan` (stride 1: the scan itself).
fn thinned(scan: &Scan, stride: usize) -> Result<std::borrow::Cow<'_, Scan>> {
    if stride <= 1 {
        return Ok(std::borrow::Cow::Borrowed(scan));
    }
    let ranges = scan.ranges().iter().step_by(stride).copied().collect();
    let bearings = scan.bearings().iter().step_by(stride).copied().collect();
    Ok(std::borrow::Cow::Owned(Scan::new(
        scan.pose(),
        ranges,
        bearings,
    )?))
}

/// A Map Weaver run.
#[derive(Debug, Clone)]
pub struct Weaver {
    settings: WeaverSettings,
    geometry: GridGeometry,
    sim: ApartmentSim,
    tracked_cells: [usize; 3],
    scans_per_lap: usize,
    /// The learned model, trained once per run and kept across resets.
    learned: LearnedInverse,
    history: Vec<SimScan>,
    panes: [Pane; 2],
    frame_ms: Vec<f64>,
    /// Times each pane's scans when set.
    clock: Option<Clock>,
}

impl Weaver {
    /// Validates `settings`, trains the learned model and starts a run at
    /// scan 0.
    pub fn new(settings: WeaverSettings) -> Result<Self> {
        // Reject bad settings before spending time on training.
        settings.validate()?;
        let (learned, _, _) = training::train(&settings.training)?;
        Self::with_learned(settings, learned)
    }

    /// Like [`Weaver::new`] with an already trained model (a page that
    /// trained one for another widget, or a test that trains once).
    pub fn with_learned(settings: WeaverSettings, learned: LearnedInverse) -> Result<Self> {
        settings.validate()?;
        let sim = ApartmentSim::new(settings.scene.clone(), settings.seed, settings.person)?;
        let geometry = *sim.ground_truth().geometry();
        let tracked_cells = settings.scene.tracked_cells()?;
        let panes = [
            Self::make_pane(&settings, &learned, 0, &settings.panes[0])?,
            Self::make_pane(&settings, &learned, 1, &settings.panes[1])?,
        ];
        #[cfg(not(target_arch = "wasm32"))]
        let clock: Option<Clock> = Some(native_clock);
        #[cfg(target_arch = "wasm32")]
        let clock: Option<Clock> = None;
        Ok(Self {
            scans_per_lap: settings.scene.scans_per_lap(),
            learned,
            geometry,
            sim,
            tracked_cells,
            history: Vec::new(),
            panes,
            frame_ms: Vec::new(),
            clock,
            settings,
        })
    }

    /// An empty pane with settings `p` (pane `k` of `settings`).
    fn make_pane(
        settings: &WeaverSettings,
        learned: &LearnedInverse,
        k: usize,
        p: &PaneSettings,
    ) -> Result<Pane> {
        validate_pane(k, p, settings.scene.lidar.beams)?;
        let scene = match p.resolution {
            Some(r) => scene_at(&settings.scene, r),
            None => settings.scene.clone(),
        };
        let world = scene.ground_truth().map_err(|e| match e {
            crate::OccError::InvalidParameter {
                value, expected, ..
            } => crate::OccError::InvalidParameter {
                field: format!("panes[{k}].resolution (the scene's width x height at it)"),
                value,
                expected,
            },
            other => other,
        })?;
        let geometry = *world.geometry();
        let truth = world.occupied().to_vec();
        let tracked_cells = scene.tracked_cells()?;
        let region = scene.cells_in(&geometry, &[scene.surveyed]);
        let grid = LogOddsGrid::new(
            geometry,
            FilterSettings {
                prior: 0.5,
                clamp: p.clamp,
            },
        )?;
        let mut view = MapView::new(&geometry, &truth, &region)?;
        view.sync(&grid);
        let model = PaneModel::build(p, &settings.hand_crafted, learned)?;
        let first = tracked_cells.map(|i| grid.log_odds()[i]);
        Ok(Pane {
            settings: *p,
            model,
            geometry,
            truth,
            tracked_cells,
            entropy_curve: vec![view.entropy_bits()],
            brier_curve: vec![view.brier_region()],
            tracked: vec![first],
            grid,
            mapper: RayMapper::new(),
            view,
            last: ScanStats::default(),
            pose: settings.scene.path.pose_at(0.0),
            ghost: GhostTracker::default(),
            scan_ms: Vec::new(),
        })
    }

    /// Sets the clock that times each pane's scans (`None`: no timing).
    pub fn set_clock(&mut self, clock: Option<Clock>) {
        self.clock = clock;
    }

    /// Starts the run again from scan 0 with the current settings (the
    /// person toggle and every pane's knobs as they are now).
    pub fn reset(&mut self) -> Result<()> {
        let mut settings = self.settings.clone();
        settings.person = self.sim.person();
        let clock = self.clock;
        *self = Self::with_learned(settings, self.learned.clone())?;
        self.clock = clock;
        Ok(())
    }

    pub fn settings(&self) -> &WeaverSettings {
        &self.settings
    }
    /// The learned model both panes use when set to it.
    pub fn learned(&self) -> &LearnedInverse {
        &self.learned
    }
    /// The scene's grid limits (a pane at another resolution has its own:
    /// [`Weaver::pane_geometry`]).
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    /// Pane `pane`'s grid limits.
    pub fn pane_geometry(&self, pane: usize) -> Result<&GridGeometry> {
        Ok(&self.pane(pane)?.geometry)
    }
    /// The ground truth at pane `pane`'s resolution.
    pub fn pane_truth(&self, pane: usize) -> Result<&[bool]> {
        Ok(&self.pane(pane)?.truth)
    }
    /// The three tracked cells of pane `pane` (indices into its grid).
    pub fn pane_tracked_cells(&self, pane: usize) -> Result<[usize; 3]> {
        Ok(self.pane(pane)?.tracked_cells)
    }
    /// The tracked cells of pane `pane` as the chart's legend and the map
    /// outline show them: name, world point, grid cell and image cell.
    pub fn tracked_readout(&self, pane: usize) -> Result<Vec<TrackedCell>> {
        let g = self.pane_geometry(pane)?;
        let cells = self.pane_tracked_cells(pane)?;
        Ok(self
            .settings
            .scene
            .tracked
            .iter()
            .zip(cells)
            .map(|(t, i)| {
                let (ix, iy) = g.cell_of_index(i);
                let image = ImageCell::of(g, ix, iy);
                TrackedCell {
                    name: t.name.clone(),
                    at: t.at,
                    ix,
                    iy,
                    col: image.col,
                    row: image.row,
                }
            })
            .collect())
    }

    pub fn scans_per_lap(&self) -> usize {
        self.scans_per_lap
    }
    /// Scans integrated so far.
    pub fn scans(&self) -> usize {
        self.history.len()
    }
    /// True once the run's laps are done.
    pub fn done(&self) -> bool {
        self.history.len() >= self.settings.laps.saturating_mul(self.scans_per_lap)
    }
    /// Every scan so far.
    pub fn history(&self) -> &[SimScan] {
        &self.history
    }
    /// The ground truth at the scene's resolution.
    pub fn ground_truth(&self) -> &[bool] {
        self.sim.ground_truth().occupied()
    }
    /// The three tracked cells (indices), in the scene's order.
    pub fn tracked_cells(&self) -> [usize; 3] {
        self.tracked_cells
    }
    pub fn grid(&self, pane: usize) -> Result<&LogOddsGrid> {
        Ok(&self.pane(pane)?.grid)
    }
    pub fn view(&self, pane: usize) -> Result<&MapView> {
        Ok(&self.pane(pane)?.view)
    }
    /// Seconds of driving that `scans` scans take at the scene's scan rate:
    /// the readout's time and the charts' x axis, both from here.
    pub fn seconds_after(&self, scans: usize) -> f64 {
        scans as f64 / self.settings.scene.scan_rate
    }

    /// The x axis of the curves: the time of each point, seconds (point 0
    /// is the empty map, point `i` the map after `i` scans).
    pub fn curve_times(&self) -> Vec<f64> {
        (0..=self.history.len())
            .map(|i| self.seconds_after(i))
            .collect()
    }

    /// Entropy (bits) after each scan, from the empty map on.
    pub fn entropy_curve(&self, pane: usize) -> Result<&[f64]> {
        Ok(&self.pane(pane)?.entropy_curve)
    }
    /// Brier score (surveyed rooms) after each scan, from the empty map on.
    pub fn brier_curve(&self, pane: usize) -> Result<&[f64]> {
        Ok(&self.pane(pane)?.brier_curve)
    }
    /// The tracked cells' log odds after each scan, from the empty map on.
    pub fn tracked_history(&self, pane: usize) -> Result<&[[f32; 3]]> {
        Ok(&self.pane(pane)?.tracked)
    }
    /// Scans each of pane `pane`'s completed ghost fades took, in the order
    /// they completed (exercise 5).
    pub fn ghost_fades(&self, pane: usize) -> Result<&[usize]> {
        Ok(&self.pane(pane)?.ghost.fades)
    }

    fn pane(&self, pane: usize) -> Result<&Pane> {
        self.panes
            .get(pane)
            .ok_or_else(|| invalid("pane", pane, "0 (left) or 1 (right)"))
    }
    fn pane_mut(&mut self, pane: usize) -> Result<&mut Pane> {
        self.panes
            .get_mut(pane)
            .ok_or_else(|| invalid("pane", pane, "0 (left) or 1 (right)"))
    }

    /// Simulates and integrates up to `n` scans (fewer when the run ends);
    /// returns how many were taken.
    pub fn advance(&mut self, n: usize) -> Result<usize> {
        let mut taken = 0;
        while taken < n && !self.done() {
            let scan = self.sim.next_scan();
            let scans = PoseScans::new(&scan, self.sim.bearings())?;
            let count = self.history.len() + 1;
            for pane in &mut self.panes {
                Self::integrate(pane, &scans, &scan, count, self.clock)?;
            }
            self.history.push(scan);
            taken += 1;
        }
        Ok(taken)
    }

    /// The most cells one scan visits, both panes together: for a pane by
    /// ray traversal, its beams x the cells along a beam at the LiDAR's
    /// range (one per the pane's resolution); for a pane by the sweep,
    /// every cell of its map. The unit of [`MAX_FAST_FORWARD_WORK`]: an
    /// estimate, but one that grows as the real work does with finer
    /// grids, more beams and the sweep.
    pub fn work_per_scan(&self) -> u64 {
        let lidar = &self.settings.scene.lidar;
        self.panes
            .iter()
            .map(|p| match p.settings.mapper {
                MapperKind::Sweep => p.geometry.len() as u64,
                MapperKind::Traversal => {
                    let cells = (lidar.z_max / p.geometry.resolution()).ceil().max(1.0);
                    let beams = p.settings.beams.unwrap_or(lidar.beams);
                    // Finite and at most z_max / resolution: `as` cannot
                    // wrap here.
                    beams as u64 * cells as u64
                }
            })
            .sum()
    }

    /// How many scans [`Weaver::advance`] will take for a request of `scans`
    /// (fewer when the run's laps end first), or an error naming `scans`
    /// when that is more than [`MAX_FAST_FORWARD_WORK`]. Checked before a
    /// page starts the work, so that a link asking for a minute of mapping
    /// is refused with its reason instead of started.
    pub fn check_fast_forward(&self, scans: usize) -> Result<usize> {
        let total = self.settings.laps.saturating_mul(self.scans_per_lap);
        let taken = scans.min(total.saturating_sub(self.history.len()));
        let per_scan = self.work_per_scan();
        let work = (taken as u64).saturating_mul(per_scan);
        if work > MAX_FAST_FORWARD_WORK {
            return Err(invalid(
                "scans",
                format!("{scans} ({taken} scans x {per_scan} cell visits = {work})"),
                "at most 250000000 cell visits before the first frame: fewer scans or laps, or a coarser resolution",
            ));
        }
        Ok(taken)
    }

    /// Integrates one scan (number `count`, from 1) into `pane` at the pose
    /// and with the beams the pane's settings ask for, then updates its
    /// view, its curves and its ghost watch.
    fn integrate(
        pane: &mut Pane,
        scans: &PoseScans,
        sim: &SimScan,
        count: usize,
        clock: Option<Clock>,
    ) -> Result<()> {
        let started = clock.map(|c| c());
        let full = scans.at(pane.settings.pose)?;
        let stride = pane.settings.beams.map_or(1, |b| full.len() / b.max(1));
        let s = thinned(full, stride)?;
        pane.last =
            pane.model
                .integrate(pane.settings.mapper, &mut pane.mapper, &mut pane.grid, &s);
        pane.pose = s.pose();
        pane.view.sync(&pane.grid);
        if let (Some(c), Some(t0)) = (clock, started) {
            if pane.scan_ms.len() == SCAN_TIME_WINDOW {
                pane.scan_ms.remove(0);
            }
            pane.scan_ms.push((c() - t0).max(0.0));
        }
        pane.entropy_curve.push(pane.view.entropy_bits());
        pane.brier_curve.push(pane.view.brier_region());
        pane.tracked
            .push(pane.tracked_cells.map(|i| pane.grid.log_odds()[i]));
        let under = sim
            .person
            .map(|r| cells_under(&pane.geometry, &r))
            .unwrap_or_default();
        pane.ghost.observe(count, &under, pane.grid.log_odds());
        Ok(())
    }

    /// Rebuilds `pane` from the empty map over every scan so far, with its
    /// current settings.
    fn rebuild(&mut self, pane: usize) -> Result<()> {
        let bearings = self.sim.bearings().to_vec();
        let clock = self.clock;
        let history = std::mem::take(&mut self.history);
        let result = (|| {
            let p = self.pane_mut(pane)?;
            p.grid.reset();
            // Start the sums from zero, as a new pane does, so a rebuilt
            // pane is bit for bit the pane that had these settings all along.
            p.view.clear();
            p.view.sync(&p.grid);
            p.entropy_curve.truncate(1);
            p.brier_curve.truncate(1);
            p.tracked.truncate(1);
            p.last = ScanStats::default();
            p.ghost.clear();
            p.scan_ms.clear();
            for (i, scan) in history.iter().enumerate() {
                Self::integrate(p, &PoseScans::new(scan, &bearings)?, scan, i + 1, clock)?;
            }
            Ok(())
        })();
        self.history = history;
        result
    }

    /// Changes every knob of pane `pane` at once. Clamp and strength act on
    /// the run as it goes; any other change (model, pose source, mapper,
    /// sensor, cone opening, beams, resolution, `l0` forgotten) rebuilds
    /// the pane over the scans so far. Nothing changes when `settings` is
    /// refused.
    pub fn set_pane(&mut self, pane: usize, settings: PaneSettings) -> Result<()> {
        validate_pane(pane, &settings, self.settings.scene.lidar.beams)?;
        let current = self.pane(pane)?.settings;
        if current.needs_rebuild(&settings) {
            let mut fresh = Self::make_pane(&self.settings, &self.learned, pane, &settings)?;
            std::mem::swap(&mut fresh, &mut self.panes[pane]);
            self.settings.panes[pane] = settings;
            if let Err(e) = self.rebuild(pane) {
                self.panes[pane] = fresh;
                self.settings.panes[pane] = current;
                return Err(e);
            }
            return Ok(());
        }
        if settings.strength != current.strength {
            self.set_strength(pane, settings.strength)?;
        }
        if settings.clamp != current.clamp {
            self.set_clamp(pane, settings.clamp)?;
        }
        Ok(())
    }

    /// Switches a pane's inverse model and rebuilds it over the scans so
    /// far.
    pub fn set_model(&mut self, pane: usize, model: ModelKind) -> Result<()> {
        let s = self.pane(pane)?.settings;
        self.set_pane(pane, PaneSettings { model, ..s })
    }

    /// Switches a pane between the pose oracle and dead reckoning and
    /// rebuilds it over the scans so far.
    pub fn set_pose_source(&mut self, pane: usize, pose: PoseSource) -> Result<()> {
        let s = self.pane(pane)?.settings;
        self.set_pane(pane, PaneSettings { pose, ..s })
    }

    /// Changes a pane's clamp now: cells beyond it are pulled in at once,
    /// later scans saturate at it.
    pub fn set_clamp(&mut self, pane: usize, clamp: f64) -> Result<()> {
        let p = self.pane_mut(pane)?;
        p.grid
            .set_clamp(clamp)
            .map_err(|e| pane_clamp_error(pane, e))?;
        p.settings.clamp = clamp;
        p.view.sync(&p.grid);
        self.settings.panes[pane].clamp = clamp;
        Ok(())
    }

    /// Changes a pane's evidence strength from the next scan on.
    pub fn set_strength(&mut self, pane: usize, strength: f64) -> Result<()> {
        check_strength(pane, strength)?;
        let base = self.settings.hand_crafted;
        let learned = self.learned.clone();
        let p = self.pane_mut(pane)?;
        let settings = PaneSettings {
            strength,
            ..p.settings
        };
        p.model = PaneModel::build(&settings, &base, &learned)?;
        p.settings.strength = strength;
        self.settings.panes[pane].strength = strength;
        Ok(())
    }

    /// Puts the person into the corridor or takes them out, from the next
    /// scan on.
    pub fn set_person(&mut self, on: bool) {
        self.sim.set_person(on);
        self.settings.person = on;
    }

    /// Records how long the page took for one frame (milliseconds, measured
    /// around the core's calls), for the "ms per frame" readout.
    pub fn record_frame_ms(&mut self, ms: f64) {
        if !ms.is_finite() || ms < 0.0 {
            return;
        }
        if self.frame_ms.len() == FRAME_WINDOW {
            self.frame_ms.remove(0);
        }
        self.frame_ms.push(ms);
    }

    /// Median of the recent frame times, milliseconds.
    pub fn frame_ms(&self) -> Option<f64> {
        median(&self.frame_ms)
    }

    fn ghost_readout(&self, p: &Pane) -> GhostReadout {
        let g = &p.ghost;
        let last = g.fades.last().copied();
        let longest = g.fades.iter().copied().max();
        GhostReadout {
            faded: g.fades.len(),
            lingering: g.pending.len(),
            last_scans: last,
            last_seconds: last.map(|n| self.seconds_after(n)),
            longest_scans: longest,
            longest_seconds: longest.map(|n| self.seconds_after(n)),
        }
    }

    pub fn readout(&self) -> Readout {
        let scans = self.history.len();
        let lidar_beams = self.settings.scene.lidar.beams;
        let pane = |p: &Pane| PaneReadout {
            model: p.settings.model,
            pose: p.settings.pose,
            clamp: p.settings.clamp,
            strength: p.settings.strength,
            mapper: p.settings.mapper,
            sensor: p.settings.sensor,
            beta_deg: p.settings.beta_deg,
            beams: p.settings.beams.unwrap_or(lidar_beams),
            resolution: p.geometry.resolution(),
            forget_l0: p.settings.forget_l0,
            width: p.geometry.width(),
            height: p.geometry.height(),
            // A mean, not a median: the page's clock may tick in steps
            // coarser than a traversal scan, and only the mean of the
            // rounded times keeps the small ones.
            scan_ms: (!p.scan_ms.is_empty())
                .then(|| p.scan_ms.iter().sum::<f64>() / p.scan_ms.len() as f64),
            ghost: self.ghost_readout(p),
            l0: p.grid.l0(),
            model_l0: p.model.l0(),
            entropy_bits: p.view.entropy_bits(),
            brier: p.view.brier_region(),
            brier_all: p.view.brier_all(),
            cells_visited: p.last.cells_visited,
            cells_updated: p.last.cells_updated,
            tracked: p.tracked_cells.map(|i| p.grid.log_odds()[i]),
        };
        Readout {
            scans,
            scans_per_lap: self.scans_per_lap,
            laps: self.settings.laps,
            lap: (scans.saturating_sub(1) / self.scans_per_lap + 1).min(self.settings.laps),
            time: self.seconds_after(scans),
            done: self.done(),
            person: self.sim.person(),
            frame_ms: self.frame_ms(),
            panes: [pane(&self.panes[0]), pane(&self.panes[1])],
        }
    }

    /// The cell under image column `col`, row `row` of pane `pane` (row 0
    /// at the top: the image is north up), or `None` outside the map.
    pub fn cell_info(&self, pane: usize, col: usize, row: usize) -> Result<Option<CellInfo>> {
        let p = self.pane(pane)?;
        Ok(readout_at_pixel(&p.grid, col, row).map(|cell| CellInfo {
            occupied: p.truth[p.geometry.index(cell.ix, cell.iy)],
            cell,
        }))
    }

    /// What to draw over a pane: the robot where the pane put the last scan,
    /// its beams, and the person.
    pub fn overlay(&self, pane: usize) -> Result<Overlay> {
        let p = self.pane(pane)?;
        let pose = p.pose;
        let z_max = self.settings.scene.lidar.z_max;
        let last = self.history.last();
        let g = &p.geometry;
        let stride = p
            .settings
            .beams
            .map_or(1, |b| self.sim.bearings().len() / b.max(1))
            .max(1);
        let mut beams = Vec::new();
        let mut hits = Vec::new();
        if let Some(scan) = last {
            for (&z, &b) in scan.ranges.iter().zip(self.sim.bearings()).step_by(stride) {
                let (x, y) = pose.point_at(z.min(z_max), b);
                beams.extend(g.world_to_image(x, y));
                hits.push(z < z_max);
            }
        }
        let truth = last.map_or(pose, |s| s.truth);
        Ok(Overlay {
            robot: RobotMark::at(g, &pose),
            tick: HEADING_TICK / g.resolution(),
            truth: {
                let [x, y] = g.world_to_image(truth.x, truth.y);
                ImagePoint { x, y }
            },
            beams,
            hits,
            person: last
                .and_then(|s| s.person)
                .map(|r| g.box_to_image(r.min_x, r.min_y, r.max_x, r.max_y)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::OnceLock;

    /// A run with a model trained once for all the tests here.
    fn weaver(settings: WeaverSettings) -> Weaver {
        static LEARNED: OnceLock<LearnedInverse> = OnceLock::new();
        let learned =
            LEARNED.get_or_init(|| training::train(&TrainingConfig::default()).unwrap().0);
        Weaver::with_learned(settings, learned.clone()).unwrap()
    }

    #[test]
    fn view_pixels_match_the_grid_renderer_after_scans_and_a_clamp_change() {
        let mut w = weaver(WeaverSettings::default());
        w.advance(40).unwrap();
        w.set_clamp(0, 1.5).unwrap();
        w.advance(5).unwrap();
        for k in 0..2 {
            let grid = w.grid(k).unwrap();
            let mut px = vec![0u8; grid.geometry().len() * 4];
            crate::render::gray::render_grid_rgba(grid, &mut px).unwrap();
            assert_eq!(w.view(k).unwrap().rgba(), &px[..], "pane {k}");
            // The view scores from a table (view.rs): within 1e-6 bits per
            // cell of the exact sum.
            let h = grid.entropy_bits();
            assert!((w.view(k).unwrap().entropy_bits() - h).abs() < 1e-6 * 10_800.0);
            let b = grid.brier_score(w.ground_truth(), None).unwrap();
            assert!((w.view(k).unwrap().brier_all() - b).abs() < 1e-6);
        }
    }

    #[test]
    fn training_past_the_update_limit_is_refused_before_it_starts() {
        let mut s = WeaverSettings::default();
        s.training.triplets = 1_000_000;
        s.training.epochs = 200;
        let e = Weaver::new(s.clone()).err().unwrap().to_string();
        assert!(
            e.contains("training.triplets x training.epochs")
                && e.contains("200000000")
                && e.contains("5000000"),
            "{e}"
        );
        // Each alone, at its own maximum, is fine.
        s.training.epochs = 5;
        s.validate().unwrap();
        s.training = TrainingConfig {
            epochs: 200,
            ..TrainingConfig::default()
        };
        s.validate().unwrap();
    }

    #[test]
    fn bad_knobs_are_rejected_naming_the_pane_and_leave_the_map_alone() {
        let mut w = weaver(WeaverSettings::default());
        w.advance(10).unwrap();
        let before = w.grid(1).unwrap().clone();
        let e = w.set_clamp(1, 0.0).unwrap_err().to_string();
        assert!(e.contains("panes[1].clamp") && e.contains('0'), "{e}");
        let e = w.set_strength(1, f64::NAN).unwrap_err().to_string();
        assert!(e.contains("panes[1].strength") && e.contains("NaN"), "{e}");
        assert!(w.set_strength(1, 11.0).is_err());
        assert!(w
            .set_clamp(2, 3.0)
            .unwrap_err()
            .to_string()
            .contains("pane"));
        assert!(w.cell_info(5, 0, 0).is_err());
        assert_eq!(w.cell_info(0, 120, 0).unwrap(), None);
        assert_eq!(w.grid(1).unwrap(), &before);
        let mut s = WeaverSettings::default();
        s.laps = 0;
        assert!(Weaver::new(s).unwrap_err().to_string().contains("laps"));
        let mut s = WeaverSettings::default();
        s.panes[0].clamp = -1.0;
        assert!(Weaver::new(s)
            .unwrap_err()
            .to_string()
            .contains("panes[0].clamp"));
    }

    #[test]
    fn switching_the_pose_source_rebuilds_the_pane_over_the_same_scans() {
        let mut s = WeaverSettings::default();
        s.panes[1].pose = PoseSource::DeadReckoning;
        let mut reference = weaver(s);
        reference.advance(120).unwrap();
        let mut w = weaver(WeaverSettings::default());
        w.advance(120).unwrap();
        w.set_pose_source(1, PoseSource::DeadReckoning).unwrap();
        assert_eq!(w.grid(1).unwrap(), reference.grid(1).unwrap());
        assert_eq!(
            w.entropy_curve(1).unwrap(),
            reference.entropy_curve(1).unwrap()
        );
        assert_eq!(w.entropy_curve(1).unwrap().len(), 121);
    }

    #[test]
    fn hover_reads_the_cell_under_the_pointer_north_up() {
        let mut w = weaver(WeaverSettings::default());
        w.advance(30).unwrap();
        // Image row 0 is the map's northernmost row.
        let info = w.cell_info(0, 30, 0).unwrap().unwrap();
        assert_eq!((info.cell.ix, info.cell.iy), (30, 89));
        assert!(info.occupied, "the north outer wall");
        let [wall, _, _] = w.tracked_cells();
        let (ix, iy) = w.geometry().cell_of_index(wall);
        let info = w.cell_info(0, ix, 89 - iy).unwrap().unwrap();
        assert_eq!(info.cell.l, w.grid(0).unwrap().log_odds()[wall] as f64);
        assert_eq!(info.cell.updates, w.grid(0).unwrap().update_counts()[wall]);
    }

    #[test]
    fn overlay_puts_the_robot_on_its_cell_with_one_end_point_per_beam() {
        let mut w = weaver(WeaverSettings::default());
        w.advance(1).unwrap();
        let o = w.overlay(0).unwrap();
        // The lap starts at (1.2 m, 4.95 m): column 12, 49.5 rows from the
        // bottom of 90, so 40.5 rows from the top.
        assert!((o.robot.x - 12.0).abs() < 1e-9 && (o.robot.y - 40.5).abs() < 1e-9);
        assert!(o.robot.heading.cos() > 0.99, "facing east");
        assert_eq!((o.beams.len(), o.hits.len()), (120, 60));
        assert!(o.person.is_some());
    }

    /// A link asking for more scans than the work budget is refused by
    /// name before any work; the run's end bounds what is asked for.
    #[test]
    fn fast_forward_is_bounded_by_the_work_budget_and_the_run() {
        let w = weaver(WeaverSettings::default());
        // 60 beams x 80 cells (8 m at 0.1 m) x 2 panes.
        assert_eq!(w.work_per_scan(), 9600);
        let total = 3 * w.scans_per_lap();
        assert_eq!(w.check_fast_forward(10).unwrap(), 10);
        assert_eq!(w.check_fast_forward(1_000_000).unwrap(), total);
        let mut s = WeaverSettings::default();
        s.laps = 20;
        s.scene.width = 960;
        s.scene.height = 720;
        s.scene.resolution = 0.0125;
        s.scene.scan_rate = 60.0;
        let fine = weaver(s);
        assert_eq!(fine.work_per_scan(), 2 * 60 * 640);
        let limit = (MAX_FAST_FORWARD_WORK / fine.work_per_scan()) as usize;
        assert_eq!(fine.check_fast_forward(limit).unwrap(), limit);
        let e = fine.check_fast_forward(1_000_000).unwrap_err().to_string();
        assert!(e.starts_with("invalid scans: 1000000 ("), "{e}");
        assert!(e.contains("250000000 cell visits"), "{e}");
        assert!(fine.check_fast_forward(limit + 1).is_err());
    }

    /// The readout's "s of driving" and the charts' time axis come from the
    /// scene's scan rate (a chart that assumed 12 scans per second put the
    /// 12th scan of a 6 Hz scene at 1 s, the readout at 2 s).
    #[test]
    fn readout_time_and_curve_times_follow_the_scene_scan_rate() {
        let mut s = WeaverSettings::default();
        s.scene.scan_rate = 6.0;
        let mut w = weaver(s);
        w.advance(12).unwrap();
        let times = w.curve_times();
        assert_eq!(times.len(), w.entropy_curve(0).unwrap().len());
        assert_eq!(times[0], 0.0);
        assert_eq!(*times.last().unwrap(), 2.0);
        assert_eq!(w.readout().time, 2.0);
    }
}
