//! The sensor-fusion session (eq. 9.9 in the table scene): what
//! `<occgrid-sensor-fusion>` shows.
//!
//! Data flow: [`TableFusion`] takes the scans of a [`TableRun`], feeds the
//! sonar (a wide cone) through the literal sweep [`sweep_scan`] and the
//! LiDAR (thin beams) through [`RayMapper`], into the per-modality grids and,
//! both together, into the summed grid; the max-fused map
//! ([`max_fused_probabilities`]) is recomputed after each step. The widget draws all
//! four and reads the table footprint's mean occupancy under each rule.

use crate::error::{self, Result};
use crate::geometry::Pose;
use crate::grid::{logit, probability, FilterSettings, LogOddsGrid};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::mapping::fusion::{max_fuse_into, max_fused_probabilities, mean_over, mean_probability};
use crate::mapping::sweep::sweep_scan;
use crate::mapping::traversal::RayMapper;
use crate::render::overlay::{RayMark, RobotMark};
use crate::scenes::table::{TableRun, TableScene};

mod cell;
mod pieces;

pub use cell::FusionCell;

/// What the widget's beam count keeps to: the chapter's LiDAR and the
/// scene's cap.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FusionLimits {
    pub default_lidar_beams: usize,
    pub max_lidar_beams: usize,
}

impl FusionLimits {
    pub fn chapter() -> Self {
        Self {
            default_lidar_beams: TableScene::default().lidar.beams,
            max_lidar_beams: crate::scenes::table::MAX_LIDAR_BEAMS,
        }
    }
}

/// The hand-crafted inverse models (Table 9.2) of the two modalities, and
/// the settings of every map. Probabilities rather than log odds, because
/// that is how a reader thinks about them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct FusionModels {
    /// Sonar: `p(m | z)` at the echo.
    pub sonar_p_occ: f64,
    /// Sonar: `p(m | z)` inside the cone in front of the echo.
    pub sonar_p_free: f64,
    /// Sonar obstacle thickness `alpha`, metres.
    pub sonar_alpha: f64,
    /// LiDAR: `p(m | z)` at the return.
    pub lidar_p_occ: f64,
    /// LiDAR: `p(m | z)` along the beam in front of the return.
    pub lidar_p_free: f64,
    /// LiDAR obstacle thickness `alpha`, metres.
    pub lidar_alpha: f64,
    /// Prior `p0` of every map.
    pub prior: f64,
    /// Saturation `|l| <= clamp` of every map, log odds.
    pub clamp: f64,
}

impl Default for FusionModels {
    /// The sonar's echo is strong evidence (something *is* at that range
    /// somewhere in the cone: 0.7), its free space weaker (0.4), because a
    /// wide cone blurs where the echo came from and smooth surfaces can
    /// deflect it; its `alpha` of 20 cm (four cells at 5 cm) covers the
    /// cone's arc and the sonar's coarse range. The LiDAR uses the values of
    /// the Intel benchmark (0.7 / 0.4, i.e. l_occ = +0.85 and
    /// l_free = -0.41) with `alpha` = 10 cm, two cells: enough that a return
    /// from a cell's near face still marks that cell. Prior 0.5, so
    /// "unknown" is mid-gray and both modalities start from the same `l0`;
    /// clamp 6 (p between 0.0025 and 0.9975) keeps every cell revisable
    /// within a lap.
    fn default() -> Self {
        Self {
            sonar_p_occ: 0.7,
            sonar_p_free: 0.4,
            sonar_alpha: 0.2,
            lidar_p_occ: 0.7,
            lidar_p_free: 0.4,
            lidar_alpha: 0.1,
            prior: 0.5,
            clamp: 6.0,
        }
    }
}

impl FusionModels {
    fn settings(&self) -> FilterSettings {
        FilterSettings {
            prior: self.prior,
            clamp: self.clamp,
        }
    }

    /// The sonar's Table 9.2 model: the cone's opening angle and range come
    /// from the scene's sonar.
    pub fn sonar_model(&self, scene: &TableScene) -> Result<HandCrafted> {
        error::open_probability("sonar_p_occ", self.sonar_p_occ)?;
        error::open_probability("sonar_p_free", self.sonar_p_free)?;
        HandCrafted::new(HandCraftedParams::from_probabilities(
            self.sonar_p_occ,
            self.sonar_p_free,
            self.prior,
            self.sonar_alpha,
            scene.sonar.beta(),
            scene.sonar.z_max,
        )?)
    }

