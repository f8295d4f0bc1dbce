//! Burley Monte Carlo estimators (plain and depth-aware ratio), the AFIS mip level and
//! the material presets, against quadrature references and hand-evaluated values.

mod common;

use std::f64::consts::PI;

use common::{SplitMix, integrate, integrate_half_line, profile, ref_pdf};
use spvg::burley::{PlainEstimator, RatioEstimator, ShapeFit, filtered_mip_level, presets};
use spvg::sequence::{pixel_seed, r2_offset_from_seed, r2_point, to_unit_f64};

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
    // docs/algorithms.md §5's table, typed in again here.
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
