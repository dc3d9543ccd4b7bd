//! The apartment of Map Weaver (docs/ARCHITECTURE.md, "The simulated world"): a 12 m × 9 m flat at 0.10 m
//! (120 × 90 = 10,800 cells), a robot driving a lap through it with a
//! 60-beam LiDAR, a person walking the corridor, and wheel odometry.
//!
//! Data flow: an [`ApartmentScene`] (plain serde data: walls and furniture
//! as boxes, named rooms, the lap, the sensor, the odometry, the person) is
//! validated and turned by [`ApartmentSim::new`] into a ground-truth
//! [`World`] and a seeded stream of [`SimScan`]s: the true pose, the
//! dead-reckoned pose and the LiDAR's ranges for every scan. The mapping
//! session ([`crate::apps::map_weaver`]) feeds those scans to the maps, and scores
//! the maps against the same ground truth.
//!
//! The floor plan, north up:
//!
//! ```text
//!  9 +---------------------------------------------------------+
//!    | study (never entered)  |##| closet  :  bedroom (never   |
//!    |                        |##|---..---   entered)          |
//!    |   __                   |##|                          __ |
//!5.6 +--+  +------------------+--+--------------------------+  +
//!    |  corridor: the lap's north leg, the person walks here   |
//!4.0 +--+  +------------------------------------------------+  +
//!    |    living room            ..     kitchen                |
//!    |   (lap's west leg)        ..  (lap's east leg)          |
//!  0 +---------------------------------------------------------+
//!    0                          6.0                            12
//! ```
//!
//! The doors of the two north rooms sit at their outer ends, right above
//! the corners where the lap turns, so the robot looks into each room only
//! along a narrow wedge: the far halves of both rooms are out of sight from
//! every pose of the lap and stay unknown. The closet opens into the
//! bedroom's far half, so no beam ever reaches it.

use super::paths::{LapPath, WalkerParams};
use crate::error::{self, invalid, Result};
use crate::geometry::GridGeometry;
use crate::geometry::Pose;
use crate::sensors::lidar::{Lidar, LidarPatch};
use crate::sensors::odometry::OdometryParams;
use crate::world::{Rect, World};
use rand::rngs::StdRng;
use rand::SeedableRng;

/// Added to the seed for the odometry's noise stream, so that the LiDAR and
/// the wheels never share random numbers (any odd constant would do).
const ODOMETRY_STREAM: u64 = 0xD1B5_4A32_D192_ED03;

/// The most scans per second a scene may ask for (a reader's attribute
/// could ask for any number).
pub const MAX_SCAN_RATE: f64 = 1000.0;
/// The fewest scans per second a scene may ask for. Slower, the run is no
/// longer a robot mapping as it drives: the page plays scans at the scene's
/// rate times its speed, so at 1e-9 scans per second the first scan after
/// the start never comes, and a lap shrinks to one scan taken at its start.
/// One a second still shows a scan every 4 s at the page's slowest speed
/// (a quarter), and the chapter's 12 a second lies well inside.
pub const MIN_SCAN_RATE: f64 = 1.0;
/// The largest apartment map, in cells (1024 x 1024): every pane keeps
/// several per-cell arrays, and a browser tab has to hold them.
pub const MAX_SCENE_CELLS: usize = 1 << 20;
/// The most boxes of each kind a scene may list (rastering the ground
/// truth visits every cell once per box).
pub const MAX_BOXES: usize = 1000;
/// The most scans one lap may take.
pub const MAX_SCANS_PER_LAP: usize = 100_000;

/// A named part of the floor plan.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Room {
    pub name: String,
    pub area: Rect,
    /// Whether the lap drives through it.
    pub entered: bool,
}

/// A cell the widget follows over time, named for the chart's legend.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TrackedPoint {
    pub name: String,
    /// A point inside the cell, metres.
    pub at: [f64; 2],
}

