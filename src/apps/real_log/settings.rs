//! What the reader of a real log chooses for its map ([`LogMapSettings`]),
//! checked once into [`CheckedSettings`] (which carries the one Table 9.2
//! model built from them), and the limits a page's controls keep to
//! ([`SettingLimits`]).

use crate::error::{self, invalid, OccError, Result};
use crate::grid::{FilterSettings, HitCounting, HitMissOdds};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::mapping::insertion::ScanInsertion;
use crate::mapping::traversal::MAX_REACH_CELLS;
use crate::mapping::walls::WallModel;
use crate::poses::PoseSourceKind;

/// What a cell of a real log's map believes (docs/ARCHITECTURE.md, "Real
/// logs"): the chapter's filter, or one of the models the tools of the
/// field use on real buildings ([`crate::grid::cell`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum LogCellModel {
    /// Table 9.1's log-odds filter with Table 9.2's evidence and the
    /// settings' clamp: the chapter's lesson (one return prints a wall,
    /// four beams clear a cell).
    #[serde(rename = "log-odds")]
    LogOdds,
    /// GMapping's counting model: hits and visits per cell, occupied above
    /// a hit ratio, free once visited with a lower one. The real-log
    /// default: on every log of the corpus its walls are as complete as
    /// Table 9.2's or more, with fewer specks on five of six, and one beam
    /// through a cell clears it (docs/ARCHITECTURE.md, "Real logs").
    #[default]
    #[serde(rename = "hit-counting")]
    HitCounting,
    /// Cartographer's probability grid: a hit multiplies the odds by
    /// odds(0.55), a miss by odds(0.49), within [0.1, 0.9].
    #[serde(rename = "hit-miss-odds")]
    HitMissOdds,
}

impl LogCellModel {
    /// The names a page and the CLI use.
    pub const NAMES: [&'static str; 3] = ["log-odds", "hit-counting", "hit-miss-odds"];
    /// Every model, in the order of [`Self::NAMES`].
    pub const ALL: [LogCellModel; 3] = [Self::LogOdds, Self::HitCounting, Self::HitMissOdds];

    /// The name a page uses (one of [`Self::NAMES`]).
    pub fn name(self) -> &'static str {
        match self {
            Self::LogOdds => Self::NAMES[0],
            Self::HitCounting => Self::NAMES[1],
            Self::HitMissOdds => Self::NAMES[2],
        }
    }

    /// The model named `name` (one of [`Self::NAMES`]), or an error naming
    /// `field` and the text.
    pub fn from_name(field: &str, name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                invalid(
                    field,
                    format!("\"{name}\""),
                    "log-odds, hit-counting or hit-miss-odds",
                )
            })
    }

    /// How a caption names the model.
    pub fn caption(self) -> &'static str {
        match self {
            Self::LogOdds => "log odds (Table 9.2)",
            Self::HitCounting => "hit counting (GMapping)",
            Self::HitMissOdds => "hit/miss odds (Cartographer)",
        }
    }

    /// GMapping's counting model at the hit ratio chosen for real logs.
    pub fn hit_counting() -> HitCounting {
        HitCounting {
            occupied_ratio: HIT_RATIO,
        }
    }

    /// Where an export draws this model's cells, when not at the export's
    /// own thresholds ([`crate::grid::CellModel::trinary_cut`]).
    pub fn trinary_cut(self) -> Option<(f64, f64)> {
        match self {
            Self::HitMissOdds => Some(HitMissOdds::TRINARY_CUT),
            Self::LogOdds | Self::HitCounting => None,
        }
    }

    /// Cartographer's 2-D probability grid defaults.
    pub fn hit_miss_odds() -> HitMissOdds {
        HitMissOdds::cartographer()
    }
}

/// The hit ratio above which a counting cell is occupied (GMapping's
/// `occupancyThreshold`, 0.25). A lower ratio (0.15) completes walls a
/// little more (wall recall +0.3 to +1.6 points on the corpus) but keeps a
/// person who stood still for `n` scans on the map for `5.7 n` scans of
/// beams through the empty place instead of `3 n`.
pub const HIT_RATIO: f32 = 0.25;

