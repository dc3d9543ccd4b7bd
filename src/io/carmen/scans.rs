//! The compact store of a log's laser scans, [`LaserScans`]: what a map
//! build reads, whoever drives it (the page's session, the command-line
//! export, workload W1 of [`crate::bench::intel`]).

use super::loader::LogLoader;
use super::parse::LaserRecord;
use crate::error::{OccError, Result};
use crate::geometry::Pose;
use crate::sensors::Scan;
use std::io::Read;

/// Mebibytes, for messages.
fn mib(bytes: usize) -> String {
    format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64)
}

/// The laser scans of a log, kept compactly for a map build: all ranges in
/// one `f32` buffer, one pose, angle pair and maximum range per scan.
///
/// Ranges are kept in `f32` (4 bytes a beam; CARMEN writes centimetres,
/// and `f32` rounds an 80 m reading by at most 4 µm). Every reader of the
/// store gets the same numbers: [`Self::scan`] widens each `f32` to the
/// `f64` of equal value (exact), so the page, the export and W1 map the
/// same readings. (W1's counts are the same as when it mapped the text's
/// `f64` readings: 8,181,340 cell updates, bit-identical cells.)
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LaserScans {
    poses: Vec<Pose>,
    /// The odometry pose of each scan (FLASER's `odom_*` fields; the laser
    /// pose where the line has none).
    odometry: Vec<Pose>,
    /// `[first_bearing, bearing_step]`, radians.
    angles: Vec<[f64; 2]>,
    /// The laser's own maximum range, metres; infinite when the log does
    /// not say (FLASER). Kept in `f32` like the ranges, so that "at or
    /// beyond the maximum" is decided the same way after rounding.
    max_range: Vec<f32>,
    /// Scan `k`'s ranges are `ranges[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<usize>,
    ranges: Vec<f32>,
    lines: Vec<usize>,
}

impl LaserScans {
    pub fn new() -> Self {
        Self::default()
    }

    /// Reads every laser record of a log (gzip or plain) through
    /// [`LogLoader`], within the default budget.
    pub fn read<R: Read>(reader: R) -> Result<Self> {
        LogLoader::new(reader).read_to_end().map(|(scans, _)| scans)
    }

    /// Bytes kept per scan besides its ranges: pose, odometry, angles, maximum range,
    /// offset and line number.
    pub const SCAN_BYTES: usize = 2 * std::mem::size_of::<Pose>()
        + std::mem::size_of::<[f64; 2]>()
        + std::mem::size_of::<f32>()
        + 2 * std::mem::size_of::<usize>();

    /// Bytes the scans take (by the same reckoning as the budget).
    pub fn kept_bytes(&self) -> usize {
        self.ranges.len() * std::mem::size_of::<f32>() + self.len() * Self::SCAN_BYTES
    }

    /// Grows `v` to hold `more` more items: doubling, but never past
    /// `most` items (the budget), and without aborting when memory is short.
    fn grow<T>(v: &mut Vec<T>, more: usize, most: usize) -> std::result::Result<(), ()> {
        let need = v.len() + more;
        if need <= v.capacity() {
            return Ok(());
        }
        let target = need.max(v.capacity().saturating_mul(2)).min(most.max(need));
        v.try_reserve_exact(target - v.len()).map_err(|_| ())
    }

    /// Keeps `record`, unless the scans would then take more than `budget`
    /// bytes: then an error naming the line, the budget and what keeping
    /// the log so far would need, and nothing is added. Room is reserved
    /// before anything is written (`try_reserve`), so an allocation that
    /// fails is the same clear error, not an abort. A record the store
    /// could not give back as a [`Scan`] (a reading past `f32`, a pose or
    /// angle that is not finite: the reader refuses these already) is
    /// refused too, so that every scan kept is mapped.
    pub fn push(&mut self, record: &LaserRecord, budget: usize) -> Result<()> {
        let beams = record.ranges.len();
        let need = self.kept_bytes() + beams * std::mem::size_of::<f32>() + Self::SCAN_BYTES;
        let refuse = |what: String| OccError::Parse {
            line: record.line,
            reason: what,
        };
        if let Some(why) = Self::unmappable(record) {
            return Err(refuse(why));
        }
        if need > budget {
            return Err(refuse(format!(
                "the log is too large to keep: its scans up to this line need {} ({} scans, {} beams), \
                 over the budget of {} for a log's scans",
                mib(need),
                self.len() + 1,
                self.beams() + beams,
                mib(budget)
            )));
        }
        let scans_most = budget / Self::SCAN_BYTES + 1;
        let beams_most = budget / std::mem::size_of::<f32>();
        let n = self.len();
        let ok = Self::grow(&mut self.poses, 1, scans_most).is_ok()
            && Self::grow(&mut self.odometry, 1, scans_most).is_ok()
            && Self::grow(&mut self.angles, 1, scans_most).is_ok()
            && Self::grow(&mut self.max_range, 1, scans_most).is_ok()
            && Self::grow(
                &mut self.offsets,
                if n == 0 { 2 } else { 1 },
                scans_most + 1,
            )
            .is_ok()
            && Self::grow(&mut self.lines, 1, scans_most).is_ok()
            && Self::grow(&mut self.ranges, beams, beams_most).is_ok();
        if !ok {
            return Err(refuse(format!(
                "out of memory keeping the log's scans: {} needed ({} scans so far)",
                mib(need),
                n + 1
            )));
        }
        if self.offsets.is_empty() {
            self.offsets.push(0);
        }
        self.poses.push(record.pose);
        self.odometry.push(record.odometry.unwrap_or(record.pose));
        self.angles
            .push([record.first_bearing, record.bearing_step]);
        self.max_range
            .push(record.max_range.map_or(f32::INFINITY, |m| m as f32));
        self.ranges.extend(record.ranges.iter().map(|&r| r as f32));
        self.offsets.push(self.ranges.len());
        self.lines.push(record.line);
        Ok(())
    }

