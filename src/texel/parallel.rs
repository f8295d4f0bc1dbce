//! Multi-threaded frame updates (feature `std`): the frame is cut into one contiguous
//! range of pixels per thread, each range a multiple of the chunk width, and each thread
//! runs the serial chunk loop on its range with the range's global first pixel index.
//!
//! Every pixel is computed from its own inputs and texels only, and the stochastic-rounding
//! words depend on the global pixel index alone, so the result is bit for bit the serial
//! one for any thread count (`tests/texel_parallel.rs` checks it).

use super::batch::{ConstantCoefficient, ConstantUpdate, OcvUpdate};
use super::encoding::{CHUNK, Texel, TexelEncoding};
use super::inputs::FrameInputs;
use super::rounding::Rounding;
use crate::cv::{Ocv, PixelController};
use crate::{CvHistory, Error, SpvgHistory};

/// Frames below this many pixels per thread are not worth a thread (spawning one costs
/// about as much as updating a few thousand pixels).
const MIN_PIXELS_PER_THREAD: usize = 16 * CHUNK;

/// Pixels per thread: `len / threads` rounded up to a multiple of `CHUNK`, at least
/// `MIN_PIXELS_PER_THREAD`. `threads = 0` counts as 1.
fn range_len(len: usize, threads: usize) -> usize {
    let per = len.div_ceil(threads.max(1));
    per.div_ceil(CHUNK)
        .saturating_mul(CHUNK)
        .max(MIN_PIXELS_PER_THREAD)
}

/// Runs `run(first, part)` for each of `parts`, the consecutive ranges of `per` pixels
/// of a frame (`first` is the range's first pixel), one scoped thread per range; the
/// calling thread takes the first range.
fn on_threads<P: Send>(parts: impl Iterator<Item = P>, per: usize, run: impl Fn(usize, P) + Sync) {
    let run = &run;
    std::thread::scope(|scope| {
        let mut parts = parts.enumerate();
        let head = parts.next();
        for (t, part) in parts {
            scope.spawn(move || run(t * per, part));
        }
        if let Some((_, part)) = head {
            run(0, part);
        }
    });
}

/// [`update_frame`](super::update_frame) on `threads` threads (scoped, spawned per call;
/// the calling thread takes the first range). The result is bit for bit that of
/// [`update_frame`](super::update_frame), stochastic rounding included. `threads` of 0 or
/// 1, or a frame under about a thousand pixels per thread, runs on the calling thread.
/// [`std::thread::available_parallelism`] is a sensible thread count for a frame that
/// nothing else is working on.
///
/// # Errors
///
/// As [`update_frame`](super::update_frame); nothing is written then.
///
/// # Examples
///
/// ```
/// use spvg::cv::{As, PixelController};
/// use spvg::texel::{FrameInputs, Rounding, SpvgTexel16, TexelEncoding};
/// use spvg::texel::{update_frame, update_frame_parallel};
/// use spvg::SpvgConfig;
/// let config = SpvgConfig::<f32>::published();
/// let pixel = PixelController::new(config, As);
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let n = 5000;
/// let radiance: Vec<f32> = (0..n).map(|i| (i % 7) as f32 * 0.1).collect();
/// let ones = vec![1.0_f32; n];
/// let (count, valid) = (vec![8_u32; n], vec![1_u8; n]);
/// let inputs = FrameInputs {
///     radiance: &radiance,
///     preintegrated: &ones,
///     gamma: &ones,
///     count: &count,
///     valid: &valid,
/// };
/// let rounding = Rounding::Stochastic(42);
/// let mut serial = vec![SpvgTexel16::default(); n];
/// let mut threaded = serial.clone();
/// update_frame(&pixel, &enc, rounding, &inputs, &mut serial).unwrap();
/// update_frame_parallel(&pixel, &enc, rounding, &inputs, &mut threaded, 3).unwrap();
/// assert_eq!(serial, threaded);
/// ```
pub fn update_frame_parallel<M, H>(
    pixel: &PixelController<f32, M>,
    enc: &TexelEncoding,
    rounding: Rounding,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
    threads: usize,
) -> Result<(), Error>
where
    M: ConstantCoefficient + Sync,
    H: Texel<History = SpvgHistory<f32>> + Send,
{
    inputs.check(history.len())?;
    let update = ConstantUpdate::new(pixel, enc, rounding);
    let per = range_len(history.len(), threads);
    on_threads(history.chunks_mut(per), per, |first, hs| {
        update.run(&inputs.range(first, hs.len()), hs, first);
    });
    Ok(())
}

/// [`update_frame_ocv`](super::update_frame_ocv) on `threads` threads: bit for bit its
/// result (see [`update_frame_parallel`] for the splitting and the thread count).
///
/// # Errors
///
/// As [`update_frame_ocv`](super::update_frame_ocv); nothing is written then.
///
/// # Examples
///
/// ```
/// use spvg::cv::{Ocv, PixelController};
/// use spvg::texel::{CvTexel16, FrameInputs, Rounding, SpvgTexel16, TexelEncoding};
/// use spvg::texel::{update_frame_ocv, update_frame_ocv_parallel};
/// use spvg::SpvgConfig;
/// let config = SpvgConfig::<f32>::published();
/// let ocv = Ocv::with_weight(0.05).unwrap().with_f16_inputs(true);
/// let pixel = PixelController::new(config, ocv);
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let n = 5000;
/// let radiance: Vec<f32> = (0..n).map(|i| (i % 5) as f32 * 0.2).collect();
/// let (b, gamma) = (vec![1.0_f32; n], vec![0.5_f32; n]);
/// let (count, valid) = (vec![16_u32; n], vec![1_u8; n]);
/// let inputs = FrameInputs {
///     radiance: &radiance,
///     preintegrated: &b,
///     gamma: &gamma,
///     count: &count,
///     valid: &valid,
/// };
/// let (mut h1, mut j1) = (vec![SpvgTexel16::default(); n], vec![CvTexel16::default(); n]);
/// let (mut h2, mut j2) = (h1.clone(), j1.clone());
/// let r = Rounding::Stochastic(7);
/// update_frame_ocv(&pixel, &enc, r, &inputs, &mut h1, &mut j1).unwrap();
/// update_frame_ocv_parallel(&pixel, &enc, r, &inputs, &mut h2, &mut j2, 4).unwrap();
/// assert_eq!((h1, j1), (h2, j2));
/// ```
pub fn update_frame_ocv_parallel<H, C>(
    pixel: &PixelController<f32, Ocv<f32>>,
    enc: &TexelEncoding,
    rounding: Rounding,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
    cv: &mut [C],
    threads: usize,
) -> Result<(), Error>
where
    H: Texel<History = SpvgHistory<f32>> + Send,
    C: Texel<History = CvHistory<f32>> + Send,
{
    inputs.check_with_cv(history.len(), cv.len())?;
    let update = OcvUpdate::new(pixel, enc, rounding);
    let per = range_len(history.len(), threads);
    let parts = history.chunks_mut(per).zip(cv.chunks_mut(per));
    on_threads(parts, per, |first, (hs, js)| {
        update.run(&inputs.range(first, hs.len()), hs, js, first);
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_chunk_aligned_and_cover_the_frame() {
        for (len, threads) in [(0, 4), (1, 1), (5000, 3), (1920 * 1080, 16), (100_003, 0)] {
            let per = range_len(len, threads);
            assert_eq!(
                per % CHUNK,
                0,
                "range length {per} must be a multiple of {CHUNK}"
            );
            assert!(
                per * threads.max(1) >= len,
                "{threads} ranges of {per} must cover {len} pixels"
            );
        }
    }
}
