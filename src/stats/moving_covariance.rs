//! The exponentially weighted covariance matrix of a vector stream, generic over the
//! factor of its rank-one term: one implementation behind [`Emcm`](super::Emcm) and
//! [`Ewma`](super::Ewma).

use core::marker::PhantomData;

use num_traits::Float;

use super::packed::{Dim, Packed, packed_index};
use super::{Weight, rules, saturate};

pub(super) mod sealed {
    /// Keeps [`UpdateRule`](super::UpdateRule) closed: the crate owns every rule.
    pub trait Sealed {}
}

/// The update rule of a [`MovingCovariance`]: the factor of its rank-one term.
///
/// Sealed: the two rules are [`Finch`](super::Finch) ([`Emcm`](super::Emcm), factor
/// `eta (1 - eta)`) and [`RiskMetrics`](super::RiskMetrics) ([`Ewma`](super::Ewma),
/// factor `eta`).
pub trait UpdateRule: sealed::Sealed {
    /// The name the state's `Debug` output shows (`"Emcm"`, `"Ewma"`).
    const NAME: &'static str;

    /// The factor of the rank-one term `d d^T` for the weight `w`.
    #[must_use]
    fn factor<T: Float>(w: &Weight<T>) -> T;
}

/// An exponentially weighted covariance matrix `M` of a vector stream `Z_t` in `R^N`,
/// with EMA mean `zeta`:
/// `M_t = (1 - eta) M_{t-1} + c (Z_t - zeta_{t-1})(Z_t - zeta_{t-1})^T`,
/// then `zeta_t = (1 - eta) zeta_{t-1} + eta Z_t`, where the factor `c` is set by the
/// rule `R`.
///
/// Use it through its aliases, whose docs state each estimator's rule and invariants:
/// [`Emcm`](super::Emcm) (`M = Sigma`, `c = eta (1 - eta)`) and [`Ewma`](super::Ewma)
/// (`M = S`, `c = eta`). The methods below serve both.
///
/// `M` is symmetric and stored once, as the packed lower triangle (`N (N + 1) / 2`
/// numbers, see [`Packed`]). `N` ranges over `1..=16`.
///
/// # Examples
///
/// ```
/// use spvg::stats::{Emcm, Finch, MovingCovariance, Weight};
/// let w = Weight::new(0.5_f64).unwrap();
/// let mut m: MovingCovariance<f64, 2, Finch> = Emcm::default();
/// assert!(m.update(&w, [2.0, 0.0]));
/// assert_eq!(m.mean(), [1.0, 0.0]);
/// assert_eq!(m.covariance(0, 0), 1.0); // eta (1 - eta) * 2^2
/// ```
pub struct MovingCovariance<T: Copy, const N: usize, R: UpdateRule>
where
    Dim<N>: Packed,
{
    mean: [T; N],
    packed: <Dim<N> as Packed>::Storage<T>,
    rule: PhantomData<R>,
}

