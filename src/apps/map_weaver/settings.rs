//! What a Map Weaver run is built from, and the limits every knob keeps to.
//!
//! Each limit is stated once, here, and used three ways: the check that
//! refuses a value past it, the text of that refusal, and the widget's
//! attributes and sliders, which take it from [`WeaverLimits`] (published
//! by the core's `constants()`) and, for the choices that depend on the
//! scene, from the session's [`PaneChoices`].

use super::situation::Situation;
use crate::error::{self, invalid, OccError, Result};
use crate::geometry::GridGeometry;
use crate::grid::FilterSettings;
use crate::inverse::{HandCraftedParams, TrainingConfig};
use crate::scenes::apartment::ApartmentScene;
use std::fmt::Display;

/// At most this many laps per run: every scan is kept for rebuilding a
/// pane, and a run must not grow without bound in a forgotten tab.
pub const MAX_LAPS: usize = 20;
/// The most range readings a run may keep (laps x scans x beams): every
/// scan is kept for rebuilding a pane, 8 bytes a reading.
pub const MAX_READINGS: usize = 10_000_000;
/// The most work one request for scans before the first frame may ask for
/// (a link's `scans`): cell visits, counted as scans x 2 panes x beams x the
/// cells along a beam at the LiDAR's range ([`super::Weaver::work_per_scan`]).
/// 250 million is a few seconds of mapping at the chapter's 0.1 m, where all
/// 20 laps fit, and a few thousand scans at 0.0125 m; the widget does the
/// work in time slices, this bounds how long the reader waits for it.
pub const MAX_FAST_FORWARD_WORK: u64 = 250_000_000;
/// The most SGD updates (triplets x epochs) a run's training may ask for:
/// about 26 times the default 24,000 x 8, a couple of seconds of fitting as
/// wasm. The training's own bounds (a million triplets, 200 epochs) are
/// each fine alone, but together they would hold the widget for a minute.
pub const MAX_TRAINING_UPDATES: u64 = crate::inverse::training::MAX_UPDATES;
/// The resolutions a pane may map at besides the scene's own, metres per
/// cell (exercise 6).
pub const PANE_RESOLUTIONS: [f64; 2] = [0.10, 0.05];
/// The evidence strength: a factor on the model's log odds. At a quarter
/// a cell needs four times the scans to get as sure; at three, exercise
/// 5's setting, a wall cell reaches a clamp of 12 in five returns (Table
/// 9.2's laser `l_occ` 0.85 x 3 = 2.55 each).
pub const STRENGTH: Steps = Steps {
    min: 0.25,
    max: 3.0,
    step: 0.25,
};
/// The clamp `l_max`, log odds: at 1 a cell never passes p = 0.73; from
/// 16 it may reach p = 1 - 1.1e-7, certain as far as the readouts show.
/// The range reaches 80 for exercise 5 at the chapter's strength 3: a
/// ghost then fades in `l_max / |l_free|` = `l_max / 1.2` scans, five
/// seconds of the ghost watch's twelve scans a second at 72 (at 16, every
/// fade was over in 1.1 s). A ghost reaches the clamp before the person
/// leaves (8 s, 96 scans of `l_occ` 0.85 x strength) at every clamp from
/// strength 1 up; below, only the smaller clamps are reached.
pub const CLAMP: Steps = Steps {
    min: 1.0,
    max: 80.0,
    step: 0.5,
};
/// The cone's opening angle `beta` of Table 9.2, degrees: from a LiDAR's
/// thin beam to a wide sonar cone.
pub const CONE_BETA_DEG: Steps = Steps {
    min: 1.0,
    max: 30.0,
    step: 1.0,
};

/// A knob's range as its slider offers it: `min`, `min + step`, ... `max`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Steps {
    pub min: f64,
    pub max: f64,
    pub step: f64,
}

impl Steps {
    /// True for a value on one of the steps (to a millionth of a step,
    /// as the widget's attributes read them); false for NaN.
    pub fn admits(&self, v: f64) -> bool {
        let k = (v - self.min) / self.step;
        v >= self.min && v <= self.max && (k - k.round()).abs() < 1e-6
    }

