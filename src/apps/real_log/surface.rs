//! The session as a page operates it: every call about one map takes that
//! pane's index first and answers for it (or refuses the index by name),
//! so that a page's call is one call into the core session
//! (docs/ARCHITECTURE.md, "Sessions and panes").

use super::{ImageCell, MatchView, RealLogSession, ViewLegend};
use crate::error::{invalid, Result};
use crate::grid::readout::CellReadout;
use crate::io::map_server::{ExportCounts, MapServerPair};
use crate::render::overlay::RobotMark;
use crate::render::viewport::MapViewport;

impl RealLogSession {
    /// A session about to read `bytes` (gzip or plain text), `name` its
    /// file's name.
    pub fn with_log(bytes: Vec<u8>, name: &str) -> Self {
        let mut session = Self::idle();
        session.open(bytes, name);
        session
    }

    /// Sets the size of the output pane `pane` is drawn into, device
    /// pixels; the view keeps its centre and zoom.
    pub fn set_view_size(&mut self, pane: usize, width: usize, height: usize) -> Result<()> {
        self.pane_mut(pane)?.set_view_size(width, height)
    }

    /// Shows pane `pane`'s whole map, keeping the keyboard cursor (placed
    /// at the view's centre if there was none); the cell under it.
    pub fn fit_view(&mut self, pane: usize) -> Result<Option<CellReadout>> {
        Ok(self.pane_mut(pane)?.fit_at_cursor())
    }

    /// Zooms pane `pane` by `factor` about output pixel `(x, y)`.
    pub fn zoom_at(&mut self, pane: usize, x: f64, y: f64, factor: f64) -> Result<()> {
        self.pane_mut(pane)?.zoom_view(x, y, factor)
    }

    /// Moves pane `pane`'s map by `(dx, dy)` output pixels.
    pub fn pan_by(&mut self, pane: usize, dx: f64, dy: f64) -> Result<()> {
        self.pane_mut(pane)?.pan_view(dx, dy)
    }

    /// Pane `pane`'s window onto its map.
    pub fn view_of(&self, pane: usize) -> Result<&MapViewport> {
        Ok(self.pane(pane)?.view())
    }

    /// Pane `pane`'s scale as the panel states it.
    pub fn view_legend(&self, pane: usize, device_pixel_ratio: f64) -> Result<ViewLegend> {
        self.pane(pane)?.legend(device_pixel_ratio)
    }

    /// Draws pane `pane`'s view; its RGBA bytes.
    pub fn render_view(&mut self, pane: usize) -> Result<&[u8]> {
        Ok(self.pane_mut(pane)?.render_view())
    }

    /// Draws a band of pane `pane`'s view (at most `max_samples` map cells
    /// sampled); true once the picture is whole.
    pub fn render_view_within(
        &mut self,
        pane: usize,
        max_samples: usize,
        quick: bool,
    ) -> Result<bool> {
        Ok(self.pane_mut(pane)?.render_view_within(max_samples, quick))
    }

    /// Pane `pane`'s last whole picture, RGBA bytes.
    pub fn view_pixels(&self, pane: usize) -> Result<&[u8]> {
        Ok(self.pane(pane)?.view_pixels())
    }

    /// The cell under output position `(x, y)` of pane `pane`'s view.
    pub fn cell_at_view(&self, pane: usize, x: f64, y: f64) -> Result<Option<CellReadout>> {
        self.pane(pane)?.readout_at_view(x, y)
    }

    /// The cell under image pixel `(col, row)` of pane `pane`.
    pub fn cell_at(&self, pane: usize, col: usize, row: usize) -> Result<Option<CellReadout>> {
        Ok(self.pane(pane)?.readout_at_pixel(col, row))
    }

    /// Moves pane `pane`'s keyboard cursor one arrow key's way; the cell
    /// under it.
    pub fn move_cursor(
        &mut self,
        pane: usize,
        dx: i8,
        dy: i8,
        long: bool,
    ) -> Result<Option<CellReadout>> {
        self.pane_mut(pane)?.move_cursor(dx, dy, long)
    }

