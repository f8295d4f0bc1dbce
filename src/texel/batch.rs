//! Whole-frame updates and count estimates over texel slices.
//!
//! The frame functions compute exactly what a per-pixel loop computes:
//! `h = enc.decode(texel)`, [`PixelController::update`] (or
//! [`PixelController::count`]) on `h` in `f32`, `texel = enc.encode(&h, rounding_i)`, with
//! `rounding_i = Rounding::Stochastic(channel_bits(seed, i))` for pixel `i` under
//! `Rounding::Stochastic(seed)`. They are written for the compiler to vectorise: pixels go
//! in chunks of 64, texels are widened to `f32` and transposed in bulk (the chunk
//! primitives of `texel::dispatch`), every branch of the per-pixel rules is computed and picked
//! with selects, and uniform parameters are hoisted out of the loop.
//!
//! The per-pixel rules are not written here: the lanes call the same
//! `#[inline(always)]` functions as the per-pixel API ([`crate::controller::rules`],
//! [`crate::cv::rules`], [`crate::stats::rules`]), so the two cannot drift apart.
//!
//! # Getting the speed
//!
//! A plain `cargo build --release` of a dependent crate is portable (x86-64 baseline:
//! SSE2) and still runs fast code; `BENCHMARKS.md` at the repository root has the
//! measured figures.
//!
//! - **Run-time dispatch** (feature `std`, x86-64): the chunk loops are compiled twice
//!   more, for AVX2/FMA/F16C and for AVX-512 F/BW/VL, and the frame functions take the
//!   highest variant the CPU has (detected once; [`selected_loop_variant`] says which).
//!   The portable build therefore runs 8-wide (or wider) lanes and F16C conversions
//!   without `-C target-cpu=native`; the results are bit-identical (no operation is
//!   fused or reordered). aarch64 runs its baseline NEON loop; `no_std` builds run the
//!   loop as compiled.
//! - **F16C for `f16` texels.** The `f16` chunk loads and stores convert 8 values per
//!   F16C instruction inlined into the AVX2 and AVX-512 loops (and wherever F16C is
//!   compiled in); elsewhere a branch-free conversion that vectorises with SSE2 or NEON.
//!   Both are bit-identical to `half::f16::{to_f32, from_f32}`.
//! - **`-C target-cpu=native`** (or `-C target-feature=+avx2,+fma,+f16c` for a known
//!   fleet) runs the same loop without the detection (and lets the compiler tune it
//!   for the CPU); with dispatch the gain over the portable build is small. The crate sets
//!   no flags (a committed `target-cpu` would make binaries crash on older CPUs).
//! - **Threads** for large frames: [`update_frame_parallel`] and
//!   [`update_frame_ocv_parallel`] (feature `std`, scoped threads, capped at the cores and
//!   the work), the `rayon` feature's `update_frame_rayon` / `update_frame_ocv_rayon`, or
//!   any job system through the range form [`update_frame_range`] /
//!   [`update_frame_ocv_range`] (first pixel index plus sub-slices). All give the serial
//!   functions' bits exactly, stochastic rounding included.
//!
//! [`selected_loop_variant`]: super::selected_loop_variant
//! [`update_frame_parallel`]: super::update_frame_parallel
//! [`update_frame_ocv_parallel`]: super::update_frame_ocv_parallel
//! [`update_frame_range`]: super::update_frame_range
//! [`update_frame_ocv_range`]: super::update_frame_ocv_range

use super::channels::{Scales, load_lane, store_lane};
use super::chunk::Chunked;
use super::dispatch::{self, BASELINE, Isa};
use super::encoding::{CHUNK, Texel, TexelEncoding, channels, channels_mut};
pub use super::inputs::FrameInputs;
use super::inputs::{PaddedLanes, fill, mismatch};
use super::rounding::Rounding;
use crate::controller::CountPolicy;
use crate::controller::rules::{self, Budget, EstimateUniforms, UpdateUniforms};
use crate::cv::rules as cv_rules;
use crate::cv::{As, Ccv, ControlModel, Ocv, PixelController};
use crate::stats::Weight;
use crate::{CvHistory, Error, SpvgConfig, SpvgHistory};

