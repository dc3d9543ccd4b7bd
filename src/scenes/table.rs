//! The table scene of docs/ARCHITECTURE.md, "Two sensors": one piece of furniture, two sensors, two
//! honest answers.
//!
//! A rectangular room holds a table. A sonar ring mounted at table height
//! sees the table *top*; a LiDAR mounted at shin height sees only the four
//! 6 cm legs and threads its beams between them. Each sensor is right about
//! its own horizontal slice of the world, so the scene carries two ground
//! truths ([`TableRun::top`] and [`TableRun::shins`]), one per slice.
//!
//! Data flow: a [`TableScene`] (plain serde data, seeded) is turned by
//! [`TableScene::build`] into a [`TableRun`]: the two slices, the robot's
//! poses along its path, and one sonar scan and one LiDAR scan per pose,
//! with Gaussian range noise. [`TableScene::start`] leaves the scans to be
//! simulated as the run reaches them, so that a page's first frame waits
//! for no scan of the lap's end.
//! [`crate::apps::sensor_fusion::TableFusion`] integrates those scans into
//! one grid per modality and compares the fusion rules.
//!
//! The two sensors draw their noise from two separate seeded streams, so
//! that changing only the LiDAR (its beam count, its noise) leaves every
//! sonar reading bit-identical: the fusion tests rely on that to change one
//! thing at a time.

use crate::error::{self, invalid, Result};
use crate::geometry::GridGeometry;
use crate::geometry::Pose;
use crate::sensors::lidar::{Lidar, LidarPatch};
use crate::sensors::sonar::{Sonar, SonarPatch};
use crate::sensors::Scan;
use crate::world::{Rect, World};
use rand::rngs::StdRng;
use rand::SeedableRng;
use std::f64::consts::{PI, TAU};

/// Side of a table leg's square cross-section, metres (docs/ARCHITECTURE.md, "Two sensors": "four 6 cm
/// legs").
pub const LEG_SIZE: f64 = 0.06;

/// Upper bounds that keep a scene from asking for absurd work or memory
/// (an instructor's attribute can set any of these).
pub const MAX_STEPS: usize = 20_000;
pub const MAX_LIDAR_BEAMS: usize = 2_048;
pub const MAX_SONARS: usize = 256;
pub const MAX_SONAR_SUB_RAYS: usize = 256;

/// Each bound above is harmless alone; together they are not (20,000 steps
/// of 256 sonars of 256 sub-rays is minutes of casting). The products are
/// bounded too, at multiples of the chapter's scene (81 steps, 16 sonars of
/// 25 sub-rays, 360 LiDAR beams, 12,000 cells), so that building a scene
/// or rebuilding its maps stays within about a second natively.
///
/// Cells of the map: about 20 times the chapter's (its room at 1.2 cm).
/// Every step sweeps every cell twice (Table 9.1 for the sonar's cone).
pub const MAX_SCENE_CELLS: usize = super::MAX_WIDGET_SCENE_CELLS;
/// Sonar sub-rays cast over the run (steps x sonars x sub-rays): about 60
/// times the chapter's 32,400.
pub const MAX_SONAR_RAYS: usize = 2_000_000;
/// LiDAR beams cast over the run (steps x beams): about 70 times the
/// chapter's 29,160, and 12 laps at the slider's 2,048 beams.
pub const MAX_LIDAR_RAYS: usize = 2_000_000;
/// Cells swept over the run (steps x cells): about 25 times the chapter's
/// 972,000. Changing the LiDAR's beam count re-sweeps up to this many.
pub const MAX_SWEEP_CELLS: usize = 25_000_000;

/// Added to the seed of the LiDAR's noise stream, so that the two sensors
/// never share random numbers (any odd constant would do; this is the
/// 64-bit golden-ratio constant).
const LIDAR_STREAM: u64 = 0x9E37_79B9_7F4A_7C15;

/// The table: its top (the sonar's slice) and its legs (the LiDAR's).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct TableSpec {
    /// Centre of the top, metres.
    pub center: [f64; 2],
    /// Extent of the top along x and y, metres.
    pub size: [f64; 2],
    /// Side of each leg's square cross-section, metres.
    pub leg: f64,
    /// Distance from each edge of the top to the nearest face of a leg,
    /// metres.
    pub leg_inset: f64,
}

