//! Bindings of `<occgrid-inverse-workbench>`: the hand-crafted inverse model
//! of Table 9.2 and the learned one of §9.3, for one beam, side by side.
//! The widget asks for both models' evidence over the beam's neighbourhood
//! and their log odds along its axis for one reading, and retrains the
//! learned model with another seed; it draws what it gets.

use super::{
    budget_from_js, index_from_js, now_ms, number_from_js, object_from_js, object_or_default,
    optional_number_from_js, to_js,
};
use crate::apps::inverse_workbench::WorkbenchSession;
use crate::apps::workbench_training::WorkbenchTraining;
use crate::inverse::probes::BeamLattice;
use crate::inverse::training;
use crate::sensors::beam_model::{BeamModel, BeamModelParams};
use wasm_bindgen::prelude::*;

/// Both models and the last training run, held in wasm memory:
/// [`WorkbenchSession`], and the last view's images.
#[wasm_bindgen]
pub struct InverseWorkbench {
    session: WorkbenchSession,
    images: [Vec<u8>; 2],
    /// A retraining under way (`startRetrain`, `startDensity`).
    pending: Option<WorkbenchTraining>,
}

#[wasm_bindgen]
impl InverseWorkbench {
    /// Trains the learned model with `seed` (a whole number; `undefined`
    /// for the chapter's seed) and builds the hand-crafted model for the
    /// same sensor.
    #[wasm_bindgen(constructor)]
    pub fn new(seed: JsValue) -> Result<InverseWorkbench, JsError> {
        let seed = optional_number_from_js("seed", &seed)?;
        let seed = seed.map(training::seed_from_number).transpose()?;
        Ok(InverseWorkbench {
            session: WorkbenchSession::new(seed, &now_ms)?,
            images: [Vec::new(), Vec::new()],
            pending: None,
        })
    }

    /// Retrains the learned model with another seed and returns the
    /// readout, whose `run` holds the training's timings (`sampleMs`,
    /// `fitMs`, `trainMs`: workload W5 `learn-inverse`). On an error the
    /// current model stays.
    pub fn retrain(&mut self, seed: JsValue) -> Result<JsValue, JsError> {
        let seed = number_from_js("seed", &seed)?;
        self.session
            .retrain(training::seed_from_number(seed)?, &now_ms)?;
        self.readout()
    }

    /// Retrains the learned model, same seed, on training maps filled to
    /// the occupied fraction `density` (0 to 0.6; 0 keeps the buildings as
    /// drawn) and returns the readout. On an error the current model stays.
    #[wasm_bindgen(js_name = setDensity)]
    pub fn set_density(&mut self, density: JsValue) -> Result<JsValue, JsError> {
        let density = number_from_js("density", &density)?;
        self.session.set_density(density, &now_ms)?;
        self.readout()
    }

    /// `{ run: { seed, triplets, epochs, maps, mapOccupancy, noReturns,
    /// occupiedFraction, sampleMs, fitMs, trainMs, density }, learned: { l0,
    /// shortReading, freeEvidenceShort, freeEvidenceMaxRange, bandEnd },
    /// handL0, zMax, halfWidth, handHalfWidth, learnedHalfWidth, alpha,
    /// weights }`.
    pub fn readout(&self) -> Result<JsValue, JsError> {
        to_js(&self.session.readout()?)
    }

    /// Both models for reading `z` at image pixel `(col, row)` of the
    /// images `view` drew over `lattice` (row 0 on top): `{ range,
    /// bearing, hand: { evidence, l, p }, learned: { evidence, l, p } }`,
    /// or `null` off the lattice.
    #[wasm_bindgen(js_name = cellAt)]
    pub fn cell_at(
        &self,
        z: JsValue,
        lattice: JsValue,
        col: JsValue,
        row: JsValue,
    ) -> Result<JsValue, JsError> {
        let z = number_from_js("z", &z)?;
        let lattice: BeamLattice = object_from_js("lattice", lattice)?;
        let (col, row) = (index_from_js("col", &col)?, index_from_js("row", &row)?);
        match self.session.cell(z, &lattice, col, row)? {
            Some(c) => to_js(&c),
            None => Ok(JsValue::NULL),
        }
    }