    /// The LiDAR's Table 9.2 model. Its opening angle only matters to a
    /// sweep; the ray traversal treats each beam as its own raster, so it is
    /// set to the beam spacing.
    pub fn lidar_model(&self, scene: &TableScene) -> Result<HandCrafted> {
        error::open_probability("lidar_p_occ", self.lidar_p_occ)?;
        error::open_probability("lidar_p_free", self.lidar_p_free)?;
        let spacing = std::f64::consts::TAU / scene.lidar.beams.max(1) as f64;
        HandCrafted::new(HandCraftedParams::from_probabilities(
            self.lidar_p_occ,
            self.lidar_p_free,
            self.prior,
            self.lidar_alpha,
            spacing,
            scene.lidar.z_max,
        )?)
    }

    pub fn validate(&self, scene: &TableScene) -> Result<()> {
        self.settings().validate()?;
        self.sonar_model(scene)?;
        self.lidar_model(scene)?;
        Ok(())
    }
}

/// The footprint's mean occupancy under each way of reading the sensors.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FootprintMeans {
    /// The sonar's own map.
    pub sonar: f64,
    /// The LiDAR's own map.
    pub lidar: f64,
    /// Eq. 9.9, max over the two maps.
    pub max: f64,
    /// Both streams summed into one map.
    pub sum: f64,
}

/// What the widget reads after each step.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FusionReadout {
    /// Steps integrated so far.
    pub step: usize,
    /// Steps in the whole run.
    pub steps: usize,
    pub lidar_beams: usize,
    pub sonar_count: usize,
    /// The sonar's opening angle `beta`, degrees.
    pub sonar_cone_degrees: f64,
    /// Cells under the table top.
    pub footprint_cells: usize,
    pub footprint: FootprintMeans,
    /// The last integrated pose (the first pose before any step).
    pub pose: Pose,
    /// Steps the LiDAR's two maps (its own and the summed one) still lack
    /// after a beam count changed: they are rebuilt over the steps so far
    /// by the next [`TableFusion::work`] calls.
    pub rebuilding: usize,
    /// Steps whose scans are simulated so far (the run simulates a scan
    /// when it first integrates it; a step under way counts once whole).
    pub scans_simulated: usize,
}

/// What the widget draws over the maps, in image units (see
/// [`crate::render::overlay`]): the robot, the current step's beams and the
/// table footprint.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SceneView {
    pub robot: RobotMark,
    /// Table top `[u0, v0, u1, v1]`.
    pub footprint: [f64; 4],
    /// Half the sonar's opening angle, radians.
    pub sonar_half_width: f64,
    /// The sonar ring's cones at the last integrated step (none before the
    /// first step).
    pub sonar: Vec<RayMark>,
    /// End points `[u0, v0, u1, v1, ...]` of the LiDAR's beams at the last
    /// integrated step.
    pub lidar: Vec<f64>,
}

/// What one [`TableFusion::work`] call did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FusionWork {
    /// New steps integrated by this call.
    pub steps: usize,
    /// Steps the call integrated again into the LiDAR's two maps after a
    /// beam count changed.
    pub rebuilt: usize,
    /// The call's work in cells of the sonar's sweep (every cell of the
    /// map per sweep): the raster of each LiDAR beam, the scans it
    /// simulated (each ray cast counted as the cells along its range) and
    /// the fused map's refresh count in the same unit, a fraction of a
    /// visit per cell by their cost (`pieces.rs`).
    pub cell_visits: u64,
    /// Steps integrated so far, this call's included.
    pub step: usize,
    /// Steps the LiDAR's two maps still lack after this call.
    pub rebuilding: usize,
    /// True when the call stopped within a step (new or rebuilt): the next
    /// calls finish it; the maps shown change once it is whole.
    pub under_way: bool,
    /// True once the run is over and no map lacks a step.
    pub done: bool,
}

/// The fusion experiment on the table scene: four maps fed step by step.
#[derive(Debug, Clone)]
pub struct TableFusion {
    run: TableRun,
    models: FusionModels,
    sonar_model: HandCrafted,
    lidar_model: HandCrafted,
    sonar: LogOddsGrid,
    lidar: LogOddsGrid,
    summed: LogOddsGrid,
    fused: LogOddsGrid,
    fused_p: Vec<f64>,
    lidar_mapper: RayMapper,
    summed_mapper: RayMapper,
    /// Steps integrated into the sonar's map.
    next: usize,
    /// Steps integrated into the LiDAR's two maps: `next`, except while
    /// they are rebuilt after a beam count changed.
    lidar_next: usize,
    /// A step a budgeted call left within its pieces ([`pieces`]).
    under_way: Option<pieces::StepUnderWay>,
}

