//! The forward beam model `p(z | x, m)` of Probabilistic Robotics Table 6.1.
//!
//! A mixture of four ways a range reading comes about, given the expected
//! range `z*` (the range to the first occupied cell along the beam):
//! a Gaussian hit around `z*` (normalised on `[0, z_max]`), an exponential
//! short reading (normalised on `[0, z*]`), a point mass at `z_max` (no
//! return), and a uniform random reading on `[0, z_max)`.
//!
//! In the data flow it sits between the ground truth and everything that
//! needs readings or their likelihood: [`expected_range`] casts a thin beam
//! or a cone into a [`World`] to find `z*`, [`BeamModel::density`] scores a
//! reading (the independence trap, MAP mapping), and [`BeamModel::sample`]
//! draws one (generative mode: the training data of the learned inverse
//! model, simulated scans). Sampling is seeded by the caller's `StdRng`.

use super::noise::standard_normal;
use crate::error::{self, invalid, Result};
use crate::geometry::Pose;
use crate::sensors::Scan;
use crate::world::World;
use rand::Rng;

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
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: density 0
        if !(z >= 0.0) {
            return 0.0;
        }
        if z >= p.z_max {
            // The hit Gaussian and the uniform live on [0, z_max), the short
            // exponential on [0, z*]: only the point mass remains here,
            // together with the hit Gaussian's density at the boundary when
            // z* itself is z_max.
            let mass = p.z_maxw;
            let hit = if z == p.z_max && p.z_hit > 0.0 {
                p.z_hit * self.hit(z, z_star)
            } else {
                0.0
            };
            return (mass + hit).min(f64::MAX);
        }
        // A component of weight 0 is absent, whatever its density (which
        // may be infinite in a degenerate corner: 0 * inf would be NaN).
        // The sum is capped at f64::MAX so that its logarithm stays finite.
        let part = |w: f64, density: f64| if w > 0.0 { w * density } else { 0.0 };
        (part(p.z_hit, self.hit(z, z_star))
            + part(p.z_short, self.short(z, z_star))
            + p.z_rand / p.z_max)
            .min(f64::MAX)
    }

    /// The hit component's normalised density (eq. 6.4–6.6).
    pub fn hit(&self, z: f64, z_star: f64) -> f64 {
        let p = &self.params;
        if !(0.0..=p.z_max).contains(&z) {
            return 0.0;
        }
        let s = p.sigma_hit;
        let eta = normal_cdf((p.z_max - z_star) / s) - normal_cdf(-z_star / s);
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(eta > 1e-6) {
            // A Gaussian hundreds of thousands of times wider than
            // [0, z_max] is flat on it. Its normaliser is then below the
            // erf fit's accuracy (about 1e-7) and could even come out
            // negative; the limit is the uniform density.
            return (1.0 / p.z_max).min(f64::MAX);
        }
        let u = (z - z_star) / s;
        ((-0.5 * u * u).exp() / (s * (2.0 * std::f64::consts::PI).sqrt()) / eta).min(f64::MAX)
    }

    /// The short component's normalised density (eq. 6.7–6.9).
    pub fn short(&self, z: f64, z_star: f64) -> f64 {
        let l = self.params.lambda_short;
        if !(0.0..=z_star).contains(&z) || z_star <= 0.0 {
            return 0.0;
        }
        // 1 - exp(-lambda z*) by expm1: for a tiny lambda z* the plain
        // difference rounds to 0 and the quotient to infinity. The limit
        // there is the uniform density on [0, z*].
        let d = l * (-l * z).exp() / -(-l * z_star).exp_m1();
        if d.is_finite() {
            d
        } else {
            (1.0 / z_star).min(f64::MAX)
        }
    }
}

/// Rejection samplers give up after this many proposals. Each proposal is
/// accepted with probability at least 1/3 (see [`BeamModel::sample`]), so
/// the cap is reached with probability below 1e-50: it exists only so that
/// no loop in the core is unbounded.
const MAX_PROPOSALS: usize = 256;

