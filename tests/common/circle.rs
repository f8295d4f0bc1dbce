//! The docs/algorithms.md §7 *circle* scenario, shared by `tests/controller.rs` and
//! `examples/circle.rs`: one pixel whose integrand is `4/pi` inside the disk of radius 0.5
//! centred in the unit square and 0 outside (mean 1, per-sample variance
//! `4/pi - 1 ~ 0.2732`), sampled uniformly, under the SPVG controller with `eta = 0.2`,
//! `sigma0^2 = 0.08^2` and budget `[8, 64]`.
//!
//! A test reaches this as `common::circle`; an example includes it (and `splitmix.rs`,
//! which it uses through `super::splitmix`) with `#[path = "../tests/common/circle.rs"]`.
#![allow(
    dead_code,
    reason = "each test crate and example uses a different subset"
)]

use std::f64::consts::PI;

use spvg::{SpvgConfig, SpvgHistory};

use super::splitmix::SplitMix64;

/// The target variance `sigma0^2 = 0.08^2`.
pub(crate) const TARGET: f64 = 0.08 * 0.08;

/// Per-sample variance of the circle integrand: `E f^2 - 1 = (16/pi^2)(pi/4) - 1`.
pub(crate) fn per_sample_variance() -> f64 {
    4.0 / PI - 1.0
}

/// The scenario's controller: `eta = 0.2`, [`TARGET`], the given `kappa`, budget
/// `[8, 64]`, the other parameters published.
pub(crate) fn config(kappa: f64) -> Result<SpvgConfig<f64>, spvg::Error> {
    SpvgConfig::builder()
        .eta(0.2)
        .target_variance(TARGET)
        .kappa(kappa)
        .budget(8, 64)
        .build()
}

/// One frame's Monte Carlo estimate with `n >= 1` uniform samples: `4/pi` times the
/// fraction of the samples inside the disk.
pub(crate) fn estimate(rng: &mut SplitMix64, n: u32) -> f64 {
    let inside = (0..n)
        .filter(|_| {
            let x = rng.next_f64() - 0.5;
            let y = rng.next_f64() - 0.5;
            x * x + y * y <= 0.25
        })
        .count();
    inside as f64 * (4.0 / PI) / f64::from(n)
}

/// What one frame of a circle pixel did.
pub(crate) struct Frame {
    /// The count the controller chose.
    pub(crate) count: u32,
    /// The frame's estimate `S`.
    pub(crate) sample: f64,
    /// Whether `update` absorbed the frame.
    pub(crate) accepted: bool,
}

/// Runs frame `t` of a pixel: count, estimate, update. With `seeded`, frame 0 is a
/// disocclusion (`history_valid = false`), so the history starts from the docs/algorithms.md §2.3 seed
/// instead of the zero history.
pub(crate) fn frame(
    config: &SpvgConfig<f64>,
    history: &mut SpvgHistory<f64>,
    rng: &mut SplitMix64,
    t: usize,
    seeded: bool,
) -> Frame {
    let valid = !(seeded && t == 0);
    let count = config.estimate_with_validity(history, 1.0, valid);
    let sample = estimate(rng, count);
    let accepted = config.update(history, sample, count, valid);
    Frame {
        count,
        sample,
        accepted,
    }
}
