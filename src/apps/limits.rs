//! The one table of what the widgets' controls offer: every slider's range
//! and step, every menu's names and the words it shows, read by every
//! widget through the core's `constants()` (its `limits`), so that no page
//! restates a number or a name the core knows.
//!
//! Where the core refuses a value, the table's end is that limit, taken
//! from the constant or the setting the core checks against (a scene's
//! `z_max`, the most readings a scene may have, the traversal's reach).
//! Where the core takes a wider range (any open probability, any positive
//! clamp), the table's range is the one the page offers, written here
//! once; the tests check that the core accepts every end of it.

use super::inverse_workbench::WorkbenchLimits;
use super::map_weaver::Steps;
use super::real_log::{LogCellModel, LogMapSettings, SettingLimits, MAX_SEED};
use super::two_cell_table::TwoCellLimits;
use crate::mapping::walls::WallModel;
use crate::poses::PoseSourceKind;

/// A probability of an inverse model, as the cell filter offers it: in
/// hundredths, short of 0 and 1 (which the core refuses: eq. 9.5's log
/// odds are infinite there).
const INVERSE_PROBABILITY: Steps = Steps {
    min: 0.01,
    max: 0.99,
    step: 0.01,
};

/// A prior occupancy p(m), as the cell filter and the two-cell table offer
/// it: in twentieths, short of 0 and 1 (which the core refuses).
const PRIOR: Steps = Steps {
    min: 0.05,
    max: 0.95,
    step: 0.05,
};

/// The cell filter's clamp l_max, log odds: from about 1 (a cell that a
/// reading or two can always move) to well past the 15.25 of the chapter's
/// first exercise. The slider's notch past `max` is "off" (no clamp,
/// which the core takes as infinity).
const CELL_FILTER_CLAMP: Steps = Steps {
    min: 1.0,
    max: 30.0,
    step: 0.5,
};

/// The shortest reading and cell range the two-cell table offers, metres:
/// a cell nearer the sonar than this fills the whole cone.
const TWO_CELL_MIN_RANGE: f64 = 0.1;
/// The two-cell table's reading slider's step, metres.
const TWO_CELL_READING_STEP: f64 = 0.01;

/// The shortest reading the inverse workbench offers, metres: nearer, the
/// obstacle band of either model covers the sensor's own cell.
const WORKBENCH_MIN_READING: f64 = 0.2;
/// The workbench's reading and density sliders' step.
const WORKBENCH_STEP: f64 = 0.05;

/// The LiDAR beam counts the sensor fusion slider offers: from a handful,
/// where the table's legs fall between beams, to half a degree.
const LIDAR_BEAM_STEPS: [usize; 14] = [4, 6, 8, 12, 16, 24, 36, 45, 60, 90, 120, 180, 360, 720];

/// The cell sizes a real log may be mapped at, metres.
const LOG_RESOLUTIONS: [f64; 4] = [0.025, 0.05, 0.1, 0.2];
/// The real-log range cap's slider, metres: its least value and its step
/// (its largest is the traversal's reach, [`SettingLimits::range_cap_max`]).
const LOG_RANGE_CAP_MIN: f64 = 2.0;
const LOG_RANGE_CAP_STEP: f64 = 1.0;
/// Table 9.2's obstacle depth alpha on a real log, metres.
const LOG_ALPHA: Steps = Steps {
    min: 0.02,
    max: 0.5,
    step: 0.01,
};
/// Table 9.2's l_occ on a real log (above 0, which the core requires).
const LOG_L_OCC: Steps = Steps {
    min: 0.05,
    max: 3.0,
    step: 0.05,
};
/// Table 9.2's l_free on a real log (below 0, which the core requires).
const LOG_L_FREE: Steps = Steps {
    min: -3.0,
    max: -0.05,
    step: 0.05,
};
/// The clamp l_max of a real log's log-odds map.
const LOG_CLAMP: Steps = Steps {
    min: 0.5,
    max: 12.0,
    step: 0.5,
};
/// How far a no-return clears free space on a real log, metres.
const LOG_NO_RETURN_REACH: Steps = Steps {
    min: 1.0,
    max: 80.0,
    step: 1.0,
};

