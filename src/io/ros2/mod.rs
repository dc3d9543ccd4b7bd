//! ROS 2 bags: the messages of an MCAP file ([`crate::io::mcap`]) read as
//! a robot's laser log.
//!
//! * `cdr`: CDR, ROS 2's serialisation, in either byte order;
//! * `schema`: the bag's message definitions (`ros2msg`) checked against
//!   the fields decoded, so that a schema that says otherwise is refused;
//! * `messages`: `sensor_msgs/msg/LaserScan`, `nav_msgs/msg/Odometry` and
//!   `tf2_msgs/msg/TFMessage` decoded (a topic of another type is listed,
//!   not decoded);
//! * `frames`: the laser's mount from `/tf_static` (a chain of any length
//!   from the odometry's child frame to the scan's frame, yaw included)
//!   and the odometry interpolated at a scan's stamp;
//! * `bag`: [`BagLoader`], the format's [`super::LogSource`].
//!
//! # What a bag becomes
//!
//! One LaserScan topic is mapped, placed by one Odometry topic: with one
//! of each the bag just maps; with several, [`TopicChoice`] names them,
//! and without it the read is refused with the bag's topics (topic, type,
//! message count). A bag without a LaserScan topic is refused with the
//! same list. Each scan's laser pose is the odometry interpolated at the
//! scan's stamp (odometry and scans are never stamped together in a real
//! bag), moved by the mount; a scan with no odometry on both sides of its
//! stamp is skipped and counted in the warning, and a bag where no scan
//! has any is refused. The log's poses are odometry (the odometry frame
//! is the map's frame): [`crate::sensors::LogPoseKinds`] says they are
//! its own odometry, not reference poses, unless the bag carries a
//! map-frame pose: a `map → odom` transform (the parent frame `map`, the
//! child the odometry's frame, or a frame the static transforms lead from
//! to it) on `/tf`, or `/tf_static`'s fixed one. Then each scan's
//! reference (corrected) pose is that transform at the scan's stamp,
//! interpolated between the two around it as the odometry is (as tf2
//! looks a transform up: a localiser's correction spreads over the time
//! between two of its transforms, as the drift it corrects grew; outside
//! them, the nearest, named in the warning), composed with the scan's
//! odometry pose; the odometry stays the log's own.
//!
//! Ranges follow REP 117: `+inf` is no return (it only clears, as a
//! CARMEN no-return does), as is a reading past `range_max`; both are
//! kept at `range_max`, the laser's maximum the store reads no-returns by.
//! `-inf` and readings below `range_min` (an object too close to measure)
//! and NaN (invalid) say nothing of the cells along their beam: they are
//! dropped (the store's "no measurement") and counted by kind in the
//! read's warning, and a scan with no reading left is skipped.
//! `angle_increment` may be negative (the beams then run clockwise).
//!
//! Stamps that run backwards (a scan's or an odometry message's before
//! the one before it on its topic) are refused, naming the message.

mod bag;
mod cdr;
mod frames;
mod messages;
mod schema;
mod table;

pub use bag::{BagLoader, TopicChoice};
