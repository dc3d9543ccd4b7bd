//! Small ROS 2 bags written by the tests themselves: an MCAP writer (no
//! compression, zstd or lz4 chunks, a summary or none) and CDR messages
//! in either byte order, and a robot that drives a straight, turning path
//! with its odometry stamped between the scans.
#![allow(dead_code)]

use std::collections::BTreeMap;

pub const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

fn crc32(b: &[u8]) -> u32 {
    crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC).checksum(b)
}

fn record(out: &mut Vec<u8>, op: u8, body: &[u8]) {
    out.push(op);
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(body);
}

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// How a chunk's records are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Compression {
    /// No chunks: every record at the top level.
    Unchunked,
    None,
    Zstd,
    Lz4,
}

/// An MCAP file being written.
pub struct Writer {
    pub out: Vec<u8>,
    chunk: Vec<u8>,
    compression: Compression,
    chunk_bytes: usize,
    schemas: Vec<Vec<u8>>,
    channels: Vec<Vec<u8>>,
    counts: BTreeMap<u16, u64>,
    /// A chunk's stated CRC replaced by this, when set.
    pub lie_chunk_crc: Option<u32>,
    /// A chunk's stated uncompressed size replaced by this, when set.
    pub lie_chunk_size: Option<u64>,
    /// Skippable LZ4 frames (magic, size, bytes) written before and after
    /// each lz4 chunk's frame, when set.
    pub lz4_skippable: Option<Vec<u8>>,
}

impl Writer {
    pub fn new(compression: Compression) -> Self {
        let mut out = MAGIC.to_vec();
        let mut header = Vec::new();
        string(&mut header, "ros2");
        string(&mut header, "occgrid tests");
        record(&mut out, 0x01, &header);
        Self {
            out,
            chunk: Vec::new(),
            compression,
            chunk_bytes: 4096,
            schemas: Vec::new(),
            channels: Vec::new(),
            counts: BTreeMap::new(),
            lie_chunk_crc: None,
            lie_chunk_size: None,
            lz4_skippable: None,
        }
    }

    fn put(&mut self, op: u8, body: &[u8]) {
        if self.compression == Compression::Unchunked {
            record(&mut self.out, op, body);
        } else {
            record(&mut self.chunk, op, body);
            if self.chunk.len() >= self.chunk_bytes {
                self.flush();
            }
        }
    }

    pub fn schema(&mut self, id: u16, name: &str, text: &str) {
        let mut b = id.to_le_bytes().to_vec();
        string(&mut b, name);
        string(&mut b, "ros2msg");
        string(&mut b, text);
        self.schemas.push(b.clone());
        self.put(0x03, &b);
    }

    pub fn channel(&mut self, id: u16, schema: u16, topic: &str) {
        let mut b = id.to_le_bytes().to_vec();
        b.extend_from_slice(&schema.to_le_bytes());
        string(&mut b, topic);
        string(&mut b, "cdr");
        b.extend_from_slice(&0u32.to_le_bytes());
        self.channels.push(b.clone());
        self.put(0x04, &b);
    }

    pub fn message(&mut self, channel: u16, time: f64, data: &[u8]) {
        let ns = (time * 1e9) as u64;
        let mut b = channel.to_le_bytes().to_vec();
        b.extend_from_slice(&0u32.to_le_bytes());
        b.extend_from_slice(&ns.to_le_bytes());
        b.extend_from_slice(&ns.to_le_bytes());
        b.extend_from_slice(data);
        *self.counts.entry(channel).or_default() += 1;
        self.put(0x05, &b);
    }

    /// Ends the current chunk.
    pub fn flush(&mut self) {
        if self.chunk.is_empty() {
            return;
        }
        let records = std::mem::take(&mut self.chunk);
        let (name, stored) = match self.compression {
            Compression::Zstd => (
                "zstd",
                ruzstd::encoding::compress_to_vec(
                    &records[..],
                    ruzstd::encoding::CompressionLevel::Fastest,
                ),
            ),
            Compression::Lz4 => {
                let skip = self.lz4_skippable.clone().unwrap_or_default();
                let mut enc = lz4_flex::frame::FrameEncoder::new(skip.clone());
                std::io::Write::write_all(&mut enc, &records).unwrap();
                let mut frames = enc.finish().unwrap();
                frames.extend_from_slice(&skip);
                ("lz4", frames)
            }
            _ => ("", records.clone()),
        };
        let mut b = Vec::new();
        b.extend_from_slice(&0u64.to_le_bytes());
        b.extend_from_slice(&0u64.to_le_bytes());
        b.extend_from_slice(
            &self
                .lie_chunk_size
                .unwrap_or(records.len() as u64)
                .to_le_bytes(),
        );
        b.extend_from_slice(&self.lie_chunk_crc.unwrap_or(crc32(&records)).to_le_bytes());
        string(&mut b, name);
        b.extend_from_slice(&(stored.len() as u64).to_le_bytes());
        b.extend_from_slice(&stored);
        record(&mut self.out, 0x06, &b);
    }

