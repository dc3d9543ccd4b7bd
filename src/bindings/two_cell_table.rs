//! Bindings of the two-cell table: the exact joint posterior of a
//! few cells against the product of their marginals.

use super::{object_from_js, string_from_js, to_js};
use crate::apps::two_cell_table::{preset, two_cell_report};
use crate::mapping::joint::{JointPosterior, JointQuery};
use wasm_bindgen::prelude::*;

/// The exact joint posterior of a query `{ prior, beta_deg, cells: [{ range,
/// bearing_deg }], readings, model? }`, with everything the two-cell table
/// prints: `{ joint, marginals, allFreeTrue, allFreeFactored, allFreeRatio,
/// mutualInformationBits, table: [{ index, occupied, expectedRange,
/// likelihood, joint, factored }], marginalGrays, allOccupiedTrue,
/// allOccupiedFactored, allOccupiedRatio }`.
#[wasm_bindgen(js_name = jointPosterior)]
pub fn joint_posterior(query: JsValue) -> Result<JsValue, JsError> {
    let q: JointQuery = object_from_js("joint query", query)?;
    to_js(&two_cell_report(&q)?)
}

/// The numbers script's answer to a query: exactly `{ joint, marginals,
/// allFreeTrue, allFreeFactored }`.
#[wasm_bindgen(js_name = jointAnswer)]
pub fn joint_answer(query: JsValue) -> Result<JsValue, JsError> {
    let q: JointQuery = object_from_js("joint query", query)?;
    to_js(&JointPosterior::compute(&q)?.answer())
}

/// The chapter's two-cell query, as data.
#[wasm_bindgen(js_name = chapterTwoCellQuery)]
pub fn chapter_two_cell_query() -> Result<JsValue, JsError> {
    to_js(&JointQuery::chapter_two_cells())
}

/// One of the table's presets (`"side"`, `"collinear"`, `"apart"`) as a
/// query: the chapter's, with the two cells placed by the preset.
#[wasm_bindgen(js_name = twoCellPreset)]
pub fn two_cell_preset(name: JsValue) -> Result<JsValue, JsError> {
    let name = string_from_js("preset", &name, "one of side, collinear, apart")?;
    to_js(&preset(&name)?)
}