/// What the reader of a log chooses for its map: the grid's resolution,
/// the inverse model of Table 9.2, how far a no-return clears, how free
/// evidence ends near a wall ([`WallModel`]), the filter's clamp and where
/// the scans are put ([`PoseSourceKind`], with the seed of its noise). The
/// defaults keep walls and the outside of a building gray
/// ([`crate::mapping::walls`]); [`Self::chapter`] is Table 9.2 with the
/// chapter's clamp, exactly workload W1 (BENCHMARKS.md).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, rename_all = "camelCase", deny_unknown_fields)]
pub struct LogMapSettings {
    /// Metres per cell.
    pub resolution: f64,
    /// The model's `z_max`, metres: readings at or beyond it are
    /// no-returns (they carve free space out to it and mark nothing), and
    /// only endpoints closer than it decide the grid's extent.
    pub range_cap: f64,
    /// Obstacle thickness `alpha`, metres.
    pub alpha: f64,
    /// Evidence at the reading, log odds.
    pub l_occ: f64,
    /// Evidence in front of the reading, log odds.
    pub l_free: f64,
    /// Saturation `|l| <= clamp`, log odds.
    pub clamp: f64,
    /// Free border around the log's extent, metres.
    pub margin: f64,
    /// How far a no-return (a reading at or beyond `rangeCap`) clears free
    /// space, metres (at most `rangeCap`).
    pub no_return_reach: f64,
    /// How a beam's free evidence ends before its reading.
    pub walls: WallModel,
    /// The poses the scans are mapped at.
    pub poses: PoseSourceKind,
    /// The seed of dead reckoning's noise (one seed, one path, and one
    /// scan-matched path from it; unused for the corrected poses).
    pub seed: u64,
    /// What a cell believes ([`LogCellModel`]).
    pub model: LogCellModel,
    /// A second map of the same scans at the same poses with another cell
    /// model, shown beside the first (`None`: no comparison).
    pub compare_model: Option<LogCellModel>,
    /// Free space between neighbouring beams: each beam as wide as the
    /// beam spacing (Table 9.2's `β`), so that floor seen between two
    /// beams' axes is not left gray in one-cell pinholes
    /// ([`crate::mapping::traversal::RayMapper::integrate_bands_between`]).
    pub between_beams: bool,
}

/// The default no-return reach, metres (Cartographer's
/// `missing_data_ray_length` default).
pub const NO_RETURN_REACH: f64 = 5.0;

/// The largest seed: the largest whole number a JavaScript number holds
/// exactly.
pub const MAX_SEED: u64 = (1 << 53) - 1;

impl Default for LogMapSettings {
    fn default() -> Self {
        let laser = HandCraftedParams::laser(30.0);
        Self {
            resolution: 0.05,
            range_cap: laser.z_max,
            alpha: laser.alpha,
            l_occ: laser.l_occ,
            l_free: laser.l_free,
            clamp: 3.5,
            margin: 1.0,
            no_return_reach: NO_RETURN_REACH,
            walls: WallModel::Incidence,
            poses: PoseSourceKind::Corrected,
            seed: 1,
            model: LogCellModel::default(),
            compare_model: None,
            between_beams: true,
        }
    }
}

/// The bounds a page's controls keep to at one resolution: what the core
/// accepts, so that a slider never offers a value it would refuse.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SettingLimits {
    /// Metres per cell these limits are for.
    pub resolution: f64,
    /// The longest range cap, metres: a scan is gathered in a window as
    /// wide as its longest beam, at most [`MAX_REACH_CELLS`] cells of the
    /// resolution (102.25 m at 5 cm, 51.125 m at 2.5 cm).
    pub range_cap_max: f64,
    /// Cells of the resolution a beam may reach.
    pub reach_cells: f64,
    /// The largest seed ([`MAX_SEED`]).
    pub seed_max: u64,
}

impl SettingLimits {
    /// The limits at `resolution` metres per cell (a positive number).
    pub fn at(resolution: f64) -> Result<Self> {
        let resolution = error::positive("resolution", resolution)?;
        Ok(Self {
            resolution,
            range_cap_max: MAX_REACH_CELLS * resolution,
            reach_cells: MAX_REACH_CELLS,
            seed_max: MAX_SEED,
        })
    }
}

impl LogMapSettings {
    /// The field names as a page spells them (the serde names).
    pub const FIELDS: [&'static str; 14] = [
        "resolution",
        "rangeCap",
        "alpha",
        "lOcc",
        "lFree",
        "clamp",
        "margin",
        "noReturnReach",
        "walls",
        "poses",
        "seed",
        "model",
        "compareModel",
        "betweenBeams",
    ];

    /// Table 9.2 with the chapter's clamp, no-returns carving out to
    /// `z_max`: workload W1's map, and the lesson of walls that wear away.
    pub fn chapter() -> Self {
        Self {
            no_return_reach: 30.0,
            walls: WallModel::Table92,
            model: LogCellModel::LogOdds,
            between_beams: false,
            ..Self::default()
        }
    }

    /// The maps a session shows under these settings, the one the reader
    /// operates first: one per pose source ([`PoseSourceKind::panes`]) with
    /// [`Self::model`], then the first pose source's map again with
    /// [`Self::compare_model`] when one is chosen.
    pub fn pane_plan(&self) -> Vec<(PoseSourceKind, LogCellModel)> {
        let mut plan: Vec<_> = PoseSourceKind::panes(self.poses)
            .into_iter()
            .map(|source| (source, self.model))
            .collect();
        if let Some(other) = self.compare_model {
            plan.push((self.poses, other));
        }
        plan
    }

    /// How these settings put one scan into a map.
    pub fn scan_insertion(&self) -> ScanInsertion {
        ScanInsertion {
            model: self.model_params(),
            no_return_reach: self.no_return_reach,
            walls: self.walls,
            between_beams: self.between_beams,
        }
    }

