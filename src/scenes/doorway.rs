//! The doorway scene (docs/ARCHITECTURE.md, "The simulated world"): the chapter's picture of how a wide sonar
//! cone closes an open door in an occupancy grid.
//!
//! A room's north wall has an open door; a far wall stands behind it. A
//! robot with a fan of sonars (22° cones) stops at a few poses south of the
//! wall and takes one reading per sonar. A cone that straddles a door jamb
//! returns the jamb's range, and Table 9.2 paints the whole arc at that
//! range occupied — across the doorway. The same readings drive both halves
//! of the doorway-trap widget: the literal Table 9.1 sweep
//! ([`crate::mapping::sweep::sweep_scan`]) and the MAP search of Table 9.3
//! ([`crate::mapping::map_search`]).
//!
//! The scene is data (serde): walls, poses, sonar bearings, noise and seed.
//! Readings are the sonar's ([`Sonar::read`]: the exact cone cast of
//! [`World::cast_cone`] plus seeded Gaussian noise), so the same scene gives
//! the same readings bit for bit.

use crate::error::{self, invalid, Result};
use crate::geometry::raster::{raster_work, MAX_RASTER_WORK};
use crate::geometry::GridGeometry;
use crate::geometry::Pose;
use crate::sensors::scan::ConeBeam;
use crate::sensors::sonar::{Sonar, SonarPatch};
use crate::sensors::Scan;
use crate::world::{Rect, World};
use rand::rngs::StdRng;
use rand::SeedableRng;

/// The most readings a scene may ask for (poses x sonars): the widget sweeps
/// and climbs on them interactively.
pub const MAX_SCENE_READINGS: usize = 4096;

/// The most cells a scene's map may hold: 125 times the chapter's 2,000
/// (the chapter's room at 1 cm is 200,000). Every sweep step visits each
/// cell and every MAP flip scans all of them for the best gain: at this
/// size a sweep step takes about 12 ms and a whole climb a few tenths of a
/// second natively, where a grid at the 16.7-million-cell limit of
/// [`GridGeometry`] would hold the widget for minutes.
pub const MAX_SCENE_CELLS: usize = super::MAX_WIDGET_SCENE_CELLS;

/// The whole scene, as data. Missing fields (when read with serde) take the
/// chapter's scene, so a page may override only the seed; a nested `sonar`
/// overrides only the fields it names.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct DoorwayScene {
    /// Map limits (metres) and resolution (m/cell).
    pub min_x: f64,
    pub min_y: f64,
    pub max_x: f64,
    pub max_y: f64,
    pub resolution: f64,
    /// Every occupied box of the ground truth.
    pub walls: Vec<Rect>,
    /// The open door: the gap in the wall (for the widget's labels and the
    /// tests' "is it closed?").
    pub door: Rect,
    /// The part of the far wall seen through the door.
    pub far_wall: Rect,
    /// Where the robot stops to read its sonars; heading in radians.
    pub poses: Vec<Pose>,
    /// Sonar axes relative to the heading, degrees: the robot carries one
    /// sonar (a ring of one, facing the heading) per bearing.
    pub bearings_deg: Vec<f64>,
    /// A partial `sonar` keeps the fields it does not name from
    /// [`DoorwayScene::SONAR`].
    #[serde(deserialize_with = "read_sonar")]
    pub sonar: Sonar,
    /// Prior occupancy of a cell, for both the grid and the MAP objective.
    pub prior: f64,
    pub seed: u64,
}

impl Default for DoorwayScene {
    fn default() -> Self {
        Self::standard()
    }
}

/// A scene object's `sonar`, over the doorway's own.
fn read_sonar<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Sonar, D::Error> {
    Ok(<SonarPatch as serde::Deserialize>::deserialize(d)?.over(DoorwayScene::SONAR))
}

impl DoorwayScene {
    /// The chapter's sonar: a 22° cone, 3 m range, 2 cm noise, 13 sub-rays
    /// (enough that neighbouring sub-rays are less than a cell apart at
    /// `z_max`, so the cone's raster has no holes).
    pub const SONAR: Sonar = Sonar {
        count: 1,
        beta_deg: 22.0,
        z_max: 3.0,
        sigma: 0.02,
        sub_rays: 13,
    };

