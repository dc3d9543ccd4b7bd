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
use crate::inverse::{HandCrafted, InverseModel};
use crate::mapping::traversal::BeamBand;
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
    let mut extent = ExtentBox::new(no_return_reach);
    for (scan, model) in scans {
        extent.add(&scan, &model);
    }
    extent.bounds()
}

/// [`scan_extent`] a scan at a time: a log's extent grown as its scans are
/// read, so that no walk over every scan is left for when the last one is
/// (docs/ARCHITECTURE.md, "Real logs"). Adding the same scans in the same
/// order gives the same box, bit for bit, as [`scan_extent`].
#[derive(Debug, Clone)]
pub struct ExtentBox {
    no_return_reach: f64,
    bounds: [f64; 4],
    /// Scans walked (added or skipped), and whether any was added.
    scans: usize,
    any: bool,
}

impl ExtentBox {
    /// An empty box for beams whose no-returns clear `no_return_reach`.
    pub fn new(no_return_reach: f64) -> Self {
        Self {
            no_return_reach,
            bounds: [
                f64::INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
            ],
            scans: 0,
            any: false,
        }
    }

    /// Grows the box by `scan`'s pose and its beams' bands under `model`.
    pub fn add(&mut self, scan: &Scan, model: &HandCrafted) {
        self.scans += 1;
        self.any = true;
        let b = &mut self.bounds;
        let mut grow = |x: f64, y: f64| {
            *b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        };
        let pose = scan.pose();
        grow(pose.x, pose.y);
        for (&z, &bearing) in scan.ranges().iter().zip(scan.bearings()) {
            if let Some(reach) = band_reach(model, z, self.no_return_reach) {
                let (x, y) = pose.point_at(reach, bearing);
                grow(x, y);
            }
        }
    }

    /// Passes over a scan that has no place on the map (a log's scan at a
    /// pose that is not a number): walked, and not in the box.
    pub fn skip(&mut self) {
        self.scans += 1;
    }

    /// Scans walked so far (added or skipped).
    pub fn scans(&self) -> usize {
        self.scans
    }

    /// The box, `None` before a scan is added.
    pub fn bounds(&self) -> Option<[f64; 4]> {
        self.any.then_some(self.bounds)
    }
}

/// How far the band [`beam_bands`] makes for a reading `z` reaches, `None`
/// for a beam with nothing to walk: a return's `z + α/2`, a no-return's
/// clearing out to `no_return_reach` at most. (Where free evidence ends
/// near a wall does not move a band's reach; one beam at a time, so that
/// growing a log's extent as it is read keeps no buffer of a scan's
/// bands.)
fn band_reach(model: &HandCrafted, z: f64, no_return_reach: f64) -> Option<f64> {
    let reach = model.reach(z);
    model.axis_profile(z).filter(|_| reach > 0.0)?;
    Some(if z < model.z_max() {
        reach
    } else {
        reach.min(no_return_reach)
    })
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
    let mut tiles = TileReach::new(extent);
    for scan in scans {
        tiles.add(&scan, reach);
    }
    tiles.count()
}

/// [`tiles_reached`] a scan at a time, so that a page can walk a long log
/// in calls of bounded work.
#[derive(Debug, Clone)]
pub struct TileReach {
    extent: GridGeometry,
    /// Per tile (row-major on the grid of tiles), true once a beam reaches it.
    marks: Vec<bool>,
    /// Tiles marked so far.
    count: usize,
    /// Scratch: the current scan's bands.
    bands: Vec<Option<BeamBand>>,
}

impl TileReach {
    /// No tile reached yet on `extent`'s grid of tiles.
    pub fn new(extent: &GridGeometry) -> Self {
        let (tx, ty) = tiles_of(extent);
        Self {
            extent: *extent,
            marks: vec![false; tx * ty],
            count: 0,
            bands: Vec::new(),
        }
    }

    /// Marks the tiles `scan`'s beams reach.
    pub fn add(&mut self, scan: &Scan, reach: BeamReach<'_>) {
        let extent = &self.extent;
        let (tx, ty) = tiles_of(extent);
        let per_tile = 1.0 / (extent.resolution() * TILE_SIDE as f64);
        beam_bands(
            scan,
            reach.model,
            reach.no_return_reach,
            reach.walls,
            extent.resolution(),
            &mut self.bands,
        );
        let p = scan.pose();
        let (su, sv) = extent.world_to_grid(p.x, p.y);
        let start = (su / TILE_SIDE as f64, sv / TILE_SIDE as f64);
        for (band, &b) in self.bands.iter().zip(scan.bearings()) {
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
                    marks: &mut self.marks,
                    count: &mut self.count,
                };
                walk.run(&mut m);
            }
        }
    }

    /// Tiles reached so far.
    pub fn count(&self) -> usize {
        self.count
    }
}

/// Marks the tiles a walk on the grid of tiles visits.
struct TileMarks<'a> {
    at: (usize, usize),
    step: (i8, i8),
    width: usize,
    marks: &'a mut [bool],
    count: &'a mut usize,
}

impl RasterCursor for TileMarks<'_> {
    fn visit(&mut self) {
        if let Some(m) = self.marks.get_mut(self.at.1 * self.width + self.at.0) {
            *self.count += !*m as usize;
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

    /// One beam's reach is the reach of the band `beam_bands` makes for it,
    /// for returns, no-returns, readings past the cap and no reading.
    #[test]
    fn a_beam_s_reach_is_its_band_s() {
        use crate::inverse::HandCraftedParams;
        let model = HandCrafted::new(HandCraftedParams::laser(30.0)).unwrap();
        let ranges = vec![0.0, 0.01, 2.0, 29.99, 30.0, 45.0, 81.9];
        let n = ranges.len();
        let scan = Scan::uniform(
            Pose::new(1.0, -2.0, 0.4).unwrap(),
            ranges.clone(),
            -1.0,
            2.0 / n as f64,
        )
        .unwrap();
        let mut bands = Vec::new();
        beam_bands(&scan, &model, 5.0, WallModel::Table92, 1.0, &mut bands);
        let reaches: Vec<_> = ranges.iter().map(|&z| band_reach(&model, z, 5.0)).collect();
        let expected: Vec<_> = bands.iter().map(|b| b.map(|b| b.reach)).collect();
        assert_eq!(reaches, expected);
        assert!(reaches.iter().any(Option::is_some));
    }

    #[test]
    fn the_covering_grid_lines_up_on_whole_cells() {
        let g = covering_grid([-20.87, 0.01, 1.0, 2.0], 0.05, 0.0).unwrap();
        assert_eq!(g.origin(), [-20.9, 0.0]);
        assert!(covering_grid([0.0, 0.0, 1.0, 1.0], 0.0, 1.0).is_err());
        assert!(covering_grid([0.0, 0.0, 1.0, 1.0], 0.1, -1.0).is_err());
    }
}
