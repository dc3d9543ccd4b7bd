//! [`BagLoader`]: a ROS 2 bag read into a [`ScanLog`] a bounded step at a
//! time, the MCAP format's [`LogSource`]. The read runs in two stages:
//! the bag's messages in file order (the scans of one LaserScan topic kept
//! as they are, the odometry of each Odometry topic and the static
//! transforms gathered), then the scans placed, each at the odometry
//! interpolated at its stamp and moved by the laser's mount.

use super::frames::{compose, odometry_at, pose, MapLink, MapLinks, StaticTree};
use super::messages::{decode_transforms, Kind, LaserScan, Odometry};
use super::schema;
use super::table::{IdTable, MAX_IDS};
use crate::error::{OccError, Result};
use crate::io::log_source::{
    LoadProgress, LogBudget, LogFormat, LogSource, LogTopic, TopicChoices,
};
use crate::io::mcap::{quoted, Channel, Event, McapReader, Place, Schema};
use crate::sensors::{LogPoseKinds, ScanLog, ScanRecord};

/// What a bag calls the records [`ScanRecord::origin`] counts.
const UNIT: &str = "message";

/// The topics a bag is mapped from, when it has several of a type.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TopicChoice {
    /// The LaserScan topic mapped.
    pub scan_topic: Option<String>,
    /// The Odometry topic the scans are placed by.
    pub odom_topic: Option<String>,
}

/// One channel of the bag, as its records and messages say.
#[derive(Debug, Clone)]
struct ChannelInfo {
    topic: String,
    type_name: String,
    kind: Option<Kind>,
    /// Messages seen, or the summary's count until the read is done.
    count: u64,
    /// Why its messages cannot be decoded (its schema or encoding), if so.
    refused: Option<String>,
}

/// One Odometry topic's samples (stamp, planar pose), sorted by stamp,
/// and its frame and child frame.
type OdometryTrack = (Vec<(f64, [f64; 3])>, String, String);

/// A scan kept until it is placed.
#[derive(Debug, Clone, Copy)]
struct PendingScan {
    origin: usize,
    place: Place,
    stamp: f64,
    first: f64,
    step: f64,
    max_range: f64,
    /// `ranges[range_from..range_from + beams]` of the kept ranges.
    range_from: usize,
    beams: usize,
    frame: usize,
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum Stage {
    Reading,
    /// Placing scan `next` of the kept ones.
    Placing {
        next: usize,
    },
    Done,
}

/// Reads a ROS 2 bag (MCAP, CDR) into a [`ScanLog`].
pub struct BagLoader {
    reader: McapReader,
    budget: LogBudget,
    choice: TopicChoice,
    schemas: IdTable<Schema>,
    channels: IdTable<ChannelInfo>,
    /// The LaserScan channel whose scans are kept.
    scan_channel: Option<u16>,
    /// Odometry per channel: stamp and planar pose, and the frames.
    odometry: IdTable<OdometryTrack>,
    tree: StaticTree,
    /// The transforms of `/tf` (each link's last), for a bag that gives
    /// the laser's mount there and not in `/tf_static`.
    moving_tree: StaticTree,
    /// True when the mount came from `/tf`.
    mount_from_tf: bool,
    /// The transforms of `/tf` from the `map` frame.
    map_links: MapLinks,
    frames: Vec<String>,
    pending: Vec<PendingScan>,
    /// Scans decoded plus scans placed so far ([`LogSource::scan_steps`]).
    scan_steps: usize,
    ranges: Vec<f32>,
    last_scan_stamp: Option<f64>,
    messages: usize,
    /// Readings dropped by REP 117: NaN (invalid), and `-inf` or below
    /// `range_min` (too close); scans with no other reading, skipped.
    invalid_readings: usize,
    close_readings: usize,
    unmeasured_scans: usize,
    skipped: (usize, Option<usize>),
    /// The odometry chosen, the laser's mount in each scan frame, and the
    /// odometry frame's pose in `map` ([`MapLink`]) where the bag has one.
    placing: Option<(u16, Vec<[f64; 3]>, Option<MapLink>)>,
    /// Scans outside the stamps of the `map` transforms (their nearest
    /// taken).
    map_held: usize,
    stage: Stage,
    scans: ScanLog,
    failure: Option<OccError>,
    summary_used: bool,
}

/// Bytes kept per pending scan besides its ranges.
const PENDING_BYTES: usize = std::mem::size_of::<PendingScan>();

impl BagLoader {
    pub fn new(bytes: Vec<u8>, budget: LogBudget) -> Self {
        Self {
            reader: McapReader::new(bytes),
            budget: budget.at_least_one(),
            choice: TopicChoice::default(),
            schemas: IdTable::default(),
            channels: IdTable::default(),
            scan_channel: None,
            odometry: IdTable::default(),
            tree: StaticTree::default(),
            moving_tree: StaticTree::default(),
            mount_from_tf: false,
            map_links: MapLinks::default(),
            frames: Vec::new(),
            pending: Vec::new(),
            scan_steps: 0,
            ranges: Vec::new(),
            last_scan_stamp: None,
            messages: 0,
            invalid_readings: 0,
            close_readings: 0,
            unmeasured_scans: 0,
            map_held: 0,
            skipped: (0, None),
            placing: None,
            stage: Stage::Reading,
            scans: ScanLog::new(UNIT),
            failure: None,
            summary_used: false,
        }
    }

