//! Where things move in a scene: the robot's lap ([`LapPath`], a closed
//! loop of waypoints driven at constant speed, turning in place at each
//! corner) and a person walking back and forth ([`WalkerParams`]).
//!
//! Plain serde data; the true pose at any time is a pure function of it.

use crate::error::{self, invalid, Result};
use crate::geometry::{wrap_angle, Pose};

/// A closed lap through `waypoints` (metres): the robot starts on the first
/// waypoint facing the second, drives each leg at `speed` (m/s), turns in
/// place at `turn_rate` (rad/s) by the shorter way at every corner, and
/// after the last leg back to the start turns to its starting heading, so
/// that lap after lap repeats exactly.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LapPath {
    pub waypoints: Vec<[f64; 2]>,
    /// Driving speed, metres per second.
    pub speed: f64,
    /// Turning rate in place, radians per second.
    pub turn_rate: f64,
}

/// One piece of a lap: a turn in place or a straight drive.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Leg {
    Turn {
        at: [f64; 2],
        from: f64,
        by: f64,
        seconds: f64,
    },
    Drive {
        from: [f64; 2],
        to: [f64; 2],
        heading: f64,
        seconds: f64,
    },
}

impl Leg {
    fn seconds(&self) -> f64 {
        match *self {
            Leg::Turn { seconds, .. } | Leg::Drive { seconds, .. } => seconds,
        }
    }
}

impl LapPath {
    /// Checks the lap: at least two waypoints, all finite, no two
    /// consecutive ones (cyclically) closer than 1 mm, positive speed and
    /// turn rate.
    pub fn validate(&self) -> Result<()> {
        if self.waypoints.len() < 2 {
            return Err(invalid(
                "path.waypoints",
                self.waypoints.len(),
                "at least 2 waypoints",
            ));
        }
        for (i, w) in self.waypoints.iter().enumerate() {
            error::finite(&format!("path.waypoints[{i}].x"), w[0])?;
            error::finite(&format!("path.waypoints[{i}].y"), w[1])?;
        }
        let n = self.waypoints.len();
        for i in 0..n {
            let (a, b) = (self.waypoints[i], self.waypoints[(i + 1) % n]);
            if (b[0] - a[0]).hypot(b[1] - a[1]) < 1e-3 {
                return Err(invalid(
                    &format!("path.waypoints[{}]", (i + 1) % n),
                    format!("({}, {})", b[0], b[1]),
                    "a waypoint at least 1 mm from the one before it",
                ));
            }
        }
        error::positive("path.speed", self.speed)?;
        error::positive("path.turn_rate", self.turn_rate)?;
        Ok(())
    }

    /// The lap as legs: drive, turn, drive, turn, ... ending with the turn
    /// back to the starting heading.
    fn legs(&self) -> Vec<Leg> {
        let n = self.waypoints.len();
        let heading_of = |i: usize| {
            let (a, b) = (self.waypoints[i], self.waypoints[(i + 1) % n]);
            (b[1] - a[1]).atan2(b[0] - a[0])
        };
        let mut legs = Vec::with_capacity(2 * n);
        for i in 0..n {
            let (from, to) = (self.waypoints[i], self.waypoints[(i + 1) % n]);
            let heading = heading_of(i);
            let length = (to[0] - from[0]).hypot(to[1] - from[1]);
            legs.push(Leg::Drive {
                from,
                to,
                heading,
                seconds: length / self.speed,
            });
            let by = wrap_angle(heading_of((i + 1) % n) - heading);
            if by != 0.0 {
                legs.push(Leg::Turn {
                    at: to,
                    from: heading,
                    by,
                    seconds: by.abs() / self.turn_rate,
                });
            }
        }
        legs
    }

    /// Seconds one lap takes.
    pub fn lap_seconds(&self) -> f64 {
        self.legs().iter().map(Leg::seconds).sum()
    }

    /// Metres driven in one lap.
    pub fn lap_length(&self) -> f64 {
        let n = self.waypoints.len();
        (0..n)
            .map(|i| {
                let (a, b) = (self.waypoints[i], self.waypoints[(i + 1) % n]);
                (b[0] - a[0]).hypot(b[1] - a[1])
            })
            .sum()
    }