    /// The chapter's scene: a 5 m x 4 m room at 0.10 m (2,000 cells). The
    /// north wall (y = 2.4–2.5 m) has a 0.7 m door at x = 2.1–2.8 m; the far
    /// wall (y = 3.5–3.6 m) stands 2.5 m from the robot's line, inside the
    /// sonar's 3 m range. Seven stops on y = 1.0 m facing north, nine sonars
    /// each from -60° to +60° every 15° (a 22° cone overlaps its
    /// neighbours): 63 readings. From 1.4 m a cone is 0.54 m wide at the
    /// wall, so only a cone aimed almost at the door's centre passes through
    /// cleanly; the others that reach the doorway straddle a jamb.
    pub fn standard() -> Self {
        Self {
            min_x: 0.0,
            min_y: 0.0,
            max_x: 5.0,
            max_y: 4.0,
            resolution: 0.1,
            walls: vec![
                // North wall with the door gap.
                Rect::new(0.0, 2.4, 2.1, 2.5),
                Rect::new(2.8, 2.4, 5.0, 2.5),
                // Far wall behind the door.
                Rect::new(0.0, 3.5, 5.0, 3.6),
                // The room's west and east walls.
                Rect::new(0.0, 0.0, 0.1, 2.4),
                Rect::new(4.9, 0.0, 5.0, 2.4),
            ],
            door: Rect::new(2.1, 2.4, 2.8, 2.5),
            far_wall: Rect::new(1.6, 3.5, 3.3, 3.6),
            poses: [1.45, 1.95, 2.2, 2.45, 2.7, 2.95, 3.45]
                .iter()
                .map(|&x| Pose {
                    x,
                    y: 1.0,
                    theta: std::f64::consts::FRAC_PI_2,
                })
                .collect(),
            bearings_deg: (0..9).map(|i| -60.0 + 15.0 * i as f64).collect(),
            sonar: Self::SONAR,
            prior: 0.5,
            seed: 7,
        }
    }

    pub fn validate(&self) -> Result<()> {
        let g = GridGeometry::covering(
            self.min_x,
            self.min_y,
            self.max_x,
            self.max_y,
            self.resolution,
        )?;
        super::check_scene_cells(&g)?;
        if self.poses.is_empty() {
            return Err(invalid("poses", "[]", "at least one pose"));
        }
        for p in &self.poses {
            Pose::new(p.x, p.y, p.theta)?;
        }
        if self.bearings_deg.is_empty() {
            return Err(invalid("bearings_deg", "[]", "at least one sonar"));
        }
        for (i, &b) in self.bearings_deg.iter().enumerate() {
            error::finite(&format!("bearings_deg[{i}]"), b)?;
        }
        let readings = self.poses.len().saturating_mul(self.bearings_deg.len());
        if readings > MAX_SCENE_READINGS {
            return Err(invalid(
                "poses x bearings_deg",
                readings,
                "at most 4096 readings",
            ));
        }
        for r in self.walls.iter().chain([&self.door, &self.far_wall]) {
            for v in [r.min_x, r.min_y, r.max_x, r.max_y] {
                error::finite("walls", v)?;
            }
        }
        self.sonar.validate()?;
        // The bearings place the doorway's sonars; a ring around each
        // bearing would be a reading the widget cannot show.
        if self.sonar.count != 1 {
            return Err(invalid(
                "sonar.count",
                self.sonar.count,
                "1: the doorway's robot carries one sonar per entry of bearings_deg",
            ));
        }
        // The MAP search needs a half-angle below a right angle.
        if self.sonar.beta_deg >= 180.0 {
            return Err(invalid(
                "sonar.beta_deg",
                self.sonar.beta_deg,
                "an opening angle below 180 degrees",
            ));
        }
        // The MAP search's own limit, checked here before the readings are
        // cast (casting them is the same order of work): the search would
        // refuse the scene only after the sweep had cast it.
        let work = raster_work(
            readings,
            self.sonar.sub_rays,
            self.sonar.z_max,
            self.resolution,
        );
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(work <= MAX_RASTER_WORK) {
            return Err(invalid(
                "poses x bearings_deg x sonar.sub_rays",
                format!(
                    "{readings} readings x {} sub-rays reaching {} m ({work:.2e} raster steps)",
                    self.sonar.sub_rays,
                    error::show(self.sonar.z_max),
                ),
                "at most 5e7 raster steps: fewer readings or sub-rays, a shorter sonar.z_max or a coarser resolution",
            ));
        }
        error::open_probability("prior", self.prior)?;
        Ok(())
    }

    pub fn geometry(&self) -> Result<GridGeometry> {
        GridGeometry::covering(
            self.min_x,
            self.min_y,
            self.max_x,
            self.max_y,
            self.resolution,
        )
    }

    /// The ground truth.
    pub fn world(&self) -> Result<World> {
        self.validate()?;
        Ok(World::from_boxes(self.geometry()?, &self.walls))
    }

    /// Half the cone's opening angle, radians.
    pub fn half_width(&self) -> f64 {
        self.sonar.half_width()
    }

