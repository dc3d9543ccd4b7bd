//! Training the learned inverse model (Probabilistic Robotics §9.3).
//!
//! Where the data come from, and how the weights are fitted:
//!
//! 1. **A map prior** ([`sample_map`]): floor plans of buildings — thin
//!    walls between open rooms, doorways, furniture that is mostly legs and
//!    small pieces (described below) — as ground-truth [`World`]s.
//! 2. **Triplets** ([`sample_triplets`]): in a sampled map, a pose where a
//!    robot fits and a beam direction; the beam's expected range `z*` by ray
//!    casting (a cone of a few sub-rays), a reading `z` drawn from the
//!    forward model of Table 6.1 in generative mode; and a target cell near
//!    the beam, recorded as its beam-frame range `r`, bearing offset `psi`,
//!    the reading, and its true occupancy.
//! 3. **Logistic regression by SGD** ([`fit`]) on the features of
//!    [`super::learned`], with a step that decays as `eta0 / (1 + t / N)`
//!    (`N` triplets, `t` updates so far), 24,000 triplets and 8 epochs by
//!    default, the weights averaged over the last epoch. It lands within a
//!    thousandth of a nat of the exact optimum (Newton's method, in the
//!    tests).
//!
//! Nothing about obstacles' thickness or the beam's width is told to the
//! model: it learns them from the maps and the sensor, together with its own
//! prior and how far past a reading its evidence reaches. What it learns is
//! only as good as the prior: trained on maps of deep solid blocks its
//! occupied band runs as far past the reading as its features let it (0.7 m
//! when they reached 0.9 m), and Map Weaver paints it behind every wall of
//! the flat; trained on buildings, it ends some 0.4 m past the reading. Everything is seeded: the same configuration gives the same
//! weights, bit for bit.
//!
//! Speed (docs/BENCHMARKS.md W5, under 150 ms as wasm): ray casts stop at the
//! first occupied cell, beam directions are drawn as unit vectors (no angle,
//! so no sine or cosine), features are polynomials computed once per
//! triplet, and each SGD update costs one exponential.

use super::learned::{
    FeatureFrame, LearnedInverse, BEHIND_BAND, BIAS, FEATURES, FIELD, SPLINE_END, SPLINE_START,
};
use super::probes::mean_free_evidence;
use super::HandCraftedParams;
use crate::error::{self, invalid, Result};
use crate::scenes::floor_plans::{
    add_clutter, is_clear_around, sample_floor_plan, MAX_DENSITY, POSE_CLEARANCE,
};
use crate::sensors::beam_model::{expected_range_along, BeamModel, BeamModelParams, BeamShape};
use crate::world::World;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// The most SGD updates (`triplets x epochs`) one training may take: about
/// 26 times the default 24,000 x 8.
pub const MAX_UPDATES: u64 = 5_000_000;

/// Everything that defines a training run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct TrainingConfig {
    pub seed: u64,
    /// Number of (cell, reading, occupancy) samples.
    pub triplets: usize,
    /// Passes of SGD over the triplets.
    pub epochs: usize,
    /// Initial SGD step `eta0`.
    pub learning_rate: f64,
    /// The sensor's forward model (its `z_max` is the sensor's range).
    pub sensor: BeamModelParams,
    /// Half-angle of the sensor's cone, radians.
    pub half_width: f64,
    /// Rays that probe the cone for its expected range.
    pub sub_rays: usize,
    /// Cell size of the sampled maps, metres.
    pub resolution: f64,
    /// Occupied fraction the sampled maps are filled to with solid boxes
    /// ([`crate::scenes::floor_plans::add_clutter`]); 0, the default,
    /// keeps the thin-walled buildings as drawn (about 17% occupied).
    pub density: f64,
}

/// The default seed: chapter 9.
pub const DEFAULT_SEED: u64 = 9;

/// Spread of a hit of the default training sensor, metres: a LiDAR's range
/// noise of a few centimetres (the simulated apartment's is 2 cm).
pub const LIDAR_SIGMA_HIT: f64 = 0.05;