impl<T: Float, const N: usize, R: UpdateRule> MovingCovariance<T, N, R>
where
    Dim<N>: Packed,
{
    /// The first-sample seed: mean `z` (non-finite components become zero), covariance
    /// zero.
    #[inline]
    #[must_use]
    pub fn seeded(z: [T; N]) -> Self {
        Self {
            mean: z.map(|v| if v.is_finite() { v } else { T::zero() }),
            packed: <Dim<N> as Packed>::filled(T::zero()),
            rule: PhantomData,
        }
    }

    /// A state from its parts: the mean `zeta` and the packed lower triangle of `M`
    /// (row by row: `(0,0), (1,0), (1,1), (2,0), ..`). Read defensively, as every update
    /// reads stored numbers: a non-finite entry becomes 0, and so does a negative
    /// diagonal entry (a variance).
    ///
    /// # Examples
    ///
    /// ```
    /// use spvg::stats::Emcm;
    /// let m = Emcm::<f32, 2>::from_parts([1.0, f32::NAN], [-4.0, 0.5, 2.0]);
    /// assert_eq!(m.mean(), [1.0, 0.0]);
    /// assert_eq!((m.covariance(0, 0), m.covariance(1, 0), m.covariance(1, 1)), (0.0, 0.5, 2.0));
    /// ```
    #[inline(always)]
    #[must_use]
    pub fn from_parts(mean: [T; N], packed: <Dim<N> as Packed>::Storage<T>) -> Self {
        let mut packed = packed;
        // Row i's diagonal entry is slot i (i + 3) / 2: 0, 2, 5, 9, ..
        let (mut row, mut diagonal) = (0, 0);
        for (k, v) in packed.as_mut().iter_mut().enumerate() {
            let finite = if v.is_finite() { *v } else { T::zero() };
            let on_diagonal = k == diagonal;
            if on_diagonal {
                row += 1;
                diagonal += row + 1;
            }
            *v = if on_diagonal && finite < T::zero() {
                T::zero()
            } else {
                finite
            };
        }
        Self {
            mean: mean.map(|v| if v.is_finite() { v } else { T::zero() }),
            packed,
            rule: PhantomData,
        }
    }

    /// Folds in one observation vector. Returns `false`, leaving the state unchanged, when
    /// any component of `z` is not finite.
    #[inline(always)]
    pub fn update(&mut self, w: &Weight<T>, z: [T; N]) -> bool {
        if !z.iter().all(|v| v.is_finite()) {
            return false;
        }
        let factor = R::factor(w);
        let mut d = [T::zero(); N];
        for ((di, &zi), &mi) in d.iter_mut().zip(&z).zip(&self.mean) {
            *di = rules::deviation(zi, mi);
        }
        // Walk the packed lower triangle row by row: slot k holds (i, j) with j <= i.
        let mut slots = self.packed.as_mut().iter_mut();
        for (i, &di) in d.iter().enumerate() {
            for &dj in &d[..=i] {
                if let Some(s) = slots.next() {
                    *s = rules::moment(w.retain(), factor, *s, di, dj);
                }
            }
        }
        for (m, &zi) in self.mean.iter_mut().zip(&z) {
            *m = rules::ema(w, *m, zi);
        }
        true
    }

    /// The current mean vector `zeta`.
    #[inline]
    #[must_use]
    pub fn mean(&self) -> [T; N] {
        self.mean
    }

    /// Entry `M_ij` (`== M_ji`): `Sigma_ij` of an [`Emcm`](super::Emcm), `S_ij` of an
    /// [`Ewma`](super::Ewma). Out-of-range indices give zero instead of panicking.
    #[inline]
    #[must_use]
    pub fn covariance(&self, i: usize, j: usize) -> T {
        packed_index::<N>(i, j)
            .and_then(|k| self.packed.as_ref().get(k).copied())
            .unwrap_or_else(T::zero)
    }

    /// The full symmetric matrix `M`: `Sigma` of an [`Emcm`](super::Emcm), `S` of an
    /// [`Ewma`](super::Ewma).
    #[inline]
    #[must_use]
    pub fn matrix(&self) -> [[T; N]; N] {
        core::array::from_fn(|i| core::array::from_fn(|j| self.covariance(i, j)))
    }

    /// The coefficient matrix `A = diag(M)^-1 M`: row `i` divided by `M_ii`, so
    /// `A_ii = 1` always. A row whose variance `M_ii` is zero (no information yet) is the
    /// unit row (1 on the diagonal, 0 elsewhere) instead of NaN; a ratio beyond the type's
    /// range saturates. Since `S = Sigma / (1 - eta)`, [`Emcm`](super::Emcm) and
    /// [`Ewma`](super::Ewma) give the same coefficients from equal starting states (up to
    /// rounding).
    #[inline]
    #[must_use]
    pub fn coefficients(&self) -> [[T; N]; N] {
        core::array::from_fn(|i| {
            let d = self.covariance(i, i);
            core::array::from_fn(|j| {
                if i == j {
                    T::one()
                } else if d > T::zero() {
                    // |M_ij| <= sqrt(M_ii M_jj) can still exceed M_ii by more than the
                    // type's range when M_ii is tiny: saturate instead of storing inf.
                    saturate(self.covariance(i, j) / d)
                } else {
                    T::zero()
                }
            })
        })
    }
}

#[cfg(feature = "nalgebra")]
impl<T: Float + nalgebra::Scalar, const N: usize, R: UpdateRule> MovingCovariance<T, N, R>
where
    Dim<N>: Packed,
{
    /// [`matrix`](Self::matrix) as a `nalgebra` matrix.
    #[inline]
    #[must_use]
    pub fn to_nalgebra(&self) -> nalgebra::SMatrix<T, N, N> {
        nalgebra::SMatrix::from_fn(|i, j| self.covariance(i, j))
    }

    /// [`coefficients`](Self::coefficients) as a `nalgebra` matrix.
    #[inline]
    #[must_use]
    pub fn coefficients_nalgebra(&self) -> nalgebra::SMatrix<T, N, N> {
        let a = self.coefficients();
        nalgebra::SMatrix::from_fn(|i, j| a[i][j])
    }
}

