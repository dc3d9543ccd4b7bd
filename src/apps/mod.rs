//! One plain-Rust session per widget: every number a reader sees, answered
//! in image units (pixels of the drawn map, x right, y down), so that the
//! JavaScript only draws. The bindings wrap each session in one newtype.

pub mod doorway_trap;
pub mod inverse_workbench;
pub mod limits;
pub mod map_weaver;
pub mod pane;
pub mod real_log;
pub mod sensor_fusion;
pub mod two_cell_table;
pub mod workbench_training;

use crate::mapping::cell_filter::CellFilterPreset;

/// The model values the widgets' attributes, sliders and presets keep to,
/// one group per widget, so that no page restates them, and the one table
/// of every control's range, names and words ([`limits::Limits`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Constants {
    pub cell_filter: CellFilterPresets,
    pub inverse_workbench: inverse_workbench::WorkbenchLimits,
    pub map_weaver: map_weaver::WeaverLimits,
    pub sensor_fusion: sensor_fusion::FusionLimits,
    pub two_cell_table: two_cell_table::TwoCellLimits,
    pub limits: limits::Limits,
}

/// The cell filter's two presets.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CellFilterPresets {
    pub worked_example: CellFilterPreset,
    pub l0_lesson: CellFilterPreset,
}

impl Constants {
    pub fn chapter() -> Self {
        let inverse_workbench = inverse_workbench::WorkbenchLimits::chapter();
        let two_cell_table = two_cell_table::TwoCellLimits::chapter();
        Self {
            cell_filter: CellFilterPresets {
                worked_example: CellFilterPreset::WORKED_EXAMPLE,
                l0_lesson: CellFilterPreset::L0_LESSON,
            },
            inverse_workbench,
            map_weaver: map_weaver::WeaverLimits::chapter(),
            sensor_fusion: sensor_fusion::FusionLimits::chapter(),
            two_cell_table,
            limits: limits::Limits::chapter(&two_cell_table, &inverse_workbench),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inverse::training::TrainingConfig;
    use crate::mapping::joint::{ConeCell, JointQuery};
    use crate::scenes::table::TableScene;

    /// Each limit is the one the core enforces: at it is accepted, past it
    /// refused, so a widget keeping to it never meets a refusal.
    #[test]
    fn the_widgets_limits_are_where_the_core_refuses() {
        let k = Constants::chapter();

        let beams = k.sensor_fusion;
        assert_eq!(TableScene::default().lidar.beams, beams.default_lidar_beams);
        let scene = TableScene::default();
        assert!(scene.with_lidar_beams(beams.max_lidar_beams).is_ok());
        assert!(scene.with_lidar_beams(beams.max_lidar_beams + 1).is_err());

        let bench = k.inverse_workbench;
        let at = |density| TrainingConfig {
            density,
            ..TrainingConfig::default()
        };
        assert!(at(bench.max_density).validate().is_ok());
        assert!(at(bench.max_density + 1e-9).validate().is_err());
        assert_eq!(TrainingConfig::default().sensor.z_max, bench.z_max);

        let cone = k.two_cell_table;
        let with = |bearing_deg| JointQuery {
            cells: vec![ConeCell {
                range: cone.max_range,
                bearing_deg,
            }],
            ..JointQuery::chapter_two_cells()
        };
        assert!(with(cone.half_cone_deg).validate().is_ok());
        assert!(with(-cone.half_cone_deg).validate().is_ok());
        assert!(with(cone.half_cone_deg + 0.01).validate().is_err());
        assert_eq!(JointQuery::chapter_two_cells().model.z_max, cone.max_range);
    }

    /// Map Weaver's knobs: each published range is accepted at both ends
    /// and on every step, and refused a step past either end and between
    /// steps, naming the pane's field (the strength was published as
    /// 0.25 to 3 while the core took anything up to 10).
    #[test]
    fn map_weavers_limits_are_where_its_settings_refuse() {
        use map_weaver::{PaneSettings, WeaverSettings};
        let m = Constants::chapter().map_weaver;
        let scene = crate::scenes::apartment::ApartmentScene::default();
        type Set = fn(&mut PaneSettings, f64);
        let knobs: [(&str, map_weaver::Steps, Set); 3] = [
            ("strength", m.strength, |p, v| p.strength = v),
            ("clamp", m.clamp, |p, v| p.clamp = v),
            ("betaDeg", m.beta_deg, |p, v| p.beta_deg = v),
        ];
        for (field, r, set) in knobs {
            let at = |v: f64| {
                let mut p = PaneSettings::default();
                set(&mut p, v);
                p.validate(1, &scene)
            };
            let steps = ((r.max - r.min) / r.step).round() as usize;
            for i in 0..=steps {
                at(r.min + i as f64 * r.step).unwrap();
            }
            for v in [
                r.min - r.step,
                r.max + r.step,
                r.min + r.step / 2.0,
                f64::NAN,
            ] {
                let e = at(v).unwrap_err().to_string();
                assert!(e.starts_with(&format!("invalid panes[1].{field}: ")), "{e}");
            }
        }
        for r in m.pane_resolutions {
            let p = PaneSettings {
                resolution: Some(r),
                ..PaneSettings::default()
            };
            p.validate(0, &scene).unwrap();
        }
        let laps = |laps| WeaverSettings {
            laps,
            ..WeaverSettings::default()
        };
        laps(m.max_laps).validate().unwrap();
        assert!(laps(m.max_laps + 1).validate().is_err());
        let mut lidar = scene.lidar;
        lidar.beams = m.max_lidar_beams;
        lidar.validate().unwrap();
        lidar.beams += 1;
        assert!(lidar.validate().is_err());
        let d = WeaverSettings::default();
        assert_eq!(
            (
                m.defaults.seed,
                m.defaults.laps,
                m.defaults.person,
                m.defaults.panes
            ),
            (d.seed, d.laps, d.person, d.panes)
        );
    }
}
