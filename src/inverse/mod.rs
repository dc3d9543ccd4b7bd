//! Inverse sensor models: from one beam's reading to evidence about a cell.
//!
//! An inverse model answers `p(m_i | z, x)` for a cell near one beam, as log
//! odds (Probabilistic Robotics §9.2). Mappers only see the
//! [`InverseModel`] trait, so the hand-crafted model of Table 9.2 and the
//! learned model of §9.3 are interchangeable in every mapper.

mod hand_crafted;
pub mod learned;
pub mod probes;
pub mod scaled;
pub mod training;

pub use hand_crafted::{HandCrafted, HandCraftedParams};
pub use learned::LearnedInverse;
pub use scaled::Scaled;
pub use training::TrainingConfig;

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

    /// `evidence(r, 0, z)` for every range `r` at once, when it is a step
    /// function of `r` (Table 9.2 is: free, then occupied, then nothing).
    /// A thin beam's traversal then compares each cell's range with two
    /// numbers instead of asking the model per cell. `None` (the default)
    /// means the mapper calls [`InverseModel::evidence`] per cell.
    fn axis_profile(&self, _z: f64) -> Option<AxisProfile> {
        None
    }
}

/// The evidence along a beam's axis (`phi = 0`) for one reading, as a step
/// function of the range `r` (metres):
///
/// * `r <= free_until`: `free`;
/// * `free_until < r <= occupied_until`: `occupied`;
/// * beyond: zero (no information).
///
/// An empty band has `occupied_until == free_until`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisProfile {
    /// Last range (metres) with free evidence.
    pub free_until: f64,
    /// Evidence net of `l0` for the free band, log odds.
    pub free: f32,
    /// Last range (metres) with occupied evidence.
    pub occupied_until: f64,
    /// Evidence net of `l0` for the occupied band, log odds.
    pub occupied: f32,
}

impl AxisProfile {
    /// The evidence at range `r` (metres) along the axis.
    #[inline(always)]
    pub fn at(&self, r: f64) -> f32 {
        if r <= self.free_until {
            self.free
        } else if r <= self.occupied_until {
            self.occupied
        } else {
            0.0
        }
    }
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
    fn axis_profile(&self, z: f64) -> Option<AxisProfile> {
        (**self).axis_profile(z)
    }
}