/// Everything that defines the simulated apartment. The default is the
/// chapter's apartment; every field can be overridden (serde default).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct ApartmentScene {
    /// Map size in cells and resolution in metres per cell; the map's
    /// lower-left corner is the world origin.
    pub width: usize,
    pub height: usize,
    pub resolution: f64,
    /// Walls and furniture: every cell whose centre lies in one of these
    /// boxes is occupied.
    pub obstacles: Vec<Rect>,
    pub rooms: Vec<Room>,
    /// The closet the robot never sees.
    pub closet: Rect,
    /// The parts of the never-entered rooms that no beam of the lap can
    /// reach (their far interiors).
    pub hidden: Vec<Rect>,
    /// The part of the map the lap surveys (corridor, the two south rooms
    /// and their walls): the region of the widget's Brier score.
    pub surveyed: Rect,
    /// The three cells of the log-odds chart: a wall cell, a corridor cell
    /// and a closet cell.
    pub tracked: [TrackedPoint; 3],
    pub path: LapPath,
    /// Scans per second.
    pub scan_rate: f64,
    /// A partial `lidar` keeps the fields it does not name from
    /// [`ApartmentScene::LIDAR`].
    #[serde(deserialize_with = "read_lidar")]
    pub lidar: Lidar,
    pub odometry: OdometryParams,
    pub person: WalkerParams,
}

impl Default for ApartmentScene {
    fn default() -> Self {
        let r = Rect::new;
        let mut obstacles = vec![
            // Outer walls, 0.2 m thick.
            r(0.0, 0.0, 12.0, 0.2),
            r(0.0, 8.8, 12.0, 9.0),
            r(0.0, 0.0, 0.2, 9.0),
            r(11.8, 0.0, 12.0, 9.0),
            // The corridor's south wall, with the doors to the living room
            // (x 0.7–1.7) and the kitchen (x 10.3–11.3).
            r(0.2, 3.9, 0.7, 4.0),
            r(1.7, 3.9, 10.3, 4.0),
            r(11.3, 3.9, 11.8, 4.0),
            // The corridor's north wall, with the doors to the study
            // (x 0.4–1.3) and the bedroom (x 10.7–11.6).
            r(0.2, 5.5, 0.4, 5.6),
            r(1.3, 5.5, 10.7, 5.6),
            r(11.6, 5.5, 11.8, 5.6),
            // Living room | kitchen, with a door at y 1.5–2.5.
            r(6.0, 0.2, 6.1, 1.5),
            r(6.0, 2.5, 6.1, 3.9),
            // Study | bedroom.
            r(5.0, 5.6, 5.1, 8.8),
            // The closet in the bedroom's north-west corner; its door
            // (x 5.5–6.2) opens into the bedroom's far half.
            r(5.1, 7.1, 5.5, 7.2),
            r(6.2, 7.1, 6.6, 7.2),
            r(6.5, 7.2, 6.6, 8.8),
        ];
        obstacles.extend([
            // Living room: a sofa against the south wall, an armchair.
            r(2.0, 0.2, 4.2, 0.9),
            r(4.6, 2.9, 5.3, 3.6),
            // Kitchen: a counter along the south wall, an island.
            r(6.6, 0.2, 9.8, 0.8),
            r(7.6, 2.7, 9.2, 3.2),
            // Study: a desk. Bedroom: a bed.
            r(3.0, 8.2, 4.6, 8.8),
            r(7.4, 7.0, 9.2, 8.8),
        ]);
        let room = |name: &str, area: Rect, entered: bool| Room {
            name: name.into(),
            area,
            entered,
        };
        Self {
            width: 120,
            height: 90,
            resolution: 0.1,
            obstacles,
            rooms: vec![
                room("corridor", r(0.2, 4.0, 11.8, 5.5), true),
                room("living room", r(0.2, 0.2, 6.0, 3.9), true),
                room("kitchen", r(6.1, 0.2, 11.8, 3.9), true),
                room("study", r(0.2, 5.6, 5.0, 8.8), false),
                room("bedroom", r(5.1, 5.6, 11.8, 8.8), false),
            ],
            closet: r(5.1, 7.2, 6.5, 8.8),
            hidden: vec![
                r(2.0, 5.6, 5.0, 8.8),
                r(5.1, 5.6, 9.6, 7.2),
                r(6.6, 7.2, 9.6, 8.8),
            ],
            surveyed: r(0.1, 0.1, 11.9, 5.6),
            tracked: [
                // Mid-corridor, one above the other: the wall north of the
                // robot's track, and the floor just below the track (clear
                // of the person's walk, so only the floor's own evidence
                // shows).
                TrackedPoint {
                    name: "corridor wall".into(),
                    at: [6.05, 5.55],
                },
                TrackedPoint {
                    name: "corridor floor".into(),
                    at: [6.05, 4.85],
                },
                TrackedPoint {
                    name: "closet".into(),
                    at: [5.85, 8.05],
                },
            ],
            // Clockwise: east along the corridor, south into the kitchen,
            // west through both south rooms, north back into the corridor.
            path: LapPath {
                waypoints: vec![[1.2, 4.95], [10.8, 4.95], [10.8, 2.0], [1.2, 2.0]],
                speed: 0.5,
                turn_rate: 1.5,
            },
            scan_rate: 12.0,
            lidar: Self::LIDAR,
            odometry: OdometryParams::WHEELS,
            person: WalkerParams {
                size: 0.5,
                from: [3.0, 4.35],
                to: [9.0, 4.35],
                speed: 0.5,
                pause: 4.0,
                phase: 0.1,
            },
        }
    }
}

