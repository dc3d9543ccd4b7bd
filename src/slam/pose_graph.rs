//! A pose graph on SE(2) and its optimiser ([`PoseGraph`], [`Optimizer`]):
//! one node per scan, one edge per measured relative pose (a local match
//! between consecutive scans, a loop closure between a scan and the first
//! scan of a submap), each edge weighted by a diagonal information matrix
//! (Grisetti et al. 2010, "A tutorial on graph-based SLAM", eq. 15–30).
//!
//! The optimiser is Gauss–Newton with the first node held fixed (the
//! gauge). Loop edges are robust: Huber's loss, by iteratively reweighted
//! least squares, and a loop edge whose error stays past a gate once the
//! graph has converged is switched off and the graph optimised again
//! without it (a hard form of the switchable constraints of Sünderhauf and
//! Protzel 2012): a wrong closure bends the graph less than a right one,
//! and a right one agrees with the rest once the graph has bent.
//!
//! The linear system is solved by a Cholesky factorisation of our own,
//! over the envelope (skyline) of the matrix (George and Liu 1981,
//! "Computer solution of large sparse positive definite systems", ch. 4):
//! a row's entries from its first nonzero on, and no fill outside that
//! envelope. In the scans' own order a loop edge between scans `i < j`
//! widens the rows of node `j` back to node `i`, and every entry of those
//! rows is an inner product over that width; the nodes are ordered instead
//! by reverse Cuthill–McKee (`envelope_order`), which puts the places a
//! loop joins side by side (Intel at 870 scans: 124 million multiply–adds
//! an optimisation instead of 535 million).
//! No dependency: nothing is added to the wasm but this file's code.
//!
//! Work is counted in multiply–adds of the factorisation and the
//! assembly, so a caller can bound a call ([`Optimizer::run_within`]). A
//! call may stop inside an iteration: between two edges added to the
//! normal equations, two entries of the factor (George and Liu's row-by-row
//! envelope Cholesky, one entry an inner product over the envelope), two
//! rows of a triangular solve; one iteration of a long log with many loops
//! is tens of millions of multiply–adds, a step at most a row's few
//! thousand. Every iteration is the same arithmetic in the
//! same order whatever the budget, so an optimisation spread over budgeted
//! calls ends bit for bit where one call ends.

// The block and envelope loops index rows and columns as the matrix
// algebra writes them.
#![allow(clippy::needless_range_loop)]

use crate::geometry::{wrap_angle, Pose};
use crate::mapping::scan_match::relative_motion;

/// A measured relative pose between two nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    pub from: usize,
    pub to: usize,
    /// `to` as seen from `from`: `(forward, left, turn)`
    /// ([`relative_motion`]).
    pub measurement: [f64; 3],
    /// The diagonal of the information matrix, in `from`'s frame:
    /// `1 / σ²` of forward, left and turn.
    pub information: [f64; 3],
    /// True for a loop closure: Huber's loss and the gate apply.
    pub robust: bool,
    /// False once the gate has switched the edge off.
    pub active: bool,
}

impl Edge {
    /// An edge measured as `measurement` with spreads `sigma` (metres,
    /// metres, radians).
    pub fn new(
        from: usize,
        to: usize,
        measurement: [f64; 3],
        sigma: [f64; 3],
        robust: bool,
    ) -> Self {
        Self {
            from,
            to,
            measurement,
            information: sigma.map(|s| 1.0 / (s * s)),
            robust,
            active: true,
        }
    }

    /// The error of this edge at `nodes`, and its Mahalanobis length.
    fn error(&self, nodes: &[Pose]) -> ([f64; 3], f64) {
        let r = relative_motion(&nodes[self.from], &nodes[self.to]);
        let e = [
            r[0] - self.measurement[0],
            r[1] - self.measurement[1],
            wrap_angle(r[2] - self.measurement[2]),
        ];
        let chi2: f64 = (0..3).map(|i| e[i] * e[i] * self.information[i]).sum();
        (e, chi2.sqrt())
    }
}

