//! The inverse-model workbench session (Table 9.2 against §9.3): both
//! models for one beam, trained and timed, with everything the widget shows:
//! the evidence images rendered on one fixed scale ([`EVIDENCE_SCALE`]), the log odds along the
//! beam axis, the mean free evidence in front of the reading, and the
//! training run's figures.

use crate::error::Result;
use crate::inverse::probes::{mean_free_evidence, side_by_side, BeamLattice};
use crate::inverse::training::{self, ModelSummary, TrainingConfig};
use crate::inverse::{HandCrafted, InverseModel, LearnedInverse};
use crate::render::evidence::render_evidence_rgba;

/// The images' colour scale, log odds: `+4` black, `-4` white, whatever the
/// reading. A scale fitted to each reading's strongest cell would swing
/// from about 0.8 at a max-range reading to 4 at a short one, and draw a
/// max-range reading's faint free evidence as strongly white as a short
/// reading's: the opposite of what the image is for (the learned model
/// hardly trusts a no-return). Both models' evidence stays within it but
/// for a few cells next to the sensor, which are drawn at its ends.
pub const EVIDENCE_SCALE: f32 = 4.0;

/// What the widget's reading and density keep to: the training sensor's
/// maximum range (a reading there is a no-return) and the densest training
/// maps the core fills.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WorkbenchLimits {
    pub z_max: f64,
    pub max_density: f64,
}

impl WorkbenchLimits {
    pub fn chapter() -> Self {
        Self {
            z_max: TrainingConfig::default().sensor.z_max,
            max_density: crate::scenes::floor_plans::MAX_DENSITY,
        }
    }
}

/// What the readout says about the last training run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TrainingRun {
    pub seed: u64,
    pub triplets: usize,
    pub epochs: usize,
    pub maps: usize,
    /// The occupied fraction the training maps were filled to (0: the
    /// buildings as drawn).
    pub density: f64,
    pub map_occupancy: f64,
    pub no_returns: f64,
    pub occupied_fraction: f64,
    /// Milliseconds on the host's clock (NaN where it has none).
    pub sample_ms: f64,
    pub fit_ms: f64,
    pub train_ms: f64,
}

/// The readout: the last run, the learned model's figures, and both
/// models' geometry.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WorkbenchReadout<'a> {
    pub run: &'a TrainingRun,
    pub learned: ModelSummary,
    pub hand_l0: f32,
    pub z_max: f64,
    /// Half-angle of the sensor's cone, radians.
    pub half_width: f64,
    pub hand_half_width: f64,
    pub learned_half_width: f64,
    pub alpha: f64,
    pub weights: &'a [f64],
}

/// Both models for one reading over one lattice: the evidence fields, their
/// images (RGBA, `ranges x bearings`, most positive bearing on top), the
/// axis curves, the shared scale and the mean free evidence.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkbenchView {
    /// Evidence, log odds net of each model's `l0`: hand-crafted, learned.
    pub fields: [Vec<f32>; 2],
    pub images: [Vec<u8>; 2],
    /// Log odds along the axis: hand-crafted, learned.
    pub axes: [Vec<f32>; 2],
    /// The images' colour scale, [`EVIDENCE_SCALE`]: `+scale` black,
    /// `-scale` white.
    pub scale: f32,
    /// The largest `|evidence|` of either model at this reading (cells
    /// beyond `scale` are drawn at its ends).
    pub strongest: f32,
    pub range_axis: Vec<f32>,
    pub bearing_axis: Vec<f32>,
    /// Mean evidence in front of the reading (`None` when the reading is
    /// too short to have any free space in front of its ramp).
    pub free: [Option<f64>; 2],
    pub l0: [f32; 2],
}

/// One model's answer for one cell of the beam's neighbourhood.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ModelCell {
    /// Log odds net of the model's `l0` (what the image draws).
    pub evidence: f32,
    /// The inverse model's own log odds, `evidence + l0`.
    pub l: f64,
    /// The inverse model's probability `p(m | z)` (Table 9.1, line 4).
    pub p: f64,
}

/// One lattice sample of both images, as the cell readout shows it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WorkbenchCell {
    /// Range along the beam, metres.
    pub range: f64,
    /// Bearing offset from the beam axis, radians.
    pub bearing: f64,
    pub hand: ModelCell,
    pub learned: ModelCell,
}

fn model_cell(m: &dyn InverseModel, r: f64, phi: f64, z: f64) -> ModelCell {
    let evidence = m.evidence(r, phi, z);
    let l = evidence as f64 + m.l0() as f64;
    ModelCell {
        evidence,
        l,
        p: crate::grid::probability(l),
    }
}

/// The workbench: the training configuration, both models and the last run.
pub struct WorkbenchSession {
    config: TrainingConfig,
    hand: HandCrafted,
    learned: LearnedInverse,
    run: TrainingRun,
}

