//! Walls that last: how a real-log map keeps its walls under many scans
//! (docs/ARCHITECTURE.md, "Real logs"), and how far a no-return clears.
//!
//! # Why walls wear away under Table 9.2
//!
//! A beam that meets a wall at a grazing angle `θ` (between beam and wall)
//! runs inside the wall's row of cells for about `res / sin θ` before its
//! endpoint. Table 9.2 gives every cell before `z - α/2` free evidence, so
//! such a beam carves the very wall cells that its neighbours (and earlier
//! scans) marked occupied: on a long log, and on corridors seen almost
//! edge-on (the fhw log), the walls break into dots. Weakening `l_free`
//! only slows this down; the carving is still there on every grazing beam.
//!
//! # The choice: free evidence stops at the wall's band ([`WallModel::Incidence`])
//!
//! Each return's incidence is measured from the scan itself: neighbouring
//! endpoints on one plane lie `Δe ≈ z δφ / sin θ` apart, so
//! `1 / sin θ ≈ Δe / (z δφ)` (the smaller of the two neighbours, so that a
//! depth jump at an object's edge does not count). The beam then gives free
//! evidence only up to `z - max(α/2, res / sin θ)` (at most
//! [`MAX_MARGIN`]) and, as Table 9.2, occupied evidence within `α/2` of the
//! reading; between the two, nothing. A beam at right angles to a wall is
//! Table 9.2 exactly; a grazing one no longer carves the wall it runs
//! along, while the cells in front of the wall are still cleared by the
//! beams that see them squarely.
//!
//! Why this and not the alternatives: Cartographer-style weak misses and a
//! GMapping-style hit count both keep walls by making every free reading
//! cheap (or by never forgetting a hit), so a person who stood still for a
//! while takes far longer to fade; protecting the neighbourhood of every
//! hit freezes space near any obstacle, a person's ghost included. The
//! incidence margin touches only the cells a grazing beam cannot tell from
//! the wall, so the free evidence a ghost needs to fade (beams through the
//! empty place, seen squarely) is untouched, and the filter, its clamp and
//! Table 9.2's weights stay the chapter's.
//!
//! # No-returns
//!
//! A reading at or beyond `z_max` carves free space out to the no-return
//! reach only (Cartographer's `missing_data_ray_length`, GMapping's
//! `maxUrange`), so that windows and open doors do not fan free space
//! across the outside of a building. With the reach at `z_max` and
//! [`WallModel::Table92`] the bands are Table 9.2's axis profile and the map
//! is bit for bit the chapter's (and W1's).

use super::neighbour_support::rest_on_neighbours;
use super::traversal::BeamBand;
use crate::inverse::{HandCrafted, InverseModel};
use crate::sensors::Scan;

/// The most free evidence is withheld before a reading, metres: at 5 cm
/// cells a beam at 3° to a wall (1 / sin θ ≈ 19 cells).
pub const MAX_MARGIN: f64 = 1.0;

/// How a beam's free evidence ends before its reading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum WallModel {
    /// Table 9.2 as printed: free up to `z - α/2` on every beam (the
    /// chapter's lesson: on long logs the walls wear away).
    #[serde(rename = "table-9.2")]
    Table92,
    /// Free evidence stops `res / sin θ` before the reading, `θ` the beam's
    /// incidence on the surface it hit (see the module doc).
    #[default]
    #[serde(rename = "incidence")]
    Incidence,
}

impl WallModel {
    /// The names a page and the CLI use.
    pub const NAMES: [&'static str; 2] = ["table-9.2", "incidence"];
}

/// Fills `out` with the bands of each beam of `scan` under `model`: no-returns
/// (readings at or beyond the model's `z_max`) clear free space out to
/// `no_return_reach` at most, and under [`WallModel::Incidence`] a return's
/// free evidence stops at the wall's band (`res` the grid's cell size).
pub fn beam_bands(
    scan: &Scan,
    model: &HandCrafted,
    no_return_reach: f64,
    walls: WallModel,
    res: f64,
    out: &mut Vec<Option<BeamBand>>,
) {
    out.clear();
    let (ranges, bearings) = (scan.ranges(), scan.bearings());
    let z_max = model.z_max();
    let is_return = |z: f64| z < z_max && z > 0.0;
    // Each bearing's `(sin, cos)` computed once, kept for the beam and its
    // two neighbours (three consecutive indices, three slots): in wasm
    // each is a library routine, and four per beam were a twentieth of a
    // real log's build.
    let mut kept = [(usize::MAX, (0.0, 0.0)); 3];
    let mut trig = |k: usize| {
        let slot = &mut kept[k % 3];
        if slot.0 != k {
            *slot = (k, bearings[k].sin_cos());
        }
        slot.1
    };
    for (i, &z) in ranges.iter().enumerate() {
        let reach = model.reach(z);
        let Some(p) = model.axis_profile(z).filter(|_| reach > 0.0) else {
            out.push(None);
            continue;
        };
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN range is a no-return
        if !(z < z_max) {
            let r = reach.min(no_return_reach);
            out.push(Some(BeamBand {
                reach: r,
                free_until: r,
                occupied_from: r,
                occupied_until: r,
            }));
            continue;
        }
        let mut free_until = p.free_until;
        if walls == WallModel::Incidence && is_return(z) {
            // 1 / sin θ from the nearer neighbouring endpoint.
            let mut inv_sin = f64::INFINITY;
            for j in [i.wrapping_sub(1), i + 1] {
                let (Some(&zj), Some(&bj)) = (ranges.get(j), bearings.get(j)) else {
                    continue;
                };
                if !is_return(zj) {
                    continue;
                }
                let dphi = (bj - bearings[i]).abs();
                let (si, ci) = trig(i);
                let (sj, cj) = trig(j);
                let de = ((z * ci - zj * cj).powi(2) + (z * si - zj * sj).powi(2)).sqrt();
                if dphi > 0.0 {
                    inv_sin = inv_sin.min(de / (z * dphi));
                }
            }
            if inv_sin.is_finite() {
                let margin = (res * inv_sin.max(1.0)).min(MAX_MARGIN);
                free_until = free_until.min(z - margin);
            }
        }
        out.push(Some(BeamBand {
            reach,
            free_until,
            occupied_from: p.free_until,
            occupied_until: p.occupied_until,
        }));
    }
    if walls == WallModel::Incidence {
        rest_on_neighbours(ranges, bearings, is_return, out);
    }
}
