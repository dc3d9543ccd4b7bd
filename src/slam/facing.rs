//! Which way a surface faces, for loop search ([`super::loop_search`]).
//!
//! A wall has two sides, and a submap usually saw one: a post seen from
//! the west is its west face alone, the cells behind it unknown. A scan
//! from the east sees the east face, a post's width further on, and placed
//! a post's width back its returns would lie on the west face's cells and
//! outscore the true placement (a corridor driven out and back with a
//! forward-facing laser had every such closure a post's width off, and
//! came out 0.6 % short). So a cell also keeps the normal of the surface
//! its returns ended on, where they lay on a line ([`surface_normals`]),
//! and a point scores it only if the point's own surface could be that
//! one: its normal within a quarter turn of the cell's (the normal
//! compatibility test of ICP's pair rejection; Rusinkiewicz and Levoy
//! 2001, "Efficient variants of the ICP algorithm"), or, for a point on no
//! line (leaves, grass, a far face of few returns), the cell's normal
//! within a quarter turn of the way back along the point's beam, since a
//! surface a beam returns from faces it. Opposite faces never match; a
//! face seen again from anywhere in front of it does, and so does every
//! cell without a normal. The grids of maxima keep the probabilities
//! alone: still an upper bound of every offset below them.

/// Sectors a surface's normal is kept in: 15 (codes 1 to 15), code 0
/// for a cell whose returns' normals disagree or are not known.
const NORMAL_SECTORS: f64 = 15.0;
/// How far (radians) a point's normal may turn from a cell's and still
/// score it: a quarter turn, and the sectors' half width twice over.
const NORMAL_AGREEMENT: f64 = std::f64::consts::FRAC_PI_2 + 0.4;
/// How far a cell's normal may turn from the way back along the beam of a
/// point that has no normal of its own: a surface a beam returns from
/// faces it, its normal within a quarter turn of the way back (and the
/// sectors' half width).
const BEAM_AGREEMENT: f64 = std::f64::consts::FRAC_PI_2 + 0.2;
/// Steps of a turn [`AgreementTable`] holds (a third of a degree each; a
/// power of two).
const AGREEMENT_STEPS: usize = 1024;
/// Returns farther apart than this (metres) are not taken for one surface.
const SURFACE_GAP: f64 = 0.5;
/// The neighbours either way a return's surface is fitted to.
const SURFACE_NEIGHBOURS: usize = 3;
/// The most spread across a surface's line (metres, root mean square) and
/// the least ratio of its spread along the line to that: a wall's returns
/// lie within a laser's centimetre or two of their line.
const SURFACE_RESIDUAL: f64 = 0.03;
const SURFACE_ELONGATION: f64 = 4.0;

/// The code of a surface normal pointing at `angle` (radians): 1 to 15.
pub fn normal_code(angle: f64) -> u8 {
    let turn = angle.rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU;
    1 + ((turn * NORMAL_SECTORS) as u8).min(NORMAL_SECTORS as u8 - 1)
}

/// The codes a point facing `angle` scores against, as bits (code 0
/// always): those within `within` radians of it.
pub(super) fn codes_agreeing(angle: f64, within: f64) -> u16 {
    let mut bits = 1u16;
    for code in 1..=NORMAL_SECTORS as u16 {
        let centre = (code as f64 - 0.5) / NORMAL_SECTORS * std::f64::consts::TAU;
        if crate::geometry::wrap_angle(centre - angle).abs() <= within {
            bits |= 1 << code;
        }
    }
    bits
}

/// [`codes_agreeing`] for every step of a turn, for a point with a normal
/// and for one seen along its beam alone: a search reads it for every
/// point at every heading.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct AgreementTable {
    by_normal: Vec<u16>,
    by_beam: Vec<u16>,
}

