//! The ghost of exercise 5, per pane: the person is seen by the LiDAR, so
//! the cells where their outline stood gain occupied evidence, and once
//! they walk on only later scans through those cells can bring them back
//! below p = 0.5. The clamp bounds how much evidence a ghost can gather,
//! and with it how many scans the fade takes (Table 9.1 adds, the clamp
//! caps): a cell at the clamp `l_max`, contradicted by every scan, needs
//! `l_max / |l_free|` scans ([`GhostReadout::recursion_scans`]).

/// Cells near the person that were above p = 0.5 when they left, and how
/// many scans each took to fall back below p = 0.5.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct GhostTracker {
    /// The cells near the person after the last scan, and whether each
    /// was above p = 0.5 then.
    under: Vec<(usize, bool)>,
    /// Ghost cells not yet faded: (cell, the last scan that saw the
    /// person near it, counted from 1).
    pending: Vec<(usize, usize)>,
    /// Scans each completed fade took, in the order they completed.
    fades: Vec<usize>,
}

impl GhostTracker {
    /// After scan `scan` (counted from 1) was integrated, with the person
    /// near `now` (sorted cell indices: the cells their outline may have
    /// marked) and the map's log odds `l`.
    pub fn observe(&mut self, scan: usize, now: &[usize], l: &[f32]) {
        let under_now = |c: usize| now.binary_search(&c).is_ok();
        for &(c, ghost) in &self.under {
            if ghost && !under_now(c) {
                self.pending.push((c, scan - 1));
            }
        }
        let fades = &mut self.fades;
        self.pending.retain(|&(c, left)| {
            if under_now(c) {
                // Back under the person: the ghost is refreshed, not faded.
                return false;
            }
            if l[c] < 0.0 {
                fades.push(scan - left);
                return false;
            }
            true
        });
        self.under = now.iter().map(|&c| (c, l[c] > 0.0)).collect();
    }

    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// Scans each completed fade took, in the order they completed.
    pub fn fades(&self) -> &[usize] {
        &self.fades
    }

    /// The readout, with `seconds(n)` the driving time of `n` scans, the
    /// pane's clamp and its free evidence per scan (`None` for a model
    /// whose free evidence depends on the range, as the learned one's
    /// does).
    pub fn readout(
        &self,
        seconds: impl Fn(f64) -> f64,
        clamp: f64,
        free_evidence: Option<f32>,
    ) -> GhostReadout {
        let now = &self.fades[..];
        let last = now.last().copied();
        let longest = now.iter().copied().max();
        let recursion = free_evidence
            .filter(|&f| f < 0.0)
            .map(|f| clamp / (-f64::from(f)));
        GhostReadout {
            faded: self.fades.len(),
            lingering: self.pending.len(),
            last_scans: last,
            last_seconds: last.map(|n| seconds(n as f64)),
            longest_scans: longest,
            longest_seconds: longest.map(|n| seconds(n as f64)),
            free_evidence,
            recursion_scans: recursion,
            recursion_seconds: recursion.map(&seconds),
        }
    }
}

/// Exercise 5's readout: how long the person's ghost took to fade, and
/// how long the recursion says a cell at the clamp takes when every scan
/// contradicts it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GhostReadout {
    /// Ghost cells that have faded at the current clamp and strength (a
    /// change of either starts the count again).
    pub faded: usize,
    /// Ghost cells still at p >= 0.5 since the person left them.
    pub lingering: usize,
    /// Scans and seconds the most recent fade took.
    pub last_scans: Option<usize>,
    pub last_seconds: Option<f64>,
    /// The slowest fade at the current clamp and strength.
    pub longest_scans: Option<usize>,
    pub longest_seconds: Option<f64>,
    /// The log odds one free reading adds (`l_free - l0` at the pane's
    /// strength), when the model has one value for it.
    pub free_evidence: Option<f32>,
    /// `l_max / |l_free|`: the free readings that take a cell at the
    /// clamp down to p = 0.5, and their time at the scene's scan rate.
    pub recursion_scans: Option<f64>,
    pub recursion_seconds: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three cells, scan by scan: the person covers cells 0 and 1, moves
    /// to 1 and 2, then leaves. Cell 0 fades two scans after they left
    /// it, cell 2 (free when they left) is no ghost, cell 1 lingers until
    /// its log odds go negative.
    #[test]
    fn fades_are_counted_from_the_scan_the_person_left() {
        let mut g = GhostTracker::default();
        // Scan 1: over 0 and 1, both occupied now.
        g.observe(1, &[0, 1], &[1.0, 1.0, -0.5]);
        // Scan 2: over 1 and 2; cell 0 left behind at p > 0.5, cell 2 free.
        g.observe(2, &[1, 2], &[0.5, 1.5, -0.1]);
        assert_eq!(g.readout(|n| n, 12.0, None).lingering, 1);
        // Scan 3: gone. Cell 0 still positive; cell 1 now a ghost too.
        g.observe(3, &[], &[0.1, 1.0, -0.3]);
        assert_eq!(
            (g.fades(), g.readout(|n| n, 12.0, None).lingering),
            (&[][..], 2)
        );
        // Scan 4: cell 0 below 0.5: it left after scan 1, so 3 scans.
        g.observe(4, &[], &[-0.2, 0.4, -0.3]);
        assert_eq!(g.fades(), [3]);
        // Scan 5: cell 1 fades, 3 scans after scan 2.
        g.observe(5, &[], &[-0.2, -0.1, -0.3]);
        assert_eq!(g.fades(), [3, 3]);
        let r = g.readout(|n| n / 12.0, 12.0, Some(-0.5));
        assert_eq!(
            r,
            GhostReadout {
                faded: 2,
                lingering: 0,
                last_scans: Some(3),
                last_seconds: Some(0.25),
                longest_scans: Some(3),
                longest_seconds: Some(0.25),
                free_evidence: Some(-0.5),
                recursion_scans: Some(24.0),
                recursion_seconds: Some(2.0),
            }
        );
    }

    /// A ghost the person walks back onto is refreshed, not faded.
    #[test]
    fn a_ghost_walked_over_again_is_not_a_fade() {
        let mut g = GhostTracker::default();
        g.observe(1, &[4], &[0.0, 0.0, 0.0, 0.0, 2.0]);
        g.observe(2, &[], &[0.0, 0.0, 0.0, 0.0, 1.0]);
        g.observe(3, &[4], &[0.0, 0.0, 0.0, 0.0, -1.0]);
        assert_eq!(g.fades(), [] as [usize; 0]);
        assert_eq!(g.readout(|n| n, 12.0, None).lingering, 0);
        g.clear();
        assert_eq!(g, GhostTracker::default());
    }
}