/// A scene object's `lidar`, over the apartment's own.
fn read_lidar<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Lidar, D::Error> {
    Ok(<LidarPatch as serde::Deserialize>::deserialize(d)?.over(ApartmentScene::LIDAR))
}

impl ApartmentScene {
    /// The robot's LiDAR: 60 beams, the first along the heading, 8 m range,
    /// 2 cm noise.
    pub const LIDAR: Lidar = Lidar {
        beams: 60,
        z_max: 8.0,
        sigma: 0.02,
        first_bearing: 0.0,
    };

    /// The map's limits: `width × height` cells of `resolution` metres,
    /// lower-left corner at the origin.
    pub fn geometry(&self) -> Result<GridGeometry> {
        GridGeometry::new(self.width, self.height, self.resolution, 0.0, 0.0)
    }

    /// Checks every field, naming the first one that is wrong.
    pub fn validate(&self) -> Result<GridGeometry> {
        let g = self.geometry()?;
        if g.len() > MAX_SCENE_CELLS {
            return Err(invalid(
                "width x height",
                format!("{} x {}", self.width, self.height),
                "at most 1048576 cells",
            ));
        }
        for (field, n) in [
            ("obstacles", self.obstacles.len()),
            ("rooms", self.rooms.len()),
            ("hidden", self.hidden.len()),
        ] {
            if n > MAX_BOXES {
                return Err(invalid(field, n, "at most 1000 boxes"));
            }
        }
        let check_rect = |field: &str, b: &Rect| -> Result<()> {
            for (k, v) in [
                ("min_x", b.min_x),
                ("min_y", b.min_y),
                ("max_x", b.max_x),
                ("max_y", b.max_y),
            ] {
                error::finite(&format!("{field}.{k}"), v)?;
            }
            Ok(())
        };
        for (i, b) in self.obstacles.iter().enumerate() {
            check_rect(&format!("obstacles[{i}]"), b)?;
        }
        for (i, room) in self.rooms.iter().enumerate() {
            check_rect(&format!("rooms[{i}].area"), &room.area)?;
        }
        for (i, b) in self.hidden.iter().enumerate() {
            check_rect(&format!("hidden[{i}]"), b)?;
        }
        check_rect("closet", &self.closet)?;
        check_rect("surveyed", &self.surveyed)?;
        if self.cells_in(&g, &[self.surveyed]).is_empty() {
            return Err(invalid(
                "surveyed",
                format!("{:?}", self.surveyed),
                "a box holding at least one cell centre of the map",
            ));
        }
        for (i, t) in self.tracked.iter().enumerate() {
            if g.world_to_cell(t.at[0], t.at[1]).is_none() {
                return Err(invalid(
                    &format!("tracked[{i}].at"),
                    format!("({}, {})", t.at[0], t.at[1]),
                    "a point inside the map",
                ));
            }
        }
        self.path.validate()?;
        for (i, w) in self.path.waypoints.iter().enumerate() {
            if g.world_to_cell(w[0], w[1]).is_none() {
                return Err(invalid(
                    &format!("path.waypoints[{i}]"),
                    format!("({}, {})", w[0], w[1]),
                    "a waypoint inside the map",
                ));
            }
        }
        error::positive("scan_rate", self.scan_rate)?;
        if !(MIN_SCAN_RATE..=MAX_SCAN_RATE).contains(&self.scan_rate) {
            return Err(invalid(
                "scan_rate",
                error::show(self.scan_rate),
                format!("{MIN_SCAN_RATE} to {MAX_SCAN_RATE} scans per second"),
            ));
        }
        self.lidar.validate()?;
        self.odometry.validate()?;
        self.person.validate()?;
        let scans = self.path.lap_seconds() * self.scan_rate;
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(scans <= MAX_SCANS_PER_LAP as f64) {
            return Err(invalid(
                "path",
                format!("a lap of {scans:.0} scans"),
                "a lap of at most 100000 scans (a faster robot or a shorter path)",
            ));
        }
        Ok(g)
    }

