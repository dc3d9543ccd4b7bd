//! A bag's message definitions (`ros2msg` schemas: the type's fields, then
//! each type it uses after a line of `=` and `MSG: package/Type`), checked
//! against the fields this reader decodes, so that a schema that says
//! something else is refused rather than misread.

/// The fields this reader decodes, type by type: `(type, name)` in order,
/// types as the definitions write them (a type of another package by its
/// last name).
pub const DEFINITIONS: &[(&str, &[(&str, &str)])] = &[
    (
        "sensor_msgs/LaserScan",
        &[
            ("Header", "header"),
            ("float32", "angle_min"),
            ("float32", "angle_max"),
            ("float32", "angle_increment"),
            ("float32", "time_increment"),
            ("float32", "scan_time"),
            ("float32", "range_min"),
            ("float32", "range_max"),
            ("float32[]", "ranges"),
            ("float32[]", "intensities"),
        ],
    ),
    (
        "nav_msgs/Odometry",
        &[
            ("Header", "header"),
            ("string", "child_frame_id"),
            ("PoseWithCovariance", "pose"),
            ("TwistWithCovariance", "twist"),
        ],
    ),
    (
        "tf2_msgs/TFMessage",
        &[("TransformStamped[]", "transforms")],
    ),
    (
        "std_msgs/Header",
        &[("Time", "stamp"), ("string", "frame_id")],
    ),
    (
        "builtin_interfaces/Time",
        &[("int32", "sec"), ("uint32", "nanosec")],
    ),
    (
        "geometry_msgs/PoseWithCovariance",
        &[("Pose", "pose"), ("float64[36]", "covariance")],
    ),
    (
        "geometry_msgs/Pose",
        &[("Point", "position"), ("Quaternion", "orientation")],
    ),
    (
        "geometry_msgs/Point",
        &[("float64", "x"), ("float64", "y"), ("float64", "z")],
    ),
    (
        "geometry_msgs/Quaternion",
        &[
            ("float64", "x"),
            ("float64", "y"),
            ("float64", "z"),
            ("float64", "w"),
        ],
    ),
    (
        "geometry_msgs/TwistWithCovariance",
        &[("Twist", "twist"), ("float64[36]", "covariance")],
    ),
    (
        "geometry_msgs/Twist",
        &[("Vector3", "linear"), ("Vector3", "angular")],
    ),
    (
        "geometry_msgs/Vector3",
        &[("float64", "x"), ("float64", "y"), ("float64", "z")],
    ),
    (
        "geometry_msgs/TransformStamped",
        &[
            ("Header", "header"),
            ("string", "child_frame_id"),
            ("Transform", "transform"),
        ],
    ),
    (
        "geometry_msgs/Transform",
        &[("Vector3", "translation"), ("Quaternion", "rotation")],
    ),
];

/// A type name without its `msg/` part (`sensor_msgs/msg/LaserScan` is
/// `sensor_msgs/LaserScan`).
pub fn plain_type(name: &str) -> String {
    name.replace("/msg/", "/")
}

/// A field's type by its last name (`geometry_msgs/Pose[]` is `Pose[]`).
fn short_type(t: &str) -> &str {
    t.rsplit('/').next().unwrap_or(t)
}

/// The fields of one section of a definition: `(type, name)`, constants
/// (`TYPE NAME=VALUE`) and comments left out, default values dropped.
fn fields(section: &str) -> Vec<(String, String)> {
    section
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty() && !l.starts_with("MSG:"))
        .filter_map(|l| {
            // A constant (`uint8 NAME=1`) is no field.
            if l.contains('=') {
                return None;
            }
            let mut words = l.split_whitespace();
            let t = words.next()?;
            let name = words.next()?;
            Some((short_type(t).to_string(), name.to_string()))
        })
        .collect()
}

/// Checks the definition `text` of the type `name` against
/// [`DEFINITIONS`]: the type's own fields, and those of each type it uses
/// that this reader decodes. The first difference, in words.
pub fn check(name: &str, text: &str) -> Result<(), String> {
    let mut sections = vec![(plain_type(name), String::new())];
    for line in text.lines() {
        let trimmed = line.trim();
        if trimmed.starts_with("===") {
            continue;
        }
        if let Some(t) = trimmed.strip_prefix("MSG:") {
            sections.push((plain_type(t.trim()), String::new()));
            continue;
        }
        if let Some((_, body)) = sections.last_mut() {
            body.push_str(line);
            body.push('\n');
        }
    }
    let main = plain_type(name);
    for (type_name, body) in &sections {
        let Some((_, want)) = DEFINITIONS.iter().find(|(t, _)| t == type_name) else {
            continue;
        };
        let found = fields(body);
        let same = found.len() == want.len()
            && found
                .iter()
                .zip(want.iter())
                .all(|((ft, fname), (wt, wname))| ft == wt && fname == wname);
        if !same {
            let said: Vec<String> = found.iter().map(|(t, n)| format!("{t} {n}")).collect();
            let expected: Vec<String> = want.iter().map(|(t, n)| format!("{t} {n}")).collect();
            return Err(format!(
                "its schema defines {type_name} as [{}], not [{}]",
                said.join(", "),
                expected.join(", ")
            ));
        }
    }
    if !DEFINITIONS.iter().any(|(t, _)| *t == main) {
        return Err(format!("{main} is not a type this reader decodes"));
    }
    Ok(())
}