impl Default for TrainingConfig {
    /// The simulated apartment's LiDAR (range 8 m, 0.10 m cells) with the
    /// chapter's mixture weights, a 5 degree cone, 24,000 triplets.
    ///
    /// The hit's spread is a LiDAR's, [`LIDAR_SIGMA_HIT`], not the
    /// chapter's 0.15 m: a model learns the sensor it is trained on, and
    /// one trained on 0.15 m readings of thin walls spreads every wall
    /// over some 0.3 m on either side of the reading. Mapped with the
    /// apartment's 2 cm readings, that thickens every wall by a cell or
    /// two in front and behind, and its Brier score falls some 0.02 behind
    /// Table 9.2's.
    fn default() -> Self {
        Self {
            seed: DEFAULT_SEED,
            triplets: 24_000,
            epochs: 8,
            learning_rate: 0.5,
            sensor: BeamModelParams {
                z_max: 8.0,
                sigma_hit: LIDAR_SIGMA_HIT,
                ..BeamModelParams::CHAPTER
            },
            half_width: 2.5f64.to_radians(),
            sub_rays: 3,
            resolution: 0.1,
            density: 0.0,
        }
    }
}

/// Triplets sampled per map: enough to amortise drawing the map, few enough
/// that 24,000 triplets see a couple of hundred different floor plans.
const TRIPLETS_PER_MAP: usize = 100;
/// Target cells taken per no-return reading (one per real return).
const NO_RETURN_TARGETS: usize = 4;
/// Largest sampled map, in cells.
const MAX_MAP_CELLS: usize = 1 << 20;
/// The SGD's shuffling stream is seeded apart from the sampling stream, so
/// that refitting the same triplets does not depend on how many random
/// numbers the sampler drew.
const FIT_STREAM: u64 = 0x0005_EED0_F56D;

impl TrainingConfig {
    pub fn validate(&self) -> Result<()> {
        if !(1..=1_000_000).contains(&self.triplets) {
            return Err(invalid(
                "triplets",
                self.triplets,
                "between 1 and 1000000 triplets",
            ));
        }
        if !(1..=200).contains(&self.epochs) {
            return Err(invalid("epochs", self.epochs, "between 1 and 200 epochs"));
        }
        // Each bound alone still allows 2e8 SGD updates (a minute in a
        // page); cap their product at about 26 times the default
        // 24,000 x 8, a couple of seconds as wasm.
        let updates = self.triplets as u64 * self.epochs as u64;
        if updates > MAX_UPDATES {
            return Err(invalid(
                "triplets x epochs",
                format!("{} x {} = {updates}", self.triplets, self.epochs),
                "at most 5000000 updates: fewer triplets or epochs",
            ));
        }
        error::positive("learning_rate", self.learning_rate)?;
        if self.learning_rate > 10.0 {
            return Err(invalid(
                "learning_rate",
                self.learning_rate,
                "a step of at most 10",
            ));
        }
        BeamModel::new(self.sensor)?;
        self.frame().validate()?;
        BeamShape::cone(self.half_width, self.sub_rays)?;
        error::positive("resolution", self.resolution)?;
        if !(0.0..=MAX_DENSITY).contains(&self.density) {
            return Err(invalid(
                "density",
                self.density,
                "an occupied fraction between 0 and 0.6",
            ));
        }
        let cells = (self.map_side() / self.resolution).ceil();
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(cells * cells <= MAX_MAP_CELLS as f64) {
            return Err(invalid(
                "resolution",
                self.resolution,
                "cells no smaller than z_max / 800 (a sampled map holds at most 2^20 cells)",
            ));
        }
        Ok(())
    }

    /// The features' frame for this sensor.
    pub fn frame(&self) -> FeatureFrame {
        FeatureFrame {
            z_max: self.sensor.z_max,
            half_width: self.half_width,
        }
    }

    /// Side of a sampled map, metres: one and a half times the sensor's
    /// range (at least 6 m), so that a pose anywhere inside sees mostly map
    /// out to `z_max`.
    pub fn map_side(&self) -> f64 {
        (1.5 * self.sensor.z_max).max(6.0)
    }

    /// Table 9.2 for the same sensor, for the widgets' side-by-side
    /// comparison: obstacles two cells thick (`alpha = 2 * resolution`),
    /// `beta` the cone's full angle, `l_occ = +0.85`, `l_free = -0.40`,
    /// `l0 = 0` (the values of docs/BENCHMARKS.md W1).
    pub fn hand_crafted_counterpart(&self) -> Result<HandCraftedParams> {
        self.validate()?;
        let p = HandCraftedParams {
            alpha: 2.0 * self.resolution,
            beta: 2.0 * self.half_width,
            ..HandCraftedParams::laser(self.sensor.z_max)
        };
        p.validate()?;
        Ok(p)
    }
}