    /// The topics to map (before the first read): an error once reading
    /// has begun.
    pub fn choose_topics(&mut self, choice: TopicChoice) -> Result<()> {
        if self.messages > 0 || self.reader.records() > 0 {
            return Err(OccError::State(
                "the topics are chosen before the bag is read: open it again to choose others"
                    .into(),
            ));
        }
        self.choice = choice;
        Ok(())
    }

    /// Every topic of the bag (read so far, or named by its summary):
    /// `(topic, type, messages)`.
    pub fn topics(&self) -> Vec<(String, String, u64)> {
        self.channels
            .iter()
            .map(|(_, c)| (c.topic.clone(), c.type_name.clone(), c.count))
            .collect()
    }

    /// The topics of `kind`, and whether a read wants a choice between
    /// them: several, and `chosen` none of them.
    fn choices_of(&self, kind: Kind, chosen: Option<&str>) -> (Vec<LogTopic>, bool) {
        let topics: Vec<LogTopic> = self
            .channels
            .iter()
            .filter(|(_, c)| c.kind == Some(kind))
            .map(|(_, c)| LogTopic {
                topic: c.topic.clone(),
                type_name: c.type_name.clone(),
                messages: c.count,
            })
            .collect();
        let named = chosen.is_some_and(|t| topics.iter().any(|c| c.topic == t));
        let wanted = topics.len() > 1 && !named;
        (topics, wanted)
    }

    fn topic_list(&self) -> String {
        let list: Vec<String> = self
            .topics()
            .iter()
            .map(|(t, ty, n)| format!("{} ({}, {n} messages)", quoted(t), quoted(ty)))
            .collect();
        if list.is_empty() {
            "no topics".into()
        } else {
            list.join(", ")
        }
    }

    fn add_schema(&mut self, s: Schema) -> Result<()> {
        if self.schemas.insert(s.id, s) {
            Ok(())
        } else {
            Err(OccError::State(format!(
                "the bag defines more than {MAX_IDS} schemas"
            )))
        }
    }

