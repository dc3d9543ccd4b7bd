//! Where a scan is expected, and how far off that may be: the prior a
//! match is weighed against.
//!
//! The odometry motion model of Table 5.6 splits a motion into a turn
//! `rot1` towards the direction of travel, a translation `trans` and a
//! turn `rot2`, each with noise that grows with the motion; the same
//! split says how much the predicted pose can be trusted. After a drive
//! straight down a corridor the heading is good to a fraction of a degree,
//! and a match that turns the scan by 20° to fit a doorway must be wrong;
//! after a sideways step (`rot1` near 90°) the same odometry can be 20° off,
//! and a match that finds it is right.
//!
//! A candidate pose is ranked by `N s - ((d / σ_t)^2 + (Δθ / σ_θ)^2) / 2`:
//! `s` the mean match value of its `N` points (each point on a wall counts
//! as one nat of evidence), `d` and `Δθ` its distance and turn from the
//! prediction. Strong evidence (a tenth more of a 180-point scan on walls
//! is 18 nats) outweighs a three-sigma correction (4.5 nats); a weak fit
//! does not.

use super::{relative_motion, MatchSettings};
use crate::geometry::{wrap_angle, Pose};
use crate::sensors::odometry::OdometryParams;

/// A predicted pose and its spread (one standard deviation).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Prediction {
    pub pose: Pose,
    /// Metres, in any direction.
    pub position_spread: f64,
    /// Radians.
    pub heading_spread: f64,
}

impl Prediction {
    /// `pose` with the least spreads of `settings`: a prediction nothing
    /// more is known about.
    pub fn at(pose: Pose, settings: &MatchSettings) -> Self {
        Self {
            pose,
            position_spread: settings.min_position_spread,
            heading_spread: settings.min_heading_spread,
        }
    }

    /// The pose `previous` moved as the odometry moved from `from` to `to`,
    /// with the spread `noise` gives that motion (Table 5.6, lines 2–7;
    /// the systematic errors count in full), at least the least spreads of
    /// `settings`.
    pub fn from_odometry(
        previous: &Pose,
        from: &Pose,
        to: &Pose,
        noise: &OdometryParams,
        settings: &MatchSettings,
    ) -> Self {
        let motion = relative_motion(from, to);
        let pose = super::compose(previous, motion);
        let trans = motion[0].hypot(motion[1]);
        let [a1, a2, a3, a4] = noise.alpha;
        // The direction of travel, rot1. A translation shorter than twice
        // the noise a full turnaround adds to it (a4 (|rot1| + |rot2|)
        // with both near pi) may have gone either way: the noisy odometry
        // of a short step back can read as a short step ahead, and then
        // only the worst case (rot1 = pi) spans the truth.
        let turnaround = 2.0 * a4 * std::f64::consts::TAU;
        let rot1 = if trans <= turnaround {
            std::f64::consts::PI
        } else {
            motion[1].atan2(motion[0])
        };
        let rot2 = wrap_angle(motion[2] - rot1).abs();
        let rot1 = rot1.abs();
        let scale = noise.turn_scale.abs();
        let sigma_rot1 = (a1 + scale) * rot1 + a2 * trans;
        let heading =
            sigma_rot1 + (a1 + scale) * rot2 + a2 * trans + noise.heading_drift.abs() * trans;
        // Along the way, the translation's noise; across it, the first
        // turn's error swung over the distance.
        let position = a3 * trans + a4 * (rot1 + rot2) + sigma_rot1 * trans;
        Self {
            pose,
            position_spread: position.max(settings.min_position_spread),
            heading_spread: heading.max(settings.min_heading_spread),
        }
    }

