//! Burley profile: integrals by quadrature, exact and approximate inverse, truncated
//! sampling. Every reference is computed here or in `common`, from the closed forms of
//! docs/algorithms.md §5, by quadrature or by a second implementation.

mod common;

use std::f64::consts::PI;

use common::{
    SplitMix, golubev, integrate, integrate_half_line, ks_statistic, profile, ref_ccdf, ref_cdf,
    ref_pdf,
};
use proptest::prelude::*;
use spvg::burley::{APPROX_C_PAPER, APPROX_C_UNREAL, BurleyProfile, ShapeFit, footprint_radius};
use spvg::sequence::{pixel_seed, r2_offset_from_seed, r2_point, to_unit_f64};

// ---------------------------------------------------------------- integrals

#[test]
fn profile_integrates_to_albedo() {
    for &a in &[0.0, 0.13, 0.33, 0.8, 1.0] {
        for &d in &[0.05, 1.0, 7.3] {
            let p = profile(a, d);
            let got = integrate_half_line(|r| 2.0 * PI * r * p.profile(r), d);
            let err = (got - a).abs();
            assert!(
                err <= 1e-13,
                "int 2 pi r R = {got} != A = {a} (d {d}, err {err:e})"
            );
        }
    }
}

#[test]
fn pdf_integrates_to_one_and_cdf_is_its_integral() {
    for &d in &[0.05, 1.0, 7.3] {
        let p = profile(0.5, d);
        let total = integrate_half_line(|r| p.pdf(r), d);
        assert!(
            (total - 1.0).abs() <= 1e-13,
            "int pdf = {total} != 1 (d {d})"
        );
        for &x in &[1e-9, 1e-3, 0.1, 0.5, 1.0, 2.0, 5.0, 20.0] {
            let r = x * d;
            let want = integrate(|s| p.pdf(s), 0.0, r, 16);
            let got = p.cdf(r);
            let err = (got - want).abs() / want;
            assert!(
                err <= 1e-13,
                "cdf({r}) = {got} != int pdf = {want} (rel {err:e})"
            );
            // The tail ratio against the tail integral, relative, far out too.
            let r_tail = (x * 10.0) * d;
            let want = integrate_half_line(|s| p.pdf(r_tail + s), d);
            let got = p.distant_ratio(r_tail);
            let err = (got - want).abs() / want;
            assert!(
                err <= 1e-12,
                "gamma({r_tail}) = {got} != {want} (rel {err:e})"
            );
        }
    }
}

#[test]
fn importance_weight_is_albedo() {
    // 2 pi r R(r) / pdf(r) = A for every r: the plain estimator's zero-variance identity.
    let mut rng = SplitMix(7);
    for _ in 0..1000 {
        let a = rng.next_f64();
        let d = 0.01 + 10.0 * rng.next_f64();
        let r = d * 60.0 * rng.next_f64().powi(3) + 1e-12;
        let p = profile(a, d);
        let w = 2.0 * PI * r * p.profile(r) / p.pdf(r);
        assert!(
            (w - a).abs() <= 8.0 * f64::EPSILON * a,
            "weight {w} != A {a} at r {r}"
        );
    }
}

#[test]
fn reference_forms_agree() {
    // Cross-check the test's own references: pdf = cdf' by central differences.
    let d = 1.7;
    for &r in &[0.1, 1.0, 4.0] {
        let h = 1e-5;
        let fd = (ref_cdf(r + h, d) - ref_cdf(r - h, d)) / (2.0 * h);
        let want = ref_pdf(r, d);
        assert!((fd - want).abs() <= 1e-9, "cdf' {fd} != pdf {want}");
        let sum = ref_cdf(r, d) + ref_ccdf(r, d);
        assert!((sum - 1.0).abs() <= 2e-16, "cdf + ccdf = {sum}");
    }
}

// ---------------------------------------------------------------- profile basics

