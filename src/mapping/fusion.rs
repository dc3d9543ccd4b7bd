//! Multi-sensor fusion: one grid per sensor, fused by the max rule
//! (Probabilistic Robotics §9.2, eq. 9.9), against the naive single grid.
//!
//! Two sensors that look at different horizontal slices of the world answer
//! two different questions. In the table scene ([`crate::world::table`]) a
//! sonar at table height reports the top; a LiDAR at shin height reports
//! four thin legs and free floor between them. Both are right. Adding both
//! streams into one log-odds grid treats them as independent readings of
//! the *same* cell state, which they are not: the sum then settles wherever
//! the ratio of the two evidence rates puts it (how many beams and scans
//! each sensor delivers), not on any fact about the table.
//!
//! The chapter's remedy keeps one map per modality, each a proper binary
//! Bayes filter over what that sensor can see, and fuses them per cell by
//! `p_i = max_k p_i^(k)` (eq. 9.9). The rule is deliberately biased toward
//! "occupied": a cell one sensor believes occupied stays occupied in the
//! fused map whatever the other sensor says. For a robot that plans through
//! the fused map the two errors cost very different amounts: a phantom
//! obstacle costs a detour, a deleted obstacle costs a collision. The same
//! bias has a price the widget shows: with a prior of 0.5, a cell one sensor
//! has never looked at (`p = 0.5`) outranks another sensor's "free", so the
//! fused map only clears space that every sensor has cleared.
//!
//! Data flow: [`TableFusion`] takes the scans of a [`TableRun`], feeds the
//! sonar (a wide cone) through the literal sweep [`sweep_scan`] and the
//! LiDAR (thin beams) through [`RayMapper`], into the per-modality grids and,
//! both together, into the summed grid; the max-fused map is recomputed
//! after each step. The widget `<occgrid-sensor-fusion>` draws all four and
//! reads the table footprint's mean occupancy under each rule.

use crate::error::{self, invalid, OccError, Result};
use crate::geometry::Pose;
use crate::grid::{logit, probability, FilterSettings, LogOddsGrid};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::mapping::sweep::sweep_scan;
use crate::mapping::traversal::RayMapper;
use crate::scenes::table::{TableRun, TableScene};

/// Eq. 9.9 per cell: `p_i = max_k p_i^(k)` over maps of the same limits.
pub fn max_fused_probabilities(maps: &[&LogOddsGrid]) -> Result<Vec<f64>> {
    check_same_limits(maps)?;
    let n = maps.first().map_or(0, |m| m.geometry().len());
    // `p` rises with `l`, so the largest probability is the probability of
    // the largest log odds: one exponential per cell instead of one per map.
    Ok((0..n)
        .map(|i| {
            let l = maps
                .iter()
                .map(|m| m.log_odds()[i])
                .fold(f32::NEG_INFINITY, f32::max);
            probability(l as f64)
        })
        .collect())
}

/// Writes eq. 9.9 into `out` as a map that can be drawn like any other:
/// since `p` rises with `l`, the most occupied modality of a cell is the one
/// with the largest log odds, and `out` takes that value. A cell every
/// modality has left at the prior stays "unknown". `out` must have the same
/// limits and prior as the inputs; on error it is left untouched.
pub fn max_fuse_into(out: &mut LogOddsGrid, maps: &[&LogOddsGrid]) -> Result<()> {
    check_same_limits(maps)?;
    if let Some(first) = maps.first() {
        if out.geometry() != first.geometry() {
            return Err(invalid(
                "fused map",
                "limits unlike the modalities' maps",
                "the same geometry as every modality",
            ));
        }
        if out.l0() != first.l0() {
            return Err(invalid(
                "fused map",
                format!("prior log odds {}", out.l0()),
                "the same prior as every modality",
            ));
        }
    }
    let clamp = maps.iter().map(|m| m.clamp()).fold(out.clamp(), f32::max);
    out.set_clamp(clamp as f64)?;
    out.reset();
    let l0 = out.l0();
    for i in 0..out.geometry().len() {
        let l = maps
            .iter()
            .map(|m| m.log_odds()[i])
            .fold(f32::NEG_INFINITY, f32::max);
        if l != l0 {
            out.apply(i, l - l0);
        }
    }
    Ok(())
}

