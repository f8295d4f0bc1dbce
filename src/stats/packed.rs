//! Packed storage of a symmetric `N x N` matrix: each entry stored once.
//!
//! A symmetric matrix has `N (N + 1) / 2` distinct entries. Stable Rust cannot size an
//! array `[T; N * (N + 1) / 2]` from a const parameter `N` (that needs the unstable
//! `generic_const_exprs`), so the length is supplied by a sealed trait implemented for
//! [`Dim<N>`] with `N` in `1..=16`: `<Dim<N> as Packed>::Storage<T>` is exactly
//! `[T; N (N + 1) / 2]`. Users never name the trait; they write `Emcm<f32, 3>`, and an
//! unsupported `N` is a compile-time error naming the bound.

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
            size_of::<<Dim<3> as Packed>::Storage<f32>>(),
            6 * 4,
            "no duplicated symmetric storage"
        );
    }
}
