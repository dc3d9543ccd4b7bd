//! The inverse-model workbench's training spread over calls of a bounded
//! amount of work ([`crate::inverse::training::Trainer`]), so that a page
//! keeps its frames while the learned model of §9.3 trains: the model is
//! the one [`WorkbenchSession::new`], `retrain` and `set_density` train,
//! bit for bit, and the run's figures are theirs but for the timings, which
//! add up the calls' times (sampling and fitting apart).

use super::inverse_workbench::{TrainingRun, WorkbenchSession};
use crate::error::Result;
use crate::inverse::training::{self, Trainer, TrainingConfig};

/// A training under way.
#[derive(Debug, Clone)]
pub struct WorkbenchTraining {
    config: TrainingConfig,
    trainer: Trainer,
    sample_ms: f64,
    fit_ms: f64,
}

impl WorkbenchTraining {
    /// A training with `config`, checked before any work.
    pub fn new(config: TrainingConfig) -> Result<Self> {
        config.validate()?;
        Ok(Self {
            trainer: Trainer::new(&config)?,
            config,
            sample_ms: 0.0,
            fit_ms: 0.0,
        })
    }

    /// The chapter's training with `seed` (its own when `None`), as a new
    /// session trains.
    pub fn for_seed(seed: Option<u64>) -> Result<Self> {
        Self::new(TrainingConfig {
            seed: seed.unwrap_or(training::DEFAULT_SEED),
            ..TrainingConfig::default()
        })
    }

    /// `session`'s training with another seed.
    pub fn retrain(session: &WorkbenchSession, seed: u64) -> Result<Self> {
        Self::new(TrainingConfig {
            seed,
            ..*session.config()
        })
    }

    /// `session`'s training on maps filled to `density`.
    pub fn with_density(session: &WorkbenchSession, density: f64) -> Result<Self> {
        Self::new(TrainingConfig {
            density,
            ..*session.config()
        })
    }

    /// True once the model is trained.
    pub fn done(&self) -> bool {
        self.trainer.done()
    }

    /// Trains for about `budget` units (a triplet drawn or an SGD update),
    /// timed on `now` (milliseconds); returns true once trained.
    pub fn step(&mut self, budget: usize, now: &dyn Fn() -> f64) -> Result<bool> {
        let sampling = self.trainer.sampling();
        let t0 = now();
        self.trainer.step(budget)?;
        let ms = now() - t0;
        // A call that crosses from sampling to fitting counts as sampling.
        if sampling {
            self.sample_ms += ms;
        } else {
            self.fit_ms += ms;
        }
        Ok(self.done())
    }

    /// The model and its run's figures, training what is left first.
    fn finish(
        self,
        now: &dyn Fn() -> f64,
    ) -> Result<(TrainingConfig, crate::inverse::LearnedInverse, TrainingRun)> {
        let t0 = now();
        let (model, set, report) = self.trainer.finish()?;
        let rest = now() - t0;
        let (sample_ms, fit_ms) = (self.sample_ms, self.fit_ms + rest);
        let c = self.config;
        let run = TrainingRun {
            seed: c.seed,
            triplets: set.triplets.len(),
            epochs: c.epochs,
            maps: set.maps,
            density: c.density,
            map_occupancy: set.map_occupancy,
            no_returns: set.no_returns,
            occupied_fraction: report.occupied_fraction,
            sample_ms,
            fit_ms,
            train_ms: sample_ms + fit_ms,
        };
        Ok((c, model, run))
    }

    /// A new session with the trained model.
    pub fn into_session(self, now: &dyn Fn() -> f64) -> Result<WorkbenchSession> {
        let (config, model, run) = self.finish(now)?;
        WorkbenchSession::with_model(config, model, run)
    }

    /// Puts the trained model into `session` in place of its own.
    pub fn apply(self, session: &mut WorkbenchSession, now: &dyn Fn() -> f64) -> Result<()> {
        let (config, model, run) = self.finish(now)?;
        session.adopt(config, model, run);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn no_clock() -> f64 {
        0.0
    }

    /// A session trained in calls of 500 units is the session trained in
    /// one go: the same model and figures (the timings aside); so are a
    /// retraining with another seed and one on denser maps.
    #[test]
    fn a_workbench_trained_in_calls_is_the_one_trained_at_once() {
        let whole = WorkbenchSession::new(None, &no_clock).unwrap();
        let mut t = WorkbenchTraining::for_seed(None).unwrap();
        let mut calls = 0;
        while !t.step(500, &no_clock).unwrap() {
            calls += 1;
        }
        assert!(calls > 100, "{calls} calls");
        let mut sliced = t.into_session(&no_clock).unwrap();
        assert_eq!(sliced.learned().weights(), whole.learned().weights());
        assert_eq!(sliced.run(), whole.run());

        let mut reference = WorkbenchSession::new(None, &no_clock).unwrap();
        reference.retrain(4, &no_clock).unwrap();
        reference.set_density(0.3, &no_clock).unwrap();
        WorkbenchTraining::retrain(&sliced, 4)
            .unwrap()
            .apply(&mut sliced, &no_clock)
            .unwrap();
        let mut t = WorkbenchTraining::with_density(&sliced, 0.3).unwrap();
        while !t.step(5_000, &no_clock).unwrap() {}
        t.apply(&mut sliced, &no_clock).unwrap();
        assert_eq!(sliced.learned().weights(), reference.learned().weights());
        assert_eq!(sliced.run(), reference.run());
        assert_eq!(sliced.config(), reference.config());
    }

    /// A seed or density the training refuses is refused before any work.
    #[test]
    fn refused_settings_are_refused_at_the_start() {
        let session = WorkbenchSession::new(None, &no_clock).unwrap();
        let e = WorkbenchTraining::with_density(&session, 5.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("density"), "{e}");
    }
}