/// Mean of `p` over `cells`: the footprint's mean occupancy.
pub fn mean_over(p: &[f64], cells: &[usize]) -> Result<f64> {
    if cells.is_empty() {
        return Err(invalid("cells", "[]", "at least one cell"));
    }
    let mut sum = 0.0;
    for &i in cells {
        sum += p
            .get(i)
            .ok_or_else(|| invalid("cells", i, "cell indices inside the map"))?;
    }
    Ok(sum / cells.len() as f64)
}

/// Mean occupancy probability of `grid` over `cells`.
pub fn mean_probability(grid: &LogOddsGrid, cells: &[usize]) -> Result<f64> {
    if cells.is_empty() {
        return Err(invalid("cells", "[]", "at least one cell"));
    }
    let n = grid.geometry().len();
    let mut sum = 0.0;
    for &i in cells {
        if i >= n {
            return Err(invalid("cells", i, "cell indices inside the map"));
        }
        sum += grid.probability_at(i);
    }
    Ok(sum / cells.len() as f64)
}

/// Every map must describe the same cells: same size, resolution and
/// origin.
fn check_same_limits(maps: &[&LogOddsGrid]) -> Result<()> {
    let Some(first) = maps.first() else {
        return Err(invalid("maps", "[]", "at least one modality's map"));
    };
    for (k, m) in maps.iter().enumerate().skip(1) {
        let (a, b) = (first.geometry(), m.geometry());
        if a.len() != b.len() {
            return Err(OccError::LengthMismatch {
                field: format!("maps[{k}]"),
                expected: a.len(),
                found: b.len(),
            });
        }
        if a != b {
            return Err(invalid(
                &format!("maps[{k}]"),
                "a map placed or scaled differently",
                "the same geometry as maps[0]",
            ));
        }
    }
    Ok(())
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
            scene.sonar.beta,
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
}

/// One sonar cone of the current step, in grid units (cells), for drawing.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ConeView {
    /// World angle of the cone's axis, radians, counter-clockwise from +x.
    pub angle: f64,
    /// The reading, in cells.
    pub range: f64,
}

/// What the widget draws over the maps: the robot, the current step's
/// beams and the table footprint, all in continuous grid coordinates (cell
/// `(i, j)` spans `[i, i+1) x [j, j+1)`, `v` growing north).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SceneView {
    /// Robot position and heading (radians).
    pub robot: [f64; 3],
    /// Table top `[u_min, v_min, u_max, v_max]`.
    pub footprint: [f64; 4],
    /// Half the sonar's opening angle, radians.
    pub sonar_half_width: f64,
    /// The sonar ring's cones at the last integrated step (none before the
    /// first step).
    pub sonar: Vec<ConeView>,
    /// End points `[u0, v0, u1, v1, ...]` of the LiDAR's beams at the last
    /// integrated step.
    pub lidar: Vec<f64>,
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
    next: usize,
}

impl TableFusion {
    /// The scene with the default models.
    pub fn new(scene: &TableScene) -> Result<Self> {
        Self::with_models(scene, FusionModels::default())
    }

