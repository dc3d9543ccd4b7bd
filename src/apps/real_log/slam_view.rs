//! What a page shows of a pane mapped without the log's poses: the pose
//! graph of a SLAM pane over its map ([`LogPane::pose_graph_pixels`]: its
//! nodes, local edges and loop closures in image units) and the pose error
//! against the log's corrected poses ([`LogPane::pose_error`]: the aligned
//! absolute trajectory error over the scans placed so far,
//! [`crate::poses::GrowingAlignment`]). The chapter maps with known poses;
//! these two say what doing without them costs, and what closing loops
//! wins back.

use super::pane::LogPane;
use crate::poses::PoseSourceKind;
use crate::slam::Edge;

/// Most scans one [`LogPane::pose_error`] call adds to its sums: a few
/// milliseconds at most, so that a log of a million scans is counted over
/// a few calls and no call holds a page.
pub const ERROR_SCANS_PER_CALL: usize = 200_000;
/// Most nodes drawn (every k-th beyond it) and most local-edge segments
/// (consecutive local edges joined beyond it): the loop closures are all
/// drawn.
pub const GRAPH_NODES_DRAWN: usize = 4_096;
pub const GRAPH_LOCAL_SEGMENTS: usize = 32_768;

/// A pane's pose error against the log's corrected poses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseErrorView {
    /// Scans counted (the first `scans` placed), of `placed`.
    pub scans: usize,
    pub placed: usize,
    /// Root mean square position error after the best rigid alignment,
    /// metres (the aligned ATE).
    pub ate_m: f64,
    /// The last scan counted: its position error under that alignment.
    pub scan_error_m: f64,
}

impl PoseErrorView {
    /// `[scans, placed, ateM, scanErrorM]`, as a page reads them.
    pub fn to_array(&self) -> [f64; 4] {
        [
            self.scans as f64,
            self.placed as f64,
            self.ate_m,
            self.scan_error_m,
        ]
    }
}

impl LogPane {
    /// The pose error of this pane's scans placed so far against the log's
    /// corrected poses, counting at most [`ERROR_SCANS_PER_CALL`] more scans
    /// (the sums start again when the source revises its poses, or the map
    /// goes back): `None` when the log has no corrected poses, for the pane
    /// at them, and before the first scan.
    pub fn pose_error(&mut self) -> Option<PoseErrorView> {
        if self.source() == PoseSourceKind::Corrected {
            return None;
        }
        let reference = self.scans().reference_poses()?;
        let poses = self.poses();
        let placed = self.progress().scans_done;
        let revision = self.source.revision();
        let mut tally = self.pose_error;
        let found = tally.advance(revision, poses, reference, placed, ERROR_SCANS_PER_CALL);
        let view = found.map(|(a, scans)| {
            let (p, q) = (poses[scans - 1], reference[scans - 1]);
            PoseErrorView {
                scans,
                placed: placed.min(poses.len()).min(reference.len()),
                ate_m: a.rms,
                scan_error_m: a.error_at([p.x, p.y], [q.x, q.y]),
            }
        });
        self.pose_error = tally;
        view
    }

    /// The pose graph of a SLAM pane over the scans placed so far, in image
    /// units (`None` for a source without one), as one flat list: `[nodes,
    /// locals, loops]` counts, then `nodes` points `u, v` (every k-th scan
    /// beyond [`GRAPH_NODES_DRAWN`]), `locals` segments `u0, v0, u1, v1` of
    /// the local edges (consecutive ones joined beyond
    /// [`GRAPH_LOCAL_SEGMENTS`]), and `loops` segments of the loop closures
    /// the optimisation kept (a closure the gate switched off is no
    /// constraint and is not drawn).
    pub fn pose_graph_pixels(&self) -> Option<Vec<f32>> {
        let graph = self.source.pose_graph()?;
        let poses = self.poses();
        let placed = self.progress().scans_done.min(poses.len());
        let geometry = self.grid().geometry();
        let mut out = vec![0.0f32; 3];
        let put = |out: &mut Vec<f32>, k: usize| {
            let p = poses[k];
            out.extend(geometry.world_to_image(p.x, p.y).map(|c| c as f32));
        };
        let node_step = placed.div_ceil(GRAPH_NODES_DRAWN).max(1);
        for k in (0..placed).step_by(node_step) {
            put(&mut out, k);
        }
        let nodes = (out.len() - 3) / 2;
        let shown = |e: &&Edge| e.from < placed && e.to < placed && (!e.robust || e.active);
        let locals = graph
            .edges
            .iter()
            .filter(shown)
            .filter(|e| !e.robust)
            .count();
        let local_step = locals.div_ceil(GRAPH_LOCAL_SEGMENTS).max(1);
        // Consecutive local edges joined, `local_step` a segment: the
        // local edges run from each scan to the next.
        let mut run: Option<(usize, usize, usize)> = None;
        for e in graph.edges.iter().filter(shown).filter(|e| !e.robust) {
            let (from, n) = run.map_or((e.from, 0), |(f, _, n)| (f, n));
            run = Some((from, e.to, n + 1));
            if n + 1 == local_step {
                put(&mut out, from);
                put(&mut out, e.to);
                run = None;
            }
        }
        if let Some((from, to, _)) = run {
            put(&mut out, from);
            put(&mut out, to);
        }
        let segments = (out.len() - 3 - 2 * nodes) / 4;
        for e in graph.edges.iter().filter(shown).filter(|e| e.robust) {
            put(&mut out, e.from);
            put(&mut out, e.to);
        }
        let loops = (out.len() - 3 - 2 * nodes) / 4 - segments;
        out[..3].copy_from_slice(&[nodes as f32, segments as f32, loops as f32]);
        Some(out)
    }
}
