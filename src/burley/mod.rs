//! Burley's normalized diffusion profile (docs/algorithms.md §2.4 and §5): evaluation, exact and
//! approximate inverse-cdf sampling, truncated (distant) sampling, Monte Carlo estimators
//! and measured material presets.
//!
//! With `x = r / d`, the profile and its radial distribution are
//!
//! - `R(r) = A (e^{-x} + e^{-x/3}) / (8 pi d r)`, with `int_0^inf 2 pi r R(r) dr = A`;
//! - `pdf(r) = (e^{-x} + e^{-x/3}) / (4 d)` (normalized, including the `2 pi r` Jacobian);
//! - `cdf(r) = 1 - e^{-x}/4 - 3 e^{-x/3}/4`.
//!
//! [`BurleyProfile`] holds a validated `(A, d)` pair; [`ShapeFit`] turns an albedo and a
//! mean free path into the shape `d`. Sampling lives in [`BurleyProfile::inverse_cdf`],
//! [`BurleyProfile::approx_inverse_cdf`] and [`BurleyProfile::sample_distant`]; the
//! estimators of docs/algorithms.md §5 in [`PlainEstimator`] and [`RatioEstimator`]; the measured
//! materials in [`presets`]. The separable profile engines ship and its pre-integrated
//! kernel are [`SeparableProfile`]; [`fit_burley`] and [`fit_falloff`] convert between the
//! two parametrisations (docs/algorithms.md §5.1).
//!
//! # Examples
//!
//! ```
//! use spvg::burley::{BurleyProfile, ShapeFit};
//! let p = BurleyProfile::new(0.8_f64, 1.0, ShapeFit::DiffuseMeanFreePath).unwrap();
//! let r = p.inverse_cdf(0.5);
//! assert!((p.cdf(r) - 0.5).abs() < 1e-15);
//! ```

mod estimator;
mod fit;
mod inverse;
pub mod presets;
mod profile;
mod separable;

pub use estimator::{PlainEstimator, RatioEstimator, filtered_mip_level};
pub use fit::{
    BurleyFit, F_MIN, FIT_SAMPLES, FalloffFit, FalloffMatch, RESOLVED_STEPS, SCAN_POINTS,
    fit_burley, fit_falloff, fit_grid_spacing, forward_grid_extent, reverse_falloff_floor,
    reverse_grid_extent, s_delta,
};
pub use inverse::{APPROX_C_PAPER, APPROX_C_UNREAL, DistantSample, footprint_radius};
pub use presets::MaterialPreset;
pub use profile::{BurleyProfile, ShapeFit};
pub use separable::{FALLOFF_EPSILON, SEPARABLE_GAUSSIANS, SeparableProfile, kernel_range};

use num_traits::Float;

/// Converts an `f64` literal to `T`.
///
/// Every `Float` type the crate is used with (`f32`, `f64`) converts any `f64`; a type that
/// cannot gets NaN, which the validating constructors then reject, instead of a panic.
#[inline]
#[must_use]
pub(crate) fn lit<T: Float>(x: f64) -> T {
    T::from(x).unwrap_or_else(T::nan)
}