    /// The file, with a summary section (schemas, channels, statistics)
    /// when `summary`.
    pub fn finish(mut self, summary: bool) -> Vec<u8> {
        self.flush();
        let data_crc = crc32(&self.out);
        record(&mut self.out, 0x0f, &data_crc.to_le_bytes());
        let mut summary_start = 0u64;
        if summary {
            summary_start = self.out.len() as u64;
            for s in &self.schemas {
                record(&mut self.out, 0x03, s);
            }
            for c in &self.channels {
                record(&mut self.out, 0x04, c);
            }
            let mut st = Vec::new();
            st.extend_from_slice(&self.counts.values().sum::<u64>().to_le_bytes());
            st.extend_from_slice(&(self.schemas.len() as u16).to_le_bytes());
            st.extend_from_slice(&(self.channels.len() as u32).to_le_bytes());
            st.extend_from_slice(&[0; 12]);
            st.extend_from_slice(&[0; 16]);
            let mut map = Vec::new();
            for (id, n) in &self.counts {
                map.extend_from_slice(&id.to_le_bytes());
                map.extend_from_slice(&n.to_le_bytes());
            }
            st.extend_from_slice(&(map.len() as u32).to_le_bytes());
            st.extend_from_slice(&map);
            record(&mut self.out, 0x0b, &st);
        }
        let footer_at = self.out.len();
        let mut f = Vec::new();
        f.extend_from_slice(&summary_start.to_le_bytes());
        f.extend_from_slice(&0u64.to_le_bytes());
        self.out.push(0x02);
        self.out.extend_from_slice(&20u64.to_le_bytes());
        self.out.extend_from_slice(&f);
        let crc = if summary {
            crc32(&self.out[summary_start as usize..])
        } else {
            0
        };
        let _ = footer_at;
        self.out.extend_from_slice(&crc.to_le_bytes());
        self.out.extend_from_slice(MAGIC);
        self.out
    }
}

/// A CDR message being written.
pub struct Cdr {
    out: Vec<u8>,
    big: bool,
}

impl Cdr {
    pub fn new(big: bool) -> Self {
        Self {
            out: vec![0, if big { 0 } else { 1 }, 0, 0],
            big,
        }
    }

    fn align(&mut self, n: usize) {
        while !(self.out.len() - 4).is_multiple_of(n) {
            self.out.push(0);
        }
    }

    fn raw<const N: usize>(&mut self, mut le: [u8; N]) {
        self.align(N);
        if self.big {
            le.reverse();
        }
        self.out.extend_from_slice(&le);
    }

    pub fn u32(&mut self, v: u32) -> &mut Self {
        self.raw(v.to_le_bytes());
        self
    }
    pub fn i32(&mut self, v: i32) -> &mut Self {
        self.raw(v.to_le_bytes());
        self
    }
    pub fn f32(&mut self, v: f32) -> &mut Self {
        self.raw(v.to_le_bytes());
        self
    }
    pub fn f64(&mut self, v: f64) -> &mut Self {
        self.raw(v.to_le_bytes());
        self
    }
    pub fn string(&mut self, s: &str) -> &mut Self {
        self.u32(s.len() as u32 + 1);
        self.out.extend_from_slice(s.as_bytes());
        self.out.push(0);
        self
    }
    pub fn header(&mut self, t: f64, frame: &str) -> &mut Self {
        let sec = t.floor();
        self.i32(sec as i32)
            .u32(((t - sec) * 1e9).round() as u32)
            .string(frame)
    }
    /// A position and the quaternion of a yaw.
    pub fn planar(&mut self, p: [f64; 3]) -> &mut Self {
        let (s, c) = (p[2] / 2.0).sin_cos();
        self.f64(p[0])
            .f64(p[1])
            .f64(0.3)
            .f64(0.0)
            .f64(0.0)
            .f64(s)
            .f64(c)
    }
    pub fn bytes(&self) -> Vec<u8> {
        self.out.clone()
    }
}