impl TableFusion {
    /// The scene with the default models.
    pub fn new(scene: &TableScene) -> Result<Self> {
        Self::with_models(scene, FusionModels::default())
    }

    pub fn with_models(scene: &TableScene, models: FusionModels) -> Result<Self> {
        models.validate(scene)?;
        // The scans are simulated as the steps reach them: the first frame
        // waits for no scan of the rest of the lap.
        let run = scene.start()?;
        let g = *run.geometry();
        let s = models.settings();
        let fresh = LogOddsGrid::new(g, s)?;
        Ok(Self {
            sonar_model: models.sonar_model(scene)?,
            lidar_model: models.lidar_model(scene)?,
            models,
            sonar: fresh.clone(),
            lidar: fresh.clone(),
            summed: fresh.clone(),
            fused: fresh,
            fused_p: vec![probability(logit(s.prior)); g.len()],
            lidar_mapper: RayMapper::new(),
            summed_mapper: RayMapper::new(),
            next: 0,
            lidar_next: 0,
            under_way: None,
            run,
        })
    }

    /// Integrates the next time step's sonar and LiDAR scans, after any
    /// rebuild under way (unbounded: [`TableFusion::work`] is the bounded
    /// call); a step a budgeted call left under way is that step, finished.
    /// Returns false (and changes nothing) once the run is over.
    pub fn step(&mut self) -> bool {
        let finished = self.finish_under_way();
        let rebuilt = self.rebuild_all() || finished == Some(false);
        let stepped = finished == Some(true) || self.advance();
        if stepped || rebuilt {
            self.refresh_fused();
        }
        stepped
    }

    /// Integrates up to `steps` steps, for about `budget` cell visits: the
    /// per-frame call of a page that must keep its frames. A rebuild under
    /// way (see [`TableFusion::stage_lidar_beams`]) goes first, and new
    /// steps follow only once it is done. A step goes in pieces (its
    /// scans' simulation, bands of rows of the sonar's sweeps, the LiDAR's
    /// rasters: `pieces.rs`), and a call stops as soon as it has spent its
    /// budget (a budget of 0 counts as 1), past it by at most one piece, at
    /// least one piece done while there is work: a step left under way is
    /// finished by the next calls (it counts as one of their `steps`), and
    /// the maps shown change only when a step is whole. The fused map is
    /// refreshed once, at the end of a call that made a step whole. The
    /// maps after any sequence of calls are those of as many
    /// [`TableFusion::step`]s as steps were made whole.
    pub fn work(&mut self, steps: usize, budget: u64) -> FusionWork {
        let budget = budget.max(1);
        let (mut spent, mut taken, mut rebuilt) = (0u64, 0usize, 0usize);
        while spent < budget {
            let rebuild = self.lidar_next < self.next;
            if self.under_way.is_none() {
                if !rebuild && (taken >= steps || self.next >= self.run.len()) {
                    break;
                }
                self.begin_step(!rebuild);
            } else if !rebuild && taken >= steps {
                break;
            }
            let Some((visits, whole)) = self.work_step(budget - spent) else {
                break;
            };
            spent = spent.saturating_add(visits);
            if whole && taken + rebuilt == 0 {
                // The fused map's refresh at the end of the call, a cell
                // of each map read and max-fused per cell: about half a
                // swept cell each (measured in Chromium).
                spent = spent.saturating_add((self.fused.geometry().len() as u64).div_ceil(2));
            }
            match (whole, rebuild) {
                (true, true) => rebuilt += 1,
                (true, false) => taken += 1,
                _ => {}
            }
        }
        if taken + rebuilt > 0 {
            self.refresh_fused();
        }
        FusionWork {
            steps: taken,
            rebuilt,
            cell_visits: spent,
            step: self.next,
            rebuilding: self.rebuilding(),
            under_way: self.under_way.is_some(),
            done: self.next >= self.run.len() && self.rebuilding() == 0,
        }
    }

    /// Steps the LiDAR's two maps still lack after a beam count changed.
    pub fn rebuilding(&self) -> usize {
        self.next - self.lidar_next
    }

    /// [`TableFusion::step`] without refreshing the fused map, for replays
    /// that only need the fused map at their end.
    fn advance(&mut self) -> bool {
        self.advance_counted().is_some()
    }

