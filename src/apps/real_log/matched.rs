//! What a page draws of a pane's pose source: the last scan match of a
//! scan-matched pane ([`MatchView`]: the scan's points where the match put
//! them), and every pane's poses as the text of a `poses.tsv` file.

use super::pane::LogPane;
use crate::geometry::{wrap_angle, GridGeometry, Pose};
use crate::mapping::scan_match::ScanPoints;
use crate::poses::ScanMatching;
use crate::render::overlay::RobotMark;

/// What the last match of a pane did, as the page draws it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MatchView {
    /// The scan matched.
    pub scan: usize,
    pub accepted: bool,
    pub score: f64,
    pub predicted_score: f64,
    pub overlap: f64,
    /// The robot where the odometry predicted it, and where the scan was
    /// put, in image units.
    pub predicted: RobotMark,
    pub pose: RobotMark,
    /// How far the match moved the prediction, metres and degrees.
    pub correction_m: f64,
    pub correction_deg: f64,
    /// The matched points at the pose found, image units, `[u0, v0, ...]`.
    pub points: Vec<f32>,
}

impl MatchView {
    /// The last match of `matching`, drawn on `geometry`'s image.
    fn of(matching: &ScanMatching, geometry: &GridGeometry) -> Option<Self> {
        let (scan, r) = matching.last()?;
        let trig = r.pose.theta.sin_cos();
        let points = matching
            .matcher()
            .points()
            .points()
            .iter()
            .flat_map(|&p| {
                let [x, y] = ScanPoints::to_world(&r.pose, trig, p);
                geometry.world_to_image(x, y).map(|c| c as f32)
            })
            .collect();
        Some(Self {
            scan,
            accepted: r.accepted,
            score: r.score,
            predicted_score: r.predicted_score,
            overlap: r.overlap,
            predicted: RobotMark::at(geometry, &r.predicted),
            pose: RobotMark::at(geometry, &r.pose),
            correction_m: (r.pose.x - r.predicted.x).hypot(r.pose.y - r.predicted.y),
            correction_deg: wrap_angle(r.pose.theta - r.predicted.theta).to_degrees(),
            points,
        })
    }
}

impl LogPane {
    /// The last scan matched and where it went (`None` for a pane that
    /// does not match, or before its first scan).
    pub fn match_view(&self) -> Option<MatchView> {
        MatchView::of(self.source.matching()?, self.grid().geometry())
    }

    /// The odometry a scan-matched pane corrects (`None` for the others).
    pub fn matched_odometry(&self) -> Option<&[Pose]> {
        Some(self.source.matching()?.odometry())
    }

    /// The poses the map so far was built with, one line per scan
    /// integrated: `scan x y theta` (metres, radians, each number as the
    /// shortest text that reads back as the same `f64`).
    pub fn poses_tsv(&self) -> String {
        let done = self.progress().scans_done;
        let mut out = String::with_capacity(done * 64);
        for (k, p) in self.poses().iter().take(done).enumerate() {
            out.push_str(&format!("{k} {} {} {}\n", p.x, p.y, p.theta));
        }
        out
    }
}
