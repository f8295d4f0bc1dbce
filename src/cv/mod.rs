//! Control variates for temporally stable sample counts (docs/algorithms.md §3).
//!
//! Under changing lighting the variance that SPVG monitors mixes temporal change into the
//! Monte Carlo variance, and the controller over-samples. A control variate removes the
//! temporal part: per pixel and frame, with `fbar = L_o - (1 - gamma) B` (the distant
//! estimate) and the control `G = gamma B` (pre-integrated lighting, a known in-frame
//! constant), the SPVG history monitors the residual `S = fbar - alpha G`.
//!
//! - [`As`]: `alpha = 0` (plain adaptive sampling), no extra state.
//! - [`Ccv`]: `alpha = 1` (constant CV, Unreal Engine 5), no extra state.
//! - [`Ocv`]: `alpha = (Sigma_xy + eps_a) / (Sigma_yy + eps_a)` from an EMCM of
//!   `[fbar, G]` kept in a [`CvHistory`] (4 numbers), clamped to `[0, a0 + fbar / G]`.
//!
//! [`PixelController`] runs the whole per-pixel step with any [`ControlModel`].
//!
//! # Documented policies
//!
//! - `alpha` is always finite and never negative; `G <= 0` or non-finite inputs drop
//!   the upper bound; a NaN raw ratio (corrupt state) falls back to 1 (CCV), an
//!   overflowed one saturates to `+-MAX` before the clamp.
//! - OCV reseeds on disocclusion with the first-sample seed (means = current values,
//!   moments 0, so the next coefficient is 1); on the disoccluded frame itself
//!   [`PixelController`] takes the coefficient of the cold state (also 1 for OCV), not
//!   of the stale one.
//! - Non-finite `fbar` or `G` leave a valid state unchanged and reset an invalid one.
//!
//! # Examples
//!
//! ```
//! use spvg::{CvHistory, SpvgConfig, SpvgHistory};
//! use spvg::cv::{Ocv, PixelController, PixelFrame};
//! let pixel = PixelController::new(SpvgConfig::<f32>::published(), Ocv::with_weight(0.05).unwrap());
//! let (mut h, mut j) = (SpvgHistory::default(), CvHistory::default());
//! for t in 0..10 {
//!     let valid = t > 0;
//!     let frame = PixelFrame { radiance: 1.1, preintegrated: 1.0, gamma: 0.5 };
//!     let n = pixel.count(&h, frame.gamma, valid);
//!     let u = pixel.update(&mut h, &mut j, frame, n, valid);
//!     assert!(u.alpha >= 0.0 && u.alpha.is_finite());
//! }
//! ```

mod history;
mod model;
mod ocv;
mod pixel;
pub mod rules;

pub use history::CvHistory;
pub use model::{As, Ccv, ControlModel};
pub use ocv::{DEFAULT_A0, DEFAULT_EPS_A, Ocv};
pub use pixel::{PixelController, PixelFrame, PixelUpdate};
