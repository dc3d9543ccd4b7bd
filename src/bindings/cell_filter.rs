//! Bindings of `<occgrid-cell-filter>`: one cell's filter.

use super::{bool_from_js, describe, guarded, number_from_js, to_js};
use crate::mapping::cell_filter::{self, CellFilterParams, CellFilterPreset};
use wasm_bindgen::prelude::*;

/// Runs one cell's filter over `readings` (a `Uint8Array` or an array of
/// numbers, 1 = occupied, 0 = free) and returns `{ lOcc, lFree, l0, steps:
/// [{ step, occupied, l, p }], clamp, firstAtClamp, freeIsEvidenceForOccupied }`:
/// `firstAtClamp` the first step whose `l` sits at `±clamp` (null if none),
/// `freeIsEvidenceForOccupied` whether `p_free >= p_occ`, so that a "free"
/// reading raises the cell at least as much as an occupied one.
#[wasm_bindgen(js_name = runCellFilter)]
pub fn run_cell_filter(
    p_occ: JsValue,
    p_free: JsValue,
    prior: JsValue,
    clamp: JsValue,
    readings: JsValue,
    subtract_prior: JsValue,
) -> Result<JsValue, JsError> {
    let p_occ = number_from_js("p_occ", &p_occ)?;
    let p_free = number_from_js("p_free", &p_free)?;
    let prior = number_from_js("prior", &prior)?;
    let clamp = number_from_js("clamp", &clamp)?;
    let subtract_prior = bool_from_js("subtract_prior", &subtract_prior)?;
    let readings = readings_from_js(&readings)?;
    let params = CellFilterParams {
        p_occ,
        p_free,
        prior,
        clamp,
    };
    table_to_js(&params, &readings, subtract_prior)
}

/// The readings JavaScript sent: an array of 1 and 0 (or a Proxy of one,
/// read item by item), or bytes. The length is checked first: a
/// 100-million-item array is refused before it is copied into wasm memory.
fn readings_from_js(readings: &JsValue) -> Result<Vec<u8>, JsError> {
    const EXPECTED: &str = "a Uint8Array or an array of 1 (occupied) and 0 (free)";
    let invalid = |reason: String| JsError::new(&format!("invalid readings: {reason}"));
    if let Some(len) = guarded::array_length(readings).map_err(invalid)? {
        cell_filter::check_readings(len)?;
        // Each item as JavaScript holds it: a copy into bytes would wrap
        // 256 to 0 and -1 to 255.
        return (0..len)
            .map(|i| {
                let r = guarded::array_item(readings, i)
                    .map_err(|reason| JsError::new(&format!("invalid readings[{i}]: {reason}")))?;
                match r.as_f64() {
                    Some(v) if v == 0.0 || v == 1.0 => Ok(v as u8),
                    _ => Err(JsError::new(&format!(
                        "invalid readings[{i}]: {} (expected 1 for occupied or 0 for free)",
                        describe(&r)
                    ))),
                }
            })
            .collect();
    }
    let (source, len) = guarded::byte_source(readings).ok_or_else(|| {
        JsError::new(&format!(
            "invalid readings: {} (expected {EXPECTED})",
            describe(readings)
        ))
    })?;
    cell_filter::check_readings(len)?;
    guarded::copy_bytes(&source, len).map_err(invalid)
}

/// The filter's table for `readings` (bytes, each 1 or 0) as `runCellFilter`
/// returns it.
fn table_to_js(
    params: &CellFilterParams,
    readings: &[u8],
    subtract_prior: bool,
) -> Result<JsValue, JsError> {
    if let Some((i, &bad)) = readings.iter().enumerate().find(|(_, &r)| r > 1) {
        return Err(JsError::new(&format!(
            "invalid readings[{i}]: {bad} (expected 1 for occupied or 0 for free)"
        )));
    }
    let flags: Vec<bool> = readings.iter().map(|&r| r == 1).collect();
    let steps = cell_filter::run(params, &flags, subtract_prior)?;
    let lo = cell_filter::log_odds_of(params)?;
    #[derive(serde::Serialize)]
    #[serde(rename_all = "camelCase")]
    struct Table {
        l_occ: f64,
        l_free: f64,
        l0: f64,
        steps: Vec<cell_filter::CellStep>,
        clamp: f64,
        first_at_clamp: Option<usize>,
        free_is_evidence_for_occupied: bool,
    }
    let clamp = params.clamp;
    let first_at_clamp = steps.iter().find(|s| s.l.abs() >= clamp).map(|s| s.step);
    to_js(&Table {
        l_occ: lo.l_occ,
        l_free: lo.l_free,
        l0: lo.l0,
        first_at_clamp,
        free_is_evidence_for_occupied: params.p_free >= params.p_occ,
        clamp,
        steps,
    })
}

/// The chapter's worked example: readings occupied, occupied, free with an
/// inverse model of 0.7 / 0.3 and a prior of 0.5.
#[wasm_bindgen(js_name = workedExample)]
pub fn worked_example() -> Result<JsValue, JsError> {
    let p = CellFilterPreset::WORKED_EXAMPLE;
    let params = CellFilterParams {
        p_occ: p.p_occ,
        p_free: p.p_free,
        prior: p.prior,
        clamp: p.clamp,
    };
    table_to_js(&params, p.readings, p.subtract_prior)
}
