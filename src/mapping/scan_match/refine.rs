//! Gauss–Newton on an interpolated map (Kohlbrecher et al. 2011, Hector
//! SLAM, eqs. 7–13): the pose `ξ = (x, y, θ)` that minimises
//!
//! `E(ξ) = mean_i (1 - M(S_i(ξ)))^2 + (wt |t - t_a|)^2 + (wr (θ - θ_a))^2`
//!
//! where `S_i(ξ)` is point `i` in the world at `ξ`, `M` the map read
//! with its gradient `∇M` as a quadratic B-spline of each cell's
//! [`super::window::match_value`] (Hector reads the probability,
//! bilinearly; [`crate::grid::sample::quadratic_bspline`] says why a
//! smooth reading fits better), and the last two terms hold the pose
//! near an anchor `ξ_a` (the search's pose) where the map says nothing
//! (Cartographer's Ceres matcher adds the same terms). Each step solves
//! `H Δξ = b` with `H = mean J_i^T J_i + diag(wt², wt², wr²)`,
//! `J_i = ∇M · ∂S_i/∂ξ`, damped as Levenberg–Marquardt does, and is kept
//! only if it lowers `E` (tried again more damped otherwise), so a step
//! never makes the fit worse.

use super::match_map::MatchMap;
use super::window::{match_value, FieldSample, PooledLevel};
use crate::geometry::{wrap_angle, Pose};
use crate::grid::sample::quadratic_bspline_of_patch;
use nalgebra::{Matrix3, Vector3};

/// A map's match value read at any world point, with its gradient.
pub trait OccupancyField {
    fn sample(&self, x: f64, y: f64) -> FieldSample;
}

impl OccupancyField for PooledLevel {
    #[inline]
    fn sample(&self, x: f64, y: f64) -> FieldSample {
        PooledLevel::sample(self, x, y)
    }
}

/// A map itself as a field: its cells' match values read smoothly
/// ([`crate::grid::sample::quadratic_bspline`]); a cell outside the map
/// counts as unknown (0).
pub struct GridField<'a> {
    grid: &'a dyn MatchMap,
    l_unknown: f32,
}

impl<'a> GridField<'a> {
    pub fn new(grid: &'a dyn MatchMap) -> Self {
        Self {
            grid,
            l_unknown: grid.unknown_log_odds(),
        }
    }
}

impl OccupancyField for GridField<'_> {
    #[inline]
    fn sample(&self, x: f64, y: f64) -> FieldSample {
        let g = self.grid.geometry();
        let (u, v) = g.world_to_grid(x, y);
        if !(u.is_finite() && v.is_finite()) {
            return FieldSample {
                value: 0.0,
                gradient: [0.0; 2],
            };
        }
        let (value, [gx, gy]) = quadratic_bspline_of_patch(u, v, |i, j| {
            let around = self.grid.log_odds_around(i, j);
            // (Loops, not `array::map`: in wasm that moved each value
            // through a drain, 1.5 s of the campus's SLAM under Node.)
            let mut values = [[0.0; 3]; 3];
            for (row, cells) in values.iter_mut().zip(&around) {
                for (value, l) in row.iter_mut().zip(cells) {
                    if let Some(l) = *l {
                        *value = match_value(l, self.l_unknown);
                    }
                }
            }
            values
        });
        let per_metre = 1.0 / g.resolution();
        FieldSample {
            value,
            gradient: [gx * per_metre, gy * per_metre],
        }
    }
}

/// How strongly a refinement holds the pose near its anchor: per metre
/// and per radian (the `wt` and `wr` above).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnchorWeights {
    pub translation: f64,
    pub rotation: f64,
}

/// What a refinement did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refined {
    pub pose: Pose,
    /// `E` at the pose.
    pub cost: f64,
    /// The fit's own curvature at the pose, `mean J_i^T J_i` (without the
    /// anchor's terms), `(x, y)` block: how sharply the map pins the
    /// position, direction by direction (Hector SLAM estimates the match's
    /// covariance from the same matrix).
    pub curvature: [[f64; 2]; 2],
    /// Steps kept.
    pub iterations: usize,
    /// Points sampled (its work).
    pub samples: usize,
}

/// The normal equations at a pose.
struct Linearised {
    /// `E`.
    cost: f64,
    /// `H`, the anchor's terms included.
    h: Matrix3<f64>,
    b: Vector3<f64>,
    /// `H` without the anchor's terms.
    fit: Matrix3<f64>,
}