    /// Both models for reading `z` over `lattice` (`{ minRange, maxRange,
    /// ranges, maxBearing, bearings }`, metres and radians):
    /// `{ hand, learned }` evidence fields (`Float32Array`, log odds net of
    /// each model's `l0`, one row per bearing from `-maxBearing`),
    /// `{ handImage, learnedImage }` the addresses in wasm memory of their
    /// RGBA images (`ranges x bearings`, `+maxBearing` on top, on the
    /// shared scale), `{ handAxis, learnedAxis }` log odds along the axis
    /// (`Float32Array`), `scale`: the images' fixed colour scale (log
    /// odds, the same at every reading), `strongest`: the largest
    /// `|evidence|` of the two at this reading, `{ handL0, learnedL0 }`,
    /// `{ rangeAxis, bearingAxis }` (the lattice's ranges and bearings) and
    /// `{ handFree, learnedFree }`: the mean evidence on the axis in front
    /// of the reading (null when the reading is too short to have any).
    pub fn view(&mut self, z: JsValue, lattice: JsValue) -> Result<JsValue, JsError> {
        let z = number_from_js("z", &z)?;
        let lattice: BeamLattice = object_from_js("lattice", lattice)?;
        let v = self.session.view(z, &lattice)?;
        self.images = v.images;
        let out = js_sys::Object::new();
        let set = |key: &str, value: JsValue| -> Result<(), JsError> {
            js_sys::Reflect::set(&out, &JsValue::from_str(key), &value)
                .map(|_| ())
                .map_err(|_| JsError::new("cannot build the view object"))
        };
        let array = |v: &[f32]| JsValue::from(js_sys::Float32Array::from(v));
        let number = |v: Option<f64>| v.map_or(JsValue::NULL, JsValue::from_f64);
        set("hand", array(&v.fields[0]))?;
        set("learned", array(&v.fields[1]))?;
        set(
            "handImage",
            JsValue::from_f64(self.images[0].as_ptr() as usize as f64),
        )?;
        set(
            "learnedImage",
            JsValue::from_f64(self.images[1].as_ptr() as usize as f64),
        )?;
        set("handAxis", array(&v.axes[0]))?;
        set("learnedAxis", array(&v.axes[1]))?;
        set("scale", JsValue::from_f64(v.scale as f64))?;
        set("strongest", JsValue::from_f64(v.strongest as f64))?;
        set("rangeAxis", array(&v.range_axis))?;
        set("bearingAxis", array(&v.bearing_axis))?;
        set("handFree", number(v.free[0]))?;
        set("learnedFree", number(v.free[1]))?;
        set("handL0", JsValue::from_f64(v.l0[0] as f64))?;
        set("learnedL0", JsValue::from_f64(v.l0[1] as f64))?;
        Ok(out.into())
    }
}

/// The forward beam model's `p(z | z*)` (Table 6.1): the chapter's reference
/// setting when `params` is `undefined`, else an object overriding any of
/// its fields (`{ z_max: 8 }`). A density in 1/metres below `z_max`; at
/// `z_max` the point mass.
#[wasm_bindgen(js_name = forwardDensity)]
pub fn forward_density(z: JsValue, z_star: JsValue, params: JsValue) -> Result<f64, JsError> {
    let (z, z_star) = (number_from_js("z", &z)?, number_from_js("z_star", &z_star)?);
    let params: BeamModelParams = object_or_default("params", params, || BeamModelParams::CHAPTER)?;
    let model = BeamModel::new(params)?;
    crate::error::non_negative("z", z)?;
    // An expected range is a distance: a negative one has no density.
    crate::error::non_negative("z_star", z_star)?;
    Ok(model.density(z, z_star))
}

