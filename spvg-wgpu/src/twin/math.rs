//! CPU twins of the WGSL the pass calls: the library functions (`spvg_shaders::WGSL`) are
//! the core crate's own (sequences, Burley sampling, ratio estimator, controller, online
//! CV, texel encodings; `spvg-shaders/tests/equality.rs` holds them equal function by
//! function), and what the core crate does not have (the polynomial direction of
//! `shaders/shared/direction.wgsl`) is implemented here with the same op order.

use half::f16;
use spvg::burley::BurleyProfile;
use spvg::cv::{As, Ccv, ControlModel, CvHistory, Ocv};
use spvg::texel::{CvTexel16, Rounding, SpvgTexel16, TexelEncoding, to_f16};
use spvg::{Error, SpvgConfig, SpvgHistory};

use crate::params::PassParams;

pub use spvg::sequence::{R2_STEP, pcg3d16, r2_offset_from_seed, r2_point, to_unit_f32};

/// Everything the twin derives from the uniform block once per frame: the core crate's
/// controller, online CV and Burley profiles, built from the same f32 values the shader
/// reads.
#[derive(Clone, Copy, Debug)]
pub struct Twin {
    /// The uniform block.
    pub params: PassParams,
    /// Controller (`SpvgConfig`, Spvg policy).
    pub spvg: SpvgConfig<f32>,
    /// Online control variate.
    pub ocv: Ocv<f32>,
    /// Per-channel profiles (albedo 1: it cancels in the ratio estimator).
    pub profiles: [BurleyProfile<f32>; 3],
    /// Sampling profile (the widest channel).
    pub sampling: BurleyProfile<f32>,
    /// History texel encoding, from the block's `var_scale` and `cv_scale`.
    pub enc: TexelEncoding,
}

impl Twin {
    /// Builds the core-crate objects from the uniform block.
    ///
    /// # Errors
    ///
    /// A field that the core crate rejects.
    pub fn new(p: &PassParams) -> Result<Self, Error> {
        let l = &p.spvg;
        let spvg = SpvgConfig::builder()
            .eta(l.eta)
            .target_variance(l.target_variance)
            .kappa(l.kappa)
            .budget(l.min_samples, l.max_samples)
            .eps_u(l.eps_u)
            .build()?;
        // Without OCV the block holds eta_cv = 1, eps_a = 0, a0 = 0: valid, and unused.
        let ocv = Ocv::new(l.eta_cv, l.eps_a, l.a0)?;
        Ok(Self {
            params: *p,
            spvg,
            // The J texel is f16, so fbar and G enter the EMCM at f16 precision (the
            // library's `spvg_update_cv` rounds them the same way, `f16_inputs = 1`).
            ocv: ocv.with_f16_inputs(l.f16_inputs != 0),
            profiles: [
                BurleyProfile::from_shape(1.0, p.d_r)?,
                BurleyProfile::from_shape(1.0, p.d_g)?,
                BurleyProfile::from_shape(1.0, p.d_b)?,
            ],
            sampling: BurleyProfile::from_shape(1.0, p.d_s)?,
            // The scales the shader reads from the block (fixed per run under a moving
            // target, `PassConfig::encoding_target`): powers of two, so rebuilding the
            // encoding from them is exact.
            enc: TexelEncoding::new(l.var_scale)?.with_cv_scale(l.cv_scale)?,
        })
    }

    /// The constant coefficient of the AS and CCV models (`spvg_cv_coefficient` with
    /// `model` 0 or 1): `As` gives 0, `Ccv` 1.
    #[must_use]
    pub fn constant_alpha(&self, f: f32, g: f32) -> f32 {
        if self.params.spvg.model == 1 {
            Ccv.coefficient(&(), f, g)
        } else {
            As.coefficient(&(), f, g)
        }
    }
}

/// WGSL twin: `unit_dir`: unit vector at angle `2 pi x / 2^32` by quadrant and Taylor
/// polynomials (same op order as the WGSL; the built-in sin/cos differ between drivers:
/// Vulkan allows an absolute error of 2^-11).
#[inline]
#[must_use]
pub fn unit_dir(x: u32) -> [f32; 2] {
    let t = ((x >> 6) & 0x00ff_ffff) as f32 * (1.0 / 16_777_216.0) * core::f32::consts::FRAC_PI_2;
    let t2 = t * t;
    let s = t
        * (1.0
            + t2 * (-1.0 / 6.0
                + t2 * (1.0 / 120.0
                    + t2 * (-1.0 / 5040.0 + t2 * (1.0 / 362_880.0 + t2 * (-1.0 / 39_916_800.0))))));
    let c = 1.0
        + t2 * (-0.5
            + t2 * (1.0 / 24.0
                + t2 * (-1.0 / 720.0
                    + t2 * (1.0 / 40320.0
                        + t2 * (-1.0 / 3_628_800.0 + t2 * (1.0 / 479_001_600.0))))));
    match x >> 30 {
        0 => [c, s],
        1 => [-s, c],
        2 => [-c, -s],
        _ => [s, -c],
    }
}

