//! How far a path of positions is from a reference path: the absolute
//! trajectory error after the best rigid 2D alignment (rotation and
//! translation, least squares: Horn 1987, Umeyama 1991, without scale),
//! the measure of Sturm et al. 2012 (the TUM benchmark) and of Kümmerle et
//! al. 2009's comparison of SLAM results. A map built without known poses
//! may be right but rotated or shifted as a whole; the alignment forgives
//! that and leaves the drift.
//!
//! The sums the closed form needs are kept as the pairs come
//! ([`AlignmentSums::add`]), so that a path growing scan by scan costs one
//! step a scan, never a pass over the scans before it. In two dimensions
//! the best rotation has a closed form: with centred positions `p̃`, `q̃`,
//! `a = Σ p̃·q̃` and `b = Σ p̃ × q̃`, the angle is `atan2(b, a)` and the
//! least sum of squared distances `Σ|p̃|² + Σ|q̃|² − 2·√(a² + b²)`.

use crate::geometry::Pose;

/// The running sums of the closed-form alignment of positions `p`
/// (estimated) onto `q` (reference), kept relative to the first pair so
/// that large coordinates do not cost precision.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AlignmentSums {
    n: usize,
    /// The first pair, the origin of the sums below.
    origin: [f64; 4],
    sum_p: [f64; 2],
    sum_q: [f64; 2],
    sum_pp: f64,
    sum_qq: f64,
    /// `Σ p·q` and `Σ p × q`.
    sum_dot: f64,
    sum_cross: f64,
}

/// The best rigid alignment of the pairs added: `q ≈ R(angle)·p + t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alignment {
    /// Pairs aligned.
    pub pairs: usize,
    /// Root mean square of the distances after the alignment, metres: the
    /// aligned absolute trajectory error.
    pub rms: f64,
    /// The rotation, radians, and the translation, metres, that take the
    /// estimated positions onto the reference.
    pub angle: f64,
    pub translation: [f64; 2],
}

impl AlignmentSums {
    /// Adds the estimated position `p` of a scan and its reference
    /// position `q`.
    pub fn add(&mut self, p: [f64; 2], q: [f64; 2]) {
        if self.n == 0 {
            self.origin = [p[0], p[1], q[0], q[1]];
        }
        let d = [p[0] - self.origin[0], p[1] - self.origin[1]];
        let e = [q[0] - self.origin[2], q[1] - self.origin[3]];
        self.n += 1;
        for i in 0..2 {
            self.sum_p[i] += d[i];
            self.sum_q[i] += e[i];
        }
        self.sum_pp += d[0] * d[0] + d[1] * d[1];
        self.sum_qq += e[0] * e[0] + e[1] * e[1];
        self.sum_dot += d[0] * e[0] + d[1] * e[1];
        self.sum_cross += d[0] * e[1] - d[1] * e[0];
    }

    /// Adds the positions of two poses.
    pub fn add_poses(&mut self, estimated: &Pose, reference: &Pose) {
        self.add([estimated.x, estimated.y], [reference.x, reference.y]);
    }

    /// Pairs added.
    pub fn len(&self) -> usize {
        self.n
    }

    /// True before the first pair.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The best rigid alignment of the pairs so far, `None` before the
    /// first.
    pub fn alignment(&self) -> Option<Alignment> {
        if self.n == 0 {
            return None;
        }
        let n = self.n as f64;
        let mp = [self.sum_p[0] / n, self.sum_p[1] / n];
        let mq = [self.sum_q[0] / n, self.sum_q[1] / n];
        // Centred sums: Σ|p̃|², Σ|q̃|², Σ p̃·q̃, Σ p̃ × q̃.
        let spp = self.sum_pp - n * (mp[0] * mp[0] + mp[1] * mp[1]);
        let sqq = self.sum_qq - n * (mq[0] * mq[0] + mq[1] * mq[1]);
        let a = self.sum_dot - n * (mp[0] * mq[0] + mp[1] * mq[1]);
        let b = self.sum_cross - n * (mp[0] * mq[1] - mp[1] * mq[0]);
        let residual = (spp + sqq - 2.0 * a.hypot(b)).max(0.0);
        let angle = b.atan2(a);
        let (s, c) = angle.sin_cos();
        // t = mean(q) − R·mean(p), back in the frame of the pairs as given.
        let (op, oq) = (
            [self.origin[0], self.origin[1]],
            [self.origin[2], self.origin[3]],
        );
        let p0 = [mp[0] + op[0], mp[1] + op[1]];
        let q0 = [mq[0] + oq[0], mq[1] + oq[1]];
        let translation = [
            q0[0] - (c * p0[0] - s * p0[1]),
            q0[1] - (s * p0[0] + c * p0[1]),
        ];
        Some(Alignment {
            pairs: self.n,
            rms: (residual / n).sqrt(),
            angle,
            translation,
        })
    }
}

