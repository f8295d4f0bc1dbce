//! Exponential moving covariance matrix (EMCM) of a vector stream.

use num_traits::Float;

use super::Weight;
use super::moving_covariance::sealed::Sealed;
use super::moving_covariance::{MovingCovariance, UpdateRule};

/// Exponential moving covariance matrix of a vector stream `Z_t` in `R^N` with EMA mean
/// `zeta`:
/// `Sigma_t = (1 - eta) Sigma_{t-1} + eta (1 - eta) (Z_t - zeta_{t-1})(Z_t - zeta_{t-1})^T`,
/// then `zeta_t = (1 - eta) zeta_{t-1} + eta Z_t`.
///
/// Invariants:
/// - entry `(i, j)` is exactly the [`Emc`](super::Emc) of streams `i` and `j` (same
///   operations in the same order), and the diagonal is the [`Emv`](super::Emv) of each
///   stream, so it is never negative;
/// - `Sigma` is symmetric and stored once, as the packed lower triangle
///   (`N (N + 1) / 2` numbers, see [`Packed`](super::Packed)); it is positive
///   semi-definite in exact arithmetic, and up to rounding of order `eps * trace` in
///   floating point;
/// - non-finite input (any component) skips the whole update; overflow saturates
///   (see the [module docs](super)).
///
/// An alias of [`MovingCovariance`] with the [`Finch`] rule, where its methods are
/// documented. `Default` is the zero state; [`Emcm::seeded`] is the first-sample seed.
/// `N` ranges over `1..=16`.
///
/// # Examples
///
/// ```
/// use spvg::stats::{Emcm, Weight};
/// let w = Weight::new(0.5_f64).unwrap();
/// let mut s = Emcm::<f64, 2>::seeded([0.0, 0.0]);
/// assert!(s.update(&w, [2.0, -4.0]));
/// assert_eq!(s.mean(), [1.0, -2.0]);
/// assert_eq!(s.matrix(), [[1.0, -2.0], [-2.0, 4.0]]);
/// assert_eq!(s.covariance(1, 0), s.covariance(0, 1));
/// assert_eq!(s.covariance(7, 0), 0.0); // out of range: zero, no panic
/// // Row i divided by Sigma_ii.
/// assert_eq!(s.coefficients(), [[1.0, -2.0], [-0.5, 1.0]]);
/// assert!(!s.update(&w, [f64::NAN, 1.0])); // skipped as a whole
/// assert_eq!(s.mean(), [1.0, -2.0]);
/// ```
pub type Emcm<T, const N: usize> = MovingCovariance<T, N, Finch>;

/// The update rule of [`Emcm`]: rank-one factor `eta (1 - eta)`, the multivariate form of
/// Finch's (2009) exponential moving variance.
///
/// # Examples
///
/// ```
/// use spvg::stats::{Finch, UpdateRule, Weight};
/// let w = Weight::new(0.25_f64).unwrap();
/// assert_eq!(Finch::factor(&w), 0.25 * 0.75);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Finch;

impl Sealed for Finch {}

impl UpdateRule for Finch {
    const NAME: &'static str = "Emcm";

    #[inline]
    fn factor<T: Float>(w: &Weight<T>) -> T {
        w.eta_retain()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Emc;

    #[test]
    fn zero_variance_row_is_the_unit_row() {
        let w = Weight::new(0.25_f64).unwrap_or_else(|_| Weight::one());
        let mut s = Emcm::<f64, 3>::default();
        for k in 0..10 {
            let x = f64::from(k);
            // Stream 1 is constant zero: its variance stays zero.
            assert!(s.update(&w, [x, 0.0, -2.0 * x]), "finite update accepted");
        }
        let a = s.coefficients();
        assert_eq!(a[1], [0.0, 1.0, 0.0], "unit row for zero variance");
        for (i, row) in a.iter().enumerate() {
            assert_eq!(row[i], 1.0, "A_ii = 1");
        }
        assert!((a[0][2] + 2.0).abs() < 1e-12, "{} != -2", a[0][2]);
    }

    #[test]
    fn entries_are_pairwise_emc() {
        let w = Weight::new(0.1_f32).unwrap_or_else(|_| Weight::one());
        let mut s = Emcm::<f32, 3>::seeded([1.0, 2.0, 3.0]);
        let mut e01 = Emc::seeded(1.0, 2.0);
        let mut e12 = Emc::seeded(2.0, 3.0);
        for k in 0..50_u16 {
            let z = [
                f32::from(k).sin(),
                f32::from(k).cos() * 3.0,
                f32::from(k % 7),
            ];
            s.update(&w, z);
            e01.update(&w, z[0], z[1]);
            e12.update(&w, z[1], z[2]);
        }
        assert_eq!(s.covariance(0, 1), e01.covariance(), "Sigma_01 is Emc");
        assert_eq!(s.covariance(2, 1), e12.covariance(), "Sigma_21 is Emc");
    }
}
