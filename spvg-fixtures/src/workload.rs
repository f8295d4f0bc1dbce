//! The frame-update benchmarks' workload, shared by the core's `batch` bench and its
//! `frame_profile` example so that the timings and the instruction counts measure the same
//! thing: the frame of plausible inputs, and the straightforward scalar OCV loop the batch
//! code is compared with.

use spvg::cv::{Ocv, PixelController, PixelFrame};
use spvg::texel::{FrameInputs, Rounding, Texel, TexelEncoding};
use spvg::{CvHistory, SpvgHistory};

use crate::splitmix::SplitMix64;

/// `n` pixels of plausible inputs, about 2% of them disoccluded, from a fixed seed: each
/// pixel's frame, count and validity, in the order a frame buffer
/// (`spvg::texel::FrameInputsBuf::push`) takes them.
pub fn frame(n: usize) -> Vec<(PixelFrame<f32>, u32, bool)> {
    let mut rng = SplitMix64(0x2545_f491);
    let mut u = || rng.next_f64() as f32;
    let mut f = Vec::with_capacity(n);
    for _ in 0..n {
        let b = 0.5 + u();
        let radiance = b * (0.9 + 0.2 * u());
        let gamma = 0.2 + 0.8 * u();
        let count = 8 + (u() * 56.0) as u32;
        let valid = u() > 0.02;
        let pixel = PixelFrame {
            radiance,
            preintegrated: b,
            gamma,
        };
        f.push((pixel, count, valid));
    }
    f
}

/// The straightforward scalar OCV frame update: per texel decode, the per-pixel
/// controller in f32, per value encode with round-to-nearest.
pub fn scalar_frame_ocv<T, C>(
    pixel: &PixelController<f32, Ocv<f32>>,
    enc: &TexelEncoding,
    frame: &FrameInputs<'_>,
    history: &mut [T],
    cv: &mut [C],
) where
    T: Texel<History = SpvgHistory<f32>>,
    C: Texel<History = CvHistory<f32>>,
{
    for i in 0..history.len() {
        let mut h = enc.decode(history[i]);
        let mut j = enc.decode(cv[i]);
        let f = PixelFrame {
            radiance: frame.radiance[i],
            preintegrated: frame.preintegrated[i],
            gamma: frame.gamma[i],
        };
        pixel.update(&mut h, &mut j, f, frame.count[i], frame.valid[i] != 0);
        history[i] = enc.encode(&h, Rounding::Nearest);
        cv[i] = enc.encode(&j, Rounding::Nearest);
    }
}
