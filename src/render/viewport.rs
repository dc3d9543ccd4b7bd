//! A window onto a large map at screen resolution (docs/ARCHITECTURE.md, "Real logs", "a map you
//! can look at"): the part of the north-up map image on screen, zoomed and
//! panned, drawn into a buffer of the screen's size and never the map's.
//!
//! A 250 m campus at 5 cm is about 5,000 x 5,000 cells; a 480-pixel pane
//! shows it at eleven cells to a pixel, and one doorway at forty pixels to
//! a cell. [`MapViewport`] holds that view (which image point is at the
//! top-left pixel, how many pixels a cell spans), turns wheel, pinch, drag
//! and keys into it, and maps an output pixel back to its cell;
//! [`render_view`] draws it, for a map of any storage and cell model
//! (a whole map at one pixel per cell is the view [`MapViewport::identity`]).

use crate::error::{invalid, OccError, Result};
use crate::geometry::GridGeometry;
use crate::grid::{CellModel, Grid, Store, StoredCell};

use super::gray::UNKNOWN_GRAY;

/// The most output pixels a view may have (16 MiB of RGBA): a 2048 x 2048
/// canvas, a full-width pane on a high-density screen.
pub const MAX_VIEW_PIXELS: usize = 1 << 22;
/// The longest side of a view, pixels.
pub const MAX_VIEW_SIDE: usize = 8192;
/// The closest zoom: a cell this many pixels wide.
pub const MAX_PIXELS_PER_CELL: f64 = 64.0;
/// Samples per pixel side when a pixel spans several cells: a one-cell wall
/// stays visible down to this many cells per pixel, and the cost of a frame
/// stays within `16 x` its pixels.
pub const MAX_SAMPLES: usize = 4;
/// Outside the map: a blue-gray no cell state uses.
const OUTSIDE: [u8; 4] = [214, 222, 232, 255];

/// What part of the map image is on screen, and how large.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MapViewport {
    /// The map, in cells (image columns and rows).
    pub map_width: usize,
    pub map_height: usize,
    /// The output, in pixels.
    pub width: usize,
    pub height: usize,
    /// The image point (columns from the left, rows from the top of the
    /// north-up map image, one unit per cell) at the output's top-left
    /// corner.
    pub u0: f64,
    pub v0: f64,
    /// Output pixels per cell.
    pub scale: f64,
}

impl MapViewport {
    /// A whole `width x height` map at one pixel per cell, north up: the
    /// map's own image.
    pub fn identity(width: usize, height: usize) -> Self {
        Self {
            map_width: width,
            map_height: height,
            width,
            height,
            u0: 0.0,
            v0: 0.0,
            scale: 1.0,
        }
    }

    /// The whole map, centred in a `width x height` output.
    pub fn new(map_width: usize, map_height: usize, width: usize, height: usize) -> Result<Self> {
        if map_width == 0 || map_height == 0 {
            return Err(invalid(
                "map",
                format!("{map_width} x {map_height}"),
                "at least one cell",
            ));
        }
        check_size(width, height)?;
        let mut v = Self {
            map_width,
            map_height,
            width,
            height,
            u0: 0.0,
            v0: 0.0,
            scale: 1.0,
        };
        v.fit();
        Ok(v)
    }

    /// The scale at which the whole map just fits.
    pub fn fit_scale(&self) -> f64 {
        (self.width as f64 / self.map_width as f64).min(self.height as f64 / self.map_height as f64)
    }

    /// Shows the whole map, centred.
    pub fn fit(&mut self) {
        self.scale = self.fit_scale();
        self.centre_on(self.map_width as f64 / 2.0, self.map_height as f64 / 2.0);
    }

    /// Puts image point `(u, v)` at the output's centre.
    pub fn centre_on(&mut self, u: f64, v: f64) {
        self.u0 = u - self.width as f64 / (2.0 * self.scale);
        self.v0 = v - self.height as f64 / (2.0 * self.scale);
        self.keep_in_view();
    }

