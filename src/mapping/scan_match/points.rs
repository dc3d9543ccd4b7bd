//! The points a scan is matched with: its returns as endpoints in the
//! sensor's frame. A no-return (a reading at or beyond the laser's own
//! maximum or the matcher's range) says where no wall is, not where one
//! is, so it has no endpoint to fit to the map.

use super::MatchSettings;
use crate::geometry::Pose;
use crate::sensors::Scan;

/// A scan's returns as `(x, y)` in the sensor's frame (x ahead), metres.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScanPoints {
    points: Vec<[f64; 2]>,
    /// The farthest point's range, metres.
    reach: f64,
}

impl ScanPoints {
    /// The returns of `scan` with range in `[min_range, max_range]` and
    /// below `laser_max` (the laser's own maximum range, infinite when the
    /// log does not say), thinned evenly to at most `max_points`.
    pub fn of(scan: &Scan, laser_max: f64, settings: &MatchSettings) -> Self {
        let mut points = Self::default();
        points.fill(scan, laser_max, settings);
        points
    }

    /// [`Self::of`] into this buffer (a matcher keeps one between scans).
    pub fn fill(&mut self, scan: &Scan, laser_max: f64, settings: &MatchSettings) {
        self.points.clear();
        self.reach = 0.0;
        let returns =
            scan.ranges().iter().zip(scan.bearings()).filter(|(&r, _)| {
                r >= settings.min_range && r <= settings.max_range && r < laser_max
            });
        let count = returns.clone().count();
        // Every k-th of them, k = ceil(count / max_points): evenly spread,
        // and the first return is always kept (deterministic).
        let stride = count.div_ceil(settings.max_points.max(1)).max(1);
        for (&r, &b) in returns.step_by(stride) {
            let (s, c) = b.sin_cos();
            self.points.push([r * c, r * s]);
            self.reach = self.reach.max(r);
        }
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
    /// The points, sensor frame, metres.
    pub fn points(&self) -> &[[f64; 2]] {
        &self.points
    }
    /// The farthest point's range, metres (0 without points).
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// The points into `out`, each kept only when it lies at least
    /// `spacing` metres from the last point kept (in scan order): a level
    /// of cells `2 spacing` wide then sees about two points per cell along
    /// a wall, however close to the sensor the wall is, while the sparse
    /// far returns, which pin the heading, are all kept.
    pub fn thinned(&self, spacing: f64, out: &mut Vec<[f64; 2]>) {
        out.clear();
        let s2 = spacing * spacing;
        for &p in &self.points {
            let far = out
                .last()
                .is_none_or(|q: &[f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) >= s2);
            if far {
                out.push(p);
            }
        }
    }

    /// Point `p` (sensor frame) in the world, the sensor at `pose`.
    #[inline]
    pub fn to_world(pose: &Pose, (sin, cos): (f64, f64), p: [f64; 2]) -> [f64; 2] {
        [
            pose.x + cos * p[0] - sin * p[1],
            pose.y + sin * p[0] + cos * p[1],
        ]
    }
}
