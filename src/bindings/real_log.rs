//! Bindings for real CARMEN logs: parsing, and the W1 `intel-full` build.

use super::to_js;
use crate::carmen::{self, CarmenLog};
use crate::workloads;
use wasm_bindgen::prelude::*;

/// A parsed CARMEN log held in wasm memory.
#[wasm_bindgen]
pub struct LaserLog(CarmenLog);

#[wasm_bindgen]
impl LaserLog {
    /// Parses a log (gzip or plain text). Malformed laser lines are errors
    /// naming their line number.
    #[wasm_bindgen(js_name = fromBytes)]
    pub fn from_bytes(bytes: &[u8]) -> Result<LaserLog, JsError> {
        Ok(LaserLog(carmen::parse_bytes(bytes)?))
    }

    #[wasm_bindgen(getter, js_name = scanCount)]
    pub fn scan_count(&self) -> usize {
        self.0.scans.len()
    }

    /// Workload W1 of BENCHMARKS.md: builds the Intel map and returns
    /// `{ cell_updates, occupied, free, unknown }`.
    #[wasm_bindgen(js_name = buildIntelBenchmark)]
    pub fn build_intel_benchmark(&self) -> Result<JsValue, JsError> {
        let (_, counts) = workloads::build_intel_map(&self.0);
        to_js(&counts)
    }
}