    /// A new output size, keeping the image point at the centre and the
    /// scale (refitted if the whole map was shown).
    pub fn resize(&mut self, width: usize, height: usize) -> Result<()> {
        check_size(width, height)?;
        let fitted = (self.scale - self.fit_scale()).abs() <= 1e-12 * self.scale;
        let (cu, cv) = self.centre();
        self.width = width;
        self.height = height;
        if fitted {
            self.fit();
        } else {
            self.scale = self.scale.clamp(self.min_scale(), MAX_PIXELS_PER_CELL);
            self.centre_on(cu, cv);
        }
        Ok(())
    }

    /// The image point at the output's centre.
    pub fn centre(&self) -> (f64, f64) {
        (
            self.u0 + self.width as f64 / (2.0 * self.scale),
            self.v0 + self.height as f64 / (2.0 * self.scale),
        )
    }

    fn min_scale(&self) -> f64 {
        (self.fit_scale() / 2.0).min(MAX_PIXELS_PER_CELL)
    }

    /// Zooms by `factor` (above 1 closer) about output pixel `(x, y)`: the
    /// image point under it stays under it. The zoom stops at half the
    /// fitted scale and at [`MAX_PIXELS_PER_CELL`].
    pub fn zoom_at(&mut self, x: f64, y: f64, factor: f64) -> Result<()> {
        if !(factor.is_finite() && factor > 0.0) {
            return Err(invalid("factor", factor, "a zoom factor above 0"));
        }
        let (x, y) = (
            finite_or_centre(x, self.width),
            finite_or_centre(y, self.height),
        );
        let (u, v) = self.image_point(x, y);
        self.scale = (self.scale * factor).clamp(self.min_scale(), MAX_PIXELS_PER_CELL);
        self.u0 = u - x / self.scale;
        self.v0 = v - y / self.scale;
        self.keep_in_view();
        Ok(())
    }

    /// Moves the map by `(dx, dy)` output pixels (a drag).
    pub fn pan_by(&mut self, dx: f64, dy: f64) -> Result<()> {
        if !(dx.is_finite() && dy.is_finite()) {
            return Err(invalid(
                "pan",
                format!("({dx}, {dy})"),
                "finite pixel offsets",
            ));
        }
        self.u0 -= dx / self.scale;
        self.v0 -= dy / self.scale;
        self.keep_in_view();
        Ok(())
    }

    /// The centre stays over the map: the reader cannot lose it.
    fn keep_in_view(&mut self) {
        let (hw, hh) = (
            self.width as f64 / (2.0 * self.scale),
            self.height as f64 / (2.0 * self.scale),
        );
        let cu = (self.u0 + hw).clamp(0.0, self.map_width as f64);
        let cv = (self.v0 + hh).clamp(0.0, self.map_height as f64);
        self.u0 = cu - hw;
        self.v0 = cv - hh;
    }

    /// The image point under output pixel position `(x, y)` (pixel units,
    /// `(0.5, 0.5)` the first pixel's centre).
    pub fn image_point(&self, x: f64, y: f64) -> (f64, f64) {
        (self.u0 + x / self.scale, self.v0 + y / self.scale)
    }

    /// The map image pixel `(col, row)` (row 0 at the top) under output
    /// position `(x, y)`, or `None` off the map.
    pub fn cell_at(&self, x: f64, y: f64) -> Option<(usize, usize)> {
        let (u, v) = self.image_point(x, y);
        if !(u >= 0.0 && v >= 0.0) {
            return None;
        }
        let (c, r) = (u.floor() as usize, v.floor() as usize);
        (c < self.map_width && r < self.map_height).then_some((c, r))
    }
}

fn finite_or_centre(x: f64, n: usize) -> f64 {
    if x.is_finite() {
        x
    } else {
        n as f64 / 2.0
    }
}

fn check_size(width: usize, height: usize) -> Result<()> {
    if width == 0 || width > MAX_VIEW_SIDE {
        return Err(invalid("width", width, "1 to 8192 pixels"));
    }
    if height == 0 || height > MAX_VIEW_SIDE {
        return Err(invalid("height", height, "1 to 8192 pixels"));
    }
    if width * height > MAX_VIEW_PIXELS {
        return Err(invalid(
            "width x height",
            format!("{width} x {height}"),
            "at most 4194304 pixels (16 MiB of RGBA)",
        ));
    }
    Ok(())
}