/// The robust loss's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobustSettings {
    /// Huber's threshold, in standard deviations of the edge.
    pub huber: f64,
    /// A loop edge still this many standard deviations off once the graph
    /// has converged is switched off.
    pub gate: f64,
    /// Most Gauss–Newton iterations per round (a round ends earlier when
    /// no node moves by more than `tolerance`).
    pub max_iterations: usize,
    /// Metres (and radians): the largest step of a converged round.
    pub tolerance: f64,
}

impl Default for RobustSettings {
    fn default() -> Self {
        Self {
            huber: 1.0,
            gate: 6.0,
            max_iterations: 12,
            tolerance: 1e-5,
        }
    }
}

/// Nodes and edges.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PoseGraph {
    pub nodes: Vec<Pose>,
    pub edges: Vec<Edge>,
}

impl PoseGraph {
    /// The loop edges the gate has switched off.
    pub fn switched_off(&self) -> usize {
        self.edges.iter().filter(|e| e.robust && !e.active).count()
    }

    /// Half the sum of the squared robust errors: what the optimiser lowers.
    pub fn cost(&self, robust: &RobustSettings) -> f64 {
        self.edges
            .iter()
            .filter(|e| e.active)
            .map(|e| {
                let (_, chi) = e.error(&self.nodes);
                if e.robust && chi > robust.huber {
                    robust.huber * (chi - 0.5 * robust.huber)
                } else {
                    0.5 * chi * chi
                }
            })
            .sum()
    }
}

/// Values zeroed per step while the normal equations are laid out (each
/// counts one multiply–add).
pub const ZEROED_PER_STEP: usize = 1 << 14;

/// Where the Gauss–Newton iteration under way is: each stage goes a bounded
/// step at a time (an edge added, an entry of the factor, a row of a
/// triangular solve), so that no step does more than a row's work.
#[derive(Debug, Clone, Default, PartialEq)]
enum Stage {
    /// No iteration under way: the next step starts one (or ends the round).
    #[default]
    Between,
    /// The envelope laid out, its values being zeroed.
    Zeroing(System),
    /// Edges from `next` on still to add to the normal equations.
    Assembling { system: System, next: usize },
    /// The factor's rows before `row` done, and row `row`'s columns before
    /// `col` (its envelope starts at `first[row]`).
    Factoring {
        system: System,
        row: usize,
        col: usize,
    },
    /// `L y = -b`: rows before `row` solved.
    Forward {
        system: System,
        y: Vec<f64>,
        row: usize,
    },
    /// `Lᵀ x = y`: rows from `row` on solved (the rows go down to 0).
    Backward {
        system: System,
        y: Vec<f64>,
        row: usize,
    },
}

/// Where an optimisation is: the iteration of the round, how far that
/// iteration has got, and the work so far.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Optimizer {
    settings: RobustSettings,
    iteration: usize,
    stage: Stage,
    finished: bool,
    /// Multiply–adds since the start.
    work: u64,
    /// Iterations over all rounds.
    pub iterations: usize,
    /// A factorisation that failed (a graph not pinned down): the round
    /// ended there, the nodes as the last good step left them.
    pub failed: bool,
    /// Each free node's place in the normal equations (node `k` at
    /// `position[k - 1]`), chosen once an optimisation starts
    /// ([`envelope_order`]).
    position: Vec<usize>,
}

impl Optimizer {
    pub fn new(settings: RobustSettings) -> Self {
        Self {
            settings,
            ..Self::default()
        }
    }

    pub fn is_finished(&self) -> bool {
        self.finished
    }

    /// Multiply–adds spent so far.
    pub fn work(&self) -> u64 {
        self.work
    }

    /// Runs to the end, in one call.
    pub fn run(&mut self, graph: &mut PoseGraph) {
        while !self.run_within(graph, u64::MAX) {}
    }

