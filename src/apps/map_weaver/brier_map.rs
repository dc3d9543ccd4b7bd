//! Where each pane is closer to the truth: the two maps' Brier scores
//! taken apart cell by cell over the surveyed region (exercise 8, the
//! learned model against itself forgetting `l0`, or against Table 9.2's).
//!
//! A pane's Brier score is the mean over the region of `(p - truth)^2`;
//! the difference of the two scores is the mean of the per-cell
//! differences, so the image shows which cells make up the gap the two
//! readouts print.

use super::Weaver;

/// The per-cell Brier difference, right map minus left, over the
/// surveyed region; only when both panes map the same cells.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct BrierDifference {
    /// Cells of the surveyed region (the Brier scores' cells).
    pub region: usize,
    /// Region cells whose squared error is smaller in the left map.
    pub left_closer: usize,
    /// Region cells whose squared error is smaller in the right map.
    pub right_closer: usize,
    /// Region cells the two maps score alike (within `TIE`).
    pub tied: usize,
    /// The mean over the region of (right's squared error - left's): the
    /// right Brier score minus the left one.
    pub mean: f64,
}

/// Squared errors closer than this count as a tie: well below what a
/// single update changes (a log-odds step of 0.01 moves `p` by 0.0025).
pub const TIE: f64 = 1e-6;

/// Left map closer: Okabe & Ito's blue, a pair a colour-blind reader tells
/// apart from `RIGHT_CLOSER`.
pub const LEFT_CLOSER: [u8; 3] = [0, 114, 178];
/// Right map closer: Okabe & Ito's vermillion.
pub const RIGHT_CLOSER: [u8; 3] = [213, 94, 0];
/// A cell outside the surveyed region: not scored.
pub const NOT_SCORED: u8 = 190;
/// A cell both maps score alike whose truth is occupied: the apartment's
/// walls and furniture stay visible where neither map is closer.
pub const ALIKE_OCCUPIED: u8 = 222;

/// The image's colours, `[r, g, b]`, as its legend names them.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct BrierColours {
    pub left_closer: [u8; 3],
    pub right_closer: [u8; 3],
    pub not_scored: [u8; 3],
    pub alike_occupied: [u8; 3],
}

impl BrierColours {
    pub const SHOWN: Self = Self {
        left_closer: LEFT_CLOSER,
        right_closer: RIGHT_CLOSER,
        not_scored: [NOT_SCORED; 3],
        alike_occupied: [ALIKE_OCCUPIED; 3],
    };
}

impl Weaver {
    /// The two panes' per-cell Brier difference; `None` when they map at
    /// different resolutions (their cells are not the same cells).
    pub fn brier_difference(&self) -> Option<BrierDifference> {
        let (left, right) = self.scored_pair()?;
        let (el, er) = (left.squared_errors(), right.squared_errors());
        let mut out = BrierDifference {
            region: 0,
            left_closer: 0,
            right_closer: 0,
            tied: 0,
            mean: 0.0,
        };
        let mut sum = 0.0;
        for (i, _) in left.region().iter().enumerate().filter(|(_, &r)| r) {
            let d = er[i] - el[i];
            sum += d;
            out.region += 1;
            match d {
                d if d > TIE => out.left_closer += 1,
                d if d < -TIE => out.right_closer += 1,
                _ => out.tied += 1,
            }
        }
        out.mean = sum / out.region.max(1) as f64;
        Some(out)
    }

    /// Draws the per-cell difference as an RGBA image (width x height x 4,
    /// north up, like a pane's map): a region cell the left map scores
    /// better in `LEFT_CLOSER`, the right map `RIGHT_CLOSER`, deeper
    /// the larger the gap, white where they tie (`ALIKE_OCCUPIED` on an
    /// occupied cell); `NOT_SCORED` gray outside the region. `None` when the panes' cells differ.
    pub fn draw_brier_difference(&mut self) -> Option<&[u8]> {
        let [a, b] = &self.panes;
        if a.geometry != b.geometry {
            return None;
        }
        let (left, right) = (a.map.view().scores(), b.map.view().scores());
        let (el, er, region) = (left.squared_errors(), right.squared_errors(), left.region());
        let truth = left.truth();
        let (w, h) = (a.geometry.width(), a.geometry.height());
        let rgba = &mut self.brier_pixels;
        rgba.clear();
        rgba.resize(4 * w * h, 255);
        for (i, &scored) in region.iter().enumerate() {
            let (ix, iy) = (i % w, i / w);
            let o = 4 * ((h - 1 - iy) * w + ix);
            let d = er[i] - el[i];
            let rgb = if !scored {
                [NOT_SCORED; 3]
            } else if d.abs() <= TIE {
                [if truth[i] { ALIKE_OCCUPIED } else { 255 }; 3]
            } else {
                shade(if d > 0.0 { LEFT_CLOSER } else { RIGHT_CLOSER }, d.abs())
            };
            rgba[o..o + 3].copy_from_slice(&rgb);
        }
        Some(&self.brier_pixels)
    }