    /// `v` for `field`, or an error naming both and saying the range:
    /// "{what} from {min} to {max} in steps of {step}".
    pub fn check(&self, field: &str, v: f64, what: &str) -> Result<f64> {
        if self.admits(v) {
            return Ok(v);
        }
        Err(invalid(
            field,
            error::show(v),
            format!(
                "{what} from {} to {} in steps of {}",
                error::show(self.min),
                error::show(self.max),
                error::show(self.step)
            ),
        ))
    }
}

/// Which inverse sensor model a pane maps with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// Table 9.2.
    HandCrafted,
    /// The model learned from simulated data (§9.3).
    Learned,
}

/// Where a pane takes the robot's pose from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PoseSource {
    /// The true pose: what mapping with known poses assumes.
    Oracle,
    /// The start pose plus the noisy odometry increments.
    DeadReckoning,
}

/// How a pane applies Table 9.1 to a scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MapperKind {
    /// Each beam's raster only ([`crate::mapping::traversal::RayMapper`]):
    /// the production path.
    Traversal,
    /// Every cell of the map against its nearest beam
    /// ([`crate::mapping::sweep::sweep_scan`]), as Table 9.1 is printed.
    Sweep,
}

/// The sensor a pane reads each range as: the opening angle `beta` of
/// Table 9.2. The readings are the simulated LiDAR's either way; a cone
/// pane interprets each one as a sonar would (evidence over the whole
/// cone), which is what makes the two mappers part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SensorKind {
    /// Thin beams: Table 9.2's `beta` as the hand-crafted parameters set
    /// it (one degree).
    Lidar,
    /// A cone of opening [`PaneSettings::beta_deg`].
    Cone,
}

/// One pane's knobs.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, rename_all = "camelCase")]
pub struct PaneSettings {
    pub model: ModelKind,
    pub pose: PoseSource,
    /// Saturation `|l| <= clamp`, log odds ([`CLAMP`]).
    pub clamp: f64,
    /// Factor on the model's evidence, 1 = as designed or learned
    /// ([`STRENGTH`]).
    pub strength: f64,
    pub mapper: MapperKind,
    pub sensor: SensorKind,
    /// The cone's opening angle `beta`, degrees ([`CONE_BETA_DEG`]); used
    /// by the hand-crafted model when `sensor` is the cone (the learned
    /// model has the width it learned).
    pub beta_deg: f64,
    /// Beams of each scan the pane uses, evenly spaced: a divisor of the
    /// LiDAR's beam count. `None`: every beam.
    pub beams: Option<usize>,
    /// Metres per cell: one of [`PANE_RESOLUTIONS`]. `None`: the scene's
    /// own.
    pub resolution: Option<f64>,
    /// The mistake of exercise 8: the learned model's scores are added
    /// without removing its `l0` (the hand-crafted model's `l0` is 0, so
    /// there it changes nothing).
    pub forget_l0: bool,
}

impl Default for PaneSettings {
    fn default() -> Self {
        Self {
            model: ModelKind::HandCrafted,
            pose: PoseSource::Oracle,
            clamp: FilterSettings::default().clamp,
            strength: 1.0,
            mapper: MapperKind::Traversal,
            sensor: SensorKind::Lidar,
            beta_deg: 22.0,
            beams: None,
            resolution: None,
            forget_l0: false,
        }
    }
}

