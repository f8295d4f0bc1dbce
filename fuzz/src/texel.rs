//! Invariants of the texel storage (`spvg::texel`): encodings, the `f16` store with
//! nearest and stochastic rounding, decoding of corrupt texels, the precision check, and
//! the whole-frame functions against the per-pixel loop they document.

use half::f16;
use spvg::controller::SpvgConfig;
use spvg::cv::{As, Ccv, Ocv, PixelController, PixelFrame};
use spvg::texel::{
    ConstantCoefficient, CvTexel16, CvTexel32, FrameInputs, FrameInputsBuf, Layout, Rounding,
    SpvgTexel16, SpvgTexel32, Texel, TexelEncoding, channel_bits, check_config_precision,
    estimate_frame, update_frame, update_frame_ocv, update_frame_ocv_range, update_frame_range,
};
use spvg::{CvHistory, SpvgHistory};

use crate::input::Input;

/// Largest finite `f16`.
const F16_MAX: f32 = 65504.0;
/// Most pixels of the frame part (more than two 64-pixel chunks).
const MAX_PIXELS: usize = 160;

/// Decodes an encoding, histories, corrupt texels and a frame, and checks:
/// - `TexelEncoding::new` / `with_cv_scale` accept exactly normal positive values within
///   about `2^+-100`, and the scales are powers of two within `sqrt 2` of them;
/// - per channel, `encode` stores `z = sanitise(x * 2^-k)` (NaN to 0, non-positive
///   variances and counts to 0, clamped to the layout's range): `f32` texels exactly;
///   `f16` with `Rounding::Nearest` within half an `f16` ulp of `z` and no farther than
///   the other neighbour, with `Rounding::Stochastic` one of the two `f16` neighbours of
///   `z`; so `decode(encode(x))` is within one `f16` rounding of `x` or saturated at
///   `+-65504 * 2^k`;
/// - `decode` of any texel bits (NaN, infinities, negative variances) is finite with
///   non-negative variances and count;
/// - `check_config_precision` never panics and rejects exactly a non-positive or
///   non-finite typical deviation;
/// - `update_frame` / `update_frame_ocv` and `estimate_frame` give bit for bit what the
///   documented per-pixel loop gives (decode, `PixelController`, encode with
///   `channel_bits(seed, i)` / `channel_bits(!seed, i)`), in `f16` and `f32`, and refuse
///   mismatched slices without writing.
///
/// Layout: a selector byte (bit 0 target variance and bit 1 CV scale from all floats,
/// bit 2 stochastic rounding, bits 3-4 the model for the frame part: AS, CCV, OCV), 8
/// bytes each of target variance, CV scale, rounding seed and typical deviation; four
/// histories (3 + 4 floats); one corrupt texel (8 bytes of `f16` bits, 16 of `f32` bits);
/// the controller's configuration bytes and the OCV parameters (see `check_controller`,
/// `check_control_variates`); then per pixel a flag byte (bit 0 valid, bit 1 `gamma` from
/// all floats), a count byte, 8 bytes each of radiance, pre-integrated lighting, `gamma`,
/// and a starting SPVG and CV history (3 + 4 floats).
///
pub fn check_texel(data: &[u8]) {
    let mut input = Input::new(data);
    let sel = input.byte();
    let target: f32 = if sel & 1 != 0 {
        input.hard()
    } else {
        positive_or(input.finite(), 1e-4)
    };
    let cv_scale: f32 = if sel & 2 != 0 {
        input.hard()
    } else {
        positive_or(input.finite(), 1e-6 * 4096.0)
    };
    let seed = input.bits() as u32;
    let rounding = if sel & 4 != 0 {
        Rounding::Stochastic(seed)
    } else {
        Rounding::Nearest
    };
    let deviation: f32 = input.hard();
    let enc = encoding(target, cv_scale);

    for _ in 0..4 {
        let h = SpvgHistory {
            mean: input.hard(),
            variance: input.hard(),
            mean_count: input.hard(),
        };
        let j = CvHistory {
            cov_fg: input.hard(),
            var_g: input.hard(),
            mean_f: input.hard(),
            mean_g: input.hard(),
        };
        if let Some(enc) = enc {
            round_trip(&enc, &h, &j, rounding);
        }
    }
    let bits16 = input.bits();
    let (b32a, b32b) = (input.bits(), input.bits());
    if let Some(enc) = enc {
        corrupt_texels(&enc, bits16, [b32a, b32b]);
    }

    let (builder, _) = crate::controller::config::<f32>(&mut input);
    let config = builder.build().unwrap_or_else(|_| SpvgConfig::published());
    let ocv = crate::control_variates::ocv::<f32>(&mut input);
    precision(&config, &ocv, deviation);
    let Some(enc) = enc else { return };
    let frame = Frame::decode(&mut input);
    match (sel >> 3) & 3 {
        0 => frame.constant(&PixelController::new(config, As), &enc, rounding),
        1 => frame.constant(&PixelController::new(config, Ccv), &enc, rounding),
        _ => frame.ocv(&PixelController::new(config, ocv), &enc, rounding),
    }
    frame.estimate(&config, &enc);
}

