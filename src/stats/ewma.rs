//! RiskMetrics EWMA covariance matrix of a vector stream.

use num_traits::Float;

use super::Weight;
use super::moving_covariance::sealed::Sealed;
use super::moving_covariance::{MovingCovariance, UpdateRule};

/// The RiskMetrics (1995) exponentially weighted moving average covariance matrix:
/// `S_t = (1 - eta) S_{t-1} + eta (Z_t - zeta_{t-1})(Z_t - zeta_{t-1})^T`,
/// then `zeta_t = (1 - eta) zeta_{t-1} + eta Z_t`.
///
/// It differs from [`Emcm`](super::Emcm) only by the factor of the rank-one term (`eta`
/// instead of `eta (1 - eta)`), so from equal starting states `S_t = Sigma_t / (1 - eta)`
/// for every `t` when `eta < 1` (docs/algorithms.md §1; equal up to rounding in floating point), and the
/// [coefficients](Ewma::coefficients) `diag(S)^-1 S` of the two estimators agree. With
/// `eta = 1`, `S` is the outer product of the last deviation while `Sigma` is zero.
///
/// Invariants: symmetric and stored once (packed lower triangle, see
/// [`Packed`](super::Packed)); diagonal never negative; positive semi-definite up to
/// rounding; non-finite input skips the whole update; overflow saturates (see the
/// [module docs](super)).
///
/// An alias of [`MovingCovariance`] with the [`RiskMetrics`] rule, where its methods
/// are documented. `Default` is the zero state; [`Ewma::seeded`] is the first-sample
/// seed. `N` ranges over `1..=16`.
///
/// # Examples
///
/// ```
/// use spvg::stats::{Emcm, Ewma, Weight};
/// let w = Weight::new(0.5_f64).unwrap();
/// let mut s = Ewma::<f64, 2>::seeded([0.0, 0.0]);
/// let mut sigma = Emcm::<f64, 2>::seeded([0.0, 0.0]);
/// assert!(s.update(&w, [2.0, -4.0]));
/// sigma.update(&w, [2.0, -4.0]);
/// assert_eq!(s.matrix(), [[2.0, -4.0], [-4.0, 8.0]]);
/// assert_eq!(s.covariance(0, 1), sigma.covariance(0, 1) / (1.0 - w.eta()));
/// assert_eq!(s.coefficients(), sigma.coefficients());
/// ```
pub type Ewma<T, const N: usize> = MovingCovariance<T, N, RiskMetrics>;

/// The update rule of [`Ewma`]: rank-one factor `eta`, as in RiskMetrics (1995).
///
/// # Examples
///
/// ```
/// use spvg::stats::{RiskMetrics, UpdateRule, Weight};
/// let w = Weight::new(0.25_f64).unwrap();
/// assert_eq!(RiskMetrics::factor(&w), 0.25);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RiskMetrics;

impl Sealed for RiskMetrics {}

impl UpdateRule for RiskMetrics {
    const NAME: &'static str = "Ewma";

    #[inline]
    fn factor<T: Float>(w: &Weight<T>) -> T {
        w.eta()
    }
}

#[cfg(all(test, feature = "nalgebra"))]
mod tests {
    use super::*;

    #[test]
    fn nalgebra_matches_arrays() {
        let w = Weight::new(0.3_f64).unwrap_or_else(|_| Weight::one());
        let mut s = Ewma::<f64, 3>::default();
        for z in [[1.0, 2.0, 0.5], [-1.0, 0.0, 4.0], [3.0, -2.0, 1.0]] {
            s.update(&w, z);
        }
        let (m, a) = (s.matrix(), s.coefficients());
        let (nm, na) = (s.to_nalgebra(), s.coefficients_nalgebra());
        for i in 0..3 {
            for j in 0..3 {
                assert_eq!(nm[(i, j)], m[i][j], "matrix ({i},{j})");
                assert_eq!(na[(i, j)], a[i][j], "coefficients ({i},{j})");
            }
        }
    }
}
