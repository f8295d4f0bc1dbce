//! Packed storage of a symmetric `N x N` matrix: each entry stored once.
//!
//! A symmetric matrix has `N (N + 1) / 2` distinct entries. Stable Rust cannot size an
//! array `[T; N * (N + 1) / 2]` from a const parameter `N` (that needs the unstable
//! `generic_const_exprs`), so the length is supplied by a sealed trait implemented for
//! [`Dim<N>`] with `N` in `1..=16`: `<Dim<N> as Packed>::Storage<T>` is exactly
//! `[T; N (N + 1) / 2]`. Users never name the trait; they write `Emcm<f32, 3>`, and an
//! unsupported `N` is a compile-time error naming the bound.

use num_traits::Float;

use super::{Weight, saturate};

/// Type-level dimension `N` of a vector stream, used to look up the packed length of its
/// covariance matrix through [`Packed`].
///
/// # Examples
///
/// ```
/// use spvg::stats::{Dim, Packed};
/// assert_eq!(<Dim<3> as Packed>::LEN, 6);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dim<const N: usize>;

mod sealed {
    pub trait Sealed {}
}

/// Packed-storage length of a symmetric `N x N` matrix: implemented for [`Dim<N>`] with
/// `N` in `1..=16`. Sealed: the crate owns every implementation.
#[diagnostic::on_unimplemented(
    message = "symmetric matrices of dimension {Self} are not supported",
    note = "spvg implements packed covariance storage for N in 1..=16"
)]
pub trait Packed: sealed::Sealed {
    /// `N (N + 1) / 2`, the number of distinct entries.
    const LEN: usize;
    /// `[U; LEN]`.
    type Storage<U: Copy>: Copy + AsRef<[U]> + AsMut<[U]>;
    /// An array of `LEN` copies of `v`.
    fn filled<U: Copy>(v: U) -> Self::Storage<U>;
}

macro_rules! packed_dims {
    ($($n:literal),* $(,)?) => {$(
        impl sealed::Sealed for Dim<$n> {}
        impl Packed for Dim<$n> {
            const LEN: usize = $n * ($n + 1) / 2;
            type Storage<U: Copy> = [U; $n * ($n + 1) / 2];
            #[inline]
            fn filled<U: Copy>(v: U) -> Self::Storage<U> {
                [v; $n * ($n + 1) / 2]
            }
        }
    )*};
}

packed_dims!(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16);

/// Index of entry `(i, j)` in the packed lower triangle (row-major), or `None` when an
/// index is out of range. Symmetric: `(i, j)` and `(j, i)` share one slot.
#[inline]
#[must_use]
pub(crate) const fn packed_index<const N: usize>(i: usize, j: usize) -> Option<usize> {
    if i >= N || j >= N {
        return None;
    }
    let (r, c) = if i >= j { (i, j) } else { (j, i) };
    Some(r * (r + 1) / 2 + c)
}

/// Mean vector and packed symmetric second-moment matrix shared by
/// [`Emcm`](super::Emcm) and [`Ewma`](super::Ewma); they differ only in the factor of
/// the rank-one term.
pub(crate) struct SymState<T: Copy, const N: usize>
where
    Dim<N>: Packed,
{
    pub(crate) mean: [T; N],
    pub(crate) packed: <Dim<N> as Packed>::Storage<T>,
}

impl<T: Copy, const N: usize> Clone for SymState<T, N>
where
    Dim<N>: Packed,
{
    #[inline]
    fn clone(&self) -> Self {
        *self
    }
}

impl<T: Copy, const N: usize> Copy for SymState<T, N> where Dim<N>: Packed {}

