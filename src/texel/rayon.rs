//! The frame updates on rayon's thread pool (feature `rayon`): the frame is cut into
//! ranges of 8192 pixels, each updated by the range form of the frame
//! functions, so the bits are those of the serial call.

use rayon::prelude::{IndexedParallelIterator, ParallelIterator, ParallelSliceMut};

use super::batch::{ConstantCoefficient, ConstantUpdate, OcvUpdate};
use super::encoding::{Texel, TexelEncoding};
use super::inputs::FrameInputs;
use super::rounding::Rounding;
use crate::cv::{Ocv, PixelController};
use crate::{CvHistory, Error, SpvgHistory};

/// Pixels per rayon task: 128 chunks of 64, about 30-60 us of work per task at 1080p
/// speeds, enough tasks (253 at 1080p) for the pool to balance.
const RAYON_RANGE: usize = 8192;

/// [`update_frame`](super::update_frame) on rayon's current thread pool, bit for bit its
/// result (stochastic rounding included): the frame goes in ranges of 8192 pixels through
/// [`update_frame_range`](super::update_frame_range)'s code path.
///
/// # Errors
///
/// As [`update_frame`](super::update_frame); nothing is written then.
///
/// # Examples
///
/// ```
/// use spvg::cv::{Ccv, PixelController};
/// use spvg::texel::{FrameInputs, Rounding, SpvgTexel16, TexelEncoding};
/// use spvg::texel::{update_frame, update_frame_rayon};
/// use spvg::SpvgConfig;
/// let config = SpvgConfig::<f32>::published();
/// let pixel = PixelController::new(config, Ccv);
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let n = 20_000;
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
/// let (mut serial, mut pooled) = (vec![SpvgTexel16::default(); n], vec![SpvgTexel16::default(); n]);
/// update_frame(&pixel, &enc, Rounding::Stochastic(3), &inputs, &mut serial).unwrap();
/// update_frame_rayon(&pixel, &enc, Rounding::Stochastic(3), &inputs, &mut pooled).unwrap();
/// assert_eq!(serial, pooled);
/// ```
pub fn update_frame_rayon<M, H>(
    pixel: &PixelController<f32, M>,
    enc: &TexelEncoding,
    rounding: Rounding,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
) -> Result<(), Error>
where
    M: ConstantCoefficient,
    H: Texel<History = SpvgHistory<f32>> + Send,
{
    inputs.check(history.len())?;
    let update = ConstantUpdate::new(pixel, enc, rounding);
    history
        .par_chunks_mut(RAYON_RANGE)
        .enumerate()
        .for_each(|(k, hs)| {
            let first = k * RAYON_RANGE;
            update.run(&inputs.range(first, hs.len()), hs, first);
        });
    Ok(())
}

/// [`update_frame_ocv`](super::update_frame_ocv) on rayon's current thread pool, bit for
/// bit its result (see [`update_frame_rayon`]).
///
/// # Errors
///
/// As [`update_frame_ocv`](super::update_frame_ocv); nothing is written then.
pub fn update_frame_ocv_rayon<H, C>(
    pixel: &PixelController<f32, Ocv<f32>>,
    enc: &TexelEncoding,
    rounding: Rounding,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
    cv: &mut [C],
) -> Result<(), Error>
where
    H: Texel<History = SpvgHistory<f32>> + Send,
    C: Texel<History = CvHistory<f32>> + Send,
{
    inputs.check_with_cv(history.len(), cv.len())?;
    let update = OcvUpdate::new(pixel, enc, rounding);
    history
        .par_chunks_mut(RAYON_RANGE)
        .zip(cv.par_chunks_mut(RAYON_RANGE))
        .enumerate()
        .for_each(|(k, (hs, js))| {
            let first = k * RAYON_RANGE;
            update.run(&inputs.range(first, hs.len()), hs, js, first);
        });
    Ok(())
}