    /// Every reading, pose by pose and sonar by sonar: the sonar's noisy
    /// cone reading ([`Sonar::read`], seeded), in `[0, z_max]`.
    pub fn beams(&self) -> Result<Vec<ConeBeam>> {
        let world = self.world()?;
        let mut rng = StdRng::seed_from_u64(self.seed);
        let mut beams = Vec::with_capacity(self.poses.len() * self.bearings_deg.len());
        for pose in &self.poses {
            for &b in &self.bearings_deg {
                let bearing = b.to_radians();
                let range =
                    self.sonar
                        .read(&world, pose.x, pose.y, pose.theta + bearing, &mut rng)?;
                beams.push(ConeBeam {
                    pose: *pose,
                    bearing,
                    range,
                });
            }
        }
        Ok(beams)
    }

    /// The same readings as one scan per pose, for the Table 9.1 mappers.
    pub fn scans(&self) -> Result<Vec<Scan>> {
        let beams = self.beams()?;
        let per_pose = self.bearings_deg.len();
        beams
            .chunks(per_pose)
            .map(|chunk| {
                Scan::new(
                    chunk[0].pose,
                    chunk.iter().map(|b| b.range).collect(),
                    chunk.iter().map(|b| b.bearing).collect(),
                )
            })
            .collect()
    }

    /// Cells whose centres lie inside `rect`, as `(ix, iy)` columns: for
    /// each column of the rectangle, the cell indices in it.
    pub fn cells_in(&self, rect: &Rect) -> Result<Vec<Vec<usize>>> {
        let g = self.geometry()?;
        let mut columns = Vec::new();
        for ix in 0..g.width() {
            let mut col = Vec::new();
            for iy in 0..g.height() {
                let (x, y) = g.cell_center(ix, iy);
                if rect.contains(x, y) {
                    col.push(g.index(ix, iy));
                }
            }
            if !col.is_empty() {
                columns.push(col);
            }
        }
        Ok(columns)
    }
}

impl DoorwayScene {
    /// The passage: the door's columns from the wall to the far wall.
    pub fn passage(&self) -> Rect {
        Rect::new(
            self.door.min_x,
            self.door.min_y,
            self.door.max_x,
            self.far_wall.min_y,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_scene_is_big_enough_and_deterministic() {
        let s = DoorwayScene::standard();
        let g = s.geometry().unwrap();
        assert!(g.len() >= 1200, "{} cells", g.len());
        let a = s.beams().unwrap();
        assert!(a.len() >= 24);
        assert_eq!(a, s.beams().unwrap(), "same seed, same readings");
        let other = DoorwayScene {
            seed: 8,
            ..s.clone()
        }
        .beams()
        .unwrap();
        assert_ne!(a, other);
        assert!(a.iter().all(|b| (0.0..=3.0).contains(&b.range)));
    }

    #[test]
    fn a_partial_sonar_keeps_the_scenes_other_values_and_noise_sigma_reads() {
        let read = |json: &str| serde_json::from_str::<DoorwayScene>(json).unwrap();
        let s = read(r#"{"sonar": {"z_max": 2.5}}"#);
        assert_eq!(
            s.sonar,
            Sonar {
                z_max: 2.5,
                ..DoorwayScene::SONAR
            }
        );
        assert_eq!(
            read(r#"{"sonar": {"noise_sigma": 0.05}}"#).sonar.sigma,
            0.05
        );
        assert_eq!(read(r#"{"sonar": {}}"#), DoorwayScene::standard());
        // The doorway's robot carries one sonar per bearing, not a ring.
        let e = read(r#"{"sonar": {"count": 4}}"#).validate().unwrap_err();
        assert!(e.to_string().contains("sonar.count"), "{e}");
        let e = read(r#"{"sonar": {"beta_deg": 180}}"#)
            .validate()
            .unwrap_err();
        assert!(e.to_string().contains("below 180"), "{e}");
    }

    #[test]
    fn rejects_a_broken_scene() {
        let s = DoorwayScene {
            prior: 0.0,
            ..DoorwayScene::standard()
        };
        assert!(s.beams().unwrap_err().to_string().contains("prior"));
        let s = DoorwayScene {
            poses: vec![],
            ..DoorwayScene::standard()
        };
        assert!(s.validate().is_err());
        let s = DoorwayScene {
            bearings_deg: vec![0.0; 1000],
            ..DoorwayScene::standard()
        };
        let e = s.validate().unwrap_err().to_string();
        assert!(
            e.contains("poses x bearings_deg") && e.contains("7000"),
            "{e}"
        );
    }
}
