//! Robustness on hard inputs: PSD up to rounding, no NaN anywhere in the float range,
//! the non-finite policy, saturation.

use proptest::prelude::*;
use spvg::arbitrary::{
    finite_f32, finite_f64, hard_stream_f32, hard_stream_f64, stream_f32, stream_f64, weight_f32,
    weight_f64,
};
use spvg::stats::{Ema, Emc, Emcm, Emv, Ewma, Weight};

fn weight<T: num_traits::Float>(eta: T) -> Result<Weight<T>, TestCaseError> {
    Weight::new(eta).map_err(|e| TestCaseError::fail(format!("{e}")))
}

/// True when `m + delta I` has a Cholesky factorisation with non-negative pivots, i.e.
/// the smallest eigenvalue of `m` is at least `-delta`. Runs in f64.
fn psd_within<const N: usize>(m: &[[f64; N]; N], delta: f64) -> Result<(), String> {
    let mut l = [[0.0_f64; N]; N];
    for i in 0..N {
        for j in 0..=i {
            let s: f64 = (0..j).map(|k| l[i][k] * l[j][k]).sum();
            if i == j {
                let p = m[i][i] + delta - s;
                if p < 0.0 {
                    return Err(format!("pivot {i} = {p} < 0 (delta {delta}) for {m:?}"));
                }
                l[i][i] = p.sqrt();
            } else {
                l[i][j] = if l[j][j] > 0.0 {
                    (m[i][j] - s) / l[j][j]
                } else {
                    0.0
                };
            }
        }
    }
    Ok(())
}

macro_rules! psd_test {
    ($name:ident, $t:ty, $n:literal, $stream:ident, $weight:ident, $limit:expr) => {
        proptest! {
            #![proptest_config(ProptestConfig::with_cases(256))]

            /// Emcm and Ewma stay PSD up to rounding (smallest eigenvalue >= -tol trace) on
            /// hard-case streams, limited to magnitudes whose squares do not saturate
            /// (saturation clamps entries independently and can break Cauchy-Schwarz).
            #[test]
            fn $name(xs in $stream(1..80), eta in $weight()) {
                let w = weight(eta)?;
                let lim: $t = $limit;
                let mut m = Emcm::<$t, $n>::default();
                let mut s = Ewma::<$t, $n>::default();
                for k in 0..xs.len() {
                    let z: [$t; $n] = core::array::from_fn(|o| xs[(k * 7 + o) % xs.len()].clamp(-lim, lim));
                    m.update(&w, z);
                    s.update(&w, z);
                    for mat in [m.matrix(), s.matrix()] {
                        let f = mat.map(|r| r.map(f64::from));
                        let trace: f64 = (0..$n).map(|i| f[i][i]).sum();
                        for i in 0..$n {
                            prop_assert!(f[i][i] >= 0.0, "negative variance {f:?}");
                        }
                        let delta = 64.0 * f64::from(<$t>::EPSILON) * trace
                            + 16.0 * f64::from(<$t>::MIN_POSITIVE);
                        if let Err(e) = psd_within(&f, delta) {
                            return Err(TestCaseError::fail(e));
                        }
                    }
                }
            }
        }
    };
}

psd_test!(psd_2_f64, f64, 2, stream_f64, weight_f64, 1e150);
psd_test!(psd_3_f64, f64, 3, stream_f64, weight_f64, 1e150);
psd_test!(psd_2_f32, f32, 2, stream_f32, weight_f32, 1e18);
psd_test!(psd_3_f32, f32, 3, stream_f32, weight_f32, 1e18);

