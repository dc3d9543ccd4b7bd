//! How far a log's scans reach, before and beyond a map build: the box of
//! every laser pose and every cell a beam marks or clears, a no-return's
//! clearing included (what a real log's grid must hold), the grid that
//! covers that box, and the tiles the beams of every scan would touch (what
//! a tiled map would allocate, checked before a build).
//!
//! The scans come as [`Scan`]s at whatever poses a pose source gives them
//! (the log's corrected ones, a dead-reckoned path): one extent and one
//! estimate for every pose source.

use crate::error::{self, invalid, Result};
use crate::geometry::raster::{Cursor as RasterCursor, Walk};
use crate::geometry::GridGeometry;
use crate::grid::storage::{tiles_of, TILE_SIDE};
use crate::inverse::HandCrafted;
use crate::mapping::walls::{beam_bands, WallModel};
use crate::sensors::Scan;

/// The box `[min_x, min_y, max_x, max_y]` (metres) holding every laser
/// pose and every cell the beams carve or mark: each beam's band out to its
/// reach (a return's `z + α/2`, a no-return's clearing out to
/// `no_return_reach`), as [`beam_bands`] makes them with each scan's model
/// (the one of its laser's own maximum range). `None` when there are no
/// scans. A box of endpoints alone would cut off the free space that
/// no-returns carve past the last wall (docs/ARCHITECTURE.md, "Real logs").
pub fn scan_extent(
    scans: impl IntoIterator<Item = (Scan, HandCrafted)>,
    no_return_reach: f64,
) -> Option<[f64; 4]> {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut any = false;
    let mut grow = |x: f64, y: f64| {
        b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    };
    let mut bands = Vec::new();
    for (scan, model) in scans {
        any = true;
        let pose = scan.pose();
        grow(pose.x, pose.y);
        // (Where free evidence ends near a wall does not move a band's
        // reach: the cheaper Table 9.2 bands serve.)
        beam_bands(
            &scan,
            &model,
            no_return_reach,
            WallModel::Table92,
            1.0,
            &mut bands,
        );
        for (band, &bearing) in bands.iter().zip(scan.bearings()) {
            if let Some(band) = band {
                let (x, y) = pose.point_at(band.reach, bearing);
                grow(x, y);
            }
        }
    }
    any.then_some(b)
}

/// The grid covering `extent` plus a free border of `margin` metres, its
/// corners on whole multiples of `resolution` (so that maps of one log at
/// one resolution line up cell for cell). Its cells are allocated in tiles
/// as the beams reach them, so the bounding box is limited only by its
/// export ([`GridGeometry::sparse`]). The fields are named as a page
/// spells them (`resolution`, `margin`).
pub fn covering_grid(extent: [f64; 4], resolution: f64, margin: f64) -> Result<GridGeometry> {
    let r = error::positive("resolution", resolution)?;
    let m = error::non_negative("margin", margin)?;
    let [x0, y0, x1, y1] = extent;
    let (i0, j0) = (((x0 - m) / r).floor(), ((y0 - m) / r).floor());
    let (i1, j1) = (((x1 + m) / r).floor() + 1.0, ((y1 + m) / r).floor() + 1.0);
    let (w, h) = (i1 - i0, j1 - j0);
    // Written so that a NaN (cells so small that both edges overflow to
    // the same infinity) is refused too; `GridGeometry::sparse` then says
    // what the size would weigh.
    if !(w >= 1.0 && h >= 1.0 && w * h <= 1e15) {
        return Err(invalid(
            "width x height",
            format!("{w} x {h}"),
            "at most 268435456 cells (a 256 MiB image): a coarser resolution",
        ));
    }
    // Rounded to a nanometre: -418 cells of 0.05 m is -20.900000000000002
    // in binary, and the exported YAML should read -20.9.
    let round = |v: f64| (v * 1e9).round() / 1e9;
    let (ox, oy) = (round(i0 * r), round(j0 * r));
    // Absurdly large cells put the corners beyond f64 (the rounding above
    // overflows first): the page sent a resolution, so name it.
    let corners = [ox, oy, ox + w * r, oy + h * r];
    if !corners.iter().all(|c| c.is_finite()) {
        return Err(invalid(
            "resolution",
            error::show(r),
            "cells small enough that the map's corners are finite numbers of metres",
        ));
    }
    GridGeometry::sparse(w as usize, h as usize, r, ox, oy)
}

/// How a beam's free evidence is bounded: what [`tiles_reached`] walks.
#[derive(Debug, Clone, Copy)]
pub struct BeamReach<'a> {
    /// The inverse model of Table 9.2 (its `z_max` decides no-returns).
    pub model: &'a HandCrafted,
    /// How far a no-return clears, metres.
    pub no_return_reach: f64,
    /// Where free evidence ends near a wall.
    pub walls: WallModel,
}

