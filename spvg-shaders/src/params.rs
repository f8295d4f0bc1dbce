//! The parameter block shared by every library function: `spvg_Params` in WGSL.

use bytemuck::{Pod, Zeroable};
use spvg::SpvgConfig;
use spvg::controller::CountPolicy;
use spvg::cv::Ocv;
use spvg::texel::{Layout, TexelEncoding};

/// The control-variate model the library functions run (`spvg_MODEL_*`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// Plain adaptive sampling, `alpha = 0` ([`spvg::cv::As`]).
    As,
    /// Constant control variate, `alpha = 1` ([`spvg::cv::Ccv`]).
    Ccv,
    /// Online control variate with its validated parameters ([`Ocv`]).
    Ocv(Ocv<f32>),
}

impl Control {
    /// Short name (`as`, `ccv`, `ocv`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::As => "as",
            Self::Ccv => "ccv",
            Self::Ocv(_) => "ocv",
        }
    }

    /// Whether the history update reads a control value `G` (CCV and OCV).
    #[must_use]
    pub fn needs_control(&self) -> bool {
        !matches!(self, Self::As)
    }

    /// Bytes of history per pixel kept between frames in RGBA16F texels: 8 for the SPVG
    /// texel, 8 more for OCV's CV texel (a ping-pong copy not counted).
    #[must_use]
    pub fn history_bytes_per_pixel(&self) -> u32 {
        match self {
            Self::As | Self::Ccv => 8,
            Self::Ocv(_) => 16,
        }
    }
}

/// How `f16` history texels are rounded on store (`spvg_ROUNDING_*`); the random word of
/// stochastic rounding is per pixel, an argument of the encode functions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StoreRounding {
    /// Round to nearest, ties to even ([`spvg::texel::Rounding::Nearest`]).
    #[default]
    Nearest,
    /// Stochastic rounding ([`spvg::texel::Rounding::Stochastic`]).
    Stochastic,
}

/// How the histories are stored: the texel encoding (scales), the texel precision and
/// the `f16` rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Storage {
    /// Scales of the variance and the CV moments.
    pub encoding: TexelEncoding,
    /// RGBA16F or RGBA32F.
    pub layout: Layout,
    /// Rounding of `f16` stores (ignored by `f32` texels).
    pub rounding: StoreRounding,
}