/// One training sample: a cell seen from a beam, and whether it is occupied.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Triplet {
    /// Range of the cell's centre from the sensor, metres.
    pub r: f32,
    /// Bearing offset of the cell's centre from the beam axis, radians.
    pub psi: f32,
    /// The beam's reading, metres (`z_max` for a no-return).
    pub z: f32,
    pub occupied: bool,
}

/// The sampled training data and what it says about the map prior.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainingSet {
    pub triplets: Vec<Triplet>,
    /// Number of maps drawn.
    pub maps: usize,
    /// Fraction of occupied cells over all sampled maps: the map prior's
    /// occupancy, which the model's `l0` should come near.
    pub map_occupancy: f64,
    /// Fraction of readings that were no-returns.
    pub no_returns: f64,
    /// Readings drawn.
    pub readings: usize,
}

/// Draws one floor plan from the map prior
/// ([`crate::scenes::floor_plans::sample_floor_plan`]), a square of
/// [`TrainingConfig::map_side`] metres at the configured resolution.
pub fn sample_map<R: Rng + ?Sized>(config: &TrainingConfig, rng: &mut R) -> Result<World> {
    config.validate()?;
    let mut world = sample_floor_plan(config.map_side(), config.resolution, rng)?;
    add_clutter(&mut world, config.density, rng)?;
    Ok(world)
}

/// Samples the training set of `config` (step 2 of the module's recipe).
pub fn sample_triplets(config: &TrainingConfig) -> Result<TrainingSet> {
    let mut sampler = Sampler::new(config)?;
    while !sampler.done() {
        sampler.next_map()?;
    }
    Ok(sampler.finish())
}

/// [`sample_triplets`] a map at a time, for a caller that spreads the work
/// over several calls ([`Trainer`]): the same triplets, in the same order.
#[derive(Debug, Clone)]
pub struct Sampler {
    config: TrainingConfig,
    rng: StdRng,
    sensor: BeamModel,
    shape: BeamShape,
    triplets: Vec<Triplet>,
    maps: usize,
    readings: usize,
    no_returns: usize,
    occupied_cells: usize,
    all_cells: usize,
}

impl Sampler {
    pub fn new(config: &TrainingConfig) -> Result<Self> {
        config.validate()?;
        Ok(Self {
            config: *config,
            rng: StdRng::seed_from_u64(config.seed),
            sensor: BeamModel::new(config.sensor)?,
            shape: BeamShape::cone(config.half_width, config.sub_rays)?,
            triplets: Vec::with_capacity(config.triplets),
            maps: 0,
            readings: 0,
            no_returns: 0,
            occupied_cells: 0,
            all_cells: 0,
        })
    }

    /// True once every triplet asked for is drawn.
    pub fn done(&self) -> bool {
        self.triplets.len() >= self.config.triplets
    }

    /// Triplets drawn so far.
    pub fn triplets(&self) -> usize {
        self.triplets.len()
    }

