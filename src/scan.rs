//! Poses and range scans: what a mapper consumes.
//!
//! A [`Scan`] is one sweep of a range sensor taken at one pose: a range and a
//! bearing per beam. It is validated once, when built, so that the mappers
//! never meet a NaN or a negative range half-way through an update.

use crate::error::{self, invalid, OccError, Result};
use nalgebra::{Isometry2, Point2, Vector2};

/// A robot (sensor) pose in the world: metres and radians, counter-clockwise
/// from the x axis. Kept in `f64`: a 50 m map at 5 cm needs it.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Pose {
    pub x: f64,
    pub y: f64,
    pub theta: f64,
}

impl Pose {
    pub fn new(x: f64, y: f64, theta: f64) -> Result<Self> {
        Ok(Self {
            x: error::finite("pose.x", x)?,
            y: error::finite("pose.y", y)?,
            theta: error::finite("pose.theta", theta)?,
        })
    }

    pub fn isometry(&self) -> Isometry2<f64> {
        Isometry2::new(Vector2::new(self.x, self.y), self.theta)
    }

    /// The world point at range `r` (m) along bearing `b` (rad, relative to
    /// the heading).
    #[inline]
    pub fn point_at(&self, r: f64, b: f64) -> (f64, f64) {
        let a = self.theta + b;
        (self.x + r * a.cos(), self.y + r * a.sin())
    }

    /// A world point seen from this pose, as `(x, y)` in the sensor frame.
    pub fn to_local(&self, x: f64, y: f64) -> (f64, f64) {
        let p = self.isometry().inverse_transform_point(&Point2::new(x, y));
        (p.x, p.y)
    }
}

/// Wraps an angle to `(-pi, pi]`.
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let mut w = a % TAU;
    if w > PI {
        w -= TAU;
    } else if w <= -PI {
        w += TAU;
    }
    w
}

/// One range scan: `ranges[i]` metres measured along `bearings[i]` radians
/// (relative to the pose's heading).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Scan {
    pose: Pose,
    ranges: Vec<f64>,
    bearings: Vec<f64>,
}

impl Scan {
    /// Checks everything a mapper relies on: at least one beam, as many
    /// bearings as ranges, every range finite and non-negative, every bearing
    /// finite.
    pub fn new(pose: Pose, ranges: Vec<f64>, bearings: Vec<f64>) -> Result<Self> {
        Pose::new(pose.x, pose.y, pose.theta)?;
        if ranges.is_empty() {
            return Err(invalid("ranges", "[]", "at least one beam"));
        }
        if bearings.len() != ranges.len() {
            return Err(OccError::LengthMismatch {
                field: "bearings".into(),
                expected: ranges.len(),
                found: bearings.len(),
            });
        }
        // The field name is formatted only on error: a log holds millions
        // of ranges.
        if let Some((i, &r)) = ranges
            .iter()
            .enumerate()
            .find(|(_, r)| !(r.is_finite() && **r >= 0.0))
        {
            return Err(invalid(
                &format!("ranges[{i}]"),
                r,
                "a finite number of at least 0",
            ));
        }
        if let Some((i, &b)) = bearings.iter().enumerate().find(|(_, b)| !b.is_finite()) {
            return Err(invalid(&format!("bearings[{i}]"), b, "a finite number"));
        }
        Ok(Self {
            pose,
            ranges,
            bearings,
        })
    }

    /// A scan whose beam `i` lies at bearing `first_bearing + i * step`.
    pub fn uniform(pose: Pose, ranges: Vec<f64>, first_bearing: f64, step: f64) -> Result<Self> {
        error::finite("first_bearing", first_bearing)?;
        error::finite("bearing_step", step)?;
        let bearings = (0..ranges.len())
            .map(|i| first_bearing + i as f64 * step)
            .collect();
        Self::new(pose, ranges, bearings)
    }

    pub fn pose(&self) -> Pose {
        self.pose
    }
    pub fn ranges(&self) -> &[f64] {
        &self.ranges
    }
    pub fn bearings(&self) -> &[f64] {
        &self.bearings
    }
    pub fn len(&self) -> usize {
        self.ranges.len()
    }
    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }
    /// The same beams seen from another pose (dead reckoning vs. oracle).
    pub fn with_pose(&self, pose: Pose) -> Result<Self> {
        let pose = Pose::new(pose.x, pose.y, pose.theta)?;
        Ok(Self {
            pose,
            ..self.clone()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_nan_negative_and_mismatched_beams() {
        let p = Pose::default();
        let e = Scan::new(p, vec![1.0, f64::NAN], vec![0.0, 0.1]).unwrap_err();
        assert!(e.to_string().contains("ranges[1]") && e.to_string().contains("NaN"));
        let e = Scan::new(p, vec![1.0, -2.0], vec![0.0, 0.1]).unwrap_err();
        assert!(e.to_string().contains("-2"));
        let e = Scan::new(p, vec![1.0], vec![0.0, 0.1]).unwrap_err();
        assert!(e.to_string().contains("bearings"));
        assert!(Scan::new(p, vec![], vec![]).is_err());
        assert!(Scan::new(p, vec![f64::INFINITY], vec![0.0]).is_err());
        let bad_pose = Pose {
            x: f64::NAN,
            y: 0.0,
            theta: 0.0,
        };
        assert!(Scan::new(bad_pose, vec![1.0], vec![0.0])
            .unwrap_err()
            .to_string()
            .contains("pose.x"));
    }

    #[test]
    fn wrap_angle_stays_in_half_open_interval() {
        use std::f64::consts::PI;
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn to_local_inverts_point_at() {
        let p = Pose {
            x: 1.0,
            y: -2.0,
            theta: 0.7,
        };
        let (x, y) = p.point_at(3.0, 0.2);
        let (lx, ly) = p.to_local(x, y);
        assert!((lx - 3.0 * 0.2f64.cos()).abs() < 1e-12 && (ly - 3.0 * 0.2f64.sin()).abs() < 1e-12);
    }
}