/// A model whose coefficient is a constant: [`As`] (0) and [`Ccv`] (1).
pub trait ConstantCoefficient: ControlModel<f32, State = ()> + Copy {
    /// The coefficient `alpha`.
    const ALPHA: f32;
}

impl ConstantCoefficient for As {
    const ALPHA: f32 = 0.0;
}

impl ConstantCoefficient for Ccv {
    const ALPHA: f32 = 1.0;
}

/// `Ocv::update_inputs` with f16 inputs on a chunk of lanes, in `f32`: each value
/// becomes the nearest `f16` (ties to even) of it clamped to `+-65504`, the value
/// `half::f16::from_f32(..).to_f32()` gives, sign of zero included; NaN passes through.
/// Through the chunk conversions of the loop's instruction set, 8 values per F16C
/// instruction in the AVX2 loop; a call into `half` per value made the f16 OCV frame
/// update 2.5x slower, and a branch-free conversion per lane was a fifth of the AVX2
/// loop's time.
#[inline(always)]
fn round_to_f16<I: Isa>(isa: I, v: &[f32; CHUNK]) -> [f32; CHUNK] {
    let mut clamped = [0.0_f32; CHUNK];
    for (c, &x) in clamped.iter_mut().zip(v) {
        // NaN to 0 for the conversion (its result is replaced below).
        *c = if x.is_nan() {
            0.0
        } else {
            x.clamp(-65504.0, 65504.0)
        };
    }
    let mut bits = [0_u16; CHUNK];
    isa.narrow(&clamped, &mut bits);
    let mut out = [0.0_f32; CHUNK];
    isa.widen(&bits, &mut out);
    for (o, &x) in out.iter_mut().zip(v) {
        // A select, not a conditional store (a masked store is slow on some CPUs).
        *o = if x.is_nan() { x } else { *o };
    }
    out
}

/// One pixel of `SpvgConfig::update` on a decoded history (decoded values are already
/// what the update's defensive read gives): the controller's rule, branch-free. Returns
/// the new `(mean, variance, mean_count)` and whether the frame was accepted.
#[inline(always)]
fn spvg_lane(
    u: &UpdateUniforms<f32>,
    h: [f32; 3],
    s: f32,
    count: u32,
    valid: bool,
) -> ([f32; 3], bool) {
    let [mean, variance, mean_count] = h;
    let h = SpvgHistory {
        mean,
        variance,
        mean_count,
    };
    let (h1, accepted) = rules::update(u, h, h, s, count, valid);
    ([h1.mean, h1.variance, h1.mean_count], accepted)
}

/// Decodes lane `i` of a chunk of SPVG texels into `(mean, variance, mean_count)`.
#[inline(always)]
fn decode_spvg<H: Texel>(raw: &[[f32; CHUNK]; 4], i: usize, scales: &Scales) -> [f32; 3] {
    let [m, v, nb, _] = load_lane::<H::Element, SpvgHistory<f32>>(raw, i, scales);
    [m, v, nb]
}

#[inline(always)]
fn encode_spvg<H: Texel>(out: &mut [[f32; CHUNK]; 4], i: usize, h: [f32; 3], scales: &Scales) {
    let [m, v, nb] = h;
    store_lane::<H::Element, SpvgHistory<f32>>(out, i, [m, v, nb, 0.0], scales);
}

