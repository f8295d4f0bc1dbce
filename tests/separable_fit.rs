//! The separable profile, its kernel and its Burley fit (docs/algorithms.md §5.1) against
//! references written here: the profiles restated from their formulas, closed-form
//! integrals, and brute-force grid searches of `S_delta`.

use std::f64::consts::PI;

use spvg::burley::{
    BurleyProfile, FIT_SAMPLES, FalloffMatch, SeparableProfile, ShapeFit, fit_burley, fit_falloff,
    presets,
};

const V: [f64; 5] = [0.0484, 0.187, 0.567, 1.99, 7.41];
const W: [f64; 5] = [0.100, 0.118, 0.113, 0.358, 0.078];

/// `r R_S(r; f)`, restated from the formula.
fn r_sep(r: f64, f: f64) -> f64 {
    let x = r / (0.001 + f);
    r * V
        .iter()
        .zip(W)
        .map(|(v, w)| w * (-x * x / (2.0 * v)).exp() / (2.0 * PI * v))
        .sum::<f64>()
}

/// `r R_B(r; A, d)`, restated from the formula.
fn r_burley(r: f64, a: f64, d: f64) -> f64 {
    a * ((-r / d).exp() + (-r / (3.0 * d)).exp()) / (8.0 * PI * d)
}

fn grid(r_max: f64) -> Vec<f64> {
    let h = r_max / FIT_SAMPLES as f64;
    (0..FIT_SAMPLES).map(|i| (i as f64 + 0.5) * h).collect()
}

/// The forward brute force: every `(A, ln d)` of a grid, then a finer grid around the
/// best, each point's `S_delta` summed directly (no projection).
fn brute_force_burley(f: f64) -> (f64, f64, f64) {
    let radii = grid(6.0 * 7.41_f64.sqrt() * (0.001 + f));
    let y: Vec<f64> = radii.iter().map(|&r| r_sep(r, f)).collect();
    let s_delta = |a: f64, d: f64| -> f64 {
        radii
            .iter()
            .zip(&y)
            .map(|(&r, &t)| (r_burley(r, a, d) - t).powi(2))
            .sum()
    };
    let (mut a_lo, mut a_hi) = (0.0, 1.0);
    let s = 0.001 + f;
    let (mut ld_lo, mut ld_hi) = ((s * 1e-2).ln(), (s * 1e1).ln());
    let mut best = (f64::INFINITY, 0.0, 0.0);
    for _ in 0..4 {
        let n = 40;
        for i in 0..=n {
            let a = a_lo + (a_hi - a_lo) * i as f64 / n as f64;
            for j in 0..=n {
                let d = (ld_lo + (ld_hi - ld_lo) * j as f64 / n as f64).exp();
                let c = s_delta(a, d);
                if c < best.0 {
                    best = (c, a, d);
                }
            }
        }
        // Zoom to two cells around the best point.
        let (da, dl) = ((a_hi - a_lo) / 20.0, (ld_hi - ld_lo) / 20.0);
        a_lo = (best.1 - da).max(0.0);
        a_hi = (best.1 + da).min(1.0);
        ld_lo = best.2.ln() - dl;
        ld_hi = best.2.ln() + dl;
    }
    best
}

#[test]
fn forward_fit_matches_a_brute_force_search() {
    for f in [0.15, 0.4, 0.7, 1.0] {
        let fit = fit_burley(f, ShapeFit::DiffuseMeanFreePath).unwrap();
        let (c, a, d) = brute_force_burley(f);
        // The fit is at least as good as the brute force, and lands at the same place.
        assert!(
            fit.residual <= c * (1.0 + 1e-9),
            "f {f}: fit S_delta {} > brute force {c}",
            fit.residual
        );
        assert!(
            (fit.albedo - a).abs() < 2e-3 && (fit.shape / d).ln().abs() < 2e-3,
            "f {f}: fit (A, d) = ({}, {}), brute force ({a}, {d})",
            fit.albedo,
            fit.shape
        );
        // Its mean free path is the shape fit's, l = d s(A).
        let p = BurleyProfile::new(
            fit.albedo,
            fit.mean_free_path,
            ShapeFit::DiffuseMeanFreePath,
        )
        .unwrap();
        assert!(
            (p.shape() / fit.shape - 1.0).abs() < 1e-12,
            "{} != {}",
            p.shape(),
            fit.shape
        );
    }
}

