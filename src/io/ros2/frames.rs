//! Frames and time: the laser's mount from the static transforms (a chain
//! of any length from the odometry's child frame to the scan's frame) and
//! the odometry interpolated at a scan's stamp.

use crate::geometry::{wrap_angle, Pose};

/// `a` then `b` (`b` given in `a`'s frame). Not inlined: a few calls per
/// scan, and each inlined copy costs the wasm its size.
#[inline(never)]
pub fn compose(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let (s, c) = a[2].sin_cos();
    [
        a[0] + c * b[0] - s * b[1],
        a[1] + s * b[0] + c * b[1],
        wrap_angle(a[2] + b[2]),
    ]
}

pub fn pose(p: [f64; 3]) -> Pose {
    Pose {
        x: p[0],
        y: p[1],
        theta: p[2],
    }
}

/// The static transforms: each child frame's parent and pose in it.
#[derive(Debug, Clone, Default)]
pub struct StaticTree {
    /// `(child, parent, pose)`, in the order first given.
    links: Vec<(String, String, [f64; 3])>,
}

/// The most static frames kept: a robot has tens.
const MAX_FRAMES: usize = 1024;

impl StaticTree {
    pub fn add(&mut self, parent: &str, child: &str, pose: [f64; 3]) {
        let full = self.links.len() >= MAX_FRAMES;
        match self.links.iter_mut().find(|l| l.0 == child) {
            Some(l) => {
                l.1 = parent.to_string();
                l.2 = pose;
            }
            None if !full => self
                .links
                .push((child.to_string(), parent.to_string(), pose)),
            None => {}
        }
    }

    /// The pose of frame `to` in frame `from`, following the static
    /// transforms up from `to`: `None` when `from` is not among its
    /// ancestors. (A loop ends the walk after as many steps as frames.)
    pub fn pose_of(&self, from: &str, to: &str) -> Option<[f64; 3]> {
        let mut at = to;
        let mut pose = [0.0; 3];
        for _ in 0..=self.links.len() {
            if at == from {
                return Some(pose);
            }
            let (_, parent, step) = self.links.iter().find(|l| l.0 == at)?;
            pose = compose(*step, pose);
            at = parent;
        }
        None
    }

    /// The frames that have a parent, with it, for messages.
    pub fn describe(&self) -> String {
        let links: Vec<String> = self
            .links
            .iter()
            .take(20)
            .map(|(c, p, _)| {
                format!(
                    "{} \u{2192} {}",
                    crate::io::mcap::quoted(p),
                    crate::io::mcap::quoted(c)
                )
            })
            .collect();
        if links.is_empty() {
            "none".into()
        } else {
            links.join(", ")
        }
    }
}

/// The pose between `a` (at `ta`) and `b` (at `tb`) at time `t`: position
/// linear, heading along the shorter turn.
pub fn interpolate((ta, a): (f64, [f64; 3]), (tb, b): (f64, [f64; 3]), t: f64) -> [f64; 3] {
    let u = if tb > ta { (t - ta) / (tb - ta) } else { 0.0 };
    let turn = wrap_angle(b[2] - a[2]);
    [
        a[0] + u * (b[0] - a[0]),
        a[1] + u * (b[1] - a[1]),
        wrap_angle(a[2] + u * turn),
    ]
}

/// The odometry at `t` from samples sorted by stamp: `None` when `t` lies
/// outside them (a sample at exactly `t` counts).
pub fn odometry_at(samples: &[(f64, [f64; 3])], t: f64) -> Option<[f64; 3]> {
    let i = samples.partition_point(|s| s.0 < t);
    let after = samples.get(i)?;
    if after.0 == t {
        return Some(after.1);
    }
    let before = samples.get(i.checked_sub(1)?)?;
    Some(interpolate(*before, *after, t))
}
