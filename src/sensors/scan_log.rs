//! A log's laser scans in one format-neutral store, [`ScanLog`]: what a
//! map build and every pose source read, whichever file format the scans
//! came from (a reader under `crate::io` hands each scan over as a
//! [`ScanRecord`]). Per scan: the laser pose the log puts it at, the
//! ranges and the beams' geometry, the laser's own maximum range, the
//! stamp, where in the file it came from; per log: the laser's mount on
//! the robot, and whether its poses are reference poses (a corrected log's)
//! and whether it carries odometry of its own.

use crate::error::{invalid, Result};
use crate::geometry::Pose;
use crate::sensors::Scan;

/// Mebibytes, for messages.
fn mib(bytes: usize) -> String {
    format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64)
}

/// One scan as a log's reader hands it over, in the log's own terms
/// turned into the store's: metres, radians, seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanRecord<'a> {
    /// Where in the file the scan came from (a CARMEN log's line, a bag's
    /// message), counted from 1 in the format's own unit.
    pub origin: usize,
    /// When the scan was taken, seconds, when the log says.
    pub stamp: Option<f64>,
    /// The laser pose the log puts the scan at: its reference pose when it
    /// has one (a corrected log's), else where its odometry puts the laser.
    pub pose: Pose,
    /// The laser pose by the log's own odometry, when the record has one.
    pub odometry: Option<Pose>,
    /// Ranges, metres; beam `i` lies at `first_bearing + i * bearing_step`
    /// from the pose's heading. A NaN is no measurement at that bearing (a
    /// ROS 2 bag's too-close or invalid reading, REP 117): kept in its
    /// place, and left out of the scan [`ScanLog::scan`] gives back, so
    /// that it neither marks nor clears a cell.
    pub ranges: &'a [f64],
    pub first_bearing: f64,
    pub bearing_step: f64,
    /// The laser's own maximum range, metres, when the log says: a reading
    /// at or beyond it is a no-return.
    pub max_range: Option<f64>,
}

/// What a log's poses are, as its reader found them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LogPoseKinds {
    /// True when [`ScanLog::poses`] are reference poses (another estimator's
    /// corrected path, the "pose oracle" of the chapter), not odometry.
    pub reference: bool,
    /// True when the log's odometry is its own raw odometry, independent
    /// of its reference poses ([`ScanLog::odometry`]).
    pub odometry: bool,
}

/// The laser scans of a log, kept compactly for a map build: all ranges in
/// one `f32` buffer, one pose, angle pair, maximum range, stamp and origin
/// per scan.
///
/// Ranges are kept in `f32` (4 bytes a beam; CARMEN writes centimetres,
/// and `f32` rounds an 80 m reading by at most 4 µm). Every reader of the
/// store gets the same numbers: [`Self::scan`] widens each `f32` to the
/// `f64` of equal value (exact), so the page, the export and W1 map the
/// same readings. (W1's counts are the same as when it mapped the text's
/// `f64` readings: 8,181,340 cell updates, bit-identical cells.)
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScanLog {
    poses: Vec<Pose>,
    /// The odometry's laser pose of each scan (the scan's pose where the
    /// record has none).
    odometry: Vec<Pose>,
    /// `[first_bearing, bearing_step]`, radians.
    angles: Vec<[f64; 2]>,
    /// The laser's own maximum range, metres; infinite when the log does
    /// not say. Kept in `f32` like the ranges, so that "at or beyond the
    /// maximum" is decided the same way after rounding.
    max_range: Vec<f32>,
    /// Scan `k`'s ranges are `ranges[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<usize>,
    ranges: Vec<f32>,
    /// Seconds, where the log gives a stamp.
    stamps: Vec<Option<f64>>,
    origins: Vec<usize>,
    kinds: LogPoseKinds,
    /// The laser's pose in the robot's frame (identity where the log gives
    /// laser poses directly).
    mount: Pose,
    /// What the format calls the unit [`ScanRecord::origin`] counts
    /// (`"line"`, `"message"`), for messages.
    unit: &'static str,
}

impl ScanLog {
    /// An empty log whose records are counted in `unit`s of the file
    /// (`"line"` for a text log).
    pub fn new(unit: &'static str) -> Self {
        Self {
            unit,
            ..Self::default()
        }
    }