/// Every widget's controls, one group per widget.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Limits {
    pub cell_filter: CellFilterControls,
    pub doorway_trap: DoorwayTrapControls,
    pub two_cell_table: TwoCellControls,
    pub inverse_workbench: WorkbenchControls,
    pub sensor_fusion: FusionControls,
    pub real_log: RealLogControls,
}

/// `<occgrid-cell-filter>`'s sliders.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CellFilterControls {
    pub p_occ: Steps,
    pub p_free: Steps,
    pub prior: Steps,
    pub clamp: Steps,
}

/// `<occgrid-doorway-trap>`'s scene half.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DoorwayTrapControls {
    /// The most sweep scans a link may ask for before the first frame: a
    /// scene has at most [`crate::scenes::doorway::MAX_SCENE_READINGS`]
    /// readings, so at most as many scans.
    pub max_scans: usize,
}

/// The two-cell table's sliders (a cell's range keeps to the reading's).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct TwoCellControls {
    /// Up to the sonar's `z_max` (a reading there is no echo).
    pub reading: Steps,
    pub prior: Steps,
}

/// `<occgrid-inverse-workbench>`'s sliders.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WorkbenchControls {
    /// Up to the trained sensor's `z_max` (a no-return).
    pub reading: Steps,
    /// Up to the densest training maps the core builds.
    pub density: Steps,
}

/// `<occgrid-sensor-fusion>`'s beam slider.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FusionControls {
    pub beam_steps: Vec<usize>,
}

/// A menu's choice: the name a page and a link use, and the words shown.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Choice {
    pub value: &'static str,
    pub caption: &'static str,
}

/// A cell size a menu offers, metres, and the words shown.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CellSize {
    pub value: f64,
    pub caption: String,
}

/// Map Weaver's real-log panel: its sliders and its menus (its defaults are
/// the real-log module's, `RealLogSession.defaultSettings()`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct RealLogControls {
    pub resolutions: Vec<CellSize>,
    /// At the default resolution; the panel's slider goes as far as the
    /// chosen resolution lets the core reach (`RealLogSession.limits`).
    pub range_cap: Steps,
    pub alpha: Steps,
    pub l_occ: Steps,
    pub l_free: Steps,
    pub clamp: Steps,
    pub no_return_reach: Steps,
    pub max_seed: u64,
    /// How free evidence ends near a wall, the default first.
    pub walls: Vec<Choice>,
    /// The pose sources, the default first.
    pub poses: Vec<Choice>,
    /// The cell models, the default first.
    pub models: Vec<Choice>,
}

impl Limits {
    /// The table, its ends at the sonar's and the trained sensor's reach
    /// as `Constants` computes them (`cone`, `bench`).
    pub fn chapter(cone: &TwoCellLimits, bench: &WorkbenchLimits) -> Self {
        Self {
            cell_filter: CellFilterControls {
                p_occ: INVERSE_PROBABILITY,
                p_free: INVERSE_PROBABILITY,
                prior: PRIOR,
                clamp: CELL_FILTER_CLAMP,
            },
            doorway_trap: DoorwayTrapControls {
                max_scans: crate::scenes::doorway::MAX_SCENE_READINGS,
            },
            two_cell_table: TwoCellControls {
                reading: Steps {
                    min: TWO_CELL_MIN_RANGE,
                    max: cone.max_range,
                    step: TWO_CELL_READING_STEP,
                },
                prior: PRIOR,
            },
            inverse_workbench: WorkbenchControls {
                reading: Steps {
                    min: WORKBENCH_MIN_READING,
                    max: bench.z_max,
                    step: WORKBENCH_STEP,
                },
                density: Steps {
                    min: 0.0,
                    max: bench.max_density,
                    step: WORKBENCH_STEP,
                },
            },
            sensor_fusion: FusionControls {
                beam_steps: LIDAR_BEAM_STEPS.to_vec(),
            },
            real_log: RealLogControls::chapter(),
        }
    }
}

