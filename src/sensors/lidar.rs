//! A planar LiDAR: evenly spaced thin beams with Gaussian range noise; its
//! exact ranges come from the world's one ray caster, [`World::cast`]. The
//! apartment's robot and the table's robot both carry one; each scene states
//! its own, and a scene object's partial `lidar` names only what it changes
//! ([`LidarPatch`]).

use super::noise::standard_normal;
use crate::error::{self, invalid, Result};
use crate::geometry::Pose;
use crate::world::World;
use rand::rngs::StdRng;
use std::f64::consts::TAU;

/// Upper bound on a LiDAR's beam count (an instructor's attribute can set
/// it; more beams than this would not make a better picture, only a slower
/// one).
pub const MAX_BEAMS: usize = 4096;

/// A planar LiDAR: `beams` beams spread evenly over a full turn starting at
/// `first_bearing` (radians from the heading), range `z_max` metres, and
/// Gaussian range noise of standard deviation `sigma` metres on every
/// return. A beam that meets nothing within `z_max` reads exactly `z_max`
/// (a no-return, which Table 9.2 treats as free space and no obstacle).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Lidar {
    pub beams: usize,
    pub z_max: f64,
    pub sigma: f64,
    pub first_bearing: f64,
}

impl Lidar {
    pub fn validate(&self) -> Result<()> {
        if self.beams == 0 || self.beams > MAX_BEAMS {
            return Err(invalid("lidar.beams", self.beams, "1 to 4096 beams"));
        }
        error::positive("lidar.z_max", self.z_max)?;
        error::non_negative("lidar.sigma", self.sigma)?;
        error::finite("lidar.first_bearing", self.first_bearing)?;
        Ok(())
    }

    /// Bearing of every beam, radians relative to the heading.
    pub fn bearings(&self) -> Vec<f64> {
        let step = self.spacing();
        (0..self.beams)
            .map(|i| self.first_bearing + i as f64 * step)
            .collect()
    }

    /// Angle between neighbouring beams, radians.
    pub fn spacing(&self) -> f64 {
        TAU / self.beams as f64
    }

    /// One noisy scan of `world` from `pose`, written into `ranges` (resized
    /// to the beam count). Exactly one normal sample is drawn per beam, hit
    /// or no hit, so the noise of beam `i` at scan `k` does not depend on
    /// what the other beams saw (a person stepping into one beam changes
    /// that beam only).
    pub fn scan_into(&self, world: &World, pose: &Pose, rng: &mut StdRng, ranges: &mut Vec<f64>) {
        ranges.clear();
        let step = self.spacing();
        // The first beam's world angle, then one step per beam: the order
        // of the additions is kept as the scenes' scans were pinned with.
        let first = pose.theta + self.first_bearing;
        for i in 0..self.beams {
            let exact = world.cast(pose.x, pose.y, first + i as f64 * step, self.z_max);
            let noise = self.sigma * standard_normal(rng);
            let z = if exact >= self.z_max {
                self.z_max
            } else {
                // Noise cannot turn a return into a no-return or a negative
                // range: a real sensor reports neither for a wall it sees.
                (exact + noise).clamp(0.0, self.z_max * (1.0 - 1e-9))
            };
            ranges.push(z);
        }
    }
}

/// A partial `lidar` of a scene object: the fields it names replace the
/// scene's own LiDAR's, the others stay (see [`LidarPatch::over`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LidarPatch {
    pub beams: Option<usize>,
    pub z_max: Option<f64>,
    pub sigma: Option<f64>,
    pub first_bearing: Option<f64>,
}

impl LidarPatch {
    /// `base` with the fields this patch names replaced.
    pub fn over(self, base: Lidar) -> Lidar {
        Lidar {
            beams: self.beams.unwrap_or(base.beams),
            z_max: self.z_max.unwrap_or(base.z_max),
            sigma: self.sigma.unwrap_or(base.sigma),
            first_bearing: self.first_bearing.unwrap_or(base.first_bearing),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;
    use crate::world::Rect;
    use rand::SeedableRng;

    #[test]
    fn noiseless_lidar_reads_exact_ranges_and_no_returns() {
        let g = GridGeometry::new(40, 40, 0.1, 0.0, 0.0).unwrap();
        let world = World::from_boxes(g, &[Rect::new(3.0, 0.0, 3.1, 4.0)]);
        let lidar = Lidar {
            beams: 4,
            z_max: 2.5,
            sigma: 0.0,
            first_bearing: 0.0,
        };
        let mut rng = StdRng::seed_from_u64(1);
        let mut z = Vec::new();
        lidar.scan_into(
            &world,
            &Pose::new(1.05, 2.05, 0.0).unwrap(),
            &mut rng,
            &mut z,
        );
        assert!((z[0] - 1.95).abs() < 1e-9, "east wall: {z:?}");
        assert_eq!(z[1], 2.5, "north: nothing within range");
        assert_eq!(z[2], 2.5);
        let bad = Lidar { beams: 0, ..lidar };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("lidar.beams"));
    }
}
