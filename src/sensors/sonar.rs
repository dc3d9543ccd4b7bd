//! A ring of sonar transducers: wide cones whose reading is the nearest echo
//! anywhere inside the cone (Table 6.1), with Gaussian range noise. The
//! doorway's robot and the table's robot both carry one; each scene states
//! its own, and a scene object's partial `sonar` names only what it changes
//! ([`SonarPatch`]).

use super::noise::standard_normal;
use crate::error::{self, invalid, Result};
use crate::world::World;
use rand::rngs::StdRng;
use std::f64::consts::TAU;

/// Upper bound on the transducers of one ring (an instructor's attribute
/// can set it; a scene may allow fewer).
pub const MAX_COUNT: usize = 4096;
/// Upper bound on the sub-rays cast across one cone.
pub const MAX_SUB_RAYS: usize = 1024;

/// `count` transducers evenly spaced around the robot, the first facing its
/// heading; each a cone of full opening `beta_deg` degrees, range `z_max`
/// metres, Gaussian range noise of standard deviation `sigma` metres, its
/// nearest echo found with `sub_rays` rays spread across the cone.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sonar {
    pub count: usize,
    pub beta_deg: f64,
    pub z_max: f64,
    pub sigma: f64,
    pub sub_rays: usize,
}

impl Sonar {
    /// Checks the sensor's own ranges, naming the field (`sonar.beta_deg`);
    /// a scene adds its own budgets.
    pub fn validate(&self) -> Result<()> {
        if self.count == 0 || self.count > MAX_COUNT {
            return Err(invalid("sonar.count", self.count, "1 to 4096 transducers"));
        }
        error::positive("sonar.beta_deg", self.beta_deg)?;
        if self.beta_deg > 180.0 {
            return Err(invalid(
                "sonar.beta_deg",
                error::show(self.beta_deg),
                "a cone of at most 180 degrees",
            ));
        }
        error::positive("sonar.z_max", self.z_max)?;
        error::non_negative("sonar.sigma", self.sigma)?;
        if self.sub_rays == 0 || self.sub_rays > MAX_SUB_RAYS {
            return Err(invalid("sonar.sub_rays", self.sub_rays, "1 to 1024 rays"));
        }
        Ok(())
    }

    /// The cone's full opening angle, radians.
    pub fn beta(&self) -> f64 {
        self.beta_deg.to_radians()
    }

    /// Half the cone's opening angle, radians.
    pub fn half_width(&self) -> f64 {
        0.5 * self.beta()
    }

    /// Angle between neighbouring transducers of the ring, radians.
    pub fn spacing(&self) -> f64 {
        TAU / self.count as f64
    }

    /// One noisy reading of the cone whose axis points along `axis`
    /// (radians, world frame) from `(x, y)`: the nearest echo inside it plus
    /// noise, kept in `[0, z_max]`. A cone with no echo reads exactly
    /// `z_max` (nothing echoed, nothing to blur), but its noise sample is
    /// drawn all the same, so that every reading keeps its own draw
    /// whatever the others saw.
    pub fn read(&self, world: &World, x: f64, y: f64, axis: f64, rng: &mut StdRng) -> Result<f64> {
        let exact = world.cast_cone(x, y, axis, self.half_width(), self.sub_rays, self.z_max)?;
        let noise = self.sigma * standard_normal(rng);
        Ok(if exact >= self.z_max {
            self.z_max
        } else {
            (exact + noise).clamp(0.0, self.z_max)
        })
    }
}

/// A partial `sonar` of a scene object: the fields it names replace the
/// scene's own sonar's, the others stay (see [`SonarPatch::over`]). The
/// doorway's old spelling `noise_sigma` still reads; the table's old
/// `beta` (radians) is an unknown field now, refused by name.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SonarPatch {
    pub count: Option<usize>,
    pub beta_deg: Option<f64>,
    pub z_max: Option<f64>,
    #[serde(alias = "noise_sigma")]
    pub sigma: Option<f64>,
    pub sub_rays: Option<usize>,
}

impl SonarPatch {
    /// `base` with the fields this patch names replaced.
    pub fn over(self, base: Sonar) -> Sonar {
        Sonar {
            count: self.count.unwrap_or(base.count),
            beta_deg: self.beta_deg.unwrap_or(base.beta_deg),
            z_max: self.z_max.unwrap_or(base.z_max),
            sigma: self.sigma.unwrap_or(base.sigma),
            sub_rays: self.sub_rays.unwrap_or(base.sub_rays),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;
    use crate::world::Rect;
    use rand::SeedableRng;

    const RING: Sonar = Sonar {
        count: 4,
        beta_deg: 20.0,
        z_max: 3.0,
        sigma: 0.0,
        sub_rays: 5,
    };

    #[test]
    fn a_cone_reads_its_nearest_echo_and_a_miss_reads_z_max() {
        let g = GridGeometry::new(40, 40, 0.1, 0.0, 0.0).unwrap();
        let world = World::from_boxes(g, &[Rect::new(3.0, 0.0, 3.1, 4.0)]);
        let mut rng = StdRng::seed_from_u64(1);
        let east = RING.read(&world, 1.05, 2.05, 0.0, &mut rng).unwrap();
        assert!((east - 1.95).abs() < 1e-9, "{east}");
        let north = RING.read(&world, 1.05, 2.05, RING.spacing(), &mut rng);
        assert_eq!(north.unwrap(), 3.0);
    }

    #[test]
    fn validation_names_the_field() {
        let text = |s: Sonar| s.validate().unwrap_err().to_string();
        assert!(text(Sonar { count: 0, ..RING }).contains("sonar.count"));
        let wide = text(Sonar {
            beta_deg: 181.0,
            ..RING
        });
        assert!(
            wide.contains("sonar.beta_deg") && wide.contains("181"),
            "{wide}"
        );
        assert!(text(Sonar {
            sigma: -1.0,
            ..RING
        })
        .contains("sonar.sigma"));
        assert!(text(Sonar {
            sub_rays: 2000,
            ..RING
        })
        .contains("sonar.sub_rays"));
        RING.validate().unwrap();
    }

    #[test]
    fn a_patch_replaces_only_the_fields_it_names() {
        let patch = SonarPatch {
            z_max: Some(5.0),
            ..SonarPatch::default()
        };
        assert_eq!(patch.over(RING), Sonar { z_max: 5.0, ..RING });
        assert_eq!(SonarPatch::default().over(RING), RING);
    }
}
