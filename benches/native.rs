//! Native figures for the workloads of docs/BENCHMARKS.md, one JSON object per
//! line (the wasm figures come from scripts/bench.mjs). Run with
//! `cargo bench --bench native`; the datasets folder defaults to
//! `../shared/datasets` and can be set with OCCGRID_DATASETS.

use occgrid::bench::intel as workloads;
use occgrid::io::carmen;
use occgrid::poses::PoseSourceKind;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Timed repetitions per workload (OCCGRID_BENCH_RUNS, default 7): 1 for
/// instruction counting under valgrind.
fn runs() -> usize {
    std::env::var("OCCGRID_BENCH_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|&n| n > 0)
        .unwrap_or(7)
}

fn datasets() -> std::path::PathBuf {
    std::env::var_os("OCCGRID_DATASETS")
        .map(Into::into)
        .unwrap_or_else(|| {
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/datasets")
        })
}

fn intel_full() {
    let path = datasets().join("intel-corrected.log.gz");
    let Ok(bytes) = std::fs::read(&path) else {
        eprintln!("skipping intel-full: cannot read {}", path.display());
        return;
    };
    let t = Instant::now();
    // The reader the page uses, to the end: W1 maps the page's numbers.
    let log = carmen::read_scans(&bytes[..]).expect("the Intel log parses");
    let parse_ms = t.elapsed().as_secs_f64() * 1e3;
    let mut times = Vec::new();
    let mut counts = None;
    for _ in 0..runs() {
        let t = Instant::now();
        let (_, c) = workloads::build_intel_map(&log);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        counts = Some(c);
    }
    let c = counts.unwrap();
    println!(
        "{{\"workload\":\"intel-full\",\"runtime\":\"native\",\"scans\":{},\"parse_ms\":{:.2},\"build_ms\":{:.2},\"beams\":{},\"cells_visited\":{},\"cell_updates\":{},\"occupied\":{},\"free\":{},\"unknown\":{}}}",
        log.len(), parse_ms, median(times), c.beams, c.cells_visited, c.cell_updates, c.occupied, c.free, c.unknown
    );
}

/// The sensor-fusion widget's work (docs/ARCHITECTURE.md, "Two sensors"): building the table scene's
/// scans, and one lap integrated into the sonar, LiDAR, summed and
/// max-fused maps (two 12,000-cell sweeps and two ray traversals per scan).
fn table_fusion() {
    use occgrid::apps::sensor_fusion::TableFusion;
    use occgrid::scenes::table::TableScene;
    let scene = TableScene::default();
    let (mut build, mut lap, mut per_step) = (Vec::new(), Vec::new(), Vec::new());
    let mut steps = 0;
    for _ in 0..runs() {
        let t = Instant::now();
        let mut f = TableFusion::new(&scene).expect("the default scene builds");
        build.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        steps = 0;
        loop {
            let s = Instant::now();
            if !f.step() {
                break;
            }
            per_step.push(s.elapsed().as_secs_f64() * 1e6);
            steps += 1;
        }
        lap.push(t.elapsed().as_secs_f64() * 1e3);
    }
    println!(
        "{{\"workload\":\"table-fusion\",\"runtime\":\"native\",\"scans\":{},\"sonar_cones_per_scan\":{},\"lidar_beams_per_scan\":{},\"cells_per_map\":{},\"build_ms\":{:.2},\"lap_ms\":{:.2},\"step_us\":{:.1}}}",
        steps, scene.sonar.count, scene.lidar.beams, scene.geometry().map_or(0, |g| g.len()), median(build), median(lap), median(per_step)
    );
}

/// W2 `apartment-frame`: one Map Weaver frame (a scan into the hand-crafted
/// and the learned map, both views redrawn and rescored) and one
/// `integrate_scan` call, medians over `runs()` laps (src/bench/apartment.rs).
fn apartment_frame() {
    use occgrid::bench::apartment::ApartmentFrame;
    use occgrid::inverse::training::{train, TrainingConfig};
    let (learned, _, _) = train(&TrainingConfig::default()).expect("the default training runs");
    let mut w = ApartmentFrame::new(learned).expect("the apartment builds");
    let n = w.scans();
    let time = |w: &mut ApartmentFrame, call: &dyn Fn(&mut ApartmentFrame) -> usize| {
        let (mut us, mut cells) = (Vec::new(), 0);
        for _ in 0..runs() {
            w.restart();
            for _ in 0..n {
                let t = Instant::now();
                cells += call(w);
                us.push(t.elapsed().as_secs_f64() * 1e6);
            }
        }
        (median(us), cells as f64 / (runs() * n) as f64)
    };
    let (frame_us, _) = time(&mut w, &|w| w.frame().iter().map(|s| s.cells_visited).sum());
    let (hand_us, hand_cells) = time(&mut w, &|w| w.integrate(0).map_or(0, |s| s.cells_visited));
    let (learned_us, learned_cells) =
        time(&mut w, &|w| w.integrate(1).map_or(0, |s| s.cells_visited));
    println!(
        "{{\"workload\":\"apartment-frame\",\"runtime\":\"native\",\"scans\":{n},\"laps\":{},\"cells\":10800,\"frame_us\":{frame_us:.1},\"integrate_us\":{hand_us:.1},\"cells_per_scan\":{hand_cells:.0},\"integrate_learned_us\":{learned_us:.1},\"cells_per_scan_learned\":{learned_cells:.0}}}",
        runs()
    );
}

/// W3 `all-cells-vs-traversal`: the W2 lap by ray traversal and by the
/// literal sweep over every cell, at 0.10 m and 0.05 m, medians per scan.
fn all_cells_vs_traversal() {
    use occgrid::bench::apartment::AllCellsVsTraversal;
    for resolution in [0.1, 0.05] {
        let mut w = AllCellsVsTraversal::new(resolution).expect("the apartment builds");
        let n = w.scans();
        let time = |w: &mut AllCellsVsTraversal, sweep: bool| {
            let (mut us, mut cells) = (Vec::new(), 0);
            for k in 0..n {
                let t = Instant::now();
                let stats = if sweep { w.sweep(k) } else { w.traverse(k) };
                us.push(t.elapsed().as_secs_f64() * 1e6);
                cells += stats.map_or(0, |s| s.cells_visited);
            }
            (median(us), cells as f64 / n as f64)
        };
        let (traversal_us, traversal_cells) = time(&mut w, false);
        let (sweep_us, sweep_cells) = time(&mut w, true);
        println!(
            "{{\"workload\":\"all-cells-vs-traversal\",\"runtime\":\"native\",\"resolution\":{resolution},\"scans\":{n},\"traversal_us\":{traversal_us:.1},\"sweep_us\":{sweep_us:.1},\"traversal_cells\":{traversal_cells:.0},\"sweep_cells\":{sweep_cells:.0},\"speedup\":{:.1}}}",
            sweep_us / traversal_us
        );
    }
}

/// Map Weaver's real-log path on the Intel log: the streaming reader into
/// the compact scan store, then the whole build over the log's own extent
/// (W1's model and clamp, 5 cm), each timed from scratch.
fn intel_real_log() {
    let Ok(bytes) = std::fs::read(datasets().join("intel-corrected.log.gz")) else {
        return eprintln!("skipping intel-real-log: cannot read the Intel log");
    };
    let (mut read, mut build, mut last) = (Vec::new(), Vec::new(), None);
    for _ in 0..runs() {
        let t = Instant::now();
        let scans = carmen::read_scans(&bytes[..]).expect("the Intel log parses");
        read.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        let mut b = occgrid::apps::real_log::LogPane::new(
            scans,
            occgrid::apps::real_log::LogMapSettings::default(),
        )
        .expect("default settings");
        let p = b.advance(usize::MAX);
        build.push(t.elapsed().as_secs_f64() * 1e3);
        last = Some((p, b.counts(), *b.grid().geometry()));
    }
    let (p, c, g) = last.expect("at least one run");
    println!(
        "{{\"workload\":\"intel-real-log\",\"runtime\":\"native\",\"scans\":{},\"beams\":{},\"read_ms\":{:.2},\"build_ms\":{:.2},\"width\":{},\"height\":{},\"cell_updates\":{},\"occupied\":{},\"free\":{},\"unknown\":{}}}",
        p.scans_total, p.beams, median(read), median(build), g.width(), g.height(), p.cell_updates, c.occupied, c.free, c.unknown
    );
}

/// W4 `doorway-map`: the MAP hill climb (Table 9.3) on the doorway scene.
/// One flip step and the climb to convergence from the all-free start are
/// timed apart; building the incidence cache is `setup_ms`.
fn doorway_map() {
    use occgrid::scenes::doorway::DoorwayScene;
    let scene = DoorwayScene::standard();
    let (mut setup, mut converge, mut step) = (Vec::new(), Vec::new(), Vec::new());
    let mut search =
        occgrid::apps::doorway_trap::map_search(&scene).expect("the chapter's scene is valid");
    for _ in 0..runs() {
        let t = Instant::now();
        search =
            occgrid::apps::doorway_trap::map_search(&scene).expect("the chapter's scene is valid");
        setup.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        search.run(usize::MAX);
        converge.push(t.elapsed().as_secs_f64() * 1e3);
        search.reset();
        loop {
            let t = Instant::now();
            let flipped = search.step().is_some();
            let dt = t.elapsed().as_secs_f64() * 1e3;
            if !flipped {
                break;
            }
            step.push(dt);
        }
    }
    let g = search.geometry();
    println!(
        "{{\"workload\":\"doorway-map\",\"runtime\":\"native\",\"cells\":{},\"readings\":{},\"incidence\":{},\"step_ms\":{:.4},\"converge_ms\":{:.3},\"flips\":{},\"log_posterior\":{:.4},\"setup_ms\":{:.3}}}",
        g.len(), search.beams().len(), search.incidence_len(), median(step), median(converge), search.flips().len(), search.objective(), median(setup)
    );
}

/// W5 `learn-inverse`: sampling the 24,000 training triplets and fitting
/// the learned inverse model (default configuration, seed 9), timed apart.
fn learn_inverse() {
    use occgrid::inverse::training::{fit, sample_triplets, TrainingConfig};
    let config = TrainingConfig::default();
    let (mut sample, mut train, mut out) = (Vec::new(), Vec::new(), None);
    for _ in 0..runs() {
        let t = Instant::now();
        let set = sample_triplets(&config).expect("the default configuration is valid");
        sample.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        let (model, report) = fit(&config, &set).expect("the default configuration is valid");
        train.push(t.elapsed().as_secs_f64() * 1e3);
        out = Some((set.triplets.len(), set.maps, report.updates, model.own_l0()));
    }
    let (triplets, maps, updates, l0) = out.expect("at least one run");
    println!(
        "{{\"workload\":\"learn-inverse\",\"runtime\":\"native\",\"triplets\":{triplets},\"maps\":{maps},\"epochs\":{},\"sgd_updates\":{updates},\"sample_ms\":{:.2},\"train_ms\":{:.2},\"l0\":{l0:.4}}}",
        config.epochs, median(sample), median(train)
    );
}

fn main() {
    let only = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let run = |name: &str| only.as_deref().is_none_or(|o| name.contains(o));
    // Minutes per log: run only when named.
    let named = |name: &str| only.as_deref() == Some(name);
    if run("intel-full") {
        intel_full();
    }
    if run("table-fusion") {
        table_fusion();
    }
    if run("apartment-frame") {
        apartment_frame();
    }
    if run("all-cells-vs-traversal") {
        all_cells_vs_traversal();
    }
    if run("intel-real-log") {
        intel_real_log();
    }
    if run("doorway-map") {
        doorway_map();
    }
    if run("learn-inverse") {
        learn_inverse();
    }
    if named("scan-match") {
        recovered_poses(PoseSourceKind::ScanMatched, "scan-match");
    }
    if named("slam") {
        recovered_poses(PoseSourceKind::Slam, "slam");
    }
    if run("real-logs") {
        real_logs();
    }
}

/// Every log of the datasets folder mapped natively at the real-log
/// defaults (5 cm), read and built timed apart: the core's share of W6.
/// `OCCGRID_LOG` keeps the logs whose file name contains it.
fn real_logs() {
    let only = std::env::var("OCCGRID_LOG").unwrap_or_default();
    let Ok(dir) = std::fs::read_dir(datasets()) else {
        return eprintln!("skipping real-logs: no datasets folder");
    };
    let mut logs: Vec<_> = dir
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().ends_with(".log.gz"))
        .filter(|p| p.to_string_lossy().contains(&only))
        .collect();
    logs.sort();
    for path in logs {
        let bytes = std::fs::read(&path).expect("a readable log");
        let (mut read, mut build, mut last) = (Vec::new(), Vec::new(), None);
        let (mut render, mut counting) = (Vec::new(), Vec::new());
        for _ in 0..runs() {
            let t = Instant::now();
            let scans = carmen::read_scans(&bytes[..]).expect("the corpus's logs parse");
            read.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            let mut b = occgrid::apps::real_log::LogPane::new(
                scans,
                occgrid::apps::real_log::LogMapSettings::default(),
            )
            .expect("default settings");
            let p = b.advance(usize::MAX);
            build.push(t.elapsed().as_secs_f64() * 1e3);
            // What a page's redraw costs: the whole map in a 1200 x 900
            // view, and the counts beside it.
            b.set_view_size(1200, 900)
                .expect("a view size within bounds");
            let t = Instant::now();
            b.render_view();
            render.push(t.elapsed().as_secs_f64() * 1e3);
            let t = Instant::now();
            let c = b.counts();
            counting.push(t.elapsed().as_secs_f64() * 1e3);
            last = Some((p, c));
        }
        let (p, c) = last.expect("at least one run");
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        println!(
            "{{\"workload\":\"real-log\",\"runtime\":\"native\",\"log\":\"{}\",\"scans\":{},\"beams\":{},\"read_ms\":{:.2},\"build_ms\":{:.2},\"render_ms\":{:.2},\"counts_ms\":{:.2},\"cells_allocated\":{},\"cell_updates\":{},\"occupied\":{},\"free\":{},\"unknown\":{}}}",
            name, p.scans_total, p.beams, median(read), median(build), median(render), median(counting), p.cells_allocated, p.cell_updates, c.occupied, c.free, c.unknown
        );
    }
}