    /// Runs until this call's work reaches `budget` multiply–adds (at
    /// least one step: an edge added, an entry of the factor, a row of a
    /// solve, a block of values zeroed, when any is left), stopping inside
    /// an iteration if need be: a call does at most its budget and one
    /// step's work (a row's, or [`ZEROED_PER_STEP`]). True once finished.
    /// The nodes move only at the end of an iteration, and every iteration
    /// is the same arithmetic in the same order however it is cut, so an
    /// optimisation spread over budgeted calls ends bit for bit where one
    /// call ends.
    pub fn run_within(&mut self, graph: &mut PoseGraph, budget: u64) -> bool {
        let start = self.work;
        let limit = start.saturating_add(budget);
        loop {
            self.advance(graph, limit);
            if self.finished || self.work >= limit && self.work > start {
                return self.finished;
            }
        }
    }

    /// Goes on with the stage under way until the work reaches `limit` or
    /// the stage ends (at least one unit of it: an edge, an entry, a row).
    fn advance(&mut self, graph: &mut PoseGraph, limit: u64) {
        match std::mem::take(&mut self.stage) {
            Stage::Between => self.begin(graph),
            Stage::Zeroing(mut system) => {
                let total = system.start[system.b.len()];
                loop {
                    let more = ZEROED_PER_STEP.min(total - system.values.len());
                    system.values.resize(system.values.len() + more, 0.0);
                    self.work += more as u64;
                    if system.values.len() == total || self.work >= limit {
                        break;
                    }
                }
                self.stage = if system.values.len() == total {
                    Stage::Assembling { system, next: 0 }
                } else {
                    Stage::Zeroing(system)
                };
            }
            Stage::Assembling {
                mut system,
                mut next,
            } => {
                while next < graph.edges.len() {
                    let e = &graph.edges[next];
                    if e.active {
                        system.add_edge(e, &graph.nodes, &self.settings);
                    }
                    next += 1;
                    self.work += EDGE_WORK;
                    if self.work >= limit {
                        break;
                    }
                }
                self.stage = if next == graph.edges.len() {
                    Stage::Factoring {
                        col: system.first[0],
                        system,
                        row: 0,
                    }
                } else {
                    Stage::Assembling { system, next }
                };
            }
            Stage::Factoring {
                mut system,
                mut row,
                mut col,
            } => {
                let dim = system.b.len();
                while row < dim {
                    let (work, positive) = system.factor_entry(row, col);
                    self.work += work;
                    if !positive {
                        self.failed = true;
                        self.end_iteration(graph, 0.0);
                        return;
                    }
                    col += 1;
                    if col > row {
                        row += 1;
                        col = system.first.get(row).copied().unwrap_or(0);
                    }
                    if self.work >= limit {
                        break;
                    }
                }
                self.stage = if row == dim {
                    let y = system.b.iter().map(|v| -v).collect();
                    Stage::Forward { system, y, row: 0 }
                } else {
                    Stage::Factoring { system, row, col }
                };
            }
            Stage::Forward {
                system,
                mut y,
                mut row,
            } => {
                let dim = y.len();
                while row < dim {
                    self.work += system.forward_row(row, &mut y);
                    row += 1;
                    if self.work >= limit {
                        break;
                    }
                }
                self.stage = if row == dim {
                    Stage::Backward {
                        system,
                        y,
                        row: dim,
                    }
                } else {
                    Stage::Forward { system, y, row }
                };
            }
            Stage::Backward {
                system,
                mut y,
                mut row,
            } => {
                while row > 0 {
                    row -= 1;
                    self.work += system.backward_row(row, &mut y);
                    if self.work >= limit {
                        break;
                    }
                }
                if row == 0 {
                    let step = Self::apply(graph, &y, &system.position);
                    self.end_iteration(graph, step);
                } else {
                    self.stage = Stage::Backward { system, y, row };
                }
            }
        }
    }