    /// The pose kept once a match has found `fit`: fit and prediction
    /// combined by their precisions (the measurement update of a Kalman
    /// filter, Probabilistic Robotics Table 3.1, the two treated as
    /// independent), position and heading apart.
    ///
    /// The fit's precision in position has the shape of its `curvature`
    /// (the map pins a position only across the walls in view: down a
    /// featureless corridor, not along it), scaled so that its sharpest
    /// direction has the spread `fitPositionSpread`; along a direction the
    /// map does not pin, the pose follows the odometry. In heading, the
    /// fit's spread is `fitHeadingSpread`, and a fit, pinned by every wall
    /// in view, is far more precise than the odometry after a turn.
    pub fn update(&self, fit: &Pose, curvature: [[f64; 2]; 2], settings: &MatchSettings) -> Pose {
        let prior = 1.0 / (self.position_spread * self.position_spread);
        // The curvature's largest eigenvalue scales it to a precision.
        let [[a, b], [_, d]] = curvature;
        let largest = 0.5 * (a + d) + (0.25 * (a - d) * (a - d) + b * b).sqrt();
        let (dx, dy) = (fit.x - self.pose.x, fit.y - self.pose.y);
        let (mx, my) = if largest > 0.0 && largest.is_finite() {
            let k = 1.0 / (largest * settings.fit_position_spread * settings.fit_position_spread);
            let (fa, fb, fd) = (a * k, b * k, d * k);
            // (P + F)^-1 F (fit - prediction), P = prior I.
            let (pa, pd) = (fa + prior, fd + prior);
            let det = pa * pd - fb * fb;
            let (fx, fy) = (fa * dx + fb * dy, fb * dx + fd * dy);
            ((pd * fx - fb * fy) / det, (pa * fy - fb * fx) / det)
        } else {
            (0.0, 0.0)
        };
        let h = 1.0 / (settings.fit_heading_spread * settings.fit_heading_spread);
        let kh = h / (h + 1.0 / (self.heading_spread * self.heading_spread));
        let p = &self.pose;
        Pose {
            x: p.x + mx,
            y: p.y + my,
            theta: wrap_angle(p.theta + kh * wrap_angle(fit.theta - p.theta)),
        }
    }

    /// The log prior of `pose`, nats (0 at the prediction).
    #[inline]
    pub fn log_prior(&self, pose: &Pose) -> f64 {
        let d2 = (pose.x - self.pose.x).powi(2) + (pose.y - self.pose.y).powi(2);
        let t = wrap_angle(pose.theta - self.pose.theta) / self.heading_spread;
        -0.5 * (d2 / (self.position_spread * self.position_spread) + t * t)
    }

    /// [`Self::log_prior`] of a candidate `(dx, dy, dtheta)` from the
    /// prediction.
    #[inline]
    pub fn log_prior_of_offset(&self, dx: f64, dy: f64, dtheta: f64) -> f64 {
        let t = dtheta / self.heading_spread;
        -0.5 * ((dx * dx + dy * dy) / (self.position_spread * self.position_spread) + t * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x: f64, y: f64, theta: f64) -> Pose {
        Pose { x, y, theta }
    }

    /// Straight ahead the heading is trusted to about a degree a metre;
    /// a sideways step of the same length, whose direction of travel is a
    /// quarter turn from the heading, to several degrees.
    #[test]
    fn a_sideways_step_is_trusted_less_than_a_step_ahead() {
        let s = MatchSettings {
            min_heading_spread: 1e-6,
            min_position_spread: 1e-6,
            ..MatchSettings::default()
        };
        let w = OdometryParams::WHEELS;
        let start = pose(0.0, 0.0, 0.0);
        let ahead = Prediction::from_odometry(&start, &start, &pose(1.0, 0.0, 0.0), &w, &s);
        let sideways = Prediction::from_odometry(&start, &start, &pose(0.0, 1.0, 0.0), &w, &s);
        assert!(ahead.heading_spread < 1.5f64.to_radians(), "{ahead:?}");
        assert!(sideways.heading_spread > 5f64.to_radians(), "{sideways:?}");
        assert!(sideways.position_spread > 2.0 * ahead.position_spread);
        // A few centimetres "ahead" may have been a step back.
        let short = Prediction::from_odometry(&start, &start, &pose(0.03, 0.0, 0.2), &w, &s);
        assert!(short.heading_spread > 10f64.to_radians(), "{short:?}");
        // The prediction itself carries the motion over.
        let moved = Prediction::from_odometry(
            &pose(1.0, 1.0, std::f64::consts::FRAC_PI_2),
            &start,
            &pose(1.0, 0.0, 0.0),
            &w,
            &s,
        );
        assert!((moved.pose.x - 1.0).abs() < 1e-12 && (moved.pose.y - 2.0).abs() < 1e-12);
        assert_eq!(moved.log_prior(&moved.pose), 0.0);
        let off = pose(
            moved.pose.x,
            moved.pose.y,
            moved.pose.theta + moved.heading_spread,
        );
        assert!(
            (moved.log_prior(&off) + 0.5).abs() < 1e-9,
            "one sigma is half a nat"
        );
    }
}