impl<T: Float, const N: usize> SymState<T, N>
where
    Dim<N>: Packed,
{
    /// Mean `z` (non-finite components become zero), matrix zero.
    #[inline]
    pub(crate) fn seeded(z: [T; N]) -> Self {
        Self {
            mean: z.map(|v| if v.is_finite() { v } else { T::zero() }),
            packed: <Dim<N> as Packed>::filled(T::zero()),
        }
    }

    /// `M = (1 - eta) M + factor d d^T` with `d = z - mean_old`, then
    /// `mean = (1 - eta) mean + eta z`. Skips the whole update (returns `false`) when any
    /// component of `z` is not finite.
    #[inline]
    pub(crate) fn update(&mut self, w: &Weight<T>, factor: T, z: [T; N]) -> bool {
        if !z.iter().all(|v| v.is_finite()) {
            return false;
        }
        let mut d = [T::zero(); N];
        for ((di, &zi), &mi) in d.iter_mut().zip(&z).zip(&self.mean) {
            *di = saturate(zi - mi);
        }
        // Walk the packed lower triangle row by row: slot k holds (i, j) with j <= i.
        let mut slots = self.packed.as_mut().iter_mut();
        for (i, &di) in d.iter().enumerate() {
            for &dj in &d[..=i] {
                if let Some(s) = slots.next() {
                    *s = saturate(w.retain() * *s + factor * saturate(di * dj));
                }
            }
        }
        for (m, &zi) in self.mean.iter_mut().zip(&z) {
            *m = saturate(w.retain() * *m + w.eta() * zi);
        }
        true
    }

    /// Entry `(i, j)`; zero when an index is out of range.
    #[inline]
    pub(crate) fn get(&self, i: usize, j: usize) -> T {
        packed_index::<N>(i, j)
            .and_then(|k| self.packed.as_ref().get(k).copied())
            .unwrap_or_else(T::zero)
    }

    /// The full symmetric matrix.
    #[inline]
    pub(crate) fn matrix(&self) -> [[T; N]; N] {
        core::array::from_fn(|i| core::array::from_fn(|j| self.get(i, j)))
    }

    /// `diag(M)^-1 M`; a row whose diagonal entry is zero is the unit row.
    #[inline]
    pub(crate) fn coefficients(&self) -> [[T; N]; N] {
        core::array::from_fn(|i| {
            let d = self.get(i, i);
            core::array::from_fn(|j| {
                if i == j {
                    T::one()
                } else if d > T::zero() {
                    // |M_ij| <= sqrt(M_ii M_jj) can still exceed M_ii by more than the
                    // type's range when M_ii is tiny: saturate instead of storing inf.
                    saturate(self.get(i, j) / d)
                } else {
                    T::zero()
                }
            })
        })
    }

    /// `PartialEq` by value on mean and packed entries.
    #[inline]
    pub(crate) fn eq(&self, other: &Self) -> bool {
        self.mean == other.mean && self.packed.as_ref() == other.packed.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_index_is_a_bijection_onto_the_triangle() {
        const N: usize = 5;
        let mut seen = [false; 15];
        for i in 0..N {
            for j in 0..N {
                let k = packed_index::<N>(i, j);
                assert_eq!(k, packed_index::<N>(j, i), "({i},{j}) not symmetric");
                let k = k.unwrap_or(usize::MAX);
                assert!(k < 15, "({i},{j}) -> {k} out of packed range");
                if j <= i {
                    assert!(!seen[k], "slot {k} hit twice");
                    seen[k] = true;
                }
            }
        }
        assert!(seen.iter().all(|&s| s), "every slot used");
        assert_eq!(packed_index::<N>(5, 0), None, "row out of range");
        assert_eq!(packed_index::<N>(0, 9), None, "column out of range");
    }

    #[test]
    fn packed_len_matches_formula() {
        assert_eq!(<Dim<1> as Packed>::LEN, 1, "N=1");
        assert_eq!(<Dim<4> as Packed>::LEN, 10, "N=4");
        assert_eq!(<Dim<16> as Packed>::LEN, 136, "N=16");
        assert_eq!(
            core::mem::size_of::<<Dim<3> as Packed>::Storage<f32>>(),
            6 * 4,
            "no duplicated symmetric storage"
        );
    }
}
