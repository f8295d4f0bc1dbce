//! References shared by the integration tests: the closed forms of docs/algorithms.md §5 written out
//! independently, Gauss-Legendre quadrature, an i.i.d. generator and the KS statistic
//! (the Burley tests), the docs/algorithms.md §7 circle scenario and deterministic random numbers (from
//! `spvg-fixtures`, shared with the examples, benches and report).
#![allow(dead_code, reason = "each test crate uses a different subset")]

#[allow(unused_imports, reason = "each test crate uses a different subset")]
pub(crate) use spvg_fixtures::{circle, splitmix};

use std::f64::consts::PI;

use spvg::burley::BurleyProfile;

/// SplitMix64, an independent source of i.i.d. uniforms for the statistical tests.
#[allow(
    unused_imports,
    reason = "the Burley tests use this name, the others do not"
)]
pub(crate) use splitmix::SplitMix64 as SplitMix;

/// Reference radial pdf, docs/algorithms.md §5, written out independently.
pub(crate) fn ref_pdf(r: f64, d: f64) -> f64 {
    ((-r / d).exp() + (-r / (3.0 * d)).exp()) / (4.0 * d)
}

/// Reference cdf, the docs/algorithms.md §5 closed form with `expm1` (accurate near 0).
pub(crate) fn ref_cdf(r: f64, d: f64) -> f64 {
    -((-r / d).exp_m1() + 3.0 * (-r / (3.0 * d)).exp_m1()) / 4.0
}

/// Reference complementary cdf `1 - cdf`, accurate in the tail.
pub(crate) fn ref_ccdf(r: f64, d: f64) -> f64 {
    ((-r / d).exp() + 3.0 * (-r / (3.0 * d)).exp()) / 4.0
}

/// Golubev's closed form, literally as docs/algorithms.md §5 writes it (`u = 1 - xi`).
pub(crate) fn golubev(xi: f64, d: f64) -> f64 {
    let u = 1.0 - xi;
    let g = 1.0 + 4.0 * u * (2.0 * u + (1.0 + 4.0 * u * u).sqrt());
    3.0 * d * ((1.0 + g.powf(-1.0 / 3.0) + g.powf(1.0 / 3.0)) / (4.0 * u)).ln()
}

/// Nodes and weights of `n`-point Gauss-Legendre quadrature on [-1, 1], by Newton's
/// iteration on the Legendre polynomial.
pub(crate) fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
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
pub(crate) fn integrate(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
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
pub(crate) fn integrate_half_line(f: impl Fn(f64) -> f64, scale: f64) -> f64 {
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

/// Kolmogorov-Smirnov statistic of `samples` against the continuous cdf `f`.
pub(crate) fn ks_statistic(mut samples: Vec<f64>, f: impl Fn(f64) -> f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples.iter().enumerate().fold(0.0_f64, |acc, (i, &x)| {
        let c = f(x);
        acc.max((c - i as f64 / n).abs())
            .max(((i + 1) as f64 / n - c).abs())
    })
}

pub(crate) fn profile(albedo: f64, d: f64) -> BurleyProfile<f64> {
    BurleyProfile::from_shape(albedo, d).expect("valid test parameters")
}