#[test]
fn shape_fits_at_special_points() {
    // Hand-evaluated s(A): A = 0.8 zeroes the searchlight and transmission corrections,
    // A = 0.33 the mean-free-path one.
    // 1.85 - 0.33 + 7 * 0.47^3 = 1.52 + 7 * 0.103823 = 2.246761
    // 1.9 - 0.33 + 3.5 * 0.47^2 = 1.57 + 3.5 * 0.2209 = 2.34315
    // 3.5 + 100 * 0.47^4 = 3.5 + 100 * 0.04879681 = 8.379681
    let cases = [
        (ShapeFit::Searchlight, 0.8_f64, 1.05_f64),
        (ShapeFit::DiffuseTransmission, 0.8, 1.1),
        (ShapeFit::DiffuseMeanFreePath, 0.8, 8.379_681),
        (ShapeFit::Searchlight, 0.33, 2.246_761),
        (ShapeFit::DiffuseTransmission, 0.33, 2.343_15),
        (ShapeFit::DiffuseMeanFreePath, 0.33, 3.5),
    ];
    for (fit, a, s) in cases {
        let l = 2.5;
        let got = fit.shape(a, l);
        let want = l / s;
        assert!(
            (got - want).abs() <= 1e-14 * want,
            "{fit:?} at A {a}: d {got} != {want}"
        );
        let p = BurleyProfile::new(a, l, fit).expect("valid");
        assert!(
            (p.shape() - want).abs() <= 1e-14 * want,
            "profile d {} != {want}",
            p.shape()
        );
        assert_eq!(p.albedo(), a, "albedo getter");
    }
    assert_eq!(
        ShapeFit::default(),
        ShapeFit::DiffuseMeanFreePath,
        "docs/algorithms.md §5 default"
    );
}

#[test]
fn constructors_validate() {
    let fit = ShapeFit::default();
    for bad in [-0.01, 1.01, f64::NAN, f64::INFINITY] {
        assert!(
            BurleyProfile::new(bad, 1.0, fit).is_err(),
            "albedo {bad} accepted"
        );
        assert!(
            BurleyProfile::from_shape(bad, 1.0).is_err(),
            "albedo {bad} accepted"
        );
    }
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-320] {
        assert!(
            BurleyProfile::new(0.5, bad, fit).is_err(),
            "mfp {bad} accepted"
        );
        assert!(
            BurleyProfile::from_shape(0.5, bad).is_err(),
            "d {bad} accepted"
        );
    }
    assert!(BurleyProfile::new(0.0, 1.0, fit).is_ok(), "A = 0 is valid");
    assert!(BurleyProfile::new(1.0, 1.0, fit).is_ok(), "A = 1 is valid");
    assert!(
        BurleyProfile::<f32>::new(0.5, 1e-3, fit).is_ok(),
        "f32 profile"
    );
}

#[test]
fn evaluations_are_total() {
    let p = profile(0.6, 2.0);
    assert!(p.profile(f64::NAN).is_nan(), "profile NaN");
    assert_eq!(p.profile(-1.0), 0.0, "profile r < 0");
    assert_eq!(p.profile(0.0), f64::INFINITY, "profile r = 0");
    assert_eq!(p.profile(f64::INFINITY), 0.0, "profile r = inf");
    assert!(p.pdf(f64::NAN).is_nan(), "pdf NaN");
    assert_eq!(p.pdf(-1.0), 0.0, "pdf r < 0");
    assert_eq!(p.pdf(0.0), 0.25, "pdf(0) = 1 / (2 d)");
    assert_eq!(p.pdf(f64::INFINITY), 0.0, "pdf r = inf");
    assert!(p.cdf(f64::NAN).is_nan(), "cdf NaN");
    assert_eq!(p.cdf(-1.0), 0.0, "cdf r < 0");
    assert_eq!(p.cdf(f64::INFINITY), 1.0, "cdf r = inf");
    assert_eq!(p.distant_ratio(-1.0), 1.0, "gamma r0 < 0");
    assert_eq!(p.distant_ratio(f64::INFINITY), 0.0, "gamma r0 = inf");
    assert!(p.distant_ratio(f64::NAN).is_nan(), "gamma NaN");
    // A = 0: R vanishes everywhere (nothing divides by A), the pdf is untouched.
    let k = profile(0.0, 2.0);
    for r in [0.0, 1e-300, 1.0, f64::INFINITY] {
        assert_eq!(k.profile(r), 0.0, "R({r}) with A = 0");
    }
    assert_eq!(k.pdf(0.0), 0.25, "pdf with A = 0");
}

