//! The doorway-trap session (Table 9.1 against Table 9.3; docs/ARCHITECTURE.md,
//! "The independence trap"): the
//! doorway scene swept literally with a 22° sonar (the sweep closes the door
//! with a one-cell wall) beside the MAP search over the same readings, and
//! the door report the widget prints.

use crate::error::{invalid, Result};
use crate::grid::readout::{readout_at_cell, CellReadout};
use crate::grid::{FilterSettings, LogOddsGrid};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::io::map_server::{map_server_pair, MapServerPair};
use crate::mapping::map_search::{Flip, MapSearch, MapSearchSettings, MapSearchSetup};
use crate::mapping::sweep::sweep_scan;
use crate::mapping::traversal::ScanStats;
use crate::render::gray::render_binary_rgba;
use crate::render::overlay::{ImageCell, ImagePoint, RayMark};
use crate::scenes::doorway::DoorwayScene;
use crate::sensors::beam_model::BeamModelParams;
use crate::sensors::Scan;
use crate::world::Rect;

/// Table 9.2 for this sonar: the full 22° cone, `alpha` one cell, and
/// the chapter's 0.7 / 0.3 inverse model against the scene's prior.
pub fn inverse_model(scene: &DoorwayScene) -> Result<HandCrafted> {
    HandCrafted::new(HandCraftedParams::from_probabilities(
        0.7,
        0.3,
        scene.prior,
        2.0 * scene.resolution,
        scene.sonar.beta_deg.to_radians(),
        scene.sonar.z_max,
    )?)
}

/// The MAP search's view of the sonar: the same cone and sub-rays, the
/// chapter's forward model at this sonar's `z_max`.
pub fn search_settings(scene: &DoorwayScene) -> MapSearchSettings {
    MapSearchSettings {
        prior: scene.prior,
        half_width: scene.half_width(),
        sub_rays: scene.sonar.sub_rays,
        model: BeamModelParams {
            z_max: scene.sonar.z_max,
            ..BeamModelParams::CHAPTER
        },
    }
}

/// What the widget reports about the door, computed here so the page only
/// prints it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DoorReport {
    /// Cells of the doorway (the gap in the wall).
    pub door_cells: usize,
    /// Doorway cells the swept grid believes occupied (`p > 0.5`): all of
    /// them means the sweep has closed the door.
    pub sweep_closed: usize,
    /// Occupied MAP cells in the passage from the door to the far wall.
    pub map_in_doorway: usize,
    /// Occupied MAP cells on the far wall behind the door.
    pub map_on_far_wall: usize,
}

/// Counts what the door report says for a swept grid and a MAP map of
/// this scene's geometry.
pub fn door_report(scene: &DoorwayScene, swept: &LogOddsGrid, map: &[bool]) -> Result<DoorReport> {
    let n = scene.geometry()?.len();
    if swept.geometry().len() != n || map.len() != n {
        return Err(crate::error::OccError::LengthMismatch {
            field: "map".into(),
            expected: n,
            found: map.len().min(swept.geometry().len()),
        });
    }
    let flat =
        |r: &Rect| -> Result<Vec<usize>> { Ok(scene.cells_in(r)?.into_iter().flatten().collect()) };
    let door = flat(&scene.door)?;
    Ok(DoorReport {
        door_cells: door.len(),
        sweep_closed: door
            .iter()
            .filter(|&&i| swept.probability_at(i) > 0.5)
            .count(),
        map_in_doorway: flat(&scene.passage())?.iter().filter(|&&i| map[i]).count(),
        map_on_far_wall: flat(&scene.far_wall)?.iter().filter(|&&i| map[i]).count(),
    })
}

/// The left half of the widget: Table 9.1 swept literally over every cell,
/// one stop's scan at a time, with the scene's 22° Table 9.2 model.
#[derive(Debug, Clone)]
pub struct DoorwaySweep {
    grid: LogOddsGrid,
    model: HandCrafted,
    scans: Vec<Scan>,
    done: usize,
}

