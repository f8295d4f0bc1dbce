//! The controller as the component's WGSL calls it, on the CPU: one function per `spvg_ad_ctl_*`
//! wrapper of `component.wgsl` runs the core crate's rule on a texel, with the
//! [`Controller`] the component's block was built from. The component's twin
//! ([`AdaptiveTwin`](super::AdaptiveTwin)) builds on them.

use half::f16;
use spvg::controller::young::{SpatialMoments, read_age};
use spvg::cv::{As, Ccv, ControlModel, CvHistory, Ocv};
use spvg::texel::{CvTexel16, Rounding, SpvgTexel16, TexelEncoding, to_f16};
use spvg::{SpvgConfig, SpvgHistory};
use spvg_shaders::Control;

/// The core crate's controller, online CV and texel encoding the component's block was
/// built from ([`derive`](super::settings::derive)): the twin runs these, the GPU reads
/// the block.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Controller {
    /// Controller (`SpvgConfig`, Spvg policy) with its target as the f16 texel stores it.
    pub(crate) spvg: SpvgConfig<f32>,
    /// The control model, OCV with f16 inputs.
    pub(crate) control: Control,
    /// History texel encoding.
    pub(crate) enc: TexelEncoding,
}

impl Controller {
    pub(crate) fn new(spvg: SpvgConfig<f32>, control: Control, enc: TexelEncoding) -> Self {
        Self { spvg, control, enc }
    }

    /// The online control variate (OCV only; `None` for AS and CCV).
    fn ocv(&self) -> Option<Ocv<f32>> {
        match self.control {
            Control::Ocv(o) => Some(o),
            Control::As | Control::Ccv => None,
        }
    }

