//! What a cell believes, and how one scan's verdict changes it: the cell
//! model, separate from where cells live ([`super::storage`]).
//!
//! The traversal decides, per scan, at most one verdict per cell: occupied
//! (a *hit*: the beam ended in it) or free (a *miss*: the beam passed
//! through), hits winning (Table 9.1 applied once per cell per scan). A
//! cell model turns a verdict into a new cell value, and says what a cell
//! value believes: its probability of occupancy, and whether anything has
//! measured it. Every consumer of a map asks for that belief (a state
//! count or an export asks for a [`Verdict`] under its thresholds, a
//! renderer or a score for the probability).
//!
//! Log odds are one way to hold a belief. [`LogOdds`] is the chapter's
//! binary Bayes filter (Table 9.1: `l <- l + evidence - l0`, clamped); a
//! model that counts hits and visits ([`HitCounting`], GMapping's) or one
//! that steps through tables of odds ([`HitMissOdds`], Cartographer's)
//! keeps log odds at hand too, and says so ([`CellModel::held_log_odds`]),
//! so that the consumers that compare many cells compare them in log odds
//! without a logarithm or an exponential per cell. A model that does not
//! (the tests' last-reading and Beta-count cells, `tests/cell_models.rs`)
//! states a probability and is read through it.

use super::storage::{InCell, StoredCell};
use super::{logit, probability};

/// What a verdict under thresholds is: the three states of a map, and the
/// measured cells between the thresholds (which a trinary map shows as
/// unknown).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Never measured: the cell still holds the model's unknown value.
    Unknown,
    /// Above the occupied threshold.
    Occupied,
    /// Below the free threshold.
    Free,
    /// Measured, and between the thresholds.
    Undecided,
}

/// The thresholds of a verdict: `p > occupied_above` is occupied,
/// `p < free_below` free (strict, as the export's loader compares, see
/// docs/ARCHITECTURE.md, "Real logs"). Held in both forms: a model that
/// holds log odds is compared in log odds (no exponential per cell), in
/// the `f32` form its cells have.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thresholds {
    occupied_above: f64,
    free_below: f64,
    occupied_log_odds: f32,
    free_log_odds: f32,
}

impl Thresholds {
    /// `p > occupied_above` occupied, `p < free_below` free.
    pub fn new(occupied_above: f64, free_below: f64) -> Self {
        Self {
            occupied_above,
            free_below,
            occupied_log_odds: logit(occupied_above) as f32,
            free_log_odds: logit(free_below) as f32,
        }
    }
    /// The occupied threshold, a probability.
    pub fn occupied_above(&self) -> f64 {
        self.occupied_above
    }
    /// The free threshold, a probability.
    pub fn free_below(&self) -> f64 {
        self.free_below
    }
    /// Both thresholds as the log odds cells are compared with.
    pub fn log_odds(&self) -> (f32, f32) {
        (self.occupied_log_odds, self.free_log_odds)
    }
}

/// A cell model: the value a cell holds, what a verdict does to it, and
/// what it believes.
///
/// Required: the updates, [`Self::probability`] and [`Self::is_unknown`].
/// Everything else is derived from them; a model that holds log odds (or
/// has them at hand) overrides [`Self::held_log_odds`] so that the numbers
/// derived from them are its own.
pub trait CellModel: Clone + std::fmt::Debug + PartialEq {
    /// What one cell holds, and how a store counts its updates.
    type Cell: StoredCell;

    /// The cell nothing has measured: the third state, neither free nor
    /// occupied.
    fn unknown(&self) -> Self::Cell;

    /// An occupied verdict. `evidence` is the scan's occupied log odds net
    /// of the prior (`> 0`); a model that does not weigh evidence ignores it.
    fn hit(&self, cell: &mut Self::Cell, evidence: f32);

    /// A free verdict; `evidence` the scan's free log odds net of the prior
    /// (`< 0`).
    fn miss(&self, cell: &mut Self::Cell, evidence: f32);

    /// A verdict of any inverse model as log odds net of the prior, of
    /// either sign (Table 9.1 with a model whose evidence varies per cell,
    /// such as the learned model of §9.3).
    fn add(&self, cell: &mut Self::Cell, evidence: f32);

    /// What the cell believes: its probability of occupancy.
    fn probability(&self, cell: Self::Cell) -> f64;

    /// True while the cell holds exactly the unknown value: measured or
    /// not.
    fn is_unknown(&self, cell: Self::Cell) -> bool;

