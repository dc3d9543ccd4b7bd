//! Map Weaver's work in bounded calls.
//!
//! A page that plays the lap asks, once per animation frame, for the scans
//! the frame owes and gives a budget of cell visits ([`Weaver::work`]); a
//! knob turned mid-lap starts its pane again from the empty map
//! ([`Weaver::stage_pane`]) and the same calls bring it back up to the
//! scans so far. No call does much more than its budget: a pane mapped by
//! ray traversal takes a whole scan at a time (its cells are gathered over
//! every beam before each is updated once, Table 9.1, so a scan cannot be
//! cut), and a pane mapped by the literal sweep takes a band of rows of a
//! scan at a time (each cell's update depends on that cell alone, so the
//! bands leave the grid exactly as one sweep would). The view, the curves
//! and the ghost watch take their point when a scan's last row is swept,
//! so a pane built in slices is bit for bit the pane built in one go.
//!
//! [`Weaver::advance`] and [`Weaver::set_pane`] keep their meaning: they
//! are these calls with no budget.

use super::pane::Pane;
use super::pane::{PaneModel, PoseScans, SweepProgress, WeaverMap};
use super::settings::{renamed, MapperKind, PaneSettings};
use super::Weaver;
use crate::error::Result;
use crate::mapping::sweep::sweep_rows;
use crate::mapping::traversal::ScanStats;
use crate::sensors::Scan;
use std::ops::Range;

/// What one call of [`Weaver::work`] did, and what is left.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct WorkReport {
    /// New scans simulated by this call (each is integrated into both
    /// panes, over this call and perhaps later ones).
    pub scans: usize,
    /// Cell visits this call spent, the budget's unit: a traversal scan's
    /// visits along its beams, or a swept band's cells.
    pub cell_visits: u64,
    /// Scans each pane has still to integrate to reach the scans so far: a
    /// rebuild or a sweep under way.
    pub behind: [usize; 2],
    /// True once the run's laps are done and both panes have every scan.
    pub done: bool,
}

impl Weaver {
    /// Scans pane `pane` has still to integrate to reach the scans so far.
    fn behind(&self, pane: usize) -> usize {
        self.history.len() - self.panes[pane].scans_done()
    }

    /// Where the work stands, without doing any.
    pub fn progress(&self) -> WorkReport {
        let behind = [self.behind(0), self.behind(1)];
        WorkReport {
            scans: 0,
            cell_visits: 0,
            behind,
            done: self.done() && behind == [0, 0],
        }
    }

    /// Changes every knob of pane `pane` at once and starts the pane again
    /// from the empty map with them: [`Weaver::work`] then integrates the
    /// scans so far before any new one, so that the map shows what these
    /// settings give for the same scans (a clamp turned to 1 and back to 12
    /// leaves the map as if it had never moved). Returns false when the
    /// settings were those the pane had. Nothing changes when `settings`
    /// is refused.
    pub fn stage_pane(&mut self, pane: usize, settings: PaneSettings) -> Result<bool> {
        let current = self.pane(pane)?.settings;
        if settings.resolution != current.resolution {
            return Ok(self.swap_pane(pane, settings)?.is_some());
        }
        settings.validate(pane, &self.settings.scene)?;
        if settings == current {
            return Ok(false);
        }
        // The same cells: the pane is emptied in place rather than made
        // anew (a slider dragged over a large map stages many times).
        let model = PaneModel::build(&settings, &self.settings.hand_crafted, &self.learned)?;
        let p = &mut self.panes[pane];
        p.map
            .grid_mut()
            .set_clamp(settings.clamp)
            .map_err(|e| renamed(&format!("panes[{pane}].clamp"), e))?;
        p.model = model;
        p.settings = settings;
        p.clear();
        self.settings.panes[pane] = settings;
        Ok(true)
    }

    /// [`Weaver::stage_pane`], returning the pane it replaced (`None` when
    /// nothing changed).
    pub(super) fn swap_pane(
        &mut self,
        pane: usize,
        settings: PaneSettings,
    ) -> Result<Option<Pane>> {
        let current = self.pane(pane)?.settings;
        settings.validate(pane, &self.settings.scene)?;
        if settings == current {
            return Ok(None);
        }
        let fresh = Pane::new(&self.settings, &self.learned, pane, &settings)?;
        self.settings.panes[pane] = settings;
        Ok(Some(std::mem::replace(&mut self.panes[pane], fresh)))
    }

