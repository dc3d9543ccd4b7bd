//! Poses: where a robot (and its sensor) stands, and angles wrapped to one turn.
//!
//! The bottom layer with the grid's geometry and the raster: everything else
//! places itself in the world through a [`Pose`].

use crate::error::{self, Result};
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

#[cfg(test)]
mod tests {
    use super::*;

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