/// Updates a frame of SPVG histories under a constant-coefficient model ([`As`] or
/// [`Ccv`]): the same result, bit for bit, as decoding each texel, calling
/// [`PixelController::update`] and encoding it again (see the module docs).
///
/// # Errors
///
/// [`Error::InconsistentParameters`] when a slice of `inputs` differs in length from
/// `history`; nothing is written then.
///
/// # Examples
///
/// ```
/// use spvg::cv::{Ccv, PixelController};
/// use spvg::texel::{FrameInputs, Rounding, SpvgTexel16, TexelEncoding, update_frame};
/// use spvg::SpvgConfig;
/// let config = SpvgConfig::<f32>::published();
/// let pixel = PixelController::new(config, Ccv);
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let mut history = vec![SpvgTexel16::default(); 3];
/// let inputs = FrameInputs {
///     radiance: &[1.0, 2.0, 3.0],
///     preintegrated: &[1.0, 1.0, 1.0],
///     gamma: &[1.0, 1.0, 1.0],
///     count: &[8, 8, 8],
///     valid: &[0, 0, 0],
/// };
/// update_frame(&pixel, &enc, Rounding::Nearest, &inputs, &mut history).unwrap();
/// // Disocclusion seed: mean = S = fbar - G = L_o - B.
/// let h = enc.decode(history[2]);
/// assert_eq!((h.mean, h.mean_count), (2.0, 8.0));
/// let short = FrameInputs { count: &[8], ..inputs };
/// assert!(update_frame(&pixel, &enc, Rounding::Nearest, &short, &mut history).is_err());
/// ```
pub fn update_frame<M: ConstantCoefficient, H: Texel<History = SpvgHistory<f32>>>(
    pixel: &PixelController<f32, M>,
    enc: &TexelEncoding,
    rounding: Rounding,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
) -> Result<(), Error> {
    super::update_frame_range(pixel, enc, rounding, 0, inputs, history)
}

/// An [`update_frame`] with its uniforms computed once, run on ranges of pixels by the
/// serial and the threaded frame functions.
#[derive(Clone, Copy)]
pub(super) struct ConstantUpdate {
    u: UpdateUniforms<f32>,
    alpha: f32,
    scales: Scales,
    rounding: Rounding,
}

impl ConstantUpdate {
    pub(super) fn new<M: ConstantCoefficient>(
        pixel: &PixelController<f32, M>,
        enc: &TexelEncoding,
        rounding: Rounding,
    ) -> Self {
        Self {
            u: UpdateUniforms::new(pixel.config()),
            alpha: M::ALPHA,
            scales: enc.scales(),
            rounding,
        }
    }

    /// Updates pixels `first..first + history.len()` of a frame, with `inputs` already
    /// cut to that range and checked: `first` only feeds the stochastic-rounding words,
    /// so a frame split into ranges gives the bits of the whole-frame call.
    pub(super) fn run<H: Texel<History = SpvgHistory<f32>>>(
        &self,
        inputs: &FrameInputs<'_>,
        history: &mut [H],
        first: usize,
    ) {
        let dispatched = dispatch::dispatched(
            #[inline(always)]
            |isa| self.run_lanes(isa, inputs, history, first),
        );
        if !dispatched {
            self.run_lanes(BASELINE, inputs, history, first);
        }
    }

    /// The chunk loop of [`run`](Self::run), inlined into each instruction-set variant
    /// that `texel::dispatch` compiles.
    #[inline(always)]
    pub(super) fn run_lanes<I: Isa, H: Texel<History = SpvgHistory<f32>>>(
        &self,
        isa: I,
        inputs: &FrameInputs<'_>,
        history: &mut [H],
        first: usize,
    ) {
        let Self {
            u,
            alpha,
            scales,
            rounding,
        } = *self;
        let mut raw = [[0.0_f32; CHUNK]; 4];
        let mut wide = [[0.0_f32; 4]; CHUNK];
        let mut out = [[0.0_f32; CHUNK]; 4];
        let mut pad = PaddedLanes::new();
        for (k, hc) in history.chunks_mut(CHUNK).enumerate() {
            let start = k * CHUNK;
            let lanes = pad.lanes(inputs, start);
            H::Element::load_chunk(isa, channels(hc), &mut wide, &mut raw);
            for i in 0..CHUNK {
                let h = decode_spvg::<H>(&raw, i, &scales);
                let (l, b, gamma) = (lanes.radiance[i], lanes.preintegrated[i], lanes.gamma[i]);
                // The PixelController's order: fbar, G, then S = fbar - alpha G, each
                // saturated when its operands are finite (finite input is never dropped).
                let (fbar, g) = cv_rules::split(l, b, gamma);
                let s = cv_rules::residual(fbar, g, alpha);
                let (h1, _) = spvg_lane(&u, h, s, lanes.count[i], lanes.valid[i] != 0);
                encode_spvg::<H>(&mut out, i, h1, &scales);
            }
            // Pixel indices wrap past 2^32 pixels (only the stochastic-rounding words
            // depend on them).
            let index = first.wrapping_add(start) as u32;
            H::Element::store_chunk(isa, &out, &mut wide, channels_mut(hc), rounding, index);
        }
    }
}

