//! How one scan of a real log is written into a map, written once for
//! every map of a log (the panes' maps, and a pose source's own):
//! Table 9.2's model with the range cap as `z_max` (or the laser's own
//! shorter maximum range), the beams' bands of evidence that stop at the
//! wall a beam grazes ([`beam_bands`]), and the ray traversal of Table 9.1
//! ([`RayMapper`]), with the space between beams when asked for; and,
//! with the free space that rests on evidence ([`WallModel::Incidence`]),
//! the cell the laser stood in ([`LASER_CELL_EVIDENCE`]).

use crate::error::{self, invalid, Result};
use crate::grid::{CellModel, Grid, Store};
use crate::inverse::{HandCrafted, HandCraftedParams};
use crate::mapping::traversal::{BeamBand, RayMapper, ScanStats};
use crate::mapping::walls::{beam_bands, WallModel};
use crate::sensors::Scan;

/// The evidence given to the cell the laser stood in at each scan, under
/// [`WallModel::Incidence`]: the laser was there, so the cell held free
/// space, the strongest free evidence there is; every cell model takes it
/// as far as it goes (the log-odds filter to its clamp, a counting cell
/// one visit without a hit, the hit/miss odds one miss). Without it the
/// robot's own path rests on the beams that cross it: where no-returns
/// clear nothing (outdoors, where most beams see open sky) that is a few
/// returns' free lines per scan, too weak for the log-odds filter to
/// cross `map_server`'s free threshold (Table 9.2's `l_free` of -0.4 needs
/// four, `logit(0.196)` being -1.41), so a planner finds the robot standing
/// in unknown space. One cell per scan: no cost a scan's beams would feel.
pub const LASER_CELL_EVIDENCE: f32 = f32::MIN;

/// How a scan is written into the map: Table 9.2's model (its `z_max` the
/// range cap), how far a no-return clears, how free evidence ends before
/// a wall ([`WallModel`]), and whether the space between neighbouring
/// beams is filled ([`RayMapper::integrate_bands_between`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanInsertion {
    pub model: HandCraftedParams,
    /// Metres a no-return clears (at most the model's `z_max` is used).
    pub no_return_reach: f64,
    pub walls: WallModel,
    pub between_beams: bool,
}

impl ScanInsertion {
    /// Checks the model (its own field names) and the reach.
    pub fn validate(&self) -> Result<HandCrafted> {
        let model = HandCrafted::new(self.model)?;
        error::positive("no_return_reach", self.no_return_reach)?;
        let p = &self.model;
        if !((p.l_occ - p.l0) as f32 > 0.0 && ((p.l_free - p.l0) as f32) < 0.0) {
            return Err(invalid(
                "l_occ, l_free",
                format!("{}, {}", error::show(p.l_occ), error::show(p.l_free)),
                "occupied evidence above l0 and free evidence below it",
            ));
        }
        Ok(model)
    }
}

/// Writes scans into a map, one at a time ([`ScanInsertion`]), keeping the
/// traversal's scratch between scans.
#[derive(Debug, Clone)]
pub struct ScanInserter {
    insertion: ScanInsertion,
    model: HandCrafted,
    /// The model of the last laser whose own maximum range is shorter than
    /// the cap, with that range: built once per such laser, not per scan.
    short_model: Option<(f64, HandCrafted)>,
    mapper: RayMapper,
    bands: Vec<Option<BeamBand>>,
}

impl ScanInserter {
    pub fn new(insertion: ScanInsertion) -> Result<Self> {
        Ok(Self {
            model: insertion.validate()?,
            insertion,
            short_model: None,
            mapper: RayMapper::new(),
            bands: Vec::new(),
        })
    }

    /// An inserter of `insertion` whose model was built already (by the
    /// one validation of the settings it came from).
    pub fn with_model(insertion: ScanInsertion, model: HandCrafted) -> Self {
        Self {
            model,
            insertion,
            short_model: None,
            mapper: RayMapper::new(),
            bands: Vec::new(),
        }
    }

    pub fn insertion(&self) -> &ScanInsertion {
        &self.insertion
    }

    /// The model for a scan whose laser reaches `laser_max` metres: a
    /// laser that says its own maximum range is shorter than the cap
    /// reports no-returns at that maximum, which the model must treat as
    /// no-returns, not as walls at the maximum.
    pub fn model_for(&mut self, laser_max: f64) -> HandCrafted {
        let cap = self.insertion.model.z_max;
        if laser_max >= cap || laser_max.is_nan() {
            return self.model;
        }
        if let Some((max, model)) = self.short_model {
            if max == laser_max {
                return model;
            }
        }
        match HandCrafted::new(HandCraftedParams {
            z_max: laser_max,
            ..self.insertion.model
        }) {
            Ok(model) => {
                self.short_model = Some((laser_max, model));
                model
            }
            Err(_) => self.model,
        }
    }

    /// Integrates `scan` at its own pose into `grid` (`laser_max` the
    /// laser's own maximum range, infinite when the log does not say):
    /// what the traversal did. Beams past the map's edge are clipped; past
    /// the store's budget nothing more is written ([`Grid::refused`] says
    /// so).
    pub fn insert<C: CellModel, S: Store<C::Cell>>(
        &mut self,
        grid: &mut Grid<C, S>,
        scan: &Scan,
        laser_max: f64,
    ) -> ScanStats {
        let model = self.model_for(laser_max);
        let ins = self.insertion;
        let res = grid.geometry().resolution();
        beam_bands(
            scan,
            &model,
            ins.no_return_reach,
            ins.walls,
            res,
            &mut self.bands,
        );
        let p = model.params();
        let evidence = ((p.l_free - p.l0) as f32, (p.l_occ - p.l0) as f32);
        let mut stats = self.mapper.integrate_bands_between(
            grid,
            scan,
            &self.bands,
            evidence,
            ins.between_beams,
        );
        if ins.walls == WallModel::Incidence {
            let pose = scan.pose();
            if let Some((ix, iy)) = grid.geometry().world_to_cell(pose.x, pose.y) {
                grid.apply_at(ix, iy, LASER_CELL_EVIDENCE);
                stats.cells_updated += 1;
            }
        }
        stats
    }
}