    /// Starts the next Gauss–Newton iteration of the round (laying out the
    /// normal equations' envelope), or, past the round's last, ends it.
    fn begin(&mut self, graph: &mut PoseGraph) {
        if graph.nodes.len() < 2 {
            self.finished = true;
            return;
        }
        if self.iteration < self.settings.max_iterations {
            self.iteration += 1;
            self.iterations += 1;
            if self.position.len() != graph.nodes.len() - 1 {
                self.position = envelope_order(graph);
                self.work += 4 * graph.edges.len() as u64 + graph.nodes.len() as u64;
            }
            self.stage = Stage::Zeroing(System::lay_out(graph, self.position.clone()));
        } else {
            self.end_iteration(graph, 0.0);
        }
    }

    /// Moves every node but the first by its share of `dx` (node `k`'s at
    /// block `position[k - 1]`): the largest change of a coordinate.
    fn apply(graph: &mut PoseGraph, dx: &[f64], position: &[usize]) -> f64 {
        let mut largest: f64 = 0.0;
        for (k, node) in graph.nodes.iter_mut().enumerate().skip(1) {
            let at = position[k - 1];
            let d = &dx[3 * at..3 * at + 3];
            node.x += d[0];
            node.y += d[1];
            node.theta = wrap_angle(node.theta + d[2]);
            largest = largest.max(d[0].abs()).max(d[1].abs()).max(d[2].abs());
        }
        largest
    }

    /// An iteration ended with its largest `step`: the round goes on while
    /// the nodes move; once it has converged, the gate.
    fn end_iteration(&mut self, graph: &mut PoseGraph, step: f64) {
        self.stage = Stage::Between;
        if step > self.settings.tolerance {
            return;
        }
        // A round converged: the worst loop edge past the gate is switched
        // off, and the graph optimised again.
        let worst = graph
            .edges
            .iter()
            .enumerate()
            .filter(|(_, e)| e.robust && e.active)
            .map(|(i, e)| (i, e.error(&graph.nodes).1))
            .filter(|&(_, chi)| chi > self.settings.gate)
            .fold(None, |best: Option<(usize, f64)>, (i, chi)| match best {
                Some((_, b)) if b >= chi => best,
                _ => Some((i, chi)),
            });
        self.work += graph.edges.len() as u64;
        match worst {
            Some((i, _)) if !self.failed => {
                graph.edges[i].active = false;
                self.iteration = 0;
            }
            _ => self.finished = true,
        }
    }
}

/// Multiply–adds counted for an edge added to the normal equations (its
/// error, Jacobians and blocks), active or not.
const EDGE_WORK: u64 = 60;

/// The normal equations `H dx = -b` over nodes `1..n` (node 0 fixed), `H`
/// stored by rows over its envelope.
#[derive(Debug, Clone, Default, PartialEq)]
struct System {
    /// First column of each row's envelope.
    first: Vec<usize>,
    /// Where each row starts in `values`; one more, the envelope's size.
    start: Vec<usize>,
    /// The envelope's values by rows (filled by [`Stage::Zeroing`]).
    values: Vec<f64>,
    b: Vec<f64>,
    /// Node `k`'s block is block `position[k - 1]`.
    position: Vec<usize>,
}