    pub fn with_models(scene: &TableScene, models: FusionModels) -> Result<Self> {
        models.validate(scene)?;
        let run = scene.build()?;
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
            run,
        })
    }

    /// Integrates the next time step's sonar and LiDAR scans. Returns false
    /// (and changes nothing) once the run is over.
    pub fn step(&mut self) -> bool {
        let stepped = self.advance();
        if stepped {
            self.refresh_fused();
        }
        stepped
    }

    /// [`TableFusion::step`] without refreshing the fused map, for replays
    /// that only need the fused map at their end.
    fn advance(&mut self) -> bool {
        let (Some(sonar), Some(lidar)) = (
            self.run.sonar().get(self.next),
            self.run.lidar().get(self.next),
        ) else {
            return false;
        };
        // One grid per modality, each with the mapper its beam shape needs:
        // a 25° cone covers cells no beam raster crosses (SPEC §3).
        sweep_scan(&mut self.sonar, &self.sonar_model, sonar);
        self.lidar_mapper
            .integrate(&mut self.lidar, &self.lidar_model, lidar);
        // The naive alternative: both streams into the same cells.
        sweep_scan(&mut self.summed, &self.sonar_model, sonar);
        self.summed_mapper
            .integrate(&mut self.summed, &self.lidar_model, lidar);
        self.next += 1;
        true
    }

    /// Steps to the end of the run; returns the number of steps taken.
    pub fn run_to_end(&mut self) -> usize {
        let mut n = 0;
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
        self.refresh_fused();
    }

    /// Changes only the LiDAR's beam count (same seed, same path, same
    /// sonar readings) and rebuilds every map up to the current step, so the
    /// reader sees the effect at the same point of the run. On error nothing
    /// changes.
    pub fn set_lidar_beams(&mut self, beams: usize) -> Result<()> {
        let run = self.run.with_lidar_beams(beams)?;
        let lidar_model = self.models.lidar_model(run.scene())?;
        self.run = run;
        self.lidar_model = lidar_model;
        // The sonar's scans are unchanged, and so is its map: only the maps
        // the LiDAR feeds are rebuilt (a slider drag stays responsive).
        self.lidar.reset();
        self.summed.reset();
        for k in 0..self.next {
            let (Some(sonar), Some(lidar)) = (self.run.sonar().get(k), self.run.lidar().get(k))
            else {
                break;
            };
            self.lidar_mapper
                .integrate(&mut self.lidar, &self.lidar_model, lidar);
            sweep_scan(&mut self.summed, &self.sonar_model, sonar);
            self.summed_mapper
                .integrate(&mut self.summed, &self.lidar_model, lidar);
        }
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
        let res = g.resolution();
        let last = self.next.checked_sub(1);
        let pose = self.readout().pose;
        let (u, v) = g.world_to_grid(pose.x, pose.y);
        let t = self.run.scene().table.top();
        let (u0, v0) = g.world_to_grid(t.min_x, t.min_y);
        let (u1, v1) = g.world_to_grid(t.max_x, t.max_y);
        let sonar = last
            .and_then(|k| self.run.sonar().get(k))
            .map(|scan| {
                scan.ranges()
                    .iter()
                    .zip(scan.bearings())
                    .map(|(&z, &b)| ConeView {
                        angle: pose.theta + b,
                        range: z / res,
                    })
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
                        let (eu, ev) = g.world_to_grid(x, y);
                        [eu, ev]
                    })
                    .collect()
            })
            .unwrap_or_default();
        SceneView {
            robot: [u, v, pose.theta],
            footprint: [u0, v0, u1, v1],
            sonar_half_width: 0.5 * self.run.scene().sonar.beta,
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
            sonar_cone_degrees: scene.sonar.beta.to_degrees(),
            footprint_cells: self.run.footprint().len(),
            footprint: self.footprint_means(),
            pose: self.run.poses().get(last).copied().unwrap_or_default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;

    fn map(l: &[f32]) -> LogOddsGrid {
        let g = GridGeometry::new(l.len(), 1, 0.1, 0.0, 0.0).unwrap();
        let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        for (i, &v) in l.iter().enumerate() {
            m.apply(i, v);
        }
        m
    }

    #[test]
    fn max_rule_takes_the_more_occupied_modality_per_cell() {
        let a = map(&[2.0, -2.0, 0.0]);
        let b = map(&[-1.0, 1.0, -3.0]);
        let p = max_fused_probabilities(&[&a, &b]).unwrap();
        assert!((p[0] - probability(2.0)).abs() < 1e-12);
        assert!((p[1] - probability(1.0)).abs() < 1e-12);
        assert_eq!(p[2], 0.5, "unknown beats free: max(0.5, 0.047)");
        let mut out = map(&[0.0; 3]);
        max_fuse_into(&mut out, &[&a, &b]).unwrap();
        assert_eq!(out.log_odds(), &[2.0, 1.0, 0.0]);
        assert!(out.is_unknown(2));
    }

    #[test]
    fn fusion_rejects_maps_of_different_limits() {
        let a = map(&[0.0; 3]);
        let b = map(&[0.0; 4]);
        let e = max_fused_probabilities(&[&a, &b]).unwrap_err().to_string();
        assert!(e.contains("maps[1]"), "{e}");
        assert!(max_fused_probabilities(&[]).is_err());
        let mut out = map(&[0.5; 3]);
        let before = out.clone();
        assert!(max_fuse_into(&mut out, &[&b]).is_err());
        assert_eq!(out, before, "untouched on error");
        assert!(mean_over(&[0.1], &[3]).is_err());
        assert!(mean_probability(&a, &[]).is_err());
    }
}