    /// Zooms pane `pane` by `factor` about its keyboard cursor; the cell
    /// under it.
    pub fn zoom_at_cursor(&mut self, pane: usize, factor: f64) -> Result<Option<CellReadout>> {
        self.pane_mut(pane)?.zoom_at_cursor(factor)
    }

    /// Pane `pane`'s keyboard cursor.
    pub fn cursor(&self, pane: usize) -> Result<Option<ImageCell>> {
        Ok(self.pane(pane)?.cursor())
    }

    /// Forgets pane `pane`'s keyboard cursor.
    pub fn clear_cursor(&mut self, pane: usize) -> Result<()> {
        self.pane_mut(pane)?.clear_cursor();
        Ok(())
    }

    /// Pane `pane`'s cells counted as the exported map holds them.
    pub fn counts(&self, pane: usize) -> Result<ExportCounts> {
        Ok(self.pane(pane)?.counts())
    }

    /// The laser positions of all scans on pane `pane`, image pixels.
    pub fn path_pixels(&self, pane: usize) -> Result<Vec<f32>> {
        Ok(self.pane(pane)?.path_in_pixels())
    }

    /// The robot at scan `k` over pane `pane`, or an error naming the scan.
    pub fn robot_at(&self, pane: usize, k: usize) -> Result<RobotMark> {
        let robot = self.pane(pane)?.robot_at(k);
        robot.ok_or_else(|| invalid("scan", k, "a scan of the log"))
    }

    /// What pane `pane`'s last scan match did (for a scan-matched pane).
    pub fn match_view(&self, pane: usize) -> Result<Option<MatchView>> {
        Ok(self.pane(pane)?.match_view())
    }

    /// The poses pane `pane`'s map so far was built with, as `poses.tsv`.
    pub fn poses_tsv(&self, pane: usize) -> Result<String> {
        Ok(self.pane(pane)?.poses_tsv())
    }

    /// The file stem pane `pane`'s export takes for a log named `file_name`.
    pub fn export_stem(&self, pane: usize, file_name: &str) -> Result<String> {
        Ok(self.pane(pane)?.export_stem(file_name))
    }

    /// Pane `pane`'s map as a ROS `map_server` pair, the image `NAME.pgm`
    /// (`map.pgm` without a name).
    pub fn export_map(&self, pane: usize, name: Option<&str>) -> Result<MapServerPair> {
        Ok(self.pane(pane)?.export_map(name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLASER: &str = "FLASER 4 1.0 2.0 3.0 2.5 0.5 -1.5 0.1 0 0 0 1.0 host 1.0\n";

    #[test]
    fn a_pane_is_operated_through_its_index() {
        let mut s = RealLogSession::with_log(FLASER.repeat(3).into_bytes(), "lab.log");
        s.read(usize::MAX).unwrap();
        s.build_slice(u64::MAX).unwrap();
        assert!(s.robot_at(0, 2).is_ok());
        let e = s.robot_at(0, 3).unwrap_err().to_string();
        assert!(e.contains("invalid scan: 3"), "{e}");
        let e = s.counts(7).unwrap_err().to_string();
        assert!(e.contains("pane"), "{e}");
        s.set_view_size(0, 64, 48).unwrap();
        assert_eq!(s.render_view(0).unwrap().len(), 64 * 48 * 4);
        assert_eq!(s.view_pixels(0).unwrap().len(), 64 * 48 * 4);
        assert!(s.cursor(0).unwrap().is_none());
        assert!(s.move_cursor(0, 1, 0, false).unwrap().is_some());
        assert!(s.cursor(0).unwrap().is_some());
        s.clear_cursor(0).unwrap();
        assert!(s.cursor(0).unwrap().is_none());
        assert_eq!(s.poses_tsv(0).unwrap().lines().count(), 3);
        let pair = s.export_map(0, Some("lab")).unwrap();
        assert!(pair.yaml.starts_with("image: lab.pgm"), "{}", pair.yaml);
    }
}
