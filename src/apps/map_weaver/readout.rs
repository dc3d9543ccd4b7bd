//! Everything the widget shows about a run, as plain serde objects in the
//! map image's units (columns from the left, rows from the top, north up):
//! the readouts of the run and of each pane, the cell under the pointer,
//! the robot and beams over each map, the tracked cells, and the choices
//! of each pane's menus. The page formats these numbers; it computes none.

use super::brier_map::BrierDifference;
use super::compare::{L0Drift, MapDifference};
use super::ghosts::GhostReadout;
use super::pane::Pane;
use super::settings::{MapperKind, ModelKind, PaneChoices, PoseSource, SensorKind};
use super::situation::Situation;
use super::Weaver;
use crate::error::Result;
use crate::grid::readout::{readout_at_pixel, CellReadout};
use crate::render::overlay::{ImageCell, ImagePoint, RobotMark};

/// Length of the robot's heading tick over the map, metres.
const HEADING_TICK: f64 = 0.3;

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
    /// Scans in the whole run (laps x scans per lap).
    pub total_scans: usize,
    /// The lap under way, from 1.
    pub lap: usize,
    /// Simulated seconds since the start.
    pub time: f64,
    /// True once the run's laps are done.
    pub done: bool,
    /// The lap, or exercise 5's ghost watch.
    pub situation: Situation,
    pub person: bool,
    /// Median milliseconds per frame over the last frames, if any were
    /// timed.
    pub frame_ms: Option<f64>,
    pub panes: [PaneReadout; 2],
    /// Cells the two maps' exports disagree on, when both map at the same
    /// resolution (exercise 6).
    pub difference: Option<MapDifference>,
    /// The drift of a pane that forgets `l0` beside one that does not
    /// (exercise 8).
    pub l0_drift: Option<L0Drift>,
    /// Where each map is closer to the truth, cell by cell, when both map
    /// the same cells (exercise 8).
    pub brier_difference: Option<BrierDifference>,
    /// What each pane's beam and resolution menus offer in this run.
    pub choices: PaneChoices,
}

/// Which way a cell's belief leans, as the hover line says it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Leaning {
    /// Never updated: still exactly at the prior.
    Unknown,
    /// p > 0.5.
    Occupied,
    /// p < 0.5.
    Free,
    /// Updated, and its evidence has cancelled out to p = 0.5.
    Even,
}

impl Leaning {
    pub fn of(cell: &CellReadout) -> Self {
        if cell.unknown {
            Self::Unknown
        } else if cell.l > 0.0 {
            Self::Occupied
        } else if cell.l < 0.0 {
            Self::Free
        } else {
            Self::Even
        }
    }
}

/// One cell as the hover readout shows it: the pane's cell, which way it
/// leans, and the ground truth under it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CellInfo {
    #[serde(flatten)]
    pub cell: CellReadout,
    pub leaning: Leaning,
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

impl Weaver {
    /// The tracked cells of pane `pane` as the chart's legend and the map
    /// outline show them: name, world point, grid cell and image cell.
    pub fn tracked_readout(&self, pane: usize) -> Result<Vec<TrackedCell>> {
        let p = self.pane(pane)?;
        let g = &p.geometry;
        Ok(self
            .settings
            .scene
            .tracked
            .iter()
            .zip(p.tracked_cells)
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

    /// The beam counts and resolutions a pane of this run may be set to.
    pub fn choices(&self) -> PaneChoices {
        PaneChoices::for_scene(&self.settings.scene)
    }

    fn pane_readout(&self, p: &Pane) -> PaneReadout {
        let s = &p.settings;
        PaneReadout {
            model: s.model,
            pose: s.pose,
            clamp: s.clamp,
            strength: s.strength,
            mapper: s.mapper,
            sensor: s.sensor,
            beta_deg: s.beta_deg,
            beams: s.beams.unwrap_or(self.settings.scene.lidar.beams),
            resolution: p.geometry.resolution(),
            forget_l0: s.forget_l0,
            width: p.geometry.width(),
            height: p.geometry.height(),
            scan_ms: p.scan_ms.mean(),
            ghost: p.ghost.readout(
                |n| n / self.settings.scene.scan_rate,
                s.clamp,
                p.model.free_evidence(),
            ),
            l0: p.map.grid().l0(),
            model_l0: p.model.l0(),
            entropy_bits: p.map.view().entropy_bits(),
            brier: p.map.view().brier_region(),
            brier_all: p.map.view().brier_all(),
            cells_visited: p.last.cells_visited,
            cells_updated: p.last.cells_updated,
            tracked: p.tracked_cells.map(|i| p.map.grid().log_odds()[i]),
        }
    }

    pub fn readout(&self) -> Readout {
        let scans = self.history.len();
        Readout {
            scans,
            scans_per_lap: self.scans_per_lap,
            laps: self.settings.laps,
            total_scans: self.total_scans(),
            lap: (scans.saturating_sub(1) / self.scans_per_lap + 1).min(self.settings.laps),
            time: self.seconds_after(scans),
            done: self.done(),
            situation: self.settings.situation,
            person: self.sim.person(),
            frame_ms: self.frame_ms(),
            panes: [
                self.pane_readout(&self.panes[0]),
                self.pane_readout(&self.panes[1]),
            ],
            difference: self.map_difference(),
            l0_drift: self.l0_drift(),
            brier_difference: self.brier_difference(),
            choices: self.choices(),
        }
    }

    /// The cell under image column `col`, row `row` of pane `pane` (row 0
    /// at the top: the image is north up), or `None` outside the map.
    pub fn cell_info(&self, pane: usize, col: usize, row: usize) -> Result<Option<CellInfo>> {
        let p = self.pane(pane)?;
        Ok(
            readout_at_pixel(p.map.grid(), col, row).map(|cell| CellInfo {
                occupied: p.truth[p.geometry.index(cell.ix, cell.iy)],
                leaning: Leaning::of(&cell),
                cell,
            }),
        )
    }

    /// What to draw over a pane: the robot where the pane put the last scan,
    /// its beams, and the person.
    pub fn overlay(&self, pane: usize) -> Result<Overlay> {
        let p = self.pane(pane)?;
        let pose = p.pose;
        let z_max = self.settings.scene.lidar.z_max;
        let last = self.history.last();
        let g = &p.geometry;
        let bearings = self.sim.bearings();
        let stride = p.beam_stride(bearings.len());
        let mut beams = Vec::new();
        let mut hits = Vec::new();
        if let Some(scan) = last {
            for (&z, &b) in scan.ranges.iter().zip(bearings).step_by(stride) {
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

    fn cell(l: f64, unknown: bool) -> CellReadout {
        CellReadout {
            ix: 0,
            iy: 0,
            x: 0.05,
            y: 0.05,
            l,
            p: 1.0 - 1.0 / (1.0 + l.exp()),
            updates: u32::from(!unknown),
            unknown,
        }
    }

    #[test]
    fn a_cell_leans_by_the_sign_of_its_log_odds() {
        assert_eq!(Leaning::of(&cell(0.0, true)), Leaning::Unknown);
        assert_eq!(Leaning::of(&cell(0.2, false)), Leaning::Occupied);
        assert_eq!(Leaning::of(&cell(-1e-6, false)), Leaning::Free);
        assert_eq!(Leaning::of(&cell(0.0, false)), Leaning::Even);
    }
}