    /// Bytes kept per scan besides its ranges: pose, odometry, angles,
    /// maximum range, offset, stamp and origin.
    pub const SCAN_BYTES: usize = 2 * std::mem::size_of::<Pose>()
        + std::mem::size_of::<[f64; 2]>()
        + std::mem::size_of::<f32>()
        + std::mem::size_of::<Option<f64>>()
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
    /// bytes: then the reason (the budget and what keeping the log so far
    /// would need), for the reader to name the record by, and nothing is
    /// added. Room is reserved before anything is written (`try_reserve`),
    /// so an allocation that fails is the same clear refusal, not an
    /// abort. A record the store could not give back as a [`Scan`] (a
    /// reading past `f32`, a pose or angle that is not finite) is refused
    /// too, so that every scan kept is mapped.
    pub fn push(
        &mut self,
        record: &ScanRecord<'_>,
        budget: usize,
    ) -> std::result::Result<(), String> {
        let beams = record.ranges.len();
        let need = self.kept_bytes() + beams * std::mem::size_of::<f32>() + Self::SCAN_BYTES;
        if let Some(why) = Self::unmappable(record) {
            return Err(why);
        }
        if need > budget {
            return Err(format!(
                "the log is too large to keep: its scans up to this {} need {} ({} scans, {} beams), \
                 over the budget of {} for a log's scans",
                self.unit,
                mib(need),
                self.len() + 1,
                self.beams() + beams,
                mib(budget)
            ));
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
            && Self::grow(&mut self.stamps, 1, scans_most).is_ok()
            && Self::grow(&mut self.origins, 1, scans_most).is_ok()
            && Self::grow(&mut self.ranges, beams, beams_most).is_ok();
        if !ok {
            return Err(format!(
                "out of memory keeping the log's scans: {} needed ({} scans so far)",
                mib(need),
                n + 1
            ));
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
        self.stamps.push(record.stamp);
        self.origins.push(record.origin);
        Ok(())
    }

    /// Why `record` would not give back a [`Scan`], if it would not.
    fn unmappable(record: &ScanRecord<'_>) -> Option<String> {
        if let Some(i) = record
            .ranges
            .iter()
            .position(|&r| !(r.is_nan() || r >= 0.0 && (r as f32).is_finite()))
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
        if record.ranges.iter().all(|r| r.is_nan()) {
            Some("the scan has no beams".into())
        } else if !finite {
            Some("the scan's pose or angles are not finite numbers".into())
        } else {
            None
        }
    }

    /// Says what the log's poses are (its reader decides, once the log is
    /// read).
    pub fn set_pose_kinds(&mut self, kinds: LogPoseKinds) {
        self.kinds = kinds;
    }

    pub fn pose_kinds(&self) -> LogPoseKinds {
        self.kinds
    }

    /// Sets the laser's pose in the robot's frame.
    pub fn set_mount(&mut self, mount: Pose) {
        self.mount = mount;
    }

    /// The laser's pose in the robot's frame.
    pub fn mount(&self) -> Pose {
        self.mount
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

    /// The log's reference poses (a corrected path), one laser pose per
    /// scan, when it has them.
    pub fn reference_poses(&self) -> Option<&[Pose]> {
        self.kinds.reference.then_some(&self.poses[..])
    }

    /// The log's own odometry, one laser pose per scan, when it has odometry
    /// independent of its reference poses ([`LogPoseKinds::odometry`]).
    pub fn odometry(&self) -> Option<&[Pose]> {
        self.kinds.odometry.then_some(&self.odometry[..])
    }

    /// Every scan's odometry pose as kept, raw or not: the scan's own pose
    /// where its record had none (what a reader compares to decide
    /// [`LogPoseKinds::odometry`]).
    pub fn kept_odometry(&self) -> &[Pose] {
        &self.odometry
    }

    /// Puts the scans at other poses (a dead-reckoned path), one per scan:
    /// an error, and nothing changed, when the count differs.
    pub fn set_poses(&mut self, poses: &[Pose]) -> Result<()> {
        if poses.len() != self.poses.len() {
            let given = format!("{} poses for {} scans", poses.len(), self.poses.len());
            return Err(invalid("poses", given, "one pose per scan"));
        }
        self.poses.copy_from_slice(poses);
        Ok(())
    }

    /// Where in the file scan `k` came from ([`ScanRecord::origin`]).
    pub fn origin(&self, k: usize) -> Option<usize> {
        self.origins.get(k).copied()
    }

    /// What the file's records are called (`"line"`), for messages.
    pub fn unit(&self) -> &'static str {
        self.unit
    }

    /// When scan `k` was taken, seconds, when the log says.
    pub fn stamp(&self, k: usize) -> Option<f64> {
        self.stamps.get(k).copied().flatten()
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
        // Beam `i` at `first + i * step`, as [`Scan::uniform`] puts it; a
        // beam of no measurement ([`ScanRecord::ranges`]) left out.
        let mut kept = Vec::with_capacity(ranges.len());
        let mut bearings = Vec::with_capacity(ranges.len());
        for (i, &r) in ranges.iter().enumerate() {
            if !r.is_nan() {
                kept.push(r as f64);
                bearings.push(first + i as f64 * step);
            }
        }
        Scan::new(pose, kept, bearings).ok()
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
