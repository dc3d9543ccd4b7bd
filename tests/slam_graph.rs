//! The pose graph's optimiser: a small graph whose answer is known, one
//! optimisation spread over budgeted calls against one call, bit for bit,
//! a budgeted call that stays within its budget though one iteration is
//! many budgets long, and a wrong closure between twin corridors switched
//! off while a right one closes the loop.

use occgrid::geometry::Pose;
use occgrid::mapping::scan_match::relative_motion;
use occgrid::slam::pose_graph::ZEROED_PER_STEP;
use occgrid::slam::{Edge, Optimizer, PoseGraph, RobustSettings};

fn pose(x: f64, y: f64, theta: f64) -> Pose {
    Pose { x, y, theta }
}

/// A loop round a 10 x 4 m block (two long sides: the twin corridors),
/// one pose every metre, heading along the way.
fn ring() -> Vec<Pose> {
    let mut out = Vec::new();
    for i in 0..10 {
        out.push(pose(i as f64, 0.0, 0.0));
    }
    for i in 0..4 {
        out.push(pose(10.0, i as f64, std::f64::consts::FRAC_PI_2));
    }
    for i in 0..10 {
        out.push(pose(10.0 - i as f64, 4.0, std::f64::consts::PI));
    }
    for i in 0..4 {
        out.push(pose(0.0, 4.0 - i as f64, -std::f64::consts::FRAC_PI_2));
    }
    out
}

/// The ring's chain, each link measured with a small systematic turn (the
/// drift), and the nodes started where the drifting links put them.
fn drifting(truth: &[Pose]) -> PoseGraph {
    let mut edges = Vec::new();
    let mut nodes = vec![truth[0]];
    for k in 1..truth.len() {
        let mut m = relative_motion(&truth[k - 1], &truth[k]);
        m[2] += 0.01;
        edges.push(Edge::new(k - 1, k, m, [0.05, 0.05, 0.02], false));
        let last = nodes[k - 1];
        nodes.push(occgrid::mapping::scan_match::compose(&last, m));
    }
    PoseGraph { nodes, edges }
}

fn rms(a: &[Pose], b: &[Pose]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p.x - q.x).powi(2) + (p.y - q.y).powi(2))
        .sum();
    (sum / a.len() as f64).sqrt()
}

#[test]
fn the_optimiser_finds_a_small_graph_whose_answer_is_known() {
    // Exact measurements of every link and two closures, nodes started off:
    // the answer is the truth.
    let truth = ring();
    let mut g = drifting(&truth);
    for e in g.edges.iter_mut() {
        e.measurement = relative_motion(&truth[e.from], &truth[e.to]);
    }
    let n = truth.len();
    g.edges.push(Edge::new(
        0,
        n - 1,
        relative_motion(&truth[0], &truth[n - 1]),
        [0.05, 0.05, 0.02],
        true,
    ));
    g.edges.push(Edge::new(
        5,
        20,
        relative_motion(&truth[5], &truth[20]),
        [0.05, 0.05, 0.02],
        true,
    ));
    let before = rms(&g.nodes, &truth);
    let mut o = Optimizer::new(RobustSettings::default());
    o.run(&mut g);
    assert!(o.is_finished() && !o.failed);
    assert!(before > 0.3, "the start is off: {before}");
    assert!(rms(&g.nodes, &truth) < 1e-6, "{}", rms(&g.nodes, &truth));
    assert_eq!(g.switched_off(), 0);
}

#[test]
fn budgeted_optimisation_equals_one_call_bit_for_bit() {
    let truth = ring();
    let mut one = drifting(&truth);
    let n = truth.len();
    one.edges.push(Edge::new(
        0,
        n - 1,
        relative_motion(&truth[0], &truth[n - 1]),
        [0.05, 0.05, 0.02],
        true,
    ));
    let mut sliced = one.clone();
    let mut o = Optimizer::new(RobustSettings::default());
    o.run(&mut one);
    let mut s = Optimizer::new(RobustSettings::default());
    let mut calls = 0;
    while !s.run_within(&mut sliced, 1) {
        calls += 1;
        assert!(calls < 10_000, "the budgeted optimisation ends");
    }
    assert!(calls > 2, "spread over several calls: {calls}");
    assert_eq!(s.work(), o.work());
    for (a, b) in one.nodes.iter().zip(&sliced.nodes) {
        assert_eq!(
            [a.x.to_bits(), a.y.to_bits(), a.theta.to_bits()],
            [b.x.to_bits(), b.y.to_bits(), b.theta.to_bits()]
        );
    }
    assert!(rms(&one.nodes, &truth) < rms(&drifting(&truth).nodes, &truth));
}

/// The ring driven `laps` times, a pose every half metre, each link
/// drifting as in [`drifting`], and every fourth pose of a lap after the
/// first closed against the same place on the first lap: rows that reach
/// far back in the poses' own order, and many places joined by loops,
/// so that even in the optimiser's order one iteration of six laps
/// costs millions of multiply–adds.
fn lapped(laps: usize) -> PoseGraph {
    let lap: Vec<Pose> = ring()
        .windows(2)
        .flat_map(|w| {
            let mid = pose(0.5 * (w[0].x + w[1].x), 0.5 * (w[0].y + w[1].y), w[0].theta);
            [w[0], mid]
        })
        .collect();
    let truth: Vec<Pose> = (0..laps).flat_map(|_| lap.iter().copied()).collect();
    let mut g = drifting(&truth);
    for k in lap.len()..truth.len() {
        if k % 4 == 0 {
            let i = k % lap.len();
            g.edges.push(Edge::new(
                i,
                k,
                relative_motion(&truth[i], &truth[k]),
                [0.05, 0.05, 0.02],
                true,
            ));
        }
    }
    g
}

