//! Gaussian noise, drawn one way everywhere, from the caller's seeded
//! generator, so that a seed fixes every reading.
//!
//! The Box–Muller transform takes exactly two uniforms per draw, whatever
//! the value, so streams stay aligned whatever is sampled. (A ziggurat
//! sampler such as `rand_distr`'s `StandardNormal` takes a varying number,
//! which re-draws everything after the first noisy reading: the learned
//! model's training set among it.)

use rand::Rng;
use std::f64::consts::TAU;

/// One standard normal draw from `rng` (Box–Muller; `1 - u` lies in
/// `(0, 1]`, so the logarithm is finite).
#[inline]
pub fn standard_normal<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::rngs::StdRng;
    use rand::SeedableRng;

    #[test]
    fn standard_normal_has_unit_variance_and_zero_mean() {
        let mut rng = StdRng::seed_from_u64(3);
        let n = 20_000;
        let xs: Vec<f64> = (0..n).map(|_| standard_normal(&mut rng)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.03, "{mean}");
        assert!((var - 1.0).abs() < 0.05, "{var}");
    }
}