    fn add_channel(&mut self, c: Channel) -> Result<()> {
        if self.channels.get(c.id).is_some() {
            return Ok(());
        }
        let schema = self.schemas.get(c.schema_id);
        let type_name = schema.map_or_else(|| "(no schema)".to_string(), |s| s.name.clone());
        let kind = Kind::of(&type_name);
        let refused = match (kind, schema) {
            (None, _) => None,
            (Some(_), None) => Some(format!("its Schema {} is not in the bag", c.schema_id)),
            (Some(_), Some(s)) if s.encoding != "ros2msg" => Some(format!(
                "its schema encoding is {}, not ros2msg",
                quoted(&s.encoding)
            )),
            (Some(_), Some(_)) if c.message_encoding != "cdr" => Some(format!(
                "its message encoding is {}, not cdr",
                quoted(&c.message_encoding)
            )),
            (Some(_), Some(s)) => schema::check(&s.name, &String::from_utf8_lossy(&s.data)).err(),
        };
        let info = ChannelInfo {
            topic: c.topic,
            type_name,
            kind,
            count: 0,
            refused,
        };
        if self.channels.insert(c.id, info) {
            Ok(())
        } else {
            Err(OccError::State(format!(
                "the bag defines more than {MAX_IDS} channels"
            )))
        }
    }

    /// The channels of `kind`.
    fn of_kind(&self, kind: Kind) -> Vec<u16> {
        self.channels
            .iter()
            .filter(|(_, c)| c.kind == Some(kind))
            .map(|(id, _)| id)
            .collect()
    }

    /// The channel of `kind` to use: the one chosen by name, or the only
    /// one; an error naming the bag's topics otherwise.
    fn pick(&self, kind: Kind, chosen: Option<&str>, option: &str, type_name: &str) -> Result<u16> {
        let ids = self.of_kind(kind);
        if let Some(name) = chosen {
            return ids
                .into_iter()
                .find(|&id| self.channels.get(id).is_some_and(|c| c.topic == name))
                .ok_or_else(|| {
                    OccError::State(format!(
                        "{option} {} is no {type_name} topic of the bag, which holds {}",
                        quoted(name),
                        self.topic_list()
                    ))
                });
        }
        match ids.as_slice() {
            [id] => Ok(*id),
            [] => Err(OccError::State(format!(
                "the bag has no {type_name} topic to map: it holds {}",
                self.topic_list()
            ))),
            _ => Err(OccError::State(format!(
                "the bag has {} {type_name} topics: choose one with {option}; it holds {}",
                ids.len(),
                self.topic_list()
            ))),
        }
    }

    /// Takes the summary's channels and counts, once, and refuses a topic
    /// choice that cannot be made before any message is read.
    fn use_summary(&mut self) -> Result<()> {
        if self.summary_used {
            return Ok(());
        }
        self.summary_used = true;
        let Some(summary) = self.reader.summary().cloned() else {
            return Ok(());
        };
        for s in summary.schemas {
            self.add_schema(s)?;
        }
        for c in summary.channels {
            self.add_channel(c)?;
        }
        if let Some(counts) = &summary.counts {
            for &(id, n) in counts {
                if let Some(c) = self.channels.get_mut(id) {
                    c.count = n;
                }
            }
            let choice = self.choice.clone();
            let scan = self.pick(
                Kind::LaserScan,
                choice.scan_topic.as_deref(),
                "scan_topic",
                "sensor_msgs/msg/LaserScan",
            )?;
            self.pick(
                Kind::Odometry,
                choice.odom_topic.as_deref(),
                "odom_topic",
                "nav_msgs/msg/Odometry",
            )?;
            self.scan_channel = Some(scan);
            for c in self.channels.values_mut() {
                c.count = 0;
            }
        }
        Ok(())
    }

    /// A message's refusal: its number, topic, place and why.
    fn bad_message(&self, channel: u16, place: Place, why: impl std::fmt::Display) -> OccError {
        let topic = self
            .channels
            .get(channel)
            .map_or("?".into(), |c| quoted(&c.topic));
        OccError::State(format!(
            "the bag's Message record at {place} (message {}, topic {topic}) cannot be read: {why}",
            self.messages
        ))
    }