/// Uniform constants of the OCV model.
#[derive(Clone, Copy)]
struct CvConst {
    weight: Weight<f32>,
    eps_a: f32,
    a0: f32,
    /// `Ocv::f16_inputs`: round `fbar` and `G` to f16 before the state update.
    f16_inputs: bool,
}

/// Updates a frame of SPVG histories and OCV histories: the same result, bit for bit, as
/// the per-pixel loop of [`update_frame`] with [`Ocv`] and its [`CvHistory`] texels,
/// where the CV texel of pixel `i` is stored with
/// `Rounding::Stochastic(channel_bits(!seed, i))` under `Rounding::Stochastic(seed)`.
///
/// With `f16` CV texels build the model with [`Ocv::with_f16_inputs`]: without it the
/// f16 rounding of the stored mean of a constant control moves the coefficient across its
/// whole bound on static pixels (see [`Ocv`]).
///
/// # Errors
///
/// [`Error::InconsistentParameters`] when a slice of `inputs` or `cv` differs in length
/// from `history`; nothing is written then.
///
/// # Examples
///
/// ```
/// use spvg::cv::{Ocv, PixelController};
/// use spvg::texel::{CvTexel16, FrameInputs, Rounding, SpvgTexel16, TexelEncoding};
/// use spvg::texel::update_frame_ocv;
/// use spvg::SpvgConfig;
/// let config = SpvgConfig::<f32>::published();
/// // f16 CV texels: fbar and G enter the covariance update at f16 precision.
/// let ocv = Ocv::with_weight(0.05).unwrap().with_f16_inputs(true);
/// let pixel = PixelController::new(config, ocv);
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let (mut h, mut j) = (vec![SpvgTexel16::default(); 2], vec![CvTexel16::default(); 2]);
/// let inputs = FrameInputs {
///     radiance: &[1.0, 2.0],
///     preintegrated: &[1.0, 1.0],
///     gamma: &[0.5, 0.5],
///     count: &[8, 8],
///     valid: &[0, 0],
/// };
/// update_frame_ocv(&pixel, &enc, Rounding::Nearest, &inputs, &mut h, &mut j).unwrap();
/// // Disocclusion seeds the CV means with fbar = L_o - (1 - gamma) B and G = gamma B.
/// let cv = enc.decode(j[1]);
/// assert_eq!((cv.mean_f, cv.mean_g, cv.var_g), (1.5, 0.5, 0.0));
/// ```
pub fn update_frame_ocv<H, C>(
    pixel: &PixelController<f32, Ocv<f32>>,
    enc: &TexelEncoding,
    rounding: Rounding,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
    cv: &mut [C],
) -> Result<(), Error>
where
    H: Texel<History = SpvgHistory<f32>>,
    C: Texel<History = CvHistory<f32>>,
{
    super::update_frame_ocv_range(pixel, enc, rounding, 0, inputs, history, cv)
}

/// An [`update_frame_ocv`] with its uniforms computed once (see [`ConstantUpdate`]).
#[derive(Clone, Copy)]
pub(super) struct OcvUpdate {
    u: UpdateUniforms<f32>,
    k: CvConst,
    scales: Scales,
    rounding: Rounding,
    cv_rounding: Rounding,
}

impl OcvUpdate {
    pub(super) fn new(
        pixel: &PixelController<f32, Ocv<f32>>,
        enc: &TexelEncoding,
        rounding: Rounding,
    ) -> Self {
        let model = pixel.model();
        Self {
            u: UpdateUniforms::new(pixel.config()),
            k: CvConst {
                weight: model.weight(),
                eps_a: model.eps_a(),
                a0: model.a0(),
                f16_inputs: model.f16_inputs(),
            },
            scales: enc.scales(),
            rounding,
            // The CV texels draw their stochastic-rounding words from `!seed`, so that
            // they are independent of the SPVG texel's.
            cv_rounding: match rounding {
                Rounding::Nearest => Rounding::Nearest,
                Rounding::Stochastic(seed) => Rounding::Stochastic(!seed),
            },
        }
    }