    /// The ground truth: obstacles rastered onto the map.
    pub fn ground_truth(&self) -> Result<World> {
        let g = self.validate()?;
        Ok(World::from_boxes(g, &self.obstacles))
    }

    /// The same apartment (extent, boxes, lap, sensor) rastered at
    /// `resolution` metres per cell, as a pane of exercise 6 maps it: the
    /// width and height are the extent over the new cell size, rounded to
    /// whole cells. Refused when the cell size is not a positive number or
    /// the map would hold more than [`MAX_SCENE_CELLS`] cells.
    pub fn at_resolution(&self, resolution: f64) -> Result<Self> {
        error::positive("resolution", resolution)?;
        if resolution == self.resolution {
            return Ok(self.clone());
        }
        let scale = self.resolution / resolution;
        let (width, height) = (
            (self.width as f64 * scale).round(),
            (self.height as f64 * scale).round(),
        );
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(width * height <= MAX_SCENE_CELLS as f64) {
            return Err(invalid(
                "resolution",
                format!("{} ({width} x {height} cells)", error::show(resolution)),
                format!(
                    "a cell size at which the apartment fits in at most {MAX_SCENE_CELLS} cells"
                ),
            ));
        }
        Ok(Self {
            // Whole numbers of at most MAX_SCENE_CELLS: `as` is exact.
            width: width as usize,
            height: height as usize,
            resolution,
            ..self.clone()
        })
    }

    /// Indices of the cells of `g` whose centres lie in any of `boxes`, in
    /// increasing order. Only the cells under each box's bounds are looked
    /// at, so a small box (the person, once per scan and pane) costs its
    /// own cells, not the map's.
    pub fn cells_in(&self, g: &GridGeometry, boxes: &[Rect]) -> Vec<usize> {
        let mut out = Vec::new();
        for b in boxes {
            let (xs, ys) = b.cells_under(g);
            for iy in ys {
                for ix in xs.clone() {
                    let (x, y) = g.cell_center(ix, iy);
                    if b.contains(x, y) {
                        out.push(g.index(ix, iy));
                    }
                }
            }
        }
        // One box's cells come row by row, already in order; several boxes
        // may interleave and overlap.
        if boxes.len() > 1 {
            out.sort_unstable();
            out.dedup();
        }
        out
    }