    /// [`TableFusion::advance`], returning the cells its mappers visited
    /// and the cost of the scans it simulated (at least 1); `None` once
    /// the run is over. Only with the LiDAR's maps caught up.
    fn advance_counted(&mut self) -> Option<u64> {
        let cost = self.integrate_step(self.next, true)?;
        self.next += 1;
        self.lidar_next = self.next;
        Some(cost)
    }

    /// Integrates the next step the LiDAR's two maps lack (after a beam
    /// count changed) into them, returning the cells visited and the cost
    /// of the LiDAR scan it simulated (at least 1); `None` when they lack
    /// none. The summed map takes the step's sonar scan then its LiDAR
    /// scan, as in [`TableFusion::advance_counted`], so a rebuilt map is
    /// the map of a run that had the new beam count all along.
    fn rebuild_counted(&mut self) -> Option<u64> {
        if self.lidar_next >= self.next {
            return None;
        }
        let cost = self.integrate_step(self.lidar_next, false)?;
        self.lidar_next += 1;
        Some(cost)
    }

    /// Integrates step `k`'s scans (simulated first, if they are not yet)
    /// into the LiDAR map and the summed map, and into the sonar map too
    /// with `into_sonar`; returns the cells visited plus the simulation's
    /// cost (at least 1), `None` past the run's end.
    fn integrate_step(&mut self, k: usize, into_sonar: bool) -> Option<u64> {
        // A validated scene's sensors refuse no reading (`TableScene::
        // validate` checks what a cast refuses): an error here would be a
        // bug, and the run stops at it rather than integrate a wrong scan.
        let simulated = self.run.simulate_through(k + 1).ok()?;
        let (Some(sonar), Some(lidar)) = (self.run.sonar().get(k), self.run.lidar().get(k)) else {
            return None;
        };
        // One grid per modality, each with the mapper its beam shape needs:
        // a 25° cone covers cells no beam raster crosses (docs/ARCHITECTURE.md, "The data flow").
        let mut visits = 0;
        if into_sonar {
            visits += sweep_scan(&mut self.sonar, &self.sonar_model, sonar).cells_visited as u64;
        }
        visits += self
            .lidar_mapper
            .integrate(&mut self.lidar, &self.lidar_model, lidar)
            .cells_visited as u64;
        // The naive alternative: both streams into the same cells.
        visits += sweep_scan(&mut self.summed, &self.sonar_model, sonar).cells_visited as u64;
        visits += self
            .summed_mapper
            .integrate(&mut self.summed, &self.lidar_model, lidar)
            .cells_visited as u64;
        Some(visits.saturating_add(simulated).max(1))
    }

    /// Finishes a rebuild under way at once; true if it had one.
    fn rebuild_all(&mut self) -> bool {
        let mut any = false;
        while self.rebuild_counted().is_some() {
            any = true;
        }
        any
    }

    /// Steps to the end of the run (after any rebuild under way); returns
    /// the number of new steps taken.
    pub fn run_to_end(&mut self) -> usize {
        let mut n = usize::from(self.finish_under_way() == Some(true));
        self.rebuild_all();
        while self.advance() {
            n += 1;
        }
        self.refresh_fused();
        n
    }

    /// Every map back to the prior, the robot back to the start.
    pub fn reset(&mut self) {
        for m in [
            &mut self.sonar,
            &mut self.lidar,
            &mut self.summed,
            &mut self.fused,
        ] {
            m.reset();
        }
        self.next = 0;
        self.lidar_next = 0;
        self.under_way = None;
        self.refresh_fused();
    }

    /// Changes only the LiDAR's beam count (same seed, same path, same
    /// sonar readings) and rebuilds every map up to the current step at
    /// once, so the reader sees the effect at the same point of the run.
    /// On error nothing changes. [`TableFusion::stage_lidar_beams`] is the
    /// same change with the rebuild left to bounded calls.
    pub fn set_lidar_beams(&mut self, beams: usize) -> Result<()> {
        self.stage_lidar_beams(beams)?;
        self.rebuild_all();
        self.refresh_fused();
        Ok(())
    }

