//! Range scans, what a mapper consumes, and single cone readings, what the
//! MAP search (Table 9.3) consumes.
//!
//! A [`Scan`] is one sweep of a range sensor taken at one pose: a range and a
//! bearing per beam. It is validated once, when built, so that the mappers
//! never meet a NaN or a negative range half-way through an update.

use crate::error::{self, invalid, OccError, Result};
use crate::geometry::Pose;
use std::borrow::Cow;

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

    /// Every `stride`-th beam, starting with the first: the scan of a
    /// sensor with fewer, evenly spaced beams (a stride that divides the
    /// beam count keeps the spacing uniform all the way round). Stride 1
    /// is the scan itself, borrowed; a stride past the beam count keeps
    /// only the first beam. The beams kept were checked when this scan was
    /// built, so the thinned scan needs no second check.
    pub fn thinned(&self, stride: usize) -> Result<Cow<'_, Self>> {
        if stride == 0 {
            return Err(invalid("stride", 0, "a whole number of at least 1"));
        }
        if stride == 1 {
            return Ok(Cow::Borrowed(self));
        }
        Ok(Cow::Owned(Self {
            pose: self.pose,
            ranges: self.ranges.iter().step_by(stride).copied().collect(),
            bearings: self.bearings.iter().step_by(stride).copied().collect(),
        }))
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

    /// A 60-beam scan thinned to every third beam is the 20-beam scan of
    /// the same sensor: beam k of it is beam 3k of the full one.
    #[test]
    fn thinning_keeps_every_stride_th_beam_from_the_first() {
        let pose = Pose {
            x: 1.0,
            y: 2.0,
            theta: 0.5,
        };
        let step = std::f64::consts::TAU / 60.0;
        let ranges: Vec<f64> = (0..60).map(|i| 0.5 + 0.1 * i as f64).collect();
        let full = Scan::uniform(pose, ranges.clone(), 0.0, step).unwrap();

        let third = full.thinned(3).unwrap();
        assert_eq!(third.len(), 20);
        assert_eq!(third.pose(), pose);
        for k in 0..20 {
            assert_eq!(third.ranges()[k], ranges[3 * k]);
            assert_eq!(third.bearings()[k], full.bearings()[3 * k]);
        }
        let twenty = Scan::uniform(
            pose,
            (0..20).map(|k| ranges[3 * k]).collect(),
            0.0,
            3.0 * step,
        )
        .unwrap();
        for k in 0..20 {
            assert!((third.bearings()[k] - twenty.bearings()[k]).abs() < 1e-12);
        }

        assert!(matches!(full.thinned(1).unwrap(), Cow::Borrowed(s) if s == &full));
        let one = full.thinned(1000).unwrap();
        assert_eq!((one.ranges(), one.bearings()), (&ranges[..1], &[0.0][..]));
        let e = full.thinned(0).unwrap_err().to_string();
        assert!(e.contains("stride") && e.contains('0'), "{e}");
    }
}