    /// The log odds the model holds for the cell, when it holds its belief
    /// as log odds or has them at hand without a logarithm; `None` (the
    /// default) for a model read through its probability. Consumers that
    /// compare many cells (the gray ramp, the verdicts) compare these when
    /// there are any, and the probability otherwise.
    #[inline(always)]
    fn held_log_odds(&self, _cell: Self::Cell) -> Option<f32> {
        None
    }

    /// The cell's log odds of occupancy: the ones the model holds, or
    /// those of its probability.
    #[inline(always)]
    fn log_odds(&self, cell: Self::Cell) -> f32 {
        match self.held_log_odds(cell) {
            Some(l) => l,
            None => logit(self.probability(cell)) as f32,
        }
    }

    /// Whether the cell's belief lies above the occupied threshold and
    /// below the free one, whatever [`Self::is_unknown`] says: the two
    /// comparisons of a [`Verdict`], apart, so that a count over many cells
    /// can add them up without a branch.
    #[inline(always)]
    fn beyond(&self, cell: Self::Cell, t: &Thresholds) -> (bool, bool) {
        match self.held_log_odds(cell) {
            Some(l) => (l > t.occupied_log_odds, l < t.free_log_odds),
            None => {
                let p = self.probability(cell);
                (p > t.occupied_above, p < t.free_below)
            }
        }
    }

    /// The cell's state under thresholds `t`: unknown while never
    /// measured (whatever the thresholds say of the unknown value),
    /// occupied above, free below, undecided between.
    #[inline]
    fn verdict(&self, cell: Self::Cell, t: &Thresholds) -> Verdict {
        if self.is_unknown(cell) {
            return Verdict::Unknown;
        }
        match self.beyond(cell, t) {
            (true, _) => Verdict::Occupied,
            (_, true) => Verdict::Free,
            _ => Verdict::Undecided,
        }
    }

    /// The probabilities a trinary export draws this model's cells by,
    /// `(occupied above, free below)`, when they are not the export's
    /// own (`None`, the default: `map_server`'s 0.65 and 0.196). A model
    /// whose single updates are too weak to cross those within the scans a
    /// building gives a cell says where its own verdicts lie.
    #[inline]
    fn trinary_cut(&self) -> Option<(f64, f64)> {
        None
    }

    /// True when known cell `a` believes more in occupancy than known cell
    /// `b`: a view's darkest sample of sixteen (`render::viewport`) is
    /// found with this, and its gray level computed once.
    #[inline(always)]
    fn more_occupied(&self, a: Self::Cell, b: Self::Cell) -> bool {
        match (self.held_log_odds(a), self.held_log_odds(b)) {
            (Some(la), Some(lb)) => la > lb,
            _ => self.probability(a) > self.probability(b),
        }
    }
}

/// The chapter's cell: log odds `l = ln(p / (1 - p))`, one binary Bayes
/// filter per cell (Table 9.1), saturated at `|l| <= clamp` so that a cell
/// stays revisable (a ghost fades after as many contradicting scans as the
/// clamp allows, not as many as confirmed it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogOdds {
    /// The prior's log odds: the unknown cell.
    pub l0: f32,
    /// The saturation, `> 0`.
    pub clamp: f32,
}

impl LogOdds {
    /// From a validated prior probability and clamp.
    pub fn new(prior: f64, clamp: f64) -> Self {
        Self {
            l0: logit(prior) as f32,
            clamp: clamp as f32,
        }
    }
}

impl CellModel for LogOdds {
    type Cell = f32;

    #[inline(always)]
    fn unknown(&self) -> f32 {
        self.l0
    }

    /// (Comparisons rather than `f32::clamp`, which re-checks its bounds on
    /// every call; the evidence is positive, so only the upper clamp can
    /// bind.)
    #[inline(always)]
    fn hit(&self, l: &mut f32, evidence: f32) {
        debug_assert!(evidence >= 0.0);
        let c = self.clamp;
        let v = *l + evidence;
        *l = if v > c { c } else { v };
    }

    #[inline(always)]
    fn miss(&self, l: &mut f32, evidence: f32) {
        debug_assert!(evidence <= 0.0);
        let c = -self.clamp;
        let v = *l + evidence;
        *l = if v < c { c } else { v };
    }