    fn model_params(&self) -> HandCraftedParams {
        HandCraftedParams {
            alpha: self.alpha,
            l_occ: self.l_occ,
            l_free: self.l_free,
            ..HandCraftedParams::laser(self.range_cap)
        }
    }

    fn filter(&self) -> FilterSettings {
        FilterSettings {
            prior: 0.5,
            clamp: self.clamp,
        }
    }

    /// Checks every field, naming the first bad one as a page spells it
    /// (the serde names), and builds the Table 9.2 model they describe:
    /// the one check and the one model of a configuration. (The range
    /// cap's reach in cells is checked with the grid, once the log's extent
    /// is known: a grid too large is the first thing to say.)
    pub fn validate(&self) -> Result<CheckedSettings> {
        error::positive("resolution", self.resolution)?;
        error::positive("rangeCap", self.range_cap)?;
        error::positive("alpha", self.alpha)?;
        error::finite("lOcc", self.l_occ)?;
        error::finite("lFree", self.l_free)?;
        error::non_negative("margin", self.margin)?;
        error::positive("noReturnReach", self.no_return_reach)?;
        // A page sends the seed as a JavaScript number: past 2^53 two seeds
        // would be the same number there.
        if self.seed > MAX_SEED {
            return Err(invalid(
                "seed",
                self.seed,
                "a whole number from 0 to 9007199254740991 (2^53 - 1)",
            ));
        }
        // Free evidence lowers a cell and occupied evidence raises it: the
        // traversal gathers them as two flags.
        // (Compared as the f32 the map stores: 1e-50 is 0 there.)
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !((self.l_occ as f32) > 0.0) {
            return Err(invalid(
                "lOcc",
                error::show(self.l_occ),
                "log odds above 0 (at least 1e-38)",
            ));
        }
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !((self.l_free as f32) < 0.0) {
            return Err(invalid(
                "lFree",
                error::show(self.l_free),
                "log odds below 0 (at most -1e-38)",
            ));
        }
        if self.compare_model == Some(self.model) {
            return Err(invalid(
                "compareModel",
                format!("\"{}\"", self.model.name()),
                "another cell model than `model`, or none",
            ));
        }
        // The model checks what is left of it (evidence past f32) under its
        // own names: report them as the page spells them.
        let model = HandCrafted::new(self.model_params()).map_err(Self::page_names)?;
        // What is left to check (the clamp) is named alike by the filter.
        self.filter().validate()?;
        Ok(CheckedSettings {
            settings: *self,
            model,
        })
    }

    /// A Table 9.2 model error under the name the page used for the field.
    fn page_names(e: OccError) -> OccError {
        match e {
            OccError::InvalidParameter {
                field,
                value,
                expected,
            } => {
                let field = match field.as_str() {
                    "z_max" => "rangeCap".to_string(),
                    "l_occ" => "lOcc".to_string(),
                    "l_free" => "lFree".to_string(),
                    _ => field,
                };
                OccError::InvalidParameter {
                    field,
                    value,
                    expected,
                }
            }
            other => other,
        }
    }

    /// Refuses a range cap whose beams would reach past the traversal's
    /// window at this resolution ([`SettingLimits::range_cap_max`]).
    pub(crate) fn check_reach(&self) -> Result<()> {
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN fails every comparison: refused
        if !(self.range_cap / self.resolution <= MAX_REACH_CELLS) {
            return Err(invalid(
                "rangeCap",
                error::show(self.range_cap),
                "at most 2045 cells of the resolution (102 m at 5 cm, 51 m at 2.5 cm)",
            ));
        }
        Ok(())
    }
}

/// Settings that passed [`LogMapSettings::validate`], with the Table 9.2
/// model built from them: what a pane is configured with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckedSettings {
    settings: LogMapSettings,
    model: HandCrafted,
}

impl CheckedSettings {
    pub fn settings(&self) -> &LogMapSettings {
        &self.settings
    }

    /// The inverse model of Table 9.2 at the settings' `z_max`.
    pub fn model(&self) -> &HandCrafted {
        &self.model
    }

    /// The log-odds filter: prior 0.5, the settings' clamp.
    pub fn filter(&self) -> FilterSettings {
        self.settings.filter()
    }

    /// The model for a laser whose own maximum range `laser_max` is shorter
    /// than the range cap: its no-returns come at that maximum and must be
    /// treated as no-returns, not as walls there. `None` when the laser
    /// reaches the cap (the settings' model serves).
    pub fn model_for_laser(&self, laser_max: f64) -> Option<HandCrafted> {
        (laser_max < self.settings.range_cap)
            .then(|| {
                HandCrafted::new(HandCraftedParams {
                    z_max: laser_max,
                    ..self.settings.model_params()
                })
                .ok()
            })
            .flatten()
    }
}

impl Default for CheckedSettings {
    fn default() -> Self {
        LogMapSettings::default()
            .validate()
            .expect("the default settings are valid")
    }
}
