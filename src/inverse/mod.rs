//! Inverse sensor models: from one beam's reading to evidence about a cell.
//!
//! An inverse model answers `p(m_i | z, x)` for a cell near one beam, as log
//! odds (Probabilistic Robotics §9.2). Mappers only see the
//! [`InverseModel`] trait, so the hand-crafted model of Table 9.2 and the
//! learned model of §9.3 are interchangeable in every mapper.

mod hand_crafted;

pub use hand_crafted::{HandCrafted, HandCraftedParams};

/// What a mapper asks of an inverse sensor model.
///
/// Geometry is in the beam's frame: `r` is the cell centre's range from the
/// sensor in metres, `phi` its bearing offset from the beam axis in radians,
/// `z` the beam's reading in metres (already validated: finite, `>= 0`).
pub trait InverseModel {
    /// Evidence for the cell, in log odds, *net of the model's own prior*:
    /// the term `inverse_sensor_model(m_i, x_t, z_t) - l0` of Table 9.1,
    /// line 4. Zero means "no information".
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32;

    /// The largest range along a beam reading `z` at which a cell can still
    /// receive evidence: a ray traversal stops there.
    fn reach(&self, z: f64) -> f64;

    /// Half the opening angle of the perceptual field, radians: cells
    /// farther off the beam axis receive no evidence.
    fn half_width(&self) -> f64;

    /// The sensor's maximum range, metres. A reading at or beyond it is a
    /// no-return.
    fn z_max(&self) -> f64;

    /// The model's own prior, in log odds.
    fn l0(&self) -> f32;
}

impl<M: InverseModel + ?Sized> InverseModel for &M {
    fn evidence(&self, r: f64, phi: f64, z: f64) -> f32 {
        (**self).evidence(r, phi, z)
    }
    fn reach(&self, z: f64) -> f64 {
        (**self).reach(z)
    }
    fn half_width(&self) -> f64 {
        (**self).half_width()
    }
    fn z_max(&self) -> f64 {
        (**self).z_max()
    }
    fn l0(&self) -> f32 {
        (**self).l0()
    }
}
