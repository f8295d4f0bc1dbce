//! Burley profile: integrals by quadrature, exact and approximate inverse, truncated
//! sampling, Monte Carlo estimators, presets. Every reference is computed here, from the
//! closed forms of SPEC 5, by quadrature or by a second implementation.

use std::f64::consts::PI;

use proptest::prelude::*;
use spvg::burley::{
    APPROX_C_PAPER, APPROX_C_UNREAL, BurleyProfile, PlainEstimator, RatioEstimator, ShapeFit,
    filtered_mip_level, footprint_radius, presets,
};
use spvg::sequence::{pixel_seed, r2_offset_from_seed, r2_point, to_unit_f64};

// ---------------------------------------------------------------- references

/// Reference radial pdf, SPEC 5, written out independently.
fn ref_pdf(r: f64, d: f64) -> f64 {
    ((-r / d).exp() + (-r / (3.0 * d)).exp()) / (4.0 * d)
}

/// Reference cdf, the SPEC 5 closed form with `expm1` (accurate near 0).
fn ref_cdf(r: f64, d: f64) -> f64 {
    -((-r / d).exp_m1() + 3.0 * (-r / (3.0 * d)).exp_m1()) / 4.0
}

/// Reference complementary cdf `1 - cdf`, accurate in the tail.
fn ref_ccdf(r: f64, d: f64) -> f64 {
    ((-r / d).exp() + 3.0 * (-r / (3.0 * d)).exp()) / 4.0
}

/// Golubev's closed form, literally as SPEC 5 writes it (`u = 1 - xi`).
fn golubev(xi: f64, d: f64) -> f64 {
    let u = 1.0 - xi;
    let g = 1.0 + 4.0 * u * (2.0 * u + (1.0 + 4.0 * u * u).sqrt());
    3.0 * d * ((1.0 + g.powf(-1.0 / 3.0) + g.powf(1.0 / 3.0)) / (4.0 * u)).ln()
}

/// Nodes and weights of `n`-point Gauss-Legendre quadrature on [-1, 1], by Newton's
/// iteration on the Legendre polynomial.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Composite 20-point Gauss-Legendre over `panels` equal panels of `[a, b]`.
fn integrate(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let rule = gauss_legendre(20);
    let h = (b - a) / panels as f64;
    let mut total = 0.0;
    for p in 0..panels {
        let lo = a + h * p as f64;
        let mut s = 0.0;
        for &(x, w) in &rule {
            s += w * f(lo + 0.5 * h * (x + 1.0));
        }
        total += 0.5 * h * s;
    }
    total
}

/// `int_0^inf f(r) dr` via `r = scale * t / (1 - t)`, `t in (0, 1)`; the Gauss nodes
/// never touch the endpoints, so `f` is never evaluated at 0 or infinity.
fn integrate_half_line(f: impl Fn(f64) -> f64, scale: f64) -> f64 {
    integrate(
        |t| {
            let r = scale * t / (1.0 - t);
            f(r) * scale / ((1.0 - t) * (1.0 - t))
        },
        0.0,
        1.0,
        64,
    )
}

/// SplitMix64, an independent source of i.i.d. uniforms for the statistical tests.
struct SplitMix(u64);