impl Default for TableSpec {
    fn default() -> Self {
        Self {
            center: [3.0, 2.5],
            size: [1.2, 0.8],
            leg: LEG_SIZE,
            leg_inset: 0.05,
        }
    }
}

impl TableSpec {
    /// The table top's footprint in the world.
    pub fn top(&self) -> Rect {
        let [cx, cy] = self.center;
        let [w, h] = self.size;
        Rect::new(cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h)
    }

    /// The four legs' cross-sections, south-west first, counter-clockwise.
    pub fn legs(&self) -> [Rect; 4] {
        let t = self.top();
        let (a, s) = (self.leg_inset, self.leg);
        let (x0, x1) = (t.min_x + a, t.max_x - a - s);
        let (y0, y1) = (t.min_y + a, t.max_y - a - s);
        [(x0, y0), (x1, y0), (x1, y1), (x0, y1)].map(|(x, y)| Rect::new(x, y, x + s, y + s))
    }
}

/// The whole scene as data: room, table, the robot's path, both sensors and
/// the seed. The same scene gives the same scans, bit for bit.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct TableScene {
    /// Outer size of the room along x and y, metres; the map covers exactly
    /// this, with the walls along its border.
    pub room: [f64; 2],
    /// Wall thickness, metres.
    pub wall: f64,
    /// Map resolution, metres per cell. It must resolve a 6 cm leg.
    pub resolution: f64,
    pub table: TableSpec,
    /// The robot's path: a closed loop through these points (metres),
    /// driven at constant speed, heading along the direction of travel.
    pub path: Vec<[f64; 2]>,
    /// Distance driven between two scans, metres.
    pub step: f64,
    /// How many times the loop is driven.
    pub laps: usize,
    /// The ring at table height. A partial `sonar` keeps the fields it does
    /// not name from [`TableScene::SONAR`].
    #[serde(deserialize_with = "read_sonar")]
    pub sonar: Sonar,
    /// The LiDAR at shin height. A partial `lidar` keeps the fields it does
    /// not name from [`TableScene::LIDAR`].
    #[serde(deserialize_with = "read_lidar")]
    pub lidar: Lidar,
    pub seed: u64,
}

impl Default for TableScene {
    /// The chapter's scene: a 6 m × 5 m room at 5 cm (12,000 cells), a
    /// 1.2 m × 0.8 m table in the middle, and one lap (81 scans, one every
    /// 10 cm) on an ellipse that keeps the robot 0.7–0.85 m from the
    /// table's edges.
    fn default() -> Self {
        let table = TableSpec::default();
        let [cx, cy] = table.center;
        let path = (0..24)
            .map(|k| {
                let a = TAU * k as f64 / 24.0;
                [cx + 1.45 * a.cos(), cy + 1.1 * a.sin()]
            })
            .collect();
        Self {
            room: [6.0, 5.0],
            wall: 0.1,
            resolution: 0.05,
            table,
            path,
            step: 0.1,
            laps: 1,
            sonar: Self::SONAR,
            lidar: Self::LIDAR,
            seed: 7,
        }
    }
}

/// A scene object's `sonar`, over the table scene's own.
fn read_sonar<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Sonar, D::Error> {
    Ok(<SonarPatch as serde::Deserialize>::deserialize(d)?.over(TableScene::SONAR))
}

/// A scene object's `lidar`, over the table scene's own.
fn read_lidar<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Lidar, D::Error> {
    Ok(<LidarPatch as serde::Deserialize>::deserialize(d)?.over(TableScene::LIDAR))
}

impl TableScene {
    /// Sixteen transducers 22.5° apart, each with a 25° cone (so that
    /// neighbouring cones overlap and every bearing is covered), 5 m range,
    /// 3 cm noise: a Pioneer-style ring.
    pub const SONAR: Sonar = Sonar {
        count: 16,
        beta_deg: 25.0,
        z_max: 5.0,
        sigma: 0.03,
        sub_rays: 25,
    };

    /// 360 beams (one per degree, the first straight behind the robot),
    /// 8 m range, 1 cm noise.
    pub const LIDAR: Lidar = Lidar {
        beams: 360,
        z_max: 8.0,
        sigma: 0.01,
        first_bearing: -PI,
    };

    /// The same scene with a LiDAR of `beams` beams and nothing else changed.
    pub fn with_lidar_beams(&self, beams: usize) -> Result<Self> {
        let mut s = self.clone();
        s.lidar.beams = beams;
        s.validate()?;
        Ok(s)
    }

