//! The frame-update benchmarks' frame of plausible inputs, shared by `benches/batch.rs`
//! and `examples/frame_profile.rs` (each includes it with `#[path]`, next to
//! `splitmix.rs`) so that the timings and the instruction counts measure the same frame.

use spvg::cv::PixelFrame;
use spvg::texel::FrameInputsBuf;

use crate::splitmix::SplitMix64;

/// `n` pixels of plausible inputs, about 2% of them disoccluded, from a fixed seed.
pub(crate) fn frame(n: usize) -> FrameInputsBuf {
    let mut rng = SplitMix64(0x2545_f491);
    let mut u = || rng.next_f64() as f32;
    let mut f = FrameInputsBuf::with_capacity(n);
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
        f.push(pixel, count, valid);
    }
    f
}