impl BeamModel {
    /// Draws one reading for expected range `z*` (metres): the generative
    /// reading of Table 6.1. First the cause, with probabilities `z_hit`,
    /// `z_short`, `z_maxw`, `z_rand`; then the reading from that cause's own
    /// normalised distribution, so that the draws follow [`Self::density`]
    /// exactly. `z*` is clamped to `[0, z_max]` as in `density` (a NaN
    /// counts as no obstacle).
    pub fn sample<R: Rng + ?Sized>(&self, z_star: f64, rng: &mut R) -> f64 {
        let p = &self.params;
        let z_star = if z_star.is_nan() {
            p.z_max
        } else {
            z_star.clamp(0.0, p.z_max)
        };
        let u = rng.random::<f64>();
        if u < p.z_hit {
            self.sample_hit(z_star, rng)
        } else if u < p.z_hit + p.z_short {
            self.sample_short(z_star, rng)
        } else if u < p.z_hit + p.z_short + p.z_maxw {
            p.z_max
        } else {
            rng.random::<f64>() * p.z_max
        }
    }

    /// The hit Gaussian truncated to `[0, z_max)` (eq. 6.4–6.6), by
    /// rejection. With `sigma_hit <= z_max` a Gaussian proposal lands inside
    /// the window at least `Phi(1) - 1/2 = 34%` of the time whatever `z*`;
    /// a wider Gaussian is nearly flat over the window, so a uniform
    /// proposal kept with probability `exp(-(z - z*)^2 / 2 sigma^2)` (at
    /// least `exp(-1/2) = 61%`) is the faster exact sampler there.
    fn sample_hit<R: Rng + ?Sized>(&self, z_star: f64, rng: &mut R) -> f64 {
        let p = &self.params;
        let s = p.sigma_hit;
        for _ in 0..MAX_PROPOSALS {
            if s <= p.z_max {
                let z = z_star + s * standard_normal(rng);
                if (0.0..p.z_max).contains(&z) {
                    return z;
                }
            } else {
                let z = rng.random::<f64>() * p.z_max;
                let u = (z - z_star) / s;
                if rng.random::<f64>() < (-0.5 * u * u).exp() {
                    return z;
                }
            }
        }
        z_star.min(p.z_max * (1.0 - f64::EPSILON))
    }

    /// The short-reading exponential truncated to `[0, z*]` (eq. 6.7–6.9),
    /// by inverting its distribution function
    /// `F(z) = (1 - exp(-lambda z)) / (1 - exp(-lambda z*))`.
    fn sample_short<R: Rng + ?Sized>(&self, z_star: f64, rng: &mut R) -> f64 {
        if z_star <= 0.0 {
            return 0.0;
        }
        let l = self.params.lambda_short;
        let u = rng.random::<f64>();
        let z = -(-u * (-(-l * z_star).exp_m1())).ln_1p() / l;
        z.clamp(0.0, z_star)
    }

    /// `p(z | x, m)` for one beam of a sensor at `pose` in `world`: `z*` by
    /// [`expected_range`], then [`Self::density`].
    pub fn likelihood(
        &self,
        world: &World,
        pose: &Pose,
        bearing: f64,
        shape: BeamShape,
        z: f64,
    ) -> Result<f64> {
        error::non_negative("z", z)?;
        let z_star = expected_range(world, pose, bearing, shape, self.params.z_max)?;
        Ok(self.density(z, z_star))
    }

    /// One generated reading of the beam at `bearing` (radians, relative to
    /// the heading) from `pose` in `world`.
    pub fn sample_reading<R: Rng + ?Sized>(
        &self,
        world: &World,
        pose: &Pose,
        bearing: f64,
        shape: BeamShape,
        rng: &mut R,
    ) -> Result<f64> {
        let z_star = expected_range(world, pose, bearing, shape, self.params.z_max)?;
        Ok(self.sample(z_star, rng))
    }

    /// A whole generated scan: one reading per bearing, in order.
    pub fn sample_scan<R: Rng + ?Sized>(
        &self,
        world: &World,
        pose: &Pose,
        bearings: &[f64],
        shape: BeamShape,
        rng: &mut R,
    ) -> Result<Scan> {
        let mut ranges = Vec::with_capacity(bearings.len());
        for (i, &b) in bearings.iter().enumerate() {
            error::finite(&format!("bearings[{i}]"), b)?;
            ranges.push(self.sample_reading(world, pose, b, shape, rng)?);
        }
        Scan::new(*pose, ranges, bearings.to_vec())
    }
}