    /// The map's limits: the room, origin at its south-west corner.
    pub fn geometry(&self) -> Result<GridGeometry> {
        error::positive("room[0]", self.room[0])?;
        error::positive("room[1]", self.room[1])?;
        GridGeometry::covering(0.0, 0.0, self.room[0], self.room[1], self.resolution)
    }

    /// Checks everything [`TableScene::build`] relies on.
    pub fn validate(&self) -> Result<()> {
        let g = self.geometry()?;
        super::check_scene_cells(&g)?;
        error::positive("wall", self.wall)?;
        let [rw, rh] = self.room;
        if 2.0 * self.wall >= rw.min(rh) {
            return Err(invalid("wall", self.wall, "less than half the room's size"));
        }
        // A cell much wider than a leg turns a 6 cm leg into a block, and
        // the gaps the LiDAR threads between the legs close up.
        if self.resolution > 2.0 * self.table.leg {
            return Err(invalid(
                "resolution",
                self.resolution,
                "at most twice the leg size, so that the legs stay thin on the map",
            ));
        }
        let t = &self.table;
        error::finite("table.center[0]", t.center[0])?;
        error::finite("table.center[1]", t.center[1])?;
        error::positive("table.size[0]", t.size[0])?;
        error::positive("table.size[1]", t.size[1])?;
        error::positive("table.leg", t.leg)?;
        error::non_negative("table.leg_inset", t.leg_inset)?;
        if 2.0 * (t.leg_inset + t.leg) > t.size[0].min(t.size[1]) {
            return Err(invalid(
                "table.leg_inset",
                t.leg_inset,
                "small enough for four legs to fit under the top",
            ));
        }
        let inner = self.interior();
        let top = t.top();
        if !(top.min_x >= inner.min_x
            && top.min_y >= inner.min_y
            && top.max_x <= inner.max_x
            && top.max_y <= inner.max_y)
        {
            return Err(invalid(
                "table.center",
                format!("[{}, {}]", t.center[0], t.center[1]),
                "a table that fits inside the room's walls",
            ));
        }

        if self.path.len() < 2 {
            return Err(invalid("path", self.path.len(), "at least 2 points"));
        }
        // The sensors sit on the robot: it must stand in free space of both
        // slices, so inside the walls and not under the table.
        let stands_free = |x: f64, y: f64| inner.contains(x, y) && !top.contains(x, y);
        for (i, &[x, y]) in self.path.iter().enumerate() {
            error::finite(&format!("path[{i}][0]"), x)?;
            error::finite(&format!("path[{i}][1]"), y)?;
            if !stands_free(x, y) {
                return Err(invalid(
                    &format!("path[{i}]"),
                    format!("[{x}, {y}]"),
                    "a point inside the room and outside the table",
                ));
            }
        }
        // Every point is finite and inside the room, so the length is too.
        if self.perimeter() <= 0.0 {
            return Err(invalid("path", "a loop of length 0", "distinct points"));
        }
        error::positive("step", self.step)?;
        if self.laps == 0 {
            return Err(invalid("laps", 0, "at least 1"));
        }
        let steps = (self.perimeter() / self.step).ceil() * self.laps as f64;
        // A tiny step can make this infinite, never NaN.
        if steps > MAX_STEPS as f64 {
            return Err(invalid(
                "step",
                self.step,
                "a step long enough for at most 20000 scans",
            ));
        }

        // Corners of the loop can cut through the table: check where the
        // robot actually drives.
        if let Some(p) = self.poses().iter().find(|p| !stands_free(p.x, p.y)) {
            return Err(invalid(
                "path",
                format!("a loop through [{:.2}, {:.2}]", p.x, p.y),
                "a loop that stays inside the room and outside the table",
            ));
        }

        // The scene's own budgets first, then the sensors' ranges.
        let s = &self.sonar;
        if s.count == 0 || s.count > MAX_SONARS {
            return Err(invalid("sonar.count", s.count, "1 to 256 transducers"));
        }
        if s.sub_rays == 0 || s.sub_rays > MAX_SONAR_SUB_RAYS {
            return Err(invalid("sonar.sub_rays", s.sub_rays, "1 to 256 rays"));
        }
        s.validate()?;
        let l = &self.lidar;
        if l.beams == 0 || l.beams > MAX_LIDAR_BEAMS {
            return Err(invalid("lidar.beams", l.beams, "1 to 2048 beams"));
        }
        l.validate()?;
        self.check_work(steps as usize, g.len())
    }