    /// The true pose `t` seconds after the start (laps repeat).
    pub fn pose_at(&self, t: f64) -> Pose {
        let legs = self.legs();
        let period: f64 = legs.iter().map(Leg::seconds).sum();
        let mut t = if period > 0.0 {
            t.rem_euclid(period)
        } else {
            0.0
        };
        for leg in &legs {
            let s = leg.seconds();
            if t <= s {
                return leg_pose(leg, if s > 0.0 { t / s } else { 1.0 });
            }
            t -= s;
        }
        // Rounding left a sliver past the last leg: that is the start pose.
        legs.first()
            .map_or(Pose::default(), |leg| leg_pose(leg, 0.0))
    }
}

/// The pose a fraction `f` in `[0, 1]` of the way through `leg`.
fn leg_pose(leg: &Leg, f: f64) -> Pose {
    match *leg {
        Leg::Turn { at, from, by, .. } => Pose {
            x: at[0],
            y: at[1],
            theta: wrap_angle(from + f * by),
        },
        Leg::Drive {
            from, to, heading, ..
        } => Pose {
            x: from[0] + f * (to[0] - from[0]),
            y: from[1] + f * (to[1] - from[1]),
            theta: heading,
        },
    }
}

/// A person walking back and forth along a straight line: a square of side
/// `size` metres whose centre runs from `from` to `to` (metres) at `speed`,
/// stands still for `pause` seconds, walks back, stands again, and so on.
/// `phase` says where in that cycle the walk starts. Standing still is what
/// leaves a strong ghost: the cells under a standing person collect
/// occupied evidence scan after scan.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WalkerParams {
    pub size: f64,
    pub from: [f64; 2],
    pub to: [f64; 2],
    /// Walking speed, metres per second.
    pub speed: f64,
    /// Seconds spent standing at each end.
    pub pause: f64,
    /// Where the walk starts, as a fraction of one cycle (there and back
    /// with both pauses) in `[0, 1)`.
    pub phase: f64,
}

impl WalkerParams {
    pub fn validate(&self) -> Result<()> {
        error::positive("person.size", self.size)?;
        for (field, v) in [
            ("person.from.x", self.from[0]),
            ("person.from.y", self.from[1]),
            ("person.to.x", self.to[0]),
            ("person.to.y", self.to[1]),
        ] {
            error::finite(field, v)?;
        }
        error::positive("person.speed", self.speed)?;
        error::non_negative("person.pause", self.pause)?;
        if !(self.phase >= 0.0 && self.phase < 1.0) {
            return Err(invalid("person.phase", self.phase, "a fraction in [0, 1)"));
        }
        Ok(())
    }

    /// Centre of the person `t` seconds after the start, metres.
    pub fn center_at(&self, t: f64) -> [f64; 2] {
        let length = (self.to[0] - self.from[0]).hypot(self.to[1] - self.from[1]);
        let walk = length / self.speed;
        let cycle = 2.0 * (walk + self.pause);
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN cycle stays at the start
        if !(cycle > 0.0) {
            return self.from;
        }
        // Seconds into the cycle: walk out, stand at `to`, walk back,
        // stand at `from`.
        let s = (t + self.phase * cycle).rem_euclid(cycle);
        let f = if s < walk {
            s / walk
        } else if s < walk + self.pause {
            1.0
        } else if s < 2.0 * walk + self.pause {
            1.0 - (s - walk - self.pause) / walk
        } else {
            0.0
        };
        [
            self.from[0] + f * (self.to[0] - self.from[0]),
            self.from[1] + f * (self.to[1] - self.from[1]),
        ]
    }

    /// The person's footprint `t` seconds after the start.
    pub fn footprint_at(&self, t: f64) -> crate::world::Rect {
        let [cx, cy] = self.center_at(t);
        let h = 0.5 * self.size;
        crate::world::Rect::new(cx - h, cy - h, cx + h, cy + h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::odometry::OdometryParams;
    use rand::rngs::StdRng;
    use rand::SeedableRng;
    use std::f64::consts::PI;

    fn degrees(rad: f64) -> f64 {
        rad * 180.0 / PI
    }

    fn square() -> LapPath {
        LapPath {
            waypoints: vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]],
            speed: 0.5,
            turn_rate: PI / 2.0,
        }
    }

