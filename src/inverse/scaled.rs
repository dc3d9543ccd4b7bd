//! Evidence scaled by a constant: any inverse model, its log-odds evidence
//! multiplied by a factor.
//!
//! Table 9.2's model has its own strength (`l_occ` and `l_free` scale
//! directly, [`super::HandCrafted::with_strength`]); the learned model of
//! §9.3 has no such numbers, so an evidence-strength knob that works for
//! every model scales the term `inverse_sensor_model - l0` of Table 9.1,
//! line 4, as a whole. The perceptual field (reach, opening, `z_max`) and
//! the model's own prior are the model's, unchanged.

use super::{AxisProfile, InverseModel};
use crate::error::{self, Result};

/// `model`'s evidence times `factor`.
#[derive(Debug, Clone)]
pub struct Scaled<M> {
    pub model: M,
    pub factor: f32,
}

impl<M> Scaled<M> {
    /// `model` with its evidence times `factor`: a finite number of at
    /// least 0 (0 silences the model, 1 leaves it as it is) that an `f32`
    /// holds, as the evidence is.
    pub fn new(model: M, factor: f64) -> Result<Self> {
        error::non_negative("factor", factor)?;
        if factor > f32::MAX as f64 {
            return Err(error::invalid(
                "factor",
                error::show(factor),
                format!("at most {:e}, the largest f32", f32::MAX),
            ));
        }
        Ok(Self {
            model,
            factor: factor as f32,
        })
    }
}

impl<M: InverseModel> InverseModel for Scaled<M> {
    #[inline]
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32 {
        self.factor * self.model.evidence(r, phi, z)
    }
    #[inline]
    fn reach(&self, z: f64) -> f64 {
        self.model.reach(z)
    }
    fn half_width(&self) -> f64 {
        self.model.half_width()
    }
    fn z_max(&self) -> f64 {
        self.model.z_max()
    }
    fn l0(&self) -> f32 {
        self.model.l0()
    }
    /// The model's step profile with both steps scaled, so that a thin
    /// beam's traversal keeps its two comparisons per cell.
    fn axis_profile(&self, z: f64) -> Option<AxisProfile> {
        self.model.axis_profile(z).map(|p| AxisProfile {
            free: self.factor * p.free,
            occupied: self.factor * p.occupied,
            ..p
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inverse::{HandCrafted, HandCraftedParams};

    fn table_9_2() -> HandCrafted {
        HandCrafted::new(HandCraftedParams::laser(8.0)).unwrap()
    }

    /// Scaling the whole evidence by `s` is Table 9.2 with `l_occ` and
    /// `l_free` scaled by `s` (its `l0` is 0), everywhere in the field.
    #[test]
    fn scaled_evidence_is_the_model_with_its_log_odds_scaled() {
        let base = table_9_2();
        for s in [0.0, 0.25, 1.0, 3.0] {
            let scaled = Scaled::new(base, s).unwrap();
            let direct = HandCrafted::with_strength(HandCraftedParams::laser(8.0), s).unwrap();
            for z in [0.5, 2.0, 7.9, 8.0] {
                for i in 0..100 {
                    let r = i as f64 * 0.09;
                    for phi in [0.0, 0.005, -0.008, 0.1] {
                        let (a, b) = (scaled.evidence(r, phi, z), direct.evidence(r, phi, z));
                        assert!(
                            (a - b).abs() < 1e-6,
                            "s {s}, z {z}, r {r}, phi {phi}: {a} vs {b}"
                        );
                        assert_eq!(a, s as f32 * base.evidence(r, phi, z));
                    }
                }
                assert_eq!(scaled.reach(z), base.reach(z));
            }
            assert_eq!(scaled.half_width(), base.half_width());
            assert_eq!(scaled.z_max(), base.z_max());
            assert_eq!(scaled.l0(), base.l0());
        }
    }

    /// The forwarded step profile says what `evidence` says on the axis.
    #[test]
    fn the_scaled_axis_profile_agrees_with_the_scaled_evidence() {
        let scaled = Scaled::new(table_9_2(), 2.5).unwrap();
        for z in [0.3, 3.0, 8.0] {
            let p = scaled.axis_profile(z).unwrap();
            for i in 0..200 {
                let r = i as f64 * 0.05;
                assert_eq!(p.at(r), scaled.evidence(r, 0.0, z), "z {z}, r {r}");
            }
        }
    }

    #[test]
    fn a_factor_that_is_no_number_or_negative_is_refused_by_name() {
        for bad in [-0.5, f64::NAN, f64::INFINITY, 1e300] {
            let e = Scaled::new(table_9_2(), bad).unwrap_err().to_string();
            assert!(e.starts_with("invalid factor: "), "{e}");
        }
    }
}