    /// The bounds on the run's total work (see [`MAX_SONAR_RAYS`]), once
    /// each factor is known to be within its own bound. In 64 bits: on
    /// wasm32, 20,000 steps x 250,000 cells is past `usize`, while no
    /// product of the bounded factors comes near `u64::MAX`.
    fn check_work(&self, steps: usize, cells: usize) -> Result<()> {
        let (s, l) = (&self.sonar, &self.lidar);
        let [steps, cells, count, sub_rays, beams] =
            [steps, cells, s.count, s.sub_rays, l.beams].map(|n| n as u64);
        let sonar_rays = steps * count * sub_rays;
        if sonar_rays > MAX_SONAR_RAYS as u64 {
            return Err(invalid(
                "steps x sonar.count x sonar.sub_rays",
                format!("{steps} x {count} x {sub_rays} = {sonar_rays}"),
                "at most 2000000 sonar sub-rays per run: fewer laps, a longer step, fewer sonars or sub-rays",
            ));
        }
        let lidar_rays = steps * beams;
        if lidar_rays > MAX_LIDAR_RAYS as u64 {
            return Err(invalid(
                "steps x lidar.beams",
                format!("{steps} x {beams} = {lidar_rays}"),
                "at most 2000000 LiDAR beams per run: fewer laps, a longer step or fewer beams",
            ));
        }
        let swept = steps * cells;
        if swept > MAX_SWEEP_CELLS as u64 {
            return Err(invalid(
                "steps x width x height",
                format!("{steps} x {cells} = {swept}"),
                "at most 25000000 cells swept per run: fewer laps, a longer step, a coarser resolution or a smaller room",
            ));
        }
        Ok(())
    }

    /// The free interior of the room, inside the walls.
    fn interior(&self) -> Rect {
        let w = self.wall;
        Rect::new(w, w, self.room[0] - w, self.room[1] - w)
    }

    /// Length of the closed path, metres.
    fn perimeter(&self) -> f64 {
        self.segments()
            .map(|(a, b)| (b[0] - a[0]).hypot(b[1] - a[1]))
            .sum()
    }

