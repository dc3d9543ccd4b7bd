//! A step of the fusion run in pieces, so that a page's call stops within
//! its budget mid-step (docs/ARCHITECTURE.md, "Sessions and panes").
//!
//! A step at a fine resolution (0.0125 m: 192,000 cells) sweeps every cell
//! twice for the sonar (its own map and the summed one, Table 9.1 as
//! printed), about 30 ms in a browser: one call of at least a whole step
//! was a long task. Here a step is its two scans' simulation (a piece
//! each), the sonar's sweep of its map in bands of rows, the LiDAR's
//! rasters, then the sonar's sweep of the summed map in bands and the
//! LiDAR's rasters into it: the order of [`TableFusion::integrate_step`],
//! each cell's update depending on that
//! cell alone ([`sweep_rows`]), so the maps are those of a whole step bit
//! for bit. The pieces write copies of the maps, swapped in once the step
//! is whole: what the widget shows (maps, readouts) changes a whole step at
//! a time.

use super::TableFusion;
use crate::grid::LogOddsGrid;
use crate::mapping::sweep::sweep_rows;

/// A step's pieces count their work in cells of the sonar's sweep, the
/// unit a page's budget is learned in: a call's time then follows its
/// count whatever its pieces. A scan's simulation is counted as its rays'
/// cells out to `z_max` ([`crate::scenes::table::TableRun::simulate_through`]),
/// a raster as the cells its beams cross, and each such cell costs a
/// fraction of a swept cell (measured in Chromium at 0.0125 m: a swept
/// cell 40 ns; a sonar cone's cell 3.5 ns, a LiDAR ray's 1.3 ns, a raster's
/// cell 4 ns): this many of them count as one.
const SONAR_CAST_CELLS_PER_VISIT: u64 = 8;
const LIDAR_CAST_CELLS_PER_VISIT: u64 = 16;
const RASTER_CELLS_PER_VISIT: u64 = 8;

/// What a step under way does next, in the order of a whole step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Piece {
    /// The step's sonar scan simulated, if it is not yet.
    SimulateSonar,
    /// The step's LiDAR scan simulated, if it is not yet.
    SimulateLidar,
    /// The sonar's sweep of its own map, from this row on.
    SonarRows(usize),
    Lidar,
    /// The sonar's sweep of the summed map, from this row on.
    SummedRows(usize),
    SummedLidar,
    Whole,
}

/// A step being integrated in pieces: copies of the maps it writes.
#[derive(Debug, Clone)]
pub(super) struct StepUnderWay {
    k: usize,
    /// A new step (the three maps), or a step rebuilt into the LiDAR's two
    /// maps after a beam count changed.
    new_step: bool,
    next: Piece,
    sonar: Option<LogOddsGrid>,
    lidar: LogOddsGrid,
    summed: LogOddsGrid,
}

impl StepUnderWay {
    /// True for a new step, false for a rebuilt one.
    pub fn is_new(&self) -> bool {
        self.new_step
    }
}

/// The rows from `from` on that a sweep of about `budget` cell visits
/// takes, at least one, in a map `width` x `height`.
fn band(from: usize, width: usize, height: usize, budget: u64) -> std::ops::Range<usize> {
    let rows = (budget / width.max(1) as u64).clamp(1, height as u64) as usize;
    from..(from + rows).min(height)
}

impl TableFusion {
    /// Begins the next step (`new_step`) or the next step the LiDAR's maps
    /// lack, in pieces.
    pub(super) fn begin_step(&mut self, new_step: bool) {
        self.under_way = Some(StepUnderWay {
            k: if new_step { self.next } else { self.lidar_next },
            new_step,
            next: Piece::SimulateSonar,
            sonar: new_step.then(|| self.sonar.clone()),
            lidar: self.lidar.clone(),
            summed: self.summed.clone(),
        });
    }

