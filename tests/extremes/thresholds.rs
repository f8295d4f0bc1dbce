//! Measured degradations: the thresholds stated in the controller's "Supported numeric
//! range" documentation, each against a bound derived from IEEE rounding.

use spvg::{SpvgConfig, SpvgHistory};

/// Deviations beyond `sqrt(MAX)` square past the range: `d^2` saturates, so the stored
/// variance stops growing at `eta (1 - eta) MAX` (from a zero variance), and the count is
/// the maximum.
#[test]
fn variance_saturates_past_sqrt_max() {
    let c = SpvgConfig::<f32>::published();
    let root = f64::from(f32::MAX).sqrt();
    let w = c.weight();
    for d in [1e18_f32, 1.8e19, 1.85e19, 1e20, 1e30, f32::MAX] {
        let mut h = SpvgHistory {
            mean: 0.0,
            variance: 0.0,
            mean_count: 8.0,
        };
        assert!(c.update(&mut h, d, 8, true), "d {d} refused");
        let exact = f64::from(w.eta_retain()) * f64::from(d) * f64::from(d);
        if f64::from(d) < root {
            let err = (f64::from(h.variance) - exact).abs();
            assert!(
                err <= 1e-6 * exact,
                "{} != {exact} (tol {})",
                h.variance,
                1e-6 * exact
            );
        } else {
            assert_eq!(
                h.variance,
                w.eta_retain() * f32::MAX,
                "d {d}: saturated d^2"
            );
        }
        assert_eq!(c.estimate(&h, 1.0), 64, "d {d}: count");
    }
}

/// `1 - eta` rounds to 1 in `f32` for `eta <= 2^-25` (half an ulp below 1, ties to even):
/// such a weight cannot decay anything. Validation accepts it (it is a valid weight in
/// exact arithmetic); the documentation states the limit.
#[test]
fn f32_retain_is_one_below_2_pow_minus_25() {
    for (eta, frozen) in [
        (2f32.powi(-26), true),
        (2f32.powi(-25), true),
        (2f32.powi(-24), false),
    ] {
        let c = SpvgConfig::<f32>::builder()
            .eta(eta)
            .build()
            .expect("valid");
        let mut h = SpvgHistory {
            mean: 1.0,
            variance: 1.0,
            mean_count: 8.0,
        };
        assert!(c.update(&mut h, 1.0, 8, true), "refused");
        assert_eq!(
            h.variance == 1.0,
            frozen,
            "eta {eta}: variance {}",
            h.variance
        );
    }
}

/// At `eta = 1e-7` in `f32` a mean at 1 moves only for large steps. From IEEE rounding:
/// `1 - eta` rounds to `1 - 2^-23`, and `(1 - 2^-23) + eta x` leaves 1 upwards only
/// past `1 + 2^-24` (`x > (2^-23 + 2^-24) / eta`, about +79%) and downwards only below
/// `1 - 2^-25` (`x < (2^-23 - 2^-25) / eta`, about -11%).
#[test]
fn f32_tiny_weight_moves_a_mean_at_one_only_for_large_steps() {
    let eta = 1e-7_f32;
    let c = SpvgConfig::<f32>::builder()
        .eta(eta)
        .build()
        .expect("valid");
    let up = (2f64.powi(-23) + 2f64.powi(-24)) / f64::from(eta);
    let down = (2f64.powi(-23) - 2f64.powi(-25)) / f64::from(eta);
    for (x, moves) in [
        (up * 0.99, false),
        (up * 1.01, true),
        (down * 1.01, false),
        (down * 0.99, true),
    ] {
        let mut h = SpvgHistory {
            mean: 1.0_f32,
            variance: 0.0,
            mean_count: 8.0,
        };
        assert!(c.update(&mut h, x as f32, 8, true), "refused");
        assert_eq!(
            h.mean != 1.0,
            moves,
            "x {x} (up {up}, down {down}): mean {}",
            h.mean
        );
    }
}

/// Tiny deviations: `eta (1 - eta) d^2` falls below half the smallest `f32` subnormal
/// (`2^-150`) for `d < sqrt(2^-150 / (eta (1 - eta)))`, about 6.6e-23 at `eta = 0.2`, and
/// the variance reads 0 (up to the rounding of `d^2` among subnormals).
#[test]
fn f32_tiny_deviations_underflow() {
    let c = SpvgConfig::<f32>::published();
    let edge = (2f64.powi(-150) / f64::from(c.weight().eta_retain())).sqrt();
    for (d, zero) in [(edge * 0.7, true), (edge * 1.5, false)] {
        let mut h = SpvgHistory::default();
        assert!(c.update(&mut h, d as f32, 8, true), "refused");
        assert_eq!(
            h.variance == 0.0,
            zero,
            "d {d} (edge {edge}): var {}",
            h.variance
        );
        assert_eq!(c.estimate(&h, 1.0), 8, "count at a vanishing variance");
    }
}

/// A static pixel in `f32` from a cold history: the mean moves only while
/// `|eta (S - mean)|` exceeds about half an ulp of the mean, so it stalls short of `S`
/// by `ulp / (2 eta)` up to rounding (bounded here by `[ulp/(4 eta), 2 ulp/eta]`;
/// measured 0.87 to 2.2 times `ulp / (2 eta)`), and the variance settles at the square of
/// that stall (within 10%) instead of 0. Where that floor
/// exceeds `sigma0^2` the static pixel takes the maximum count for ever.
#[test]
fn f32_small_weights_stall_the_mean() {
    for (eta, s) in [(1e-4_f32, 1.0_f32), (1e-4, 1.9), (1e-4, 100.0), (1e-5, 1.9)] {
        let c = SpvgConfig::<f32>::builder()
            .eta(eta)
            .target_variance(1e-6)
            .budget(1, 1024)
            .build()
            .expect("valid");
        let mut h = SpvgHistory::default();
        for _ in 0..(20.0 / eta) as usize {
            c.update(&mut h, s, 16, true);
        }
        // The ulp just below `s`, where the stalled mean lies.
        let ulp = f64::from(s) - f64::from(s.next_down());
        let stall = f64::from(s) - f64::from(h.mean);
        let (lo, hi) = (ulp / (4.0 * f64::from(eta)), 2.0 * ulp / f64::from(eta));
        assert!(
            lo <= stall && stall <= hi,
            "eta {eta}, S {s}: stall {stall} not in [{lo}, {hi}]"
        );
        let var = f64::from(h.variance);
        assert!(
            (var - stall * stall).abs() <= 0.1 * stall * stall,
            "eta {eta}, S {s}: variance {var} vs stall^2 {}",
            stall * stall
        );
        // Predicted from the stall's lower bound alone: a floor this far above the
        // target gives r >= 4 with nbar = 16, i.e. the maximum count.
        if 0.9 * lo * lo > 4.0 * 1e-6 {
            assert_eq!(c.estimate(&h, 1.0), 1024, "eta {eta}, S {s}: var {var}");
        }
    }
}
