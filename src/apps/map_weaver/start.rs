//! Making a Map Weaver run the way a page does: the settings checked once,
//! the learned model trained in calls of bounded work (or taken from the
//! last run's, when its training settings are the same), then the run's
//! maps drawn in calls of a bounded number of cells ([`WeaverBuild`]), so
//! that a page keeps its frames while the model trains and a large scene is
//! drawn (docs/ARCHITECTURE.md, "Sessions and panes": a page never blocks).

use super::{BuildReport, CheckedWeaverSettings, Weaver, WeaverBuild, WeaverSettings};
use crate::error::{OccError, Result};
use crate::inverse::training::{self, Trainer, TrainingConfig};
use crate::inverse::LearnedInverse;
use std::cell::RefCell;

thread_local! {
    /// The last model trained for a run, with its training settings: a
    /// page that makes a new run (another seed, scene or number of laps)
    /// trains only when the training settings change, once per page
    /// otherwise (training is the longest part of making a run).
    static LEARNED: RefCell<Option<(TrainingConfig, LearnedInverse)>> = const { RefCell::new(None) };
}

/// The kept model, when it was trained with `config`.
fn kept_model(config: &TrainingConfig) -> Option<LearnedInverse> {
    LEARNED.with_borrow(|kept| {
        kept.as_ref()
            .filter(|(k, _)| k == config)
            .map(|(_, m)| m.clone())
    })
}

/// The model `config` trains, trained once per thread (a page) for the
/// same config.
fn learned_for(config: &TrainingConfig) -> Result<LearnedInverse> {
    if let Some(model) = kept_model(config) {
        return Ok(model);
    }
    let (model, _, _) = training::train(config)?;
    LEARNED.set(Some((*config, model.clone())));
    Ok(model)
}

/// A Map Weaver run being made: the learned model trained in calls of a
/// bounded amount of work ([`WeaverStart::train`]), then the run's maps
/// drawn in calls of a bounded number of cells ([`WeaverStart::build`]),
/// then the run ([`WeaverStart::finish`]). The model is the one
/// [`training::train`] trains, bit for bit, and is kept for the later runs
/// of the same thread; the run is the one [`Weaver::with_learned`] makes
/// with it, bit for bit.
#[derive(Debug)]
pub struct WeaverStart {
    settings: CheckedWeaverSettings,
    trainer: Option<Trainer>,
    /// Boxed: a build holds every map's parts (tens of kilobytes by
    /// value), and a page's wasm stack is small.
    build: Option<Box<WeaverBuild>>,
}

/// The refusal of a build that is not there (none is made twice).
fn finished() -> OccError {
    OccError::State("the run was already finished".into())
}

impl WeaverStart {
    /// Checks `settings` (a refusal names the field), before any training.
    pub fn new(settings: WeaverSettings) -> Result<Self> {
        let settings = settings.check()?;
        let training = &settings.settings().training;
        let trainer = match kept_model(training) {
            Some(_) => None,
            None => Some(Trainer::new(training)?),
        };
        Ok(Self {
            settings,
            trainer,
            build: None,
        })
    }

    /// The run at once: trained (or the kept model) and built with no
    /// budget.
    pub fn run(settings: WeaverSettings) -> Result<Weaver> {
        Self::new(settings)?.finish()
    }

    /// True once the model is trained.
    pub fn trained(&self) -> bool {
        self.trainer.as_ref().is_none_or(Trainer::done)
    }

    /// Trains for about `budget` units (a triplet drawn or an SGD update);
    /// returns true once the model is trained.
    pub fn train(&mut self, budget: usize) -> Result<bool> {
        match &mut self.trainer {
            Some(t) => {
                t.step(budget)?;
                Ok(t.done())
            }
            None => Ok(true),
        }
    }

    /// Draws the run's maps for about `budget` cells, the model trained
    /// first if it is not yet ([`WeaverBuild::work`]).
    pub fn build(&mut self, budget: u64) -> Result<BuildReport> {
        self.started()?.work(budget)
    }

    /// The run, what is left of the training and of the maps done first
    /// (a second call makes the run again, from the kept model).
    pub fn finish(&mut self) -> Result<Weaver> {
        self.started()?;
        self.build.take().ok_or_else(finished)?.finish()
    }

    /// The run's build, begun (with the model trained to its end) on the
    /// first call.
    fn started(&mut self) -> Result<&mut WeaverBuild> {
        if self.build.is_none() {
            let training = self.settings.settings().training;
            let learned = match self.trainer.take() {
                Some(t) => {
                    let (model, _, _) = t.finish()?;
                    LEARNED.set(Some((training, model.clone())));
                    model
                }
                None => learned_for(&training)?,
            };
            self.build = Some(Box::new(WeaverBuild::checked(
                self.settings.clone(),
                learned,
            )?));
        }
        self.build.as_deref_mut().ok_or_else(finished)
    }
}