    /// Indices of the three tracked cells.
    pub fn tracked_cells(&self) -> Result<[usize; 3]> {
        let g = self.geometry()?;
        let mut out = [0; 3];
        for (k, t) in self.tracked.iter().enumerate() {
            let (ix, iy) = g.world_to_cell(t.at[0], t.at[1]).ok_or_else(|| {
                invalid(
                    &format!("tracked[{k}].at"),
                    format!("({}, {})", t.at[0], t.at[1]),
                    "a point inside the map",
                )
            })?;
            out[k] = g.index(ix, iy);
        }
        Ok(out)
    }

    /// Number of scans in one lap (the last partial scan interval rounded
    /// up).
    pub fn scans_per_lap(&self) -> usize {
        (self.path.lap_seconds() * self.scan_rate).ceil().max(1.0) as usize
    }
}

/// One simulated scan: where the robot truly was, where its odometry says
/// it was, and what the LiDAR read.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimScan {
    /// 0 for the first scan of the run.
    pub index: usize,
    /// Seconds since the start.
    pub time: f64,
    /// The true pose (what the pose oracle gives).
    pub truth: Pose,
    /// The dead-reckoned pose: the start pose plus every noisy odometry
    /// increment since.
    pub odometry: Pose,
    /// One range per beam, metres, in the order of
    /// [`Lidar::bearings`].
    pub ranges: Vec<f64>,
    /// The person's footprint while they were in the world for this scan.
    pub person: Option<Rect>,
}

/// The running simulation: a validated scene, its ground truth, and the
/// seeded noise streams.
#[derive(Debug, Clone)]
pub struct ApartmentSim {
    scene: ApartmentScene,
    truth: World,
    /// The ground truth plus the person, rebuilt cell by cell for each scan
    /// in which the person is present.
    scratch: World,
    /// Cells of `scratch` the person currently covers.
    person_cells: Vec<usize>,
    bearings: Vec<f64>,
    lidar_rng: StdRng,
    odometry_rng: StdRng,
    next_index: usize,
    last_truth: Pose,
    last_odometry: Pose,
    person: bool,
}

impl ApartmentSim {
    /// A fresh run of `scene` with noise seeded by `seed`; the person walks
    /// the corridor when `person` is true.
    pub fn new(scene: ApartmentScene, seed: u64, person: bool) -> Result<Self> {
        let truth = scene.ground_truth()?;
        Self::with_truth(scene, truth, seed, person)
    }

    /// [`ApartmentSim::new`] with the scene's ground truth already drawn
    /// (a large one is drawn a band of rows per call, [`World::fill_rows`]).
    /// Refused when `truth` does not have the scene's limits.
    pub fn with_truth(
        scene: ApartmentScene,
        truth: World,
        seed: u64,
        person: bool,
    ) -> Result<Self> {
        let g = scene.validate()?;
        if *truth.geometry() != g {
            return Err(invalid(
                "truth",
                format!(
                    "{} x {} cells",
                    truth.geometry().width(),
                    truth.geometry().height()
                ),
                format!(
                    "the scene's ground truth, {} x {} cells",
                    g.width(),
                    g.height()
                ),
            ));
        }
        let start = scene.path.pose_at(0.0);
        Ok(Self {
            bearings: scene.lidar.bearings(),
            scratch: truth.clone(),
            truth,
            person_cells: Vec::new(),
            lidar_rng: StdRng::seed_from_u64(seed),
            odometry_rng: StdRng::seed_from_u64(seed ^ ODOMETRY_STREAM),
            next_index: 0,
            last_truth: start,
            last_odometry: start,
            person,
            scene,
        })
    }