/// Draws `view` of `grid` into `out` (resized to `width * height * 4` RGBA
/// bytes): the gray ramp, unknown cells mid-gray, blue-gray off the map.
/// A pixel that spans several cells shows the darkest of up to 4 x 4 cells
/// under it, so that one-cell walls stay visible when zoomed out; a cell
/// wider than a pixel is drawn as a block (nearest cell).
pub fn render_view<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    view: &MapViewport,
    out: &mut Vec<u8>,
) {
    out.clear();
    out.resize(view.width * view.height * 4, 0);
    render_view_into(grid, view, out);
}

/// Draws a whole map into RGBA pixels at one pixel per cell, north up (the
/// top pixel row is the grid's last row), unknown cells mid-gray.
pub fn render_grid_rgba<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    out: &mut [u8],
) -> Result<()> {
    let g = grid.geometry();
    check_pixels(g, out)?;
    render_view_into(grid, &MapViewport::identity(g.width(), g.height()), out);
    Ok(())
}

fn check_pixels(g: &GridGeometry, out: &[u8]) -> Result<()> {
    let n = g.width() * g.height() * 4;
    if out.len() != n {
        return Err(OccError::LengthMismatch {
            field: "pixel buffer".into(),
            expected: n,
            found: out.len(),
        });
    }
    Ok(())
}

/// [`render_view`] into a buffer of exactly `width * height * 4` bytes.
pub fn render_view_into<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    view: &MapViewport,
    out: &mut [u8],
) {
    render_counting_lookups(grid, view, out, 0..view.height, MAX_SAMPLES);
}

/// [`render_view_into`] for the output rows `rows` only (the others are
/// left as they are), at most `side` by `side` samples per pixel (1 for a
/// quick picture, [`MAX_SAMPLES`] for the view as drawn at once): a large
/// view drawn in bands, a call each.
pub fn render_view_rows<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    view: &MapViewport,
    out: &mut [u8],
    rows: std::ops::Range<usize>,
    side: usize,
) {
    render_counting_lookups(grid, view, out, rows, side);
}

/// Map cells sampled per output pixel at `view`'s zoom, at most `side` by
/// `side` of them: what one output row costs is `width` times this.
pub fn samples_per_pixel(view: &MapViewport, side: usize) -> usize {
    let k = samples_per_side(view, side);
    k * k
}

/// Samples per pixel side at `view`'s zoom, at most `side`.
fn samples_per_side(view: &MapViewport, side: usize) -> usize {
    ((1.0 / view.scale).ceil() as usize).clamp(1, side.clamp(1, MAX_SAMPLES))
}