/// The root-mean-square position error of `poses` against `truth` after
/// the best rigid 2-D alignment (the aligned ATE), and the mean relative
/// pose error between consecutive scans (metres, degrees): the measures
/// of `trajectory_error.py`, so that a workload line carries them.
fn trajectory_errors(
    poses: &[occgrid::geometry::Pose],
    truth: &[occgrid::geometry::Pose],
) -> (f64, f64, f64) {
    use occgrid::geometry::wrap_angle;
    use occgrid::mapping::scan_match::relative_motion;
    let n = poses.len().min(truth.len()).max(1) as f64;
    let mean = |v: &[occgrid::geometry::Pose]| {
        let (x, y) = v.iter().fold((0.0, 0.0), |(x, y), p| (x + p.x, y + p.y));
        (x / n, y / n)
    };
    let ((gx, gy), (rx, ry)) = (mean(poses), mean(truth));
    let (mut sxx, mut sxy) = (0.0, 0.0);
    for (g, r) in poses.iter().zip(truth) {
        let (ax, ay, bx, by) = (g.x - gx, g.y - gy, r.x - rx, r.y - ry);
        sxx += ax * bx + ay * by;
        sxy += ax * by - ay * bx;
    }
    let (s, c) = sxy.atan2(sxx).sin_cos();
    let ate = (poses
        .iter()
        .zip(truth)
        .map(|(g, r)| {
            let (ax, ay) = (g.x - gx, g.y - gy);
            (c * ax - s * ay + rx - r.x).powi(2) + (s * ax + c * ay + ry - r.y).powi(2)
        })
        .sum::<f64>()
        / n)
        .sqrt();
    let (mut rt, mut rr) = (0.0, 0.0);
    for k in 1..poses.len().min(truth.len()) {
        let g = relative_motion(&poses[k - 1], &poses[k]);
        let r = relative_motion(&truth[k - 1], &truth[k]);
        rt += (g[0] - r[0]).hypot(g[1] - r[1]);
        rr += wrap_angle(g[2] - r[2]).abs();
    }
    let pairs = (n - 1.0).max(1.0);
    (ate, rt / pairs, (rr / pairs).to_degrees())
}

