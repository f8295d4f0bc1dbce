//! The damped correction policy in the kappa sweep: the docs/algorithms.md §7
//! *circle* scenario run with the core crate for kappa = 0, kappa = 1 and the damped
//! correction (kappa = 0 with a per-frame cap on the relative change of the count,
//! `SpvgConfig::max_change`), measured as docs/algorithms.md §8.1 defines the figures.
//!
//! The scenario and its measurement are the ones `tests/damped.rs` and
//! `examples/circle.rs` use (the `spvg-fixtures` crate), so the report quotes
//! the very numbers those check. The pass itself does not run the damped rule yet: the
//! WGSL library's estimate has it, but `spvg_effects::sss::PassConfig` does not expose
//! `max_change` (docs/algorithms.md §8.2, status of the GPU pass).

use spvg_fixtures::circle;

use crate::error::ReportError;

/// Pixels of the ensemble (as `tests/damped.rs`).
pub const PIXELS: u64 = 2000;
/// Frames per pixel.
pub const FRAMES: usize = 400;
/// First frame of the steady window.
pub const STEADY_FROM: usize = 100;

/// One policy's figures on the circle scenario from a cold (zero) history.
#[derive(Clone, Debug, PartialEq)]
pub struct PolicyFigures {
    /// `kappa=0`, `kappa=1` or `damped c=0.35`.
    pub label: String,
    /// First frame from which the ensemble mean count stays within 10% of the steady mean.
    pub frames_to_band: usize,
    /// Mean `|n_t - n_(t-1)|` over pixels and the steady window.
    pub mean_abs_step: f64,
    /// Lag-1 autocorrelation of the count in the steady window.
    pub lag1: f64,
    /// Steady mean count.
    pub steady_mean: f64,
}

/// kappa = 0, kappa = 1 and the damped correction on the circle scenario.
///
/// # Errors
///
/// A configuration the core rejects (none: the settings are fixed).
pub fn circle_sweep() -> Result<Vec<PolicyFigures>, ReportError> {
    let rows = [
        ("kappa=0".to_owned(), circle::config(0.0)?),
        ("kappa=1".to_owned(), circle::config(1.0)?),
        (
            format!("damped c={}", circle::DAMPED_MAX_CHANGE),
            circle::damped_config()?,
        ),
    ];
    Ok(rows
        .into_iter()
        .map(|(label, config)| {
            let f = circle::figures(&config, PIXELS, FRAMES, STEADY_FROM);
            PolicyFigures {
                label,
                frames_to_band: f.frames_to_band,
                mean_abs_step: f.mean_abs_step,
                lag1: f.lag1,
                steady_mean: f.steady_mean,
            }
        })
        .collect())
}
