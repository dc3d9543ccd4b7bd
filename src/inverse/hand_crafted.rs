//! The hand-crafted inverse range sensor model of Table 9.2.

use super::{AxisProfile, InverseModel};
use crate::error::{self, invalid, Result};
use crate::grid::logit;

/// The parameters of Table 9.2, as log odds (OctoMap's habit: stored as log
/// odds, built from probabilities by [`HandCraftedParams::from_probabilities`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HandCraftedParams {
    /// Obstacle thickness `alpha`, metres.
    pub alpha: f64,
    /// Opening angle of the beam `beta`, radians.
    pub beta: f64,
    /// Maximum range `z_max`, metres.
    pub z_max: f64,
    /// Posterior log odds of a cell at the reading, `l_occ`.
    pub l_occ: f64,
    /// Posterior log odds of a cell in front of the reading, `l_free`.
    pub l_free: f64,
    /// Prior log odds `l0`, removed from every update.
    pub l0: f64,
}

impl HandCraftedParams {
    /// Table 9.2 for a laser range finder, the values of docs/BENCHMARKS.md W1
    /// (and the real-log defaults): `alpha` = 10 cm, `l_occ = +0.85`,
    /// `l_free = -0.40`, `l0 = 0`, out to `z_max` metres. A laser beam is
    /// thin: the ray mapper passes `phi = 0`, and only the literal sweep
    /// looks at the opening angle, one degree, a scan's beam spacing.
    pub fn laser(z_max: f64) -> Self {
        Self {
            alpha: 0.10,
            beta: 1f64.to_radians(),
            z_max,
            l_occ: 0.85,
            l_free: -0.40,
            l0: 0.0,
        }
    }

    /// Table 9.2 with `l_occ = logit(p_occ)`, `l_free = logit(p_free)` and
    /// `l0 = logit(prior)`.
    pub fn from_probabilities(
        p_occ: f64,
        p_free: f64,
        prior: f64,
        alpha: f64,
        beta: f64,
        z_max: f64,
    ) -> Result<Self> {
        error::open_probability("p_occ", p_occ)?;
        error::open_probability("p_free", p_free)?;
        error::open_probability("prior", prior)?;
        let p = Self {
            alpha,
            beta,
            z_max,
            l_occ: logit(p_occ),
            l_free: logit(p_free),
            l0: logit(prior),
        };
        p.validate()?;
        Ok(p)
    }

    pub fn validate(&self) -> Result<()> {
        error::positive("alpha", self.alpha)?;
        error::positive("beta", self.beta)?;
        if self.beta > std::f64::consts::TAU {
            return Err(invalid(
                "beta",
                error::show(self.beta),
                "an opening angle of at most 2 pi radians",
            ));
        }
        error::positive("z_max", self.z_max)?;
        error::finite("l_occ", self.l_occ)?;
        error::finite("l_free", self.l_free)?;
        error::finite("l0", self.l0)?;
        Ok(())
    }
}

/// Table 9.2 (with line 2 comparing the cell's range to the *reading* `z`,
/// not to `z_max` as a known misprint has it: that misprint paints a shell of
/// obstacles at maximum range).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandCrafted {
    params: HandCraftedParams,
    occ: f32,
    free: f32,
}

impl HandCrafted {
    pub fn new(params: HandCraftedParams) -> Result<Self> {
        params.validate()?;
        let (occ, free) = (
            (params.l_occ - params.l0) as f32,
            (params.l_free - params.l0) as f32,
        );
        // The evidence reaches the map as f32: finite log odds whose
        // difference overflows f32 would add an infinity to a cell.
        for (field, value, evidence) in [
            ("l_occ", params.l_occ, occ),
            ("l_free", params.l_free, free),
        ] {
            if !evidence.is_finite() {
                return Err(invalid(
                    field,
                    error::show(value),
                    "log odds within 3.4e38 of l0 (evidence is stored as f32)",
                ));
            }
        }
        Ok(Self { params, occ, free })
    }

    /// The same model with `l_occ` and `l_free` scaled together by
    /// `strength` (the widgets' evidence-strength slider).
    pub fn with_strength(params: HandCraftedParams, strength: f64) -> Result<Self> {
        error::non_negative("strength", strength)?;
        Self::new(HandCraftedParams {
            l_occ: params.l_occ * strength,
            l_free: params.l_free * strength,
            ..params
        })
    }

    pub fn params(&self) -> &HandCraftedParams {
        &self.params
    }
}

impl InverseModel for HandCrafted {
    #[inline]
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32 {
        let p = &self.params;
        let half_alpha = 0.5 * p.alpha;
        // Line 1: outside the perceptual field.
        if r > shorter(p.z_max, z + half_alpha) || phi.abs() > 0.5 * p.beta {
            return 0.0;
        }
        // Line 2: at the reading (and only for a real return). |r - z| <
        // alpha/2 is tested as z - alpha/2 < r < z + alpha/2: the band's
        // edges are then two floats, which `axis_profile` states exactly.
        if z < p.z_max && r > z - half_alpha && r < z + half_alpha {
            return self.occ;
        }
        // Line 3: in front of the reading.
        if r <= z {
            return self.free;
        }
        0.0
    }

    #[inline]
    fn reach(&self, z: f64) -> f64 {
        shorter(self.params.z_max, z + 0.5 * self.params.alpha)
    }

    fn half_width(&self) -> f64 {
        0.5 * self.params.beta
    }

    fn z_max(&self) -> f64 {
        self.params.z_max
    }

    fn l0(&self) -> f32 {
        self.params.l0 as f32
    }