    /// The constant coefficient of the AS and CCV models (`spvg_cv_coefficient` with
    /// `model` 0 or 1): `As` gives 0, `Ccv` 1.
    pub(crate) fn constant_alpha(&self, f: f32, g: f32) -> f32 {
        if self.control == Control::Ccv {
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
pub(crate) fn to_texel(t: [f32; 4]) -> [f16; 4] {
    t.map(|x| to_f16(x, Rounding::Nearest))
}

/// Reads an rgba16float texel.
#[inline]
#[must_use]
pub(crate) fn from_texel(t: [f16; 4]) -> [f32; 4] {
    t.map(f16::to_f32)
}

/// The H texel (`spvg::texel::SpvgTexel16`, spare channel = written flag) decoded to the
/// core crate's history, and the flag.
#[inline]
#[must_use]
pub(crate) fn decode_history(c: &Controller, h: [f32; 4]) -> (SpvgHistory<f32>, bool) {
    let t = to_texel(h);
    (c.enc.decode(SpvgTexel16(t)), h[3] >= 0.5)
}

/// WGSL twin: `spvg_ad_ctl_estimate` in `component.wgsl` (`spvg_estimate_count`
/// on `spvg_decode_history`): `SpvgConfig::estimate_with_validity` on the decoded texel.
#[inline]
#[must_use]
pub(crate) fn estimate_count(c: &Controller, h: [f32; 4], gamma_s: f32) -> u32 {
    let (hist, valid) = decode_history(c, h);
    c.spvg.estimate_with_validity(&hist, gamma_s, valid)
}

/// WGSL twin: `spvg_ad_ctl_estimate_fractional` in `component.wgsl`
/// (`spvg_estimate_texel_fractional`): `SpvgConfig::estimate_resolved` on the decoded
/// texel with its age (`spvg::controller::young::read_age` of the spare channel, which
/// the resolved-image rule reads), the renderer's resolve weight `input` (NaN where it
/// gave none) and the dither threshold `xi`; the real count is -1 where the integer rule
/// decided (the value the component stores for it).
#[inline]
#[must_use]
pub(crate) fn estimate_fractional(
    c: &Controller,
    h: [f32; 4],
    gamma_s: f32,
    xi: u32,
    input: f32,
) -> (u32, f32) {
    let (hist, valid) = decode_history(c, h);
    let age = read_age(h[3]);
    let f = c
        .spvg
        .estimate_resolved(&hist, age, gamma_s, valid, xi, input);
    (f.count, f.real.unwrap_or(-1.0))
}

/// WGSL twin: `spvg_update_moment_texel` (the component's `spvg_ad_ctl_update` in
/// `component.wgsl`; the guide NaN where none is bound, the second moment `moment` NaN
/// where none is, docs/algorithms.md §8.8): `SpvgConfig::update_moment`
/// on the decoded texel (a non-finite guide is the unguided update, a negative `real` the
/// integer rule), its age read from the spare channel
/// (`spvg::controller::young::read_age`; age >= 1 is the written mark), with the spatial
/// variance of `spatial`, then `TexelEncoding::encode` (round to nearest) with the new age
/// in the spare channel. A refused frame keeps a valid texel and clears an invalid one; a
/// skipped frame of a fractional count stores the history with its new mean count.
#[must_use]
#[allow(
    clippy::too_many_arguments,
    reason = "the texel update's inputs and the second moment"
)]
pub(crate) fn update_history(
    c: &Controller,
    h: [f32; 4],
    s: f32,
    guide: Option<f32>,
    n: u32,
    real: f32,
    spatial: &SpatialMoments<f32>,
    moment: f32,
) -> [f32; 4] {
    let (mut hist, valid) = decode_history(c, h);
    if !valid {
        hist = SpvgHistory::default();
    }
    let mut age = read_age(h[3]);
    let variance = spatial.variance();
    let real = spvg::controller::fractional::is_real(real).then_some(real);
    let updated = c.spvg.update_moment(
        &mut hist,
        &mut age,
        s,
        guide.unwrap_or(f32::NAN),
        moment,
        n,
        real,
        valid,
        variance,
    );
    let skipped = valid && n == 0 && real.is_some();
    if !updated && !skipped {
        return if valid { h } else { [0.0; 4] };
    }
    let SpvgTexel16(t) = c.enc.encode(&hist, Rounding::Nearest);
    // Ages up to the cap (255) are exact in f16.
    [t[0].to_f32(), t[1].to_f32(), t[2].to_f32(), age as f32]
}

fn cv_state(c: &Controller, j: [f32; 4]) -> CvHistory<f32> {
    c.enc.decode(CvTexel16(to_texel(j)))
}

/// WGSL twin: `spvg_ad_ctl_alpha` in `component.wgsl` (`spvg_cv_coefficient`): `Ocv::coefficient`
/// on the decoded J (the cold state when invalid).
#[inline]
#[must_use]
pub(crate) fn ocv_alpha(c: &Controller, j: [f32; 4], valid: bool, f: f32, g: f32) -> f32 {
    let state = if valid {
        cv_state(c, j)
    } else {
        CvHistory::default()
    };
    c.ocv().map_or(0.0, |o| o.coefficient(&state, f, g))
}

/// WGSL twin: `spvg_ad_ctl_update_cv` in `component.wgsl` (`spvg_update_cv` then `spvg_encode_cv`):
/// `Ocv::update_state` of the f16-input model (`f` and `g` at f16 precision; see
/// `Ocv::with_f16_inputs` for why), then `TexelEncoding::encode`.
#[must_use]
pub(crate) fn update_cv(
    c: &Controller,
    j: [f32; 4],
    valid: bool,
    f_in: f32,
    g_in: f32,
) -> [f32; 4] {
    if !(f_in.is_finite() && g_in.is_finite()) {
        return if valid { j } else { [0.0; 4] };
    }
    let mut state = cv_state(c, j);
    if let Some(o) = c.ocv() {
        let _ = o.update_state(&mut state, f_in, g_in, valid);
    }
    let CvTexel16(t) = c.enc.encode(&state, Rounding::Nearest);
    t.map(f16::to_f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::adaptive::AdaptiveSettings;
    use crate::adaptive::settings::derive;

    /// The texel update the twin runs is the core crate's guided young-history update on
    /// the decoded texel, encoded back; a non-finite guide gives the unguided update.
    #[test]
    fn guided_texel_update_is_the_cores() {
        let settings = AdaptiveSettings::default();
        let c = derive(&settings, settings.config.target_variance())
            .expect("default settings")
            .controller;
        let h = [0.45_f32, 0.3, 20.0, 3.0].map(|v| f16::from_f32(v).to_f32());
        let none = SpatialMoments::default();
        for (s, g) in [
            (0.5, 0.41),
            (0.5, f32::NAN),
            (0.2, 0.9),
            (0.5, f32::INFINITY),
        ] {
            let got = update_history(&c, h, s, Some(g), 16, -1.0, &none, f32::NAN);
            let (mut hist, valid) = decode_history(&c, h);
            assert!(valid, "the texel was written");
            let mut age = read_age(h[3]);
            let updated =
                c.spvg
                    .update_young_guided(&mut hist, &mut age, s, g, 16, true, none.variance());
            assert!(updated, "a finite value is taken");
            let SpvgTexel16(t) = c.enc.encode(&hist, Rounding::Nearest);
            assert_eq!(
                got,
                [t[0].to_f32(), t[1].to_f32(), t[2].to_f32(), age as f32]
            );
            if !g.is_finite() {
                let plain = update_history(&c, h, s, None, 16, -1.0, &none, f32::NAN);
                assert_eq!(got, plain, "a non-finite guide is the unguided update");
            }
        }
    }
}