impl AgreementTable {
    /// The one table, made on first use.
    pub(super) fn get() -> &'static Self {
        static TABLE: std::sync::OnceLock<AgreementTable> = std::sync::OnceLock::new();
        TABLE.get_or_init(Self::new)
    }

    fn new() -> Self {
        let step = std::f64::consts::TAU / AGREEMENT_STEPS as f64;
        let table = |within: f64| {
            (0..AGREEMENT_STEPS)
                .map(|i| codes_agreeing((i as f64 + 0.5) * step, within))
                .collect()
        };
        Self {
            by_normal: table(NORMAL_AGREEMENT),
            by_beam: table(BEAM_AGREEMENT),
        }
    }

    /// The codes a point facing `facing` agrees with, turned by `turn`.
    #[inline]
    pub(super) fn at(&self, facing: &Facing, turn: f64) -> u16 {
        // The step of the turn's fraction (a power of two of steps: the
        // mask wraps it, and no remainder of a division is taken).
        let turns = (facing.angle + turn) * (1.0 / std::f64::consts::TAU);
        let i = ((turns - turns.floor()) * AGREEMENT_STEPS as f64) as usize & (AGREEMENT_STEPS - 1);
        if facing.by_beam {
            self.by_beam[i]
        } else {
            self.by_normal[i]
        }
    }
}

/// Which way a point's surface faces, in the sensor's frame: its normal
/// ([`surface_normals`]), or without one the way back along its beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Facing {
    pub(super) angle: f64,
    pub(super) by_beam: bool,
}

/// The normal of the surface at each of `points` (the returns of one scan
/// in its order, sensor frame), pointing back to the sensor, radians in the
/// sensor's frame; `None` where the returns round it do not lie on a line.
///
/// A return's surface is the line fitted (least squares) to it and its
/// neighbours in the scan, up to `SURFACE_NEIGHBOURS` either way within
/// `SURFACE_GAP` of it; it has a normal only if at least three returns
/// lie within `SURFACE_RESIDUAL` of the line and spread along it at least
/// `SURFACE_ELONGATION` times as far as across. Leaves, grass and people
/// return from anywhere in their depth: their returns have no normal, and
/// score every cell as they always did.
pub fn surface_normals(points: &[[f64; 2]]) -> Vec<Option<f64>> {
    let near = |a: &[f64; 2], b: &[f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) <= SURFACE_GAP;
    (0..points.len())
        .map(|i| {
            let p = &points[i];
            let from = i.saturating_sub(SURFACE_NEIGHBOURS);
            let to = (i + SURFACE_NEIGHBOURS).min(points.len() - 1);
            let mut first = i;
            while first > from && near(p, &points[first - 1]) {
                first -= 1;
            }
            let mut last = i;
            while last < to && near(p, &points[last + 1]) {
                last += 1;
            }
            let run = &points[first..=last];
            if run.len() < 3 {
                return None;
            }
            let n = run.len() as f64;
            let (mx, my) = run
                .iter()
                .fold((0.0, 0.0), |(x, y), q| (x + q[0] / n, y + q[1] / n));
            let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
            for q in run {
                let (dx, dy) = (q[0] - mx, q[1] - my);
                sxx += dx * dx / n;
                syy += dy * dy / n;
                sxy += dx * dy / n;
            }
            // The covariance's eigenvalues: spread along and across the line.
            let half = 0.5 * (sxx + syy);
            let root = (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt();
            let (along, across) = (half + root, (half - root).max(0.0));
            if across > SURFACE_RESIDUAL * SURFACE_RESIDUAL
                || along < SURFACE_ELONGATION * SURFACE_ELONGATION * across
                || along <= 0.0
            {
                return None;
            }
            let direction = 0.5 * (2.0 * sxy).atan2(sxx - syy);
            let (nx, ny) = (-direction.sin(), direction.cos());
            // Of the two normals, the one facing the sensor.
            Some(if nx * -p[0] + ny * -p[1] >= 0.0 {
                ny.atan2(nx)
            } else {
                (-ny).atan2(-nx)
            })
        })
        .collect()
}

/// A cell's byte: its probability in sixteenths in the high four bits,
/// its surface's normal ([`normal_code`], 0 not known) in the low four.
pub fn pack_cell(probability: f64, normal: u8) -> u8 {
    let sixteenths = (probability.clamp(0.0, 1.0) * 15.0).round() as u8;
    (sixteenths << 4) | (normal & 0b1111)
}

/// [`pack_cell`] of the probability of log odds `l`, `1 / (1 + e^-l)`,
/// found among the log odds where the sixteenths round up rather than
/// by an exponential and a rounding per cell (each a library call in
/// wasm: 1.3 s of the campus's SLAM under Node, finishing submaps). Log
/// odds within a hair of a boundary take the exponential: the byte is
/// [`pack_cell`]'s bit for bit.
pub fn pack_log_odds(l: f32, normal: u8) -> u8 {
    let exact = || pack_cell(1.0 / (1.0 + (-(l as f64)).exp()), normal);
    if !l.is_finite() {
        return exact();
    }
    let rounds_up = SixteenthsBounds::get();
    let l = l as f64;
    let n = rounds_up.0.partition_point(|&b| b <= l);
    let near = |k: usize| rounds_up.0.get(k).is_some_and(|&b| (b - l).abs() < 1e-9);
    if near(n) || n > 0 && near(n - 1) {
        return exact();
    }
    ((n as u8) << 4) | (normal & 0b1111)
}

/// The log odds at which [`pack_cell`]'s sixteenths step from `n` to
/// `n + 1`: those of the probability `(n + 0.5) / 15`.
struct SixteenthsBounds([f64; 15]);

impl SixteenthsBounds {
    fn get() -> &'static Self {
        static BOUNDS: std::sync::OnceLock<SixteenthsBounds> = std::sync::OnceLock::new();
        BOUNDS.get_or_init(|| {
            Self(std::array::from_fn(|n| {
                crate::grid::logit((n as f64 + 0.5) / 15.0)
            }))
        })
    }
}