/// Trains the learned model, timing sampling and fitting apart on `now`
/// (milliseconds; the core has no clock of its own in wasm).
fn train(config: &TrainingConfig, now: &dyn Fn() -> f64) -> Result<(LearnedInverse, TrainingRun)> {
    let t0 = now();
    let set = training::sample_triplets(config)?;
    let t1 = now();
    let (model, report) = training::fit(config, &set)?;
    let t2 = now();
    let run = TrainingRun {
        seed: config.seed,
        triplets: set.triplets.len(),
        epochs: config.epochs,
        maps: set.maps,
        density: config.density,
        map_occupancy: set.map_occupancy,
        no_returns: set.no_returns,
        occupied_fraction: report.occupied_fraction,
        sample_ms: t1 - t0,
        fit_ms: t2 - t1,
        train_ms: t2 - t0,
    };
    Ok((model, run))
}

impl WorkbenchSession {
    /// Trains the learned model with `seed` (the chapter's when `None`) and
    /// builds the hand-crafted model for the same sensor.
    pub fn new(seed: Option<u64>, now: &dyn Fn() -> f64) -> Result<Self> {
        let config = TrainingConfig {
            seed: seed.unwrap_or(training::DEFAULT_SEED),
            ..TrainingConfig::default()
        };
        let hand = HandCrafted::new(config.hand_crafted_counterpart()?)?;
        let (learned, run) = train(&config, now)?;
        Ok(Self {
            config,
            hand,
            learned,
            run,
        })
    }

    /// A session around a model trained elsewhere (in calls spread over a
    /// page's frames: [`super::workbench_training`]) with `config`.
    pub fn with_model(
        config: TrainingConfig,
        learned: LearnedInverse,
        run: TrainingRun,
    ) -> Result<Self> {
        let hand = HandCrafted::new(config.hand_crafted_counterpart()?)?;
        Ok(Self {
            config,
            hand,
            learned,
            run,
        })
    }

    /// Takes a model trained elsewhere with `config` (another seed or
    /// density, same sensor) in place of the current one.
    pub fn adopt(&mut self, config: TrainingConfig, learned: LearnedInverse, run: TrainingRun) {
        self.config = config;
        self.learned = learned;
        self.run = run;
    }

    /// The training settings of the current model.
    pub fn config(&self) -> &TrainingConfig {
        &self.config
    }

    /// Retrains the learned model with another seed. On an error the
    /// current model stays.
    pub fn retrain(&mut self, seed: u64, now: &dyn Fn() -> f64) -> Result<()> {
        let config = TrainingConfig {
            seed,
            ..self.config
        };
        let (learned, run) = train(&config, now)?;
        self.config = config;
        self.learned = learned;
        self.run = run;
        Ok(())
    }

    /// Retrains the learned model, same seed, on maps filled to `density`
    /// (an occupied fraction from 0 to
    /// [`crate::scenes::floor_plans::MAX_DENSITY`]; 0 keeps the buildings
    /// as drawn). On an error the current model stays.
    pub fn set_density(&mut self, density: f64, now: &dyn Fn() -> f64) -> Result<()> {
        let config = TrainingConfig {
            density,
            ..self.config
        };
        config.validate()?;
        let (learned, run) = train(&config, now)?;
        self.config = config;
        self.learned = learned;
        self.run = run;
        Ok(())
    }

    pub fn run(&self) -> &TrainingRun {
        &self.run
    }

    pub fn learned(&self) -> &LearnedInverse {
        &self.learned
    }

