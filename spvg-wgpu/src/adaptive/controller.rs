//! The controller as the component's WGSL calls it, on the CPU: [`Controller`] decodes the
//! library's parameter block ([`spvg_shaders::Params`]) back into the core crate's
//! objects (the one place that does), and one function per `ctl_*` wrapper of
//! `shaders/adaptive/adaptive.wgsl` runs the core crate's rule on a texel. The component's
//! twin ([`AdaptiveTwin`](super::AdaptiveTwin)) and the consumers' twins build on them.

use half::f16;
use spvg::controller::young::{SpatialMoments, read_age};
use spvg::cv::{As, Ccv, ControlModel, CvHistory, Ocv};
use spvg::texel::{CvTexel16, Rounding, SpvgTexel16, TexelEncoding, to_f16};
use spvg::{Error, SpvgConfig, SpvgHistory};
use spvg_shaders::{Control, Params, YOUNG_AGE_WEIGHT, YOUNG_SPATIAL_MASK};

/// The core crate's controller, online CV and texel encoding, built from the same `f32`
/// values a shader reads in its [`Params`] block.
#[derive(Clone, Copy, Debug)]
pub struct Controller {
    /// The block it was decoded from.
    pub block: Params,
    /// Controller (`SpvgConfig`, Spvg policy) at the block's target variance.
    pub spvg: SpvgConfig<f32>,
    /// Online control variate (valid and unused without OCV: the block then holds
    /// `eta_cv = 1`, `eps_a = 0`, `a0 = 0`), with the block's `f16_inputs`.
    pub ocv: Ocv<f32>,
    /// History texel encoding, from the block's `var_scale` and `cv_scale`.
    pub enc: TexelEncoding,
}

impl Controller {
    /// Decodes `block`: the controller settings (`eta`, target, `kappa`, budget, `eps_u`,
    /// the firefly clamp's `k`, the young-history rules; the count policy is SPVG's), the online CV and the texel
    /// scales.
    ///
    /// # Errors
    ///
    /// A field that the core crate rejects.
    pub fn new(block: &Params) -> Result<Self, Error> {
        let spvg = SpvgConfig::builder()
            .eta(block.eta)
            .target_variance(block.target_variance)
            .kappa(block.kappa)
            .budget(block.min_samples, block.max_samples)
            .eps_u(block.eps_u)
            // 0 is the clamp off (a valid k is > 0).
            .firefly_clamp((block.firefly_k > 0.0).then_some(block.firefly_k))
            .age_weight(block.young & YOUNG_AGE_WEIGHT != 0)
            .spatial_variance(block.young & YOUNG_SPATIAL_MASK)
            .build()?;
        let ocv = Ocv::new(block.eta_cv, block.eps_a, block.a0)?;
        Ok(Self {
            block: *block,
            spvg,
            // The J texel is f16, so fbar and G enter the EMCM at f16 precision (the
            // library's `spvg_update_cv` rounds them the same way, `f16_inputs = 1`).
            ocv: ocv.with_f16_inputs(block.f16_inputs != 0),
            // Powers of two (fixed per run under a moving target), so rebuilding the
            // encoding from them is exact.
            enc: TexelEncoding::new(block.var_scale)?.with_cv_scale(block.cv_scale)?,
        })
    }

    /// The block's control model (`model` 0, 1, 2), OCV with the block's parameters as
    /// given to [`Params::new`] (before the component's f16 inputs).
    #[must_use]
    pub fn control(&self) -> Control {
        match self.block.model {
            0 => Control::As,
            1 => Control::Ccv,
            _ => Control::Ocv(self.ocv.with_f16_inputs(false)),
        }
    }

    /// The controller with its target at the block's variance scale (a power of two, its
    /// own nearest): an [`AdaptivePass`](super::AdaptivePass) built with it stores the
    /// variance exactly as the block says, whatever the frame's target.
    ///
    /// # Errors
    ///
    /// As [`SpvgConfig::builder`]'s `build` (not for a block `new` accepted).
    pub fn at_encoding_scale(&self) -> Result<SpvgConfig<f32>, Error> {
        self.spvg
            .to_builder()
            .target_variance(self.block.var_scale)
            .build()
    }

    /// The constant coefficient of the AS and CCV models (`spvg_cv_coefficient` with
    /// `model` 0 or 1): `As` gives 0, `Ccv` 1.
    #[must_use]
    pub fn constant_alpha(&self, f: f32, g: f32) -> f32 {
        if self.block.model == 1 {
            Ccv.coefficient(&(), f, g)
        } else {
            As.coefficient(&(), f, g)
        }
    }
}

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

/// The H texel (`spvg::texel::SpvgTexel16`, spare channel = written flag) decoded to the
/// core crate's history, and the flag.
#[inline]
#[must_use]
pub fn decode_history(c: &Controller, h: [f32; 4]) -> (SpvgHistory<f32>, bool) {
    let t = to_texel(h);
    (c.enc.decode(SpvgTexel16(t)), h[3] >= 0.5)
}