impl PaneSettings {
    /// Checks pane `k`'s knobs against the limits and the scene's LiDAR,
    /// naming the first one that is wrong as `panes[k].field`.
    pub fn validate(&self, k: usize, scene: &ApartmentScene) -> Result<()> {
        check_clamp(k, self.clamp)?;
        check_strength(k, self.strength)?;
        CONE_BETA_DEG.check(
            &format!("panes[{k}].betaDeg"),
            self.beta_deg,
            "an opening angle in degrees",
        )?;
        if let Some(r) = self.resolution.filter(|r| !PANE_RESOLUTIONS.contains(r)) {
            return Err(invalid(
                &format!("panes[{k}].resolution"),
                error::show(r),
                format!("{} metres per cell", or_list(PANE_RESOLUTIONS)),
            ));
        }
        let lidar_beams = scene.lidar.beams;
        if let Some(b) = self.beams {
            if b == 0 || b > lidar_beams || !lidar_beams.is_multiple_of(b) {
                return Err(invalid(
                    &format!("panes[{k}].beams"),
                    b,
                    format!(
                        "a divisor of the LiDAR's beam count ({lidar_beams}: {})",
                        or_list(beam_divisors(lidar_beams))
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Everything a Map Weaver run is built from. Defaults: the chapter's
/// apartment, seed 1, the person walking, both panes on the oracle with
/// the hand-crafted model on the left and the learned one on the right.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, rename_all = "camelCase")]
pub struct WeaverSettings {
    pub seed: u64,
    /// The chapter's lap, or the ghost watch of exercise 5 (its own robot
    /// path and person walk over the scene's).
    pub situation: Situation,
    pub person: bool,
    pub panes: [PaneSettings; 2],
    /// Table 9.2 at strength 1. The default is a thin LiDAR beam whose
    /// obstacle band `alpha` is one cell (0.10 m): a wider band paints the
    /// free cell in front of every wall occupied too.
    pub hand_crafted: HandCraftedParams,
    /// How the learned model is trained (once per run, when a pane first
    /// needs it; the default matches this LiDAR).
    pub training: TrainingConfig,
    /// The run stops after this many laps.
    pub laps: usize,
    pub scene: ApartmentScene,
}

impl Default for WeaverSettings {
    fn default() -> Self {
        Self {
            seed: 1,
            situation: Situation::Lap,
            person: true,
            // The learned model on the right, so the two models meet the
            // same scans side by side.
            panes: [
                PaneSettings::default(),
                PaneSettings {
                    model: ModelKind::Learned,
                    ..PaneSettings::default()
                },
            ],
            hand_crafted: HandCraftedParams::laser(8.0),
            training: TrainingConfig::default(),
            laps: 3,
            scene: ApartmentScene::default(),
        }
    }
}

/// A run's settings, checked: made only by [`WeaverSettings::check`], so
/// that every way to a run (at once, or in bounded calls) checks its
/// settings exactly once, before any training.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedWeaverSettings {
    settings: WeaverSettings,
    geometry: GridGeometry,
}

impl CheckedWeaverSettings {
    /// The settings, the situation applied to the scene.
    pub fn settings(&self) -> &WeaverSettings {
        &self.settings
    }
    /// The scene's grid limits.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }
    pub(super) fn into_parts(self) -> (WeaverSettings, GridGeometry) {
        (self.settings, self.geometry)
    }
    /// A run's own settings, to start it again: they were checked when the
    /// run was made, and every change since was checked as it was made (a
    /// pane's knobs by [`PaneSettings::validate`], the person a bool).
    pub(super) fn of_run(settings: WeaverSettings, geometry: GridGeometry) -> Self {
        Self { settings, geometry }
    }
}

impl WeaverSettings {
    /// The settings as a run uses them (the situation's robot path and
    /// person over the scene's), every knob checked, the refusal naming the
    /// first one that is wrong.
    pub fn check(mut self) -> Result<CheckedWeaverSettings> {
        self.scene = self.situation.apply(&self.scene);
        self.validate()?;
        let geometry = self.scene.geometry()?;
        self.scene.tracked_cells()?;
        Ok(CheckedWeaverSettings {
            settings: self,
            geometry,
        })
    }

    /// Checks every knob, naming the first one that is wrong (the check
    /// [`WeaverSettings::check`] makes).
    pub fn validate(&self) -> Result<()> {
        if self.laps == 0 || self.laps > MAX_LAPS {
            return Err(invalid("laps", self.laps, format!("1 to {MAX_LAPS} laps")));
        }
        self.hand_crafted.validate()?;
        // The scene first: the panes' beam counts are checked against its
        // LiDAR.
        self.scene.validate()?;
        for (k, p) in self.panes.iter().enumerate() {
            p.validate(k, &self.scene)?;
        }
        // Checked before the training's own rules so that the message
        // names the fields as this settings object spells them.
        let updates = self.training.triplets as u64 * self.training.epochs as u64;
        if updates > MAX_TRAINING_UPDATES {
            return Err(invalid(
                "training.triplets x training.epochs",
                format!(
                    "{} x {} = {updates}",
                    self.training.triplets, self.training.epochs
                ),
                format!("at most {MAX_TRAINING_UPDATES} updates: fewer triplets or epochs"),
            ));
        }
        self.training.validate()?;
        let readings = self
            .laps
            .saturating_mul(self.scene.scans_per_lap())
            .saturating_mul(self.scene.lidar.beams);
        if readings > MAX_READINGS {
            return Err(invalid(
                "laps",
                self.laps,
                format!(
                    "few enough laps that laps x scans per lap x beams stays within {MAX_READINGS} readings"
                ),
            ));
        }
        Ok(())
    }
}

/// Pane `k`'s clamp: on [`CLAMP`]'s steps, and one the pane's grid (prior
/// 0.5) accepts, named as the pane's own field.
pub(super) fn check_clamp(k: usize, clamp: f64) -> Result<()> {
    let field = format!("panes[{k}].clamp");
    CLAMP.check(&field, clamp, "a clamp in log odds")?;
    FilterSettings { prior: 0.5, clamp }
        .validate()
        .map_err(|e| renamed(&field, e))
}

/// Pane `k`'s evidence strength: on [`STRENGTH`]'s steps.
pub(super) fn check_strength(k: usize, strength: f64) -> Result<()> {
    STRENGTH
        .check(&format!("panes[{k}].strength"), strength, "a factor")
        .map(drop)
}

/// An error about a parameter, renamed to `field` as the settings spell it.
pub(super) fn renamed(field: &str, e: OccError) -> OccError {
    match e {
        OccError::InvalidParameter {
            value, expected, ..
        } => OccError::InvalidParameter {
            field: field.to_string(),
            value,
            expected,
        },
        other => other,
    }
}

/// The beam counts a pane of a `lidar_beams`-beam LiDAR may use: the
/// divisors, so that every thinned scan keeps its beams evenly spaced.
pub fn beam_divisors(lidar_beams: usize) -> Vec<usize> {
    (1..=lidar_beams)
        .filter(|b| lidar_beams.is_multiple_of(*b))
        .collect()
}

/// "a, b or c".
fn or_list<T: Display>(items: impl IntoIterator<Item = T>) -> String {
    let items: Vec<String> = items.into_iter().map(|t| t.to_string()).collect();
    match items.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

/// One choice a pane's menu offers: the value the pane then uses, and the
/// setting that asks for it (`None`: the scene's own).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Choice<T> {
    pub setting: Option<T>,
    pub value: T,
}

/// The beam counts and resolutions a pane of this run may use, as its
/// menus offer them (largest first, the scene's own as `None`): the same
/// values [`PaneSettings::validate`] accepts.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PaneChoices {
    pub beams: Vec<Choice<usize>>,
    pub resolutions: Vec<Choice<f64>>,
}

impl PaneChoices {
    pub fn for_scene(scene: &ApartmentScene) -> Self {
        let all = scene.lidar.beams;
        let beams = beam_divisors(all)
            .into_iter()
            .rev()
            .map(|b| Choice {
                setting: (b != all).then_some(b),
                value: b,
            })
            .collect();
        let own = scene.resolution;
        let mut resolutions: Vec<Choice<f64>> = PANE_RESOLUTIONS
            .iter()
            .filter(|&&r| r != own)
            .map(|&r| Choice {
                setting: Some(r),
                value: r,
            })
            .collect();
        resolutions.push(Choice {
            setting: None,
            value: own,
        });
        crate::geometry::order::sort_stable_by_key(&mut resolutions, |choice| -choice.value);
        Self { beams, resolutions }
    }
}

/// The limits of Map Weaver's knobs and the default panes, for the
/// widget's attributes and sliders (`constants().mapWeaver`). What depends
/// on the scene (beam counts, the scene's own resolution) is the session's
/// ([`PaneChoices`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WeaverLimits {
    pub max_laps: usize,
    pub strength: Steps,
    pub clamp: Steps,
    pub beta_deg: Steps,
    pub pane_resolutions: [f64; 2],
    /// The most beams a scene's LiDAR may have (a pane's `beams` is at most
    /// this).
    pub max_lidar_beams: usize,
    pub max_fast_forward_work: u64,
    /// The colours of the per-cell Brier difference image, for its legend.
    pub brier_colours: super::brier_map::BrierColours,
    /// The chapter's run: the attributes' defaults.
    pub defaults: WeaverDefaults,
}

/// The knobs of the chapter's run that the widget's attributes set
/// ([`WeaverSettings::default`]; the scene and the training are the
/// `scene` attribute's and the core's own).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WeaverDefaults {
    pub seed: u64,
    pub laps: usize,
    pub person: bool,
    pub panes: [PaneSettings; 2],
}

impl WeaverLimits {
    pub fn chapter() -> Self {
        Self {
            max_laps: MAX_LAPS,
            strength: STRENGTH,
            clamp: CLAMP,
            beta_deg: CONE_BETA_DEG,
            pane_resolutions: PANE_RESOLUTIONS,
            max_lidar_beams: crate::sensors::lidar::MAX_BEAMS,
            max_fast_forward_work: MAX_FAST_FORWARD_WORK,
            brier_colours: super::brier_map::BrierColours::SHOWN,
            defaults: {
                let d = WeaverSettings::default();
                WeaverDefaults {
                    seed: d.seed,
                    laps: d.laps,
                    person: d.person,
                    panes: d.panes,
                }
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_admit_exactly_their_values() {
        assert!(STRENGTH.admits(0.25) && STRENGTH.admits(1.75) && STRENGTH.admits(3.0));
        for v in [0.0, 0.2, 1.1, 3.25, f64::NAN, f64::INFINITY] {
            assert!(!STRENGTH.admits(v), "{v}");
        }
        let e = STRENGTH
            .check("s", 1.1, "a factor")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "invalid s: 1.1 (expected a factor from 0.25 to 3 in steps of 0.25)"
        );
    }

    #[test]
    fn beam_divisors_and_the_lists_in_messages() {
        assert_eq!(
            beam_divisors(60),
            [1, 2, 3, 4, 5, 6, 10, 12, 15, 20, 30, 60]
        );
        assert_eq!(beam_divisors(1), [1]);
        assert_eq!(or_list([0.1, 0.05]), "0.1 or 0.05");
        assert_eq!(or_list([1, 2, 4]), "1, 2 or 4");
    }

    /// The menus' choices for the chapter's scene and for one with a
    /// 48-beam LiDAR at 0.0125 m: the scene's own is `None`, and every
    /// setting offered is one the pane accepts.
    #[test]
    fn the_choices_follow_the_scene_and_are_all_accepted() {
        let chapter = PaneChoices::for_scene(&ApartmentScene::default());
        let values = |c: &PaneChoices| -> (Vec<usize>, Vec<f64>) {
            (
                c.beams.iter().map(|c| c.value).collect(),
                c.resolutions.iter().map(|c| c.value).collect(),
            )
        };
        assert_eq!(
            values(&chapter),
            (
                vec![60, 30, 20, 15, 12, 10, 6, 5, 4, 3, 2, 1],
                vec![0.1, 0.05]
            )
        );
        assert_eq!(chapter.beams[0].setting, None);
        assert_eq!(chapter.resolutions[0].setting, None);

        let mut scene = ApartmentScene::default();
        scene.lidar.beams = 48;
        scene.resolution = 0.0125;
        scene.width = 960;
        scene.height = 720;
        let other = PaneChoices::for_scene(&scene);
        assert_eq!(
            values(&other),
            (
                vec![48, 24, 16, 12, 8, 6, 4, 3, 2, 1],
                vec![0.1, 0.05, 0.0125]
            )
        );
        assert_eq!(other.resolutions[2].setting, None);
        for b in &other.beams {
            for r in &other.resolutions {
                let p = PaneSettings {
                    beams: b.setting,
                    resolution: r.setting,
                    ..PaneSettings::default()
                };
                p.validate(0, &scene).unwrap();
            }
        }
    }
}