impl DoorwaySweep {
    pub fn new(scene: &DoorwayScene) -> Result<Self> {
        // Check the whole scene first, so that every error names the
        // scene's own field (the model and grid below would name theirs).
        scene.validate()?;
        // The swept grid saturates at the default clamp: a prior whose log
        // odds lie beyond it is refused here, under its own name, rather
        // than as a clamp the scene does not have.
        let clamp = FilterSettings::default().clamp;
        if crate::grid::logit(scene.prior).abs() > clamp {
            return Err(invalid(
                "prior",
                scene.prior,
                "a prior whose log odds lie within the grid's clamp of 12 (about 6e-6 to 0.999994)",
            ));
        }
        let grid = LogOddsGrid::new(
            scene.geometry()?,
            FilterSettings {
                prior: scene.prior,
                ..FilterSettings::default()
            },
        )?;
        Ok(Self {
            grid,
            model: inverse_model(scene)?,
            scans: scene.scans()?,
            done: 0,
        })
    }

    /// Sweeps the next scan over the map; `None` once every scan is in.
    pub fn step(&mut self) -> Option<ScanStats> {
        let scan = self.scans.get(self.done)?;
        let stats = sweep_scan(&mut self.grid, &self.model, scan);
        self.done += 1;
        Some(stats)
    }

    pub fn reset(&mut self) {
        self.grid.reset();
        self.done = 0;
    }

    pub fn grid(&self) -> &LogOddsGrid {
        &self.grid
    }
    /// Scans swept so far.
    pub fn scans_done(&self) -> usize {
        self.done
    }
    pub fn scan_count(&self) -> usize {
        self.scans.len()
    }
}

/// The right half of the widget: the MAP search over the scene's readings.
pub fn map_search(scene: &DoorwayScene) -> Result<MapSearch> {
    MapSearch::new(scene.geometry()?, scene.beams()?, search_settings(scene))
}

/// Saturation of the exported MAP map, log odds: far past both YAML
/// thresholds, so every decided cell exports as occupied or free.
const EXPORT_CLAMP: f64 = 12.0;

/// What one sweep step did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SweepStep {
    /// Scans swept so far.
    pub scan: usize,
    pub cells_visited: usize,
    pub cells_updated: usize,
}

/// The MAP climb as the widget shows it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MapState<'a> {
    pub flips: &'a [Flip],
    /// The objective `J` before the first flip and after each.
    pub history: &'a [f64],
    pub objective: f64,
    pub converged: bool,
    pub occupied: usize,
    pub l0: f64,
    pub beams: usize,
}

/// The door report with the sweep's progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TrapReport {
    #[serde(flatten)]
    pub door: DoorReport,
    pub scans_done: usize,
    pub scans: usize,
}

/// What the MAP map says of a cell: occupied, free, or undecided where no
/// reading's cone reached it and the climb left it free (drawn gray,
/// exported unknown): no term of Table 9.3's objective but the prior
/// depends on such a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MapCell {
    Occupied,
    Free,
    Undecided,
}

/// One cell as the hover readout shows it in both halves: the swept cell,
/// the MAP cell, its objective change if flipped, and the cones through it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DoorwayCell {
    #[serde(flatten)]
    pub cell: CellReadout,
    pub occupied: bool,
    /// The MAP map's answer for the cell, as the pane draws it.
    pub map: MapCell,
    pub sensitivity: f64,
    pub beams: usize,
}

/// The doorway trap: both halves over one scene, stepped by the widget.
pub struct DoorwayTrapSession {
    scene: DoorwayScene,
    sweep: DoorwaySweep,
    search: MapSearch,
    /// Whether any reading's cone crosses each cell (the search's
    /// incidence, fixed for the scene).
    reached: Vec<bool>,
}

/// The doorway trap being made: the scene checked and the sweep's grid
/// made at once, the MAP search set up in calls of bounded work
/// ([`MapSearchSetup`]: a fine scene's incidence and gains are a long task
/// in one call). The session is the one [`DoorwayTrapSession::new`] makes.
pub struct DoorwayTrapStart {
    scene: DoorwayScene,
    sweep: DoorwaySweep,
    setup: MapSearchSetup,
}