    /// Updates pixels `first..first + history.len()` of a frame, with the slices already
    /// cut to that range and checked (see [`ConstantUpdate::run`]).
    pub(super) fn run<H, C>(
        &self,
        inputs: &FrameInputs<'_>,
        history: &mut [H],
        cv: &mut [C],
        first: usize,
    ) where
        H: Texel<History = SpvgHistory<f32>>,
        C: Texel<History = CvHistory<f32>>,
    {
        let dispatched = dispatch::dispatched(
            #[inline(always)]
            |isa| self.run_lanes(isa, inputs, history, cv, first),
        );
        if !dispatched {
            self.run_lanes(BASELINE, inputs, history, cv, first);
        }
    }

    /// The chunk loop of [`run`](Self::run), inlined into each instruction-set variant
    /// that `texel::dispatch` compiles.
    #[inline(always)]
    pub(super) fn run_lanes<I: Isa, H, C>(
        &self,
        isa: I,
        inputs: &FrameInputs<'_>,
        history: &mut [H],
        cv: &mut [C],
        first: usize,
    ) where
        H: Texel<History = SpvgHistory<f32>>,
        C: Texel<History = CvHistory<f32>>,
    {
        let Self {
            u,
            k,
            scales,
            rounding,
            cv_rounding,
        } = *self;
        let mut raw = [[0.0_f32; CHUNK]; 4];
        let mut wide = [[0.0_f32; 4]; CHUNK];
        let mut out = [[0.0_f32; CHUNK]; 4];
        let mut raw_cv = [[0.0_f32; CHUNK]; 4];
        let mut out_cv = [[0.0_f32; CHUNK]; 4];
        let mut pad = PaddedLanes::new();
        for (ci, (hc, jc)) in history
            .chunks_mut(CHUNK)
            .zip(cv.chunks_mut(CHUNK))
            .enumerate()
        {
            let start = ci * CHUNK;
            let lanes = pad.lanes(inputs, start);
            H::Element::load_chunk(isa, channels(hc), &mut wide, &mut raw);
            C::Element::load_chunk(isa, channels(jc), &mut wide, &mut raw_cv);
            // fbar and G of every lane, and the values the CV state update sees
            // (`Ocv::update_inputs`), rounded a chunk at a time.
            let mut fbars = [0.0_f32; CHUNK];
            let mut gs = [0.0_f32; CHUNK];
            for i in 0..CHUNK {
                let (l, b, gamma) = (lanes.radiance[i], lanes.preintegrated[i], lanes.gamma[i]);
                (fbars[i], gs[i]) = cv_rules::split(l, b, gamma);
            }
            let (state_f, state_g) = if k.f16_inputs {
                (round_to_f16(isa, &fbars), round_to_f16(isa, &gs))
            } else {
                (fbars, gs)
            };
            for i in 0..CHUNK {
                let count = lanes.count[i];
                let valid = lanes.valid[i] != 0;
                let h = decode_spvg::<H>(&raw, i, &scales);
                let old = load_lane::<C::Element, CvHistory<f32>>(&raw_cv, i, &scales);
                let [cov, var_g, mean_f, mean_g] = old;

                let (fbar, g) = (fbars[i], gs[i]);
                // Ocv::coefficient; a disoccluded pixel takes the cold (zero) state's.
                let (cov_a, var_a) = if valid { (cov, var_g) } else { (0.0, 0.0) };
                let a = cv_rules::raw_coefficient(k.eps_a, cov_a, var_a);
                let alpha = cv_rules::clamp_to_bound(k.a0, a, fbar, g);
                let s = cv_rules::residual(fbar, g, alpha);
                let (h1, accepted) = spvg_lane(&u, h, s, count, valid);
                encode_spvg::<H>(&mut out, i, h1, &scales);

                // Ocv::update_state, run only when the SPVG history accepted the frame, on
                // `fbar` and `G` at f16 precision if the model asks for it.
                let state = CvHistory {
                    cov_fg: cov,
                    var_g,
                    mean_f,
                    mean_g,
                };
                // This lane's `update_inputs(fbar, g)`, computed above.
                let round = |_: f32, _: f32| (state_f[i], state_g[i]);
                let (j, _) = cv_rules::update_state(&k.weight, &state, fbar, g, valid, round);
                let kept = if valid { old } else { [0.0; 4] };
                let j1 = if accepted {
                    [j.cov_fg, j.var_g, j.mean_f, j.mean_g]
                } else {
                    kept
                };
                store_lane::<C::Element, CvHistory<f32>>(&mut out_cv, i, j1, &scales);
            }
            let index = first.wrapping_add(start) as u32;
            H::Element::store_chunk(isa, &out, &mut wide, channels_mut(hc), rounding, index);
            C::Element::store_chunk(
                isa,
                &out_cv,
                &mut wide,
                channels_mut(jc),
                cv_rounding,
                index,
            );
        }
    }
}

