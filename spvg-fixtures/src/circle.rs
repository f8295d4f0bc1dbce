//! The docs/algorithms.md §7 *circle* scenario, shared by the core's tests and its
//! `circle` example: one pixel whose integrand is `4/pi` inside the disk of radius 0.5
//! centred in the unit square and 0 outside (mean 1, per-sample variance
//! `4/pi - 1 ~ 0.2732`), sampled uniformly, under the SPVG controller with `eta = 0.2`,
//! `sigma0^2 = 0.08^2` and budget `[8, 64]`.

use std::f64::consts::PI;

use spvg::{SpvgConfig, SpvgHistory};

use crate::splitmix::SplitMix64;

/// The target variance `sigma0^2 = 0.08^2`.
pub const TARGET: f64 = 0.08 * 0.08;

/// Per-sample variance of the circle integrand: `E f^2 - 1 = (16/pi^2)(pi/4) - 1`.
pub fn per_sample_variance() -> f64 {
    4.0 / PI - 1.0
}

/// The scenario's controller: `eta = 0.2`, [`TARGET`], the given `kappa`, budget
/// `[8, 64]`, the other parameters published.
pub fn config(kappa: f64) -> Result<SpvgConfig<f64>, spvg::Error> {
    SpvgConfig::builder()
        .eta(0.2)
        .target_variance(TARGET)
        .kappa(kappa)
        .budget(8, 64)
        .build()
}

/// One frame's Monte Carlo estimate with `n >= 1` uniform samples: `4/pi` times the
/// fraction of the samples inside the disk.
pub fn estimate(rng: &mut SplitMix64, n: u32) -> f64 {
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
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The count the controller chose.
    pub count: u32,
    /// The frame's estimate `S`.
    pub sample: f64,
    /// Whether `update` absorbed the frame.
    pub accepted: bool,
}

/// Runs frame `t` of a pixel: count, estimate, update. With `seeded`, frame 0 is a
/// disocclusion (`history_valid = false`), so the history starts from the docs/algorithms.md §2.3 seed
/// instead of the zero history.
pub fn frame(
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

/// The damped correction's cap `c` used on this scenario (docs/algorithms.md §8.1):
/// counts stay within `[nbar / 1.35, 1.35 nbar]`.
pub const DAMPED_MAX_CHANGE: f64 = 0.35;

/// The scenario's controller with the damped correction: `kappa = 0` and
/// [`DAMPED_MAX_CHANGE`].
pub fn damped_config() -> Result<SpvgConfig<f64>, spvg::Error> {
    config(0.0)?
        .to_builder()
        .max_change(Some(DAMPED_MAX_CHANGE))
        .build()
}

/// What a policy does on this scenario from the zero history, over an ensemble of
/// independent pixels (docs/algorithms.md §8.1 defines the figures):
#[derive(Clone, Copy, Debug)]
pub struct Figures {
    /// Steady mean count `M`: the mean count over pixels and the frames of the steady
    /// window `[steady_from, frames)`.
    pub steady_mean: f64,
    /// Frames to within 10%: the first frame `t` from which the ensemble mean count
    /// (mean over pixels at each frame) stays within `0.1 M` of `M` up to the last frame.
    pub frames_to_band: usize,
    /// Mean `|n_t - n_(t-1)|` over pixels and the frames of the steady window.
    pub mean_abs_step: f64,
    /// Lag-1 autocorrelation of each pixel's count over the steady window (about that
    /// pixel's mean), averaged over the pixels whose count is not constant there.
    pub lag1: f64,
    /// Mean over pixels of the samples spent in the first 30 frames.
    pub cold_start_samples: f64,
}

/// Runs `pixels` independent circle pixels (pixel `p` draws from
/// `SplitMix64(0x5eed ^ (p * 0x9e37))`) for `frames` frames from the zero history and
/// measures [`Figures`] with the steady window `[steady_from, frames)`.
pub fn figures(
    config: &SpvgConfig<f64>,
    pixels: u64,
    frames: usize,
    steady_from: usize,
) -> Figures {
    let mut ensemble = vec![0.0; frames];
    let (mut steps, mut lag1, mut lag1_pixels, mut cold) = (0.0, 0.0, 0_u32, 0.0);
    for p in 0..pixels {
        let mut rng = SplitMix64(0x5eed ^ (p * 0x9e37));
        let mut history = SpvgHistory::default();
        let counts: Vec<f64> = (0..frames)
            .map(|t| f64::from(frame(config, &mut history, &mut rng, t, false).count))
            .collect();
        for (e, n) in ensemble.iter_mut().zip(&counts) {
            *e += n;
        }
        cold += counts[..30.min(frames)].iter().sum::<f64>();
        let window = &counts[steady_from..];
        steps += window.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>();
        let m = window.iter().sum::<f64>() / window.len() as f64;
        let var = window.iter().map(|n| (n - m) * (n - m)).sum::<f64>();
        if var > 0.0 {
            let cov = window
                .windows(2)
                .map(|w| (w[1] - m) * (w[0] - m))
                .sum::<f64>();
            lag1 += cov / var;
            lag1_pixels += 1;
        }
    }
    let scale = 1.0 / pixels as f64;
    for e in &mut ensemble {
        *e *= scale;
    }
    let steady_mean = ensemble[steady_from..].iter().sum::<f64>() / (frames - steady_from) as f64;
    let frames_to_band = ensemble
        .iter()
        .rposition(|e| (e - steady_mean).abs() > 0.1 * steady_mean)
        .map_or(0, |t| t + 1);
    Figures {
        steady_mean,
        frames_to_band,
        mean_abs_step: steps * scale / (frames - steady_from - 1) as f64,
        lag1: lag1 / f64::from(lag1_pixels.max(1)),
        cold_start_samples: cold * scale,
    }
}
