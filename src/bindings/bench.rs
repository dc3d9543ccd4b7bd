//! The benchmark workloads' entry points (BENCHMARKS.md W1-W3) for the wasm
//! build under Node: `npm run bench` builds them in (`--features bench`);
//! the module the page ships leaves them out.

use super::real_log::LOG_BYTES;
use super::{bytes_from_js, index_from_js, number_from_js, to_js};
use crate::bench::apartment::{AllCellsVsTraversal, ApartmentFrame};
use crate::bench::intel as workloads;
use crate::inverse::training::{self, TrainingConfig};
use crate::io::carmen::read_scans;
use crate::sensors::ScanLog;
use wasm_bindgen::prelude::*;

/// A parsed CARMEN log held in wasm memory.
#[wasm_bindgen]
pub struct LaserLog(ScanLog);

#[wasm_bindgen]
impl LaserLog {
    /// Parses a log (a `Uint8Array` or `ArrayBuffer` of gzip or plain
    /// text). Malformed laser lines are errors naming their line number.
    #[wasm_bindgen(js_name = fromBytes)]
    pub fn from_bytes(bytes: JsValue) -> Result<LaserLog, JsError> {
        let bytes = bytes_from_js("bytes", &bytes, LOG_BYTES)?;
        Ok(LaserLog(read_scans(&bytes[..])?))
    }

    #[wasm_bindgen(getter, js_name = scanCount)]
    pub fn scan_count(&self) -> usize {
        self.0.len()
    }

    /// Workload W1 of BENCHMARKS.md: builds the Intel map and returns
    /// `{ cell_updates, occupied, free, unknown }`.
    #[wasm_bindgen(js_name = buildIntelBenchmark)]
    pub fn build_intel_benchmark(&self) -> Result<JsValue, JsError> {
        let (_, counts) = workloads::build_intel_map(&self.0);
        to_js(&counts)
    }
}

/// W2 `apartment-frame` for the benchmark under Node: each call does the
/// work of one call, the script holds the clock.
#[wasm_bindgen]
pub struct ApartmentFrameBench(ApartmentFrame);

#[wasm_bindgen]
impl ApartmentFrameBench {
    /// Trains the learned model (default configuration) and simulates the
    /// lap.
    #[wasm_bindgen(constructor)]
    pub fn new() -> Result<ApartmentFrameBench, JsError> {
        let (learned, _, _) = training::train(&TrainingConfig::default())?;
        Ok(ApartmentFrameBench(ApartmentFrame::new(learned)?))
    }

    #[wasm_bindgen(getter)]
    pub fn scans(&self) -> usize {
        self.0.scans()
    }

    /// Empties both maps and starts the lap again.
    pub fn restart(&mut self) {
        self.0.restart();
    }

    /// One frame; returns the cells visited by both traversals together.
    pub fn frame(&mut self) -> usize {
        self.0.frame().iter().map(|s| s.cells_visited).sum()
    }

    /// One `integrate_scan` call into map `map` (0 hand-crafted, 1
    /// learned); returns the cells visited.
    pub fn integrate(&mut self, map: JsValue) -> Result<usize, JsError> {
        Ok(self.0.integrate(index_from_js("map", &map)?)?.cells_visited)
    }
}

/// W3 `all-cells-vs-traversal` for the benchmark under Node.
#[wasm_bindgen]
pub struct AllCellsVsTraversalBench(AllCellsVsTraversal);

#[wasm_bindgen]
impl AllCellsVsTraversalBench {
    #[wasm_bindgen(constructor)]
    pub fn new(resolution: JsValue) -> Result<AllCellsVsTraversalBench, JsError> {
        let resolution = number_from_js("resolution", &resolution)?;
        Ok(AllCellsVsTraversalBench(AllCellsVsTraversal::new(
            resolution,
        )?))
    }

    #[wasm_bindgen(getter)]
    pub fn scans(&self) -> usize {
        self.0.scans()
    }

    /// Scan `k` by ray traversal; returns the cells visited.
    pub fn traverse(&mut self, k: JsValue) -> Result<usize, JsError> {
        Ok(self.0.traverse(index_from_js("scan", &k)?)?.cells_visited)
    }

    /// Scan `k` by the sweep over every cell; returns the cells visited.
    pub fn sweep(&mut self, k: JsValue) -> Result<usize, JsError> {
        Ok(self.0.sweep(index_from_js("scan", &k)?)?.cells_visited)
    }
}
