//! What a log's map will allocate, known before a cell is: the tiles its
//! beams reach, walked on the grid of tiles (docs/ARCHITECTURE.md, "Real
//! logs"). A resolution too fine for the tile budget is refused when the
//! settings are chosen, naming the finest resolution that fits, instead of
//! a build that stops part way through the log.

use super::settings::{CheckedSettings, LogPoses};
use crate::error::{invalid, show, Result};
use crate::geometry::{GridGeometry, Pose};
use crate::grid::storage::{mebibytes, tiles_of, TILE_CELLS, TILE_SIDE};
use crate::io::carmen::LaserScans;
use crate::mapping::reach::{tiles_reached, BeamReach};
use crate::sensors::Scan;

/// The resolutions offered when one is refused are whole steps of half a
/// centimetre (the finest step a reader sets by hand): steps per metre.
const RESOLUTION_STEPS_PER_METRE: f64 = 200.0;
/// Coarser resolutions tried before giving up on naming one that fits.
const TRIES: usize = 8;

/// Scan `k` of `scans` at `pose`.
pub(super) fn at_pose(scans: &LaserScans, k: usize, pose: Pose) -> Option<Scan> {
    let scan = scans.scan(k)?;
    if scan.pose() == pose {
        return Some(scan);
    }
    Scan::new(pose, scan.ranges().to_vec(), scan.bearings().to_vec()).ok()
}

/// The tiles the beams of every scan at `poses` reach on `extent`: what
/// the whole log would allocate in a tiled map.
pub(super) fn tiles_needed(
    scans: &LaserScans,
    poses: &[Pose],
    extent: &GridGeometry,
    c: &CheckedSettings,
) -> usize {
    let s = c.settings();
    tiles_reached(
        extent,
        (0..scans.len()).filter_map(|k| at_pose(scans, k, *poses.get(k)?)),
        BeamReach {
            model: c.model(),
            no_return_reach: s.no_return_reach,
            walls: s.walls,
        },
    )
}

/// Refuses settings whose map of `scans` would need more than
/// `budget_cells` cells in tiles. `poses` are where the scans will be put
/// (for a scan-matched pane, the log's own poses: the matched path stays
/// near them, where dead reckoning wanders off); `plan` gives the map's
/// extent at other settings, to find the finest resolution that fits.
pub(super) fn check_tile_budget(
    scans: &LaserScans,
    poses: &[Pose],
    extent: &GridGeometry,
    c: &CheckedSettings,
    budget_cells: usize,
    bytes_per_cell: usize,
    plan: impl Fn(&CheckedSettings) -> Result<GridGeometry>,
) -> Result<()> {
    let budget_tiles = (budget_cells / TILE_CELLS).max(1);
    // A map whose every tile fits needs no walk (most logs: only the
    // largest maps pay for counting the tiles their beams reach).
    let (tx, ty) = tiles_of(extent);
    if tx.saturating_mul(ty) <= budget_tiles {
        return Ok(());
    }
    let needed = tiles_needed(scans, poses, extent, c);
    if needed <= budget_tiles {
        return Ok(());
    }
    let resolution = c.settings().resolution;
    // Tiles grow as the area the beams sweep, with the square of 1 /
    // resolution: start from there and step up until one fits.
    let scale = (needed as f64 / budget_tiles as f64).sqrt();
    // Counted in whole steps, so that the resolution named reads as typed.
    let mut steps = (resolution * scale * RESOLUTION_STEPS_PER_METRE).ceil() as u64;
    let mut fits = None;
    for _ in 0..TRIES {
        let candidate = steps as f64 / RESOLUTION_STEPS_PER_METRE;
        let mut s = *c.settings();
        s.resolution = candidate;
        let Ok(checked) = s.validate() else { break };
        let Ok(geometry) = plan(&checked) else { break };
        if tiles_needed(scans, poses, &geometry, &checked) <= budget_tiles {
            fits = Some(candidate);
            break;
        }
        steps += 1;
    }
    let cells = needed as u128 * TILE_CELLS as u128;
    let b = bytes_per_cell as u128;
    let advice = match fits {
        Some(r) => format!("{} m or coarser fits", show(r)),
        None => "a coarser resolution".to_string(),
    };
    Err(invalid(
        "resolution",
        format!("{} m", show(resolution)),
        format!(
            "a map this log fits in: its beams would reach {needed} tiles of {TILE_SIDE} x {TILE_SIDE} cells \
             ({cells} cells, {}), over the {budget_cells} cells ({}) a map may hold; {advice}",
            mebibytes(cells * b),
            mebibytes(budget_cells as u128 * b),
        ),
    ))
}

/// The poses a budget check walks for `source`: the pane's own, except a
/// scan-matched pane's (its odometry, before matching), for which the
/// log's own poses stand in.
pub(super) fn estimate_poses<'a>(
    scans: &'a LaserScans,
    source: LogPoses,
    poses: &'a [Pose],
) -> &'a [Pose] {
    match source {
        LogPoses::ScanMatched => scans.poses(),
        _ => poses,
    }
}