/// The parameter block of the WGSL library, to upload as is (a uniform or storage
/// buffer, or a push-constant range) and pass to the functions by value.
///
/// WGSL twin: `struct spvg_Params` in `wgsl/params.wgsl`, same field order; 36 four-byte
/// scalars, 144 bytes, a multiple of 16 so it can also sit first in a larger uniform
/// struct. `tests/naga.rs` checks every member's offset and type against naga's layout
/// of the WGSL struct. Build it with [`Params::new`]; every derived constant
/// (`retain`, `eta_retain`, `k_minus_1`, `inv_target`, the scales) is the core crate's own
/// `f32` value, so the shader and the core compute from identical numbers.
///
/// # Examples
///
/// ```
/// use spvg::SpvgConfig;
/// use spvg::cv::Ocv;
/// use spvg::texel::{Layout, TexelEncoding};
/// use spvg_shaders::{Control, Params, Storage, StoreRounding};
///
/// let config = SpvgConfig::<f32>::published();
/// let ocv = Ocv::with_weight(0.2).unwrap().with_f16_inputs(true);
/// let storage = Storage {
///     encoding: TexelEncoding::for_config(&config).unwrap().for_ocv(&ocv).unwrap(),
///     layout: Layout::F16,
///     rounding: StoreRounding::Nearest,
/// };
/// let p = Params::new(&config, Control::Ocv(ocv), &storage);
/// assert_eq!((p.min_samples, p.max_samples), (8, 64));
/// assert_eq!(p.k_minus_1, config.k_minus_1());
/// assert_eq!(p.var_scale, 2f32.powi(-13)); // the power of two nearest 1e-4
/// let bytes: &[u8] = bytemuck::bytes_of(&p);
/// assert_eq!(bytes.len(), 144);
/// ```
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Params {
    /// History weight `eta` ([`SpvgConfig::eta`]).
    pub eta: f32,
    /// `1 - eta`.
    pub retain: f32,
    /// `eta (1 - eta)`.
    pub eta_retain: f32,
    /// Target variance `sigma0^2`.
    pub target_variance: f32,
    /// `1 / sigma0^2` ([`SpvgConfig::inv_target`]).
    pub inv_target: f32,
    /// Control factor `kappa`.
    pub kappa: f32,
    /// `k - 1 = 2/eta - 2` ([`SpvgConfig::k_minus_1`]); `k_minus_one` in WGSL.
    pub k_minus_1: f32,
    /// Zero-sample threshold `eps_u`.
    pub eps_u: f32,
    /// `beta_min` as `f32` ([`SpvgConfig::min_samples_f`]).
    pub min_samples_f: f32,
    /// `beta_max` as `f32` ([`SpvgConfig::max_samples_f`]).
    pub max_samples_f: f32,
    /// `beta_min`.
    pub min_samples: u32,
    /// `beta_max`.
    pub max_samples: u32,
    /// Count rule: 0 SPVG, 1 two-phase, 2 Unreal clamp, 3 fixed ([`CountPolicy`]).
    pub policy: u32,
    /// `n` of [`CountPolicy::Fixed`] (0 otherwise).
    pub fixed_count: u32,
    /// 1 where the damped correction is on ([`SpvgConfig::max_change`] is `Some`).
    pub damped: u32,
    /// `1 / (1 + c)` ([`SpvgConfig::cap_down`]).
    pub cap_down: f32,
    /// `1 + c` ([`SpvgConfig::cap_up`]; `+inf` when off).
    pub cap_up: f32,
    /// Control model: 0 AS, 1 CCV, 2 OCV ([`Control`]).
    pub model: u32,
    /// 1 where OCV rounds `fbar` and `G` to `f16` before its update
    /// ([`Ocv::with_f16_inputs`]).
    pub f16_inputs: u32,
    /// OCV weight `eta_cv` (1 without OCV).
    pub eta_cv: f32,
    /// `1 - eta_cv`.
    pub retain_cv: f32,
    /// `eta_cv (1 - eta_cv)`.
    pub eta_retain_cv: f32,
    /// OCV regulariser `eps_a` (0 without OCV).
    pub eps_a: f32,
    /// OCV bound offset `a0` (0 without OCV); `a_zero` in WGSL.
    pub a0: f32,
    /// Texel precision: 0 RGBA16F, 1 RGBA32F ([`Layout`]).
    pub texel_layout: u32,
    /// `f16` store rounding: 0 nearest, 1 stochastic ([`StoreRounding`]).
    pub rounding: u32,
    /// `2^k`: stored variance times this is the variance ([`TexelEncoding::variance_scale`]).
    pub var_scale: f32,
    /// `2^-k`.
    pub inv_var_scale: f32,
    /// `2^c`: stored CV moments times this are the moments ([`TexelEncoding::cv_scale`]).
    pub cv_scale: f32,
    /// `2^-c`.
    pub inv_cv_scale: f32,
    /// The firefly clamp's `k` ([`SpvgConfig::firefly_clamp`]), 0 when off (a valid `k`
    /// is `> 0`).
    pub firefly_k: f32,
    /// The young-history rules ([`SpvgConfig::spatial_variance`] in bits 0 to 7, 0 when
    /// off; [`SpvgConfig::age_weight`] in bit 8): see [`YOUNG_AGE_WEIGHT`].
    pub young: u32,
    /// 1 where fractional counts are on ([`SpvgConfig::fractional_floor`] is `Some`).
    pub fractional: u32,
    /// The lower bound of a real count ([`SpvgConfig::floor_f`]): the fractional floor,
    /// or `beta_min` without fractional counts.
    pub floor_f: f32,
    /// The resolved-image rule's steady resolve weight `alpha`
    /// ([`SpvgConfig::resolve_weight`]), 0 when the rule is off.
    pub resolve_weight: f32,
    /// Unused, zero (`spare_b` in WGSL).
    pub spare_b: u32,
}