/// The sums of a growing path's first `counted` positions, taken at one
/// revision of its poses ([`super::PoseSource::revision`]): a path that
/// grows scan by scan adds its new scans, one whose poses were revised (or
/// that went back) starts again.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GrowingAlignment {
    revision: u64,
    counted: usize,
    sums: AlignmentSums,
}

impl GrowingAlignment {
    /// The alignment of the first `placed` poses of `estimated` onto
    /// `reference` (at `revision`), counting at most `max_new` more of
    /// them: the alignment of those counted, and how many that is.
    pub fn advance(
        &mut self,
        revision: u64,
        estimated: &[Pose],
        reference: &[Pose],
        placed: usize,
        max_new: usize,
    ) -> Option<(Alignment, usize)> {
        let placed = placed.min(estimated.len()).min(reference.len());
        if self.revision != revision || self.counted > placed {
            *self = Self {
                revision,
                ..Self::default()
            };
        }
        let end = placed.min(self.counted.saturating_add(max_new));
        for (p, q) in estimated[self.counted..end]
            .iter()
            .zip(&reference[self.counted..end])
        {
            self.sums.add_poses(p, q);
        }
        self.counted = end;
        Some((self.sums.alignment()?, end))
    }
}

impl Alignment {
    /// The distance, metres, between estimated position `p` moved by the
    /// alignment and its reference position `q`.
    pub fn error_at(&self, p: [f64; 2], q: [f64; 2]) -> f64 {
        let (s, c) = self.angle.sin_cos();
        let x = c * p[0] - s * p[1] + self.translation[0];
        let y = s * p[0] + c * p[1] + self.translation[1];
        (x - q[0]).hypot(y - q[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path with some shape: a rigid alignment of a straight line would
    /// leave its rotation undetermined.
    fn path() -> Vec<[f64; 2]> {
        (0..50)
            .map(|k| {
                let t = k as f64 * 0.3;
                [
                    40.0 + 5.0 * t.cos() + 0.2 * t,
                    -12.0 + 3.0 * (1.7 * t).sin(),
                ]
            })
            .collect()
    }

    fn sums(p: &[[f64; 2]], q: &[[f64; 2]]) -> AlignmentSums {
        let mut s = AlignmentSums::default();
        for (p, q) in p.iter().zip(q) {
            s.add(*p, *q);
        }
        s
    }

    fn moved(p: &[[f64; 2]], angle: f64, t: [f64; 2]) -> Vec<[f64; 2]> {
        let (s, c) = angle.sin_cos();
        p.iter()
            .map(|p| [c * p[0] - s * p[1] + t[0], s * p[0] + c * p[1] + t[1]])
            .collect()
    }

    #[test]
    fn a_rotated_and_shifted_copy_aligns_with_no_error() {
        let q = path();
        let (angle, t) = (0.7, [-3.5, 12.25]);
        let p = moved(&q, angle, t);
        let a = sums(&p, &q).alignment().unwrap();
        // The closed form subtracts sums of squares of the path's spread
        // (metres here): what is left is below a micrometre.
        assert!(a.rms < 1e-6, "rms {}", a.rms);
        // The alignment undoes the motion: rotation by −angle.
        assert!((a.angle + angle).abs() < 1e-12, "angle {}", a.angle);
        for (p, q) in p.iter().zip(&q) {
            assert!(a.error_at(*p, *q) < 1e-9);
        }
    }

    #[test]
    fn an_offset_no_rigid_motion_explains_leaves_its_rms() {
        // Alternate points pushed ±d across the x axis: the mean offset is
        // zero and no rotation lowers it, so every point stays d away.
        let q = path();
        let d = 0.05;
        let p: Vec<[f64; 2]> = q
            .iter()
            .enumerate()
            .map(|(k, q)| {
                let s = if k % 2 == 0 { d } else { -d };
                [q[0] + s, q[1]]
            })
            .collect();
        let a = sums(&p, &q).alignment().unwrap();
        // The best alignment can only do better than none, and the offsets
        // barely correlate with the shape: close to d.
        let unaligned = (p
            .iter()
            .zip(&q)
            .map(|(p, q)| (p[0] - q[0]).powi(2))
            .sum::<f64>()
            / p.len() as f64)
            .sqrt();
        assert!(a.rms <= unaligned + 1e-12);
        assert!((a.rms - d).abs() < 0.002, "rms {} against {d}", a.rms);
    }

    #[test]
    fn the_closed_form_matches_the_rms_of_the_aligned_points() {
        let q = path();
        let mut p = moved(&q, -1.2, [7.0, 1.0]);
        for (k, p) in p.iter_mut().enumerate() {
            p[0] += 0.01 * (k as f64).sin();
            p[1] += 0.02 * (k as f64 * 0.7).cos();
        }
        let a = sums(&p, &q).alignment().unwrap();
        let direct = (p
            .iter()
            .zip(&q)
            .map(|(p, q)| a.error_at(*p, *q).powi(2))
            .sum::<f64>()
            / p.len() as f64)
            .sqrt();
        assert!(a.rms > 0.005);
        assert!((a.rms - direct).abs() < 1e-9, "{} against {direct}", a.rms);
        // And no nearby rigid motion does better.
        for da in [-1e-3, 1e-3] {
            let (s, c) = (a.angle + da).sin_cos();
            let worse = (p
                .iter()
                .zip(&q)
                .map(|(p, q)| {
                    let x = c * p[0] - s * p[1] + a.translation[0];
                    let y = s * p[0] + c * p[1] + a.translation[1];
                    (x - q[0]).powi(2) + (y - q[1]).powi(2)
                })
                .sum::<f64>()
                / p.len() as f64)
                .sqrt();
            assert!(worse >= a.rms);
        }
    }

    #[test]
    fn a_growing_path_is_counted_a_bounded_number_of_scans_a_call() {
        let pose = |p: &[f64; 2]| Pose {
            x: p[0],
            y: p[1],
            theta: 0.0,
        };
        let q: Vec<Pose> = path().iter().map(pose).collect();
        let mut p = q.clone();
        for (k, p) in p.iter_mut().enumerate() {
            p.x += if k % 2 == 0 { 0.03 } else { -0.03 };
        }
        let whole = {
            let (pp, qq): (Vec<[f64; 2]>, Vec<[f64; 2]>) = p
                .iter()
                .zip(&q)
                .map(|(a, b)| ([a.x, a.y], [b.x, b.y]))
                .unzip();
            sums(&pp[..40], &qq[..40]).alignment().unwrap()
        };
        let mut g = GrowingAlignment::default();
        // 40 placed, 15 a call: 15, 30, then all 40, and no further.
        let counted: Vec<usize> = (0..4)
            .map(|_| g.advance(0, &p, &q, 40, 15).unwrap().1)
            .collect();
        assert_eq!(counted, [15, 30, 40, 40]);
        let (a, _) = g.advance(0, &p, &q, 40, 15).unwrap();
        assert_eq!(a, whole);
        // Revised poses start again; so does a path that went back.
        assert_eq!(g.advance(1, &p, &q, 40, 15).unwrap().1, 15);
        assert_eq!(g.advance(1, &p, &q, 10, 15).unwrap().1, 10);
        assert!(GrowingAlignment::default()
            .advance(0, &p, &q, 0, 15)
            .is_none());
    }

    #[test]
    fn one_pair_aligns_exactly_and_none_gives_nothing() {
        assert!(AlignmentSums::default().alignment().is_none());
        let a = sums(&[[3.0, 4.0]], &[[-1.0, 2.0]]).alignment().unwrap();
        assert_eq!(a.pairs, 1);
        assert!(a.rms < 1e-12);
        assert!(a.error_at([3.0, 4.0], [-1.0, 2.0]) < 1e-12);
    }
}