    /// The two panes' scores when they score the same cells.
    fn scored_pair(
        &self,
    ) -> Option<(
        &crate::grid::stats::MapScores,
        &crate::grid::stats::MapScores,
    )> {
        let [a, b] = &self.panes;
        (a.geometry == b.geometry).then(|| (a.map.view().scores(), b.map.view().scores()))
    }
}

/// White blended towards `color` by the square root of `gap` (a squared
/// error difference, at most 1), full at a gap of 0.25: a cell at p = 0.5
/// against one at the truth.
fn shade(color: [u8; 3], gap: f64) -> [u8; 3] {
    let t = (2.0 * gap.sqrt()).min(1.0);
    color.map(|c| (255.0 - t * (255.0 - f64::from(c))).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::apps::map_weaver::{ModelKind, WeaverSettings};

    fn exercise_eight(scans: usize) -> Weaver {
        let mut s = WeaverSettings::default();
        for p in &mut s.panes {
            p.model = ModelKind::Learned;
        }
        s.panes[1].forget_l0 = true;
        let mut w = Weaver::new(s).unwrap();
        w.advance(scans).unwrap();
        w
    }

    #[test]
    fn the_per_cell_differences_add_up_to_the_gap_between_the_two_brier_scores() {
        let w = exercise_eight(653);
        let d = w.brier_difference().expect("same cells");
        let r = w.readout();
        let gap = r.panes[1].brier - r.panes[0].brier;
        assert!(
            (d.mean - gap).abs() < 1e-9,
            "mean {} against the readouts' gap {gap}",
            d.mean
        );
        assert_eq!(d.left_closer + d.right_closer + d.tied, d.region);
        // After the first lap the map that remembers l0 scores 0.0343, the
        // one that forgets 0.0755 (the chapter page's exercise 8): the
        // remembering map is closer in more cells, though not in all.
        assert!((d.mean - (0.0755 - 0.0343)).abs() < 1e-3, "{d:?}");
        assert!(
            d.left_closer > d.right_closer && d.right_closer > 0,
            "{d:?}"
        );
    }

    #[test]
    fn the_image_colours_each_region_cell_by_the_map_closer_to_the_truth() {
        let mut w = exercise_eight(653);
        let d = w.brier_difference().unwrap();
        let (width, height) = (w.panes[0].geometry.width(), w.panes[0].geometry.height());
        let px = w.draw_brier_difference().unwrap().to_vec();
        assert_eq!(px.len(), 4 * width * height);
        let hue = |c: [u8; 3]| {
            px.chunks(4)
                .filter(|p| p[0] != p[1] || p[1] != p[2])
                .filter(|p| {
                    let blue_ish = p[2] > p[0];
                    blue_ish == (c == LEFT_CLOSER)
                })
                .count()
        };
        assert_eq!(hue(LEFT_CLOSER), d.left_closer);
        assert_eq!(hue(RIGHT_CLOSER), d.right_closer);
        let unscored = px.chunks(4).filter(|p| p[..3] == [NOT_SCORED; 3]).count();
        assert_eq!(unscored, width * height - d.region);
    }

    #[test]
    fn panes_of_different_cells_have_no_difference() {
        let mut s = WeaverSettings::default();
        s.panes[1].resolution = Some(0.05);
        let mut w = Weaver::new(s).unwrap();
        w.advance(5).unwrap();
        assert_eq!(w.brier_difference(), None);
        assert!(w.draw_brier_difference().is_none());
    }

    #[test]
    fn a_cell_far_from_the_truth_in_one_map_only_is_deeply_coloured() {
        assert_eq!(shade(LEFT_CLOSER, 0.25), LEFT_CLOSER);
        assert_eq!(shade(RIGHT_CLOSER, 1.0), RIGHT_CLOSER);
        let faint = shade(LEFT_CLOSER, 1e-4);
        assert!(faint.iter().all(|&c| c > 240), "{faint:?}");
    }
}