    fn message(&mut self, channel: u16, place: Place, data: &[u8]) -> Result<()> {
        self.messages += 1;
        let Some(info) = self.channels.get_mut(channel) else {
            return Err(self.bad_message(
                channel,
                place,
                format_args!("its channel {channel} has no Channel record before it"),
            ));
        };
        info.count += 1;
        let Some(kind) = info.kind else {
            return Ok(());
        };
        let wanted = match kind {
            Kind::LaserScan => {
                let by_name = self.choice.scan_topic.as_deref().map(|t| t == info.topic);
                let wanted = by_name.unwrap_or(self.scan_channel.is_none_or(|c| c == channel));
                if wanted {
                    self.scan_channel = Some(channel);
                }
                wanted
            }
            Kind::Odometry => self
                .choice
                .odom_topic
                .as_deref()
                .is_none_or(|t| t == info.topic),
            Kind::Transforms => true,
        };
        if !wanted {
            return Ok(());
        }
        if let Some(why) = &info.refused {
            let why = format!(
                "{} ({}): {why}",
                quoted(&info.topic),
                quoted(&info.type_name)
            );
            return Err(self.bad_message(channel, place, why));
        }
        let topic_is_static = info.topic.ends_with("tf_static");
        match kind {
            Kind::LaserScan => {
                let scan =
                    LaserScan::decode(data).map_err(|why| self.bad_message(channel, place, why))?;
                self.keep_scan(scan, channel, place)
            }
            Kind::Odometry => {
                let odom =
                    Odometry::decode(data).map_err(|why| self.bad_message(channel, place, why))?;
                if self.odometry.get(channel).is_none()
                    && !self.odometry.insert(
                        channel,
                        (Vec::new(), odom.frame.clone(), odom.child.clone()),
                    )
                {
                    return Err(self.bad_message(channel, place, "too many odometry topics"));
                }
                let Some(entry) = self.odometry.get_mut(channel) else {
                    return Err(self.bad_message(channel, place, "its odometry is not kept"));
                };
                if let Some(&(last, _)) = entry.0.last() {
                    if odom.stamp < last {
                        let why = format!("its stamp {} s runs backwards, before the {} s of the odometry before it", odom.stamp, last);
                        return Err(self.bad_message(channel, place, why));
                    }
                }
                if entry.0.try_reserve(1).is_err() {
                    return Err(self.bad_message(
                        channel,
                        place,
                        "out of memory keeping the odometry",
                    ));
                }
                entry.0.push((odom.stamp, odom.pose));
                Ok(())
            }
            Kind::Transforms => {
                let transforms =
                    decode_transforms(data).map_err(|why| self.bad_message(channel, place, why))?;
                for t in transforms {
                    if topic_is_static {
                        self.tree.add(&t.parent, &t.child, t.pose);
                    } else if t.parent != "map" {
                        self.moving_tree.add(&t.parent, &t.child, t.pose);
                    } else if !self.map_links.add(t.child, t.stamp, t.pose) {
                        return Err(self.bad_message(
                            channel,
                            place,
                            "out of memory keeping the map-frame transforms",
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// Keeps a scan's readings by REP 117: `+inf` and readings past
    /// `range_max` are no-returns (kept at `range_max`, which the store
    /// reads as the laser's maximum: they clear); `-inf` and readings below
    /// `range_min` (an object too close to measure) and NaN (invalid) say
    /// nothing of the cells along the beam, so they are dropped (kept as
    /// NaN, the store's "no measurement", [`ScanRecord::ranges`]) and
    /// counted; a scan with no other reading is skipped.
    fn keep_scan(&mut self, scan: LaserScan, channel: u16, place: Place) -> Result<()> {
        if let Some(last) = self.last_scan_stamp {
            if scan.stamp < last {
                let why = format!(
                    "its stamp {} s runs backwards, before the {} s of the scan before it",
                    scan.stamp, last
                );
                return Err(self.bad_message(channel, place, why));
            }
        }
        self.last_scan_stamp = Some(scan.stamp);
        let beams = scan.ranges.len();
        let need = (self.ranges.len() + beams) * 4 + (self.pending.len() + 1) * PENDING_BYTES;
        if need > self.budget.kept_bytes
            || self.ranges.try_reserve(beams).is_err()
            || self.pending.try_reserve(1).is_err()
        {
            let why = format!(
                "the bag is too large to keep: its scans up to this message need {need} bytes, over the budget of {} bytes",
                self.budget.kept_bytes
            );
            return Err(self.bad_message(channel, place, why));
        }
        let max = scan.range_max as f32;
        let range_from = self.ranges.len();
        let dropped = self.invalid_readings + self.close_readings;
        for &r in &scan.ranges {
            let kept = if r.is_nan() {
                self.invalid_readings += 1;
                f32::NAN
            } else if r < scan.range_min || r < 0.0 {
                self.close_readings += 1;
                f32::NAN
            } else if r > scan.range_max {
                max
            } else {
                r as f32
            };
            self.ranges.push(kept);
        }
        if beams > 0 && self.invalid_readings + self.close_readings - dropped == beams {
            self.ranges.truncate(range_from);
            self.unmeasured_scans += 1;
            return Ok(());
        }
        let frame = match self.frames.iter().position(|f| *f == scan.frame) {
            Some(i) => i,
            None => {
                self.frames.push(scan.frame.clone());
                self.frames.len() - 1
            }
        };
        self.scan_steps += 1;
        self.pending.push(PendingScan {
            origin: self.messages,
            place,
            stamp: scan.stamp,
            first: scan.angle_min,
            step: scan.angle_increment,
            max_range: scan.range_max,
            range_from,
            beams,
            frame,
        });
        Ok(())
    }

    /// Once every message is read: the topics chosen and the laser's mount
    /// in each scan frame.
    fn prepare_placing(&mut self) -> Result<()> {
        let choice = self.choice.clone();
        let scan = self.pick(
            Kind::LaserScan,
            choice.scan_topic.as_deref(),
            "scan_topic",
            "sensor_msgs/msg/LaserScan",
        )?;
        let odom = self.pick(
            Kind::Odometry,
            choice.odom_topic.as_deref(),
            "odom_topic",
            "nav_msgs/msg/Odometry",
        )?;
        if self.scan_channel != Some(scan) || self.pending.is_empty() {
            return Err(self.no_scans());
        }
        let Some((samples, odom_frame, child)) = self.odometry.get(odom) else {
            return Err(OccError::State(format!(
                "the bag's odometry topic {} has no messages: the scans cannot be placed",
                quoted(self.channels.get(odom).map_or("", |c| c.topic.as_str()))
            )));
        };
        if samples.is_empty() {
            return Err(OccError::State("the bag's odometry has no messages".into()));
        }
        let mut mounts = Vec::with_capacity(self.frames.len());
        for frame in &self.frames {
            let from_tf = || {
                // Only where /tf_static has no chain: the mount as /tf
                // last gave it.
                let m = self.moving_tree.pose_of(child, frame);
                m.filter(|_| child != frame)
            };
            let mount = match self.tree.pose_of(child, frame) {
                Some(m) => Some(m),
                None => from_tf().inspect(|_| self.mount_from_tf = true),
            };
            let mount = mount.ok_or_else(|| {
                OccError::State(format!(
                    "the bag's /tf_static transforms lead from no frame {} (the odometry's child frame) to the scans' frame {}: the laser's mount is unknown (static transforms: {})",
                    quoted(child),
                    quoted(frame),
                    self.tree.describe()
                ))
            })?;
            mounts.push(mount);
        }
        // The odometry frame in `map`: a `/tf` link from `map` to it or to
        // a frame the static transforms (else `/tf`'s last) lead from to
        // it, or `map` itself in `/tf_static`.
        let map_link = (self.map_links).link_to(odom_frame, &self.tree, &self.moving_tree);
        self.placing = Some((odom, mounts, map_link));
        Ok(())
    }

    /// Places up to `most` more scans; true once all are.
    fn place(&mut self, next: usize, most: usize) -> Result<usize> {
        let Some((odom, mounts, map_link)) = &self.placing else {
            return Ok(self.pending.len());
        };
        let Some((samples, _, _)) = self.odometry.get(*odom) else {
            return Ok(self.pending.len());
        };
        let end = (next + most).min(self.pending.len());
        self.scan_steps += end - next;
        for k in next..end {
            let p = self.pending[k];
            let Some(at) = odometry_at(samples, p.stamp) else {
                self.skipped.0 += 1;
                self.skipped.1.get_or_insert(p.origin);
                continue;
            };
            let laser = compose(at, mounts[p.frame]);
            // The corrected pose: the odometry frame's pose in `map` at the
            // scan's stamp (interpolated as the odometry is, as tf2 looks a
            // transform up; the nearest outside their stamps), then the
            // odometry's laser pose in it.
            let corrected = map_link.map(|link| {
                let (in_map, held) = self.map_links.at(link, p.stamp);
                self.map_held += usize::from(held);
                compose(in_map, laser)
            });
            let ranges: Vec<f64> = self.ranges[p.range_from..p.range_from + p.beams]
                .iter()
                .map(|&r| r as f64)
                .collect();
            let record = ScanRecord {
                origin: p.origin,
                stamp: Some(p.stamp),
                pose: pose(corrected.unwrap_or(laser)),
                odometry: Some(pose(laser)),
                ranges: &ranges,
                first_bearing: p.first,
                bearing_step: p.step,
                max_range: Some(p.max_range),
            };
            self.scans
                .push(&record, self.budget.kept_bytes)
                .map_err(|why| {
                    OccError::State(format!(
                        "the bag's Message record at {} (message {}) cannot be kept: {why}",
                        p.place, p.origin
                    ))
                })?;
        }
        if end == self.pending.len() && self.scans.is_empty() {
            let (first, last) = (samples[0].0, samples[samples.len() - 1].0);
            return Err(OccError::State(format!(
                "no scan of the bag has odometry around its stamp: the odometry runs from {first} s to {last} s, the scans from {} s to {} s",
                self.pending[0].stamp,
                self.pending[self.pending.len() - 1].stamp
            )));
        }
        Ok(end)
    }

    fn finish(&mut self) {
        let mount = self
            .placing
            .as_ref()
            .and_then(|(_, m, _)| m.first().copied())
            .unwrap_or_default();
        self.scans.set_mount(pose(mount));
        self.scans.set_pose_kinds(LogPoseKinds {
            reference: self.corrected(),
            odometry: true,
        });
        self.pending = Vec::new();
        self.ranges = Vec::new();
        self.stage = Stage::Done;
    }

    /// True when the scans have corrected poses: the bag gives the odometry
    /// frame's pose in `map`.
    fn corrected(&self) -> bool {
        matches!(self.placing, Some((_, _, Some(_))))
    }

    fn fail(&mut self, e: OccError) -> OccError {
        self.failure = Some(e.clone());
        self.scans = ScanLog::new(UNIT);
        self.pending = Vec::new();
        self.ranges = Vec::new();
        self.stage = Stage::Done;
        e
    }

    fn step(&mut self, max_scans: usize) -> Result<()> {
        match self.stage {
            Stage::Reading => {
                let mut bytes = self.budget.bytes_per_read;
                let records0 = self.reader.records();
                let scans0 = self.pending.len();
                self.reader.open()?;
                self.use_summary()?;
                loop {
                    if self.reader.records() - records0 >= self.budget.records_per_read
                        || self.pending.len() - scans0 >= max_scans.max(1)
                    {
                        return Ok(());
                    }
                    let most_chunk = self.budget.kept_bytes as u64;
                    match self.reader.next(&mut bytes, most_chunk)? {
                        Event::Paused => return Ok(()),
                        Event::End => break,
                        Event::Schema(s) => self.add_schema(s)?,
                        Event::Channel(c) => self.add_channel(c)?,
                        Event::Message { head, data, place } => {
                            let data = data.to_vec();
                            self.message(head.channel_id, place, &data)?;
                        }
                    }
                }
                self.prepare_placing()?;
                self.stage = Stage::Placing { next: 0 };
                Ok(())
            }
            Stage::Placing { next } => {
                let most = self.budget.records_per_read.min(max_scans.max(1));
                let next = self.place(next, most)?;
                if next >= self.pending.len() {
                    self.finish();
                } else {
                    self.stage = Stage::Placing { next };
                }
                Ok(())
            }
            Stage::Done => Ok(()),
        }
    }

    fn warning(&self) -> Option<String> {
        let mut parts = Vec::new();
        if let Some(w) = self.reader.warning() {
            parts.push(w.to_string());
        }
        if self.invalid_readings + self.close_readings > 0 {
            parts.push(format!(
                "by REP 117, {} readings too close to measure (-inf or below range_min) and {} invalid ones (NaN) are dropped, and {} scans left with none skipped",
                self.close_readings, self.invalid_readings, self.unmeasured_scans
            ));
        }
        if self.map_held > 0 {
            parts.push(format!(
                "{} scans lie outside the stamps of the map \u{2192} odometry transforms and take the nearest",
                self.map_held
            ));
        }
        if let (n, Some(first)) = self.skipped {
            parts.push(format!(
                "{n} scans with no odometry around their stamps are skipped (the first is message {first})"
            ));
        }
        if self.mount_from_tf {
            parts.push(
                "the laser's mount is read from /tf (its last transform), as /tf_static gives none"
                    .into(),
            );
        }
        if !self.map_links.is_empty() && !self.corrected() {
            parts.push(format!(
                "the bag's map-frame transforms ({}) lead to no odometry frame: its scans have no corrected poses",
                self.map_links.describe()
            ));
        }
        (!parts.is_empty()).then(|| parts.join(". "))
    }
}

impl LogSource for BagLoader {
    fn format(&self) -> LogFormat {
        LogFormat::Mcap
    }

    fn read(&mut self, max_scans: usize) -> Result<LoadProgress> {
        if let Some(e) = &self.failure {
            return Err(e.clone());
        }
        if let Err(e) = self.step(max_scans) {
            return Err(self.fail(e));
        }
        Ok(self.progress())
    }

    fn progress(&self) -> LoadProgress {
        let finished = self.stage == Stage::Done && self.failure.is_none();
        LoadProgress {
            records: self.reader.records(),
            record_name: "records",
            // The scans kept in the log so far (placed ones): what
            // `scans()` holds, as the session counts a call's progress.
            scans: self.scans.len(),
            beams: self.scans.beams(),
            bytes_read: self.reader.bytes_read(),
            finished,
            warning: if finished { self.warning() } else { None },
        }
    }

    fn scans(&self) -> &ScanLog {
        &self.scans
    }

    fn scan_steps(&self) -> usize {
        self.scan_steps
    }

    fn into_scans(self: Box<Self>) -> ScanLog {
        self.scans
    }

    fn no_scans(&self) -> OccError {
        OccError::State(format!(
            "the bag has no sensor_msgs/msg/LaserScan messages to map: it holds {}",
            self.topic_list()
        ))
    }

    fn topic_choices(&self) -> Option<TopicChoices> {
        let (scan_topics, scan_wanted) =
            self.choices_of(Kind::LaserScan, self.choice.scan_topic.as_deref());
        let (odom_topics, odom_wanted) =
            self.choices_of(Kind::Odometry, self.choice.odom_topic.as_deref());
        (scan_wanted || odom_wanted).then_some(TopicChoices {
            scan_topics,
            odom_topics,
        })
    }

    fn choose_topics(
        &mut self,
        scan_topic: Option<String>,
        odom_topic: Option<String>,
    ) -> Result<()> {
        BagLoader::choose_topics(
            self,
            TopicChoice {
                scan_topic,
                odom_topic,
            },
        )
    }
}