    #[inline(always)]
    fn add(&self, l: &mut f32, evidence: f32) {
        let c = self.clamp;
        let v = *l + evidence;
        *l = if v > c {
            c
        } else if v < -c {
            -c
        } else {
            v
        };
    }

    #[inline(always)]
    fn probability(&self, l: f32) -> f64 {
        probability(l as f64)
    }

    #[inline(always)]
    fn is_unknown(&self, l: f32) -> bool {
        l == self.l0
    }

    #[inline(always)]
    fn held_log_odds(&self, l: f32) -> Option<f32> {
        Some(l)
    }
}

/// A counting cell (GMapping's "reflection map"): how many beams ended in
/// the cell (hits) and how many passed through or ended in it (visits),
/// each at most once per scan. Both counts are halved together when the
/// visits would overflow, which keeps their ratio.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct HitCount {
    pub hits: u16,
    pub visits: u16,
}

/// A counting cell's visits are its updates (one per scan's verdict): no
/// count beside it, 4 bytes a cell rather than 8. (Past 65,535 visits the
/// count halves with the hits, see [`HitCount`].)
impl StoredCell for HitCount {
    type Updates = InCell;
    #[inline(always)]
    fn updates(self, _: InCell) -> u32 {
        self.visits as u32
    }
}

/// GMapping's counting model: a cell is occupied when its hits are more
/// than `occupied_ratio` of its visits, free once visited with a lower
/// ratio, unknown while never visited. One return among many beams that
/// crossed the cell does not make it occupied, and one beam through a cell
/// makes it free.
///
/// Its log odds are the hit ratio placed on the export's scale, so that
/// the trinary export (occupied above p = 0.65, free below 0.196)
/// classifies each cell exactly as the model does: a ratio above the
/// threshold maps linearly onto log odds from `logit(0.651)` to
/// `logit(0.999)`, one at or below it onto `logit(0.001)` to
/// `logit(0.195)`. (Linear in log odds rather than in probability: a map's
/// counts and its render read every cell, and a logarithm per cell cost
/// more than the whole build.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HitCounting {
    /// The hit ratio above which a cell is occupied (GMapping's 0.25).
    pub occupied_ratio: f32,
}

/// The log odds the counting model places its ratios between (see
/// [`HitCounting`]): `logit(0.651)`, `logit(0.999)`, `logit(0.195)` and
/// `logit(0.001)`.
const COUNT_OCCUPIED_FROM: f32 = 0.623_437_7;
const COUNT_OCCUPIED_TO: f32 = 6.906_755;
const COUNT_FREE_FROM: f32 = -1.417_842_7;
const COUNT_FREE_TO: f32 = -6.906_755;

impl HitCounting {
    /// The log odds a ratio `r` of hits to visits stands for (see the
    /// type's doc): continuous and increasing on each side of the
    /// threshold.
    #[inline]
    fn placed(&self, r: f32) -> f32 {
        let t = self.occupied_ratio;
        if r > t {
            COUNT_OCCUPIED_FROM + (r - t) / (1.0 - t) * (COUNT_OCCUPIED_TO - COUNT_OCCUPIED_FROM)
        } else {
            COUNT_FREE_TO + r / t * (COUNT_FREE_FROM - COUNT_FREE_TO)
        }
    }

    /// The log odds a cell stands for: its ratio placed, 0 while never
    /// visited.
    #[inline]
    fn placed_log_odds(&self, cell: HitCount) -> f32 {
        if cell.visits == 0 {
            return 0.0;
        }
        self.placed(cell.hits as f32 / cell.visits as f32)
    }

    #[inline(always)]
    fn count(cell: &mut HitCount, hit: bool) {
        if cell.visits == u16::MAX {
            cell.hits /= 2;
            cell.visits /= 2;
        }
        cell.visits += 1;
        cell.hits += hit as u16;
    }
}

impl CellModel for HitCounting {
    type Cell = HitCount;