/// [`render_view_rows`], returning how many times it looked up a block of
/// storage: at most one per tile a sample row crosses, plus one per sample
/// row (the bound a test holds it to).
fn render_counting_lookups<M: CellModel, S: Store<M::Cell>>(
    grid: &Grid<M, S>,
    view: &MapViewport,
    out: &mut [u8],
    out_rows: std::ops::Range<usize>,
    side: usize,
) -> usize {
    let mut lookups = 0;
    let (w, h) = (view.width, view.height);
    let out_rows = out_rows.start.min(h)..out_rows.end.min(h);
    let g = grid.geometry();
    let (mw, mh) = (g.width(), g.height());
    let per_pixel = 1.0 / view.scale;
    let k = samples_per_side(view, side);
    // The image columns (rows) sampled for each output column (row), or
    // none off the map: computed once per frame.
    let samples = |n: usize, start: f64, extent: usize| -> Vec<[usize; MAX_SAMPLES]> {
        (0..n)
            .map(|p| {
                let mut s = [usize::MAX; MAX_SAMPLES];
                for (j, slot) in s.iter_mut().enumerate().take(k) {
                    let t = start + (p as f64 + (j as f64 + 0.5) / k as f64) * per_pixel;
                    if t >= 0.0 && (t as usize) < extent {
                        *slot = t as usize;
                    }
                }
                s
            })
            .collect()
    };
    let cols = samples(w, view.u0, mw);
    let rows = samples(h, view.v0, mh);
    let first_row = out_rows.start;
    let model = grid.model();
    let store = grid.store();
    // One accumulator per output pixel of the row being drawn: the row's
    // sample rows are walked one after another, west to east, so a tile is
    // looked up once per run of samples it holds (a zoomed-out campus
    // spans 84 tiles per row) and never once per pixel or per sample.
    let mut acc = vec![Darkest::default(); w];
    for (py, rs) in rows[out_rows].iter().enumerate() {
        let py = first_row + py;
        let Some(line) = out.get_mut(py * w * 4..(py + 1) * w * 4) else {
            return lookups;
        };
        acc.fill(Darkest::default());
        for &r in &rs[..k] {
            if r == usize::MAX {
                continue;
            }
            // Image row 0 is the top: the one place a view turns image
            // rows into grid rows.
            let iy = mh - 1 - r;
            let mut run = TileRow::at(store, 0, iy, &mut lookups);
            for (d, cs) in acc.iter_mut().zip(&cols) {
                for &c in &cs[..k] {
                    if c == usize::MAX {
                        continue;
                    }
                    if !run.holds(c) {
                        run = TileRow::at(store, c, iy, &mut lookups);
                    }
                    match run.cells {
                        Some(cells) => d.add(model, cells[c - run.x0]),
                        None => d.unknown = true,
                    }
                }
            }
        }
        for (px4, d) in line.chunks_exact_mut(4).zip(&acc) {
            if d.seen() {
                let g = d.gray(model);
                px4.copy_from_slice(&[g, g, g, 255]);
            } else {
                px4.copy_from_slice(&OUTSIDE);
            }
        }
    }
    lookups
}

/// One grid row of one block of storage: the cells `x0..x0 + width` of
/// row `iy`, or `None` where no tile was ever allocated (unknown).
struct TileRow<'a, C> {
    x0: usize,
    width: usize,
    cells: Option<&'a [C]>,
}

impl<'a, C: StoredCell> TileRow<'a, C> {
    fn at<S: Store<C>>(store: &'a S, ix: usize, iy: usize, lookups: &mut usize) -> Self {
        *lookups += 1;
        let b = store.block(ix, iy);
        let start = (iy - b.y0) * b.stride;
        Self {
            x0: b.x0,
            width: b.width,
            cells: b.cells.map(|c| &c[start..start + b.width]),
        }
    }

    #[inline(always)]
    fn holds(&self, ix: usize) -> bool {
        ix.wrapping_sub(self.x0) < self.width
    }
}

/// The darkest gray among a pixel's samples, with one log-odds and ramp
/// evaluation per pixel rather than per sample: the ramp falls as log odds
/// rise, so the darkest known sample is the one of largest log odds (a
/// zoomed-out view of a campus samples 16 cells per pixel).
#[derive(Clone, Copy)]
struct Darkest<C> {
    most_occupied: Option<C>,
    unknown: bool,
}

impl<C: Copy> Default for Darkest<C> {
    fn default() -> Self {
        Self {
            most_occupied: None,
            unknown: false,
        }
    }
}

impl<C: Copy> Darkest<C> {
    #[inline(always)]
    fn add<M: CellModel<Cell = C>>(&mut self, model: &M, cell: C) {
        if model.is_unknown(cell) {
            self.unknown = true;
        } else {
            match self.most_occupied {
                Some(d) if !model.more_occupied(cell, d) => {}
                _ => self.most_occupied = Some(cell),
            }
        }
    }

    fn seen(&self) -> bool {
        self.unknown || self.most_occupied.is_some()
    }

