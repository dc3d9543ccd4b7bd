//! Frames and time: the laser's mount from the static transforms (a chain
//! of any length from the odometry's child frame to the scan's frame), the
//! odometry interpolated at a scan's stamp, and the odometry frame's pose
//! in `map` ([`MapLinks`]) at a scan's stamp, where the bag has one.

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

/// The most child frames of `map` kept (a bag has one: its odometry frame).
const MAX_MAP_LINKS: usize = 8;

/// The transforms of `/tf` from the `map` frame: per child frame (at most
/// [`MAX_MAP_LINKS`]), its poses in `map`, in stamp order.
#[derive(Debug, Clone, Default)]
pub struct MapLinks {
    links: Vec<(String, Samples)>,
}

/// Stamped planar poses, in stamp order.
type Samples = Vec<(f64, [f64; 3])>;

/// How the odometry frame lies in `map`: the `/tf` link from `map` (its
/// index in the kept links; `None` where `/tf_static` gives `map` itself),
/// then the fixed chain from that link's child to the odometry frame.
pub type MapLink = (Option<usize>, [f64; 3]);

impl MapLinks {
    /// Keeps `map → child` at `stamp`: false when memory runs out. Kept in
    /// time order, for the interpolation: a transform stamped before its
    /// link's last is passed over, as is a link past the first
    /// [`MAX_MAP_LINKS`].
    pub fn add(&mut self, child: String, stamp: f64, pose: [f64; 3]) -> bool {
        let links = &mut self.links;
        let i = match links.iter().position(|l| l.0 == child) {
            Some(i) => i,
            None if links.len() < MAX_MAP_LINKS => {
                links.push((child, Vec::new()));
                links.len() - 1
            }
            None => return true,
        };
        let samples = &mut links[i].1;
        if samples.last().is_some_and(|l| stamp < l.0) {
            return true;
        }
        if samples.try_reserve(1).is_err() {
            return false;
        }
        samples.push((stamp, pose));
        true
    }

    /// How the odometry frame `frame` lies in `map`: a link from `map` to
    /// it or to a frame the static transforms (else `/tf`'s last, `moving`)
    /// lead from to it, or `map` itself in the static transforms.
    pub fn link_to(&self, frame: &str, tree: &StaticTree, moving: &StaticTree) -> Option<MapLink> {
        for (i, (link, _)) in self.links.iter().enumerate() {
            let chain = tree.pose_of(link, frame);
            if let Some(p) = chain.or(moving.pose_of(link, frame)) {
                return Some((Some(i), p));
            }
        }
        tree.pose_of("map", frame).map(|p| (None, p))
    }

    /// The odometry frame's pose in `map` at `t` by `link`, interpolated
    /// between the link's transforms around `t` as the odometry is (as tf2
    /// looks a transform up), and whether `t` lay outside their stamps
    /// (the nearest then taken: the stamp moved to the first or the last).
    pub fn at(&self, (link, chain): MapLink, t: f64) -> ([f64; 3], bool) {
        // Every kept link has a transform (it is kept with its first).
        let Some((_, samples)) = link.and_then(|i| self.links.get(i)) else {
            return (chain, false);
        };
        let (first, last) = (samples[0].0, samples[samples.len() - 1].0);
        let moved = t.max(first).min(last);
        let in_map = odometry_at(samples, moved).unwrap_or_default();
        (compose(in_map, chain), moved != t)
    }

    pub fn is_empty(&self) -> bool {
        self.links.is_empty()
    }

    /// The links kept, for messages (`map → "odom", …`).
    pub fn describe(&self) -> String {
        let mut out = String::new();
        for (link, _) in &self.links {
            if !out.is_empty() {
                out += ", ";
            }
            out += "map \u{2192} ";
            out += &crate::io::mcap::quoted(link);
        }
        out
    }
}