fn positive_or(v: f32, fallback: f32) -> f32 {
    let v = v.abs();
    if v > 0.0 { v } else { fallback }
}

/// Both scale constructors, against the documented range.
fn encoding(target: f32, cv_scale: f32) -> Option<TexelEncoding> {
    let check = |v: f32,
                 got: Result<TexelEncoding, spvg::Error>,
                 scale: fn(&TexelEncoding) -> f32| {
        // Clearly inside / outside `2^+-100` (the boundary is at 2^+-100.5).
        let inside = v.is_normal() && v > 0.0 && (-100.4..=100.4).contains(&f64::from(v).log2());
        let outside =
            !(v.is_normal() && v > 0.0 && (-100.6..=100.6).contains(&f64::from(v).log2()));
        match got {
            Ok(e) => {
                assert!(!outside, "encoding accepted {v:e}");
                let s = scale(&e);
                let ratio = f64::from(v) / f64::from(s);
                assert!(
                    s.to_bits() & 0x7f_ffff == 0
                        && (0.5_f64.sqrt() * (1.0 - 1e-6)..=2.0_f64.sqrt() * (1.0 + 1e-6))
                            .contains(&ratio),
                    "scale {s:e} for {v:e}"
                );
                Some(e)
            }
            Err(err) => {
                assert!(!inside, "encoding rejected {v:e}: {err}");
                None
            }
        }
    };
    let enc = check(
        target,
        TexelEncoding::new(target),
        TexelEncoding::variance_scale,
    )?;
    // The CV scale on its own; an invalid one keeps the default (the variance scale).
    let with = enc.with_cv_scale(cv_scale);
    Some(check(cv_scale, with, TexelEncoding::cv_scale).unwrap_or(enc))
}

/// One channel: the stored `f16` for `x` with scale `s` (stored = x * (1 / s)).
fn check_f16_channel(
    x: f32,
    inv: f32,
    non_negative: bool,
    stored: f16,
    rounding: Rounding,
    what: &str,
) {
    let mut z = x * inv;
    if z.is_nan() || (non_negative && z.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater)) {
        z = 0.0;
    }
    let z = z.clamp(-F16_MAX, F16_MAX);
    let c = stored.to_f32();
    assert!(c.is_finite(), "{what}: stored {c} for {x:e}");
    if non_negative {
        assert!(c >= 0.0, "{what}: stored {c} for {x:e}");
    }
    let (lo, hi) = neighbours(z);
    let in_pair = c == lo || c == hi;
    assert!(
        in_pair,
        "{what}: stored {c} for z {z:e}, not a neighbour ({lo}, {hi})"
    );
    if rounding == Rounding::Nearest {
        // Half an ulp: 2^-11 relative for normal f16, 2^-25 absolute below 2^-14.
        let err = (c - z).abs();
        let tol = (z.abs() * 2f32.powi(-11)).max(2f32.powi(-25));
        let other = if c == lo { hi } else { lo };
        assert!(
            err <= tol && err <= (other - z).abs(),
            "{what}: nearest of {z:e} gave {c:e} (err {err:e}, tol {tol:e})"
        );
    }
}

