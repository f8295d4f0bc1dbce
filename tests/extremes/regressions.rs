//! Regressions: one per defect the matrix found.

use spvg::cv::{As, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

use crate::reference::{cv_ok, history_ok};

/// Defect 1: with `kappa = 0` or `eta = 1`, a saturated variance made `variance *
/// inv_target` overflow and `0 * inf` turned the raw count into NaN, so the pixel with
/// the largest variance took `min_samples`. docs/algorithms.md §2.1's `n_hat` is `+inf`-large there
/// (`E = r nbar` alone exceeds any budget), so the count is `max_samples`.
#[test]
fn regression_saturated_variance_takes_the_maximum() {
    for (eta, kappa) in [(0.2_f32, 0.0_f32), (1.0, 0.0), (1.0, 0.5), (7.9e-6, 0.0)] {
        let c = SpvgConfig::<f32>::builder()
            .eta(eta)
            .target_variance(1e-4)
            .kappa(kappa)
            .budget(8, 64)
            .build()
            .expect("valid");
        let h = SpvgHistory {
            mean: 0.0,
            variance: f32::MAX,
            mean_count: 8.0,
        };
        let n = c.estimate(&h, 1.0);
        assert_eq!(
            n,
            64,
            "eta {eta}, kappa {kappa}: raw {}",
            c.raw_estimate(&h)
        );
    }
    // The same through the update: f32 deviations of 1e20 square past f32::MAX.
    let c = SpvgConfig::<f32>::builder()
        .kappa(0.0)
        .build()
        .expect("valid");
    let mut h = SpvgHistory::default();
    let mut n = c.estimate(&h, 1.0);
    for t in 0..8 {
        let s = if t % 2 == 0 { 1e20 } else { -1e20 };
        assert!(c.update(&mut h, s, n, true), "frame {t} refused");
        n = c.estimate(&h, 1.0);
    }
    assert_eq!(n, 64, "history {h:?}");
}

/// Defect 2: `PixelController::update` dropped frames whose inputs were all finite when
/// the residual `fbar - alpha G` (or `fbar` itself) overflowed: with `G < 0` OCV's
/// `alpha` has no upper bound, the SPVG history refused the infinite residual, the CV
/// state was therefore not updated either, and the pixel froze for as long as the
/// lighting stayed there. Finite input now saturates (the crate's overflow policy), as
/// an `f64` evaluation of the same residual, clamped to the `f32` range, predicts.
#[test]
fn regression_overflowing_residual_saturates_instead_of_freezing() {
    let config = SpvgConfig::<f32>::builder()
        .eta(1.0)
        .budget(1, 2)
        .build()
        .expect("valid");
    let ocv = Ocv::<f32>::new(1.0, 1e-6, 0.0).expect("valid");
    let pixel = PixelController::new(config, ocv);
    // The state the matrix reached (f32, eta = eta_cv = 1, budget [1, 2]).
    let mut j = CvHistory {
        cov_fg: 3.498_657_8e18,
        var_g: 1.923_165_3e-5,
        mean_f: 3.638_419_2e23,
        mean_g: 0.999_990_34,
    };
    let mut h = SpvgHistory {
        mean: 2.0,
        variance: 0.0,
        mean_count: 1.0,
    };
    let frame = PixelFrame {
        radiance: 1.0,
        preintegrated: -2.829_276_8e23,
        gamma: 1.0,
    };
    let alpha = pixel.model().coefficient(&j, 1.0, frame.preintegrated);
    let exact = 1.0 - f64::from(alpha) * f64::from(frame.preintegrated);
    let want = exact.clamp(-f64::from(f32::MAX), f64::from(f32::MAX)) as f32;
    let u = pixel.update(&mut h, &mut j, frame, 1, true);
    assert!(u.accepted, "finite frame refused: {u:?}");
    assert_eq!(
        u.monitored, want,
        "residual {} vs exact {exact}",
        u.monitored
    );
    assert!(history_ok(&h) && cv_ok(&j), "state {h:?} {j:?}");

    // `fbar` itself overflowing (|radiance| + |(1 - gamma) B| beyond f32::MAX).
    let pixel = PixelController::new(config, As);
    let frame = PixelFrame {
        radiance: 3e38_f32,
        preintegrated: -3e38,
        gamma: 0.5,
    };
    let exact = 3e38 + 0.5 * 3e38_f64;
    assert!(exact > f64::from(f32::MAX), "the case must overflow f32");
    let mut h = SpvgHistory::default();
    let u = pixel.update(&mut h, &mut (), frame, 1, true);
    assert!(u.accepted, "finite frame refused: {u:?}");
    assert_eq!(u.monitored, f32::MAX, "saturated fbar");
    // Non-finite input is still refused.
    let frame = PixelFrame {
        radiance: f32::INFINITY,
        ..frame
    };
    assert!(
        !pixel.update(&mut h, &mut (), frame, 1, true).accepted,
        "inf accepted"
    );
}

/// Defect 3: an OCV ratio `(cov + eps_a) / (var + eps_a)` that overflowed `T` fell back
/// to 1 (CCV) instead of keeping its sign, so the coefficient jumped from the bound it
/// pointed to (the upper bound of `D` for a huge positive covariance, 0 for a huge
/// negative one) to 1. The reference evaluates the ratio in `f64` (where it is finite)
/// and clamps it to `D`.
#[test]
fn regression_overflowing_ratio_keeps_its_sign() {
    let ocv = Ocv::<f32>::with_weight(0.1).expect("valid");
    let (fbar, g) = (1.0_f32, 1e-30_f32);
    let upper = f64::from(ocv.a0()) + f64::from(fbar) / f64::from(g);
    for cov in [1e33_f32, -1e33] {
        let j = CvHistory {
            cov_fg: cov,
            var_g: 1e-7,
            mean_f: 0.0,
            mean_g: 0.0,
        };
        let eps = f64::from(ocv.eps_a());
        let ratio = (f64::from(cov) + eps) / (1e-7_f64 + eps);
        assert!(
            ratio.abs() > f64::from(f32::MAX),
            "the case must overflow f32"
        );
        let want = ratio.clamp(0.0, upper);
        let got = f64::from(ocv.coefficient(&j, fbar, g));
        assert!(
            (got - want).abs() <= 1e-6 * want,
            "cov {cov}: {got} != {want} (tol {})",
            1e-6 * want
        );
    }
}