    /// The path's segments, closing the loop.
    fn segments(&self) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
        let n = self.path.len();
        (0..n).map(move |i| (self.path[i], self.path[(i + 1) % n]))
    }

    /// One pose every `step` metres along the loop, `laps` times round.
    fn poses(&self) -> Vec<Pose> {
        let segs: Vec<([f64; 2], [f64; 2], f64)> = self
            .segments()
            .map(|(a, b)| (a, b, (b[0] - a[0]).hypot(b[1] - a[1])))
            .filter(|s| s.2 > 0.0)
            .collect();
        let per_lap = (self.perimeter() / self.step).ceil() as usize;
        let mut poses = Vec::with_capacity(per_lap * self.laps);
        for _ in 0..self.laps {
            let (mut seg, mut start) = (0, 0.0);
            for k in 0..per_lap {
                let s = k as f64 * self.step;
                while seg + 1 < segs.len() && s >= start + segs[seg].2 {
                    start += segs[seg].2;
                    seg += 1;
                }
                let (a, b, len) = segs[seg];
                let f = ((s - start) / len).clamp(0.0, 1.0);
                poses.push(Pose {
                    x: a[0] + f * (b[0] - a[0]),
                    y: a[1] + f * (b[1] - a[1]),
                    theta: (b[1] - a[1]).atan2(b[0] - a[0]),
                });
            }
        }
        poses
    }

    /// The two ground-truth slices: walls and table top (what a sensor at
    /// table height faces), walls and legs (what a sensor at shin height
    /// faces).
    fn slices(&self, g: GridGeometry) -> (World, World) {
        let [rw, rh] = self.room;
        let w = self.wall;
        let walls = [
            Rect::new(0.0, 0.0, rw, w),
            Rect::new(0.0, rh - w, rw, rh),
            Rect::new(0.0, 0.0, w, rh),
            Rect::new(rw - w, 0.0, rw, rh),
        ];
        let mut top = World::from_boxes(g, &walls);
        top.fill(&self.table.top(), true);
        let mut shins = World::from_boxes(g, &walls);
        for leg in self.table.legs() {
            shins.fill(&leg, true);
            // A leg between cell centres still stands somewhere: mark the
            // cell holding its centre, so a 6 cm leg is never lost to the
            // raster.
            let (x, y) = (0.5 * (leg.min_x + leg.max_x), 0.5 * (leg.min_y + leg.max_y));
            if let Some((ix, iy)) = g.world_to_cell(x, y) {
                let i = g.index(ix, iy);
                if let Some(c) = shins.occupied_mut().get_mut(i) {
                    *c = true;
                }
            }
        }
        (top, shins)
    }

    /// Builds the scene: both slices, the poses, and one noisy sonar scan
    /// and one noisy LiDAR scan per pose, all simulated at once.
    pub fn build(&self) -> Result<TableRun> {
        let mut run = self.start()?;
        run.simulate_through(run.len())?;
        Ok(run)
    }

    /// Builds the scene without its scans: the slices, the poses and the
    /// footprint, which take time in proportion to the map; each scan is
    /// simulated when the run first needs it ([`TableRun::simulate_through`]),
    /// from the same noise streams in the same order, so the scans are those
    /// of [`TableScene::build`] bit for bit.
    pub fn start(&self) -> Result<TableRun> {
        self.validate()?;
        let geometry = self.geometry()?;
        let (top, shins) = self.slices(geometry);
        let poses = self.poses();
        let table = self.table.top();
        let footprint = (0..geometry.len())
            .filter(|&i| {
                let (ix, iy) = geometry.cell_of_index(i);
                let (x, y) = geometry.cell_center(ix, iy);
                table.contains(x, y)
            })
            .collect();
        Ok(TableRun {
            scene: self.clone(),
            geometry,
            top,
            shins,
            footprint,
            poses,
            sonar: Vec::new(),
            lidar: Vec::new(),
            sonar_noise: StdRng::seed_from_u64(self.seed),
            lidar_noise: self.lidar_noise(),
        })
    }

    /// The LiDAR's own noise stream, from its first draw.
    fn lidar_noise(&self) -> StdRng {
        StdRng::seed_from_u64(self.seed.wrapping_add(LIDAR_STREAM))
    }

    /// The sonar ring's scan from `p`: each cone reads the nearest echo
    /// inside it (the table top's near edge, or a wall), plus noise.
    fn sonar_scan(&self, top: &World, p: &Pose, rng: &mut StdRng) -> Result<Scan> {
        let s = self.sonar;
        let spacing = s.spacing();
        let ranges = (0..s.count)
            .map(|j| s.read(top, p.x, p.y, p.theta + j as f64 * spacing, rng))
            .collect::<Result<Vec<f64>>>()?;
        Scan::uniform(*p, ranges, 0.0, spacing)
    }

    /// The LiDAR's scan from `p`: thin beams, the exact range to the first
    /// occupied cell of the shin slice, plus noise.
    fn lidar_scan(&self, shins: &World, p: &Pose, rng: &mut StdRng) -> Result<Scan> {
        let l = self.lidar;
        let mut ranges = Vec::with_capacity(l.beams);
        l.scan_into(shins, p, rng, &mut ranges);
        Scan::uniform(*p, ranges, l.first_bearing, l.spacing())
    }

    /// What simulating one scan on `g` costs, in the cell visits a
    /// mapper's work is counted in: every ray cast (a sonar cone's
    /// sub-rays, a LiDAR beam) counted as the most cells its walk can
    /// cross, those along its whole range but no more than the map's width
    /// and height together (a walk leaves the map after those).
    fn scan_cost(&self, g: &GridGeometry, lidar: bool) -> u64 {
        let across = (g.width() + g.height()) as f64;
        let cells = |z_max: f64| (z_max / self.resolution).ceil().clamp(1.0, across) as u64;
        let (rays, z_max) = if lidar {
            (self.lidar.beams, self.lidar.z_max)
        } else {
            (
                self.sonar.count.saturating_mul(self.sonar.sub_rays),
                self.sonar.z_max,
            )
        };
        (rays as u64).saturating_mul(cells(z_max))
    }
}

/// A built table scene: ground truth per slice, the poses, and the scans
/// simulated so far (all of them from [`TableScene::build`], none yet from
/// [`TableScene::start`]) with each sensor's noise stream where it stopped.
#[derive(Debug, Clone, PartialEq)]
pub struct TableRun {
    scene: TableScene,
    geometry: GridGeometry,
    top: World,
    shins: World,
    footprint: Vec<usize>,
    poses: Vec<Pose>,
    sonar: Vec<Scan>,
    lidar: Vec<Scan>,
    sonar_noise: StdRng,
    lidar_noise: StdRng,
}

