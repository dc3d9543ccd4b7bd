//! One plain-Rust session per widget: every number a reader sees, answered
//! in image units (pixels of the drawn map, x right, y down), so that the
//! JavaScript only draws. The bindings wrap each session in one newtype.

pub mod doorway_trap;
pub mod inverse_workbench;
pub mod map_weaver;
pub mod pane;
pub mod real_log;
pub mod sensor_fusion;
pub mod two_cell_table;

use crate::mapping::cell_filter::CellFilterPreset;

/// The model values the widgets' attributes, sliders and presets keep to,
/// one group per widget, so that no page restates them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Constants {
    pub cell_filter: CellFilterPresets,
    pub inverse_workbench: inverse_workbench::WorkbenchLimits,
    pub sensor_fusion: sensor_fusion::FusionLimits,
    pub two_cell_table: two_cell_table::TwoCellLimits,
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
        Self {
            cell_filter: CellFilterPresets {
                worked_example: CellFilterPreset::WORKED_EXAMPLE,
                l0_lesson: CellFilterPreset::L0_LESSON,
            },
            inverse_workbench: inverse_workbench::WorkbenchLimits::chapter(),
            sensor_fusion: sensor_fusion::FusionLimits::chapter(),
            two_cell_table: two_cell_table::TwoCellLimits::chapter(),
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
}
