//! Native figures for the workloads of BENCHMARKS.md, one JSON object per
//! line (the wasm figures come from scripts/bench.mjs). Run with
//! `cargo bench --bench native`; the datasets folder defaults to
//! `../shared/datasets` and can be set with OCCGRID_DATASETS.

use occgrid::carmen;
use occgrid::workloads;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
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
    let log = carmen::parse_bytes(&bytes).expect("the Intel log parses");
    let parse_ms = t.elapsed().as_secs_f64() * 1e3;
    let mut times = Vec::new();
    let mut counts = None;
    for _ in 0..7 {
        let t = Instant::now();
        let (_, c) = workloads::build_intel_map(&log);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        counts = Some(c);
    }
    let c = counts.unwrap();
    println!(
        "{{\"workload\":\"intel-full\",\"runtime\":\"native\",\"scans\":{},\"parse_ms\":{:.2},\"build_ms\":{:.2},\"cell_updates\":{},\"occupied\":{},\"free\":{},\"unknown\":{}}}",
        log.scans.len(), parse_ms, median(times), c.cell_updates, c.occupied, c.free, c.unknown
    );
}

fn main() {
    let only = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let run = |name: &str| only.as_deref().map_or(true, |o| name.contains(o));
    if run("intel-full") {
        intel_full();
    }
}
