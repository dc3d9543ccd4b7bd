//! What every beam of a scan shares ([`BeamFrame`]: the sensor, the grid,
//! the window its verdicts are gathered in) and where a beam's walk stands
//! ([`BeamState`]).

use super::{Code, Codes, Gathered, Pending, SEGMENT, UNTOUCHED};
use crate::geometry::raster::Walk;
use crate::geometry::{GridGeometry, Pose};
use crate::grid::{CellModel, Store, Window};

/// What every beam of a scan shares: the sensor in grid coordinates, the
/// grid's size and resolution, the heading, and the window of the map the
/// scan's verdicts are gathered in.
pub(super) struct BeamFrame {
    pub(super) su: f64,
    pub(super) sv: f64,
    pub(super) res: f64,
    /// `1 / res`: cells per metre.
    pub(super) per_metre: f64,
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) sin_t: f64,
    pub(super) cos_t: f64,
    /// The index space the verdicts are gathered in: the whole grid for a
    /// dense map, a window around the sensor for a windowed one. The walk
    /// itself is always in the map's own frame, so both visit the same
    /// cells.
    pub(super) window: Window,
    /// The window's width in map cells (its stride, unless the frame is
    /// [`Self::in_segments`]).
    pub(super) cols: usize,
    /// True when the scratch buffers fit the window exactly (a dense map).
    pub(super) shrink: bool,
}

impl BeamFrame {
    /// The frame of a scan taken at `pose` whose longest beam reaches
    /// `reach` metres; `None` when no cell can be reached (a pose that is
    /// not a number, or a window that misses the map).
    pub(super) fn new<C: CellModel, S: Store<C::Cell>>(
        g: &GridGeometry,
        pose: &Pose,
        reach: f64,
    ) -> Option<Self> {
        let (su, sv) = g.world_to_grid(pose.x, pose.y);
        let res = g.resolution();
        let (window, cols) = if S::WINDOWED {
            if !(reach > 0.0 && su.is_finite() && sv.is_finite()) {
                return None;
            }
            // Every cell a beam visits lies within its reach of the sensor,
            // plus the cell the sensor is in.
            let rc = reach / res + 2.0;
            let span = |s: f64, n: usize| {
                let lo = (s - rc).floor().clamp(0.0, n as f64) as usize;
                let hi = ((s + rc).ceil() + 1.0).clamp(0.0, n as f64) as usize;
                (lo, hi)
            };
            let ((x0, x1), (y0, y1)) = (span(su, g.width()), span(sv, g.height()));
            if x0 >= x1 || y0 >= y1 {
                return None;
            }
            (
                Window {
                    x0,
                    y0,
                    stride: x1 - x0,
                    rows: y1 - y0,
                },
                x1 - x0,
            )
        } else {
            (Window::whole(g), g.width())
        };
        let (sin_t, cos_t) = pose.theta.sin_cos();
        Some(Self {
            su,
            sv,
            res,
            per_metre: 1.0 / res,
            width: g.width(),
            height: g.height(),
            sin_t,
            cos_t,
            window,
            cols,
            shrink: !S::WINDOWED,
        })
    }

    /// Scratch slots for the window's verdicts as codes: a dense map's
    /// exactly (its window never changes), a windowed map's grown and never
    /// shrunk (windows differ from scan to scan near the map's edges).
    pub(super) fn codes<'a>(&self, codes: &'a mut Vec<u8>, touched: &'a mut Vec<u32>) -> Codes<'a> {
        fit(codes, Code::Untouched as u8, self.window.len(), self.shrink);
        same_length(touched, codes.len());
        Codes::new(codes, touched, &mut [])
    }

    /// The frame with its window widened to start on a tile's west edge
    /// and to hold whole segments per row, so that a segment of the window
    /// is a row of one tile ([`Gathered`]); the cells it covers are the
    /// same.
    pub(super) fn in_segments(mut self) -> Self {
        let w = &mut self.window;
        let pad = w.x0 % SEGMENT;
        w.x0 -= pad;
        self.cols += pad;
        w.stride = self.cols.div_ceil(SEGMENT) * SEGMENT;
        self
    }

