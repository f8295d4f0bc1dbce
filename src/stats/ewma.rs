//! RiskMetrics EWMA covariance matrix of a vector stream.

use num_traits::Float;

use super::Weight;
use super::packed::{Dim, Packed, SymState};

/// The RiskMetrics (1995) exponentially weighted moving average covariance matrix:
/// `S_t = (1 - eta) S_{t-1} + eta (Z_t - zeta_{t-1})(Z_t - zeta_{t-1})^T`,
/// then `zeta_t = (1 - eta) zeta_{t-1} + eta Z_t`.
///
/// It differs from [`Emcm`](super::Emcm) only by the factor of the rank-one term (`eta`
/// instead of `eta (1 - eta)`), so from equal starting states `S_t = Sigma_t / (1 - eta)`
/// for every `t` when `eta < 1` (SPEC 1; equal up to rounding in floating point), and the
/// [coefficients](Ewma::coefficients) `diag(S)^-1 S` of the two estimators agree. With
/// `eta = 1`, `S` is the outer product of the last deviation while `Sigma` is zero.
///
/// Invariants: symmetric and stored once (packed lower triangle, see [`Packed`]);
/// diagonal never negative; positive semi-definite up to rounding; non-finite input
/// skips the whole update; overflow saturates (see the [module docs](super)).
///
/// `Default` is the zero state; [`Ewma::seeded`] is the first-sample seed. `N` ranges over
/// `1..=16`.
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
pub struct Ewma<T: Copy, const N: usize>
where
    Dim<N>: Packed,
{
    state: SymState<T, N>,
}

impl<T: Float, const N: usize> Ewma<T, N>
where
    Dim<N>: Packed,
{
    /// The first-sample seed: mean `z` (non-finite components become zero), covariance
    /// zero.
    #[inline]
    #[must_use]
    pub fn seeded(z: [T; N]) -> Self {
        Self {
            state: SymState::seeded(z),
        }
    }

    /// Folds in one observation vector. Returns `false`, leaving the state unchanged, when
    /// any component of `z` is not finite.
    #[inline]
    pub fn update(&mut self, w: &Weight<T>, z: [T; N]) -> bool {
        self.state.update(w, w.eta(), z)
    }

    /// The current mean vector `zeta`.
    #[inline]
    #[must_use]
    pub fn mean(&self) -> [T; N] {
        self.state.mean
    }

    /// Entry `S_ij` (`== S_ji`). Out-of-range indices give zero instead of panicking.
    #[inline]
    #[must_use]
    pub fn covariance(&self, i: usize, j: usize) -> T {
        self.state.get(i, j)
    }

    /// The full symmetric matrix `S`.
    #[inline]
    #[must_use]
    pub fn matrix(&self) -> [[T; N]; N] {
        self.state.matrix()
    }

    /// The coefficient matrix `diag(S)^-1 S`: row `i` divided by `S_ii`, so the diagonal
    /// is 1. A row whose `S_ii` is zero is the unit row; a ratio beyond the type's range
    /// saturates.
    #[inline]
    #[must_use]
    pub fn coefficients(&self) -> [[T; N]; N] {
        self.state.coefficients()
    }
}

#[cfg(feature = "nalgebra")]
impl<T: Float + nalgebra::Scalar, const N: usize> Ewma<T, N>
where
    Dim<N>: Packed,
{
    /// [`Ewma::matrix`] as a `nalgebra` matrix.
    #[inline]
    #[must_use]
    pub fn to_nalgebra(&self) -> nalgebra::SMatrix<T, N, N> {
        nalgebra::SMatrix::from_fn(|i, j| self.state.get(i, j))
    }

    /// [`Ewma::coefficients`] as a `nalgebra` matrix.
    #[inline]
    #[must_use]
    pub fn coefficients_nalgebra(&self) -> nalgebra::SMatrix<T, N, N> {
        let a = self.state.coefficients();
        nalgebra::SMatrix::from_fn(|i, j| a[i][j])
    }
}

impl<T: Float, const N: usize> Default for Ewma<T, N>
where
    Dim<N>: Packed,
{
    /// The zero state: mean zero, covariance zero.
    #[inline]
    fn default() -> Self {
        Self::seeded([T::zero(); N])
    }
}

impl<T: Copy, const N: usize> Clone for Ewma<T, N>
where
    Dim<N>: Packed,
{
    #[inline]
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: Copy, const N: usize> Copy for Ewma<T, N> where Dim<N>: Packed {}

impl<T: Float, const N: usize> PartialEq for Ewma<T, N>
where
    Dim<N>: Packed,
{
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.state.eq(&other.state)
    }
}

impl<T: Float + core::fmt::Debug, const N: usize> core::fmt::Debug for Ewma<T, N>
where
    Dim<N>: Packed,
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Ewma")
            .field("mean", &self.state.mean)
            .field("packed_lower", &self.state.packed.as_ref())
            .finish()
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
