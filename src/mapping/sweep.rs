//! Table 9.1 as printed: every cell of the map is visited, the beam nearest
//! to it in bearing is found, and the inverse model (Table 9.2) is applied.
//!
//! Its cost is the map, not the beams: what a wide cone sensor (a sonar whose
//! cone covers cells no beam's raster passes through) needs, and what the
//! ray traversal of [`super::traversal`] avoids for thin beams (docs/BENCHMARKS.md
//! W3 compares the two).

use super::traversal::ScanStats;
use crate::geometry::wrap_angle;
use crate::grid::LogOddsGrid;
use crate::inverse::InverseModel;
use crate::sensors::Scan;

/// Table 9.1 literally: every cell of the map, the nearest beam by bearing,
/// the inverse model. Each cell is updated at most once by construction.
pub fn sweep_scan<M: InverseModel + ?Sized>(
    grid: &mut LogOddsGrid,
    model: &M,
    scan: &Scan,
) -> ScanStats {
    let rows = 0..grid.geometry().height();
    sweep_rows(grid, model, scan, rows)
}

/// [`sweep_scan`] over the rows `rows` of the map only (clipped to it).
/// Each cell's update depends on that cell alone, so a scan swept in
/// several calls over rows that cover the map, in any split, leaves the
/// grid exactly as one [`sweep_scan`] does: a page spreads a large map's
/// sweep over several frames this way.
pub fn sweep_rows<M: InverseModel + ?Sized>(
    grid: &mut LogOddsGrid,
    model: &M,
    scan: &Scan,
    rows: std::ops::Range<usize>,
) -> ScanStats {
    let pose = scan.pose();
    // Beams sorted by bearing in (-pi, pi], for a binary search per cell.
    let mut beams: Vec<(f64, f64)> = scan
        .bearings()
        .iter()
        .zip(scan.ranges())
        .map(|(&b, &z)| (wrap_angle(b), z))
        .collect();
    crate::geometry::order::sort_stable_by_key(&mut beams, |beam| beam.0);
    let max_reach = beams
        .iter()
        .map(|&(_, z)| model.reach(z))
        .fold(0.0, f64::max);

    let geometry = *grid.geometry();
    let rows = rows.start.min(geometry.height())..rows.end.min(geometry.height());
    let mut updated = 0;
    for iy in rows.clone() {
        for ix in 0..geometry.width() {
            let (cx, cy) = geometry.cell_center(ix, iy);
            let (dx, dy) = (cx - pose.x, cy - pose.y);
            let r = dx.hypot(dy);
            if r > max_reach {
                continue;
            }
            let bearing = wrap_angle(dy.atan2(dx) - pose.theta);
            let (phi, z) = nearest_beam(&beams, bearing);
            let e = model.evidence(r, phi, z);
            if e != 0.0 {
                grid.apply(geometry.index(ix, iy), e);
                updated += 1;
            }
        }
    }
    ScanStats {
        cells_visited: rows.len() * geometry.width(),
        cells_updated: updated,
    }
}

/// The beam nearest in bearing to `bearing` among `beams` (sorted by
/// bearing, wrapped): returns the cell's offset from that beam's axis and
/// the beam's reading.
fn nearest_beam(beams: &[(f64, f64)], bearing: f64) -> (f64, f64) {
    let k = beams.partition_point(|&(b, _)| b < bearing);
    // The candidates are the neighbours of the insertion point, wrapping
    // around at +-pi.
    let below = beams[(k + beams.len() - 1) % beams.len()];
    let above = beams[k % beams.len()];
    let (d_below, d_above) = (wrap_angle(bearing - below.0), wrap_angle(bearing - above.0));
    if d_below.abs() <= d_above.abs() {
        (d_below, below.1)
    } else {
        (d_above, above.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_beam_wraps_around_pi() {
        let beams = [(-3.1, 1.0), (0.0, 2.0), (3.0, 3.0)];
        // 3.13 is 0.13 from the beam at 3.0 but 0.053 from the one at -3.1,
        // across the wrap.
        assert_eq!(nearest_beam(&beams, 3.13).1, 1.0);
        assert_eq!(nearest_beam(&beams, 3.05).1, 3.0);
        assert_eq!(nearest_beam(&beams, -3.13).1, 1.0);
        let (phi, z) = nearest_beam(&beams, 0.1);
        assert!((phi - 0.1).abs() < 1e-12 && z == 2.0);
    }
}