#[test]
fn forward_fit_scales_with_the_falloff() {
    // The grid scales with s = 0.001 + f and R_S(r; f) = R_S(r / s; 1 - 0.001): the best
    // d is proportional to s and the best A to s^2 (while it stays below 1), with the same
    // relative residual.
    let base = fit_burley(1.0, ShapeFit::default()).unwrap();
    for f in [0.05, 0.3, 0.6] {
        let fit = fit_burley(f, ShapeFit::default()).unwrap();
        let k = (0.001 + f) / 1.001;
        let (want_d, want_a) = (base.shape * k, base.albedo * k * k);
        assert!(
            (fit.shape / want_d - 1.0).abs() < 1e-6,
            "f {f}: d {} != {want_d}",
            fit.shape
        );
        assert!(
            (fit.albedo / want_a - 1.0).abs() < 1e-6,
            "f {f}: A {} != {want_a}",
            fit.albedo
        );
        assert!(
            (fit.relative_residual - base.relative_residual).abs() < 1e-6,
            "{} != {}",
            fit.relative_residual,
            base.relative_residual
        );
    }
}

/// The reverse brute force: 1500 falloffs evenly spaced in ln f over `[f_lo, 1]`, each
/// `S_delta` summed directly.
fn brute_force_falloff(a: f64, d: f64, shape_only: bool, f_lo: f64) -> (f64, f64) {
    let radii = grid((30.0 * d).max(6.0 * 7.41_f64.sqrt() * 1.001));
    let mut best = (f64::INFINITY, 0.0);
    let n = 1500;
    for i in 0..=n {
        let f = (f_lo.ln() * (1.0 - i as f64 / n as f64)).exp();
        let s = 0.001 + f;
        let gain = if shape_only {
            a / (s * s * W.iter().sum::<f64>())
        } else {
            1.0
        };
        let c: f64 = radii
            .iter()
            .map(|&r| (r_burley(r, a, d) - gain * r_sep(r, f)).powi(2))
            .sum();
        if c < best.0 {
            best = (c, f);
        }
    }
    best
}

#[test]
fn reverse_fit_matches_a_brute_force_search() {
    for preset in [presets::SKIN1, presets::KETCHUP] {
        for p in preset.profiles::<f64>(ShapeFit::default()).unwrap() {
            for (matching, shape_only) in
                [(FalloffMatch::Profile, false), (FalloffMatch::Shape, true)]
            {
                let fit = fit_falloff(&p, matching);
                let h = (30.0 * p.shape()).max(6.0 * 7.41_f64.sqrt() * 1.001) / FIT_SAMPLES as f64;
                let f_lo = (8.0 * h / 7.41_f64.sqrt() - 0.001).max(1e-3);
                let (c, f) = brute_force_falloff(p.albedo(), p.shape(), shape_only, f_lo);
                assert!(
                    fit.residual <= c * (1.0 + 1e-9) + 1e-300,
                    "{} {matching:?}: fit {} > brute force {c}",
                    preset.name,
                    fit.residual
                );
                assert!(
                    (fit.falloff / f).ln().abs() < 5e-3,
                    "{} {matching:?}: f {} != brute force {f}",
                    preset.name,
                    fit.falloff
                );
            }
        }
    }
}