    #[inline(always)]
    fn unknown(&self) -> HitCount {
        HitCount::default()
    }
    #[inline(always)]
    fn hit(&self, cell: &mut HitCount, _: f32) {
        Self::count(cell, true)
    }
    #[inline(always)]
    fn miss(&self, cell: &mut HitCount, _: f32) {
        Self::count(cell, false)
    }
    #[inline(always)]
    fn add(&self, cell: &mut HitCount, evidence: f32) {
        if evidence != 0.0 {
            Self::count(cell, evidence > 0.0)
        }
    }
    /// The probability of the log odds the ratio is placed at (see the
    /// type's doc), 0.5 while never visited.
    #[inline]
    fn probability(&self, cell: HitCount) -> f64 {
        probability(self.placed_log_odds(cell) as f64)
    }
    #[inline(always)]
    fn is_unknown(&self, cell: HitCount) -> bool {
        cell.visits == 0
    }
    #[inline]
    fn held_log_odds(&self, cell: HitCount) -> Option<f32> {
        Some(self.placed_log_odds(cell))
    }
    /// The log odds rise with the hit ratio (both pieces of `placed`
    /// rise): the ratios compared without a division.
    #[inline(always)]
    fn more_occupied(&self, a: HitCount, b: HitCount) -> bool {
        a.hits as u32 * b.visits as u32 > b.hits as u32 * a.visits as u32
    }
}

/// The steps of the hit/miss odds model's lookup tables: a cell holds one
/// of these many probabilities (Cartographer's 15-bit cell values).
const ODDS_STEPS: usize = 32_767;

/// Cartographer's probability grid: a hit multiplies the cell's odds by
/// `odds(p_hit)`, a miss by `odds(p_miss)`, the probability kept within
/// `[p_min, p_max]`; an unknown cell takes `p_hit` or `p_miss` at once.
/// Cells hold a 15-bit index of their probability (0: unknown), and an
/// update is one lookup in a table made once per model.
#[derive(Debug, Clone, PartialEq)]
pub struct HitMissOdds {
    pub p_hit: f32,
    pub p_miss: f32,
    pub p_min: f32,
    pub p_max: f32,
    hit_table: std::sync::Arc<[u16]>,
    miss_table: std::sync::Arc<[u16]>,
    /// Per cell value, its log odds (0 for the unknown value): a map's
    /// counts and render read every cell.
    log_odds_table: std::sync::Arc<[f32]>,
}

impl HitMissOdds {
    /// The tables for `p_hit` (> 0.5), `p_miss` (< 0.5) within
    /// `[p_min, p_max]` (validated by the caller: 0 < p_min < p_miss <
    /// 0.5 < p_hit < p_max < 1).
    pub fn new(p_hit: f32, p_miss: f32, p_min: f32, p_max: f32) -> Self {
        let value_of = |p: f32| -> u16 {
            let f = (p.clamp(p_min, p_max) - p_min) / (p_max - p_min);
            1 + (f * (ODDS_STEPS - 1) as f32).round() as u16
        };
        let table = |p_update: f32| -> std::sync::Arc<[u16]> {
            let odds = p_update / (1.0 - p_update);
            (0..=ODDS_STEPS)
                .map(|v| {
                    if v == 0 {
                        return value_of(p_update);
                    }
                    let p = p_min + (v - 1) as f32 / (ODDS_STEPS - 1) as f32 * (p_max - p_min);
                    let o = p / (1.0 - p) * odds;
                    value_of(o / (1.0 + o))
                })
                .collect()
        };
        let log_odds_table = (0..=ODDS_STEPS)
            .map(|v| {
                if v == 0 {
                    return 0.0;
                }
                let p = p_min + (v - 1) as f32 / (ODDS_STEPS - 1) as f32 * (p_max - p_min);
                (p / (1.0 - p)).ln()
            })
            .collect();
        Self {
            p_hit,
            p_miss,
            p_min,
            p_max,
            hit_table: table(p_hit),
            miss_table: table(p_miss),
            log_odds_table,
        }
    }

    /// Where a trinary export draws these cells: occupied above even odds,
    /// free below them, i.e. by which way its hits and misses have moved
    /// it. A miss multiplies the odds by `odds(0.49)`, so a cell needs
    /// some 34 misses to fall below `map_server`'s 0.196 from its first
    /// 0.49: at that cut the floor of a building, crossed by a few beams
    /// per cell, exported gray and the robot's own path was not free.
    /// (Cartographer's own occupancy grids publish the probability and
    /// leave the cut to the planner.)
    pub const TRINARY_CUT: (f64, f64) = (0.5, 0.5);

    /// Cartographer's 2-D defaults: hit 0.55, miss 0.49, within [0.1, 0.9].
    pub fn cartographer() -> Self {
        Self::new(0.55, 0.49, 0.1, 0.9)
    }