    pub fn scene(&self) -> &ApartmentScene {
        &self.scene
    }
    /// The static ground truth (walls and furniture; the person is a
    /// passer-by, not part of the map).
    pub fn ground_truth(&self) -> &World {
        &self.truth
    }
    /// Bearing of every beam, radians relative to the heading.
    pub fn bearings(&self) -> &[f64] {
        &self.bearings
    }
    /// How many scans have been taken.
    pub fn scans_taken(&self) -> usize {
        self.next_index
    }
    pub fn person(&self) -> bool {
        self.person
    }
    /// Puts the person into the corridor or takes them out, from the next
    /// scan on. Their position follows the clock either way, so they
    /// reappear where they would have been.
    pub fn set_person(&mut self, on: bool) {
        self.person = on;
    }

    /// Simulates the next scan.
    pub fn next_scan(&mut self) -> SimScan {
        let index = self.next_index;
        let time = index as f64 / self.scene.scan_rate;
        let truth = self.scene.path.pose_at(time);
        let odometry = if index == 0 {
            truth
        } else {
            self.scene.odometry.dead_reckon(
                &self.last_odometry,
                &self.last_truth,
                &truth,
                &mut self.odometry_rng,
            )
        };
        let person = self.person.then(|| self.scene.person.footprint_at(time));
        self.draw_person(person);
        let mut ranges = Vec::with_capacity(self.bearings.len());
        self.scene
            .lidar
            .scan_into(&self.scratch, &truth, &mut self.lidar_rng, &mut ranges);
        self.next_index += 1;
        self.last_truth = truth;
        self.last_odometry = odometry;
        SimScan {
            index,
            time,
            truth,
            odometry,
            ranges,
            person,
        }
    }

