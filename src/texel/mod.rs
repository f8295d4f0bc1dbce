//! Per-pixel histories in RGBA16F / RGBA32F texels (SPEC 4).
//!
//! A renderer keeps the SPVG history `H = (mu, var, nbar)` and, for the online control
//! variate, `J = (Sigma_xy, Sigma_yy, zeta_f, zeta_g)` in textures between frames. This
//! module fixes the texel layouts ([`SpvgTexel16`], [`SpvgTexel32`], [`CvTexel16`],
//! [`CvTexel32`]), the encodings ([`TexelEncoding`]), the `f32 -> f16` store with optional
//! stochastic rounding ([`to_f16`], [`Rounding`]), and a check that tells whether the
//! configured weights can move `f16` storage at all ([`check_precision`]).
//!
//! # Channel order (the WGSL shader must read the same)
//!
//! | texel | r | g | b | a |
//! |---|---|---|---|---|
//! | SPVG `H` | `mu` | `var * 2^-k` | `nbar` | `0` (spare) |
//! | CV `J` | `Sigma_xy * 2^-c` | `Sigma_yy * 2^-c` | `zeta_f` | `zeta_g` |
//!
//! `2^k` is the power of two nearest `sigma0^2` and `2^c` the CV scale
//! ([`TexelEncoding::variance_scale`], [`TexelEncoding::cv_scale`]).
//!
//! # Why these encodings
//!
//! - **Mean** `mu` (HDR luminance): stored as is. `f16`'s relative step is the same in
//!   every normal binade, so a scale only moves the window `[6.1e-5, 65504]`, whose
//!   geometric centre is already near 2, where display-referred luminance lives. Luminance
//!   above 65504 saturates; below `6.1e-5` it loses relative precision (subnormals).
//! - **Variance**: stored relative to `sigma0^2` (to a power of two within `sqrt 2` of
//!   it), the quantity the controller divides by: the counts the controller can ask for
//!   (`var / sigma0^2 * nbar` between the budget bounds) correspond to stored values near
//!   1, in the middle of `f16`'s range. Saturation at 65504 (`var > 6.5` for `sigma0^2 =
//!   1e-4`) still asks for the maximum count; it only shortens the decay after a spike.
//! - **Mean count** `nbar`: stored as is. It lies in `[0, beta_max]`; dividing by
//!   `beta_max = 64` (a power of two) would change no bit, and any other scale no
//!   precision. The step is 1/32 in `[32, 64)`, a tiny fraction of one sample; keeping raw
//!   counts also keeps stored history valid when the budget changes at run time.
//! - **Control variate moments** `Sigma_xy`, `Sigma_yy`: only the ratio
//!   `(Sigma_xy + eps_a) / (Sigma_yy + eps_a)` is used, and what matters is their size
//!   relative to `eps_a`. Stored as is, `eps_a = 1e-6` would be an `f16` subnormal (6%
//!   steps); scaled by `2^-c` it sits in the normal range. See
//!   [`TexelEncoding::with_cv_scale`] for the choice of `c` and how `eps_a` is applied.
//! - **Control variate means** `zeta_f`, `zeta_g`: luminances, stored as is like `mu`.
//!
//! Nothing non-finite is ever stored: NaN becomes 0, overflow saturates at `+-65504`
//! (`f16`) or `+-f32::MAX`, negative variances and counts become 0.
//!
//! # Frozen updates
//!
//! With round-to-nearest, an `f16` EMA cannot move when `eta |x - mu|` is under half an
//! ulp of `mu` (relative `2^-12` to `2^-11`): with `eta = 0.005` a change under about 10%
//! of the mean is lost, with `eta_cv = 1e-6` nothing ever moves and OCV silently becomes
//! CCV. [`check_precision`] reports this for given weights; [`Rounding::Stochastic`]
//! makes the stored state move in expectation; [`Layout::F32`] moves it for any `eta`
//! above `2^-24`.

mod batch;
mod encoding;
mod precision;
mod rounding;
mod types;

pub use batch::{ConstantCoefficient, FrameInputs, estimate_frame, update_frame, update_frame_ocv};
pub use encoding::{Layout, Texel, TexelEncoding};
pub use precision::{
    Mobility, PrecisionReport, QuantityPrecision, StoredQuantity, check_config_precision,
    check_precision,
};
pub use rounding::{Rounding, channel_bits, to_f16};
pub use types::{CvTexel16, CvTexel32, SpvgTexel16, SpvgTexel32};