impl DoorwayTrapStart {
    /// Checks `scene` as the session does (the search's fields first).
    pub fn new(scene: DoorwayScene) -> Result<Self> {
        let setup =
            MapSearchSetup::new(scene.geometry()?, scene.beams()?, search_settings(&scene))?;
        Ok(Self {
            sweep: DoorwaySweep::new(&scene)?,
            setup,
            scene,
        })
    }

    /// Sets the search up for about `budget` units ([`MapSearchSetup::work`]);
    /// returns the units spent.
    pub fn work(&mut self, budget: u64) -> u64 {
        self.setup.work(budget)
    }

    pub fn done(&self) -> bool {
        self.setup.done()
    }

    /// The session, what is left of the setup done first.
    pub fn finish(self) -> Result<DoorwayTrapSession> {
        let search = self.setup.finish()?;
        let reached = (0..search.geometry().len())
            .map(|i| search.beams_through(i) > 0)
            .collect();
        Ok(DoorwayTrapSession {
            sweep: self.sweep,
            search,
            reached,
            scene: self.scene,
        })
    }
}

impl DoorwayTrapSession {
    pub fn new(scene: DoorwayScene) -> Result<Self> {
        DoorwayTrapStart::new(scene)?.finish()
    }

    /// Draws the MAP map into `out` (RGBA, north up): occupied black, free
    /// white, and mid-gray where no cone ever reached, as its export marks
    /// those cells unknown.
    pub fn map_render(&self, out: &mut Vec<u8>) -> Result<()> {
        out.resize(self.search.geometry().len() * 4, 0);
        render_binary_rgba(
            self.search.geometry(),
            self.search.occupied(),
            &self.reached,
            out,
        )
    }

    /// Cells no reading's cone crosses: what the MAP map cannot decide.
    pub fn unreached_cells(&self) -> usize {
        self.reached.iter().filter(|&&r| !r).count()
    }

    pub fn scene(&self) -> &DoorwayScene {
        &self.scene
    }
    pub fn sweep(&self) -> &DoorwaySweep {
        &self.sweep
    }
    pub fn search(&self) -> &MapSearch {
        &self.search
    }

    /// Sweeps the next scan; `None` once every scan is in.
    pub fn sweep_step(&mut self) -> Option<SweepStep> {
        let stats = self.sweep.step()?;
        Some(SweepStep {
            scan: self.sweep.scans_done(),
            cells_visited: stats.cells_visited,
            cells_updated: stats.cells_updated,
        })
    }

    pub fn sweep_reset(&mut self) {
        self.sweep.reset();
    }

    /// One steepest-ascent flip, or `None` at a local maximum.
    pub fn map_step(&mut self) -> Option<&Flip> {
        self.search.step()
    }

    pub fn map_reset(&mut self) {
        self.search.reset();
    }

    /// Runs the climb on, at most `max_flips` more flips; the flips made.
    pub fn map_run(&mut self, max_flips: usize) -> usize {
        self.search.run(max_flips)
    }