    /// Works the step under way while less than `budget` cell visits are
    /// spent, at least one piece: returns the visits (the simulation's cost
    /// included) and whether the step is now whole (its maps swapped in).
    /// `None`, the step dropped, when there is none or it lies past the
    /// run's end.
    pub(super) fn work_step(&mut self, budget: u64) -> Option<(u64, bool)> {
        let mut spent = 0u64;
        loop {
            let Some(visits) = self.piece(budget.saturating_sub(spent)) else {
                self.under_way = None;
                return None;
            };
            spent = spent.saturating_add(visits);
            if self.under_way.as_ref()?.next == Piece::Whole {
                self.swap_in();
                return Some((spent.max(1), true));
            }
            if spent >= budget {
                return Some((spent, false));
            }
        }
    }

    /// One piece of the step under way, of about `budget` visits (a band
    /// of at least one row); returns its visits.
    fn piece(&mut self, budget: u64) -> Option<u64> {
        let w = self.under_way.as_mut()?;
        let k = w.k;
        let (width, height) = (w.lidar.geometry().width(), w.lidar.geometry().height());
        let visits = match w.next {
            // A validated scene's sensors refuse no reading (`TableScene::
            // validate` checks what a cast refuses): an error here would be
            // a bug, and the run stops at it.
            Piece::SimulateSonar => {
                let cost = self.run.simulate_sensor_through(k + 1, false).ok()?;
                let cost = cost.div_ceil(SONAR_CAST_CELLS_PER_VISIT);
                self.run.sonar().get(k)?;
                w.next = Piece::SimulateLidar;
                cost
            }
            Piece::SimulateLidar => {
                let cost = self.run.simulate_sensor_through(k + 1, true).ok()?;
                let cost = cost.div_ceil(LIDAR_CAST_CELLS_PER_VISIT);
                self.run.lidar().get(k)?;
                w.next = if w.new_step {
                    Piece::SonarRows(0)
                } else {
                    Piece::Lidar
                };
                cost
            }
            Piece::SonarRows(from) | Piece::SummedRows(from) => {
                let scan = self.run.sonar().get(k)?;
                let rows = band(from, width, height, budget);
                let own = matches!(w.next, Piece::SonarRows(_));
                let grid = if own {
                    w.sonar.as_mut()?
                } else {
                    &mut w.summed
                };
                let stats = sweep_rows(grid, &self.sonar_model, scan, rows.clone());
                w.next = match (own, rows.end >= height) {
                    (true, true) => Piece::Lidar,
                    (true, false) => Piece::SonarRows(rows.end),
                    (false, true) => Piece::SummedLidar,
                    (false, false) => Piece::SummedRows(rows.end),
                };
                stats.cells_visited as u64
            }
            Piece::Lidar => {
                let scan = self.run.lidar().get(k)?;
                let stats = self
                    .lidar_mapper
                    .integrate(&mut w.lidar, &self.lidar_model, scan);
                w.next = Piece::SummedRows(0);
                (stats.cells_visited as u64).div_ceil(RASTER_CELLS_PER_VISIT)
            }
            Piece::SummedLidar => {
                let scan = self.run.lidar().get(k)?;
                let stats = self
                    .summed_mapper
                    .integrate(&mut w.summed, &self.lidar_model, scan);
                w.next = Piece::Whole;
                (stats.cells_visited as u64).div_ceil(RASTER_CELLS_PER_VISIT)
            }
            Piece::Whole => 0,
        };
        Some(visits)
    }

    /// The whole step's maps in place of the shown ones.
    fn swap_in(&mut self) {
        let Some(w) = self.under_way.take() else {
            return;
        };
        if let Some(sonar) = w.sonar {
            self.sonar = sonar;
        }
        self.lidar = w.lidar;
        self.summed = w.summed;
        if w.new_step {
            self.next += 1;
            self.lidar_next = self.next;
        } else {
            self.lidar_next += 1;
        }
    }

    /// Finishes a step under way at once; `Some(true)` for a new step made
    /// whole, `Some(false)` for a rebuilt one, `None` when there was none.
    pub(super) fn finish_under_way(&mut self) -> Option<bool> {
        let new_step = self.under_way.as_ref()?.is_new();
        let (_, whole) = self.work_step(u64::MAX)?;
        whole.then_some(new_step)
    }
}
