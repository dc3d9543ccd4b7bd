//! The odometry motion model of Probabilistic Robotics Table 5.6 (rotate,
//! translate, rotate, each with noise that grows with the motion), plus the
//! systematic errors real wheels have. Integrating the noisy increments from
//! the start pose gives the dead-reckoned poses a map is built at when the
//! pose oracle is off.

use super::noise::standard_normal;
use crate::error::{self, invalid, Result};
use crate::geometry::{wrap_angle, Pose};
use rand::rngs::StdRng;
use rand::SeedableRng;

/// Odometry noise. `alpha` are the four coefficients of Table 5.6, used as
/// standard deviations: rotation noise per radian turned (`alpha[0]`) and
/// per metre driven (`alpha[1]`), translation noise per metre driven
/// (`alpha[2]`) and per radian turned (`alpha[3]`). On top of that random
/// noise, two systematic errors that do not average out and make a map
/// built by dead reckoning bend: `heading_drift` radians of heading error
/// per metre driven (unequal wheel diameters) and `turn_scale` (the
/// fraction by which every turn is over-reported: a wrong wheel base).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OdometryParams {
    pub alpha: [f64; 4],
    pub heading_drift: f64,
    pub turn_scale: f64,
}

impl OdometryParams {
    /// The wheels of Map Weaver's apartment robot, also the noise a real
    /// log's dead reckoning is given: a few percent of every motion, plus
    /// the drift and turn error of slightly unequal wheels.
    pub const WHEELS: Self = Self {
        alpha: [0.05, 0.01, 0.02, 0.01],
        heading_drift: -0.003,
        turn_scale: 0.01,
    };

    /// No noise and no systematic error: the increments as they are.
    pub const EXACT: Self = Self {
        alpha: [0.0; 4],
        heading_drift: 0.0,
        turn_scale: 0.0,
    };

    /// The dead-reckoned path of `truth`: it starts at the first true pose
    /// and is advanced by each noisy increment between consecutive true
    /// poses ([`Self::dead_reckon`]), the noise drawn from a generator
    /// seeded with `seed` (one seed, one path).
    pub fn dead_reckon_path(&self, truth: &[Pose], seed: u64) -> Vec<Pose> {
        let mut path = DeadReckoner::new(*self, seed);
        path.extend(truth, usize::MAX);
        path.into_path()
    }

    pub fn validate(&self) -> Result<()> {
        for (i, &a) in self.alpha.iter().enumerate() {
            error::non_negative(&format!("odometry.alpha[{i}]"), a)?;
        }
        error::finite("odometry.heading_drift", self.heading_drift)?;
        error::finite("odometry.turn_scale", self.turn_scale)?;
        if self.turn_scale.abs() >= 1.0 {
            return Err(invalid(
                "odometry.turn_scale",
                self.turn_scale,
                "a fraction between -1 and 1",
            ));
        }
        Ok(())
    }

    /// Advances the dead-reckoned pose `estimate` by what the wheels report
    /// for the true motion from `from` to `to`: the motion is split into
    /// rotate, translate, rotate (Table 5.6, lines 2–4), each part is
    /// corrupted (lines 5–7, plus the systematic errors) and the result is
    /// composed onto the estimate (lines 8–10). Draws exactly three normal
    /// samples.
    pub fn dead_reckon(&self, estimate: &Pose, from: &Pose, to: &Pose, rng: &mut StdRng) -> Pose {
        let (dx, dy) = (to.x - from.x, to.y - from.y);
        let trans = dx.hypot(dy);
        // A turn in place has no direction of travel: all of it is rot2.
        let rot1 = if trans > 1e-9 {
            wrap_angle(dy.atan2(dx) - from.theta)
        } else {
            0.0
        };
        let rot2 = wrap_angle(to.theta - from.theta - rot1);
        let [a1, a2, a3, a4] = self.alpha;
        let n1 = standard_normal(rng);
        let n2 = standard_normal(rng);
        let n3 = standard_normal(rng);
        let rot1_hat = rot1 * (1.0 + self.turn_scale) + (a1 * rot1.abs() + a2 * trans) * n1;
        let trans_hat = trans + (a3 * trans + a4 * (rot1.abs() + rot2.abs())) * n2;
        let rot2_hat = rot2 * (1.0 + self.turn_scale)
            + self.heading_drift * trans
            + (a1 * rot2.abs() + a2 * trans) * n3;
        let heading = estimate.theta + rot1_hat;
        Pose {
            x: estimate.x + trans_hat * heading.cos(),
            y: estimate.y + trans_hat * heading.sin(),
            theta: wrap_angle(heading + rot2_hat),
        }
    }
}

/// A dead-reckoned path ([`OdometryParams::dead_reckon_path`]) integrated a
/// bounded number of poses at a time, so that a caller with a budget per
/// call (a page's real-log session) can follow a log of any length: the
/// same seed gives the same path, bit for bit, however it is cut.
#[derive(Debug, Clone)]
pub struct DeadReckoner {
    params: OdometryParams,
    rng: StdRng,
    path: Vec<Pose>,
}

impl DeadReckoner {
    /// A path not yet begun, its noise drawn from `seed`.
    pub fn new(params: OdometryParams, seed: u64) -> Self {
        Self {
            params,
            rng: StdRng::seed_from_u64(seed),
            path: Vec::new(),
        }
    }

    /// Integrates up to `max_poses` more poses of the path of `truth` (the
    /// same poses at every call); returns how many.
    pub fn extend(&mut self, truth: &[Pose], max_poses: usize) -> usize {
        let k0 = self.path.len();
        let end = truth.len().min(k0.saturating_add(max_poses));
        if k0 >= end {
            return 0;
        }
        // Room for the whole path at once: no call copies the poses before.
        self.path.reserve_exact(truth.len() - k0);
        for k in k0..end {
            let pose = match k.checked_sub(1).and_then(|j| self.path.get(j)) {
                // The first pose is the truth's; each after it is the one
                // before advanced by the noisy increment.
                None => truth[k],
                Some(estimate) => {
                    self.params
                        .dead_reckon(estimate, &truth[k - 1], &truth[k], &mut self.rng)
                }
            };
            self.path.push(pose);
        }
        end - k0
    }

    /// The poses integrated so far.
    pub fn len(&self) -> usize {
        self.path.len()
    }

    /// True before the first pose.
    pub fn is_empty(&self) -> bool {
        self.path.is_empty()
    }

    /// The path integrated so far.
    pub fn path(&self) -> &[Pose] {
        &self.path
    }

    /// The path integrated so far, taken.
    pub fn into_path(self) -> Vec<Pose> {
        self.path
    }
}