    pub fn readout(&self) -> Result<WorkbenchReadout<'_>> {
        Ok(WorkbenchReadout {
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

    /// Both models for reading `z` at image pixel `(col, row)` of
    /// `lattice`'s images (column `col` a range, row 0 the most positive
    /// bearing, as drawn); `None` off the lattice.
    pub fn cell(
        &self,
        z: f64,
        lattice: &BeamLattice,
        col: usize,
        row: usize,
    ) -> Result<Option<WorkbenchCell>> {
        crate::error::non_negative("z", z)?;
        lattice.validate()?;
        if col >= lattice.ranges || row >= lattice.bearings {
            return Ok(None);
        }
        let (r, phi) = (
            lattice.range(col),
            lattice.bearing(lattice.bearings - 1 - row),
        );
        Ok(Some(WorkbenchCell {
            range: r,
            bearing: phi,
            hand: model_cell(&self.hand, r, phi, z),
            learned: model_cell(&self.learned, r, phi, z),
        }))
    }

    /// Both models for reading `z` (metres) over `lattice`.
    pub fn view(&self, z: f64, lattice: &BeamLattice) -> Result<WorkbenchView> {
        let v = side_by_side(&self.hand, &self.learned, z, lattice)?;
        let mut images = [Vec::new(), Vec::new()];
        for (image, field) in images.iter_mut().zip(&v.fields) {
            render_evidence_rgba(
                field,
                lattice.ranges,
                lattice.bearings,
                EVIDENCE_SCALE as f64,
                image,
            )?;
        }
        let free = |m: &dyn InverseModel| mean_free_evidence(m, z, training::FREE_MARGIN).ok();
        Ok(WorkbenchView {
            images,
            axes: v.axes,
            scale: EVIDENCE_SCALE,
            strongest: v.scale,
            range_axis: (0..lattice.ranges)
                .map(|i| lattice.range(i) as f32)
                .collect(),
            bearing_axis: (0..lattice.bearings)
                .map(|j| lattice.bearing(j) as f32)
                .collect(),
            free: [free(&self.hand), free(&self.learned)],
            l0: [self.hand.l0(), self.learned.l0()],
            fields: v.fields,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice() -> BeamLattice {
        BeamLattice {
            min_range: 0.0,
            max_range: 4.0,
            ranges: 40,
            max_bearing: 0.3,
            bearings: 9,
        }
    }

    #[test]
    fn the_session_trains_times_and_draws_both_models_on_one_scale() {
        let clock = std::cell::Cell::new(0.0);
        let now = || {
            clock.set(clock.get() + 5.0);
            clock.get()
        };
        let mut w = WorkbenchSession::new(None, &now).unwrap();
        assert_eq!(w.run().seed, training::DEFAULT_SEED);
        assert_eq!((w.run().sample_ms, w.run().fit_ms), (5.0, 5.0));
        let v = w.view(2.0, &lattice()).unwrap();
        assert_eq!(v.images[0].len(), 40 * 9 * 4);
        // The image is the field on the fixed scale, pixel by pixel.
        // (Rows are flipped, so compare the sorted grays.)
        for (field, image) in v.fields.iter().zip(&v.images) {
            let mut grays: Vec<u8> = image.iter().step_by(4).copied().collect();
            let mut want: Vec<u8> = field
                .iter()
                .map(|e| {
                    (128.0 - 127.0 * e / EVIDENCE_SCALE)
                        .round()
                        .clamp(0.0, 255.0) as u8
                })
                .collect();
            grays.sort_unstable();
            want.sort_unstable();
            assert_eq!(grays, want);
        }
        // One scale at every reading: a short one, the chapter's, a
        // no-return. (Fitted to each reading, it swung from 4.2 to 0.8.)
        let z_max = w.readout().unwrap().z_max;
        let views: Vec<_> = [0.2, 2.0, z_max]
            .iter()
            .map(|&z| w.view(z, &lattice()).unwrap())
            .collect();
        assert!(views.iter().all(|v| v.scale == EVIDENCE_SCALE));
        // A no-return's free evidence is faint on that scale: no pixel of
        // the learned image comes near white.
        let lightest = views[2].images[1].iter().step_by(4).max().copied().unwrap();
        assert!(lightest < 200, "max-range reading drawn {lightest}");
        assert!(
            views[2].strongest < 0.5 * EVIDENCE_SCALE,
            "{}",
            views[2].strongest
        );
        assert!(
            v.free[1].is_some() && v.free[1].unwrap() < 0.0,
            "free space in front"
        );
        // A cell's readout is the image's field value at that pixel (rows
        // flipped: row 0 is the most positive bearing).
        let l = lattice();
        for (col, row) in [(0, 0), (13, 4), (39, 8)] {
            let c = w.cell(2.0, &l, col, row).unwrap().unwrap();
            let at = (l.bearings - 1 - row) * l.ranges + col;
            assert_eq!(c.hand.evidence, v.fields[0][at]);
            assert_eq!(c.learned.evidence, v.fields[1][at]);
            assert!((c.learned.p - crate::grid::probability(c.learned.l)).abs() < 1e-12);
        }
        assert_eq!(w.cell(2.0, &l, 40, 0).unwrap(), None);
        assert!(w.cell(-1.0, &l, 0, 0).is_err());
        let before = w.learned().clone();
        w.retrain(10, &now).unwrap();
        assert_eq!(w.run().seed, 10);
        assert_ne!(w.learned(), &before, "another seed, another model");
        // The density of the training maps moves l0 (§9.3).
        let thin = w.learned().own_l0();
        w.set_density(0.45, &now).unwrap();
        assert_eq!((w.run().seed, w.run().density), (10, 0.45));
        assert!(
            w.learned().own_l0() > thin + 1.0,
            "{thin} {}",
            w.learned().own_l0()
        );
        let kept = w.learned().clone();
        assert!(w
            .set_density(0.9, &now)
            .unwrap_err()
            .to_string()
            .contains("density"));
        assert_eq!(w.learned(), &kept, "a bad density keeps the model");
    }
}