    /// Draws the triplets of one more sampled map (at most
    /// `TRIPLETS_PER_MAP`); returns how many.
    pub fn next_map(&mut self) -> Result<usize> {
        let config = &self.config;
        let rng = &mut self.rng;
        let (sensor, shape) = (&self.sensor, self.shape);
        let triplets = &mut self.triplets;
        let z_max = config.sensor.z_max;
        let field = FIELD * config.half_width;
        let (near_lo, near_hi) = (SPLINE_START - 0.15, SPLINE_END + BEHIND_BAND + 0.3);
        let before = triplets.len();
        let world = sample_map(config, rng)?;
        self.maps += 1;
        let maps = self.maps;
        self.occupied_cells += world.occupied().iter().filter(|&&o| o).count();
        self.all_cells += world.occupied().len();
        let g = *world.geometry();
        let res = g.resolution();
        let side = g.width() as f64 * res;
        // Occupancy of cell (ix, iy), or None outside the map.
        let cell = |ix: f64, iy: f64| -> Option<bool> {
            if ix < 0.0 || iy < 0.0 {
                return None;
            }
            let (ix, iy) = (ix as usize, iy as usize);
            (ix < g.width() && iy < g.height()).then(|| world.is_occupied(ix, iy))
        };
        let want = TRIPLETS_PER_MAP.min(config.triplets - triplets.len());
        let (mut got, mut tries) = (0, 0);
        while got < want && tries < 50 * want {
            tries += 1;
            // A pose where a robot fits, uniformly.
            let (x, y) = (rng.random::<f64>() * side, rng.random::<f64>() * side);
            if cell((x / res).floor(), (y / res).floor()) != Some(false) {
                continue;
            }
            let c = POSE_CLEARANCE;
            if !is_clear_around(&world, x, y, c) {
                continue;
            }
            // A beam direction, uniformly, as a unit vector: a point of the
            // unit disc, normalised (no trigonometry).
            let (a, b) = (rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
            let q: f64 = a * a + b * b;
            if !(q > 1e-4 && q <= 1.0) {
                continue;
            }
            let inv = 1.0 / q.sqrt();
            let dir = (a * inv, b * inv);
            let z_star = expected_range_along(&world, x, y, dir, shape, z_max);
            let z = sensor.sample(z_star, &mut *rng);
            let no_return = z >= z_max;
            self.readings += 1;
            self.no_returns += no_return as usize;
            // A no-return is one reading in twenty or so, yet it needs a
            // profile of its own over the whole range: it gets several
            // target cells, so that its few weights are not left to a few
            // hundred samples. (Only the mix of samples changes, not what
            // each one says: the regression still estimates p(m | r, psi, z).)
            let targets = if no_return { NO_RETURN_TARGETS } else { 1 };
            for _ in 0..targets {
                if got == want {
                    break;
                }
                // The target cell: three times in four near the reading
                // (where the model has most to learn: the band past the
                // reading is where occupied cells are rare and the fit
                // noisiest), else anywhere along the beam out to past the
                // spline; for a no-return, anywhere before z_max.
                let r = if no_return {
                    rng.random::<f64>() * z_max
                } else if rng.random::<f64>() < 0.75 {
                    (z + rng.random_range(near_lo..near_hi)).max(0.0)
                } else {
                    rng.random::<f64>() * (z + near_hi)
                };
                let (ps, pc) = rng.random_range(-field..field).sin_cos();
                let (ux, uy) = (dir.0 * pc - dir.1 * ps, dir.0 * ps + dir.1 * pc);
                let (ix, iy) = (((x + r * ux) / res).floor(), ((y + r * uy) / res).floor());
                // Outside the square is the empty space a ray that leaves
                // it returns nothing from.
                let occupied = cell(ix, iy).unwrap_or(false);
                // The features see the cell's centre, as a mapper does.
                let (dx, dy) = ((ix + 0.5) * res - x, (iy + 0.5) * res - y);
                let along = dir.0 * dx + dir.1 * dy;
                let across = dir.0 * dy - dir.1 * dx;
                triplets.push(Triplet {
                    r: dx.hypot(dy) as f32,
                    psi: across.atan2(along) as f32,
                    z: z as f32,
                    occupied,
                });
                got += 1;
            }
        }
        if maps > config.triplets + 100 {
            // Unreachable with the prior above (every map has rooms), but a
            // loop in the core must be bounded.
            return Err(invalid(
                "resolution",
                res,
                "maps with free space to stand in",
            ));
        }
        Ok(triplets.len() - before)
    }

    /// The training set drawn.
    pub fn finish(self) -> TrainingSet {
        TrainingSet {
            maps: self.maps,
            map_occupancy: self.occupied_cells as f64 / self.all_cells.max(1) as f64,
            no_returns: self.no_returns as f64 / self.readings.max(1) as f64,
            readings: self.readings,
            triplets: self.triplets,
        }
    }
}

/// What a fit reports besides the model.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FitReport {
    /// Fraction of occupied target cells.
    pub occupied_fraction: f64,
    /// SGD updates made.
    pub updates: usize,
}

/// Logistic regression by SGD (step 3 of the module's recipe). The bias
/// starts at the log odds of the occupied fraction, every other weight at 0.
pub fn fit(config: &TrainingConfig, set: &TrainingSet) -> Result<(LearnedInverse, FitReport)> {
    let mut fitter = Fitter::new(config, set)?;
    while !fitter.done() {
        fitter.step(usize::MAX);
    }
    fitter.finish()
}