macro_rules! policy_test {
    ($name:ident, $t:ty, $stream:ident, $weight:ident, $finite:ident) => {
        proptest! {
            #![proptest_config(ProptestConfig::with_cases(256))]

            /// Over the whole range (finite and non-finite input, weights biased to 1e-7 and
            /// exactly 1): an update is rejected exactly when its input is non-finite, a
            /// rejected update leaves the state bit-for-bit unchanged, and nothing stored
            /// or derived is ever NaN or infinite; variances are never negative.
            #[test]
            fn $name(xs in $stream(0..64), eta in $weight(), seed in $finite()) {
                let w = weight(eta)?;
                let mut ema = Ema::seeded(seed);
                let mut emv = Emv::seeded(seed);
                let mut emc = Emc::seeded(seed, -seed);
                let mut m = Emcm::<$t, 3>::seeded([seed; 3]);
                let mut s = Ewma::<$t, 2>::default();
                for k in 0..xs.len() {
                    let (x, y, z) = (xs[k], xs[(k + 1) % xs.len()], xs[(k + 2) % xs.len()]);
                    let before = format!("{ema:?}{emv:?}{emc:?}{m:?}{s:?}");
                    let ok1 = x.is_finite();
                    let ok3 = ok1 && y.is_finite() && z.is_finite();
                    let ok2 = ok1 && y.is_finite();
                    prop_assert_eq!(ema.update(&w, x), ok1, "Ema({})", x);
                    prop_assert_eq!(emv.update(&w, x), ok1, "Emv({})", x);
                    prop_assert_eq!(emc.update(&w, x, y), ok2, "Emc({}, {})", x, y);
                    prop_assert_eq!(m.update(&w, [x, y, z]), ok3, "Emcm({}, {}, {})", x, y, z);
                    prop_assert_eq!(s.update(&w, [x, y]), ok2, "Ewma({}, {})", x, y);
                    if !ok1 {
                        // Every estimator saw a non-finite component: nothing may change
                        // (Debug prints every stored bit pattern that matters, -0 included).
                        prop_assert_eq!(before, format!("{ema:?}{emv:?}{emc:?}{m:?}{s:?}"));
                    }
                    prop_assert!(ema.mean().is_finite(), "{ema:?}");
                    prop_assert!(emv.mean().is_finite() && emv.variance().is_finite(), "{emv:?}");
                    prop_assert!(emv.variance() >= 0.0, "{emv:?}");
                    prop_assert!(emc.covariance().is_finite() && emc.mean_x().is_finite()
                        && emc.mean_y().is_finite(), "{emc:?}");
                    let all_finite = |a: &[[$t; 3]; 3]| a.iter().flatten().all(|v| v.is_finite());
                    prop_assert!(all_finite(&m.matrix()) && all_finite(&m.coefficients()), "{m:?}");
                    prop_assert!(m.mean().iter().all(|v| v.is_finite()), "{m:?}");
                    prop_assert!((0..3).all(|i| m.covariance(i, i) >= 0.0), "{m:?}");
                    prop_assert!(s.matrix().iter().flatten().all(|v| v.is_finite())
                        && s.coefficients().iter().flatten().all(|v| v.is_finite()), "{s:?}");
                    prop_assert!((0..2).all(|i| s.covariance(i, i) >= 0.0), "{s:?}");
                }
            }
        }
    };
}

policy_test!(policy_f64, f64, hard_stream_f64, weight_f64, finite_f64);
policy_test!(policy_f32, f32, hard_stream_f32, weight_f32, finite_f32);

/// Overflow saturates to the saturated formula: from `-MAX`, a sample `+MAX` gives a
/// deviation `2 MAX` -> `MAX` and a square `MAX` (both clamped), so with eta = 1/2 the
/// variance is `eta (1 - eta) MAX = MAX / 4`, the covariance of `(MAX, -MAX)` is
/// `-MAX / 4`, the EWMA entry `eta MAX = MAX / 2`, and the mean `0`.
macro_rules! saturation_test {
    ($name:ident, $t:ty) => {
        #[test]
        fn $name() {
            let w = Weight::<$t>::new(0.5).unwrap_or_else(|_| Weight::one());
            let max = <$t>::MAX;
            let mut emv = Emv::seeded(-max);
            assert!(emv.update(&w, max), "finite input accepted");
            assert_eq!(emv.variance(), max / 4.0, "{emv:?}");
            assert_eq!(emv.mean(), 0.0, "{emv:?}");
            let mut emc = Emc::seeded(-max, max);
            emc.update(&w, max, -max);
            assert_eq!(emc.covariance(), -max / 4.0, "{emc:?}");
            let mut m = Emcm::<$t, 2>::seeded([-max, max]);
            m.update(&w, [max, -max]);
            let q = max / 4.0;
            assert_eq!(m.matrix(), [[q, -q], [-q, q]], "{m:?}");
            assert_eq!(m.coefficients(), [[1.0, -1.0], [-1.0, 1.0]], "{m:?}");
            let mut s = Ewma::<$t, 2>::seeded([-max, max]);
            s.update(&w, [max, -max]);
            assert_eq!(s.covariance(0, 0), max / 2.0, "{s:?}");
            let mut ema = Ema::seeded(max);
            ema.update(&w, max);
            assert_eq!(ema.mean(), max, "{ema:?}");
        }
    };
}

saturation_test!(saturation_f64, f64);
saturation_test!(saturation_f32, f32);

/// A tiny diagonal with a large off-diagonal would give an infinite coefficient; it
/// saturates instead.
#[test]
fn coefficient_overflow_saturates() {
    let w = Weight::new(0.5_f64).unwrap_or_else(|_| Weight::one());
    let mut m = Emcm::<f64, 2>::default();
    m.update(&w, [1e-150, 1e300]);
    let a = m.coefficients();
    assert!(a[0][1] == f64::MAX, "{a:?} (Sigma {:?})", m.matrix());
    assert!(a[1][0].is_finite() && a[1][0] > 0.0, "{a:?}");
}