    #[test]
    fn lap_drives_each_leg_then_turns_in_place() {
        let p = square();
        p.validate().unwrap();
        // 6 m at 0.5 m/s plus four quarter turns of one second each.
        assert!((p.lap_seconds() - 16.0).abs() < 1e-12);
        let a = p.pose_at(2.0);
        assert!((a.x - 1.0).abs() < 1e-12 && a.y == 0.0 && a.theta == 0.0);
        let turning = p.pose_at(4.5);
        assert!((turning.x - 2.0).abs() < 1e-12);
        assert!(
            (turning.theta - PI / 4.0).abs() < 1e-12,
            "half way through a left turn"
        );
        let again = p.pose_at(16.0 + 2.0);
        assert!((again.x - a.x).abs() < 1e-9, "laps repeat");
    }

    #[test]
    fn lap_rejects_repeated_waypoints_and_bad_speeds() {
        let mut p = square();
        p.waypoints[1] = p.waypoints[0];
        assert!(p
            .validate()
            .unwrap_err()
            .to_string()
            .contains("waypoints[1]"));
        let mut p = square();
        p.speed = 0.0;
        assert!(p.validate().unwrap_err().to_string().contains("path.speed"));
        let mut p = square();
        p.waypoints = vec![[0.0, 0.0]];
        assert!(p.validate().is_err());
        let mut p = square();
        p.waypoints[2][1] = f64::NAN;
        assert!(p
            .validate()
            .unwrap_err()
            .to_string()
            .contains("waypoints[2].y"));
    }

    #[test]
    fn noiseless_odometry_reproduces_the_true_motion() {
        let odo = OdometryParams {
            alpha: [0.0; 4],
            heading_drift: 0.0,
            turn_scale: 0.0,
        };
        let mut rng = StdRng::seed_from_u64(9);
        let p = square();
        let mut estimate = p.pose_at(0.0);
        let mut prev = estimate;
        for k in 1..=160 {
            let truth = p.pose_at(k as f64 * 0.1);
            estimate = odo.dead_reckon(&estimate, &prev, &truth, &mut rng);
            prev = truth;
        }
        let end = p.pose_at(16.0);
        assert!((estimate.x - end.x).abs() < 1e-9 && (estimate.y - end.y).abs() < 1e-9);
        assert!(wrap_angle(estimate.theta - end.theta).abs() < 1e-9);
    }

    #[test]
    fn heading_drift_bends_a_straight_drive() {
        let odo = OdometryParams {
            alpha: [0.0; 4],
            heading_drift: 0.02,
            turn_scale: 0.0,
        };
        let mut rng = StdRng::seed_from_u64(9);
        let mut estimate = Pose::default();
        let mut prev = Pose::default();
        for k in 1..=100 {
            let truth = Pose::new(0.05 * k as f64, 0.0, 0.0).unwrap();
            estimate = odo.dead_reckon(&estimate, &prev, &truth, &mut rng);
            prev = truth;
        }
        // 5 m at 0.02 rad/m: 0.1 rad of heading error, and the path curls
        // left by about half of that times the distance.
        assert!(
            (estimate.theta - 0.1).abs() < 1e-9,
            "{}",
            degrees(estimate.theta)
        );
        assert!(estimate.y > 0.2 && estimate.y < 0.3, "{}", estimate.y);
    }

    #[test]
    fn walker_goes_back_and_forth_pausing_at_each_end() {
        let w = WalkerParams {
            size: 0.4,
            from: [1.0, 2.0],
            to: [5.0, 2.0],
            speed: 1.0,
            pause: 1.0,
            phase: 0.0,
        };
        assert_eq!(w.center_at(0.0), [1.0, 2.0]);
        assert_eq!(w.center_at(4.0), [5.0, 2.0]);
        assert_eq!(w.center_at(4.9), [5.0, 2.0], "standing at the far end");
        assert_eq!(w.center_at(7.0), [3.0, 2.0]);
        assert_eq!(w.center_at(9.5), [1.0, 2.0], "standing at the near end");
        assert_eq!(w.center_at(10.0 + 2.0), [3.0, 2.0], "the cycle repeats");
        let r = w.footprint_at(2.0);
        assert!((r.max_x - r.min_x - 0.4).abs() < 1e-12 && r.contains(3.0, 2.0));
        assert!(WalkerParams { phase: 1.0, ..w }.validate().is_err());
    }
}
