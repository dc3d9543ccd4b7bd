//! The forward beam model `p(z | x, m)` of Probabilistic Robotics Table 6.1.
//!
//! A mixture of four ways a range reading comes about, given the expected
//! range `z*` (the range to the first occupied cell along the beam):
//! a Gaussian hit around `z*` (normalised on `[0, z_max]`), an exponential
//! short reading (normalised on `[0, z*]`), a point mass at `z_max` (no
//! return), and a uniform random reading on `[0, z_max)`.

use crate::error::{self, invalid, Result};

/// The mixture's parameters (eq. 6.12 and the text around Table 6.1).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct BeamModelParams {
    pub z_hit: f64,
    /// Standard deviation of the hit Gaussian, metres.
    pub sigma_hit: f64,
    pub z_short: f64,
    /// Rate of the short-reading exponential, 1/metres.
    pub lambda_short: f64,
    /// Weight of the point mass at `z_max` (Table 6.1's `z_max` weight).
    pub z_maxw: f64,
    pub z_rand: f64,
    /// Maximum range, metres.
    pub z_max: f64,
}

impl Default for BeamModelParams {
    /// The chapter's reference setting.
    fn default() -> Self {
        Self::CHAPTER
    }
}

impl BeamModelParams {
    /// The chapter's reference setting: `p(z=2 | z*=2) = 2.160`,
    /// `p(z=2 | z*=3) = 0.0309`.
    pub const CHAPTER: Self = Self {
        z_hit: 0.8,
        sigma_hit: 0.15,
        z_short: 0.1,
        lambda_short: 1.0,
        z_maxw: 0.05,
        z_rand: 0.05,
        z_max: 3.0,
    };

    pub fn validate(&self) -> Result<()> {
        for (field, w) in [
            ("z_hit", self.z_hit),
            ("z_short", self.z_short),
            ("z_maxw", self.z_maxw),
            ("z_rand", self.z_rand),
        ] {
            error::non_negative(field, w)?;
        }
        let sum = self.z_hit + self.z_short + self.z_maxw + self.z_rand;
        if (sum - 1.0).abs() > 1e-6 {
            return Err(invalid(
                "z_hit + z_short + z_maxw + z_rand",
                sum,
                "mixture weights that add up to 1",
            ));
        }
        error::positive("sigma_hit", self.sigma_hit)?;
        error::positive("lambda_short", self.lambda_short)?;
        error::positive("z_max", self.z_max)?;
        Ok(())
    }
}

/// The validated beam model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamModel {
    params: BeamModelParams,
}

impl BeamModel {
    pub fn new(params: BeamModelParams) -> Result<Self> {
        params.validate()?;
        Ok(Self { params })
    }

    pub fn chapter() -> Self {
        Self {
            params: BeamModelParams::CHAPTER,
        }
    }

    pub fn params(&self) -> &BeamModelParams {
        &self.params
    }

    /// `p(z | z*)`: a density on `[0, z_max)` plus the point mass `z_maxw`
    /// at `z >= z_max` (returned as is, as the chapter does when it mixes
    /// the two). `z*` is clamped to `[0, z_max]`.
    pub fn density(&self, z: f64, z_star: f64) -> f64 {
        let p = &self.params;
        let z_star = z_star.clamp(0.0, p.z_max);
        if !(z >= 0.0) {
            return 0.0;
        }
        if z >= p.z_max {
            // The hit Gaussian and the uniform live on [0, z_max), the short
            // exponential on [0, z*]: only the point mass remains here,
            // together with the hit Gaussian's density at the boundary when
            // z* itself is z_max.
            let mass = p.z_maxw;
            let hit = if z == p.z_max {
                p.z_hit * self.hit(z, z_star)
            } else {
                0.0
            };
            return mass + hit;
        }
        p.z_hit * self.hit(z, z_star) + p.z_short * self.short(z, z_star) + p.z_rand / p.z_max
    }

    /// The hit component's normalised density (eq. 6.4–6.6).
    pub fn hit(&self, z: f64, z_star: f64) -> f64 {
        let p = &self.params;
        if !(0.0..=p.z_max).contains(&z) {
            return 0.0;
        }
        let s = p.sigma_hit;
        let eta = normal_cdf((p.z_max - z_star) / s) - normal_cdf(-z_star / s);
        let u = (z - z_star) / s;
        (-0.5 * u * u).exp() / (s * (2.0 * std::f64::consts::PI).sqrt()) / eta
    }

    /// The short component's normalised density (eq. 6.7–6.9).
    pub fn short(&self, z: f64, z_star: f64) -> f64 {
        let l = self.params.lambda_short;
        if !(0.0..=z_star).contains(&z) || z_star <= 0.0 {
            return 0.0;
        }
        l * (-l * z).exp() / (1.0 - (-l * z_star).exp())
    }
}

/// Standard normal cumulative distribution.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * (1.0 + erf(x / std::f64::consts::SQRT_2))
}

/// The error function, from the Chebyshev fit of `erfc` in Numerical
/// Recipes (§6.2): fractional error below 1.2e-7 everywhere, ample for
/// densities printed to four digits.
pub fn erf(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let erfc = t * poly.exp();
    if x >= 0.0 {
        1.0 - erfc
    } else {
        erfc - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chapter_reference_values() {
        let m = BeamModel::chapter();
        assert!(
            (m.density(2.0, 2.0) - 2.160).abs() < 1e-3,
            "{}",
            m.density(2.0, 2.0)
        );
        assert!(
            (m.density(2.0, 3.0) - 0.0309).abs() < 1e-4,
            "{}",
            m.density(2.0, 3.0)
        );
    }

    #[test]
    fn weights_must_sum_to_one() {
        let p = BeamModelParams {
            z_rand: 0.5,
            ..BeamModelParams::CHAPTER
        };
        assert!(BeamModel::new(p)
            .unwrap_err()
            .to_string()
            .contains("add up to 1"));
        let p = BeamModelParams {
            sigma_hit: f64::NAN,
            ..BeamModelParams::CHAPTER
        };
        assert!(BeamModel::new(p)
            .unwrap_err()
            .to_string()
            .contains("sigma_hit"));
    }
}