    pub fn map_state(&self) -> MapState<'_> {
        MapState {
            flips: self.search.flips(),
            history: self.search.history(),
            objective: self.search.objective(),
            converged: self.search.is_converged(),
            occupied: self.search.occupied_count(),
            l0: self.search.l0(),
            beams: self.search.beams().len(),
        }
    }

    pub fn report(&self) -> Result<TrapReport> {
        Ok(TrapReport {
            door: door_report(&self.scene, self.sweep.grid(), self.search.occupied())?,
            scans_done: self.sweep.scans_done(),
            scans: self.sweep.scan_count(),
        })
    }

    /// The hover readout of the cell under image pixel `(col, row)` (row
    /// 0 at the top).
    pub fn cell_info(&self, col: usize, row: usize) -> Result<DoorwayCell> {
        let g = *self.search.geometry();
        let (ix, iy) = g
            .image_pixel_to_cell(col, row)
            .ok_or_else(|| invalid("cell", format!("({col}, {row})"), "a cell of the map"))?;
        let i = g.index(ix, iy);
        let cell = readout_at_cell(self.sweep.grid(), ix, iy)
            .ok_or_else(|| invalid("cell", format!("({ix}, {iy})"), "a cell of the map"))?;
        let occupied = self.search.occupied()[i];
        Ok(DoorwayCell {
            cell,
            occupied,
            // As the pane draws it and the export writes it.
            map: match (occupied, self.reached[i]) {
                (true, _) => MapCell::Occupied,
                (false, true) => MapCell::Free,
                (false, false) => MapCell::Undecided,
            },
            sensitivity: self.search.sensitivity()[i],
            beams: self.search.beams_through(i),
        })
    }

    /// One half's map (`"sweep"` or `"map"`) as a ROS `map_server` pair.
    pub fn export_map(&self, which: &str) -> Result<MapServerPair> {
        let name = format!("doorway-{which}.pgm");
        match which {
            "sweep" => Ok(map_server_pair(self.sweep.grid(), &name)),
            "map" => Ok(map_server_pair(&self.search.to_grid(EXPORT_CLAMP)?, &name)),
            _ => Err(invalid(
                "map",
                format!("\"{which}\""),
                "\"sweep\" or \"map\"",
            )),
        }
    }
}

/// The doorway scene as the widget draws it over both maps, in image units
/// (see [`crate::render::overlay`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DoorwayView {
    pub width: usize,
    pub height: usize,
    /// Metres per cell.
    pub resolution: f64,
    /// Boxes as `[u0, v0, u1, v1]`.
    pub walls: Vec<[f64; 4]>,
    pub door: [f64; 4],
    pub far_wall: [f64; 4],
    /// Half the cone's opening angle, radians.
    pub half_width: f64,
    /// The cone's full opening angle, degrees (as the scene states it, for
    /// captions).
    pub beta_deg: f64,
    /// Maximum range, cells.
    pub z_max: f64,
    pub beams_per_scan: usize,
    /// Every reading, in the order of [`DoorwayScene::beams`] (the MAP
    /// search's beam indices).
    pub beams: Vec<BeamView>,
    /// Where the sonar stood for each scan.
    pub stops: Vec<ImagePoint>,
    /// The middle of the doorway's south edge, where its label goes.
    pub door_label: ImagePoint,
    /// The doorway's middle cell on that edge.
    pub door_cell: ImageCell,
}

/// One reading as the widget draws it: its cone from the sonar, and which
/// stop (scan) and which sonar of the fan it is.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct BeamView {
    pub scan: usize,
    pub sonar: usize,
    #[serde(flatten)]
    pub ray: RayMark,
}