impl RealLogControls {
    fn chapter() -> Self {
        let defaults = LogMapSettings::default();
        let reach = SettingLimits::at(defaults.resolution)
            .expect("the default resolution is positive")
            .range_cap_max;
        let whole_steps = ((reach - LOG_RANGE_CAP_MIN) / LOG_RANGE_CAP_STEP).floor();
        let mut resolutions = Vec::new();
        for value in LOG_RESOLUTIONS {
            let caption = format!("{} cm", value * 100.0);
            resolutions.push(CellSize { value, caption });
        }
        let mut walls = Vec::new();
        for w in [defaults.walls, WallModel::Table92, WallModel::Incidence] {
            push_new(&mut walls, wall_name(w), wall_words(w));
        }
        let mut poses = Vec::new();
        for p in std::iter::once(defaults.poses).chain(PoseSourceKind::ALL) {
            push_new(&mut poses, p.name(), p.info().menu);
        }
        let mut models = Vec::new();
        for m in std::iter::once(defaults.model).chain(LogCellModel::ALL) {
            push_new(&mut models, m.name(), m.caption());
        }
        Self {
            resolutions,
            range_cap: Steps {
                min: LOG_RANGE_CAP_MIN,
                max: LOG_RANGE_CAP_MIN + whole_steps * LOG_RANGE_CAP_STEP,
                step: LOG_RANGE_CAP_STEP,
            },
            alpha: LOG_ALPHA,
            l_occ: LOG_L_OCC,
            l_free: LOG_L_FREE,
            clamp: LOG_CLAMP,
            no_return_reach: LOG_NO_RETURN_REACH,
            max_seed: MAX_SEED,
            walls,
            poses,
            models,
        }
    }
}

/// Adds the choice `value` to a menu that does not list it yet (a menu
/// lists its default first, then the others in the core's order).
fn push_new(menu: &mut Vec<Choice>, value: &'static str, caption: &'static str) {
    if menu.iter().all(|c| c.value != value) {
        menu.push(Choice { value, caption });
    }
}

/// A wall model's name as a page writes it ([`WallModel::NAMES`]).
fn wall_name(w: WallModel) -> &'static str {
    match w {
        WallModel::Table92 => WallModel::NAMES[0],
        WallModel::Incidence => WallModel::NAMES[1],
    }
}