#[test]
fn every_budgeted_call_stays_within_twice_its_budget_though_an_iteration_is_longer() {
    let mut one = lapped(6);
    let mut sliced = one.clone();
    let mut o = Optimizer::new(RobustSettings::default());
    o.run(&mut one);
    assert!(o.is_finished() && !o.failed && o.iterations > 1);
    // An eighth of an iteration's mean work: every iteration is many
    // budgets long, so a call that ran whole iterations would pass it.
    let budget = o.work() / o.iterations as u64 / 8;
    assert!(
        budget >= 4 * ZEROED_PER_STEP as u64,
        "a graph big enough: {} multiply-adds in {} iterations",
        o.work(),
        o.iterations
    );
    let mut s = Optimizer::new(RobustSettings::default());
    let (mut calls, mut longest) = (0usize, 0u64);
    loop {
        let before = s.work();
        let finished = s.run_within(&mut sliced, budget);
        longest = longest.max(s.work() - before);
        calls += 1;
        assert!(calls < 100_000, "the budgeted optimisation ends");
        if finished {
            break;
        }
    }
    assert!(
        longest <= 2 * budget,
        "a call did {longest} multiply-adds, its budget {budget}"
    );
    assert!(calls >= 4 * o.iterations, "{calls} calls");
    assert_eq!(s.work(), o.work());
    assert_eq!(s.iterations, o.iterations);
    for (a, b) in one.nodes.iter().zip(&sliced.nodes) {
        assert_eq!(
            [a.x.to_bits(), a.y.to_bits(), a.theta.to_bits()],
            [b.x.to_bits(), b.y.to_bits(), b.theta.to_bits()]
        );
    }
}

#[test]
fn a_wrong_closure_between_twin_corridors_is_switched_off_and_the_loop_still_closes() {
    let truth = ring();
    let n = truth.len();
    let mut g = drifting(&truth);
    let before = rms(&g.nodes, &truth);
    // Two right closures where the end meets the start; a wrong one that
    // puts scan 19 of the upper corridor where its twin below (4 m away,
    // alike) is: on scan 5 of the lower corridor.
    g.edges.push(Edge::new(
        0,
        n - 1,
        relative_motion(&truth[0], &truth[n - 1]),
        [0.05, 0.05, 0.01],
        true,
    ));
    g.edges.push(Edge::new(
        1,
        n - 2,
        relative_motion(&truth[1], &truth[n - 2]),
        [0.05, 0.05, 0.01],
        true,
    ));
    let wrong = relative_motion(
        &truth[5],
        &pose(truth[19].x, truth[19].y - 4.0, truth[19].theta),
    );
    g.edges
        .push(Edge::new(5, 19, wrong, [0.05, 0.05, 0.01], true));
    let mut o = Optimizer::new(RobustSettings::default());
    o.run(&mut g);
    let after = rms(&g.nodes, &truth);
    assert!(
        !g.edges.last().unwrap().active,
        "the wrong closure is switched off"
    );
    assert_eq!(g.switched_off(), 1, "and only it");
    assert!(
        after < 0.25 * before && after < 0.1,
        "before {before}, after {after}"
    );
}

/// The multiply–adds of a Cholesky factorisation of `g`'s normal
/// equations over their envelope in the nodes' own order (node 0 fixed):
/// row `r` of node `k` reaches back to the first row of `k`'s lowest
/// neighbour, and entry `(r, c)` is an inner product over the columns
/// both rows' envelopes hold before `c` (George and Liu's row-by-row
/// envelope Cholesky).
fn envelope_work_in_node_order(g: &PoseGraph) -> f64 {
    let n = g.nodes.len() - 1;
    let mut lowest: Vec<usize> = (0..n).collect();
    for e in &g.edges {
        let (a, b) = (e.from.min(e.to), e.from.max(e.to));
        if a >= 1 {
            lowest[b - 1] = lowest[b - 1].min(a - 1);
        }
    }
    let first = |r: usize| 3 * lowest[r / 3];
    (0..3 * n)
        .map(|r| {
            (first(r)..=r)
                .map(|c| (c - first(r).max(first(c)) + 1) as f64)
                .sum::<f64>()
        })
        .sum()
}

/// Laps closed against the first lap: in the poses' own order every
/// closing row reaches back to the first lap, so the factor's envelope
/// holds most of the matrix; the optimiser orders the nodes so that the
/// places a loop joins sit side by side, and an iteration costs a small
/// share of that.
#[test]
fn the_optimiser_orders_the_nodes_to_keep_the_envelope_small() {
    let mut g = lapped(6);
    let in_node_order = envelope_work_in_node_order(&g);
    let mut o = Optimizer::new(RobustSettings::default());
    o.run(&mut g);
    assert!(o.is_finished() && !o.failed);
    let per_iteration = o.work() as f64 / o.iterations as f64;
    assert!(
        per_iteration < in_node_order / 3.0,
        "{per_iteration:.0} multiply-adds an iteration; the factor alone in the nodes' order {in_node_order:.0}"
    );
}
