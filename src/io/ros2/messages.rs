//! The three message types a bag is mapped from, decoded from CDR:
//! `sensor_msgs/msg/LaserScan`, `nav_msgs/msg/Odometry` and
//! `tf2_msgs/msg/TFMessage`, in the field order of their definitions
//! (checked against the bag's own by `schema`).

use super::cdr::{Cdr, CdrError};
use crate::io::carmen::MAX_BEAMS;

/// The message types this reader decodes, by their schema names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    LaserScan,
    Odometry,
    Transforms,
}

impl Kind {
    /// The kind of the type `name` (`sensor_msgs/msg/LaserScan`), if one.
    pub fn of(name: &str) -> Option<Self> {
        match super::schema::plain_type(name).as_str() {
            "sensor_msgs/LaserScan" => Some(Self::LaserScan),
            "nav_msgs/Odometry" => Some(Self::Odometry),
            "tf2_msgs/TFMessage" => Some(Self::Transforms),
            _ => None,
        }
    }
}

/// The most transforms one TFMessage may carry.
const MAX_TRANSFORMS: usize = 10_000;

/// A stamp in seconds.
fn stamp(c: &mut Cdr<'_>) -> Result<f64, CdrError> {
    let sec = c.i32("header.stamp.sec")?;
    let nanosec = c.u32("header.stamp.nanosec")?;
    Ok(sec as f64 + nanosec as f64 * 1e-9)
}

/// A header: its stamp (seconds) and frame.
fn header<'a>(c: &mut Cdr<'a>) -> Result<(f64, &'a str), CdrError> {
    let t = stamp(c)?;
    Ok((t, c.string("header.frame_id")?))
}

/// A 3-D position and a quaternion, as the planar pose `[x, y, yaw]`
/// (yaw from the quaternion's rotation about the vertical axis).
fn planar(c: &mut Cdr<'_>, what: &str) -> Result<[f64; 3], CdrError> {
    let mut v = [0.0; 7];
    for slot in v.iter_mut() {
        *slot = c.f64(what)?;
    }
    let [x, y, _z, qx, qy, qz, qw] = v;
    let yaw = (2.0 * (qw * qz + qx * qy)).atan2(1.0 - 2.0 * (qy * qy + qz * qz));
    if !(x.is_finite() && y.is_finite() && yaw.is_finite()) {
        return Err(format!("{what}: not finite numbers ({x}, {y}, yaw {yaw})"));
    }
    Ok([x, y, yaw])
}

/// A LaserScan, its ranges widened to `f64`.
#[derive(Debug, Clone, PartialEq)]
pub struct LaserScan {
    pub stamp: f64,
    pub frame: String,
    pub angle_min: f64,
    pub angle_increment: f64,
    pub range_min: f64,
    pub range_max: f64,
    pub ranges: Vec<f64>,
}

impl LaserScan {
    pub fn decode(data: &[u8]) -> Result<Self, CdrError> {
        let mut c = Cdr::new(data)?;
        let (stamp, frame) = header(&mut c)?;
        let angle_min = c.f32("angle_min")? as f64;
        c.f32("angle_max")?;
        let angle_increment = c.f32("angle_increment")? as f64;
        c.f32("time_increment")?;
        c.f32("scan_time")?;
        let range_min = c.f32("range_min")? as f64;
        let range_max = c.f32("range_max")? as f64;
        let n = c.count("ranges", 4, MAX_BEAMS)?;
        let mut ranges = Vec::with_capacity(n);
        for _ in 0..n {
            ranges.push(c.f32("ranges")? as f64);
        }
        for (field, v) in [
            ("angle_min", angle_min),
            ("angle_increment", angle_increment),
        ] {
            if !v.is_finite() {
                return Err(format!("{field} = {v} is not a finite angle"));
            }
        }
        if !(range_min.is_finite() && range_min >= 0.0) {
            return Err(format!(
                "range_min = {range_min} is not a range (0 or more metres)"
            ));
        }
        if !(range_max.is_finite() && range_max > range_min) {
            return Err(format!(
                "range_max = {range_max} is not a finite range above range_min = {range_min}"
            ));
        }
        if n == 0 {
            return Err("ranges: the scan has no readings".into());
        }
        Ok(Self {
            stamp,
            frame: frame.to_string(),
            angle_min,
            angle_increment,
            range_min,
            range_max,
            ranges,
        })
    }
}

/// An Odometry message's stamp, frames and planar pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Odometry {
    pub stamp: f64,
    pub frame: String,
    pub child: String,
    pub pose: [f64; 3],
}

impl Odometry {
    pub fn decode(data: &[u8]) -> Result<Self, CdrError> {
        let mut c = Cdr::new(data)?;
        let (stamp, frame) = header(&mut c)?;
        let child = c.string("child_frame_id")?;
        let pose = planar(&mut c, "pose.pose")?;
        c.skip_f64s("pose.covariance", 36)?;
        c.skip_f64s("twist", 6 + 36)?;
        Ok(Self {
            stamp,
            frame: frame.to_string(),
            child: child.to_string(),
            pose,
        })
    }
}

/// One transform of a TFMessage: `parent → child` at `stamp`.
#[derive(Debug, Clone, PartialEq)]
pub struct Transform {
    pub stamp: f64,
    pub parent: String,
    pub child: String,
    pub pose: [f64; 3],
}

/// A TFMessage's transforms.
pub fn decode_transforms(data: &[u8]) -> Result<Vec<Transform>, CdrError> {
    let mut c = Cdr::new(data)?;
    // A TransformStamped takes at least 68 bytes.
    let n = c.count("transforms", 68, MAX_TRANSFORMS)?;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let (stamp, parent) = header(&mut c)?;
        let child = c.string("child_frame_id")?;
        let pose = planar(&mut c, "transform")?;
        out.push(Transform {
            stamp,
            parent: parent.to_string(),
            child: child.to_string(),
            pose,
        });
    }
    Ok(out)
}