impl TableRun {
    pub fn scene(&self) -> &TableScene {
        &self.scene
    }
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    /// Ground truth at table height: walls and the table top.
    pub fn top(&self) -> &World {
        &self.top
    }
    /// Ground truth at shin height: walls and the four legs.
    pub fn shins(&self) -> &World {
        &self.shins
    }
    /// The cells whose centres lie under the table top (row-major indices).
    pub fn footprint(&self) -> &[usize] {
        &self.footprint
    }
    pub fn poses(&self) -> &[Pose] {
        &self.poses
    }
    /// The sonar scans simulated so far, one per pose from the first.
    pub fn sonar(&self) -> &[Scan] {
        &self.sonar
    }
    /// The LiDAR scans simulated so far, one per pose from the first.
    pub fn lidar(&self) -> &[Scan] {
        &self.lidar
    }
    /// Poses whose two scans are both simulated.
    pub fn simulated(&self) -> usize {
        self.sonar.len().min(self.lidar.len())
    }

    /// Simulates every scan not yet simulated of the first `steps` poses
    /// (at most the run's) and returns their cost in cell visits. Each
    /// sensor draws from its own noise stream in pose order, so a scan is
    /// the same whenever it is simulated.
    pub fn simulate_through(&mut self, steps: usize) -> Result<u64> {
        let sonar = self.simulate_sensor_through(steps, false)?;
        Ok(sonar.saturating_add(self.simulate_sensor_through(steps, true)?))
    }

    /// [`TableRun::simulate_through`] for the LiDAR's scans (`lidar`) or the
    /// sonar's: independent streams, so a step may simulate them apart.
    pub fn simulate_sensor_through(&mut self, steps: usize, lidar: bool) -> Result<u64> {
        let steps = steps.min(self.poses.len());
        let (scans, world, rng) = if lidar {
            (&mut self.lidar, &self.shins, &mut self.lidar_noise)
        } else {
            (&mut self.sonar, &self.top, &mut self.sonar_noise)
        };
        let from = scans.len();
        for p in self.poses.get(from..steps).unwrap_or_default() {
            let scan = if lidar {
                self.scene.lidar_scan(world, p, rng)
            } else {
                self.scene.sonar_scan(world, p, rng)
            };
            scans.push(scan?);
        }
        let cost = self.scene.scan_cost(&self.geometry, lidar);
        Ok(cost.saturating_mul(steps.saturating_sub(from) as u64))
    }

    /// The same run with a LiDAR of `beams` beams: only the LiDAR's scans
    /// are simulated again, as many as this run had (from the LiDAR's own
    /// noise stream, so exactly as [`TableScene::build`] would); slices,
    /// poses and sonar scans are kept.
    pub fn with_lidar_beams(&self, beams: usize) -> Result<TableRun> {
        let mut run = self.clone();
        run.restart_lidar(beams)?;
        run.simulate_through(self.lidar.len())?;
        Ok(run)
    }

    /// A LiDAR of `beams` beams from the first pose on: its scans so far
    /// are dropped, to be simulated again as the run reaches them, from the
    /// start of its noise stream. Slices, poses and sonar scans are kept.
    /// On error (a refused beam count) nothing changes.
    pub fn restart_lidar(&mut self, beams: usize) -> Result<()> {
        self.scene = self.scene.with_lidar_beams(beams)?;
        self.lidar.clear();
        self.lidar_noise = self.scene.lidar_noise();
        Ok(())
    }

    /// Number of time steps (poses) in the run.
    pub fn len(&self) -> usize {
        self.poses.len()
    }
    pub fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_two_slices_disagree_only_under_the_table() {
        let run = TableScene::default().build().unwrap();
        let (top, shins) = (run.top().occupied(), run.shins().occupied());
        let footprint: std::collections::HashSet<usize> = run.footprint().iter().copied().collect();
        for i in 0..top.len() {
            if !footprint.contains(&i) {
                assert_eq!(top[i], shins[i], "cell {i} outside the table");
            }
        }
        // 1.2 m x 0.8 m at 5 cm: 24 x 16 cells, all occupied at table height.
        assert_eq!(run.footprint().len(), 384);
        assert!(run.footprint().iter().all(|&i| top[i]));
        // At shin height only the legs: four 6 cm legs, one or two cells
        // each way at 5 cm.
        let legs = run.footprint().iter().filter(|&&i| shins[i]).count();
        assert!((4..=16).contains(&legs), "{legs} leg cells");
    }