/// `E`, and the normal equations' `H` and `b`, at `pose`.
fn linearise(
    field: &dyn OccupancyField,
    points: &[[f64; 2]],
    pose: &Pose,
    anchor: &Pose,
    w: AnchorWeights,
) -> Linearised {
    let (s, c) = pose.theta.sin_cos();
    let mut h = Matrix3::zeros();
    let mut b = Vector3::zeros();
    let mut sum = 0.0;
    for &[px, py] in points {
        let (x, y) = (pose.x + c * px - s * py, pose.y + s * px + c * py);
        let f = field.sample(x, y);
        let r = 1.0 - f.value;
        sum += r * r;
        let [gx, gy] = f.gradient;
        let j = Vector3::new(gx, gy, gx * (-s * px - c * py) + gy * (c * px - s * py));
        h += j * j.transpose();
        b += j * r;
    }
    let n = points.len().max(1) as f64;
    let (wt2, wr2) = (w.translation.powi(2), w.rotation.powi(2));
    let (dx, dy) = (pose.x - anchor.x, pose.y - anchor.y);
    let dt = wrap_angle(pose.theta - anchor.theta);
    let cost = sum / n + wt2 * (dx * dx + dy * dy) + wr2 * dt * dt;
    h /= n;
    b /= n;
    let fit = h;
    h += Matrix3::from_diagonal(&Vector3::new(wt2, wt2, wr2));
    b -= Vector3::new(wt2 * dx, wt2 * dy, wr2 * dt);
    Linearised { cost, h, b, fit }
}

/// Steps smaller than this (metres and radians) end the refinement: half
/// a millimetre, a hundredth of a 5 cm cell.
const CONVERGED: f64 = 5e-4;

/// The Levenberg–Marquardt damping a refinement starts from, the least
/// it falls to and the most it rises to before giving up: each step
/// solves `(H + λ diag H) Δξ = b`. Down a corridor the map barely slopes
/// along the walls, and a plain Gauss–Newton step along them overshoots
/// by metres; the damping shortens it until the fit improves, direction
/// by direction, where halving the whole step would stop short.
const INITIAL_DAMPING: f64 = 1e-3;
const MIN_DAMPING: f64 = 1e-9;
const MAX_DAMPING: f64 = 1e6;

/// Refines `start` on `field` with at most `max_iterations` steps kept
/// (Levenberg–Marquardt: a step that does not lower `E` is tried again
/// more damped, at most three tries per step kept), held near `anchor`
/// with weights `w`.
pub fn gauss_newton(
    field: &dyn OccupancyField,
    points: &[[f64; 2]],
    start: Pose,
    anchor: &Pose,
    w: AnchorWeights,
    max_iterations: usize,
) -> Refined {
    let mut pose = start;
    let mut at = linearise(field, points, &pose, anchor, w);
    let mut samples = points.len();
    let mut iterations = 0;
    let mut damping = INITIAL_DAMPING;
    // Each try reads every point once: at most three per step kept.
    for _ in 0..3 * max_iterations {
        if iterations == max_iterations {
            break;
        }
        let mut h = at.h;
        for i in 0..3 {
            h[(i, i)] *= 1.0 + damping;
        }
        let Some(step) = h.try_inverse().map(|inv| inv * at.b) else {
            break;
        };
        if !step.iter().all(|v| v.is_finite()) {
            break;
        }
        let trial = Pose {
            x: pose.x + step[0],
            y: pose.y + step[1],
            theta: wrap_angle(pose.theta + step[2]),
        };
        let next = linearise(field, points, &trial, anchor, w);
        samples += points.len();
        if next.cost < at.cost {
            pose = trial;
            at = next;
            iterations += 1;
            damping = (damping * 0.1).max(MIN_DAMPING);
            if step[0].hypot(step[1]) < CONVERGED && step[2].abs() < CONVERGED {
                break;
            }
        } else {
            damping *= 10.0;
            if damping > MAX_DAMPING {
                break;
            }
        }
    }
    Refined {
        pose,
        cost: at.cost,
        curvature: [
            [at.fit[(0, 0)], at.fit[(0, 1)]],
            [at.fit[(1, 0)], at.fit[(1, 1)]],
        ],
        iterations,
        samples,
    }
}