/// An order of the free nodes (every node but the first) that keeps the
/// factor's envelope small: reverse Cuthill–McKee (George and Liu 1981,
/// ch. 4) over the active edges, from a node of least degree, each node's
/// neighbours taken by degree then index. Node `k`'s place is
/// `position[k - 1]`.
///
/// In the scans' own order a loop edge from scan `j` back to scan `i`
/// widens every row between them back to `i` (Intel's graph: some fifty
/// million multiply–adds an iteration at 900 scans); ordered by
/// breadth-first levels from one end, the scans a loop joins sit side by
/// side, and a row reaches back only over its level.
fn envelope_order(graph: &PoseGraph) -> Vec<usize> {
    let n = graph.nodes.len().saturating_sub(1);
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); n];
    for e in graph.edges.iter().filter(|e| e.active) {
        if e.from == 0 || e.to == 0 || e.from == e.to {
            continue;
        }
        neighbours[e.from - 1].push(e.to - 1);
        neighbours[e.to - 1].push(e.from - 1);
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    let degree: Vec<usize> = neighbours.iter().map(Vec::len).collect();
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    let mut queue = std::collections::VecDeque::new();
    let mut fresh = Vec::new();
    while order.len() < n {
        // A component's start: its unplaced node of least degree.
        let Some(start) = (0..n)
            .filter(|&i| !placed[i])
            .min_by_key(|&i| (degree[i], i))
        else {
            break;
        };
        placed[start] = true;
        queue.push_back(start);
        while let Some(u) = queue.pop_front() {
            order.push(u);
            fresh.clear();
            fresh.extend(neighbours[u].iter().copied().filter(|&v| !placed[v]));
            fresh.sort_unstable_by_key(|&v| (degree[v], v));
            for &v in &fresh {
                placed[v] = true;
                queue.push_back(v);
            }
        }
    }
    let mut position = vec![0; n];
    for (place, &node) in order.iter().rev().enumerate() {
        position[node] = place;
    }
    position
}

impl System {
    /// The envelope of the graph's active edges, its values not yet
    /// allocated.
    fn lay_out(graph: &PoseGraph, position: Vec<usize>) -> Self {
        let n = graph.nodes.len() - 1;
        let dim = 3 * n;
        // Each block's row reaches back to its lowest neighbour's block.
        let mut lowest: Vec<usize> = (0..n).collect();
        for e in graph.edges.iter().filter(|e| e.active) {
            if e.from == 0 || e.to == 0 || e.from == e.to {
                continue;
            }
            let (p, q) = (position[e.from - 1], position[e.to - 1]);
            let (a, b) = (p.min(q), p.max(q));
            lowest[b] = lowest[b].min(a);
        }
        let mut first = Vec::with_capacity(dim);
        let mut start = Vec::with_capacity(dim + 1);
        let mut total = 0;
        for r in 0..dim {
            let f = 3 * lowest[r / 3];
            first.push(f);
            start.push(total);
            total += r + 1 - f;
        }
        start.push(total);
        Self {
            first,
            start,
            values: Vec::with_capacity(total),
            b: vec![0.0; dim],
            position,
        }
    }

    fn at(&mut self, r: usize, c: usize) -> &mut f64 {
        let (r, c) = if c > r { (c, r) } else { (r, c) };
        &mut self.values[self.start[r] + c - self.first[r]]
    }