/// The `f16` values bracketing `z` (equal when it is representable), found by stepping
/// the magnitude bits around `half`'s nearest value.
fn neighbours(z: f32) -> (f32, f32) {
    let n = f16::from_f32(z);
    if n.to_f32() == z {
        return (z, z);
    }
    let sign = n.to_bits() & 0x8000;
    let mag = n.to_bits() & 0x7fff;
    let at = |m: u16| f16::from_bits(sign | m).to_f32();
    if n.to_f32().abs() < z.abs() {
        (at(mag), at(mag + 1))
    } else {
        (at(mag - 1), at(mag))
    }
}

/// Encode and decode one SPVG and one CV history in all four layouts.
fn round_trip(enc: &TexelEncoding, h: &SpvgHistory<f32>, j: &CvHistory<f32>, rounding: Rounding) {
    let (vs, cs) = (enc.variance_scale(), enc.cv_scale());
    let (iv, ic) = (1.0 / vs, 1.0 / cs);
    for r in [rounding, Rounding::Nearest] {
        let t: SpvgTexel16 = enc.encode(h, r);
        let [m, v, n, spare] = t.0;
        let ch = |c: u32| match r {
            Rounding::Nearest => Rounding::Nearest,
            Rounding::Stochastic(s) => Rounding::Stochastic(channel_bits(s, c)),
        };
        check_f16_channel(h.mean, 1.0, false, m, ch(0), "mean");
        check_f16_channel(h.variance, iv, true, v, ch(1), "variance");
        check_f16_channel(h.mean_count, 1.0, true, n, ch(2), "mean count");
        assert_eq!(spare.to_bits(), 0, "spare channel");
        decoded_spvg(&enc.decode(t), "SpvgTexel16");

        let t: CvTexel16 = enc.encode(j, r);
        let [c, v, f, g] = t.0;
        check_f16_channel(j.cov_fg, ic, false, c, ch(0), "cov_fg");
        check_f16_channel(j.var_g, ic, true, v, ch(1), "var_g");
        check_f16_channel(j.mean_f, 1.0, false, f, ch(2), "mean_f");
        check_f16_channel(j.mean_g, 1.0, false, g, ch(3), "mean_g");
        decoded_cv(&enc.decode(t), "CvTexel16");
    }
    // f32 texels: exact wherever the power-of-two scaling is exact.
    let exact = |x: f32, inv: f32, non_negative: bool, got: f32, what: &str| {
        let z = x * inv;
        let scaled_exact = z.is_normal() && (z * (1.0 / inv)) == x;
        if x.is_finite() && scaled_exact && (!non_negative || x > 0.0) {
            assert_eq!(
                got.to_bits(),
                x.to_bits(),
                "{what}: f32 round trip of {x:e}"
            );
        }
    };
    let t: SpvgTexel32 = enc.encode(h, rounding);
    let d = enc.decode(t);
    decoded_spvg(&d, "SpvgTexel32");
    exact(h.mean, 1.0, false, d.mean, "mean");
    exact(h.variance, iv, true, d.variance, "variance");
    exact(h.mean_count, 1.0, true, d.mean_count, "mean count");
    let t: CvTexel32 = enc.encode(j, rounding);
    let d = enc.decode(t);
    decoded_cv(&d, "CvTexel32");
    exact(j.cov_fg, ic, false, d.cov_fg, "cov_fg");
    exact(j.var_g, ic, true, d.var_g, "var_g");
    exact(j.mean_f, 1.0, false, d.mean_f, "mean_f");
    exact(j.mean_g, 1.0, false, d.mean_g, "mean_g");
}