    /// Why `record` would not give back a [`Scan`], if it would not.
    fn unmappable(record: &LaserRecord) -> Option<String> {
        if let Some(i) = record
            .ranges
            .iter()
            .position(|&r| !(r >= 0.0 && (r as f32).is_finite()))
        {
            let r = record.ranges[i];
            return Some(format!(
                "range {} = {r:e} cannot be kept as a reading",
                i + 1
            ));
        }
        let p = record.pose;
        let last = record.first_bearing
            + record.ranges.len().saturating_sub(1) as f64 * record.bearing_step;
        let finite = [p.x, p.y, p.theta, record.bearing_step, last]
            .iter()
            .all(|v| v.is_finite());
        if record.ranges.is_empty() {
            Some("the scan has no beams".into())
        } else if !finite {
            Some("the scan's pose or angles are not finite numbers".into())
        } else {
            None
        }
    }

    /// Number of scans.
    pub fn len(&self) -> usize {
        self.poses.len()
    }

    pub fn is_empty(&self) -> bool {
        self.poses.is_empty()
    }

    /// Number of beams over all scans.
    pub fn beams(&self) -> usize {
        self.ranges.len()
    }

    /// The laser pose of scan `k`.
    pub fn pose(&self, k: usize) -> Option<Pose> {
        self.poses.get(k).copied()
    }

    /// Every scan's laser pose, in order.
    pub fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// The log's own odometry, one pose per scan, when it is raw: `None`
    /// when it repeats the laser poses (a corrected log's odometry fields
    /// copy its corrected poses; ROBOTLASER1 lines carry none).
    pub fn raw_odometry(&self) -> Option<&[Pose]> {
        (self.odometry != self.poses).then_some(&self.odometry[..])
    }

    /// Puts the scans at other poses (a dead-reckoned path), one per scan:
    /// an error, and nothing changed, when the count differs.
    pub fn set_poses(&mut self, poses: &[Pose]) -> Result<()> {
        if poses.len() != self.poses.len() {
            let given = format!("{} poses for {} scans", poses.len(), self.poses.len());
            return Err(crate::error::invalid("poses", given, "one pose per scan"));
        }
        self.poses.copy_from_slice(poses);
        Ok(())
    }

    /// The line of the file scan `k` came from.
    pub fn line(&self, k: usize) -> Option<usize> {
        self.lines.get(k).copied()
    }

    /// The laser's own maximum range for scan `k` (infinite when unknown).
    pub fn max_range(&self, k: usize) -> Option<f64> {
        self.max_range.get(k).map(|&m| m as f64)
    }

    fn raw(&self, k: usize) -> Option<(&[f32], [f64; 2], Pose)> {
        let (&a, &b) = (self.offsets.get(k)?, self.offsets.get(k + 1)?);
        Some((
            self.ranges.get(a..b)?,
            *self.angles.get(k)?,
            *self.poses.get(k)?,
        ))
    }

    /// Scan `k` as the mappers take it: `None` only past the end (every
    /// scan [`Self::push`] kept is a valid [`Scan`]; [`Self::set_poses`]
    /// could put one at a pose that is not, which the sessions check).
    pub fn scan(&self, k: usize) -> Option<Scan> {
        let (ranges, [first, step], pose) = self.raw(k)?;
        let ranges = ranges.iter().map(|&r| r as f64).collect();
        Scan::uniform(pose, ranges, first, step).ok()
    }

    /// The box `[min_x, min_y, max_x, max_y]` (metres) holding every laser
    /// pose and every beam endpoint closer than `range_cap` (and than the
    /// laser's own maximum range: a no-return has no endpoint), or `None`
    /// when there are no scans. (Not the grid's extent: the grid built
    /// over it adds a margin and snaps to cells.)
    pub fn endpoint_bounds(&self, range_cap: f64) -> Option<[f64; 4]> {
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut grow = |x: f64, y: f64| {
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        };
        for k in 0..self.len() {
            let Some((ranges, [first, step], pose)) = self.raw(k) else {
                continue;
            };
            grow(pose.x, pose.y);
            let max = self.max_range[k];
            for (i, &r) in ranges.iter().enumerate() {
                if r < max && (r as f64) < range_cap {
                    let (x, y) = pose.point_at(r as f64, first + i as f64 * step);
                    grow(x, y);
                }
            }
        }
        (!self.is_empty()).then_some(b)
    }
}