#[test]
fn profile_and_kernel_closed_forms() {
    for f in [0.01_f64, 0.3, 1.0] {
        let p = SeparableProfile::new(f).unwrap();
        let s = 0.001 + f;
        // The 2D integral int 2 pi r R_S dr = s^2 sum w_k, by midpoint quadrature.
        let n = 20_000;
        let h = 30.0 * s / n as f64;
        let radial: f64 = (0..n)
            .map(|i| {
                let r = (i as f64 + 0.5) * h;
                2.0 * PI * r_sep(r, f) * h
            })
            .sum();
        assert!(
            (radial / p.total() - 1.0).abs() < 1e-6,
            "{radial} != {}",
            p.total()
        );
        // The kernel is the profile integrated across y, at a few x.
        for x in [0.0, 0.3 * s, 1.7 * s] {
            let line: f64 = (0..n)
                .map(|i| {
                    let y = -15.0 * s + (i as f64 + 0.5) * h;
                    let r = x.hypot(y);
                    if r == 0.0 { 0.0 } else { r_sep(r, f) / r * h }
                })
                .sum();
            let k = p.kernel_1d(x);
            assert!((line / k - 1.0).abs() < 1e-6, "f {f} x {x}: {line} != {k}");
        }
    }
}

#[test]
fn kernel_weights_sum_to_one_and_are_symmetric() {
    for f in [0.05_f64, 0.5, 1.0] {
        let p = SeparableProfile::new(f).unwrap();
        for n in [3, 7, 11, 21, 25, 33] {
            let (mut o, mut w) = (vec![0.0; n], vec![0.0; n]);
            p.fill_kernel(&mut o, &mut w).unwrap();
            let sum: f64 = w.iter().sum();
            assert!((sum - 1.0).abs() < 1e-12, "n {n}: sum {sum}");
            let range = if n > 20 { 3.0 } else { 2.0 };
            assert_eq!((o[0], o[n / 2], o[n - 1]), (-range, 0.0, range), "n {n}");
            for i in 0..n {
                assert_eq!(o[i], -o[n - 1 - i], "offsets symmetric");
                assert_eq!(w[i], w[n - 1 - i], "weights symmetric");
                assert!(w[i] >= 0.0, "weight {i} negative");
                // o_i = sign(x_i) x_i^2 / R with x_i uniform in [-R, R].
                let x = -range + 2.0 * range * i as f64 / (n - 1) as f64;
                assert!(
                    (o[i] - x.signum() * x * x / range).abs() < 1e-12,
                    "offset {i}"
                );
            }
        }
    }
}

#[test]
fn bad_parameters_are_rejected_by_name() {
    for f in [0.0, -0.1, 1.5, f64::NAN, f64::INFINITY] {
        let e = SeparableProfile::new(f).unwrap_err();
        assert!(e.to_string().contains("falloff"), "{e}");
        assert!(fit_burley(f, ShapeFit::default()).is_err(), "f {f}");
    }
    let p = SeparableProfile::new(0.5_f64).unwrap();
    let (mut o, mut w) = ([0.0; 4], [0.0; 4]);
    let e = p.fill_kernel(&mut o, &mut w).unwrap_err();
    assert!(e.to_string().contains("samples"), "{e}");
    let (mut o, mut w) = ([0.0; 5], [0.0; 3]);
    assert!(p.fill_kernel(&mut o, &mut w).is_err(), "length mismatch");
}

#[test]
fn s_delta_is_the_quantity_the_fits_minimise() {
    use spvg::burley::{forward_grid_extent, reverse_grid_extent, s_delta};
    for f in [0.2, 0.9] {
        let fit = fit_burley(f, ShapeFit::default()).unwrap();
        let b = BurleyProfile::from_shape(fit.albedo, fit.shape).unwrap();
        let s = s_delta(
            &b,
            &SeparableProfile::new(f).unwrap(),
            forward_grid_extent(f),
        )
        .unwrap();
        assert!(
            (s / fit.residual - 1.0).abs() < 1e-9,
            "{s} != {}",
            fit.residual
        );
    }
    let p = presets::MARBLE
        .profiles::<f64>(ShapeFit::default())
        .unwrap()[2];
    let back = fit_falloff(&p, FalloffMatch::Profile);
    let sep = SeparableProfile::new(back.falloff).unwrap();
    let s = s_delta(&p, &sep, reverse_grid_extent(p.shape())).unwrap();
    assert!(
        (s / back.residual - 1.0).abs() < 1e-9,
        "{s} != {}",
        back.residual
    );
    let e = s_delta(&p, &sep, f64::NAN).unwrap_err();
    assert!(e.to_string().contains("r_max"), "{e}");
}