    #[test]
    fn lidar_threads_between_the_legs_where_the_sonar_stops_at_the_top() {
        let run = TableScene::default().build().unwrap();
        let table = run.scene().table.top();
        // A reading "passes under" the table when a point of the beam short
        // of its end lies under the top while the end lies beyond it.
        let passes_under = |p: Pose, z: f64, b: f64| {
            let (x, y) = p.point_at(z, b);
            !table.contains(x, y)
                && (1..40).any(|k| {
                    let (mx, my) = p.point_at(z * k as f64 / 40.0, b);
                    table.contains(mx, my)
                })
        };
        let count = |scans: &[Scan]| -> usize {
            scans
                .iter()
                .map(|s| {
                    let p = s.pose();
                    s.ranges()
                        .iter()
                        .zip(s.bearings())
                        .filter(|&(&z, &b)| passes_under(p, z, b))
                        .count()
                })
                .sum()
        };
        let lidar = count(run.lidar());
        assert!(lidar > 1000, "{lidar} LiDAR beams passed under the table");
        // The sonar's cone axis may graze a corner of the top by noise, but
        // its echo comes from the top: almost none of its readings go past.
        let sonar = count(run.sonar());
        let sonar_total: usize = run.sonar().iter().map(Scan::len).sum();
        assert!(sonar * 100 < sonar_total, "{sonar} of {sonar_total}");
    }

    #[test]
    fn same_seed_same_scans_and_lidar_changes_leave_the_sonar_alone() {
        let a = TableScene::default().build().unwrap();
        let b = TableScene::default().build().unwrap();
        assert_eq!(a, b);
        let c = TableScene::default()
            .with_lidar_beams(45)
            .unwrap()
            .build()
            .unwrap();
        assert_eq!(a.sonar(), c.sonar(), "sonar readings unchanged");
        assert_eq!(c.lidar()[0].len(), 45);
        assert_eq!(
            a.with_lidar_beams(45).unwrap(),
            c,
            "rebuilding only the LiDAR"
        );
        let d = TableScene {
            seed: 8,
            ..TableScene::default()
        }
        .build()
        .unwrap();
        assert_ne!(a.sonar(), d.sonar());
    }

