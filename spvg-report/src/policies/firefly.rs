//! The firefly clamp (`SpvgConfig::firefly_clamp`, docs/algorithms.md §8.3) measured on
//! the core crate: an ensemble of independent pixels whose monitored value is 0.5 plus
//! Monte Carlo noise, under the published controller, hit by one outlier frame, and
//! one that steps to a new level for good. Measured for the clamp off and for a few
//! `k`: how many frames the outlier holds the count away from its steady value, and how
//! many frames the history's mean takes to follow a real change.

use spvg::{SpvgConfig, SpvgHistory};

use spvg_fixtures::splitmix::SplitMix64;

use crate::error::ReportError;

/// Pixels of the ensemble.
pub const PIXELS: u64 = 2000;
/// The steady window `[STEADY_FROM, OUTLIER_FRAME)` that defines the steady count.
pub const STEADY_FROM: usize = 60;
/// The frame whose monitored value is the outlier (or where the step happens).
pub const OUTLIER_FRAME: usize = 100;
/// Frames after the outlier frame that are watched.
pub const AFTER: usize = 150;
/// The monitored value's level.
pub const LEVEL: f64 = 0.5;
/// Per-sample standard deviation of the noise: the steady count is about
/// `PER_SAMPLE_SD^2 / sigma0^2 = 25` samples at the published `sigma0^2 = 1e-4`.
pub const PER_SAMPLE_SD: f64 = 0.05;
/// The outlier frames measured: the monitored value times 100, and the 1e4.
pub const OUTLIERS: [Outlier; 2] = [Outlier::Times(100.0), Outlier::Value(1e4)];
/// The real change: the level steps to 10 times [`LEVEL`] at [`OUTLIER_FRAME`].
pub const STEP: f64 = 10.0;
/// The `k` measured besides the clamp off.
pub const KS: [f64; 4] = [3.0, 4.0, 6.0, 8.0];
/// The `k` the documentation recommends and the acceptance line judges
/// (docs/algorithms.md §8.3 says why).
pub const RECOMMENDED_K: f64 = 4.0;
/// The acceptance bound: frames after a 100x outlier until the mean count is back within
/// 10% of the steady count.
pub const RECOVERY_BOUND: usize = 10;

/// One outlier frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outlier {
    /// The frame's monitored value times this factor.
    Times(f64),
    /// The frame's monitored value replaced by this value.
    Value(f64),
}

impl Outlier {
    fn apply(self, s: f64) -> f64 {
        match self {
            Self::Times(f) => s * f,
            Self::Value(v) => v,
        }
    }

    /// A short label: `100x`, `S=1e4`.
    #[must_use]
    pub fn label(self) -> String {
        match self {
            Self::Times(f) => format!("{f}x"),
            Self::Value(v) => format!("S={v:e}"),
        }
    }
}

/// What one outlier does to the ensemble.
#[derive(Clone, Debug, PartialEq)]
pub struct Recovery {
    /// Frames after the outlier frame whose ensemble mean count lies outside 10% of the
    /// steady count, up to the last one (0: it never left the band): the frames until
    /// the count is back for good.
    pub frames: usize,
    /// The largest ensemble mean count after the outlier.
    pub peak: f64,
    /// Samples per pixel spent above the steady count over the watched frames.
    pub extra_samples: f64,
}

/// One setting's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct FireflyFigures {
    /// `off` or `k=6`.
    pub label: String,
    /// The clamp's `k`, `None` when off.
    pub k: Option<f64>,
    /// The steady mean count (ensemble mean over the steady window).
    pub steady_mean: f64,
    /// One [`Recovery`] per entry of [`OUTLIERS`].
    pub recoveries: Vec<Recovery>,
    /// Updates, from the step frame on, after a step of the level to [`STEP`] times
    /// [`LEVEL`], until the ensemble mean of the history's mean is within 10% of the new
    /// level for good (the plain EMA of weight 0.2 takes 10).
    pub step_frames: usize,
    /// [`frames_at_ceiling`] of each of [`CEILING_VALUES`] at this setting.
    pub ceiling_frames: Vec<usize>,
}

/// The monitored value of a frame with `n` samples: the level plus the mean of `n`
/// samples' noise (normal, standard deviation `PER_SAMPLE_SD / sqrt(n)`).
fn monitored(rng: &mut SplitMix64, level: f64, n: u32) -> f64 {
    level + PER_SAMPLE_SD / f64::from(n.max(1)).sqrt() * rng.normal()
}