// ---------------------------------------------------------------- exact inverse

/// Log-spaced `xi` from `1e-300` to `1/2` and their complements up to `1 - 2^-53`.
fn hard_xis() -> Vec<f64> {
    let mut v = Vec::new();
    let mut e = -300.0;
    while e < -0.302 {
        v.push(10f64.powf(e));
        e += 0.037;
    }
    v.push(0.5);
    let tail: Vec<f64> = v
        .iter()
        .filter(|&&x| x >= f64::EPSILON / 2.0)
        .map(|x| 1.0 - x)
        .collect();
    v.extend(tail);
    v.extend((1..1000).map(|i| i as f64 / 1000.0));
    v.extend([
        1e-12,
        1.0 - 1e-12,
        f64::MIN_POSITIVE,
        1.0 - f64::EPSILON / 2.0,
    ]);
    v
}

/// Relative condition number of the cdf (or ccdf, value `c`) with respect to `r`.
fn condition(r: f64, d: f64, c: f64) -> f64 {
    r * ref_pdf(r, d) / c
}

#[test]
fn inverse_roundtrip() {
    for &d in &[0.01, 1.0, 13.0] {
        let p = profile(0.5, d);
        let (mut head, mut tail) = (0.0_f64, 0.0_f64);
        for xi in hard_xis() {
            let r = p.inverse_cdf(xi);
            assert!(r.is_finite() && r >= 0.0, "inverse({xi}) = {r}");
            // Absolute, as the brief states it: cdf(inverse(xi)) == xi to 1e-12.
            let c = ref_cdf(r, d);
            assert!((c - xi).abs() <= 1e-12, "cdf(inverse({xi})) = {c}");
            // Relative, on the small side of each half, in units of the error that merely
            // rounding r to f64 causes (the condition number r pdf(r) / min(cdf, ccdf)
            // times one ulp): in the far tail ln(ccdf) ~ -r / (3d) amplifies it.
            let err = if xi <= 0.5 {
                (c - xi).abs() / xi / (1.0 + condition(r, d, c))
            } else {
                let u = 1.0 - xi;
                (ref_ccdf(r, d) - u).abs() / u / (1.0 + condition(r, d, u))
            };
            if xi <= 0.5 {
                head = head.max(err / f64::EPSILON);
            } else {
                tail = tail.max(err / f64::EPSILON);
            }
        }
        println!(
            "d {d}: max relative error / (1 + condition) in ulps: head {head:.2}, tail {tail:.2}"
        );
        assert!(head <= 4.0, "head relative error {head} ulps");
        assert!(tail <= 4.0, "tail relative error {tail} ulps");
    }
}

#[test]
fn inverse_matches_golubev_and_is_monotone() {
    let p = profile(0.5, 1.3);
    let mut prev = 0.0;
    for i in 1..20_000 {
        let xi = i as f64 / 20_000.0;
        let r = p.inverse_cdf(xi);
        assert!(r >= prev, "not monotone at {xi}: {r} < {prev}");
        prev = r;
        // Golubev's literal form cancels near xi = 0; compare where it is well conditioned.
        if (0.01..=0.99).contains(&xi) {
            let g = golubev(xi, 1.3);
            assert!(
                (r - g).abs() <= 1e-13 * g,
                "inverse({xi}) = {r} != Golubev {g}"
            );
        }
    }
}