    #[test]
    fn a_partial_sensor_keeps_the_scenes_other_values_and_beta_is_refused() {
        let read = |json: &str| serde_json::from_str::<TableScene>(json);
        let s = read(r#"{"sonar": {"z_max": 3}, "lidar": {"beams": 90}}"#).unwrap();
        assert_eq!(
            s.sonar,
            Sonar {
                z_max: 3.0,
                ..TableScene::SONAR
            }
        );
        assert_eq!(
            s.lidar,
            Lidar {
                beams: 90,
                ..TableScene::LIDAR
            }
        );
        assert_eq!(read("{}").unwrap(), TableScene::default());
        // The old `beta` was radians: read as degrees it would shrink the
        // cone 57-fold without a word, so it is refused by name.
        let e = read(r#"{"sonar": {"beta": 0.44}}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`beta`") && e.contains("beta_deg"), "{e}");
    }

    /// The scans as the scene computed them before it held the shared
    /// sensor types (its own cone and beam loops, the beam's world angle as
    /// `theta - pi + j * spacing`, readings clamped to `[0, z_max]`): the
    /// shared types give every default reading bit for bit.
    #[test]
    fn default_scans_are_those_of_the_scenes_former_loops_bit_for_bit() {
        use crate::sensors::noise::standard_normal;
        let scene = TableScene::default();
        let run = scene.build().unwrap();
        let noisy = |z: f64, z_max: f64, sigma: f64, rng: &mut StdRng| {
            let n = standard_normal(rng);
            if z >= z_max {
                z_max
            } else {
                (z + sigma * n).clamp(0.0, z_max)
            }
        };
        let (s, l) = (scene.sonar, scene.lidar);
        let mut rng = StdRng::seed_from_u64(scene.seed);
        let spacing = TAU / s.count as f64;
        let beta = 25f64.to_radians();
        for (scan, p) in run.sonar().iter().zip(run.poses()) {
            for (j, &got) in scan.ranges().iter().enumerate() {
                let a = p.theta + j as f64 * spacing;
                let z = run
                    .top()
                    .cast_cone(p.x, p.y, a, 0.5 * beta, s.sub_rays, s.z_max)
                    .unwrap();
                assert_eq!(
                    got.to_bits(),
                    noisy(z, s.z_max, s.sigma, &mut rng).to_bits()
                );
            }
        }
        let mut rng = StdRng::seed_from_u64(scene.seed.wrapping_add(LIDAR_STREAM));
        let spacing = TAU / l.beams as f64;
        for (scan, p) in run.lidar().iter().zip(run.poses()) {
            for (j, (&got, &b)) in scan.ranges().iter().zip(scan.bearings()).enumerate() {
                let z = run
                    .shins()
                    .cast(p.x, p.y, p.theta - PI + j as f64 * spacing, l.z_max);
                assert_eq!(
                    got.to_bits(),
                    noisy(z, l.z_max, l.sigma, &mut rng).to_bits()
                );
                assert_eq!(b.to_bits(), (-PI + j as f64 * spacing).to_bits());
            }
        }
    }

    #[test]
    fn rejects_bad_scenes_naming_the_field() {
        let e = |s: TableScene| s.build().unwrap_err().to_string();
        let d = TableScene::default;
        assert!(e(TableScene {
            resolution: 0.2,
            ..d()
        })
        .contains("resolution"));
        assert!(e(TableScene { step: 0.0, ..d() }).contains("step"));
        assert!(e(TableScene { step: 1e-9, ..d() }).contains("step"));
        let under_table = TableScene {
            path: vec![[3.0, 2.5], [1.0, 1.0]],
            ..d()
        };
        assert!(e(under_table).contains("path[0]"));
        assert!(d()
            .with_lidar_beams(0)
            .unwrap_err()
            .to_string()
            .contains("lidar.beams"));
        let mut s = d();
        s.sonar.beta_deg = f64::NAN;
        assert!(e(s).contains("sonar.beta_deg"));
        let mut s = d();
        s.table.center = [0.2, 0.2];
        assert!(e(s).contains("table.center"));
        assert!(e(TableScene {
            room: [f64::INFINITY, 5.0],
            ..d()
        })
        .contains("room[0]"));
    }

    #[test]
    fn work_past_the_run_limits_is_refused_naming_the_factors_and_the_limit() {
        let e = |s: TableScene| s.validate().unwrap_err().to_string();
        let d = TableScene::default;
        // About 20,000 steps (a 0.41 mm step) and every other count at its
        // own maximum: minutes of casting before.
        let mut s = TableScene {
            step: 0.00041,
            ..d()
        };
        s.sonar.count = MAX_SONARS;
        s.sonar.sub_rays = MAX_SONAR_SUB_RAYS;
        s.lidar.beams = MAX_LIDAR_BEAMS;
        let text = e(s);
        assert!(
            text.contains("steps x sonar.count x sonar.sub_rays") && text.contains("2000000"),
            "{text}"
        );
        // 25 laps (2,025 steps) of the chapter's scene pass every bound;
        // 2,048 LiDAR beams on them do not.
        let mut s = TableScene { laps: 25, ..d() };
        s.validate().unwrap();
        s.lidar.beams = MAX_LIDAR_BEAMS;
        let text = e(s);
        assert!(
            text.contains("steps x lidar.beams") && text.contains("2000000"),
            "{text}"
        );
        // 1 cm cells: 300,000 of them.
        let text = e(TableScene {
            resolution: 0.01,
            ..d()
        });
        assert!(
            text.contains("width x height")
                && text.contains("600 x 500")
                && text.contains("250000"),
            "{text}"
        );
        // 2.5 cm cells (48,000) over 7 laps: 27 million cells swept.
        let text = e(TableScene {
            resolution: 0.025,
            laps: 7,
            ..d()
        });
        assert!(
            text.contains("steps x width x height") && text.contains("25000000"),
            "{text}"
        );
        // The slider's whole range stays open on the chapter's lap.
        for beams in [1, 360, MAX_LIDAR_BEAMS] {
            d().with_lidar_beams(beams).unwrap();
        }
        TableScene {
            resolution: 0.025,
            laps: 5,
            ..d()
        }
        .validate()
        .unwrap();
    }
}