/// [`Params::young`] bit: the age-aware weight ([`SpvgConfig::age_weight`]); bits 0 to 7
/// hold [`SpvgConfig::spatial_variance`] (at most `spvg::controller::young::AGE_CAP`, 255).
pub const YOUNG_AGE_WEIGHT: u32 = 256;
/// [`Params::young`] bits of [`SpvgConfig::spatial_variance`].
pub const YOUNG_SPATIAL_MASK: u32 = 255;

const _: () = assert!(
    size_of::<Params>() == 144,
    "Params must match the 144-byte WGSL struct spvg_Params"
);
const _: () = assert!(
    align_of::<Params>() == 4,
    "Params is a sequence of 4-byte scalars like spvg_Params"
);

impl Params {
    /// The parameter block of a validated controller configuration, a control model and a
    /// history storage. Infallible: every input is already validated by the core crate.
    #[must_use]
    pub fn new(config: &SpvgConfig<f32>, control: Control, storage: &Storage) -> Self {
        let w = config.weight();
        let (policy, fixed_count) = match config.policy() {
            CountPolicy::Spvg => (0, 0),
            CountPolicy::TwoPhase => (1, 0),
            CountPolicy::UnrealClamp => (2, 0),
            CountPolicy::Fixed(n) => (3, n),
        };
        let (model, ocv) = match control {
            Control::As => (0, None),
            Control::Ccv => (1, None),
            Control::Ocv(o) => (2, Some(o)),
        };
        let cv_weight = ocv.map(|o| o.weight());
        let enc = &storage.encoding;
        Self {
            eta: w.eta(),
            retain: w.retain(),
            eta_retain: w.eta_retain(),
            target_variance: config.target_variance(),
            inv_target: config.inv_target(),
            kappa: config.kappa(),
            k_minus_1: config.k_minus_1(),
            eps_u: config.eps_u(),
            min_samples_f: config.min_samples_f(),
            max_samples_f: config.max_samples_f(),
            min_samples: config.min_samples(),
            max_samples: config.max_samples(),
            policy,
            fixed_count,
            damped: u32::from(config.max_change().is_some()),
            cap_down: config.cap_down(),
            cap_up: config.cap_up(),
            model,
            f16_inputs: u32::from(ocv.is_some_and(|o| o.f16_inputs())),
            eta_cv: cv_weight.map_or(1.0, |w| w.eta()),
            retain_cv: cv_weight.map_or(0.0, |w| w.retain()),
            eta_retain_cv: cv_weight.map_or(0.0, |w| w.eta_retain()),
            eps_a: ocv.map_or(0.0, |o| o.eps_a()),
            a0: ocv.map_or(0.0, |o| o.a0()),
            texel_layout: match storage.layout {
                Layout::F16 => 0,
                Layout::F32 => 1,
            },
            rounding: match storage.rounding {
                StoreRounding::Nearest => 0,
                StoreRounding::Stochastic => 1,
            },
            var_scale: enc.variance_scale(),
            inv_var_scale: 1.0 / enc.variance_scale(),
            cv_scale: enc.cv_scale(),
            inv_cv_scale: 1.0 / enc.cv_scale(),
            firefly_k: config.firefly_clamp().unwrap_or(0.0),
            young: config.spatial_variance() | (u32::from(config.age_weight()) * YOUNG_AGE_WEIGHT),
            fractional: u32::from(config.fractional_floor().is_some()),
            floor_f: config.floor_f(),
            resolve_weight: config.resolve_weight().unwrap_or(0.0),
            spare_b: 0,
        }
    }
}