/// Estimates a frame's counts: `counts[i]` is
/// [`SpvgConfig::estimate_with_validity`] of the decoded `history[i]`, `gamma[i]` and
/// `valid[i] != 0`, bit for bit.
///
/// # Errors
///
/// [`Error::InconsistentParameters`] when `gamma`, `valid` or `counts` differs in length
/// from `history`; nothing is written then.
///
/// # Examples
///
/// ```
/// use spvg::texel::{SpvgTexel32, TexelEncoding, estimate_frame};
/// use spvg::{SpvgConfig, SpvgHistory};
/// let config = SpvgConfig::<f32>::published();
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let busy = SpvgHistory { mean: 1.0, variance: 1.0, mean_count: 64.0 };
/// let history = [enc.encode::<SpvgTexel32>(&busy, spvg::texel::Rounding::Nearest); 3];
/// let mut counts = [0_u32; 3];
/// estimate_frame(&config, &enc, &history, &[1.0, 0.0, 1.0], &[1, 1, 0], &mut counts).unwrap();
/// assert_eq!(counts, [64, 0, 8]);
/// ```
pub fn estimate_frame<H: Texel<History = SpvgHistory<f32>>>(
    config: &SpvgConfig<f32>,
    enc: &TexelEncoding,
    history: &[H],
    gamma: &[f32],
    valid: &[u8],
    counts: &mut [u32],
) -> Result<(), Error> {
    let len = history.len();
    if gamma.len() != len || valid.len() != len || counts.len() != len {
        return Err(mismatch());
    }
    let estimate = Estimate::new(config, enc);
    let dispatched = dispatch::dispatched(
        #[inline(always)]
        |isa| estimate.run_lanes(isa, history, gamma, valid, counts),
    );
    if !dispatched {
        estimate.run_lanes(BASELINE, history, gamma, valid, counts);
    }
    Ok(())
}

/// An [`estimate_frame`] with its uniforms computed once.
#[derive(Clone, Copy)]
pub(super) struct Estimate {
    scales: Scales,
    uniforms: EstimateUniforms<f32>,
    budget: Budget<f32>,
    eps_u: f32,
    fixed: Option<u32>,
}

impl Estimate {
    pub(super) fn new(config: &SpvgConfig<f32>, enc: &TexelEncoding) -> Self {
        Self {
            scales: enc.scales(),
            uniforms: EstimateUniforms::new(config),
            budget: Budget::new(config),
            eps_u: config.eps_u(),
            fixed: match config.policy() {
                CountPolicy::Fixed(f) => Some(f),
                _ => None,
            },
        }
    }