pub const HEADER_DEF: &str =
    "================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
";

pub fn laser_scan_def() -> String {
    format!(
        "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\nfloat32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\nfloat32[] ranges # metres\nfloat32[] intensities\n{HEADER_DEF}"
    )
}

pub fn odometry_def() -> String {
    format!("std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n{HEADER_DEF}================================================================================
MSG: geometry_msgs/PoseWithCovariance
Pose pose
float64[36] covariance
================================================================================
MSG: geometry_msgs/Pose
Point position
Quaternion orientation
================================================================================
MSG: geometry_msgs/Point
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x 0
float64 y 0
float64 z 0
float64 w 1
")
}

pub fn tf_def() -> String {
    format!("geometry_msgs/TransformStamped[] transforms\n================================================================================
MSG: geometry_msgs/TransformStamped
std_msgs/Header header
string child_frame_id
Transform transform
================================================================================
MSG: geometry_msgs/Transform
Vector3 translation
Quaternion rotation
{HEADER_DEF}")
}

/// A LaserScan's CDR.
pub fn laser_scan(
    big: bool,
    t: f64,
    frame: &str,
    first: f32,
    step: f32,
    max: f32,
    ranges: &[f32],
) -> Vec<u8> {
    let mut c = Cdr::new(big);
    c.header(t, frame)
        .f32(first)
        .f32(first + step * (ranges.len() as f32 - 1.0))
        .f32(step)
        .f32(0.0)
        .f32(0.1)
        .f32(0.05)
        .f32(max)
        .u32(ranges.len() as u32);
    for &r in ranges {
        c.f32(r);
    }
    c.u32(0);
    c.bytes()
}

/// An Odometry's CDR.
pub fn odometry(big: bool, t: f64, child: &str, p: [f64; 3]) -> Vec<u8> {
    let mut c = Cdr::new(big);
    c.header(t, "odom").string(child).planar(p);
    for _ in 0..(36 + 6 + 36) {
        c.f64(0.0);
    }
    c.bytes()
}

/// A TFMessage's CDR: `(parent, child, pose)` at `t`.
pub fn transforms(big: bool, t: f64, links: &[(&str, &str, [f64; 3])]) -> Vec<u8> {
    let mut c = Cdr::new(big);
    c.u32(links.len() as u32);
    for (parent, child, p) in links {
        c.header(t, parent).string(child).planar(*p);
    }
    c.bytes()
}

pub fn compose(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let (s, c) = a[2].sin_cos();
    [
        a[0] + c * b[0] - s * b[1],
        a[1] + s * b[0] + c * b[1],
        a[2] + b[2],
    ]
}

/// What a test bag holds.
#[derive(Debug, Clone)]
pub struct BagSpec {
    pub compression: Compression,
    pub big_endian: bool,
    /// The odometry of `base_footprint`, with `base_footprint → base_link
    /// → laser` in /tf_static (else of `base_link`, one link to the laser).
    pub chain: bool,
    pub mount: [f64; 3],
    pub scan_topics: Vec<&'static str>,
    pub odom_topics: Vec<&'static str>,
    pub summary: bool,
    pub scans: usize,
    pub beams: usize,
    /// Beam `i` of scan `k`.
    pub range: fn(usize, usize) -> f32,
    pub step: f32,
    /// Stamps of scan `k` (seconds).
    pub stamp: fn(usize) -> f64,
    /// The first scan with odometry before it (the scans before it have
    /// none).
    pub odom_from: usize,
    /// The mount's transforms on `/tf` instead of `/tf_static`.
    pub mount_on_tf: bool,
    /// `map → odom` transforms on `/tf` (the odometry's frame in `map` at
    /// a time, [`map_odom_at`]) at these stamps: none when empty.
    pub map_stamps: Vec<f64>,
    /// The child frame of those transforms (`odom`, the odometry's frame,
    /// unless another is named).
    pub map_child: &'static str,
    /// With a `map_child` other than `odom`: `/tf_static`'s link from it
    /// to `odom`, or none.
    pub map_via: Option<[f64; 3]>,
}

impl Default for BagSpec {
    fn default() -> Self {
        Self {
            compression: Compression::Zstd,
            big_endian: false,
            chain: false,
            mount: [0.2, -0.05, 0.0],
            scan_topics: vec!["/scan"],
            odom_topics: vec!["/odom"],
            summary: true,
            scans: 12,
            beams: 90,
            range: |k, i| 1.0 + ((k * 7 + i) % 13) as f32 * 0.25,
            step: std::f32::consts::PI / 89.0,
            stamp: |k| 1_700_000_000.0 + k as f64 * 0.5,
            odom_from: 0,
            mount_on_tf: false,
            map_stamps: Vec::new(),
            map_child: "odom",
            map_via: None,
        }
    }
}

/// The base's path: linear in time, so interpolation recovers it.
pub fn base_at(t: f64) -> [f64; 3] {
    let u = t - 1_700_000_000.0;
    [1.0 + 0.4 * u, -2.0 + 0.1 * u, 0.3 + 0.05 * u]
}

/// The odometry frame's pose in `map` at `t`: linear in time, so that
/// interpolating between two transforms recovers it.
pub fn map_odom_at(t: f64) -> [f64; 3] {
    let u = t - 1_700_000_000.0;
    [0.5 - 0.02 * u, 1.5 + 0.03 * u, -0.2 + 0.01 * u]
}

/// The bag and each scan's laser pose (odometry frame).
pub fn robot_bag(spec: &BagSpec) -> (Vec<u8>, Vec<[f64; 3]>) {
    let big = spec.big_endian;
    let mut w = Writer::new(spec.compression);
    w.schema(1, "sensor_msgs/msg/LaserScan", &laser_scan_def());
    w.schema(2, "nav_msgs/msg/Odometry", &odometry_def());
    w.schema(3, "tf2_msgs/msg/TFMessage", &tf_def());
    let mut id = 1u16;
    let mut scan_ids = Vec::new();
    for t in &spec.scan_topics {
        w.channel(id, 1, t);
        scan_ids.push(id);
        id += 1;
    }
    let mut odom_ids = Vec::new();
    for t in &spec.odom_topics {
        w.channel(id, 2, t);
        odom_ids.push(id);
        id += 1;
    }
    let tf_static = id;
    w.channel(
        tf_static,
        3,
        if spec.mount_on_tf {
            "/tf"
        } else {
            "/tf_static"
        },
    );
    let t0 = (spec.stamp)(0);
    let foot = [0.05, 0.0, 0.0];
    if let Some(via) = spec.map_via {
        w.message(
            tf_static,
            t0,
            &transforms(big, t0, &[(spec.map_child, "odom", via)]),
        );
    }
    let (child, whole) = if spec.chain {
        w.message(
            tf_static,
            t0,
            &transforms(
                big,
                t0,
                &[
                    ("base_link", "laser", spec.mount),
                    ("base_footprint", "base_link", foot),
                ],
            ),
        );
        ("base_footprint", compose(foot, spec.mount))
    } else {
        w.message(
            tf_static,
            t0,
            &transforms(big, t0, &[("base_link", "laser", spec.mount)]),
        );
        ("base_link", spec.mount)
    };
    let tf = id + 1;
    if !spec.map_stamps.is_empty() {
        w.channel(tf, 3, "/tf");
    }
    let mut map_stamps = spec.map_stamps.iter().copied().peekable();
    let mut truth = Vec::new();
    let odom = |w: &mut Writer, t: f64| {
        for &o in &odom_ids {
            w.message(o, t, &odometry(big, t, child, base_at(t)));
        }
    };
    for k in 0..spec.scans {
        if k == spec.odom_from {
            odom(&mut w, (spec.stamp)(k) - 0.1);
        }
        let t = (spec.stamp)(k);
        while let Some(m) = map_stamps.next_if(|&m| m <= t + 0.5) {
            w.message(
                tf,
                m,
                &transforms(big, m, &[("map", spec.map_child, map_odom_at(m))]),
            );
        }
        let ranges: Vec<f32> = (0..spec.beams).map(|i| (spec.range)(k, i)).collect();
        let first = -spec.step * (spec.beams as f32 - 1.0) / 2.0;
        for &s in &scan_ids {
            w.message(
                s,
                t,
                &laser_scan(big, t, "laser", first, spec.step, 8.0, &ranges),
            );
        }
        if k >= spec.odom_from {
            truth.push(compose(base_at(t), whole));
            odom(&mut w, t + 0.0002);
            odom(&mut w, t + 0.25);
        }
    }
    for m in map_stamps {
        w.message(
            tf,
            m,
            &transforms(big, m, &[("map", spec.map_child, map_odom_at(m))]),
        );
    }
    (w.finish(spec.summary), truth)
}
