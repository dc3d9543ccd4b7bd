//! The correlative search (Olson 2009; Cartographer's real-time
//! correlative scan matcher, Hess et al. 2016): every candidate pose of a
//! window around the prediction — headings a fixed step apart, positions
//! one coarse cell apart — is scored by the mean match value
//! ([`super::window::match_value`]) of the scan's points on the coarse
//! level, and ranked by that evidence against the prediction's prior
//! ([`super::Prediction`]).
//! The best candidate of each heading is kept, and the best few headings
//! that are not neighbours of a better one are handed on: the coarse level
//! blurs (a max-pooled 20 cm cell in a cluttered place is a wall almost
//! everywhere), so a wrong heading can outscore the right one by a little
//! there, and only the map itself tells them apart
//! ([`super::ScanMatcher`] refines each).
//!
//! Positions step by exactly one coarse cell, so a point's place inside its
//! cell (and its bilinear weights) is the same for every position of one
//! heading: each heading rotates the points once, and each candidate then
//! costs four reads and a few products per point.

use super::points::ScanPoints;
use super::window::PooledLevel;
use super::{MatchSettings, Prediction};
use crate::geometry::{wrap_angle, Pose};

/// A point of the rotated scan on the coarse level: the coarse cell below
/// and left of it (the first of the four whose centres surround it) and
/// its place between their centres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacedPoint {
    i: i64,
    j: i64,
    /// The bilinear weights of the four cells `(i, j)`, `(i + 1, j)`,
    /// `(i, j + 1)` and `(i + 1, j + 1)`.
    w: [f32; 4],
}

/// One candidate pose of the search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    pub pose: Pose,
    /// Its heading's offset from the prediction's, in steps.
    pub step: i64,
    /// Its mean match value on the coarse level.
    pub score: f64,
    /// What ranks it: its points' evidence plus its log prior, nats.
    pub weighted: f64,
}

/// The search's answer.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SearchOutcome {
    /// The best candidates of distinct headings, best first.
    pub best: Vec<Candidate>,
    /// Candidates scored.
    pub candidates: usize,
}

/// Headings this many steps or fewer from a better one are not handed on
/// (they are that one's slope, and Gauss–Newton climbs it anyway).
const HEADING_SEPARATION: i64 = 2;

/// `0, -1, 1, -2, 2, …, -n, n`: the order in which a search tries offsets,
/// so that among candidates of equal score the one nearest the prediction
/// is found first (and kept: only a strictly better one replaces it).
fn centre_out(n: i64) -> impl Iterator<Item = i64> {
    (0..=2 * n).map(|k| if k % 2 == 1 { -(k + 1) / 2 } else { k / 2 })
}

/// The headings a search tries around `predicted`, in order: as an offset
/// from the prediction's and as a heading.
pub fn headings(predicted: &Pose, settings: &MatchSettings) -> impl Iterator<Item = (f64, f64)> {
    let n = settings.heading_steps() as i64;
    let (step, theta) = (settings.angular_step, predicted.theta);
    centre_out(n).map(move |k| {
        let offset = k as f64 * step;
        (offset, wrap_angle(theta + offset))
    })
}

/// The world box `[min_x, min_y, max_x, max_y]` every candidate of the
/// search puts a point in (before the position offsets).
pub fn reach_box(points: &[[f64; 2]], predicted: &Pose, settings: &MatchSettings) -> [f64; 4] {
    let mut b = [predicted.x, predicted.y, predicted.x, predicted.y];
    for (_, theta) in headings(predicted, settings) {
        let trig = theta.sin_cos();
        let pose = Pose {
            theta,
            ..*predicted
        };
        for &p in points {
            let [x, y] = ScanPoints::to_world(&pose, trig, p);
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        }
    }
    b
}

