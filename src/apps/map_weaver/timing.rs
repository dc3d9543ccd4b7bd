//! The session's clock readouts: milliseconds per frame (as the page
//! measured them) and per scan and pane (as the core measures them), each
//! over a short window of recent times.

use std::collections::VecDeque;

/// A monotonic clock in milliseconds. Natively the standard library's;
/// in the browser the bindings hand in `performance.now`.
pub type Clock = fn() -> f64;

/// The clock a native run starts with.
#[cfg(not(target_arch = "wasm32"))]
pub(super) fn native_clock() -> f64 {
    use std::sync::OnceLock;
    use std::time::Instant;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64() * 1e3
}

/// How many recent times a readout summarises: half a second of frames at
/// 60 a second, enough to steady the number without hiding a change.
pub(super) const WINDOW: usize = 31;

/// The last [`WINDOW`] times, milliseconds.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct RecentTimes {
    times: VecDeque<f64>,
}

impl RecentTimes {
    /// Keeps `ms` (dropping the oldest past the window); a time that is no
    /// finite number of at least 0 is not a time and is ignored.
    pub fn record(&mut self, ms: f64) {
        if !(ms.is_finite() && ms >= 0.0) {
            return;
        }
        if self.times.len() == WINDOW {
            self.times.pop_front();
        }
        self.times.push_back(ms);
    }

    pub fn clear(&mut self) {
        self.times.clear();
    }

    /// The median (of an even count, the upper middle): a frame that waited
    /// on the page's garbage collector does not move it.
    pub fn median(&self) -> Option<f64> {
        if self.times.is_empty() {
            return None;
        }
        let mut v: Vec<f64> = self.times.iter().copied().collect();
        crate::geometry::order::sort_stable_by_key(&mut v, |&x| x);
        Some(v[v.len() / 2])
    }

    /// The mean: where the page's clock ticks in steps coarser than the
    /// times measured, only the mean of the rounded times keeps the small
    /// ones (a median of zeros and one-tenths says 0).
    pub fn mean(&self) -> Option<f64> {
        (!self.times.is_empty()).then(|| self.times.iter().sum::<f64>() / self.times.len() as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_mean_of_the_window_only() {
        let mut t = RecentTimes::default();
        assert_eq!((t.median(), t.mean()), (None, None));
        for ms in [5.0, 1.0, 3.0] {
            t.record(ms);
        }
        assert_eq!((t.median(), t.mean()), (Some(3.0), Some(3.0)));
        t.record(100.0);
        assert_eq!(t.median(), Some(5.0), "the upper middle of 1, 3, 5, 100");
        // A full window of 2 ms pushes every earlier time out.
        for _ in 0..WINDOW {
            t.record(2.0);
        }
        assert_eq!((t.median(), t.mean()), (Some(2.0), Some(2.0)));
        for bad in [f64::NAN, -1.0, f64::INFINITY] {
            t.record(bad);
        }
        assert_eq!(t.mean(), Some(2.0), "no number is no time");
        t.clear();
        assert_eq!(t.median(), None);
    }

    /// Clock ticks of 0.1 ms: 30 scans of 0.03 ms read as 0, 0 and 0.1.
    #[test]
    fn the_mean_keeps_times_below_the_clock_tick() {
        let mut t = RecentTimes::default();
        for i in 0..30 {
            t.record(if i % 3 == 2 { 0.1 } else { 0.0 });
        }
        assert_eq!(t.median(), Some(0.0));
        assert!((t.mean().unwrap() - 0.1 / 3.0).abs() < 1e-12);
    }
}