    /// The chunk loop of [`estimate_frame`], on slices of one length, inlined into each
    /// instruction-set variant that `texel::dispatch` compiles.
    #[inline(always)]
    pub(super) fn run_lanes<I: Isa, H: Texel<History = SpvgHistory<f32>>>(
        &self,
        isa: I,
        history: &[H],
        gamma: &[f32],
        valid: &[u8],
        counts: &mut [u32],
    ) {
        let Self {
            scales,
            uniforms,
            budget,
            eps_u,
            fixed,
        } = *self;
        let mut raw = [[0.0_f32; CHUNK]; 4];
        let mut wide = [[0.0_f32; 4]; CHUNK];
        let mut gammas = [0.0_f32; CHUNK];
        let mut valids = [0_u8; CHUNK];
        let mut out = [0_u32; CHUNK];
        let chunks = history
            .chunks(CHUNK)
            .zip(gamma.chunks(CHUNK))
            .zip(valid.chunks(CHUNK))
            .zip(counts.chunks_mut(CHUNK));
        for (((hc, gc), vc), oc) in chunks {
            H::Element::load_chunk(isa, channels(hc), &mut wide, &mut raw);
            fill(&mut gammas, gc);
            fill(&mut valids, vc);
            for i in 0..CHUNK {
                let [_, v, nb] = decode_spvg::<H>(&raw, i, &scales);
                // An invalid history is treated as zero (estimate_with_validity).
                let ok = valids[i] != 0;
                let (v, nb) = (if ok { v } else { 0.0 }, if ok { nb } else { 0.0 });
                let n = rules::round_count(&budget, rules::raw_count(&uniforms, v, nb));
                let n = fixed.unwrap_or(n);
                out[i] = if rules::samples_distant(eps_u, gammas[i]) {
                    n
                } else {
                    0
                };
            }
            for (o, n) in oc.iter_mut().zip(&out) {
                *o = *n;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::dispatch::{BASELINE, LoopVariant, Portable, run_on};
    use super::{CHUNK, round_to_f16};
    use half::f16;
    use std::io::Write;

    fn reference(v: f32) -> f32 {
        f16::from_f32(v.clamp(-65504.0, 65504.0)).to_f32()
    }

    /// `round_to_f16` of the values, a chunk at a time, in the baseline and the portable
    /// loop and, on a CPU with their features, the AVX2 and AVX-512 loops, against `half`
    /// value by value.
    fn same(values: &[f32]) {
        for variant in [LoopVariant::Avx2, LoopVariant::Avx512] {
            if !variant.is_available() {
                // Straight to stderr: the harness captures `eprintln!`, and a skipped
                // variant must show in every run.
                let _ = writeln!(
                    std::io::stderr(),
                    "round_to_f16: the {variant} loop is skipped: this CPU lacks its \
                     features, the build compiles them in (then BASELINE is that loop), \
                     or it dispatches nothing (no `std`, not x86-64)"
                );
            }
        }
        for part in values.chunks(CHUNK) {
            let mut v = [0.0_f32; CHUNK];
            v[..part.len()].copy_from_slice(part);
            let mut got = vec![
                ("baseline", round_to_f16(BASELINE, &v)),
                ("portable", round_to_f16(Portable, &v)),
            ];
            for variant in [LoopVariant::Avx2, LoopVariant::Avx512] {
                run_on(
                    variant,
                    #[inline(always)]
                    |isa| got.push((variant.name(), round_to_f16(isa, &v))),
                );
            }
            for (loop_, out) in got {
                for (&x, &r) in v.iter().zip(&out) {
                    if x.is_nan() {
                        assert!(r.is_nan(), "{loop_}: NaN passes through, got {r:e}");
                        continue;
                    }
                    let want = reference(x);
                    assert!(
                        r.to_bits() == want.to_bits(),
                        "{loop_}: round_to_f16({x:e} = {:#x}) = {r:e}, half gives {want:e}",
                        x.to_bits()
                    );
                }
            }
        }
    }

    /// Every f16 value, the midpoints to its neighbours (the ties) and the f32 values one
    /// ulp either side of each, in both signs; beyond the f16 range; zeros; NaN.
    #[test]
    fn matches_half_on_every_f16_neighbourhood() {
        let mut values = Vec::new();
        for bits in 0..0x7BFF_u16 {
            let a = f16::from_bits(bits).to_f32();
            let b = f16::from_bits(bits + 1).to_f32();
            let mid = 0.5 * (a + b);
            for v in [
                a,
                mid,
                f32::from_bits(mid.to_bits() - 1),
                f32::from_bits(mid.to_bits() + 1),
            ] {
                values.extend([v, -v]);
            }
        }
        for v in [
            65504.0,
            65519.0,
            65520.0,
            1e6,
            f32::MAX,
            f32::INFINITY,
            0.0,
            1e-30,
            1e-45,
            f32::NAN,
        ] {
            values.extend([v, -v]);
        }
        same(&values);
    }

    /// A stride through all f32 bit patterns (both signs, every exponent).
    #[test]
    fn matches_half_on_a_stride_of_all_f32() {
        let values: Vec<f32> = (0..=u32::MAX).step_by(65_537).map(f32::from_bits).collect();
        same(&values);
    }
}