/// How wide a beam is when its expected range is sought: a thin ray, or a
/// cone of half-angle `half_width` (radians) probed by `sub_rays` rays
/// spread evenly across it, edges included (Table 6.1, the same spread as
/// [`World::cast_cone`]). `z*` of a cone is the nearest hit of its rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamShape {
    half_width: f64,
    sub_rays: usize,
    /// Rotation from the axis to the first sub-ray, `(cos, sin)` of
    /// `-half_width`.
    first: (f64, f64),
    /// Rotation from one sub-ray to the next.
    step: (f64, f64),
}

impl BeamShape {
    /// A thin beam: one ray along the axis.
    pub const THIN: Self = Self {
        half_width: 0.0,
        sub_rays: 1,
        first: (1.0, 0.0),
        step: (1.0, 0.0),
    };

    /// The most sub-rays a cone may have: more would only slow every cast.
    pub const MAX_SUB_RAYS: usize = 64;

    /// A cone. `half_width` in radians, at most pi / 2; `sub_rays` from 1
    /// (the axis only) to [`Self::MAX_SUB_RAYS`].
    pub fn cone(half_width: f64, sub_rays: usize) -> Result<Self> {
        error::non_negative("half_width", half_width)?;
        if half_width > std::f64::consts::FRAC_PI_2 {
            return Err(invalid(
                "half_width",
                half_width,
                "a half-angle of at most pi/2 radians",
            ));
        }
        if !(1..=Self::MAX_SUB_RAYS).contains(&sub_rays) {
            return Err(invalid("sub_rays", sub_rays, "between 1 and 64 rays"));
        }
        if sub_rays == 1 {
            return Ok(Self {
                half_width,
                ..Self::THIN
            });
        }
        let (s, c) = half_width.sin_cos();
        let delta = 2.0 * half_width / (sub_rays - 1) as f64;
        let (sd, cd) = delta.sin_cos();
        Ok(Self {
            half_width,
            sub_rays,
            first: (c, -s),
            step: (cd, sd),
        })
    }

    pub fn half_width(&self) -> f64 {
        self.half_width
    }
    pub fn sub_rays(&self) -> usize {
        self.sub_rays
    }
}

/// The expected range `z*` (metres) of a beam at `bearing` (radians,
/// relative to the heading) from `pose`: the range to the first occupied
/// cell along the ray, or for a cone the nearest over its sub-rays; `z_max`
/// when nothing is hit within `z_max` or the ray leaves the map.
pub fn expected_range(
    world: &World,
    pose: &Pose,
    bearing: f64,
    shape: BeamShape,
    z_max: f64,
) -> Result<f64> {
    let pose = Pose::new(pose.x, pose.y, pose.theta)?;
    error::finite("bearing", bearing)?;
    // Two finite angles can still add up to an infinity (and a beam
    // without a direction).
    error::finite("pose.theta + bearing", pose.theta + bearing)?;
    error::positive("z_max", z_max)?;
    let (s, c) = (pose.theta + bearing).sin_cos();
    Ok(expected_range_along(
        world,
        pose.x,
        pose.y,
        (c, s),
        shape,
        z_max,
    ))
}

/// [`expected_range`] for a beam whose axis is the unit vector `(cos, sin)`
/// in world coordinates: callers that draw directions without angles (the
/// training sampler) save the trigonometry, which is slow in wasm. Inputs
/// are trusted (finite, `z_max > 0`); anything else still terminates.
pub fn expected_range_along(
    world: &World,
    x: f64,
    y: f64,
    axis: (f64, f64),
    shape: BeamShape,
    z_max: f64,
) -> f64 {
    if shape.sub_rays <= 1 {
        return world.cast_along(x, y, axis, z_max);
    }
    let rotate = |(c, s): (f64, f64), (rc, rs): (f64, f64)| (c * rc - s * rs, c * rs + s * rc);
    let mut dir = rotate(axis, shape.first);
    let mut nearest = z_max;
    for _ in 0..shape.sub_rays {
        nearest = nearest.min(world.cast_along(x, y, dir, nearest));
        dir = rotate(dir, shape.step);
    }
    nearest
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
    // The fit slightly exceeds 1 right at 0; capping it keeps erf odd and
    // monotone there (else Phi(a) - Phi(b) could be negative for a > b).
    let erfc = (t * poly.exp()).min(1.0);
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
