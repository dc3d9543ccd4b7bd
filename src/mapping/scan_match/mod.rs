//! Scan matching: what the scan-matched pose source ([`crate::poses`])
//! corrects its predictions with. The chapter assumes an oracle hands it
//! the poses; without one, dead reckoning wrecks the map
//! (docs/ARCHITECTURE.md, "Real logs"). A scan matcher corrects each
//! predicted pose by fitting the scan to the map built so far, before the
//! scan is integrated at the corrected pose.
//!
//! The matcher is the field's coarse-to-fine pair:
//!
//! 1. [`search`]: a correlative search (Olson 2009; the real-time
//!    correlative scan matcher of Hess et al. 2016) over a window of
//!    `(x, y, θ)` around the predicted pose, scored on a coarse copy of the
//!    map in which each cell holds the most occupied of the fine cells it
//!    covers ([`window`]), so that a coarse step cannot jump over a wall;
//! 2. [`refine`]: Gauss–Newton, damped as Levenberg–Marquardt does, on the
//!    interpolated map (Kohlbrecher et al. 2011, Hector SLAM), level by
//!    level from the coarse copy down to the map itself, from each of the
//!    search's best headings; on the map itself also from the prediction,
//!    the better fit winning. The map itself is read as a quadratic
//!    B-spline ([`crate::grid::sample::quadratic_bspline`]), smooth where
//!    a bilinear reading is flat, so that a fit lands between cell
//!    centres; the coarse levels bilinearly.
//!
//! The search window is as wide as the prediction's spread asks
//! ([`MatchSettings::window_for`]): wider after an in-place turn, whose
//! odometry can be tens of degrees off.
//!
//! Candidates are weighed against the prediction's prior, its spread
//! given by the odometry motion model of Table 5.6 ([`Prediction`]): a
//! weak fit does not overrule good odometry, and strong evidence corrects
//! bad odometry.
//!
//! [`ScanMatcher`] matches one scan against any grid ([`MatchMap`]: a grid
//! of any cell model); the pose source that advances scan by scan is
//! [`crate::poses::ScanMatching`].
//!
//! Everything is sequential `f64` arithmetic in a fixed order, so the same
//! inputs give the same poses bit for bit on every run and runtime.

mod match_map;
mod matcher;
mod points;
mod prediction;
pub mod refine;
pub mod search;
mod settings;
pub mod window;

pub use match_map::MatchMap;
pub use matcher::{MatchReport, ScanMatcher};
pub use points::ScanPoints;
pub use prediction::Prediction;
pub use settings::MatchSettings;

use crate::geometry::{wrap_angle, Pose};

/// The motion from `from` to `to`, expressed in `from`'s frame: `(forward,
/// left, turn)`, metres and radians. Composed onto another pose with
/// [`compose`], it carries that pose as the odometry carried `from`.
pub fn relative_motion(from: &Pose, to: &Pose) -> [f64; 3] {
    let (dx, dy) = (to.x - from.x, to.y - from.y);
    let (s, c) = from.theta.sin_cos();
    [
        c * dx + s * dy,
        -s * dx + c * dy,
        wrap_angle(to.theta - from.theta),
    ]
}

/// `pose` moved by `motion` given in its own frame ([`relative_motion`]).
pub fn compose(pose: &Pose, motion: [f64; 3]) -> Pose {
    let (s, c) = pose.theta.sin_cos();
    Pose {
        x: pose.x + c * motion[0] - s * motion[1],
        y: pose.y + s * motion[0] + c * motion[1],
        theta: wrap_angle(pose.theta + motion[2]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn composing_the_relative_motion_gives_the_second_pose_back() {
        let a = Pose {
            x: 1.0,
            y: -2.0,
            theta: 2.9,
        };
        let b = Pose {
            x: 0.4,
            y: -1.1,
            theta: -3.0,
        };
        let c = compose(&a, relative_motion(&a, &b));
        assert!((c.x - b.x).abs() < 1e-12 && (c.y - b.y).abs() < 1e-12);
        assert!(wrap_angle(c.theta - b.theta).abs() < 1e-12);
    }
}
