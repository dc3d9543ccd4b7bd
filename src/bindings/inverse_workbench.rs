//! Bindings of `<occgrid-inverse-workbench>`: the hand-crafted inverse model
//! of Table 9.2 and the learned one of §9.3, for one beam, side by side.
//! The widget asks for both models' evidence over the beam's neighbourhood
//! and their log odds along its axis for one reading, and retrains the
//! learned model with another seed; it draws what it gets.

use super::{object_from_js, object_or_default, to_js};
use crate::inverse::probes::{mean_free_evidence, side_by_side, BeamLattice};
use crate::inverse::training::{self, TrainingConfig};
use crate::inverse::{HandCrafted, InverseModel, LearnedInverse};
use crate::sensors::beam_model::{BeamModel, BeamModelParams};
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
extern "C" {
    /// The host's monotonic clock in milliseconds (browsers and Node both
    /// have `performance.now`): the core has no clock of its own in wasm.
    #[wasm_bindgen(catch, js_namespace = performance, js_name = now)]
    fn performance_now() -> Result<f64, JsValue>;
}

/// Milliseconds on the host's clock; NaN (a timing of "unknown") on a host
/// without `performance.now`, rather than an exception through wasm.
fn now_ms() -> f64 {
    performance_now().unwrap_or(f64::NAN)
}

/// Both models and the last training run, held in wasm memory.
#[wasm_bindgen]
pub struct InverseWorkbench {
    config: TrainingConfig,
    hand: HandCrafted,
    learned: LearnedInverse,
    run: TrainingRun,
}

/// What the readout says about the last training run.
#[derive(serde::Serialize)]
#[serde(rename_all = "camelCase")]
struct TrainingRun {
    seed: u64,
    triplets: usize,
    epochs: usize,
    maps: usize,
    map_occupancy: f64,
    no_returns: f64,
    occupied_fraction: f64,
    sample_ms: f64,
    fit_ms: f64,
    train_ms: f64,
}

/// The readout: the last run, the learned model's figures, and both
/// models' geometry.
#[derive(serde::Serialize)]
#[serde(rename_all = "camelCase")]
struct Readout<'a> {
    run: &'a TrainingRun,
    learned: training::ModelSummary,
    hand_l0: f32,
    z_max: f64,
    /// Half-angle of the sensor's cone, radians.
    half_width: f64,
    hand_half_width: f64,
    learned_half_width: f64,
    alpha: f64,
    weights: &'a [f64],
}

/// Trains the learned model, timing sampling and fitting apart.
fn train(config: &TrainingConfig) -> Result<(LearnedInverse, TrainingRun), JsError> {
    let t0 = now_ms();
    let set = training::sample_triplets(config)?;
    let t1 = now_ms();
    let (model, report) = training::fit(config, &set)?;
    let t2 = now_ms();
    let run = TrainingRun {
        seed: config.seed,
        triplets: set.triplets.len(),
        epochs: config.epochs,
        maps: set.maps,
        map_occupancy: set.map_occupancy,
        no_returns: set.no_returns,
        occupied_fraction: report.occupied_fraction,
        sample_ms: t1 - t0,
        fit_ms: t2 - t1,
        train_ms: t2 - t0,
    };
    Ok((model, run))
}

#[wasm_bindgen]
impl InverseWorkbench {
    /// Trains the learned model with `seed` (a whole number; `undefined`
    /// for the chapter's seed) and builds the hand-crafted model for the
    /// same sensor.
    #[wasm_bindgen(constructor)]
    pub fn new(seed: Option<f64>) -> Result<InverseWorkbench, JsError> {
        let config = TrainingConfig {
            seed: match seed {
                Some(s) => training::seed_from_number(s)?,
                None => training::DEFAULT_SEED,
            },
            ..TrainingConfig::default()
        };
        let hand = HandCrafted::new(config.hand_crafted_counterpart()?)?;
        let (learned, run) = train(&config)?;
        Ok(InverseWorkbench {
            config,
            hand,
            learned,
            run,
        })
    }

    /// Retrains the learned model with another seed. On an error the
    /// current model stays.
    pub fn retrain(&mut self, seed: f64) -> Result<JsValue, JsError> {
        let config = TrainingConfig {
            seed: training::seed_from_number(seed)?,
            ..self.config
        };
        let (learned, run) = train(&config)?;
        self.config = config;
        self.learned = learned;
        self.run = run;
        self.readout()
    }