    /// As [`Self::codes`], gathered by segment (a windowed map's bands,
    /// see [`Gathered`]; the frame [`Self::in_segments`]): no touched
    /// list, a bit per segment instead.
    pub(super) fn segment_codes<'a>(
        &self,
        codes: &'a mut Vec<u8>,
        segments: &'a mut Vec<u64>,
    ) -> Gathered<'a, u8, true> {
        debug_assert!(
            self.window.x0.is_multiple_of(SEGMENT) && self.window.stride.is_multiple_of(SEGMENT)
        );
        fit(codes, Code::Untouched as u8, self.window.len(), self.shrink);
        let words = (codes.len() / (SEGMENT * 64)).max(1);
        if segments.len() < words {
            *segments = vec![0; words];
        }
        Gathered::new(codes, &mut [], &mut segments[..words])
    }

    /// As [`Self::codes`], for verdicts as log odds.
    pub(super) fn pending<'a>(
        &self,
        pending: &'a mut Vec<f32>,
        touched: &'a mut Vec<u32>,
    ) -> Pending<'a> {
        fit(pending, UNTOUCHED, self.window.len(), self.shrink);
        same_length(touched, pending.len());
        Pending::new(pending, touched, &mut [])
    }

    /// The walk along the beam of bearing `(sin, cos)` from the sensor out
    /// to range `reach` (metres), and the state at its first cell; `None`
    /// when the beam misses the map.
    #[inline]
    pub(super) fn beam(&self, (sin_b, cos_b): (f64, f64), reach: f64) -> Option<(Walk, BeamState)> {
        let (su, sv) = (self.su, self.sv);
        // Beam direction theta + bearing by the angle-addition formulas
        // (within a few ulps of sin_cos of the sum).
        let s = self.sin_t * cos_b + self.cos_t * sin_b;
        let c = self.cos_t * cos_b - self.sin_t * sin_b;
        let cells = reach * self.per_metre;
        let end = (su + cells * c, sv + cells * s);
        let walk = Walk::new(self.width, self.height, (su, sv), end)?;
        let at = self.beam_state(&walk, (s, c));
        Some((walk, at))
    }

    /// The state at `walk`'s first cell (inside the window) for a beam of
    /// direction `(sin, cos)`. Per cell the walk needs the cell's index and
    /// the range of its centre along the beam axis (metres); both change by
    /// a fixed amount per step on each axis, so they are carried along. The
    /// steps point along the beam, so both range steps are >= 0.
    #[inline]
    pub(super) fn beam_state(&self, walk: &Walk, (s, c): (f64, f64)) -> BeamState {
        let (su, sv, res) = (self.su, self.sv, self.res);
        let (ix, iy) = walk.start;
        let (step_x, step_y) = (walk.step.0 as f64, walk.step.1 as f64);
        let w = &self.window;
        BeamState {
            index: (iy - w.y0) * w.stride + (ix - w.x0),
            range: res * ((ix as f64 + 0.5 - su) * c + (iy as f64 + 0.5 - sv) * s),
            index_step: (
                walk.step.0 as isize,
                walk.step.1 as isize * w.stride as isize,
            ),
            range_step: (step_x * res * c, step_y * res * s),
        }
    }
}

/// Makes the touched list as long as the slots (its contents are scratch).
pub(super) fn same_length(touched: &mut Vec<u32>, len: usize) {
    if touched.len() != len {
        *touched = vec![0; len];
    }
}

/// Makes `buffer` a power-of-two length above `cells` (its contents are
/// scratch, every slot `clear` between scans): grown when too short, and
/// with `shrink` cut to size when longer.
pub(super) fn fit<T: Copy>(buffer: &mut Vec<T>, clear: T, cells: usize, shrink: bool) {
    let len = Gathered::<u8>::len_for(cells);
    if buffer.len() < len || (shrink && buffer.len() != len) {
        *buffer = vec![clear; len];
    }
}

/// Where a beam's walk stands: the cell's row-major index and the range of
/// its centre along the beam axis (metres), with their change per step on
/// each axis. Incremental, as Amanatides & Woo carry their `tMax`.
pub(super) struct BeamState {
    pub(super) index: usize,
    pub(super) range: f64,
    pub(super) index_step: (isize, isize),
    pub(super) range_step: (f64, f64),
}

impl BeamFrame {
    /// As [`Self::beam`], from range `from` (metres) on, out to `to`;
    /// `None` also when its first cell lies outside the window (a segment
    /// past the reach the window was made for). (A function of its own:
    /// the beam's walk is the hot one, and stays as it was.)
    pub(super) fn segment(
        &self,
        (sin_b, cos_b): (f64, f64),
        from: f64,
        to: f64,
    ) -> Option<(Walk, BeamState)> {
        if !(from >= 0.0 && from < to) {
            return None;
        }
        let (su, sv) = (self.su, self.sv);
        let s = self.sin_t * cos_b + self.cos_t * sin_b;
        let c = self.cos_t * cos_b - self.sin_t * sin_b;
        let (near, far) = (from * self.per_metre, to * self.per_metre);
        let start = (su + near * c, sv + near * s);
        let end = (su + far * c, sv + far * s);
        let walk = Walk::new(self.width, self.height, start, end)?;
        let (ix, iy) = walk.start;
        let w = &self.window;
        if !(ix >= w.x0 && iy >= w.y0 && ix - w.x0 < self.cols && iy - w.y0 < w.rows) {
            return None;
        }
        let at = self.beam_state(&walk, (s, c));
        Some((walk, at))
    }
}
