//! Multi-threaded frame updates (feature `std`): the frame is cut into contiguous ranges
//! of pixels, a few per thread, each a multiple of the chunk width; the threads take
//! ranges from a shared queue and run the serial chunk loop (the run-time dispatched
//! variant, AVX2 or AVX-512, where the CPU has one) on each with the range's global
//! first pixel index.
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

/// The threads a frame of `len` pixels runs on for a requested count: at least 1, at
/// most one per `MIN_PIXELS_PER_THREAD` pixels (the work available) and at most
/// [`std::thread::available_parallelism`] (more threads than cores only add spawning
/// and switching; 1 where it is unknown).
fn thread_count(len: usize, threads: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
    threads.min(len / MIN_PIXELS_PER_THREAD).min(cores).max(1)
}

/// Ranges per thread. The threads take ranges from a shared queue, so a thread that gets
/// less of its core (other processes, the engine's own threads) takes fewer ranges,
/// and the frame ends when the threads' work together is done instead of when the slowest
/// thread's equal share is; a lock per range costs nothing against its thousands of pixels.
const RANGES_PER_THREAD: usize = 8;

/// Pixels per range: `len / (RANGES_PER_THREAD * threads)` rounded up to a multiple of
/// `CHUNK` (no chunk is cut in two, and neighbouring ranges share no cache line of
/// history where the texel slices start on one), at least
/// `MIN_PIXELS_PER_THREAD`. `threads = 0` counts as 1.
fn range_len(len: usize, threads: usize) -> usize {
    let per = len.div_ceil(threads.max(1).saturating_mul(RANGES_PER_THREAD));
    per.div_ceil(CHUNK)
        .saturating_mul(CHUNK)
        .max(MIN_PIXELS_PER_THREAD)
}

/// Runs `run(first, part)` for each of `parts`, the consecutive ranges of `per` pixels
/// of a frame (`first` is the range's first pixel), on up to `threads` threads: the
/// calling thread and up to `threads - 1` scoped threads take ranges from one shared
/// queue until it is empty. A thread that cannot be spawned (a resource limit) is not
/// an error: the ranges it would have taken go to the threads that run, in the end to
/// the calling thread alone.
fn on_threads<P: Send>(
    parts: impl Iterator<Item = P> + Send,
    per: usize,
    threads: usize,
    run: impl Fn(usize, P) + Sync,
) {
    let queue = std::sync::Mutex::new(parts.enumerate());
    let work = || {
        loop {
            // A poisoned lock only means another worker panicked; its panic reaches the
            // caller when the scope ends, and the queue itself is still consistent.
            let next = queue
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .next();
            let Some((t, part)) = next else { break };
            run(t * per, part);
        }
    };
    std::thread::scope(|scope| {
        for _ in 1..threads {
            if std::thread::Builder::new()
                .spawn_scoped(scope, work)
                .is_err()
            {
                break;
            }
        }
        work();
    });
}

/// [`update_frame`](super::update_frame) on up to `threads` threads (scoped, spawned per
/// call; the calling thread works too). The result is bit for bit that of
/// [`update_frame`](super::update_frame), stochastic rounding included.
///
/// The thread count is capped: at the work available (one thread per thousand pixels;
/// `threads` of 0 or 1, or a small frame, runs on the calling thread) and at
/// [`std::thread::available_parallelism`], so `threads = usize::MAX` means "every core".
/// A thread that cannot be spawned (for example under a process limit) is not an
/// error: its share runs on the threads that did start, the calling thread included.
/// For a job system of your own, or rayon, use the range form
/// [`update_frame_range`](super::update_frame_range).
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
    let threads = thread_count(history.len(), threads);
    let per = range_len(history.len(), threads);
    on_threads(history.chunks_mut(per), per, threads, |first, hs| {
        update.run(&inputs.range(first, hs.len()), hs, first);
    });
    Ok(())
}

/// [`update_frame_ocv`](super::update_frame_ocv) on `threads` threads: bit for bit its
/// result (see [`update_frame_parallel`] for the splitting, the thread cap and the
/// fallback when a thread cannot be spawned).
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
    let threads = thread_count(history.len(), threads);
    let per = range_len(history.len(), threads);
    let parts = history.chunks_mut(per).zip(cv.chunks_mut(per));
    on_threads(parts, per, threads, |first, (hs, js)| {
        update.run(&inputs.range(first, hs.len()), hs, js, first);
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_count_is_capped_by_work_and_cores() {
        let cores = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
        assert_eq!(thread_count(100, 8), 1, "a small frame runs on one thread");
        assert_eq!(
            thread_count(1 << 20, 0),
            1,
            "0 threads means the calling thread"
        );
        let n = thread_count(3840 * 2160, usize::MAX);
        assert_eq!(n, cores, "usize::MAX threads is one per core, got {n}");
        let n = thread_count(4 * MIN_PIXELS_PER_THREAD, 1000);
        assert!(
            n <= 4,
            "at most one thread per {MIN_PIXELS_PER_THREAD} pixels, got {n}"
        );
    }

    #[test]
    fn ranges_are_chunk_aligned_and_a_few_per_thread() {
        for (len, threads) in [(0, 4), (1, 1), (5000, 3), (1920 * 1080, 16), (100_003, 0)] {
            let per = range_len(len, threads);
            assert_eq!(
                per % CHUNK,
                0,
                "range length {per} must be a multiple of {CHUNK}"
            );
            let ranges = len.div_ceil(per);
            assert!(
                ranges <= RANGES_PER_THREAD * threads.max(1),
                "{len} pixels in ranges of {per}: {ranges} ranges for {threads} threads"
            );
            assert!(
                per >= MIN_PIXELS_PER_THREAD,
                "a range of {per} pixels is below the minimum"
            );
        }
    }
}
