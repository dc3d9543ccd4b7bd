//! One cell of the four fusion maps, as the widget's cell readout shows it:
//! each sensor's own cell, eq. 9.9's `max(p_sonar, p_lidar)` and the summed
//! grid's cell, so that a reader can check the max rule on one cell.

use super::TableFusion;
use crate::grid::readout::{readout_at_cell, CellReadout};

/// One cell under all four rules.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct FusionCell {
    pub sonar: CellReadout,
    pub lidar: CellReadout,
    /// Eq. 9.9 for the cell, exactly `max(p_sonar, p_lidar)`.
    pub max: f64,
    pub sum: CellReadout,
    /// Whether the cell lies under the table top (its footprint).
    pub footprint: bool,
}

impl TableFusion {
    /// The cell under image pixel `(col, row)` of the north-up maps (row 0
    /// at the top), `None` off the map.
    pub fn cell_at_pixel(&self, col: usize, row: usize) -> Option<FusionCell> {
        let g = self.sonar.geometry();
        let (ix, iy) = g.image_pixel_to_cell(col, row)?;
        let i = g.index(ix, iy);
        Some(FusionCell {
            sonar: readout_at_cell(&self.sonar, ix, iy)?,
            lidar: readout_at_cell(&self.lidar, ix, iy)?,
            max: *self.fused_p.get(i)?,
            sum: readout_at_cell(&self.summed, ix, iy)?,
            footprint: self.run.footprint().contains(&i),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::table::TableScene;

    #[test]
    fn a_cell_reads_both_sensors_their_max_and_the_summed_grid() {
        let mut f = TableFusion::new(&TableScene::default()).unwrap();
        for _ in 0..5 {
            f.step();
        }
        let g = f.sonar().geometry();
        let (w, h) = (g.width(), g.height());
        let mut seen_footprint = false;
        for row in (0..h).step_by(3) {
            for col in (0..w).step_by(3) {
                let c = f.cell_at_pixel(col, row).unwrap();
                assert_eq!(c.max, c.sonar.p.max(c.lidar.p), "eq. 9.9 at ({col}, {row})");
                assert_eq!((c.sonar.ix, c.sonar.iy), (c.sum.ix, c.sum.iy));
                seen_footprint |= c.footprint;
            }
        }
        assert!(seen_footprint, "some sampled cell lies under the table");
        assert!(f.cell_at_pixel(w, 0).is_none() && f.cell_at_pixel(0, h).is_none());
    }
}