/// Largest finite f16.
pub const F16_MAX: f32 = 65504.0;

/// WGSL twin: `spvg_to_f16` (nearest) on every channel, what every rgba16float store
/// receives: `spvg::texel::to_f16` (NaN to 0, clamped to the f16 range, rounded to
/// nearest even; the shader rounds explicitly because lavapipe's own store conversion
/// truncates).
#[inline]
#[must_use]
pub fn to_texel(t: [f32; 4]) -> [f16; 4] {
    t.map(|x| to_f16(x, Rounding::Nearest))
}

/// Reads an rgba16float texel.
#[inline]
#[must_use]
pub fn from_texel(t: [f16; 4]) -> [f32; 4] {
    t.map(f16::to_f32)
}

/// The H texel (`spvg::texel::SpvgTexel16`, spare channel = validity flag) decoded to the
/// core crate's history, and the flag.
#[inline]
#[must_use]
pub fn decode_history(tw: &Twin, h: [f32; 4]) -> (SpvgHistory<f32>, bool) {
    let t = to_texel(h);
    (tw.enc.decode(SpvgTexel16(t)), h[3] >= 0.5)
}

/// WGSL twin: `ctl_estimate` in `shaders/adaptive/adaptive.wgsl` (`spvg_estimate_count` on
/// `spvg_decode_history`):
/// `SpvgConfig::estimate_with_validity` on the decoded texel.
#[inline]
#[must_use]
pub fn estimate_count(tw: &Twin, h: [f32; 4], gamma_s: f32) -> u32 {
    let (hist, valid) = decode_history(tw, h);
    tw.spvg.estimate_with_validity(&hist, gamma_s, valid)
}

/// WGSL twin: `ctl_update` in `adaptive.wgsl` (`spvg_update_history`, then
/// `spvg_encode_history`):
/// `SpvgConfig::update`, then `TexelEncoding::encode`
/// (round to nearest) with the validity flag in the spare channel.
#[must_use]
pub fn update_history(tw: &Twin, h: [f32; 4], s: f32, n: u32) -> [f32; 4] {
    let (mut hist, valid) = decode_history(tw, h);
    if !valid {
        hist = SpvgHistory::default();
    }
    let updated = tw.spvg.update(&mut hist, s, n, valid);
    if !updated {
        return if valid { h } else { [0.0; 4] };
    }
    let SpvgTexel16(t) = tw.enc.encode(&hist, Rounding::Nearest);
    [t[0].to_f32(), t[1].to_f32(), t[2].to_f32(), 1.0]
}

fn cv_state(tw: &Twin, j: [f32; 4]) -> CvHistory<f32> {
    tw.enc.decode(CvTexel16(to_texel(j)))
}

/// WGSL twin: `ctl_alpha` in `adaptive.wgsl` (`spvg_cv_coefficient`): `Ocv::coefficient` on the decoded J (the cold state when
/// invalid).
#[inline]
#[must_use]
pub fn ocv_alpha(tw: &Twin, j: [f32; 4], valid: bool, f: f32, g: f32) -> f32 {
    let state = if valid {
        cv_state(tw, j)
    } else {
        CvHistory::default()
    };
    tw.ocv.coefficient(&state, f, g)
}

/// WGSL twin: `ctl_update_cv` in `adaptive.wgsl` (`spvg_update_cv` then `spvg_encode_cv`): `Ocv::update_state` of the f16-input model (`f` and `g` at f16
/// precision; see `Ocv::with_f16_inputs` for why), then `TexelEncoding::encode`.
#[must_use]
pub fn update_cv(tw: &Twin, j: [f32; 4], valid: bool, f_in: f32, g_in: f32) -> [f32; 4] {
    if !(f_in.is_finite() && g_in.is_finite()) {
        return if valid { j } else { [0.0; 4] };
    }
    let mut state = cv_state(tw, j);
    let _ = tw.ocv.update_state(&mut state, f_in, g_in, valid);
    let CvTexel16(t) = tw.enc.encode(&state, Rounding::Nearest);
    t.map(f16::to_f32)
}
