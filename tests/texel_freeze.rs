//! Why stochastic rounding: an EMA with a small weight stored in f16 between frames
//! freezes under round-to-nearest and tracks the exact EMA under stochastic rounding.
//!
//! Noise model. With stochastic rounding the stored state is `s_t = y_t + e_t`, where
//! `y_t = (1 - eta) s_{t-1} + eta x_t` is computed in f32 and `e_t` is the rounding error:
//! `E[e_t | past] = 0` and `Var[e_t | past] = p (1 - p) ulp^2 <= ulp^2 / 4` (`p` = the
//! fractional position of `y_t` between its two neighbours). The deviation from the exact
//! EMA, `d_t = s_t - mu_t`, obeys `d_t = (1 - eta) d_{t-1} + e_t`: a martingale-driven AR(1)
//! process with mean 0 and variance at most `ulp^2 / 4 / (1 - (1 - eta)^2)`, i.e. standard
//! deviation at most `sigma = ulp / (2 sqrt(2 eta - eta^2))`. (Rounding noise in the state,
//! unlike noise in the input, is not damped by `eta`: it is amplified by `1/sqrt(2 eta)`.)
//! The mean of `N` independent pixels then has standard deviation at most `sigma/sqrt(N)`.

use spvg::texel::{Rounding, to_f16};

const ETA: f64 = 1e-3;

/// One stored EMA step in f32: decode, update, store.
fn step(stored: half::f16, x: f32, rounding: Rounding) -> half::f16 {
    let eta = ETA as f32;
    let m = stored.to_f32();
    to_f16((1.0 - eta) * m + eta * x, rounding)
}

/// A xorshift-multiply stream, independent per pixel: the random words.
fn next(state: &mut u64) -> u32 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 32) as u32
}

#[test]
fn round_to_nearest_freezes_a_step() {
    let mut s = half::f16::from_f32(1.0);
    for _ in 0..5000 {
        s = step(s, 1.05, Rounding::Nearest);
        // eta (x - mu) = 5e-5 is under half an ulp of 1.0 (2^-11 ~ 4.9e-4).
        assert_eq!(
            s.to_f32(),
            1.0,
            "the stored mean moved under round-to-nearest"
        );
    }
}

#[test]
fn stochastic_rounding_tracks_the_f64_ema() {
    const PIXELS: usize = 64;
    const FRAMES: usize = 4000;
    let ulp = 2f64.powi(-10); // f16 spacing in [1, 2); below 1 it is finer
    let sigma = ulp / (2.0 * (2.0 * ETA - ETA * ETA).sqrt());
    // f32 arithmetic before the store: at most half an f32 ulp (2^-24 relative) per step,
    // accumulated through the EMA into at most 2^-24 * 1.05 / eta.
    let arithmetic = 2f64.powi(-24) * 1.05 / ETA;
    let mut states: Vec<(half::f16, u64)> = (0..PIXELS)
        .map(|p| {
            (
                half::f16::from_f32(1.0),
                0x9e37_79b9_7f4a_7c15 ^ ((p as u64 + 1) * 0x1234_5678_9abc),
            )
        })
        .collect();
    let mut exact = 1.0_f64;
    for t in 1..=FRAMES {
        exact = (1.0 - ETA) * exact + ETA * 1.05;
        for (s, rng) in &mut states {
            let r = next(rng);
            *s = step(*s, 1.05, Rounding::Stochastic(r));
        }
        if t % 500 == 0 {
            let vals: Vec<f64> = states.iter().map(|(s, _)| f64::from(s.to_f32())).collect();
            let mean = vals.iter().sum::<f64>() / PIXELS as f64;
            let tol = 5.0 * sigma / (PIXELS as f64).sqrt() + arithmetic;
            let err = (mean - exact).abs();
            println!(
                "frame {t}: mean of {PIXELS} pixels {mean:.6}, exact {exact:.6}, error {err:.2e} (tol {tol:.2e})"
            );
            assert!(
                err <= tol,
                "frame {t}: mean {mean} != exact {exact} (tol {tol})"
            );
            let sd = (vals.iter().map(|v| (v - exact).powi(2)).sum::<f64>() / PIXELS as f64).sqrt();
            // Spread across pixels: within the bound (with room for sampling error of a
            // 64-pixel estimate) and not zero: the state really moves.
            assert!(
                sd <= 1.5 * sigma && sd > 0.0,
                "frame {t}: spread {sd} vs bound {sigma}"
            );
        }
    }
    // The frozen round-to-nearest state would be off by the whole remaining step.
    let frozen_err = exact - 1.0;
    assert!(frozen_err > 0.049, "the reference moved by {frozen_err}");
}
