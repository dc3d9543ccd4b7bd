//! The ghost of exercise 5, per pane: the person is seen by the LiDAR, so
//! the cells they stood on gain occupied evidence, and once they walk on
//! only later scans through those cells can bring them back below
//! p = 0.5. The clamp bounds how much evidence a ghost can gather, and with
//! it how many scans the fade takes (Table 9.1 adds, the clamp caps).

/// Cells the person stood on that were above p = 0.5 when they left, and
/// how many scans each took to fall back below p = 0.5.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct GhostTracker {
    /// The cells under the person after the last scan, and whether each
    /// was above p = 0.5 then.
    under: Vec<(usize, bool)>,
    /// Ghost cells not yet faded: (cell, the last scan that saw the
    /// person on it, counted from 1).
    pending: Vec<(usize, usize)>,
    /// Scans each completed fade took, in the order they completed.
    fades: Vec<usize>,
}

impl GhostTracker {
    /// After scan `scan` (counted from 1) was integrated, with the person
    /// over `now` (sorted cell indices) and the map's log odds `l`.
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

    /// The readout, with `seconds(n)` the driving time of `n` scans.
    pub fn readout(&self, seconds: impl Fn(usize) -> f64) -> GhostReadout {
        let last = self.fades.last().copied();
        let longest = self.fades.iter().copied().max();
        GhostReadout {
            faded: self.fades.len(),
            lingering: self.pending.len(),
            last_scans: last,
            last_seconds: last.map(&seconds),
            longest_scans: longest,
            longest_seconds: longest.map(&seconds),
        }
    }
}

/// Exercise 5's readout: how long the person's ghost took to fade.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GhostReadout {
    /// Ghost cells that have faded so far.
    pub faded: usize,
    /// Ghost cells still at p >= 0.5 since the person left them.
    pub lingering: usize,
    /// Scans and seconds the most recent fade took.
    pub last_scans: Option<usize>,
    pub last_seconds: Option<f64>,
    /// The slowest fade so far.
    pub longest_scans: Option<usize>,
    pub longest_seconds: Option<f64>,
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
        assert_eq!(g.readout(|n| n as f64).lingering, 1);
        // Scan 3: gone. Cell 0 still positive; cell 1 now a ghost too.
        g.observe(3, &[], &[0.1, 1.0, -0.3]);
        assert_eq!((g.fades(), g.readout(|n| n as f64).lingering), (&[][..], 2));
        // Scan 4: cell 0 below 0.5: it left after scan 1, so 3 scans.
        g.observe(4, &[], &[-0.2, 0.4, -0.3]);
        assert_eq!(g.fades(), [3]);
        // Scan 5: cell 1 fades, 3 scans after scan 2.
        g.observe(5, &[], &[-0.2, -0.1, -0.3]);
        assert_eq!(g.fades(), [3, 3]);
        let r = g.readout(|n| n as f64 / 12.0);
        assert_eq!(
            r,
            GhostReadout {
                faded: 2,
                lingering: 0,
                last_scans: Some(3),
                last_seconds: Some(0.25),
                longest_scans: Some(3),
                longest_seconds: Some(0.25),
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
        assert_eq!(g.readout(|n| n as f64).lingering, 0);
        g.clear();
        assert_eq!(g, GhostTracker::default());
    }
}