    fn gray<M: CellModel<Cell = C>>(&self, model: &M) -> u8 {
        let unknown = if self.unknown { UNKNOWN_GRAY } else { u8::MAX };
        match self.most_occupied {
            Some(cell) => unknown.min(crate::render::gray::known_cell_gray(model, cell)),
            None => unknown,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{FilterSettings, LogOddsGrid, TiledGrid};
    use crate::render::gray::gray_level;

    #[test]
    fn render_puts_north_up_and_unknown_mid_gray() {
        let geometry = GridGeometry::new(4, 3, 0.5, -1.0, 2.0).unwrap();
        let mut m = LogOddsGrid::new(
            geometry,
            FilterSettings {
                prior: 0.2,
                clamp: 5.0,
            },
        )
        .unwrap();
        m.apply(0, 10.0); // south-west cell: occupied, clamped at 5
        let mut px = vec![0u8; 4 * 3 * 4];
        render_grid_rgba(&m, &mut px).unwrap();
        let bottom_left = (2 * 4) * 4;
        assert!(px[bottom_left] <= 2, "occupied is black");
        assert_eq!(px[0], 128, "unknown is mid-gray even with prior 0.2");
        assert_eq!(m.update_counts()[0], 1);
        assert!(render_grid_rgba(&m, &mut [0u8; 3]).is_err());
    }

    #[test]
    fn viewport_zoom_keeps_the_point_under_the_pointer_and_stops_at_its_limits() {
        let mut v = MapViewport::new(5009, 4906, 480, 470).unwrap();
        assert!((v.scale - 470.0 / 4906.0).abs() < 1e-12);
        assert_eq!(v.cell_at(240.0, 235.0), Some((2504, 2453)));
        let before = v.image_point(100.0, 50.0);
        v.zoom_at(100.0, 50.0, 8.0).unwrap();
        let after = v.image_point(100.0, 50.0);
        assert!((before.0 - after.0).abs() < 1e-9 && (before.1 - after.1).abs() < 1e-9);
        for _ in 0..20 {
            v.zoom_at(10.0, 10.0, 4.0).unwrap();
        }
        assert_eq!(v.scale, MAX_PIXELS_PER_CELL);
        for _ in 0..40 {
            v.zoom_at(10.0, 10.0, 0.25).unwrap();
        }
        assert!((v.scale - v.fit_scale() / 2.0).abs() < 1e-12);
        assert!(v.zoom_at(0.0, 0.0, f64::NAN).is_err());
        assert!(v.zoom_at(0.0, 0.0, 0.0).is_err());
    }

    #[test]
    fn viewport_pan_cannot_lose_the_map_and_sizes_are_bounded() {
        let mut v = MapViewport::new(100, 50, 200, 100).unwrap();
        v.zoom_at(100.0, 50.0, 10.0).unwrap();
        v.pan_by(-1e9, 1e9).unwrap();
        let (cu, cv) = v.centre();
        assert!((cu - 100.0).abs() < 1e-9 && cv.abs() < 1e-9, "({cu}, {cv})");
        assert!(v.pan_by(f64::INFINITY, 0.0).is_err());
        assert!(MapViewport::new(100, 50, 2048, 2048).is_ok());
        assert!(MapViewport::new(100, 50, 2049, 2048).is_err());
        assert!(MapViewport::new(100, 50, 0, 10).is_err());
        assert!(v.resize(9000, 10).is_err());
    }

    /// An empty tiled map of 1,000 x 800 cells of 5 cm, clamped at 3.
    fn tiled_map() -> TiledGrid {
        let e = GridGeometry::sparse(1000, 800, 0.05, 0.0, 0.0).unwrap();
        let filter = FilterSettings {
            prior: 0.5,
            clamp: 3.0,
        };
        TiledGrid::new(e, filter, 1 << 22).unwrap()
    }

    #[test]
    fn viewport_render_is_the_screen_size_and_keeps_thin_walls_when_zoomed_out() {
        let mut g = tiled_map();
        // A one-cell wall along column 500, free space to its left.
        for iy in 0..800 {
            g.apply_at(500, iy, 3.0);
            for ix in 400..500 {
                g.apply_at(ix, iy, -3.0);
            }
        }
        let v = MapViewport::new(1000, 800, 250, 200).unwrap();
        let mut out = Vec::new();
        render_view(&g, &v, &mut out);
        assert_eq!(out.len(), 250 * 200 * 4);
        let px = |x: usize, y: usize| out[(y * 250 + x) * 4];
        assert_eq!(
            px(125, 100),
            gray_level(3.0),
            "the wall at 4 cells per pixel"
        );
        assert_eq!(px(110, 100), gray_level(-3.0), "free");
        assert_eq!(px(10, 100), UNKNOWN_GRAY, "no tile: unknown");
        // Zoomed far in, off the map is its own colour.
        let mut v = v;
        v.zoom_at(0.0, 0.0, 100.0).unwrap();
        v.pan_by(1e6, 0.0).unwrap();
        render_view(&g, &v, &mut out);
        assert_eq!(&out[..4], &OUTSIDE);
        assert_eq!(out.len(), 250 * 200 * 4);
    }

    /// The view drawn sample by sample through `Grid::cell_at`: the
    /// meaning of a frame (the darkest of up to 4 x 4 cells, unknown gray,
    /// blue-gray off the map), without any shortcut through storage.
    fn reference_render(g: &TiledGrid, v: &MapViewport) -> Vec<u8> {
        use crate::render::gray::cell_gray;
        let geo = g.geometry();
        let (mw, mh) = (geo.width(), geo.height());
        let per_pixel = 1.0 / v.scale;
        let k = (per_pixel.ceil() as usize).clamp(1, MAX_SAMPLES);
        let sample = |p: usize, start: f64, j: usize, n: usize| {
            let t = start + (p as f64 + (j as f64 + 0.5) / k as f64) * per_pixel;
            (t >= 0.0 && (t as usize) < n).then_some(t as usize)
        };
        let mut out = Vec::with_capacity(v.width * v.height * 4);
        for py in 0..v.height {
            for px in 0..v.width {
                let mut darkest: Option<u8> = None;
                for j in 0..k {
                    let Some(r) = sample(py, v.v0, j, mh) else {
                        continue;
                    };
                    for i in 0..k {
                        let Some(c) = sample(px, v.u0, i, mw) else {
                            continue;
                        };
                        let gray = cell_gray(g.model(), g.cell_at(c, mh - 1 - r).unwrap());
                        darkest = Some(darkest.map_or(gray, |d| d.min(gray)));
                    }
                }
                out.extend_from_slice(&darkest.map_or(OUTSIDE, |d| [d, d, d, 255]));
            }
        }
        out
    }

    #[test]
    fn viewport_render_looks_a_tile_up_once_per_sample_row_and_equals_the_reference() {
        use crate::grid::storage::TILE_SIDE;
        // 1,000 x 800 cells, tiles allocated in a checkerboard, walls and
        // free space of many levels crossing tile borders.
        let mut g = tiled_map();
        for iy in 0..800 {
            for ix in 0..1000 {
                if (ix / TILE_SIDE + iy / TILE_SIDE).is_multiple_of(2)
                    && !(ix * 7 + iy * 3).is_multiple_of(5)
                {
                    g.apply_at(ix, iy, ((ix * 13 + iy * 29) % 61) as f32 / 10.0 - 3.0);
                }
            }
        }
        let mut views = Vec::new();
        let mut v = MapViewport::new(1000, 800, 250, 200).unwrap();
        views.push(v);
        // Half the fitted scale (8 cells to a pixel, map inside blue-gray),
        // then closer and closer, panned off the map's corner.
        for factor in [0.5, 2.0, 3.0, 1.7, 5.0, 4.0] {
            v.zoom_at(37.0, 151.0, factor).unwrap();
            views.push(v);
            let mut panned = v;
            panned.pan_by(90.0, -70.0).unwrap();
            views.push(panned);
        }
        for v in views {
            let mut out = vec![0; v.width * v.height * 4];
            let lookups = render_counting_lookups(&g, &v, &mut out, 0..v.height, MAX_SAMPLES);
            assert!(
                out == reference_render(&g, &v),
                "pixels at scale {}",
                v.scale
            );
            // Each output row's samples rows each cross the view's tiles
            // once, west to east.
            let k = ((1.0 / v.scale).ceil() as usize).clamp(1, MAX_SAMPLES);
            let tiles_across = (v.width as f64 / v.scale / TILE_SIDE as f64).ceil() as usize + 1;
            let bound = v.height * k * (tiles_across + 1);
            assert!(
                lookups <= bound,
                "{lookups} lookups at scale {}, bound {bound}",
                v.scale
            );
        }
    }
}