/// [`fit`] a number of SGD updates at a time, for a caller that spreads
/// the work over several calls ([`Trainer`]): the same updates in the same
/// order, so the same weights bit for bit.
#[derive(Debug, Clone)]
pub struct Fitter {
    frame: FeatureFrame,
    rows: Vec<([f32; FEATURES], f64)>,
    occupied: f64,
    w: [f64; FEATURES],
    mean: [f64; FEATURES],
    rng: StdRng,
    order: Vec<u32>,
    learning_rate: f64,
    epochs: usize,
    /// The epoch under way, and the next position in its order.
    epoch: usize,
    at: usize,
    /// Updates made.
    t: usize,
}

impl Fitter {
    /// The bias starts at the log odds of the occupied fraction, every
    /// other weight at 0.
    pub fn new(config: &TrainingConfig, set: &TrainingSet) -> Result<Self> {
        config.validate()?;
        let n = set.triplets.len();
        if n == 0 {
            return Err(invalid("triplets", 0, "at least one triplet"));
        }
        let frame = config.frame();
        let rows: Vec<([f32; FEATURES], f64)> = set
            .triplets
            .iter()
            .map(|t| {
                let phi = frame.features(t.r as f64, t.psi as f64, t.z as f64);
                (phi.map(|p| p as f32), if t.occupied { 1.0 } else { 0.0 })
            })
            .collect();
        let occupied = rows.iter().map(|r| r.1).sum::<f64>() / n as f64;
        let mut w = [0.0f64; FEATURES];
        w[BIAS] = crate::grid::logit(occupied.clamp(1e-3, 1.0 - 1e-3));
        Ok(Self {
            frame,
            rows,
            occupied,
            w,
            mean: [0.0f64; FEATURES],
            rng: StdRng::seed_from_u64(config.seed ^ FIT_STREAM),
            order: (0..n as u32).collect(),
            learning_rate: config.learning_rate,
            epochs: config.epochs,
            epoch: 0,
            at: 0,
            t: 0,
        })
    }

    /// True once every epoch is done.
    pub fn done(&self) -> bool {
        self.epoch >= self.epochs
    }

    /// Makes up to `updates` SGD updates (fewer at the end); returns how
    /// many.
    pub fn step(&mut self, updates: usize) -> usize {
        let n = self.rows.len();
        let mut made = 0;
        while made < updates && !self.done() {
            if self.at == 0 {
                for i in (1..n).rev() {
                    self.order.swap(i, self.rng.random_range(0..=i));
                }
            }
            // Averaged SGD (Polyak and Juditsky, 1992): the weights handed
            // out are the mean of the iterates of the last epoch, which
            // irons out the jitter a single late step still leaves (the
            // bias is touched by every update, so without averaging `l0`
            // would wander by a tenth of a log odds with the order of the
            // last few updates).
            let last = self.epoch + 1 == self.epochs;
            let end = n.min(self.at.saturating_add(updates - made));
            for &k in &self.order[self.at..end] {
                let Some((phi, y)) = self.rows.get(k as usize) else {
                    continue;
                };
                let s: f64 = phi.iter().zip(&self.w).map(|(&p, &wi)| p as f64 * wi).sum();
                let g = sigmoid(s) - y;
                let eta = self.learning_rate / (1.0 + self.t as f64 / n as f64);
                for (wi, &p) in self.w.iter_mut().zip(phi) {
                    *wi -= eta * g * p as f64;
                }
                if last {
                    for (m, &wi) in self.mean.iter_mut().zip(&self.w) {
                        *m += wi;
                    }
                }
                self.t += 1;
            }
            made += end - self.at;
            self.at = end;
            if self.at == n {
                self.at = 0;
                self.epoch += 1;
            }
        }
        made
    }

    /// The model: the mean of the last epoch's weights.
    pub fn finish(self) -> Result<(LearnedInverse, FitReport)> {
        let n = self.rows.len() as f64;
        let mean = self.mean.map(|m| m / n);
        let model = LearnedInverse::new(self.frame, mean)?;
        Ok((
            model,
            FitReport {
                occupied_fraction: self.occupied,
                updates: self.t,
            },
        ))
    }
}