/// A byte's probability, 0 to 255.
pub(super) fn strength(byte: u8) -> u32 {
    (byte >> 4) as u32 * 17
}

/// A byte's probability as a point whose normal agrees with the codes
/// `agreeing` ([`codes_agreeing`]) scores it: nothing on a surface that
/// faces away from the point's.
pub(super) fn strength_facing(byte: u8, agreeing: u16) -> u32 {
    if agreeing & (1 << (byte & 0b1111)) != 0 {
        strength(byte)
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Log odds packed from their boundaries are packed as the
    /// exponential packs them: across the clamp's range, at every
    /// boundary and a few representable values either side of each.
    #[test]
    fn log_odds_pack_as_their_probabilities_do() {
        let exact = |l: f32, normal: u8| pack_cell(1.0 / (1.0 + (-(l as f64)).exp()), normal);
        let mut values: Vec<f32> = (-40_000..=40_000).map(|k| k as f32 * 2.5e-4).collect();
        for &b in &SixteenthsBounds::get().0 {
            let b = b as f32;
            let mut up = b;
            let mut down = b;
            for _ in 0..64 {
                values.extend([up, down]);
                (up, down) = (up.next_up(), down.next_down());
            }
        }
        values.extend([f32::INFINITY, f32::NEG_INFINITY, 0.0, -0.0, 50.0, -50.0]);
        for l in values {
            for normal in [0, 5, 15] {
                assert_eq!(pack_log_odds(l, normal), exact(l, normal), "{l}");
            }
        }
        assert_eq!(pack_log_odds(0.0, 0) >> 4, 8, "one half rounds up");
    }

    /// A wall ahead of the sensor has its normal pointing back at it, from
    /// its returns' neighbours; a lone return's points back along its beam.
    #[test]
    fn a_surface_normal_faces_the_sensor() {
        let wall: Vec<[f64; 2]> = (0..11).map(|i| [2.0, -1.0 + 0.1 * i as f64]).collect();
        for n in surface_normals(&wall) {
            let n = n.expect("a wall has a normal");
            assert!((n.abs() - std::f64::consts::PI).abs() < 1e-9, "{n}");
        }
        // Lone returns, and returns scattered through leaves, have none.
        assert_eq!(surface_normals(&[[0.0, 3.0], [5.0, 0.0]]), [None, None]);
        let leaves: Vec<[f64; 2]> = (0..11)
            .map(|i| [2.0 + 0.2 * ((i * 7) % 5) as f64, -0.5 + 0.1 * i as f64])
            .collect();
        assert!(surface_normals(&leaves).iter().all(Option::is_none));
        // A face scores a point on a face turned a little, never one on
        // its back.
        let west = normal_code(std::f64::consts::PI);
        let byte = pack_cell(1.0, west);
        assert_eq!(
            strength_facing(
                byte,
                codes_agreeing(std::f64::consts::PI - 1.0, NORMAL_AGREEMENT)
            ),
            255
        );
        assert_eq!(
            strength_facing(byte, codes_agreeing(0.0, NORMAL_AGREEMENT)),
            0
        );
        assert_eq!(
            strength_facing(pack_cell(1.0, 0), codes_agreeing(0.0, BEAM_AGREEMENT)),
            255
        );
    }
}