/// Ensemble means per frame of the count and of the history's mean, each pixel seeded at
/// frame 0 from its first observation; `event(t, s)` rewrites frame `t`'s value and
/// `level(t)` is the level at frame `t`.
fn run(
    config: &SpvgConfig<f64>,
    level: impl Fn(usize) -> f64,
    event: impl Fn(usize, f64) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    let frames = OUTLIER_FRAME + 1 + AFTER;
    let (mut counts, mut means) = (vec![0.0; frames], vec![0.0; frames]);
    for p in 0..PIXELS {
        let mut rng = SplitMix64(0xf1ef ^ (p * 0x9e37));
        let mut h = SpvgHistory::default();
        for t in 0..frames {
            let valid = t > 0;
            let n = config.estimate_with_validity(&h, 1.0, valid);
            let s = event(t, monitored(&mut rng, level(t), n));
            config.update(&mut h, s, n, valid);
            counts[t] += f64::from(n);
            means[t] += h.mean;
        }
    }
    let scale = 1.0 / PIXELS as f64;
    for v in counts.iter_mut().chain(means.iter_mut()) {
        *v *= scale;
    }
    (counts, means)
}

/// Frames of `series` from `from` on up to the last one outside 10% of `target` (0 when
/// none is).
fn frames_out_of_band(series: &[f64], from: usize, target: f64) -> usize {
    series[from..]
        .iter()
        .rposition(|v| (v - target).abs() > 0.1 * target.abs())
        .map_or(0, |i| i + 1)
}

/// The figures of the clamp off and of each `k` in [`KS`], under the published controller.
///
/// # Errors
///
/// A configuration the core rejects (none: the settings are fixed).
pub fn firefly_sweep() -> Result<Vec<FireflyFigures>, ReportError> {
    let mut rows = vec![("off".to_owned(), None)];
    rows.extend(KS.iter().map(|&k| (format!("k={k}"), Some(k))));
    rows.into_iter()
        .map(|(label, k)| {
            let config = SpvgConfig::<f64>::builder().firefly_clamp(k).build()?;
            let (counts, _) = run(&config, |_| LEVEL, |_, s| s);
            let steady = &counts[STEADY_FROM..OUTLIER_FRAME];
            let steady_mean = steady.iter().sum::<f64>() / steady.len() as f64;
            let recoveries = OUTLIERS
                .iter()
                .map(|&o| {
                    let (c, _) = run(
                        &config,
                        |_| LEVEL,
                        |t, s| if t == OUTLIER_FRAME { o.apply(s) } else { s },
                    );
                    let after = &c[OUTLIER_FRAME + 1..];
                    Recovery {
                        // The outlier frame's own count was estimated before it: the
                        // first count it can move is the next frame's.
                        frames: frames_out_of_band(&c, OUTLIER_FRAME + 1, steady_mean),
                        peak: after.iter().copied().fold(0.0, f64::max),
                        extra_samples: after.iter().map(|n| n - steady_mean).sum(),
                    }
                })
                .collect();
            let new_level = STEP * LEVEL;
            let (_, means) = run(
                &config,
                |t| if t >= OUTLIER_FRAME { new_level } else { LEVEL },
                |_, s| s,
            );
            let ceiling_frames = CEILING_VALUES
                .iter()
                .map(|&v| frames_at_ceiling(k.map(|k| k as f32), v))
                .collect::<Result<_, _>>()?;
            Ok(FireflyFigures {
                label,
                k,
                ceiling_frames,
                steady_mean,
                recoveries,
                // Updates from the step frame on until the mean is in the band.
                step_frames: frames_out_of_band(&means, OUTLIER_FRAME, new_level) + 1,
            })
        })
        .collect()
}

/// The single finite values injected for the ceiling figure ([`frames_at_ceiling`]).
pub const CEILING_VALUES: [f32; 3] = [1e30, 1e4, 50.0];

/// Frames watched after the injected value before the ceiling figure gives up.
pub const CEILING_WATCH: usize = 2000;

/// The firefly recovery figure of one pixel: the core's own `f32` controller at the
/// published defaults with the firefly clamp `k` (`None`: off), the pixel of the
/// ensemble's pixel 0 (seeded at frame 0, monitored value [`LEVEL`] plus the mean of its
/// samples' noise); at [`OUTLIER_FRAME`] its monitored value is replaced by `value`. The
/// figure is the number of consecutive frames from the next one on whose count is
/// `beta_max` (0: the next frame is already below it), at most [`CEILING_WATCH`].
/// Deterministic: the noise is a fixed `SplitMix64` stream.
///
/// # Errors
///
/// A `k` the core rejects (naming `firefly_clamp`).
pub fn frames_at_ceiling(k: Option<f32>, value: f32) -> Result<usize, ReportError> {
    let config = SpvgConfig::<f32>::builder().firefly_clamp(k).build()?;
    let mut rng = SplitMix64(0xf1ef);
    let mut h = SpvgHistory::<f32>::default();
    let mut at_ceiling = 0;
    for t in 0..=OUTLIER_FRAME + CEILING_WATCH {
        let valid = t > 0;
        let n = config.estimate_with_validity(&h, 1.0, valid);
        if t > OUTLIER_FRAME {
            if n < config.max_samples() {
                break;
            }
            at_ceiling += 1;
        }
        let s = if t == OUTLIER_FRAME {
            value
        } else {
            monitored(&mut rng, LEVEL, n) as f32
        };
        config.update(&mut h, s, n, valid);
    }
    Ok(at_ceiling)
}