/// Sampling and fitting in calls of a bounded amount of work, for a page
/// that keeps its frames while it trains: a unit is a triplet drawn or an
/// SGD update, and each call goes past its budget by at most one map's
/// triplets. The model is [`train`]'s, bit for bit.
#[derive(Debug, Clone)]
pub struct Trainer {
    config: TrainingConfig,
    sampler: Option<Sampler>,
    fitter: Option<(Fitter, TrainingSet)>,
}

impl Trainer {
    pub fn new(config: &TrainingConfig) -> Result<Self> {
        Ok(Self {
            config: *config,
            sampler: Some(Sampler::new(config)?),
            fitter: None,
        })
    }

    /// True once the weights are fitted ([`Trainer::finish`] hands them
    /// out).
    pub fn done(&self) -> bool {
        self.fitter.as_ref().is_some_and(|(f, _)| f.done())
    }

    /// True while triplets are being drawn (then the weights are fitted).
    pub fn sampling(&self) -> bool {
        self.sampler.is_some()
    }

    /// Works for about `budget` units; returns the units done.
    pub fn step(&mut self, budget: usize) -> Result<usize> {
        let budget = budget.max(1);
        let mut done = 0;
        while done < budget && !self.done() {
            if let Some(sampler) = self.sampler.take_if(|s| s.done()) {
                let set = sampler.finish();
                self.fitter = Some((Fitter::new(&self.config, &set)?, set));
            } else if let Some(sampler) = &mut self.sampler {
                done += sampler.next_map()?.max(1);
            } else if let Some((fitter, _)) = &mut self.fitter {
                done += fitter.step(budget - done);
            } else {
                break;
            }
        }
        Ok(done)
    }

    /// The model, its training set and the fit's report, training what is
    /// left first.
    pub fn finish(mut self) -> Result<(LearnedInverse, TrainingSet, FitReport)> {
        while !self.done() {
            self.step(usize::MAX)?;
        }
        let (fitter, set) = self
            .fitter
            .ok_or_else(|| invalid("training", "unfinished", "a finished training"))?;
        let (model, report) = fitter.finish()?;
        Ok((model, set, report))
    }
}

/// Samples and fits in one go.
pub fn train(config: &TrainingConfig) -> Result<(LearnedInverse, TrainingSet, FitReport)> {
    let set = sample_triplets(config)?;
    let (model, report) = fit(config, &set)?;
    Ok((model, set, report))
}

/// What the chapter quotes about a trained model (`npm run numbers`,
/// the workbench's readout).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ModelSummary {
    /// The model's own prior, log odds.
    pub l0: f64,
    /// The short reading the free evidence is quoted for, metres.
    pub short_reading: f64,
    /// Mean evidence (log odds, net of `l0`) on the axis in front of the
    /// short reading.
    pub free_evidence_short: f64,
    /// The same along a max-range reading (a no-return).
    pub free_evidence_max_range: f64,
    /// Depth past a reading where the model's occupied band ends, metres
    /// ([`LearnedInverse::band_end`]): a real return reaches no further.
    pub band_end: f64,
}

/// Free space is averaged up to this far in front of a reading, metres:
/// what lies closer belongs to the ramp into the occupied band.
pub const FREE_MARGIN: f64 = 0.3;

/// The chapter's figures for a model: its `l0`, its mean free evidence
/// along the axis for a short reading (a quarter of `z_max`) and for a
/// max-range reading, and where its occupied band ends.
pub fn summarize(model: &LearnedInverse) -> Result<ModelSummary> {
    let z_max = model.frame().z_max;
    let short = 0.25 * z_max;
    Ok(ModelSummary {
        l0: model.own_l0(),
        short_reading: short,
        free_evidence_short: mean_free_evidence(model, short, FREE_MARGIN)?,
        free_evidence_max_range: mean_free_evidence(model, z_max, FREE_MARGIN)?,
        band_end: model.band_end(),
    })
}

/// A seed as JavaScript numbers carry it: a whole number from 0 to
/// 2^53 - 1 (every such number is exact in a double).
pub fn seed_from_number(value: f64) -> Result<u64> {
    const MAX: f64 = 9_007_199_254_740_991.0;
    if (0.0..=MAX).contains(&value) && value.fract() == 0.0 {
        Ok(value as u64)
    } else {
        Err(invalid(
            "seed",
            value,
            "a whole number from 0 to 9007199254740991",
        ))
    }
}

