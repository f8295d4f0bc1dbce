//! The SPVG per-pixel sample-count controller (SPEC section 2).
//!
//! Per pixel the renderer keeps a [`SpvgHistory`] `H = (mu, var, nbar)` and, once per
//! frame, asks [`SpvgConfig::estimate`] for a count before sampling and calls
//! [`SpvgConfig::update`] with the monitored value `S_t` after.
//!
//! # Formulas
//!
//! Estimate (SPEC 2.1), from the previous frame's history, with `r = var / sigma0^2`
//! and `k - 1 = 2/eta - 2`:
//! - `E = r nbar`, `Delta = (r - 1) nbar (k - 1)`, `n_hat = kappa Delta + E`;
//! - `n = ceil(clamp(n_hat, beta_min, beta_max))`, NaN giving `beta_min`;
//! - zero samples when `gamma < eps_u` or `gamma` is not positive (SPEC 2.4);
//! - an invalid history (disocclusion, SPEC 2.3) is treated as zero: `n = beta_min`.
//!
//! Update (SPEC 2.2): EMV then EMA of `S` with weight `eta`, EMA of the count; with an
//! invalid history, `mu = S`, `var = sigma0^2`, `nbar = n` (SPEC 2.3).
//!
//! The exact single-precision operation order, which a GPU port must follow, is given on
//! [`SpvgConfig::raw_estimate`], [`SpvgConfig::round_count`] and [`SpvgConfig::update`].
//!
//! # Documented policies
//!
//! - The count is always within `[min_samples, max_samples]` unless the zero-sample rule
//!   gives 0, whatever the history holds: a NaN raw count gives `min_samples` (a
//!   poisoned history must not burn the budget), `+inf` gives `max_samples`.
//! - `min_samples >= 1`: a pixel that took zero samples would never observe variance
//!   again; zero samples come only from the `gamma` rule.
//! - A frame without a usable observation (non-finite `S`, or `count == 0`) leaves a
//!   valid history unchanged and resets an invalid one to zero; nothing non-finite is
//!   ever stored.
//! - Baselines ([`CountPolicy`]) share the clamp, rounding and update.
//!
//! # Examples
//!
//! ```
//! use spvg::{SpvgConfig, SpvgHistory};
//! let config = SpvgConfig::<f32>::published();
//! let mut history = SpvgHistory::default();
//! for frame in 0..4 {
//!     let n = config.estimate_with_validity(&history, 1.0, frame > 0);
//!     assert!((8..=64).contains(&n));
//!     let s = 0.5; // the pixel's luminance estimate from `n` samples
//!     config.update(&mut history, s, n, frame > 0);
//! }
//! ```

mod config;
mod estimate;
mod history;
mod policy;
mod update;

pub use config::{SpvgConfig, SpvgConfigBuilder};
pub use history::SpvgHistory;
pub use policy::CountPolicy;

/// The cold (all-zero) history, for any `Float` (which does not imply `Default`).
#[inline]
fn zero_history<T: num_traits::Float>() -> SpvgHistory<T> {
    SpvgHistory {
        mean: T::zero(),
        variance: T::zero(),
        mean_count: T::zero(),
    }
}
