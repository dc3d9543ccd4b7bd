//! Range scans, what a mapper consumes, and single cone readings, what the
//! MAP search (Table 9.3) consumes.
//!
//! A [`Scan`] is one sweep of a range sensor taken at one pose: a range and a
//! bearing per beam. It is validated once, when built, so that the mappers
//! never meet a NaN or a negative range half-way through an update.

use crate::error::{self, invalid, OccError, Result};
use crate::geometry::Pose;

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

/// One range reading of a cone sensor: the sensor's pose, the cone axis's
/// bearing relative to the heading (radians), and the reading (metres).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ConeBeam {
    pub pose: Pose,
    pub bearing: f64,
    pub range: f64,
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
}