    /// `{ run: { seed, triplets, epochs, maps, mapOccupancy, noReturns,
    /// occupiedFraction, sampleMs, fitMs, trainMs }, learned: { l0,
    /// shortReading, freeEvidenceShort, freeEvidenceMaxRange, bandEnd },
    /// handL0, zMax, halfWidth, handHalfWidth, learnedHalfWidth, alpha,
    /// weights }`.
    pub fn readout(&self) -> Result<JsValue, JsError> {
        to_js(&Readout {
            run: &self.run,
            learned: training::summarize(&self.learned)?,
            hand_l0: self.hand.l0(),
            z_max: self.config.sensor.z_max,
            half_width: self.config.half_width,
            hand_half_width: self.hand.half_width(),
            learned_half_width: self.learned.half_width(),
            alpha: self.hand.params().alpha,
            weights: self.learned.weights(),
        })
    }

    /// Both models for reading `z` over `lattice` (`{ minRange, maxRange,
    /// ranges, maxBearing, bearings }`, metres and radians):
    /// `{ hand, learned }` evidence images (`Float32Array`, log odds net of
    /// each model's `l0`, one row per bearing from `-maxBearing`),
    /// `{ handAxis, learnedAxis }` log odds along the axis
    /// (`Float32Array`), `scale`: the largest `|evidence|` of the two
    /// images (their shared colour scale), `{ handL0, learnedL0 }`,
    /// `{ rangeAxis, bearingAxis }` (the lattice's ranges and bearings) and
    /// `{ handFree, learnedFree }`: the mean evidence on the axis in front
    /// of the reading (null when the reading is too short to have any).
    pub fn view(&self, z: f64, lattice: JsValue) -> Result<JsValue, JsError> {
        let lattice: BeamLattice = object_from_js("lattice", lattice)?;
        let v = side_by_side(&self.hand, &self.learned, z, &lattice)?;
        let out = js_sys::Object::new();
        let set = |key: &str, value: JsValue| -> Result<(), JsError> {
            js_sys::Reflect::set(&out, &JsValue::from_str(key), &value)
                .map(|_| ())
                .map_err(|_| JsError::new("cannot build the view object"))
        };
        let array = |v: &[f32]| JsValue::from(js_sys::Float32Array::from(v));
        set("hand", array(&v.fields[0]))?;
        set("learned", array(&v.fields[1]))?;
        set("handAxis", array(&v.axes[0]))?;
        set("learnedAxis", array(&v.axes[1]))?;
        set("scale", JsValue::from_f64(v.scale as f64))?;
        let ranges: Vec<f32> = (0..lattice.ranges)
            .map(|i| lattice.range(i) as f32)
            .collect();
        let bearings: Vec<f32> = (0..lattice.bearings)
            .map(|j| lattice.bearing(j) as f32)
            .collect();
        set("rangeAxis", array(&ranges))?;
        set("bearingAxis", array(&bearings))?;
        // Too short a reading has no free space in front of its ramp: null.
        let free = |m: &dyn InverseModel| {
            mean_free_evidence(m, z, training::FREE_MARGIN).map_or(JsValue::NULL, JsValue::from_f64)
        };
        set("handFree", free(&self.hand))?;
        set("learnedFree", free(&self.learned))?;
        set("handL0", JsValue::from_f64(self.hand.l0() as f64))?;
        set("learnedL0", JsValue::from_f64(self.learned.l0() as f64))?;
        Ok(out.into())
    }

    /// Workload W5 `learn-inverse` once, with `seed`: `{ sampleMs, fitMs,
    /// trainMs, triplets, epochs }` (the model is kept).
    #[wasm_bindgen(js_name = benchmarkTraining)]
    pub fn benchmark_training(&mut self, seed: f64) -> Result<JsValue, JsError> {
        self.retrain(seed)?;
        to_js(&self.run)
    }
}

/// The forward beam model's `p(z | z*)` (Table 6.1): the chapter's reference
/// setting when `params` is `undefined`, else an object overriding any of
/// its fields (`{ z_max: 8 }`). A density in 1/metres below `z_max`; at
/// `z_max` the point mass.
#[wasm_bindgen(js_name = forwardDensity)]
pub fn forward_density(z: f64, z_star: f64, params: JsValue) -> Result<f64, JsError> {
    let params: BeamModelParams = object_or_default("params", params, || BeamModelParams::CHAPTER)?;
    let model = BeamModel::new(params)?;
    crate::error::non_negative("z", z)?;
    crate::error::finite("z_star", z_star)?;
    Ok(model.density(z, z_star))
}
