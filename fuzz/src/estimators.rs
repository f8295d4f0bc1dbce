//! Invariants of the streaming estimators (`spvg::stats`).

use spvg::arbitrary::{
    bits_from_bytes, stream_f32_from_bytes, stream_f64_from_bytes, weight_f32_from_bits,
    weight_f64_from_bits,
};
use spvg::stats::{Ema, Emc, Emcm, Emv, Ewma, Weight};

/// Decodes `data` (8 bytes of weight bits, then the stream) and feeds every estimator in
/// `f32` and `f64`, asserting: no panic, nothing non-finite stored, variances and
/// covariance-matrix diagonals never negative, a rejected update leaves the state unchanged,
/// and an update is rejected exactly when its input is not finite.
pub fn check_estimators(data: &[u8]) {
    let (head, rest) = data.split_at(data.len().min(8));
    let bits = bits_from_bytes(head);
    check_f64(bits, &stream_f64_from_bytes(rest));
    check_f32(bits, &stream_f32_from_bytes(rest));
}

macro_rules! check_type {
    ($name:ident, $t:ty, $weight:ident) => {
        fn $name(bits: u64, xs: &[$t]) {
            let eta = $weight(bits);
            let w = match Weight::new(eta) {
                Ok(w) => w,
                Err(e) => panic!("generator gave an invalid weight {eta}: {e}"),
            };
            let fin = |v: $t| v.is_finite();
            let mut ema = Ema::<$t>::default();
            let mut emv = Emv::<$t>::seeded(xs.first().copied().unwrap_or(0.0));
            let mut emc = Emc::<$t>::default();
            let mut m2 = Emcm::<$t, 2>::default();
            let mut m3 = Emcm::<$t, 3>::seeded([1.0, -1.0, 0.5]);
            let mut s2 = Ewma::<$t, 2>::default();
            for (k, &x) in xs.iter().enumerate() {
                let y = xs.get(k + 1).copied().unwrap_or(x);
                let z = xs.get(k + 2).copied().unwrap_or(y);
                let ok1 = fin(x);
                let ok2 = ok1 && fin(y);
                let ok3 = ok2 && fin(z);

                let before = (ema, emv, emc, m2, m3, s2);
                assert_eq!(ema.update(&w, x), ok1, "Ema accepts exactly finite input");
                assert_eq!(emv.update(&w, x), ok1, "Emv accepts exactly finite input");
                assert_eq!(
                    emc.update(&w, x, y),
                    ok2,
                    "Emc accepts exactly finite input"
                );
                assert_eq!(
                    m2.update(&w, [x, y]),
                    ok2,
                    "Emcm<2> accepts exactly finite input"
                );
                assert_eq!(
                    m3.update(&w, [x, y, z]),
                    ok3,
                    "Emcm<3> accepts exactly finite input"
                );
                assert_eq!(
                    s2.update(&w, [x, y]),
                    ok2,
                    "Ewma<2> accepts exactly finite input"
                );
                if !ok1 {
                    assert_eq!(ema, before.0, "rejected Ema update changed state");
                    assert_eq!(emv, before.1, "rejected Emv update changed state");
                }
                if !ok2 {
                    assert_eq!(emc, before.2, "rejected Emc update changed state");
                    assert_eq!(m2, before.3, "rejected Emcm<2> update changed state");
                    assert_eq!(s2, before.5, "rejected Ewma<2> update changed state");
                }
                if !ok3 {
                    assert_eq!(m3, before.4, "rejected Emcm<3> update changed state");
                }

                assert!(fin(ema.mean()), "Ema stored {}", ema.mean());
                assert!(fin(emv.mean()) && fin(emv.variance()), "Emv stored {emv:?}");
                assert!(emv.variance() >= 0.0, "negative variance {emv:?}");
                assert!(
                    fin(emc.mean_x()) && fin(emc.mean_y()) && fin(emc.covariance()),
                    "Emc stored {emc:?}"
                );
                check_matrix(&m2.mean(), &m2.matrix(), &m2.coefficients(), "Emcm<2>");
                check_matrix(&m3.mean(), &m3.matrix(), &m3.coefficients(), "Emcm<3>");
                check_matrix(&s2.mean(), &s2.matrix(), &s2.coefficients(), "Ewma<2>");
            }
        }
    };
}

check_type!(check_f64, f64, weight_f64_from_bits);
check_type!(check_f32, f32, weight_f32_from_bits);

/// Finite mean, finite symmetric matrix with a non-negative diagonal, finite coefficients
/// with a unit diagonal.
fn check_matrix<T, const N: usize>(mean: &[T; N], m: &[[T; N]; N], a: &[[T; N]; N], what: &str)
where
    T: num_traits_float::Float + core::fmt::Debug,
{
    let zero = T::zero();
    assert!(mean.iter().all(|v| v.is_finite()), "{what}: mean {mean:?}");
    for i in 0..N {
        assert!(m[i][i] >= zero, "{what}: negative diagonal {m:?}");
        assert!(a[i][i] == T::one(), "{what}: coefficient diagonal {a:?}");
        for j in 0..N {
            assert!(m[i][j].is_finite(), "{what}: non-finite entry {m:?}");
            assert!(m[i][j] == m[j][i], "{what}: asymmetric {m:?}");
            assert!(a[i][j].is_finite(), "{what}: non-finite coefficient {a:?}");
        }
    }
}

/// The float operations `check_matrix` needs, for `f32` and `f64`, without a direct
/// dependency on `num-traits`.
mod num_traits_float {
    pub(crate) trait Float: Copy + PartialOrd {
        fn zero() -> Self;
        fn one() -> Self;
        fn is_finite(self) -> bool;
    }
    macro_rules! imp {
        ($t:ty) => {
            impl Float for $t {
                fn zero() -> Self {
                    0.0
                }
                fn one() -> Self {
                    1.0
                }
                fn is_finite(self) -> bool {
                    <$t>::is_finite(self)
                }
            }
        };
    }
    imp!(f32);
    imp!(f64);
}
