//! Exponential moving covariance matrix (EMCM) of a vector stream.

use num_traits::Float;

use super::Weight;
use super::packed::{Dim, Packed, SymState};

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
///   (`N (N + 1) / 2` numbers, see [`Packed`]); it is positive semi-definite in exact
///   arithmetic, and up to rounding of order `eps * trace` in floating point;
/// - non-finite input (any component) skips the whole update; overflow saturates
///   (see the [module docs](super)).
///
/// `Default` is the zero state; [`Emcm::seeded`] is the first-sample seed. `N` ranges over
/// `1..=16`.
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
pub struct Emcm<T: Copy, const N: usize>
where
    Dim<N>: Packed,
{
    state: SymState<T, N>,
}

impl<T: Float, const N: usize> Emcm<T, N>
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
        self.state.update(w, w.eta_retain(), z)
    }

    /// The current mean vector `zeta`.
    #[inline]
    #[must_use]
    pub fn mean(&self) -> [T; N] {
        self.state.mean
    }

    /// Entry `Sigma_ij` (`== Sigma_ji`). Out-of-range indices give zero instead of
    /// panicking.
    #[inline]
    #[must_use]
    pub fn covariance(&self, i: usize, j: usize) -> T {
        self.state.get(i, j)
    }

    /// The full symmetric matrix `Sigma`.
    #[inline]
    #[must_use]
    pub fn matrix(&self) -> [[T; N]; N] {
        self.state.matrix()
    }

    /// The coefficient matrix `A = diag(Sigma)^-1 Sigma`: row `i` divided by `Sigma_ii`,
    /// so `A_ii = 1` always. A row whose variance `Sigma_ii` is zero (no information
    /// yet) is the unit row (1 on the diagonal, 0 elsewhere) instead of NaN; a ratio
    /// beyond the type's range saturates.
    #[inline]
    #[must_use]
    pub fn coefficients(&self) -> [[T; N]; N] {
        self.state.coefficients()
    }
}

#[cfg(feature = "nalgebra")]
impl<T: Float + nalgebra::Scalar, const N: usize> Emcm<T, N>
where
    Dim<N>: Packed,
{
    /// [`Emcm::matrix`] as a `nalgebra` matrix.
    #[inline]
    #[must_use]
    pub fn to_nalgebra(&self) -> nalgebra::SMatrix<T, N, N> {
        nalgebra::SMatrix::from_fn(|i, j| self.state.get(i, j))
    }

    /// [`Emcm::coefficients`] as a `nalgebra` matrix.
    #[inline]
    #[must_use]
    pub fn coefficients_nalgebra(&self) -> nalgebra::SMatrix<T, N, N> {
        let a = self.state.coefficients();
        nalgebra::SMatrix::from_fn(|i, j| a[i][j])
    }
}

impl<T: Float, const N: usize> Default for Emcm<T, N>
where
    Dim<N>: Packed,
{
    /// The zero state: mean zero, covariance zero.
    #[inline]
    fn default() -> Self {
        Self::seeded([T::zero(); N])
    }
}

impl<T: Copy, const N: usize> Clone for Emcm<T, N>
where
    Dim<N>: Packed,
{
    #[inline]
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: Copy, const N: usize> Copy for Emcm<T, N> where Dim<N>: Packed {}

impl<T: Float, const N: usize> PartialEq for Emcm<T, N>
where
    Dim<N>: Packed,
{
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.state.eq(&other.state)
    }
}

impl<T: Float + core::fmt::Debug, const N: usize> core::fmt::Debug for Emcm<T, N>
where
    Dim<N>: Packed,
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Emcm")
            .field("mean", &self.state.mean)
            .field("packed_lower", &self.state.packed.as_ref())
            .finish()
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