#[test]
fn inverse_is_monotone_across_the_branch_switch() {
    // Adjacent floats around xi = 1/2, where the head and tail formulas meet, and around
    // the truncated sampler's own switch (target = 1/2).
    let p = profile(0.5, 1.0);
    let below = |x: f64, k: u64| f64::from_bits(x.to_bits() - k);
    let mut xs: Vec<f64> = (0..2000).map(|k| below(0.5 + 1e-12, k)).collect();
    xs.reverse();
    let rs: Vec<f64> = xs.iter().map(|&x| p.inverse_cdf(x)).collect();
    assert!(
        rs.windows(2).all(|w| w[0] <= w[1]),
        "inverse_cdf not monotone near 1/2"
    );
    let r0 = 0.4;
    let xi_switch = (0.5 - ref_cdf(r0, 1.0)) / ref_ccdf(r0, 1.0);
    let mut xs: Vec<f64> = (0..2000).map(|k| below(xi_switch + 1e-12, k)).collect();
    xs.reverse();
    let rs: Vec<f64> = xs.iter().map(|&x| p.sample_distant(x, r0).radius).collect();
    assert!(
        rs.windows(2).all(|w| w[0] <= w[1]),
        "sample_distant not monotone at switch"
    );
    let rs: Vec<f64> = (0..5000)
        .map(|i| p.sample_distant(f64::from(i) / 5000.0, r0).radius)
        .collect();
    assert!(
        rs.windows(2).all(|w| w[0] <= w[1]),
        "sample_distant not monotone in xi"
    );
}

#[test]
fn inverse_f32_roundtrip() {
    let p = BurleyProfile::<f32>::from_shape(0.5, 1.0).expect("valid");
    let mut worst = 0.0_f64;
    for xi in hard_xis() {
        let x32 = xi as f32;
        // Subnormal f32 inputs carry less than 24 bits; skip them.
        if !(f32::MIN_POSITIVE..1.0).contains(&x32) {
            continue;
        }
        let r = f64::from(p.inverse_cdf(x32));
        let x = f64::from(x32);
        let err = if x <= 0.5 {
            let c = ref_cdf(r, 1.0);
            (c - x).abs() / x / (1.0 + condition(r, 1.0, c))
        } else {
            let u = 1.0 - x;
            (ref_ccdf(r, 1.0) - u).abs() / u / (1.0 + condition(r, 1.0, u))
        };
        worst = worst.max(err / f64::from(f32::EPSILON));
    }
    println!("f32 max relative error / (1 + condition): {worst:.2} ulps");
    assert!(worst <= 8.0, "f32 relative error {worst} ulps");
}

#[test]
fn inverse_special_values() {
    let p = profile(0.5, 1.0);
    assert!(p.inverse_cdf(f64::NAN).is_nan(), "NaN");
    assert_eq!(p.inverse_cdf(0.0), 0.0, "xi = 0");
    assert_eq!(p.inverse_cdf(-3.0), 0.0, "xi < 0");
    assert_eq!(p.inverse_cdf(1.0), f64::INFINITY, "xi = 1");
    assert_eq!(p.inverse_cdf(7.0), f64::INFINITY, "xi > 1");
    // Largest xi below 1: u = 2^-53, r = -3 ln(y) with y ~ 4u/3, i.e. 3 ln(3 * 2^51).
    let r = p.inverse_cdf(1.0 - f64::EPSILON / 2.0);
    let want = 3.0 * (3.0 * 2f64.powi(51)).ln();
    assert!((r - want).abs() <= 1e-12 * want, "r {r} != {want}");
    // Near 0: r ~ 2 d xi (pdf(0) = 1 / (2d)).
    let r = p.inverse_cdf(1e-300);
    assert!((r - 2e-300).abs() <= 1e-15 * 2e-300, "r {r} != 2e-300");
}

// ---------------------------------------------------------------- approximate inverse

/// Max and RMS of `cdf(g_c(xi)) - xi` over `n` midpoints of (0, 1), with `g_c` written
/// here from docs/algorithms.md §5.
fn approx_errors(c: f64, n: usize) -> (f64, f64) {
    let (mut max, mut sum) = (0.0_f64, 0.0);
    for i in 0..n {
        let xi = (i as f64 + 0.5) / n as f64;
        let g = ((2.0 - c) * xi - 2.0) * (-xi).ln_1p();
        let e = ref_cdf(g, 1.0) - xi;
        max = max.max(e.abs());
        sum += e * e;
    }
    (max, (sum / n as f64).sqrt())
}