/// Mean cross-entropy (nats) of a model's scores on a set of triplets: what
/// SGD minimises.
pub fn cross_entropy(model: &LearnedInverse, set: &TrainingSet) -> f64 {
    let n = set.triplets.len().max(1) as f64;
    set.triplets
        .iter()
        .map(|t| {
            let s = model.score(t.r as f64, t.psi as f64, t.z as f64);
            log_loss(s, t.occupied)
        })
        .sum::<f64>()
        / n
}

/// `-ln p(y | s)` for score `s`, without overflow: `ln(1 + e^-s)` for an
/// occupied cell, `ln(1 + e^s)` for a free one.
fn log_loss(s: f64, occupied: bool) -> f64 {
    let m = if occupied { -s } else { s };
    if m > 0.0 {
        m + (-m).exp().ln_1p()
    } else {
        m.exp().ln_1p()
    }
}

#[inline]
fn sigmoid(s: f64) -> f64 {
    1.0 / (1.0 + (-s).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Training spread over calls of 37 units (a prime, so that calls end
    /// mid-map and mid-epoch) gives `train`'s model, set and report exactly,
    /// and no call goes past its budget by more than one map's triplets.
    #[test]
    fn a_training_in_small_calls_is_the_training_in_one_go() {
        let config = TrainingConfig {
            triplets: 2_000,
            epochs: 3,
            ..TrainingConfig::default()
        };
        let whole = train(&config).unwrap();
        let mut trainer = Trainer::new(&config).unwrap();
        let mut calls = 0;
        while !trainer.done() {
            let done = trainer.step(37).unwrap();
            assert!(done <= 37 + TRIPLETS_PER_MAP, "{done}");
            calls += 1;
        }
        assert!(
            calls > (2_000 * 4) / (37 + TRIPLETS_PER_MAP),
            "{calls} calls"
        );
        let sliced = trainer.finish().unwrap();
        assert_eq!(sliced.0.weights(), whole.0.weights());
        assert_eq!(sliced.1, whole.1);
        assert_eq!(sliced.2, whole.2);
    }

    #[test]
    fn training_work_is_capped_by_the_product_of_triplets_and_epochs() {
        let ok = TrainingConfig {
            triplets: 625_000,
            epochs: 8,
            ..TrainingConfig::default()
        };
        assert!(ok.validate().is_ok(), "exactly the cap is allowed");
        let big = TrainingConfig {
            triplets: 1_000_000,
            epochs: 200,
            ..TrainingConfig::default()
        };
        let e = big.validate().unwrap_err().to_string();
        assert!(
            e.contains("triplets x epochs") && e.contains("200000000"),
            "{e}"
        );
    }

    /// §9.3: the learned `l0` is the prior of the sampled maps, so a
    /// denser prior must give a larger one, and the chapter's dense prior
    /// (random boxes) one near -0.3 against the buildings' -1.9.
    #[test]
    fn the_learned_l0_follows_the_density_of_the_training_maps() {
        let mut l0s = Vec::new();
        for density in [0.0, 0.3, 0.45] {
            let config = TrainingConfig {
                density,
                ..TrainingConfig::default()
            };
            let set = sample_triplets(&config).unwrap();
            let (model, _) = fit(&config, &set).unwrap();
            eprintln!(
                "density {density}: occupancy {:.3} l0 {:.3}",
                set.map_occupancy,
                model.own_l0()
            );
            if density > 0.0 {
                assert!(
                    set.map_occupancy >= density,
                    "{density} {}",
                    set.map_occupancy
                );
            }
            l0s.push(model.own_l0());
        }
        assert!(l0s.windows(2).all(|w| w[0] < w[1]), "{l0s:?}");
        assert!(l0s[0] < -1.5, "buildings: {l0s:?}");
        assert!(
            (l0s[2] - -0.3).abs() < 0.35,
            "the chapter's dense prior: {l0s:?}"
        );
        for bad in [-0.1, 0.61, f64::NAN] {
            let c = TrainingConfig {
                density: bad,
                ..TrainingConfig::default()
            };
            assert!(c.validate().unwrap_err().to_string().contains("density"));
        }
    }
}
