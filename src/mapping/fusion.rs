//! Multi-sensor fusion: one grid per sensor, fused by the max rule
//! (Probabilistic Robotics §9.2, eq. 9.9), against the naive single grid.
//!
//! Two sensors that look at different horizontal slices of the world answer
//! two different questions. In the table scene ([`crate::scenes::table`]) a
//! sonar at table height reports the top; a LiDAR at shin height reports
//! four thin legs and free floor between them. Both are right. Adding both
//! streams into one log-odds grid treats them as independent readings of
//! the *same* cell state, which they are not: the sum then settles wherever
//! the ratio of the two evidence rates puts it (how many beams and scans
//! each sensor delivers), not on any fact about the table.
//!
//! The chapter's remedy keeps one map per modality, each a proper binary
//! Bayes filter over what that sensor can see, and fuses them per cell by
//! `p_i = max_k p_i^(k)` (eq. 9.9). The rule is deliberately biased toward
//! "occupied": a cell one sensor believes occupied stays occupied in the
//! fused map whatever the other sensor says. For a robot that plans through
//! the fused map the two errors cost very different amounts: a phantom
//! obstacle costs a detour, a deleted obstacle costs a collision. The same
//! bias has a price the widget shows: with a prior of 0.5, a cell one sensor
//! has never looked at (`p = 0.5`) outranks another sensor's "free", so the
//! fused map only clears space that every sensor has cleared.
//!
//! The table experiment that shows it, one grid per modality against the
//! summed grid, is the sensor-fusion session ([`crate::apps::sensor_fusion`]).

use crate::error::{invalid, OccError, Result};
use crate::grid::{probability, LogOddsGrid};

/// Eq. 9.9 per cell: `p_i = max_k p_i^(k)` over maps of the same limits.
pub fn max_fused_probabilities(maps: &[&LogOddsGrid]) -> Result<Vec<f64>> {
    check_same_limits(maps)?;
    let n = maps.first().map_or(0, |m| m.geometry().len());
    // `p` rises with `l`, so the largest probability is the probability of
    // the largest log odds: one exponential per cell instead of one per map.
    Ok((0..n)
        .map(|i| {
            let l = maps
                .iter()
                .map(|m| m.log_odds()[i])
                .fold(f32::NEG_INFINITY, f32::max);
            probability(l as f64)
        })
        .collect())
}

/// Writes eq. 9.9 into `out` as a map that can be drawn like any other:
/// since `p` rises with `l`, the most occupied modality of a cell is the one
/// with the largest log odds, and `out` takes that value. A cell every
/// modality has left at the prior stays "unknown". `out` must have the same
/// limits and prior as the inputs; on error it is left untouched.
pub fn max_fuse_into(out: &mut LogOddsGrid, maps: &[&LogOddsGrid]) -> Result<()> {
    check_same_limits(maps)?;
    if let Some(first) = maps.first() {
        if out.geometry() != first.geometry() {
            return Err(invalid(
                "fused map",
                "limits unlike the modalities' maps",
                "the same geometry as every modality",
            ));
        }
        if out.l0() != first.l0() {
            return Err(invalid(
                "fused map",
                format!("prior log odds {}", out.l0()),
                "the same prior as every modality",
            ));
        }
    }
    let clamp = maps.iter().map(|m| m.clamp()).fold(out.clamp(), f32::max);
    out.set_clamp(clamp as f64)?;
    out.reset();
    let l0 = out.l0();
    for i in 0..out.geometry().len() {
        let l = maps
            .iter()
            .map(|m| m.log_odds()[i])
            .fold(f32::NEG_INFINITY, f32::max);
        if l != l0 {
            out.apply(i, l - l0);
        }
    }
    Ok(())
}

/// Mean of `p` over `cells`: the footprint's mean occupancy.
pub fn mean_over(p: &[f64], cells: &[usize]) -> Result<f64> {
    if cells.is_empty() {
        return Err(invalid("cells", "[]", "at least one cell"));
    }
    let mut sum = 0.0;
    for &i in cells {
        sum += p
            .get(i)
            .ok_or_else(|| invalid("cells", i, "cell indices inside the map"))?;
    }
    Ok(sum / cells.len() as f64)
}

/// Mean occupancy probability of `grid` over `cells`.
pub fn mean_probability(grid: &LogOddsGrid, cells: &[usize]) -> Result<f64> {
    if cells.is_empty() {
        return Err(invalid("cells", "[]", "at least one cell"));
    }
    let n = grid.geometry().len();
    let mut sum = 0.0;
    for &i in cells {
        if i >= n {
            return Err(invalid("cells", i, "cell indices inside the map"));
        }
        sum += grid.probability_at(i);
    }
    Ok(sum / cells.len() as f64)
}

/// Every map must describe the same cells: same size, resolution and
/// origin.
fn check_same_limits(maps: &[&LogOddsGrid]) -> Result<()> {
    let Some(first) = maps.first() else {
        return Err(invalid("maps", "[]", "at least one modality's map"));
    };
    for (k, m) in maps.iter().enumerate().skip(1) {
        let (a, b) = (first.geometry(), m.geometry());
        if a.len() != b.len() {
            return Err(OccError::LengthMismatch {
                field: format!("maps[{k}]"),
                expected: a.len(),
                found: b.len(),
            });
        }
        if a != b {
            return Err(invalid(
                &format!("maps[{k}]"),
                "a map placed or scaled differently",
                "the same geometry as maps[0]",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::GridGeometry;
    use crate::grid::FilterSettings;

    fn map(l: &[f32]) -> LogOddsGrid {
        let g = GridGeometry::new(l.len(), 1, 0.1, 0.0, 0.0).unwrap();
        let mut m = LogOddsGrid::new(g, FilterSettings::default()).unwrap();
        for (i, &v) in l.iter().enumerate() {
            m.apply(i, v);
        }
        m
    }

    #[test]
    fn max_rule_takes_the_more_occupied_modality_per_cell() {
        let a = map(&[2.0, -2.0, 0.0]);
        let b = map(&[-1.0, 1.0, -3.0]);
        let p = max_fused_probabilities(&[&a, &b]).unwrap();
        assert!((p[0] - probability(2.0)).abs() < 1e-12);
        assert!((p[1] - probability(1.0)).abs() < 1e-12);
        assert_eq!(p[2], 0.5, "unknown beats free: max(0.5, 0.047)");
        let mut out = map(&[0.0; 3]);
        max_fuse_into(&mut out, &[&a, &b]).unwrap();
        assert_eq!(out.log_odds(), &[2.0, 1.0, 0.0]);
        assert!(out.is_unknown(2));
    }

    #[test]
    fn fusion_rejects_maps_of_different_limits() {
        let a = map(&[0.0; 3]);
        let b = map(&[0.0; 4]);
        let e = max_fused_probabilities(&[&a, &b]).unwrap_err().to_string();
        assert!(e.contains("maps[1]"), "{e}");
        assert!(max_fused_probabilities(&[]).is_err());
        let mut out = map(&[0.5; 3]);
        let before = out.clone();
        assert!(max_fuse_into(&mut out, &[&b]).is_err());
        assert_eq!(out, before, "untouched on error");
        assert!(mean_over(&[0.1], &[3]).is_err());
        assert!(mean_probability(&a, &[]).is_err());
    }
}