/// WGSL twin: `ctl_estimate` in `shaders/adaptive/adaptive.wgsl` (`spvg_estimate_count`
/// on `spvg_decode_history`): `SpvgConfig::estimate_with_validity` on the decoded texel.
#[inline]
#[must_use]
pub fn estimate_count(c: &Controller, h: [f32; 4], gamma_s: f32) -> u32 {
    let (hist, valid) = decode_history(c, h);
    c.spvg.estimate_with_validity(&hist, gamma_s, valid)
}

/// WGSL twin: `ctl_update` in `adaptive.wgsl` (`spvg_update_history`, then
/// `spvg_encode_history`): `SpvgConfig::update`, then `TexelEncoding::encode` (round to
/// nearest) with the written flag in the spare channel.
#[must_use]
pub fn update_history(c: &Controller, h: [f32; 4], s: f32, n: u32) -> [f32; 4] {
    update_history_guided(c, h, s, None, n)
}

/// WGSL twin: `ctl_update` in `adaptive.wgsl` with or without the guide bound
/// (`spvg_update_history_texel_guided` / `spvg_update_history_texel`):
/// `SpvgConfig::update_guided` with `Some(guide)`, [`update_history`] with `None`.
#[must_use]
pub fn update_history_guided(
    c: &Controller,
    h: [f32; 4],
    s: f32,
    guide: Option<f32>,
    n: u32,
) -> [f32; 4] {
    let (mut hist, valid) = decode_history(c, h);
    if !valid {
        hist = SpvgHistory::default();
    }
    let updated = match guide {
        Some(g) => c.spvg.update_guided(&mut hist, s, g, n, valid),
        None => c.spvg.update(&mut hist, s, n, valid),
    };
    if !updated {
        return if valid { h } else { [0.0; 4] };
    }
    let SpvgTexel16(t) = c.enc.encode(&hist, Rounding::Nearest);
    [t[0].to_f32(), t[1].to_f32(), t[2].to_f32(), 1.0]
}

/// WGSL twin: `spvg_update_young_texel` / `spvg_update_young_texel_guided` (the
/// component's `ctl_update` in `adaptive.wgsl`, without and with the guide bound):
/// `SpvgConfig::update_young_guided` on the decoded texel (a `None` guide is the unguided
/// `SpvgConfig::update_young`), its age read from the spare channel
/// (`spvg::controller::young::read_age`; age >= 1 is the written mark), with the spatial
/// variance of `spatial`, then `TexelEncoding::encode` (round to nearest) with the new age
/// in the spare channel. A refused frame keeps a valid texel and clears an invalid one.
#[must_use]
pub fn update_history_young(
    c: &Controller,
    h: [f32; 4],
    s: f32,
    guide: Option<f32>,
    n: u32,
    spatial: &SpatialMoments<f32>,
) -> [f32; 4] {
    let (mut hist, valid) = decode_history(c, h);
    if !valid {
        hist = SpvgHistory::default();
    }
    let mut age = read_age(h[3]);
    let variance = spatial.variance();
    let updated = match guide {
        Some(g) => c
            .spvg
            .update_young_guided(&mut hist, &mut age, s, g, n, valid, variance),
        None => c
            .spvg
            .update_young(&mut hist, &mut age, s, n, valid, variance),
    };
    if !updated {
        return if valid { h } else { [0.0; 4] };
    }
    let SpvgTexel16(t) = c.enc.encode(&hist, Rounding::Nearest);
    // Ages up to the cap (255) are exact in f16.
    [t[0].to_f32(), t[1].to_f32(), t[2].to_f32(), age as f32]
}

fn cv_state(c: &Controller, j: [f32; 4]) -> CvHistory<f32> {
    c.enc.decode(CvTexel16(to_texel(j)))
}

/// WGSL twin: `ctl_alpha` in `adaptive.wgsl` (`spvg_cv_coefficient`): `Ocv::coefficient`
/// on the decoded J (the cold state when invalid).
#[inline]
#[must_use]
pub fn ocv_alpha(c: &Controller, j: [f32; 4], valid: bool, f: f32, g: f32) -> f32 {
    let state = if valid {
        cv_state(c, j)
    } else {
        CvHistory::default()
    };
    c.ocv.coefficient(&state, f, g)
}

/// WGSL twin: `ctl_update_cv` in `adaptive.wgsl` (`spvg_update_cv` then `spvg_encode_cv`):
/// `Ocv::update_state` of the f16-input model (`f` and `g` at f16 precision; see
/// `Ocv::with_f16_inputs` for why), then `TexelEncoding::encode`.
#[must_use]
pub fn update_cv(c: &Controller, j: [f32; 4], valid: bool, f_in: f32, g_in: f32) -> [f32; 4] {
    if !(f_in.is_finite() && g_in.is_finite()) {
        return if valid { j } else { [0.0; 4] };
    }
    let mut state = cv_state(c, j);
    let _ = c.ocv.update_state(&mut state, f_in, g_in, valid);
    let CvTexel16(t) = c.enc.encode(&state, Rounding::Nearest);
    t.map(f16::to_f32)
}