    /// The probability a cell value stands for.
    #[inline]
    pub fn probability_of(&self, v: u16) -> f32 {
        self.p_min + (v.max(1) - 1) as f32 / (ODDS_STEPS - 1) as f32 * (self.p_max - self.p_min)
    }
}

impl CellModel for HitMissOdds {
    type Cell = u16;

    #[inline(always)]
    fn unknown(&self) -> u16 {
        0
    }
    #[inline(always)]
    fn hit(&self, v: &mut u16, _: f32) {
        *v = self.hit_table[*v as usize & ODDS_STEPS];
    }
    #[inline(always)]
    fn miss(&self, v: &mut u16, _: f32) {
        *v = self.miss_table[*v as usize & ODDS_STEPS];
    }
    #[inline(always)]
    fn add(&self, v: &mut u16, evidence: f32) {
        if evidence > 0.0 {
            self.hit(v, evidence)
        } else if evidence < 0.0 {
            self.miss(v, evidence)
        }
    }
    /// The probability of the value's log odds (the table's, so that the
    /// probability and the log odds a consumer reads agree to rounding);
    /// 0.5 for the unknown value.
    #[inline]
    fn probability(&self, v: u16) -> f64 {
        probability(self.log_odds_table[v as usize & ODDS_STEPS] as f64)
    }
    #[inline(always)]
    fn is_unknown(&self, v: u16) -> bool {
        v == 0
    }
    #[inline]
    fn trinary_cut(&self) -> Option<(f64, f64)> {
        Some(Self::TRINARY_CUT)
    }
    #[inline]
    fn held_log_odds(&self, v: u16) -> Option<f32> {
        Some(self.log_odds_table[v as usize & ODDS_STEPS])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_odds_cell_clamps_on_the_side_its_verdict_moves() {
        let m = LogOdds::new(0.5, 2.0);
        let mut l = m.unknown();
        assert!(m.is_unknown(l));
        m.hit(&mut l, 1.5);
        m.hit(&mut l, 1.5);
        assert_eq!(l, 2.0);
        m.miss(&mut l, -5.0);
        assert_eq!(l, -2.0);
        m.add(&mut l, 0.5);
        assert_eq!(l, -1.5);
        m.add(&mut l, 9.0);
        assert_eq!(l, 2.0);
        assert!(!m.is_unknown(l));
        assert!((m.probability(l) - probability(2.0)).abs() < 1e-12);
    }

    /// One stray return among beams that crossed the cell leaves it free;
    /// hits above the ratio make it occupied; one beam makes a cell free.
    #[test]
    fn counting_cell_is_occupied_above_its_hit_ratio_and_free_once_crossed() {
        let m = HitCounting {
            occupied_ratio: 0.25,
        };
        let mut c = m.unknown();
        assert!(m.is_unknown(c));
        m.miss(&mut c, -0.4);
        assert!(!m.is_unknown(c) && m.probability(c) < 0.196);
        m.hit(&mut c, 0.85);
        assert_eq!(c, HitCount { hits: 1, visits: 2 });
        assert!(m.probability(c) > 0.65, "1 of 2 is above 0.25");
        for _ in 0..3 {
            m.miss(&mut c, -0.4);
        }
        assert!(m.probability(c) < 0.196, "1 of 5 is a stray return");
        let mut full = HitCount {
            hits: 40_000,
            visits: u16::MAX,
        };
        m.hit(&mut full, 0.85);
        assert_eq!(
            full,
            HitCount {
                hits: 20_001,
                visits: 32_768
            }
        );
    }

    /// The counting model's log odds classify a cell as the model does,
    /// under the export's thresholds, at and around the hit ratio.
    #[test]
    fn counting_log_odds_put_the_hit_ratio_on_the_export_s_thresholds() {
        let m = HitCounting {
            occupied_ratio: 0.25,
        };
        let p = |hits, visits| m.probability(HitCount { hits, visits });
        assert!(p(1, 4) < 0.196 && p(1, 4) > 0.19, "at the ratio: free");
        assert!(p(1001, 4000) > 0.65, "just above it: occupied");
        assert!(p(0, 1) < 0.002 && p(1, 1) > 0.998);
        let mut last = 0.0;
        for hits in 0..=40 {
            let now = p(hits, 40);
            assert!(now > last, "increasing in the ratio");
            last = now;
        }
        assert_eq!(m.log_odds(m.unknown()), 0.0);
        let odds = HitMissOdds::cartographer();
        for v in [1u16, 2, 100, 20_000, 32_767] {
            let q = odds.probability_of(v);
            assert!((odds.probability(v) - q as f64).abs() < 1e-5);
        }
        assert_eq!(odds.log_odds(0), 0.0);
    }

    /// Cartographer's odds: an unknown cell takes p_hit or p_miss at once,
    /// then each update multiplies the odds, within [p_min, p_max].
    #[test]
    fn hit_miss_odds_multiply_and_stay_within_their_bounds() {
        let m = HitMissOdds::cartographer();
        let mut v = m.unknown();
        m.hit(&mut v, 1.0);
        assert!((m.probability(v) - 0.55).abs() < 1e-4);
        m.hit(&mut v, 1.0);
        let odds = (0.55f64 / 0.45).powi(2);
        assert!((m.probability(v) - odds / (1.0 + odds)).abs() < 1e-4);
        for _ in 0..100 {
            m.hit(&mut v, 1.0);
        }
        assert!((m.probability(v) - 0.9).abs() < 1e-4);
        for _ in 0..1000 {
            m.miss(&mut v, -1.0);
        }
        assert!((m.probability(v) - 0.1).abs() < 1e-4);
        let mut u = m.unknown();
        m.miss(&mut u, -1.0);
        assert!((m.probability(u) - 0.49).abs() < 1e-4);
    }

    /// A model that holds log odds is read through them: its log odds are
    /// the held ones, its probability theirs, and its verdicts are made
    /// in log odds against the thresholds' `f32` log odds (no cell changes
    /// state for being read through its probability).
    #[test]
    fn held_log_odds_are_what_verdicts_and_log_odds_read() {
        fn check<M: CellModel>(m: &M, cells: &[M::Cell]) -> usize {
            let mut states = [0; 4];
            for t in [Thresholds::new(0.65, 0.35), Thresholds::new(0.65, 0.196)] {
                let (occ_l, free_l) = t.log_odds();
                for &c in cells {
                    let l = m.held_log_odds(c).unwrap();
                    assert_eq!(m.log_odds(c).to_bits(), l.to_bits());
                    assert_eq!(m.probability(c).to_bits(), probability(l as f64).to_bits());
                    let expected = if m.is_unknown(c) {
                        Verdict::Unknown
                    } else if l > occ_l {
                        Verdict::Occupied
                    } else if l < free_l {
                        Verdict::Free
                    } else {
                        Verdict::Undecided
                    };
                    assert_eq!(m.verdict(c, &t), expected, "{c:?}");
                    assert_eq!(m.beyond(c, &t), (l > occ_l, l < free_l));
                    states[expected as usize] += 1;
                }
            }
            states.iter().filter(|&&n| n > 0).count()
        }
        let log_odds = LogOdds::new(0.3, 4.0);
        let ls: Vec<f32> = (-45..=45)
            .map(|k| k as f32 * 0.1)
            .chain([log_odds.l0])
            .collect();
        assert_eq!(check(&log_odds, &ls), 4);
        let counting = HitCounting {
            occupied_ratio: 0.25,
        };
        let counts: Vec<HitCount> = (0..=12u16)
            .flat_map(|visits| (0..=visits).map(move |hits| HitCount { hits, visits }))
            .collect();
        // (Its log odds skip the band between the export's thresholds:
        // no counting cell is undecided.)
        assert_eq!(check(&counting, &counts), 3);
        let odds = HitMissOdds::cartographer();
        let values: Vec<u16> = (0..=32_767u16).step_by(97).chain([0, 1, 32_767]).collect();
        assert_eq!(check(&odds, &values), 4);
    }

    #[test]
    fn hit_counting_orders_cells_by_log_odds_without_a_division() {
        // Every pair of cells of up to 40 visits, at GMapping's ratio and
        // at ratios on and between the cells' own: the comparison the
        // view uses agrees with the log odds it stands for.
        for occupied_ratio in [0.25, 0.5, 0.1, 0.9] {
            let m = HitCounting { occupied_ratio };
            let cells: Vec<HitCount> = (1..=40u16)
                .flat_map(|visits| (0..=visits).map(move |hits| HitCount { hits, visits }))
                .collect();
            for &a in &cells {
                for &b in &cells {
                    assert_eq!(
                        m.more_occupied(a, b),
                        m.log_odds(a) > m.log_odds(b),
                        "{a:?} against {b:?} at {occupied_ratio}"
                    );
                }
            }
        }
    }
}