#[test]
fn approx_inverse_error() {
    let p = profile(0.5, 1.0);
    let n = 1_000_000;
    for (c, name) in [(APPROX_C_PAPER, "paper"), (APPROX_C_UNREAL, "unreal")] {
        // The library's g agrees with the one written here.
        for i in 1..1000 {
            let xi = i as f64 / 1000.0;
            let want = ((2.0 - c) * xi - 2.0) * (-xi).ln_1p();
            let got = p.approx_inverse_cdf(xi, c);
            assert!(
                (got - want).abs() <= 4.0 * f64::EPSILON * want,
                "g({xi}) {got} != {want}"
            );
        }
        let (max, rms) = approx_errors(c, n);
        println!("c = {c} ({name}): max |cdf(g(xi)) - xi| = {max:.4e}, RMS = {rms:.4e}");
        assert!(max < 0.01, "{name} max error {max}");
    }
    let (max_p, rms_p) = approx_errors(APPROX_C_PAPER, n);
    let (max_u, rms_u) = approx_errors(APPROX_C_UNREAL, n);
    // The paper's c is the least-squares one, Unreal's trades RMS for a smaller maximum.
    assert!(rms_p < rms_u, "RMS paper {rms_p} >= unreal {rms_u}");
    assert!(max_u < max_p, "max unreal {max_u} >= paper {max_p}");
    // Near 0, g ~ 2 d xi exactly to first order.
    let g = p.approx_inverse_cdf(1e-10, APPROX_C_PAPER);
    assert!((g - 2e-10).abs() <= 1e-9 * 2e-10, "g(1e-10) = {g}");
    assert!(p.approx_inverse_cdf(f64::NAN, 2.6).is_nan(), "NaN xi");
    assert_eq!(p.approx_inverse_cdf(0.0, 2.6), 0.0, "xi = 0");
    assert_eq!(p.approx_inverse_cdf(1.0, 2.6), f64::INFINITY, "xi = 1");
}

#[test]
fn approx_constant_fit() {
    // Least squares of cdf(g_c(xi)) against xi on a uniform midpoint grid, minimized over
    // c by golden-section search.
    let n = 20_000;
    let objective = |c: f64| {
        let (_, rms) = approx_errors(c, n);
        rms
    };
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (2.0, 3.0);
    let (mut x1, mut x2) = (b - ratio * (b - a), a + ratio * (b - a));
    let (mut f1, mut f2) = (objective(x1), objective(x2));
    while b - a > 1e-6 {
        if f1 < f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - ratio * (b - a);
            f1 = objective(x1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + ratio * (b - a);
            f2 = objective(x2);
        }
    }
    let c = 0.5 * (a + b);
    println!("least-squares c = {c:.6}");
    assert!(
        (c - APPROX_C_PAPER).abs() < 5e-4,
        "fitted c {c} != {APPROX_C_PAPER}"
    );
}

// ---------------------------------------------------------------- sampling statistics

#[test]
fn ks_exact_inverse_samples() {
    let d = 2.0;
    let p = profile(0.5, d);
    let n = 10_000;
    let crit = 1.63 / (n as f64).sqrt();
    let mut rng = SplitMix(42);
    let iid: Vec<f64> = (0..n).map(|_| p.inverse_cdf(rng.next_f64())).collect();
    let ks = ks_statistic(iid, |r| ref_cdf(r, d));
    println!("KS i.i.d. {ks:.4e} (1% critical {crit:.4e})");
    assert!(ks < crit, "KS {ks} >= {crit}");
    let offset = r2_offset_from_seed(pixel_seed(3, 5, 0));
    let r2: Vec<f64> = (0..n as u32)
        .map(|m| p.inverse_cdf(to_unit_f64(r2_point(offset, m)[0])))
        .collect();
    let ks = ks_statistic(r2, |r| ref_cdf(r, d));
    println!("KS R2 {ks:.4e}");
    assert!(ks < crit / 10.0, "KS R2 {ks} >= {}", crit / 10.0);
}