/// The scene's overlays in image units.
pub fn view(scene: &DoorwayScene) -> Result<DoorwayView> {
    let g = scene.geometry()?;
    let image = |r: &Rect| g.box_to_image(r.min_x, r.min_y, r.max_x, r.max_y);
    let per_pose = scene.bearings_deg.len();
    let beams = scene
        .beams()?
        .iter()
        .enumerate()
        .map(|(k, b)| BeamView {
            scan: k / per_pose,
            sonar: k % per_pose,
            ray: RayMark::from_pose(&g, &b.pose, b.bearing, b.range, scene.half_width()),
        })
        .collect();
    let stops = scene
        .poses
        .iter()
        .map(|p| {
            let [x, y] = g.world_to_image(p.x, p.y);
            ImagePoint { x, y }
        })
        .collect();
    let door = image(&scene.door);
    // The label sits on the doorway's south edge, where the sonar looks
    // from; the cell is the doorway's middle one on that edge.
    let (mid_x, south_y) = (
        0.5 * (scene.door.min_x + scene.door.max_x),
        scene.door.min_y,
    );
    let [label_x, label_y] = g.world_to_image(mid_x, south_y);
    let door_cell = g
        .world_to_cell(mid_x, south_y)
        .map_or(ImageCell { col: 0, row: 0 }, |(ix, iy)| {
            ImageCell::of(&g, ix, iy)
        });
    Ok(DoorwayView {
        width: g.width(),
        height: g.height(),
        resolution: g.resolution(),
        walls: scene.walls.iter().map(image).collect(),
        door,
        far_wall: image(&scene.far_wall),
        half_width: scene.half_width(),
        beta_deg: scene.sonar.beta_deg,
        z_max: scene.sonar.z_max / g.resolution(),
        beams_per_scan: per_pose,
        beams,
        stops,
        door_label: ImagePoint {
            x: label_x,
            y: label_y,
        },
        door_cell,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Pose;
    use crate::render::gray::UNKNOWN_GRAY;

    /// The MAP pane draws the cells no cone reached gray, exactly the cells
    /// its export marks unknown (584 of 2,000 in the chapter's room).
    #[test]
    fn the_map_pane_draws_unreached_cells_as_its_export_marks_them() {
        let mut s = DoorwayTrapSession::new(DoorwayScene::standard()).unwrap();
        s.map_run(10_000);
        let mut px = Vec::new();
        s.map_render(&mut px).unwrap();
        let gray = px.chunks(4).filter(|p| p[0] == UNKNOWN_GRAY).count();
        assert_eq!(gray, s.unreached_cells());
        let pgm = s.export_map("map").unwrap();
        let unknown = pgm.pgm[pgm.pgm.len() - px.len() / 4..]
            .iter()
            .filter(|&&b| b == 205)
            .count();
        assert_eq!(gray, unknown, "the pane and its export agree");
        assert!(gray > 0, "the room has corners no cone reaches");
        // The hover readout says the same of every cell: undecided exactly
        // where the pane is gray.
        let view = view(s.scene()).unwrap();
        let mut undecided = 0;
        for row in 0..view.height {
            for col in 0..view.width {
                let c = s.cell_info(col, row).unwrap();
                let k = row * view.width + col;
                let drawn_gray = px[4 * k] == UNKNOWN_GRAY;
                assert_eq!(c.map == MapCell::Undecided, drawn_gray, "({col}, {row})");
                assert_eq!(c.map == MapCell::Occupied, c.occupied);
                if c.map == MapCell::Undecided {
                    assert_eq!(c.beams, 0);
                }
                undecided += usize::from(c.map == MapCell::Undecided);
            }
        }
        assert_eq!(undecided, s.unreached_cells());
    }

    #[test]
    fn scenes_too_large_to_step_interactively_are_refused_before_any_work() {
        // 1.5 mm cells: 8.9 million of them, accepted by the grid itself.
        let s = DoorwayScene {
            resolution: 0.0015,
            ..DoorwayScene::standard()
        };
        let e = s.validate().unwrap_err().to_string();
        assert!(
            e.contains("width x height") && e.contains("3334 x 2667") && e.contains("250000"),
            "{e}"
        );
        assert!(DoorwaySweep::new(&s).is_err() && map_search(&s).is_err());
        // The chapter's room at 1 cm (200,000 cells) is fine.
        let fine = DoorwayScene {
            resolution: 0.01,
            ..DoorwayScene::standard()
        };
        fine.validate().unwrap();
        // 4,096 readings of 1,024 sub-rays at 1 cm: the MAP search's
        // raster limit, refused by the scene before the sweep casts them.
        let mut s = fine.clone();
        s.poses = (0..64)
            .map(|k| Pose {
                x: 1.0 + 0.04 * k as f64,
                ..s.poses[0]
            })
            .collect();
        s.bearings_deg = (0..64).map(|k| -60.0 + 2.0 * k as f64).collect();
        s.sonar.sub_rays = 1024;
        let e = s.validate().unwrap_err().to_string();
        assert!(
            e.contains("poses x bearings_deg x sonar.sub_rays") && e.contains("5e7"),
            "{e}"
        );
        assert!(DoorwaySweep::new(&s).is_err());
    }
}