/// How the real-log panel's menu words a wall model.
fn wall_words(w: WallModel) -> &'static str {
    match w {
        WallModel::Incidence => "stops at the wall a beam grazes",
        WallModel::Table92 => "Table 9.2 (walls wear away)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inverse::TrainingConfig;
    use crate::mapping::cell_filter::CellFilterParams;

    impl Limits {
        fn of_the_chapter() -> Self {
            Self::chapter(&TwoCellLimits::chapter(), &WorkbenchLimits::chapter())
        }
    }
    use crate::mapping::joint::JointQuery;
    use crate::scenes::table::TableScene;

    /// A slider's two ends.
    fn ends(r: Steps) -> [f64; 2] {
        [r.min, r.max]
    }

    /// The two values a step past either end.
    fn past(r: Steps) -> [f64; 2] {
        [r.min - r.step, r.max + r.step]
    }

    #[test]
    fn the_cell_filters_sliders_are_inside_what_the_filter_takes_and_past_them_it_refuses() {
        let k = Limits::of_the_chapter().cell_filter;
        let with = |f: fn(&mut CellFilterParams, f64), v: f64| {
            let mut p = CellFilterParams::WORKED_EXAMPLE;
            f(&mut p, v);
            p.validate()
        };
        type Set = fn(&mut CellFilterParams, f64);
        let knobs: [(Steps, Set); 3] = [
            (k.p_occ, |p, v| p.p_occ = v),
            (k.p_free, |p, v| p.p_free = v),
            (k.prior, |p, v| p.prior = v),
        ];
        for (r, set) in knobs {
            for v in ends(r) {
                with(set, v).unwrap();
            }
            // A step past either end is 0 or 1: no log odds.
            for v in past(r) {
                assert!(with(set, v).is_err(), "{v}");
            }
        }
        for v in ends(k.clamp) {
            with(|p, v| p.clamp = v, v).unwrap();
        }
        with(|p, v| p.clamp = v, f64::INFINITY).unwrap();
    }

    #[test]
    fn the_two_cell_tables_reading_stops_at_the_sonars_z_max() {
        let t = Limits::of_the_chapter().two_cell_table;
        let q = JointQuery::chapter_two_cells();
        assert_eq!(t.reading.max, q.model.z_max);
        let reading = |z| JointQuery {
            readings: vec![z],
            ..JointQuery::chapter_two_cells()
        };
        for z in ends(t.reading) {
            reading(z).validate().unwrap();
        }
        for p in ends(t.prior) {
            JointQuery {
                prior: p,
                ..JointQuery::chapter_two_cells()
            }
            .validate()
            .unwrap();
        }
        for p in past(t.prior) {
            let q = JointQuery {
                prior: p,
                ..JointQuery::chapter_two_cells()
            };
            assert!(q.validate().is_err(), "{p}");
        }
    }

    #[test]
    fn the_workbench_reads_up_to_its_sensors_z_max_and_trains_up_to_the_densest_maps() {
        let w = Limits::of_the_chapter().inverse_workbench;
        assert_eq!(w.reading.max, TrainingConfig::default().sensor.z_max);
        let at = |density| TrainingConfig {
            density,
            ..TrainingConfig::default()
        };
        for d in ends(w.density) {
            at(d).validate().unwrap();
        }
        for d in past(w.density) {
            assert!(at(d).validate().is_err(), "{d}");
        }
    }

    #[test]
    fn every_beam_count_the_fusion_slider_offers_is_one_the_scene_takes() {
        let f = Limits::of_the_chapter().sensor_fusion;
        let scene = TableScene::default();
        for &beams in &f.beam_steps {
            scene.with_lidar_beams(beams).unwrap();
        }
        assert!(f.beam_steps.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn the_doorway_trap_offers_as_many_scans_as_a_scene_may_have_readings() {
        let d = Limits::of_the_chapter().doorway_trap;
        assert_eq!(d.max_scans, crate::scenes::doorway::MAX_SCENE_READINGS);
    }

    /// The real-log panel's sliders: every end is accepted, the range
    /// cap's end is the traversal's reach at the default resolution (a
    /// metre more is refused there), and a step past l_occ's least value
    /// or l_free's largest is refused (evidence of the wrong sign).
    #[test]
    fn the_real_log_panels_controls_are_the_cores() {
        let r = Limits::of_the_chapter().real_log;
        let d = LogMapSettings::default();
        let at = |f: &dyn Fn(&mut LogMapSettings)| {
            let mut s = LogMapSettings::default();
            f(&mut s);
            s.validate().map(|_| ()).and_then(|_| s.check_reach())
        };
        for v in ends(r.range_cap) {
            at(&|s| s.range_cap = v).unwrap();
        }
        assert_eq!(r.range_cap.max, 102.0);
        assert!(at(&|s| s.range_cap = r.range_cap.max + r.range_cap.step).is_err());
        for v in ends(r.alpha) {
            at(&|s| s.alpha = v).unwrap();
        }
        for v in ends(r.l_occ) {
            at(&|s| s.l_occ = v).unwrap();
        }
        assert!(at(&|s| s.l_occ = r.l_occ.min - r.l_occ.step).is_err());
        for v in ends(r.l_free) {
            at(&|s| s.l_free = v).unwrap();
        }
        assert!(at(&|s| s.l_free = r.l_free.max + r.l_free.step).is_err());
        for v in ends(r.clamp) {
            at(&|s| s.clamp = v).unwrap();
        }
        for v in ends(r.no_return_reach) {
            at(&|s| s.no_return_reach = v).unwrap();
        }
        for c in &r.resolutions {
            at(&|s| s.resolution = c.value).unwrap();
        }
        assert!(r.resolutions.iter().any(|c| c.value == d.resolution));
        let captions: Vec<_> = r.resolutions.iter().map(|c| c.caption.as_str()).collect();
        assert_eq!(captions, ["2.5 cm", "5 cm", "10 cm", "20 cm"]);

        // The menus' names are the core's, each once, the defaults first.
        let names = |c: &[Choice]| c.iter().map(|c| c.value).collect::<Vec<_>>();
        assert_eq!(names(&r.poses), PoseSourceKind::NAMES);
        assert_eq!(r.poses[0].value, d.poses.name());
        assert_eq!(r.models[0].value, d.model.name());
        let mut models = names(&r.models);
        models.sort_unstable();
        let mut all = LogCellModel::NAMES;
        all.sort_unstable();
        assert_eq!(models, all);
        assert_eq!(r.walls[0].value, wall_name(d.walls));
        let mut walls = names(&r.walls);
        walls.sort_unstable();
        let mut all = WallModel::NAMES;
        all.sort_unstable();
        assert_eq!(walls, all);
    }
}