    /// Table 9.2 on the beam axis: free up to the obstacle band, occupied
    /// within `alpha / 2` of the reading, nothing past the reach. The two
    /// thresholds are the exact floating-point boundaries of the tests in
    /// [`HandCrafted::evidence`], so `profile.at(r) == evidence(r, 0, z)`
    /// for every `r`, not only away from the edges.
    fn axis_profile(&self, z: f64) -> Option<AxisProfile> {
        let p = &self.params;
        let reach = self.reach(z);
        #[allow(clippy::neg_cmp_op_on_partial_ord)] // a NaN range is a no-return
        if !(z < p.z_max) {
            // A no-return (line 2 never fires): free out to the reach,
            // which is z_max <= z.
            return Some(AxisProfile {
                free_until: reach,
                free: self.free,
                occupied_until: reach,
                occupied: self.occ,
            });
        }
        // Line 2 holds on the open interval between the two edges `evidence`
        // compares with. Below it r < z, so line 3 gives free; above it
        // r > z, so nothing. Line 1 cuts the band at the reach (which is
        // >= z).
        let half_alpha = 0.5 * p.alpha;
        Some(AxisProfile {
            free_until: z - half_alpha,
            free: self.free,
            occupied_until: shorter((z + half_alpha).next_down(), reach),
            occupied: self.occ,
        })
    }
}

/// `a.min(b)` for a finite `a`, written as a comparison: in wasm `f64::min`
/// is a library call, and these run once per beam. (A NaN `b` gives `a`,
/// as `f64::min` does.)
#[inline(always)]
fn shorter(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    fn model() -> HandCrafted {
        HandCrafted::new(HandCraftedParams {
            alpha: 0.2,
            beta: 0.1,
            ..HandCraftedParams::laser(5.0)
        })
        .unwrap()
    }

    #[test]
    fn table_9_2_regions() {
        let m = model();
        assert_eq!(m.evidence(1.0, 0.0, 2.0), -0.4f32, "in front: free");
        assert_eq!(
            m.evidence(2.05, 0.0, 2.0),
            0.85f32,
            "at the reading: occupied"
        );
        assert_eq!(m.evidence(1.95, 0.0, 2.0), 0.85f32);
        assert_eq!(m.evidence(2.2, 0.0, 2.0), 0.0, "behind: no information");
        assert_eq!(m.evidence(1.0, 0.06, 2.0), 0.0, "outside the cone");
    }

    #[test]
    fn max_range_reading_carves_free_space_and_marks_nothing() {
        let m = model();
        assert_eq!(
            m.evidence(4.95, 0.0, 5.0),
            -0.4f32,
            "no shell at z_max (the misprint)"
        );
        assert_eq!(m.evidence(4.0, 0.0, 7.0), -0.4f32);
        assert_eq!(m.evidence(5.01, 0.0, 7.0), 0.0);
        assert_eq!(m.reach(7.0), 5.0);
    }

    #[test]
    fn evidence_is_net_of_the_prior() {
        let p = HandCraftedParams::from_probabilities(0.7, 0.3, 0.2, 0.2, 0.1, 5.0).unwrap();
        let m = HandCrafted::new(p).unwrap();
        let expect = ((0.7f64 / 0.3).ln() - (0.2f64 / 0.8).ln()) as f32;
        assert!((m.evidence(2.0, 0.0, 2.0) - expect).abs() < 1e-6);
    }

    #[test]
    fn rejects_bad_parameters() {
        let e = HandCraftedParams::from_probabilities(1.0, 0.3, 0.5, 0.2, 0.1, 5.0).unwrap_err();
        assert!(e.to_string().contains("p_occ"));
        let e = HandCraftedParams::from_probabilities(0.7, 0.3, 0.5, -0.2, 0.1, 5.0).unwrap_err();
        assert!(e.to_string().contains("alpha") && e.to_string().contains("-0.2"));
        assert!(HandCrafted::with_strength(*model().params(), f64::NAN).is_err());
    }

    #[test]
    fn axis_profile_agrees_with_evidence_at_every_range() {
        let mut rng = StdRng::seed_from_u64(3);
        for _ in 0..2_000 {
            let m = HandCrafted::new(HandCraftedParams {
                alpha: rng.random_range(0.01..0.5),
                beta: 0.1,
                z_max: rng.random_range(1.0..40.0),
                l_occ: rng.random_range(0.1..3.0),
                l_free: rng.random_range(-3.0..-0.1),
                l0: rng.random_range(-0.5..0.5),
            })
            .unwrap();
            let z_max = m.params().z_max;
            // Real returns, readings at and beyond z_max, and zero.
            let z = match rng.random_range(0..4) {
                0 => z_max,
                1 => z_max * rng.random_range(1.0..3.0),
                2 => 0.0,
                _ => rng.random_range(0.0..z_max),
            };
            let p = m.axis_profile(z).expect("Table 9.2 is a step function");
            let mut ranges: Vec<f64> = (0..40)
                .map(|_| rng.random_range(-1.0..z_max + 1.0))
                .collect();
            // The edges themselves and their float neighbours.
            for edge in [
                p.free_until,
                p.occupied_until,
                z,
                z - 0.5 * m.params().alpha,
            ] {
                ranges.extend([edge.next_down(), edge, edge.next_up()]);
            }
            for r in ranges {
                assert_eq!(p.at(r), m.evidence(r, 0.0, z), "r = {r}, z = {z}, {p:?}");
            }
        }
    }

    #[test]
    fn axis_profile_of_a_no_return_is_free_out_to_z_max() {
        let m = model();
        let p = m.axis_profile(7.0).unwrap();
        assert_eq!((p.free_until, p.occupied_until), (5.0, 5.0));
        assert_eq!(p.at(4.99), -0.4f32);
        assert_eq!(p.at(5.01), 0.0);
    }
}