/// W8 `scan-match` and `slam`: every log of the datasets folder at the
/// real-log defaults (5 cm), its poses found by `kind` from seeded dead
/// reckoning (the seeds of `OCCGRID_SEEDS`, comma-separated, 1 when
/// unset; `OCCGRID_LOG` keeps the logs whose file name contains it) in
/// the pane the page drives: the time of each build call (one scan
/// located and integrated, a loop search or an optimisation step;
/// median and largest) and of the whole log, beside the plain build at
/// the corrected poses, with the trajectory's errors against the
/// corrected poses for dead reckoning and for the source, and for SLAM
/// the loops closed.
fn recovered_poses(kind: PoseSourceKind, workload: &str) {
    use occgrid::apps::real_log::{LogMapSettings, LogPane};
    use occgrid::poses::ScanMatching;
    use occgrid::sensors::odometry::OdometryParams;
    let only = std::env::var("OCCGRID_LOG").unwrap_or_default();
    let seeds: Vec<u64> = std::env::var("OCCGRID_SEEDS")
        .unwrap_or_else(|_| "1".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    let Ok(dir) = std::fs::read_dir(datasets()) else {
        return eprintln!("skipping {workload}: cannot read the datasets folder");
    };
    let mut logs: Vec<_> = dir
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().ends_with(".log.gz"))
        .filter(|p| p.to_string_lossy().contains(&only))
        .collect();
    logs.sort();
    let s = LogMapSettings::default();
    for path in logs {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let Ok(bytes) = std::fs::read(&path) else {
            continue;
        };
        let scans = carmen::read_scans(&bytes[..]).expect("the corpus's logs parse");
        let mut plain = Vec::new();
        for _ in 0..runs().min(3) {
            let t = Instant::now();
            let mut b = LogPane::new(scans.clone(), s).expect("default settings");
            b.advance(usize::MAX);
            plain.push(t.elapsed().as_secs_f64() * 1e3);
        }
        let truth = scans.poses().to_vec();
        for &seed in &seeds {
            let settings = LogMapSettings {
                poses: kind,
                seed,
                ..s
            };
            let mut pane = LogPane::new(scans.clone(), settings).expect("default settings");
            let mut steps = Vec::new();
            let t = Instant::now();
            while !pane.progress().finished {
                let t = Instant::now();
                pane.advance(1);
                steps.push(t.elapsed().as_secs_f64() * 1e3);
            }
            let total = t.elapsed().as_secs_f64() * 1e3;
            assert!(pane.failure().is_none(), "the tile budget holds");
            let largest = steps.iter().copied().fold(0.0, f64::max);
            let dr = ScanMatching::odometry_of(&scans, seed, &OdometryParams::WHEELS);
            let (dr_ate, dr_rpe, dr_rpe_deg) = trajectory_errors(&dr, &truth);
            let (ate, rpe, rpe_deg) = trajectory_errors(pane.poses(), &truth);
            let p = pane.progress();
            let loops = p
                .loop_closures
                .map_or(String::new(), |n| format!(",\"loops_closed\":{n}"));
            println!(
                "{{\"workload\":\"{workload}\",\"runtime\":\"native\",\"log\":\"{name}\",\"seed\":{seed},\"scans\":{},\"step_median_ms\":{:.3},\"step_max_ms\":{:.2},\"poses_and_map_ms\":{total:.1},\"plain_build_ms\":{:.1},\"source_work_share\":{:.3}{loops},\"dead_reckoning\":{{\"ate_aligned_m\":{dr_ate:.3},\"rpe_m\":{dr_rpe:.4},\"rpe_deg\":{dr_rpe_deg:.3}}},\"{}\":{{\"ate_aligned_m\":{ate:.3},\"rpe_m\":{rpe:.4},\"rpe_deg\":{rpe_deg:.3}}}}}",
                scans.len(),
                median(steps.clone()),
                largest,
                median(plain.clone()),
                1.0 - p.cell_updates as f64 / p.work.max(1) as f64,
                kind.name(),
            );
        }
    }
}