    /// Brings pane `pane` up to the scans so far, with no budget.
    pub(super) fn catch_up(&mut self, pane: usize) -> Result<()> {
        while self.behind(pane) > 0 {
            self.step_pane(pane, u64::MAX)?;
        }
        Ok(())
    }

    /// Works for at most about `budget` cell visits: first the scans a
    /// pane lacks (a rebuild, a sweep under way), then up to `scans` new
    /// scans of the lap, simulated and integrated into both panes. Each
    /// call makes progress while there is work (a budget of 0 counts as 1),
    /// and goes past its budget by at most one traversal scan or one row
    /// of a sweep.
    pub fn work(&mut self, scans: usize, budget: u64) -> Result<WorkReport> {
        let budget = budget.max(1);
        let (mut spent, mut taken) = (0u64, 0usize);
        while spent < budget {
            if let Some(k) = (0..2).find(|&k| self.behind(k) > 0) {
                spent = spent.saturating_add(self.step_pane(k, budget - spent)?);
                continue;
            }
            if taken >= scans || self.done() {
                break;
            }
            let scan = self.sim.next_scan();
            // A scan the panes cannot take is refused before it is kept.
            PoseScans::new(&scan, self.sim.bearings())?;
            self.history.push(scan);
            taken += 1;
        }
        Ok(WorkReport {
            scans: taken,
            cell_visits: spent,
            ..self.progress()
        })
    }

    /// One piece of pane `pane`'s next scan, of about `allowance` cell
    /// visits: a whole traversal scan, or a band of a sweep's rows (at
    /// least one). Returns the cell visits it took.
    fn step_pane(&mut self, pane: usize, allowance: u64) -> Result<u64> {
        let clock = self.clock;
        let p = &mut self.panes[pane];
        let index = p.scans_done();
        let sim = &self.history[index];
        let scans = PoseScans::new(sim, self.sim.bearings())?;
        let s = p.scan(&scans)?;
        let started = clock.map(|c| c());
        match p.settings.mapper {
            MapperKind::Traversal => {
                let stats = p.model.integrate(MapperKind::Traversal, &mut p.map, &s);
                p.finish_scan(&s, stats, sim, index + 1, clock, started.map(|t| (t, 0.0)));
                Ok((stats.cells_visited as u64).max(1))
            }
            MapperKind::Sweep => {
                let (width, height) = (p.geometry.width(), p.geometry.height());
                let from = p.sweep.rows;
                let rows = usize::try_from(allowance / width.max(1) as u64)
                    .unwrap_or(usize::MAX)
                    .clamp(1, height - from);
                let band = p.model.sweep_rows(&mut p.map, &s, from..from + rows);
                p.sweep.rows += rows;
                p.sweep.stats.cells_visited += band.cells_visited;
                p.sweep.stats.cells_updated += band.cells_updated;
                if p.sweep.rows < height {
                    if let (Some(c), Some(t0)) = (clock, started) {
                        p.sweep.ms += (c() - t0).max(0.0);
                    }
                } else {
                    let SweepProgress { stats, ms, .. } = std::mem::take(&mut p.sweep);
                    p.map.count(&s, stats);
                    p.finish_scan(&s, stats, sim, index + 1, clock, started.map(|t| (t, ms)));
                }
                Ok(band.cells_visited as u64)
            }
        }
    }
}

impl PaneModel {
    /// The literal sweep of Table 9.1 over rows `rows` of `map`'s grid.
    fn sweep_rows(&self, map: &mut WeaverMap, scan: &Scan, rows: Range<usize>) -> ScanStats {
        match self {
            Self::HandCrafted(m) => sweep_rows(map.grid_mut(), m, scan, rows),
            Self::Learned(m) => sweep_rows(map.grid_mut(), &**m, scan, rows),
        }
    }
}

#[cfg(test)]
#[path = "stepping_tests.rs"]
mod tests;