fn decoded_spvg(h: &SpvgHistory<f32>, what: &str) {
    assert!(
        h.mean.is_finite() && h.variance.is_finite() && h.mean_count.is_finite(),
        "{what}: decoded {h:?}"
    );
    assert!(
        h.variance >= 0.0 && h.mean_count >= 0.0,
        "{what}: decoded {h:?}"
    );
}

fn decoded_cv(j: &CvHistory<f32>, what: &str) {
    assert!(
        [j.cov_fg, j.var_g, j.mean_f, j.mean_g]
            .iter()
            .all(|v| v.is_finite())
            && j.var_g >= 0.0,
        "{what}: decoded {j:?}"
    );
}

/// Arbitrary bits (NaN, infinities, negative variances) decode to sane histories.
fn corrupt_texels(enc: &TexelEncoding, b16: u64, b32: [u64; 2]) {
    let h16: [f16; 4] = core::array::from_fn(|i| f16::from_bits((b16 >> (16 * i)) as u16));
    decoded_spvg(&enc.decode(SpvgTexel16(h16)), "corrupt SpvgTexel16");
    decoded_cv(&enc.decode(CvTexel16(h16)), "corrupt CvTexel16");
    let h32: [f32; 4] =
        core::array::from_fn(|i| f32::from_bits((b32[i / 2] >> (32 * (i % 2))) as u32));
    decoded_spvg(&enc.decode(SpvgTexel32(h32)), "corrupt SpvgTexel32");
    decoded_cv(&enc.decode(CvTexel32(h32)), "corrupt CvTexel32");
}

fn precision(config: &SpvgConfig<f32>, ocv: &Ocv<f32>, deviation: f32) {
    for layout in [Layout::F16, Layout::F32] {
        for rounding in [Rounding::Nearest, Rounding::Stochastic(1)] {
            let r = check_config_precision(config, Some(ocv), layout, rounding, deviation);
            let valid = deviation.is_finite() && deviation > 0.0;
            assert_eq!(
                r.is_ok(),
                valid,
                "precision check for deviation {deviation:e}: {r:?}"
            );
        }
    }
}

/// A frame's inputs and starting histories, structure of arrays.
struct Frame {
    pixels: FrameInputsBuf,
    history: Vec<SpvgHistory<f32>>,
    cv: Vec<CvHistory<f32>>,
}

impl Frame {
    fn decode(input: &mut Input<'_>) -> Self {
        let mut f = Self {
            pixels: FrameInputsBuf::default(),
            history: vec![],
            cv: vec![],
        };
        while !input.is_empty() && f.pixels.len() < MAX_PIXELS {
            let flags = input.byte();
            let count = u32::from(input.byte());
            let radiance = input.hard();
            let preintegrated = input.hard();
            let gamma = if flags & 2 != 0 {
                input.hard()
            } else {
                input.unit(0.01)
            };
            let frame = PixelFrame {
                radiance,
                preintegrated,
                gamma,
            };
            f.pixels.push(frame, count, flags & 1 != 0);
            f.history.push(SpvgHistory {
                mean: input.hard(),
                variance: input.hard(),
                mean_count: input.hard(),
            });
            f.cv.push(CvHistory {
                cov_fg: input.hard(),
                var_g: input.hard(),
                mean_f: input.hard(),
                mean_g: input.hard(),
            });
        }
        f
    }