impl<T: Float, const N: usize, R: UpdateRule> Default for MovingCovariance<T, N, R>
where
    Dim<N>: Packed,
{
    /// The zero state: mean zero, covariance zero.
    #[inline]
    fn default() -> Self {
        Self::seeded([T::zero(); N])
    }
}

// Written by hand so that the only bound is `T: Copy`: a derive would also bound the
// marker `R`, which is never stored.
impl<T: Copy, const N: usize, R: UpdateRule> Clone for MovingCovariance<T, N, R>
where
    Dim<N>: Packed,
{
    #[inline]
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: Copy, const N: usize, R: UpdateRule> Copy for MovingCovariance<T, N, R> where Dim<N>: Packed {}

impl<T: Float, const N: usize, R: UpdateRule> PartialEq for MovingCovariance<T, N, R>
where
    Dim<N>: Packed,
{
    /// By value on the mean and the packed entries.
    #[inline]
    fn eq(&self, other: &Self) -> bool {
        self.mean == other.mean && self.packed.as_ref() == other.packed.as_ref()
    }
}

impl<T: Float + core::fmt::Debug, const N: usize, R: UpdateRule> core::fmt::Debug
    for MovingCovariance<T, N, R>
where
    Dim<N>: Packed,
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct(R::NAME)
            .field("mean", &self.mean)
            .field("packed_lower", &self.packed.as_ref())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::{Emcm, Ewma};

    /// Straightforward reference: full `N x N` matrix, explicit outer product.
    fn reference<const N: usize>(
        factor: f64,
        w: &Weight<f64>,
        zs: &[[f64; N]],
    ) -> ([f64; N], [[f64; N]; N]) {
        let (mut mean, mut m) = ([0.0; N], [[0.0; N]; N]);
        for z in zs {
            let d: [f64; N] = core::array::from_fn(|i| z[i] - mean[i]);
            for i in 0..N {
                for j in 0..N {
                    m[i][j] = w.retain() * m[i][j] + factor * d[i] * d[j];
                }
                mean[i] = w.retain() * mean[i] + w.eta() * z[i];
            }
        }
        (mean, m)
    }

    #[test]
    fn each_rule_matches_a_full_matrix_reference() {
        let w = Weight::new(0.3_f64).unwrap_or_else(|_| Weight::one());
        let zs = [
            [1.0, 2.0, 0.5],
            [-1.0, 0.0, 4.0],
            [3.0, -2.0, 1.0],
            [0.5, 0.5, 0.5],
        ];
        let (mut emcm, mut ewma) = (Emcm::<f64, 3>::default(), Ewma::<f64, 3>::default());
        for z in zs {
            assert!(emcm.update(&w, z), "finite update accepted");
            assert!(ewma.update(&w, z), "finite update accepted");
        }
        let cases = [
            (emcm.mean(), emcm.matrix(), w.eta() * w.retain(), "Emcm"),
            (ewma.mean(), ewma.matrix(), w.eta(), "Ewma"),
        ];
        for (mean, matrix, factor, name) in cases {
            let (want_mean, want) = reference(factor, &w, &zs);
            for i in 0..3 {
                let err = (mean[i] - want_mean[i]).abs();
                assert!(
                    err <= 1e-12,
                    "{name} mean {} != {} (tol 1e-12)",
                    mean[i],
                    want_mean[i]
                );
                for j in 0..3 {
                    let (got, want) = (matrix[i][j], want[i][j]);
                    let err = (got - want).abs();
                    assert!(err <= 1e-12, "{name} ({i},{j}) {got} != {want} (tol 1e-12)");
                }
            }
        }
    }

    #[test]
    fn debug_names_the_estimator() {
        let (m, s) = (Emcm::<f32, 1>::default(), Ewma::<f32, 1>::default());
        assert!(format!("{m:?}").starts_with("Emcm {"), "Emcm debug: {m:?}");
        assert!(format!("{s:?}").starts_with("Ewma {"), "Ewma debug: {s:?}");
    }
}