    fn add_edge(&mut self, e: &Edge, nodes: &[Pose], robust: &RobustSettings) {
        let (err, chi) = e.error(nodes);
        let weight = if e.robust && chi > robust.huber {
            robust.huber / chi
        } else {
            1.0
        };
        let omega = e.information.map(|w| w * weight);
        let (pi, pj) = (&nodes[e.from], &nodes[e.to]);
        let (s, c) = pi.theta.sin_cos();
        let (dx, dy) = (pj.x - pi.x, pj.y - pi.y);
        // d(error)/d(from) and d(error)/d(to), rows the error's components.
        let a = [
            [-c, -s, -s * dx + c * dy],
            [s, -c, -c * dx - s * dy],
            [0.0, 0.0, -1.0],
        ];
        let bj = [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]];
        // Each end's block, `None` for the fixed first node.
        let block = |n: usize| n.checked_sub(1).map(|k| self.position[k]);
        let blocks = [(block(e.from), a), (block(e.to), bj)];
        for &(bi, ji) in &blocks {
            let Some(bi) = bi else { continue };
            let oi = 3 * bi;
            for p in 0..3 {
                let g: f64 = (0..3).map(|k| ji[k][p] * omega[k] * err[k]).sum();
                self.b[oi + p] += g;
            }
            for &(bj, jj) in &blocks {
                let Some(bj) = bj.filter(|&bj| bj <= bi) else {
                    continue;
                };
                let oj = 3 * bj;
                for p in 0..3 {
                    for q in 0..3 {
                        if bi == bj && q > p {
                            continue;
                        }
                        let h: f64 = (0..3).map(|k| ji[k][p] * omega[k] * jj[k][q]).sum();
                        *self.at(oi + p, oj + q) += h;
                    }
                }
            }
        }
    }

    /// Entry `(r, c)` of the factor `H = L Lᵀ`, in place over the
    /// envelope (rows before `r` and the entries of row `r` before `c`
    /// factored already): its multiply–adds, and false when `H` is not
    /// positive definite (the entry left as it was).
    fn factor_entry(&mut self, r: usize, c: usize) -> (u64, bool) {
        let (fr, fc) = (self.first[r], self.first[c]);
        let k0 = fr.max(fc);
        let (rs, cs) = (self.start[r], self.start[c]);
        let sum = self.values[rs + c - fr]
            - dot(
                &self.values[rs + k0 - fr..rs + c - fr],
                &self.values[cs + k0 - fc..cs + c - fc],
            );
        let work = (c - k0) as u64 + 1;
        let entry = if c < r {
            sum / self.values[cs + c - fc]
        } else if sum > 0.0 && sum.is_finite() {
            sum.sqrt()
        } else {
            return (work, false);
        };
        self.values[rs + c - fr] = entry;
        (work, true)
    }

    /// Row `r` of `L y = -b` (`y` holding `-b` past the rows solved): its
    /// multiply–adds, the row's envelope.
    fn forward_row(&self, r: usize, y: &mut [f64]) -> u64 {
        let (fr, rs) = (self.first[r], self.start[r]);
        let mut sum = y[r];
        for k in fr..r {
            sum -= self.values[rs + k - fr] * y[k];
        }
        y[r] = sum / self.values[rs + r - fr];
        (self.start[r + 1] - rs) as u64
    }

    /// Row `r` of `Lᵀ x = y` (rows past `r` solved): its multiply–adds.
    fn backward_row(&self, r: usize, y: &mut [f64]) -> u64 {
        let (fr, rs) = (self.first[r], self.start[r]);
        y[r] /= self.values[rs + r - fr];
        let xr = y[r];
        for k in fr..r {
            y[k] -= self.values[rs + k - fr] * xr;
        }
        (self.start[r + 1] - rs) as u64
    }
}

/// The inner product of two rows of the envelope, in four running sums
/// (each entry of the factor is one; the sums' independence lets a
/// processor overlap their multiply–adds, and the slices' bounds are
/// checked once, not per term). The same order of additions every time,
/// so the factor is the same bit for bit however a call is cut.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut sums = [0.0f64; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (a4.remainder(), b4.remainder());
    for (x, y) in a4.zip(b4) {
        for lane in 0..4 {
            sums[lane] += x[lane] * y[lane];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_envelope_cholesky_solves_a_chain_with_a_loop() {
        // Three nodes in a line, measured exactly, the last two started off.
        let mut g = PoseGraph {
            nodes: vec![
                Pose {
                    x: 0.0,
                    y: 0.0,
                    theta: 0.0,
                },
                Pose {
                    x: 1.3,
                    y: 0.2,
                    theta: 0.1,
                },
                Pose {
                    x: 1.7,
                    y: -0.4,
                    theta: -0.2,
                },
            ],
            edges: vec![
                Edge::new(0, 1, [1.0, 0.0, 0.0], [0.1, 0.1, 0.05], false),
                Edge::new(1, 2, [1.0, 0.0, 0.0], [0.1, 0.1, 0.05], false),
                Edge::new(0, 2, [2.0, 0.0, 0.0], [0.1, 0.1, 0.05], true),
            ],
        };
        Optimizer::new(RobustSettings::default()).run(&mut g);
        assert!(
            (g.nodes[2].x - 2.0).abs() < 1e-6 && g.nodes[2].y.abs() < 1e-6,
            "{:?}",
            g.nodes
        );
    }
}