    /// Changes only the LiDAR's beam count and empties the two maps it
    /// feeds (the sonar's map is unchanged: its scans are), to be rebuilt
    /// over the steps so far by the next [`TableFusion::work`] calls before
    /// any new step, within their budgets: a slider dragged late in a long
    /// run never blocks the page. The LiDAR's scans are simulated again as
    /// the rebuild reaches them. On error nothing changes.
    pub fn stage_lidar_beams(&mut self, beams: usize) -> Result<()> {
        let scene = self.run.scene().with_lidar_beams(beams)?;
        let lidar_model = self.models.lidar_model(&scene)?;
        self.run.restart_lidar(beams)?;
        self.lidar_model = lidar_model;
        self.lidar.reset();
        self.summed.reset();
        self.lidar_next = 0;
        // A step under way wrote copies of the maps with the old beams: it
        // starts again (its scans are kept, the LiDAR's simulated again).
        self.under_way = None;
        self.refresh_fused();
        Ok(())
    }

    fn refresh_fused(&mut self) {
        let maps = [&self.sonar, &self.lidar];
        // Both maps were built with the same limits and prior, so neither
        // call can fail; on the impossible error the previous fused state
        // stays.
        if let Ok(p) = max_fused_probabilities(&maps) {
            self.fused_p = p;
        }
        let _ = max_fuse_into(&mut self.fused, &maps);
    }

    /// The sonar's own map.
    pub fn sonar(&self) -> &LogOddsGrid {
        &self.sonar
    }
    /// The LiDAR's own map.
    pub fn lidar(&self) -> &LogOddsGrid {
        &self.lidar
    }
    /// Both streams summed into one map.
    pub fn summed(&self) -> &LogOddsGrid {
        &self.summed
    }
    /// Eq. 9.9 as a drawable map.
    pub fn fused(&self) -> &LogOddsGrid {
        &self.fused
    }
    /// Eq. 9.9 per cell, exactly `max(p_sonar, p_lidar)`.
    pub fn fused_probabilities(&self) -> &[f64] {
        &self.fused_p
    }
    pub fn run(&self) -> &TableRun {
        &self.run
    }
    pub fn models(&self) -> &FusionModels {
        &self.models
    }
    /// Steps integrated so far.
    pub fn steps_done(&self) -> usize {
        self.next
    }

    /// The table footprint's mean occupancy under each rule.
    pub fn footprint_means(&self) -> FootprintMeans {
        let cells = self.run.footprint();
        // The footprint of a validated scene is never empty (the table is
        // at least one resolution wide in the map), so the means exist; a
        // NaN would show a bug rather than hide it.
        let mean = |g: &LogOddsGrid| mean_probability(g, cells).unwrap_or(f64::NAN);
        FootprintMeans {
            sonar: mean(&self.sonar),
            lidar: mean(&self.lidar),
            max: mean_over(&self.fused_p, cells).unwrap_or(f64::NAN),
            sum: mean(&self.summed),
        }
    }

    /// The robot, its last scans and the table, in grid units.
    pub fn scene_view(&self) -> SceneView {
        let g = self.run.geometry();
        let last = self.next.checked_sub(1);
        let pose = self.readout().pose;
        let t = self.run.scene().table.top();
        let half_width = self.run.scene().sonar.half_width();
        let sonar = last
            .and_then(|k| self.run.sonar().get(k))
            .map(|scan| {
                scan.ranges()
                    .iter()
                    .zip(scan.bearings())
                    .map(|(&z, &b)| RayMark::from_pose(g, &pose, b, z, half_width))
                    .collect()
            })
            .unwrap_or_default();
        let lidar = last
            .and_then(|k| self.run.lidar().get(k))
            .map(|scan| {
                scan.ranges()
                    .iter()
                    .zip(scan.bearings())
                    .flat_map(|(&z, &b)| {
                        let (x, y) = pose.point_at(z, b);
                        g.world_to_image(x, y)
                    })
                    .collect()
            })
            .unwrap_or_default();
        SceneView {
            robot: RobotMark::at(g, &pose),
            footprint: g.box_to_image(t.min_x, t.min_y, t.max_x, t.max_y),
            sonar_half_width: half_width,
            sonar,
            lidar,
        }
    }

    pub fn readout(&self) -> FusionReadout {
        let scene = self.run.scene();
        let last = self.next.saturating_sub(1);
        FusionReadout {
            step: self.next,
            steps: self.run.len(),
            lidar_beams: scene.lidar.beams,
            sonar_count: scene.sonar.count,
            sonar_cone_degrees: scene.sonar.beta_deg,
            footprint_cells: self.run.footprint().len(),
            footprint: self.footprint_means(),
            pose: self.run.poses().get(last).copied().unwrap_or_default(),
            rebuilding: self.rebuilding(),
            scans_simulated: self.run.simulated().min(self.lidar_next),
        }
    }
}