/// The tiles the beams of every scan reach on `extent`, walked on the grid
/// of tiles (a tile holding a cell a beam crosses is one the beam
/// crosses): what the whole log would allocate in a tiled map.
pub fn tiles_reached(
    extent: &GridGeometry,
    scans: impl IntoIterator<Item = Scan>,
    reach: BeamReach<'_>,
) -> usize {
    let (tx, ty) = tiles_of(extent);
    let mut marks = vec![false; tx * ty];
    let mut bands = Vec::new();
    let per_tile = 1.0 / (extent.resolution() * TILE_SIDE as f64);
    for scan in scans {
        beam_bands(
            &scan,
            reach.model,
            reach.no_return_reach,
            reach.walls,
            extent.resolution(),
            &mut bands,
        );
        let p = scan.pose();
        let (su, sv) = extent.world_to_grid(p.x, p.y);
        let start = (su / TILE_SIDE as f64, sv / TILE_SIDE as f64);
        for (band, &b) in bands.iter().zip(scan.bearings()) {
            let Some(band) = band else { continue };
            let (sn, cs) = (p.theta + b).sin_cos();
            let end = (
                start.0 + band.reach * per_tile * cs,
                start.1 + band.reach * per_tile * sn,
            );
            if let Some(walk) = Walk::new(tx, ty, start, end) {
                let mut m = TileMarks {
                    at: walk.start,
                    step: walk.step,
                    width: tx,
                    marks: &mut marks,
                };
                walk.run(&mut m);
            }
        }
    }
    marks.iter().filter(|&&m| m).count()
}

/// Marks the tiles a walk on the grid of tiles visits.
struct TileMarks<'a> {
    at: (usize, usize),
    step: (i8, i8),
    width: usize,
    marks: &'a mut [bool],
}

impl RasterCursor for TileMarks<'_> {
    fn visit(&mut self) {
        if let Some(m) = self.marks.get_mut(self.at.1 * self.width + self.at.0) {
            *m = true;
        }
    }
    fn step_x(&mut self) {
        self.at.0 = self.at.0.wrapping_add_signed(self.step.0 as isize);
    }
    fn step_y(&mut self) {
        self.at.1 = self.at.1.wrapping_add_signed(self.step.1 as isize);
    }
    fn unstep_x(&mut self) {
        self.at.0 = self.at.0.wrapping_add_signed(-(self.step.0 as isize));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Pose;

    /// A return's band ends `α/2` past it; a no-return clears out to the
    /// no-return reach (or its laser's own maximum, if shorter): the box
    /// holds both.
    #[test]
    fn the_extent_holds_poses_and_every_band_s_reach() {
        use crate::inverse::HandCraftedParams;
        let scan = |x: f64| {
            Scan::uniform(Pose::new(x, 0.0, 0.0).unwrap(), vec![2.0, 50.0], 0.0, 1.0).unwrap()
        };
        let model = |z_max: f64| HandCrafted::new(HandCraftedParams::laser(z_max)).unwrap();
        let alpha = model(30.0).params().alpha;
        let e = scan_extent([(scan(0.0), model(30.0))], 5.0).unwrap();
        // The 2 m return along x ends at 2 + α/2; the 50 m no-return
        // (bearing 1 rad) clears 5 m.
        let (x1, y1) = (5.0 * 1f64.cos(), 5.0 * 1f64.sin());
        let near = |a: [f64; 4], b: [f64; 4]| a.iter().zip(b).all(|(p, q)| (p - q).abs() < 1e-9);
        assert!(near(e, [0.0, 0.0, x1.max(2.0 + alpha / 2.0), y1]), "{e:?}");
        // A laser whose own maximum is 1.5 m: both readings are its no-returns.
        let e = scan_extent([(scan(1.0), model(1.5))], 5.0).unwrap();
        assert!(near(e, [1.0, 0.0, 2.5, 1.5 * 1f64.sin()]), "{e:?}");
        assert!(scan_extent(std::iter::empty(), 5.0).is_none());
    }

    #[test]
    fn the_covering_grid_lines_up_on_whole_cells() {
        let g = covering_grid([-20.87, 0.01, 1.0, 2.0], 0.05, 0.0).unwrap();
        assert_eq!(g.origin(), [-20.9, 0.0]);
        assert!(covering_grid([0.0, 0.0, 1.0, 1.0], 0.0, 1.0).is_err());
        assert!(covering_grid([0.0, 0.0, 1.0, 1.0], 0.1, -1.0).is_err());
    }
}