#[test]
fn truncated_samples_follow_truncated_cdf() {
    let d = 1.5;
    let p = profile(0.7, d);
    let n = 10_000;
    let crit = 1.63 / (n as f64).sqrt();
    for &r0 in &[0.0_f64, 0.05, 1.0, 6.0] {
        let mut rng = SplitMix(r0.to_bits());
        let gamma = ref_ccdf(r0, d);
        let g = p.distant_ratio(r0);
        assert!(
            (g - gamma).abs() <= 4.0 * f64::EPSILON * gamma,
            "gamma {g} != {gamma}"
        );
        let samples: Vec<f64> = (0..n)
            .map(|_| {
                let s = p.sample_distant(rng.next_f64(), r0);
                assert!(s.radius >= r0, "radius {} < r0 {r0}", s.radius);
                let want = ref_pdf(s.radius, d) / gamma;
                assert!(
                    (s.pdf - want).abs() <= 1e-14 * want,
                    "pdf {} != {want}",
                    s.pdf
                );
                s.radius
            })
            .collect();
        let ks = ks_statistic(samples, |r| (ref_cdf(r, d) - ref_cdf(r0, d)) / gamma);
        println!("r0 {r0}: KS truncated {ks:.4e} (critical {crit:.4e})");
        assert!(ks < crit, "KS {ks} >= {crit} at r0 {r0}");
    }
}

#[test]
fn truncated_sampling_deep_in_the_tail() {
    // gamma ~ 3/4 e^{-100/3} ~ 2.6e-15: 1 - cdf(r0) formed by subtraction would be noise.
    let d = 1.0;
    let p = profile(0.5, d);
    let r0 = 100.0;
    let gamma = ref_ccdf(r0, d);
    for i in 0..1000 {
        let xi = (i as f64 + 0.5) / 1000.0;
        let s = p.sample_distant(xi, r0);
        assert!(
            s.radius >= r0 && s.radius.is_finite(),
            "radius {}",
            s.radius
        );
        // The truncated survival function at the sample is 1 - xi.
        let surv = ref_ccdf(s.radius, d) / gamma;
        assert!(
            (surv - (1.0 - xi)).abs() <= 1e-12,
            "survival {surv} != {}",
            1.0 - xi
        );
    }
    // No distant energy left: pdf 0 means no sample.
    let s = p.sample_distant(0.5, f64::INFINITY);
    assert_eq!(s.pdf, 0.0, "gamma = 0 gives pdf 0");
    let s = p.sample_distant(0.5, 1e6);
    assert_eq!(s.pdf, 0.0, "underflowed gamma gives pdf 0");
    let s = p.sample_distant(f64::NAN, 1.0);
    assert!(s.radius.is_nan() && s.pdf.is_nan(), "NaN xi");
    // r0 <= 0 is plain sampling.
    assert_eq!(
        p.sample_distant(0.3, -1.0).radius,
        p.inverse_cdf(0.3),
        "r0 < 0"
    );
}

#[test]
fn footprint_radius_hand_values() {
    assert_eq!(footprint_radius(2.0_f64, 0.3, 0.4), 0.5, "3-4-5 triangle");
    assert_eq!(
        footprint_radius(-10.0_f64, 5.0, 12.0),
        65.0,
        "5-12-13, sign ignored"
    );
    assert!(
        footprint_radius(1.0_f64, 1e300, 1e300).is_finite(),
        "no overflow in hypot"
    );
    assert!(footprint_radius(f64::NAN, 1.0, 1.0).is_nan(), "NaN");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn sampling_is_total(xi in proptest::num::f64::ANY, r0 in proptest::num::f64::ANY,
                         a in 0.0..=1.0_f64, d in 1e-3..1e3_f64) {
        let p = profile(a, d);
        let r = p.inverse_cdf(xi);
        prop_assert!(r.is_nan() == xi.is_nan() && (r.is_nan() || r >= 0.0), "r {}", r);
        let s = p.sample_distant(xi, r0);
        if !(xi.is_nan() || r0.is_nan()) {
            prop_assert!(s.radius >= r0.max(0.0), "radius {} < r0 {}", s.radius, r0);
            prop_assert!(s.pdf >= 0.0, "pdf {}", s.pdf);
        }
        let c = p.cdf(r0);
        prop_assert!(r0.is_nan() || (0.0..=1.0).contains(&c), "cdf {}", c);
        let _ = (p.profile(r0), p.pdf(r0), p.approx_inverse_cdf(xi, 2.6));
    }
}