/// Scores every candidate of the window on `level` (the coarse level,
/// its match values filled) and returns the best of up to `keep` distinct
/// headings into `out`; `placed` is scratch.
pub fn correlative_search(
    level: &PooledLevel,
    points: &[[f64; 2]],
    prediction: &Prediction,
    settings: &MatchSettings,
    keep: usize,
    placed: &mut Vec<PlacedPoint>,
    out: &mut SearchOutcome,
) {
    let cell = level.cell_size();
    let m = settings.position_steps(cell) as i64;
    let (nx, ny) = level.size();
    let values = level.values();
    let [ox, oy] = level.origin();
    let predicted = &prediction.pose;
    let n = points.len().max(1) as f64;
    out.best.clear();
    out.candidates = 0;
    let n_steps = settings.heading_steps() as i64;
    for (k, (offset, theta)) in centre_out(n_steps).zip(headings(predicted, settings)) {
        let mut best: Option<Candidate> = None;
        let trig = theta.sin_cos();
        let pose = Pose {
            theta,
            ..*predicted
        };
        placed.clear();
        let (mut lo, mut hi) = ((i64::MAX, i64::MAX), (i64::MIN, i64::MIN));
        for &p in points {
            let [x, y] = ScanPoints::to_world(&pose, trig, p);
            let u = (x - ox) / cell - 0.5;
            let v = (y - oy) / cell - 0.5;
            let (i, j) = (u.floor() as i64, v.floor() as i64);
            lo = (lo.0.min(i), lo.1.min(j));
            hi = (hi.0.max(i), hi.1.max(j));
            let (fx, fy) = (u - i as f64, v - j as f64);
            placed.push(PlacedPoint {
                i,
                j,
                w: [
                    ((1.0 - fx) * (1.0 - fy)) as f32,
                    (fx * (1.0 - fy)) as f32,
                    ((1.0 - fx) * fy) as f32,
                    (fx * fy) as f32,
                ],
            });
        }
        // Every candidate's four cells lie in the window (the matcher built
        // it so): read without checks. Otherwise, check each read.
        let inside =
            lo.0 - m >= 0 && lo.1 - m >= 0 && hi.0 + m + 1 < nx as i64 && hi.1 + m + 1 < ny as i64;
        for ky in centre_out(m) {
            for kx in centre_out(m) {
                // (Summed in f32, in a fixed order: the scores only rank
                // candidates, and the sum of a few hundred values in [0, 1]
                // keeps six significant digits.)
                let mut sum = 0f32;
                if inside {
                    for q in placed.iter() {
                        let k = ((q.j + ky) as usize) * nx + (q.i + kx) as usize;
                        sum += bilinear(values, k, nx, &q.w);
                    }
                } else {
                    for q in placed.iter() {
                        let (i, j) = (q.i + kx, q.j + ky);
                        if i >= 0 && j >= 0 && i + 1 < nx as i64 && j + 1 < ny as i64 {
                            sum += bilinear(values, j as usize * nx + i as usize, nx, &q.w);
                        }
                    }
                }
                let score = sum as f64 / n;
                let (dx, dy) = (kx as f64 * cell, ky as f64 * cell);
                let weighted = sum as f64 + prediction.log_prior_of_offset(dx, dy, offset);
                out.candidates += 1;
                // Strictly better only: among equals the one tried first,
                // the nearest the prediction, stays.
                if best.as_ref().is_none_or(|b| weighted > b.weighted) {
                    best = Some(Candidate {
                        pose: Pose {
                            x: predicted.x + dx,
                            y: predicted.y + dy,
                            theta,
                        },
                        step: k,
                        score,
                        weighted,
                    });
                }
            }
        }
        out.best.extend(best);
    }
    // Best first, each heading apart from those kept before it; among
    // equals the heading nearest the prediction (the one tried first: the
    // rest keep the order they were tried in). A few picks among a few
    // dozen headings: no sort needed.
    let mut kept = 0;
    while kept < keep {
        let mut pick: Option<usize> = None;
        for i in kept..out.best.len() {
            let c = out.best[i];
            let apart = out.best[..kept]
                .iter()
                .all(|b| (b.step - c.step).abs() > HEADING_SEPARATION);
            if apart && pick.is_none_or(|p| c.weighted.total_cmp(&out.best[p].weighted).is_gt()) {
                pick = Some(i);
            }
        }
        let Some(p) = pick else {
            break;
        };
        out.best[kept..=p].rotate_right(1);
        kept += 1;
    }
    out.best.truncate(kept);
}

/// Bilinear match value between the centres of cells `k`, `k + 1`, `k + nx`
/// and `k + nx + 1`.
#[inline(always)]
fn bilinear(v: &[f32], k: usize, nx: usize, w: &[f32; 4]) -> f32 {
    let (bottom, top) = (&v[k..k + 2], &v[k + nx..k + nx + 2]);
    w[0] * bottom[0] + w[1] * bottom[1] + w[2] * top[0] + w[3] * top[1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_are_tried_from_the_centre_out() {
        assert_eq!(centre_out(2).collect::<Vec<_>>(), [0, -1, 1, -2, 2]);
        assert_eq!(centre_out(0).collect::<Vec<_>>(), [0]);
    }
}