    /// Makes `scratch` the ground truth plus the person's footprint (if
    /// any), touching only the cells the person leaves and enters.
    fn draw_person(&mut self, footprint: Option<Rect>) {
        let g = *self.truth.geometry();
        for &i in &self.person_cells {
            self.scratch.occupied_mut()[i] = self.truth.occupied()[i];
        }
        self.person_cells.clear();
        let Some(b) = footprint else { return };
        // The cells whose centres can lie in the box, clipped to the map.
        let (u0, v0) = g.world_to_grid(b.min_x, b.min_y);
        let (u1, v1) = g.world_to_grid(b.max_x, b.max_y);
        // Cell k's centre is at k + 0.5 in grid units.
        let first = |u: f64, n: usize| ((u - 0.5).ceil().max(0.0) as usize).min(n);
        for iy in first(v0, g.height())..first(v1, g.height()) {
            for ix in first(u0, g.width())..first(u1, g.width()) {
                let (x, y) = g.cell_center(ix, iy);
                if b.contains(x, y) {
                    let i = g.index(ix, iy);
                    self.scratch.occupied_mut()[i] = true;
                    self.person_cells.push(i);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every cell of the chapter's 0.10 m apartment is four cells at
    /// 0.05 m with its own truth: the boxes' edges lie on the 0.10 m grid.
    #[test]
    fn the_apartment_at_half_the_cell_size_has_four_cells_per_cell_with_its_truth() {
        let scene = ApartmentScene::default();
        let fine = scene.at_resolution(0.05).unwrap();
        assert_eq!((fine.width, fine.height, fine.resolution), (240, 180, 0.05));
        assert_eq!(fine.obstacles, scene.obstacles);
        assert_eq!(fine.path, scene.path);
        let coarse = scene.ground_truth().unwrap();
        let fine_truth = fine.ground_truth().unwrap();
        let (gc, gf) = (coarse.geometry(), fine_truth.geometry());
        for iy in 0..gf.height() {
            for ix in 0..gf.width() {
                assert_eq!(
                    fine_truth.occupied()[gf.index(ix, iy)],
                    coarse.occupied()[gc.index(ix / 2, iy / 2)],
                    "fine cell ({ix}, {iy})"
                );
            }
        }
        assert_eq!(scene.at_resolution(0.1).unwrap(), scene);
        assert_eq!(fine.at_resolution(0.1).unwrap(), scene);
    }

    #[test]
    fn a_cell_size_that_is_no_size_or_too_fine_is_refused_by_name() {
        let scene = ApartmentScene::default();
        for bad in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            let e = scene.at_resolution(bad).unwrap_err().to_string();
            assert!(e.starts_with("invalid resolution: "), "{e}");
        }
        // 0.01 m: 1200 x 900 = 1,080,000 cells, past the cap.
        let e = scene.at_resolution(0.01).unwrap_err().to_string();
        assert!(
            e.contains("0.01 (1200 x 900 cells)") && e.contains(&MAX_SCENE_CELLS.to_string()),
            "{e}"
        );
        assert!(scene.at_resolution(0.0125).unwrap().validate().is_ok());
    }

    /// `cells_in` looks only under each box, and finds what a look at every
    /// cell finds: boxes inside, across the edge, outside, overlapping,
    /// empty, with NaN or infinite bounds, on a map whose origin is not 0.
    #[test]
    fn cells_in_finds_what_a_look_at_every_cell_finds() {
        use rand::Rng;
        let every_cell = |g: &GridGeometry, boxes: &[Rect]| -> Vec<usize> {
            (0..g.len())
                .filter(|&i| {
                    let (ix, iy) = g.cell_of_index(i);
                    let (x, y) = g.cell_center(ix, iy);
                    boxes.iter().any(|b| b.contains(x, y))
                })
                .collect()
        };
        let scene = ApartmentScene::default();
        let mut rng = StdRng::seed_from_u64(7);
        let geometries = [
            scene.geometry().unwrap(),
            GridGeometry::new(50, 40, 0.2, -3.0, 1.5).unwrap(),
        ];
        for g in &geometries {
            let [ox, oy] = g.origin();
            let (w, h) = (
                g.width() as f64 * g.resolution(),
                g.height() as f64 * g.resolution(),
            );
            let mut random_box = || {
                let x = ox - 2.0 + rng.random::<f64>() * (w + 4.0);
                let y = oy - 2.0 + rng.random::<f64>() * (h + 4.0);
                Rect::new(
                    x,
                    y,
                    x + rng.random::<f64>() * 4.0,
                    y + rng.random::<f64>() * 4.0,
                )
            };
            for n in [1, 1, 1, 2, 3] {
                for _ in 0..40 {
                    let boxes: Vec<Rect> = (0..n).map(|_| random_box()).collect();
                    assert_eq!(
                        scene.cells_in(g, &boxes),
                        every_cell(g, &boxes),
                        "{boxes:?}"
                    );
                }
            }
            let odd = [
                Rect::new(f64::NAN, oy, ox + 1.0, oy + 1.0),
                Rect::new(f64::NEG_INFINITY, oy + 0.5, f64::INFINITY, oy + 0.9),
                Rect::new(ox + 1.0, oy + 1.0, ox + 1.0, oy + 2.0),
                Rect::new(ox + 3.0, oy + 3.0, ox + 1.0, oy + 1.0),
                Rect::new(ox - 9.0, oy - 9.0, ox - 5.0, oy - 5.0),
            ];
            for b in odd {
                assert_eq!(scene.cells_in(g, &[b]), every_cell(g, &[b]), "{b:?}");
            }
            assert_eq!(scene.cells_in(g, &odd), every_cell(g, &odd));
        }
        // The person's 0.5 m square covers 5 x 5 cells at 0.10 m.
        let g = scene.geometry().unwrap();
        assert_eq!(
            scene.cells_in(&g, &[Rect::new(3.0, 4.1, 3.5, 4.6)]).len(),
            25
        );
    }

    #[test]
    fn default_apartment_is_120_by_90_at_ten_centimetres() {
        let scene = ApartmentScene::default();
        let g = scene.validate().unwrap();
        assert_eq!((g.width(), g.height(), g.len()), (120, 90, 10_800));
        assert_eq!(scene.lidar.beams, 60);
        // About 12 scans a second over a lap of about a minute.
        let n = scene.scans_per_lap();
        assert!((500..800).contains(&n), "{n}");
    }

    #[test]
    fn a_partial_lidar_keeps_the_scenes_other_values() {
        let read = |json: &str| serde_json::from_str::<ApartmentScene>(json);
        let s = read(r#"{"lidar": {"sigma": 0.05}}"#).unwrap();
        assert_eq!(
            s.lidar,
            Lidar {
                sigma: 0.05,
                ..ApartmentScene::LIDAR
            }
        );
        assert_eq!(
            s,
            ApartmentScene {
                lidar: s.lidar,
                ..ApartmentScene::default()
            }
        );
        let e = read(r#"{"lidar": {"beems": 90}}"#).unwrap_err().to_string();
        assert!(e.contains("beems"), "{e}");
    }

    #[test]
    fn person_is_drawn_for_one_scan_and_erased_for_the_next() {
        let scene = ApartmentScene::default();
        let mut sim = ApartmentSim::new(scene.clone(), 1, true).unwrap();
        let truth = sim.ground_truth().occupied().to_vec();
        let s = sim.next_scan();
        let person = s.person.unwrap();
        let covered = scene.cells_in(&scene.geometry().unwrap(), &[person]);
        assert_eq!(covered.len(), 25, "a 0.5 m square covers 5 x 5 cells");
        assert!(covered.iter().all(|&i| sim.scratch.occupied()[i]));
        sim.set_person(false);
        let s = sim.next_scan();
        assert!(s.person.is_none());
        assert_eq!(
            sim.scratch.occupied(),
            &truth[..],
            "the person left no trace"
        );
    }

    #[test]
    fn bad_scene_fields_are_named() {
        let scene = ApartmentScene {
            scan_rate: 0.0,
            ..Default::default()
        };
        assert!(scene
            .validate()
            .unwrap_err()
            .to_string()
            .contains("scan_rate"));
        let mut scene = ApartmentScene::default();
        scene.obstacles[3].max_y = f64::NAN;
        assert!(scene
            .validate()
            .unwrap_err()
            .to_string()
            .contains("obstacles[3].max_y"));
        let mut scene = ApartmentScene::default();
        scene.tracked[2].at = [50.0, 1.0];
        assert!(scene
            .validate()
            .unwrap_err()
            .to_string()
            .contains("tracked[2]"));
        let scene = ApartmentScene {
            resolution: -0.1,
            ..Default::default()
        };
        assert!(ApartmentSim::new(scene, 0, false).is_err());
        let scene = ApartmentScene {
            width: 2000,
            height: 1000,
            ..Default::default()
        };
        assert!(scene
            .validate()
            .unwrap_err()
            .to_string()
            .contains("width x height"));
        let mut scene = ApartmentScene::default();
        scene.path.speed = 1e-9;
        assert!(scene.validate().unwrap_err().to_string().contains("path"));
    }

    /// A rate so slow that the page would never show a second scan (and
    /// each lap shrank to one scan at its start) is refused by its name and
    /// value, not run as "scan 0 of 3".
    #[test]
    fn a_scan_rate_below_one_a_second_is_refused_by_name_and_value() {
        for (rate, shown) in [(1e-9, "1e-9"), (0.5, "0.5")] {
            let scene = ApartmentScene {
                scan_rate: rate,
                ..Default::default()
            };
            let message = scene.validate().unwrap_err().to_string();
            assert!(
                message.contains("scan_rate") && message.contains(shown),
                "{message}"
            );
            assert!(message.contains("1 to 1000 scans per second"), "{message}");
        }
        for rate in [MIN_SCAN_RATE, 12.0, MAX_SCAN_RATE] {
            let scene = ApartmentScene {
                scan_rate: rate,
                ..Default::default()
            };
            assert!(scene.validate().is_ok(), "{rate} scans per second");
        }
    }
}
