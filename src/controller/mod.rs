//! The SPVG per-pixel sample-count controller (docs/algorithms.md §2).
//!
//! Per pixel the renderer keeps a [`SpvgHistory`] `H = (mu, var, nbar)` and, once per
//! frame, asks [`SpvgConfig::estimate`] for a count before sampling and calls
//! [`SpvgConfig::update`] with the monitored value `S_t` after.
//!
//! # Formulas
//!
//! Estimate (docs/algorithms.md §2.1), from the previous frame's history, with `r = var / sigma0^2`
//! and `k - 1 = 2/eta - 2`:
//! - `E = r nbar`, `Delta = (r - 1) nbar (k - 1)`, `n_hat = kappa Delta + E`, evaluated
//!   as `nbar (kappa (r - 1) (k - 1) + r)` (see [`SpvgConfig::raw_estimate`]);
//! - `n = ceil(clamp(n_hat, beta_min, beta_max))`, NaN giving `beta_min`;
//! - zero samples when `gamma < eps_u` or `gamma` is not positive (docs/algorithms.md §2.4);
//! - an invalid history (disocclusion, docs/algorithms.md §2.3) is treated as zero: `n = beta_min`.
//!
//! Update (docs/algorithms.md §2.2): EMV then EMA of `S` with weight `eta`, EMA of the count; with an
//! invalid history, `mu = S`, `var = sigma0^2`, `nbar = n` (docs/algorithms.md §2.3).
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
//!   again; with integer counts zero samples come only from the `gamma` rule. Fractional
//!   counts ([`fractional`], off by default) let a pixel with a valid history skip
//!   frames (a real count below one, realised by dithered rounding); pixels without
//!   history still take `min_samples`.
//! - A frame without a usable observation (non-finite `S`, or `count == 0`) leaves a
//!   valid history unchanged and resets an invalid one to zero; nothing non-finite is
//!   ever stored.
//! - Baselines ([`CountPolicy`]) share the clamp, rounding and update.
//! - The damped correction ([`SpvgConfigBuilder::max_change`], docs/algorithms.md §8.1)
//!   caps the SPVG raw count to `[nbar / (1 + c), nbar (1 + c)]` before the budget clamp;
//!   off by default.
//! - The firefly clamp ([`SpvgConfigBuilder::firefly_clamp`], docs/algorithms.md §8.3)
//!   clamps the monitored value to `mean +- k sqrt(max(variance, sigma0^2))` of a valid
//!   history before the update; off by default. It acts on the SPVG history only: the
//!   online control variate's moments of `fbar` and `G` take the frame's values as they
//!   are.
//!
//! # Supported numeric range
//!
//! Checked by the property matrix `tests/extremes/` in `f32` and `f64`: luminances
//! (radiance, pre-integrated lighting, monitored values) of either sign with magnitudes
//! from 1e-30 to 1e30, mixed with exact zeros, subnormals, `+-MAX`, NaN and `+-inf`;
//! `eta` and `eta_cv` from 1e-7 to 1; `sigma0^2` from 1e-8 to 1e2; `kappa` in `[0, 1]`;
//! budgets `1 <= beta_min <= beta_max <= 1024`; `gamma` in `[0, 1]`, NaN or negative;
//! random validity flags; 50-frame sequences through every [`CountPolicy`] (SPVG with and
//! without the damped correction, `max_change` from 1e-3 to 10), the firefly clamp off and
//! on (`k` from 0.1 to 100), and every control-variate model.
//!
//! Guaranteed for every input, in range or not, and every configuration that
//! [`SpvgConfigBuilder::build`] accepts:
//! - no panic; every stored number (history and OCV state) is finite, and variances and
//!   mean counts are never negative;
//! - the count is 0 exactly when `gamma` fails [`SpvgConfig::samples_distant`], and is
//!   otherwise within `[beta_min, beta_max]` and equal to the docs/algorithms.md §2.1 count evaluated
//!   without overflow (up to the rounding of `n_hat` next to an integer);
//! - the OCV coefficient is finite, `>= 0`, and `<= a0 + fbar / G` wherever `G > 0` and
//!   that bound is finite;
//! - a frame that sampled with finite inputs is absorbed (an overflow saturates at
//!   `+-MAX`); a frame with a non-finite input is refused and leaves a valid history
//!   unchanged.
//!
//! Validation accepts a parameter exactly when it is in its documented range and its
//! derived constant is finite in `T`: `eta` needs `2 / eta` finite (`f32`: `eta >=
//! 5.9e-39`; `f64`: `>= 1.1e-308`), `sigma0^2` needs `1 / sigma0^2` finite (`f32`:
//! `>= 2.94e-39 = 1 / f32::MAX`; `f64`: `>= 5.6e-309`). Smaller positive values are
//! rejected with [`Error::InvalidParameter`](crate::Error::InvalidParameter). Tiny
//! targets that pass are kept: where `var / sigma0^2` overflows it saturates and the
//! count is `beta_max`, which is the right answer for an unreachable target.
//!
//! What degrades, with measured thresholds (pinned by tests in `tests/extremes/`
//! against bounds derived from IEEE rounding, except the long `eta = 1e-6` run):
//! - **Huge deviations.** A deviation `|S - mu|` above `sqrt(MAX)` (`f32`: 1.845e19;
//!   `f64`: 1.34e154) squares past the range; the square saturates, so the variance
//!   stops growing (at `eta (1 - eta) MAX` from zero, 5.44e37 with `eta = 0.2` in
//!   `f32`) and the count is `beta_max`. Luminances beyond about `MAX / 2` make `fbar`
//!   or the residual overflow; they saturate and the frame is still absorbed.
//! - **Tiny deviations.** Below about 6.6e-23 in `f32` (with `eta = 0.2`)
//!   `eta (1 - eta) d^2` underflows to 0: the variance reads 0 and the count is
//!   `beta_min`, as it should be for every accepted `sigma0^2` above ~1e-44.
//! - **Small weights (f32).** A stored value `m` moves only when `|eta (x - m)|`
//!   exceeds about half an ulp of `m`; `1 - eta` rounds to exactly 1 for
//!   `eta <= 2^-25` (2.98e-8), so nothing decays. At `eta = 1e-7` a value near 1 moves
//!   only for steps of more than +79% or -11%. Consequence for a static pixel: its mean
//!   stalls 0.87 to 2.2 times `ulp(S) / (2 eta)` short of `S` and its variance
//!   settles at the square of that stall instead of 0, so the count is spurious, up to
//!   `beta_max` for ever, once `eta < ~2^-24 |S| / sigma0` (measured: `S = 1.9`,
//!   `eta = 1e-5`, variance floor 1.7e-4; `S = 1`, `eta = 1e-6`, floor 8.9e-4). Keep
//!   `eta >> 2^-24 |S| / sigma0` in `f32` (`2^-53` in `f64`, where only
//!   `|S| / sigma0 > ~1e9` at `eta = 1e-7` is affected). OCV's means stall the same way
//!   with `eta_cv`. This is docs/algorithms.md §4's f16 hazard, 2^13 times smaller in `f32`.
//! - **`eta = 1`.** `eta (1 - eta) = 0`, so the EMV is always 0 and every history-based
//!   count is `beta_min` (`k - 1 = 0` as well): valid, but it disables the controller.
//! - **OCV with `G <= 0`.** `D` has no upper bound, so `alpha G` can overflow for
//!   moderate luminances; the residual saturates and the count goes to `beta_max`. A
//!   coefficient ratio that overflows saturates to `+-MAX` before the clamp. Moments far
//!   below `eps_a` (1e-6) give `alpha ~ 1` (CCV) by design.
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
mod damping;
mod estimate;
pub mod fractional;
mod history;
mod policy;
pub mod rules;
mod update;
pub mod young;

pub use config::{MAX_BUDGET, SpvgConfig, SpvgConfigBuilder};
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