impl SplitMix {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Kolmogorov-Smirnov statistic of `samples` against the continuous cdf `f`.
fn ks_statistic(mut samples: Vec<f64>, f: impl Fn(f64) -> f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples.iter().enumerate().fold(0.0_f64, |acc, (i, &x)| {
        let c = f(x);
        acc.max((c - i as f64 / n).abs())
            .max(((i + 1) as f64 / n - c).abs())
    })
}

fn profile(albedo: f64, d: f64) -> BurleyProfile<f64> {
    BurleyProfile::from_shape(albedo, d).expect("valid test parameters")
}

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
        "SPEC 5 default"
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
/// here from SPEC 5.
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

// ---------------------------------------------------------------- estimators

#[test]
fn plain_estimator_constant_lighting_is_exact() {
    let mut rng = SplitMix(9);
    for _ in 0..100 {
        let a = rng.next_f64();
        let l = 100.0 * rng.next_f64();
        let p = profile(a, 1.0);
        let mut est = PlainEstimator::new(&p);
        let n = 1 + (rng.next_f64() * 500.0) as u32;
        for _ in 0..n {
            assert!(est.add(l), "finite lighting accepted");
        }
        assert_eq!(est.count(), n, "count");
        assert_eq!(est.finish(), Some(a * l), "A * L exactly");
        assert!(!est.add(f64::NAN), "NaN rejected");
        assert_eq!(est.finish(), Some(a * l), "NaN left the state unchanged");
    }
    assert_eq!(
        PlainEstimator::new(&profile(0.5, 1.0)).finish(),
        None,
        "no samples"
    );
}

#[test]
fn ratio_estimator_constant_lighting_is_exact() {
    let mut rng = SplitMix(10);
    let a = 0.37;
    let p = profile(a, 1.3);
    let l = 0.8125;
    let mut est = RatioEstimator::new(&p);
    assert_eq!(est.finish(), None, "no samples");
    for _ in 0..500 {
        let r = p.inverse_cdf(rng.next_f64());
        let dz = 3.0 * rng.next_f64();
        assert!(est.add(r, dz, true, p.pdf(r), l), "sample accepted");
    }
    assert_eq!(est.mean_lighting(), Some(l), "weighted mean of a constant");
    assert_eq!(est.finish(), Some(a * l), "A * L");
    assert!(!est.add(1.0, 0.0, true, 0.0, 1.0), "pdf 0 rejected");
    assert!(
        !est.add(1.0, f64::INFINITY, true, 0.5, 1.0),
        "infinite dz rejected"
    );
    // A = 0 is no special case: the estimate is 0, not None.
    let k = profile(0.0, 1.0);
    let mut est = RatioEstimator::new(&k);
    assert!(est.add(0.5, 0.0, true, k.pdf(0.5), 3.0), "accepted");
    assert_eq!(est.finish(), Some(0.0), "A = 0 gives 0");
}

#[test]
fn ratio_weight_is_profile_over_pdf() {
    // weight * A = r' R(r') / pdf(r), with R from the reference closed form.
    let (a, d) = (0.6, 0.9);
    let p = profile(a, d);
    let est = RatioEstimator::new(&p);
    for &(r, dz) in &[(0.1_f64, 0.0_f64), (1.0, 0.5), (2.0, 3.0), (0.0, 1.0)] {
        let rp = (r * r + dz * dz).sqrt();
        let big_r = a * ((-rp / d).exp() + (-rp / (3.0 * d)).exp()) / (8.0 * PI * d * rp);
        let pdf = ref_pdf(r, d);
        let want = rp * big_r / pdf;
        let got = a * est.weight(r, dz, true, pdf);
        assert!(
            (got - want).abs() <= 1e-14 * want,
            "w({r}, {dz}) {got} != {want}"
        );
        assert_eq!(est.weight(r, dz, false, pdf), 0.0, "not subsurface");
    }
}

/// Reference for the step edge: pixel at distance `s` on the dark side of an edge,
/// lighting 1 beyond it. `A int_s^inf pdf(r) acos(s / r) / pi dr` by quadrature.
fn step_reference(a: f64, d: f64, s: f64) -> f64 {
    let f = |r: f64| ref_pdf(r, d) * (s / r).clamp(-1.0, 1.0).acos() / PI;
    a * (integrate(f, s, s + 60.0 * d, 400) + integrate_half_line(|t| f(s + 60.0 * d + t), d))
}

#[test]
fn step_edge_converges_to_quadrature() {
    let (a, d) = (0.8, 1.0);
    for &s in &[0.0, 0.3, 1.5] {
        let want = step_reference(a, d, s);
        let p = profile(a, d);
        let mut rms = Vec::new();
        for &n in &[16u32, 256, 4096] {
            // RMS over 32 pixels' R2 offsets, so the trend does not hinge on one offset.
            let mut sq = 0.0;
            for px in 0..32 {
                let offset = r2_offset_from_seed(pixel_seed(px, 7, 0));
                let mut est = PlainEstimator::new(&p);
                for m in 0..n {
                    let [u, v] = r2_point(offset, m);
                    let r = p.inverse_cdf(to_unit_f64(u));
                    let phi = 2.0 * PI * to_unit_f64(v);
                    let lit = if -s + r * phi.cos() > 0.0 { 1.0 } else { 0.0 };
                    assert!(est.add(lit), "finite");
                }
                let e = est.finish().expect("samples") - want;
                sq += e * e;
            }
            rms.push((sq / 32.0).sqrt());
        }
        println!("s {s}: reference {want:.6}, RMS error at 16/256/4096: {rms:?}");
        assert!(
            rms[0] > rms[1] && rms[1] > rms[2],
            "error not decreasing: {rms:?}"
        );
        assert!(rms[2] < 2e-3, "RMS at 4096 samples {} too large", rms[2]);
    }
}

#[test]
fn ratio_estimator_stops_bleeding_across_depth_edges() {
    // Pixel at x = -s on a dark surface (lighting 0); beyond x = 0 a lit surface (lighting
    // 1) that lies dz = 50 d deeper. The plain estimator bleeds the light across; the
    // ratio estimator gives it the weight of a point 50 d away.
    let (a, d, s, dz) = (0.8, 1.0, 0.3, 50.0);
    let p = profile(a, d);
    let offset = r2_offset_from_seed(pixel_seed(1, 2, 3));
    let mut plain = PlainEstimator::new(&p);
    let mut ratio = RatioEstimator::new(&p);
    let mut masked = RatioEstimator::new(&p);
    for m in 0..4096 {
        let [u, v] = r2_point(offset, m);
        let r = p.inverse_cdf(to_unit_f64(u));
        let phi = 2.0 * PI * to_unit_f64(v);
        let across = -s + r * phi.cos() > 0.0;
        let (lighting, depth) = if across { (1.0, dz) } else { (0.0, 0.0) };
        assert!(plain.add(lighting), "plain");
        assert!(ratio.add(r, depth, true, p.pdf(r), lighting), "ratio");
        // Variant: the far side is not a subsurface pixel at all.
        assert!(masked.add(r, 0.0, !across, p.pdf(r), lighting), "masked");
    }
    let plain = plain.finish().expect("samples");
    let ratio = ratio.finish().expect("samples");
    let want = step_reference(a, d, s);
    println!("plain {plain:.4e} (reference {want:.4e}), ratio {ratio:.4e}");
    assert!((plain - want).abs() < 0.01, "plain {plain} != {want}");
    assert!(plain > 0.1, "the plain estimate bleeds: {plain}");
    // Weight of a crossing sample relative to a local one is at most ~e^{-(50-r)/3}.
    assert!(ratio < 1e-5 * plain, "ratio estimate {ratio} still bleeds");
    assert_eq!(
        masked.finish(),
        Some(0.0),
        "non-subsurface pixels contribute nothing"
    );
}

#[test]
fn ratio_equals_plain_without_depth_differences() {
    let p = profile(0.55, 2.0);
    let offset = r2_offset_from_seed(pixel_seed(4, 4, 4));
    let mut plain = PlainEstimator::new(&p);
    let mut ratio = RatioEstimator::new(&p);
    for m in 0..1000 {
        let [u, v] = r2_point(offset, m);
        let r = p.inverse_cdf(to_unit_f64(u));
        let lighting = to_unit_f64(v) * 4.0;
        assert!(
            plain.add(lighting) && ratio.add(r, 0.0, true, p.pdf(r), lighting),
            "add"
        );
    }
    let (x, y) = (plain.finish().expect("n"), ratio.finish().expect("n"));
    assert!((x - y).abs() <= 1e-12 * x, "plain {x} != ratio {y}");
}

#[test]
fn mip_level_hand_values() {
    // q = pdf n / (16 lmax^2 t); level = max(-log2 q, 0) / 2.
    let cases = [
        ((1.0_f64, 1, 1.0, 1.0), 2.0_f64), // q = 2^-4
        ((0.25, 4, 2.0, 4.0), 4.0),        // q = 1 / (16 * 4 * 4) = 2^-8
        ((2.0, 8, 0.5, 0.25), 0.0),        // q = 16 / 1 > 1
        ((1.0, 16, 1.0, 1.0), 0.0),        // q = 1
        ((1.0, 1, 1.0, 1024.0), 7.0),      // q = 2^-14
    ];
    for ((pdf, n, lmax, t), want) in cases {
        let got = filtered_mip_level(pdf, n, lmax, t);
        assert!(
            (got - want).abs() <= 1e-15,
            "level({pdf}, {n}, {lmax}, {t}) {got} != {want}"
        );
    }
    assert_eq!(filtered_mip_level(f64::NAN, 1, 1.0, 1.0), 0.0, "NaN pdf");
    assert_eq!(filtered_mip_level(0.0, 1, 0.0, 1.0), 0.0, "0/0");
    assert_eq!(filtered_mip_level(1.0, 0, 1.0, 1.0), f64::INFINITY, "n = 0");
    assert_eq!(
        filtered_mip_level(0.0, 4, 1.0, 1.0),
        f64::INFINITY,
        "pdf = 0"
    );
    assert_eq!(filtered_mip_level(1.0, 4, 1.0, 0.0), 0.0, "t = 0");
    assert_eq!(filtered_mip_level(1.0_f32, 1, 1.0, 1.0), 2.0, "f32");
}

// ---------------------------------------------------------------- presets

#[test]
fn presets_match_spec_and_build() {
    // SPEC 5's table, typed in again here.
    let spec: [(&str, [f64; 3], [f64; 3]); 7] = [
        ("skin1", [3.75, 1.47, 0.79], [0.44, 0.22, 0.13]),
        ("skin2", [4.85, 1.11, 0.62], [0.63, 0.44, 0.34]),
        ("marble", [8.51, 5.57, 3.96], [0.83, 0.79, 0.75]),
        ("apple", [6.97, 6.40, 1.92], [0.85, 0.84, 0.53]),
        ("potato", [14.29, 7.27, 2.31], [0.77, 0.62, 0.21]),
        ("wholemilk", [10.90, 6.58, 2.54], [0.91, 0.88, 0.76]),
        ("ketchup", [5.33, 0.80, 0.56], [0.16, 0.01, 0.00]),
    ];
    for (m, (name, l, a)) in presets::ALL.iter().zip(spec) {
        assert_eq!(
            (m.name, m.mean_free_path_mm, m.albedo),
            (name, l, a),
            "preset {name}"
        );
        for fit in [
            ShapeFit::Searchlight,
            ShapeFit::DiffuseTransmission,
            ShapeFit::default(),
        ] {
            let ps = m.profiles::<f64>(fit).expect("valid preset");
            for (k, p) in ps.iter().enumerate() {
                let want = fit.shape(a[k], l[k]);
                assert_eq!(p.shape(), want, "{name} channel {k} shape");
                assert_eq!(p.albedo(), a[k], "{name} channel {k} albedo");
            }
            assert!(m.profiles::<f32>(fit).is_ok(), "{name} in f32");
        }
        let lmax = l.iter().copied().fold(0.0, f64::max);
        assert_eq!(m.max_mean_free_path_mm(), lmax, "{name} lmax");
    }
    let [_, _, blue] = presets::KETCHUP
        .profiles::<f64>(ShapeFit::default())
        .expect("valid");
    assert_eq!(blue.profile(0.3), 0.0, "ketchup blue R = 0");
    assert!(
        blue.inverse_cdf(0.5).is_finite(),
        "ketchup blue still samples"
    );
}