/// A training of the workbench's learned model spread over calls of a
/// bounded amount of work ([`WorkbenchTraining`]), so that a page keeps its
/// frames while it trains: `work` until it says true, then `finish` (a new
/// workbench; a retraining goes through `InverseWorkbench.startRetrain`).
#[wasm_bindgen]
pub struct InverseWorkbenchTraining(Option<WorkbenchTraining>);

#[wasm_bindgen]
impl InverseWorkbenchTraining {
    /// The training `new InverseWorkbench(seed)` does (`seed`: a whole
    /// number, or `undefined` for the chapter's), checked before any work.
    #[wasm_bindgen(constructor)]
    pub fn new(seed: JsValue) -> Result<InverseWorkbenchTraining, JsError> {
        let seed = optional_number_from_js("seed", &seed)?;
        let seed = seed.map(training::seed_from_number).transpose()?;
        Ok(InverseWorkbenchTraining(Some(WorkbenchTraining::for_seed(
            seed,
        )?)))
    }

    /// True once the model is trained (false once `finish` took it).
    #[wasm_bindgen(getter)]
    pub fn trained(&self) -> bool {
        self.0.as_ref().is_some_and(WorkbenchTraining::done)
    }

    /// Trains for about `budget` units (a triplet drawn or an SGD update; a
    /// whole number, or `Infinity`); true once trained.
    pub fn work(&mut self, budget: JsValue) -> Result<bool, JsError> {
        let budget = budget_from_js("budget", &budget)?;
        Ok(self.training()?.step(budget, &now_ms)?)
    }

    /// The workbench with the trained model (training what is left first).
    pub fn finish(&mut self) -> Result<InverseWorkbench, JsError> {
        let session = self.take()?.into_session(&now_ms)?;
        Ok(InverseWorkbench {
            session,
            images: [Vec::new(), Vec::new()],
            pending: None,
        })
    }
}

impl InverseWorkbenchTraining {
    fn training(&mut self) -> Result<&mut WorkbenchTraining, JsError> {
        self.0
            .as_mut()
            .ok_or_else(|| JsError::new("invalid training: already used (start another)"))
    }
    fn take(&mut self) -> Result<WorkbenchTraining, JsError> {
        self.0
            .take()
            .ok_or_else(|| JsError::new("invalid training: already used (start another)"))
    }
}

#[wasm_bindgen]
impl InverseWorkbench {
    /// Starts the training `retrain(seed)` does, held by the workbench and
    /// worked by `trainWork` (a later start replaces it); a refused seed is
    /// refused here, the model staying.
    #[wasm_bindgen(js_name = startRetrain)]
    pub fn start_retrain(&mut self, seed: JsValue) -> Result<(), JsError> {
        let seed = training::seed_from_number(number_from_js("seed", &seed)?)?;
        self.pending = Some(WorkbenchTraining::retrain(&self.session, seed)?);
        Ok(())
    }

    /// Starts the training `setDensity(density)` does, as `startRetrain`.
    #[wasm_bindgen(js_name = startDensity)]
    pub fn start_density(&mut self, density: JsValue) -> Result<(), JsError> {
        let density = number_from_js("density", &density)?;
        self.pending = Some(WorkbenchTraining::with_density(&self.session, density)?);
        Ok(())
    }

    /// Works the started training for about `budget` units (a whole
    /// number, or `Infinity`); once it is trained its model takes the
    /// current one's place and this returns true (true too with none
    /// started).
    #[wasm_bindgen(js_name = trainWork)]
    pub fn train_work(&mut self, budget: JsValue) -> Result<bool, JsError> {
        let budget = budget_from_js("budget", &budget)?;
        let Some(training) = &mut self.pending else {
            return Ok(true);
        };
        if !training.step(budget, &now_ms)? {
            return Ok(false);
        }
        if let Some(training) = self.pending.take() {
            training.apply(&mut self.session, &now_ms)?;
        }
        Ok(true)
    }
}