    fn inputs(&self) -> FrameInputs<'_> {
        self.pixels.inputs()
    }

    /// Pixel `i`'s arguments to `PixelController::update`: its frame, count and validity.
    fn pixel(&self, i: usize) -> (PixelFrame<f32>, u32, bool) {
        let f = self.inputs();
        let frame = PixelFrame {
            radiance: f.radiance[i],
            preintegrated: f.preintegrated[i],
            gamma: f.gamma[i],
        };
        (frame, f.count[i], f.valid[i] != 0)
    }

    /// Where the range checks split the frame: about a third in, off the chunk grid.
    fn cut(&self) -> usize {
        (self.history.len() / 3 + 1).min(self.history.len())
    }

    /// The inputs of pixels `start..start + len`.
    fn part(&self, start: usize, len: usize) -> FrameInputs<'_> {
        let f = self.inputs();
        let r = start..start + len;
        FrameInputs {
            radiance: &f.radiance[r.clone()],
            preintegrated: &f.preintegrated[r.clone()],
            gamma: &f.gamma[r.clone()],
            count: &f.count[r.clone()],
            valid: &f.valid[r],
        }
    }

    fn constant<M: ConstantCoefficient>(
        &self,
        pixel: &PixelController<f32, M>,
        enc: &TexelEncoding,
        rounding: Rounding,
    ) {
        self.constant_in::<M, SpvgTexel16>(pixel, enc, rounding);
        self.constant_in::<M, SpvgTexel32>(pixel, enc, rounding);
    }

    fn constant_in<M: ConstantCoefficient, H: Texel<History = SpvgHistory<f32>>>(
        &self,
        pixel: &PixelController<f32, M>,
        enc: &TexelEncoding,
        rounding: Rounding,
    ) {
        let start: Vec<H> = self
            .history
            .iter()
            .map(|h| enc.encode(h, rounding))
            .collect();
        let mut want = start.clone();
        for i in 0..start.len() {
            let mut h = enc.decode(start[i]);
            let (frame, count, valid) = self.pixel(i);
            pixel.update(&mut h, &mut (), frame, count, valid);
            want[i] = enc.encode(&h, pixel_rounding(rounding, i, false));
        }
        let mut got = start.clone();
        let r = update_frame(pixel, enc, rounding, &self.inputs(), &mut got);
        assert!(r.is_ok(), "update_frame: {r:?}");
        same_texels(&got, &want, "update_frame");
        // The range form on a split at an odd point, the later range first.
        let mut ranged = start.clone();
        let (a, b) = ranged.split_at_mut(self.cut());
        let r = update_frame_range(
            pixel,
            enc,
            rounding,
            a.len(),
            &self.part(a.len(), b.len()),
            b,
        );
        assert!(r.is_ok(), "update_frame_range: {r:?}");
        let r = update_frame_range(pixel, enc, rounding, 0, &self.part(0, a.len()), a);
        assert!(r.is_ok(), "update_frame_range: {r:?}");
        same_texels(&ranged, &want, "update_frame_range");
        if let Some((_, short)) = self.inputs().count.split_last() {
            let mut untouched = start.clone();
            let bad = FrameInputs {
                count: short,
                ..self.inputs()
            };
            assert!(
                update_frame(pixel, enc, rounding, &bad, &mut untouched).is_err(),
                "short slice accepted"
            );
            same_texels(&untouched, &start, "update_frame refused but wrote");
        }
    }

    fn ocv(&self, pixel: &PixelController<f32, Ocv<f32>>, enc: &TexelEncoding, rounding: Rounding) {
        self.ocv_in::<SpvgTexel16, CvTexel16>(pixel, enc, rounding);
        self.ocv_in::<SpvgTexel32, CvTexel32>(pixel, enc, rounding);
    }

    fn ocv_in<H, C>(
        &self,
        pixel: &PixelController<f32, Ocv<f32>>,
        enc: &TexelEncoding,
        rounding: Rounding,
    ) where
        H: Texel<History = SpvgHistory<f32>>,
        C: Texel<History = CvHistory<f32>>,
    {
        let h0: Vec<H> = self
            .history
            .iter()
            .map(|h| enc.encode(h, rounding))
            .collect();
        let j0: Vec<C> = self.cv.iter().map(|j| enc.encode(j, rounding)).collect();
        let mut want_h = h0.clone();
        let mut want_j = j0.clone();
        for i in 0..h0.len() {
            let mut h = enc.decode(h0[i]);
            let mut j = enc.decode(j0[i]);
            let (frame, count, valid) = self.pixel(i);
            pixel.update(&mut h, &mut j, frame, count, valid);
            want_h[i] = enc.encode(&h, pixel_rounding(rounding, i, false));
            want_j[i] = enc.encode(&j, pixel_rounding(rounding, i, true));
        }
        let (mut h, mut j) = (h0.clone(), j0.clone());
        let r = update_frame_ocv(pixel, enc, rounding, &self.inputs(), &mut h, &mut j);
        assert!(r.is_ok(), "update_frame_ocv: {r:?}");
        same_texels(&h, &want_h, "update_frame_ocv history");
        same_texels(&j, &want_j, "update_frame_ocv cv");
        let (mut h, mut j) = (h0.clone(), j0.clone());
        let cut = self.cut();
        let ((ha, hb), (ja, jb)) = (h.split_at_mut(cut), j.split_at_mut(cut));
        let later = self.part(cut, hb.len());
        let r = update_frame_ocv_range(pixel, enc, rounding, cut, &later, hb, jb);
        assert!(r.is_ok(), "update_frame_ocv_range: {r:?}");
        let r = update_frame_ocv_range(pixel, enc, rounding, 0, &self.part(0, cut), ha, ja);
        assert!(r.is_ok(), "update_frame_ocv_range: {r:?}");
        same_texels(&h, &want_h, "update_frame_ocv_range history");
        same_texels(&j, &want_j, "update_frame_ocv_range cv");
        if !j0.is_empty() {
            let (mut h, mut j) = (h0.clone(), j0[1..].to_vec());
            let r = update_frame_ocv(pixel, enc, rounding, &self.inputs(), &mut h, &mut j);
            assert!(r.is_err(), "short cv slice accepted");
            same_texels(&h, &h0, "update_frame_ocv refused but wrote");
        }
    }

    fn estimate(&self, config: &SpvgConfig<f32>, enc: &TexelEncoding) {
        self.estimate_in::<SpvgTexel16>(config, enc);
        self.estimate_in::<SpvgTexel32>(config, enc);
    }

    fn estimate_in<H: Texel<History = SpvgHistory<f32>>>(
        &self,
        config: &SpvgConfig<f32>,
        enc: &TexelEncoding,
    ) {
        let texels: Vec<H> = self
            .history
            .iter()
            .map(|h| enc.encode(h, Rounding::Nearest))
            .collect();
        let mut counts = vec![u32::MAX; texels.len()];
        let FrameInputs { gamma, valid, .. } = self.inputs();
        let r = estimate_frame(config, enc, &texels, gamma, valid, &mut counts);
        assert!(r.is_ok(), "estimate_frame: {r:?}");
        for (i, (t, &n)) in texels.iter().zip(&counts).enumerate() {
            let h = enc.decode(*t);
            let want = config.estimate_with_validity(&h, gamma[i], valid[i] != 0);
            assert_eq!(
                n,
                want,
                "estimate_frame pixel {i}: {:?}, gamma {}",
                enc.decode(*t),
                gamma[i]
            );
        }
        if !texels.is_empty() {
            let mut short = vec![0_u32; texels.len() - 1];
            let r = estimate_frame(config, enc, &texels, gamma, valid, &mut short);
            assert!(r.is_err(), "short counts accepted");
        }
    }
}

/// The rounding of pixel `i` in the frame functions (CV texels use `!seed`).
fn pixel_rounding(rounding: Rounding, i: usize, cv: bool) -> Rounding {
    match rounding {
        Rounding::Nearest => Rounding::Nearest,
        Rounding::Stochastic(s) => {
            Rounding::Stochastic(channel_bits(if cv { !s } else { s }, i as u32))
        }
    }
}

fn same_texels<H: Texel>(got: &[H], want: &[H], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            bytemuck::bytes_of(g) == bytemuck::bytes_of(w),
            "{what}: pixel {i}: {g:?} != per-pixel loop {w:?}"
        );
    }
}
