//! The range form of the frame functions, for job systems: pixels
//! `first..first + history.len()` of a frame, given as sub-slices, with the bits of the
//! whole-frame call.
//!
//! Every pixel of a frame update is computed from its own inputs and texels, plus its
//! global index `first + i`, which only the stochastic-rounding words read. So a frame
//! cut into ranges at any pixel boundary (a chunk multiple or not), each updated by
//! [`update_frame_range`] / [`update_frame_ocv_range`] with its own first index, in any
//! order and on any threads, gives bit for bit what [`update_frame`] /
//! [`update_frame_ocv`] give on the whole frame (`tests/texel_range.rs` checks random
//! splits). [`estimate_frame`](super::estimate_frame) reads no index: call it on
//! sub-slices directly.
//!
//! [`update_frame`]: super::update_frame
//! [`update_frame_ocv`]: super::update_frame_ocv

use super::batch::{ConstantCoefficient, ConstantUpdate, OcvUpdate};
use super::encoding::{Texel, TexelEncoding};
use super::inputs::FrameInputs;
use super::rounding::Rounding;
use crate::cv::{Ocv, PixelController};
use crate::{CvHistory, Error, SpvgHistory};

/// [`update_frame`](super::update_frame) on pixels `first..first + history.len()` of a
/// frame: `inputs` and `history` hold that range only (all of one length), and `first`
/// is the range's first pixel index in the whole frame. Any split of a frame into
/// ranges gives the whole-frame call's bits: each pixel reads only its own inputs and
/// texels, and its index `first + i` only feeds the stochastic-rounding words.
///
/// # Errors
///
/// [`Error::InconsistentParameters`] when a slice of `inputs` differs in length from
/// `history`; nothing is written then.
///
/// # Examples
///
/// ```
/// use spvg::cv::{As, PixelController};
/// use spvg::texel::{FrameInputs, Rounding, SpvgTexel16, TexelEncoding};
/// use spvg::texel::{update_frame, update_frame_range};
/// use spvg::SpvgConfig;
/// let config = SpvgConfig::<f32>::published();
/// let pixel = PixelController::new(config, As);
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let n = 300;
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
/// let mut whole = vec![SpvgTexel16::default(); n];
/// update_frame(&pixel, &enc, rounding, &inputs, &mut whole).unwrap();
/// // Two jobs: pixels 0..100 and 100..300, in either order.
/// let mut split = vec![SpvgTexel16::default(); n];
/// let (a, b) = split.split_at_mut(100);
/// let part = |s: usize, e: usize| FrameInputs {
///     radiance: &radiance[s..e],
///     preintegrated: &ones[s..e],
///     gamma: &ones[s..e],
///     count: &count[s..e],
///     valid: &valid[s..e],
/// };
/// update_frame_range(&pixel, &enc, rounding, 100, &part(100, 300), b).unwrap();
/// update_frame_range(&pixel, &enc, rounding, 0, &part(0, 100), a).unwrap();
/// assert_eq!(whole, split);
/// ```
pub fn update_frame_range<M: ConstantCoefficient, H: Texel<History = SpvgHistory<f32>>>(
    pixel: &PixelController<f32, M>,
    enc: &TexelEncoding,
    rounding: Rounding,
    first: usize,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
) -> Result<(), Error> {
    inputs.check(history.len())?;
    ConstantUpdate::new(pixel, enc, rounding).run(inputs, history, first);
    Ok(())
}

/// [`update_frame_ocv`](super::update_frame_ocv) on pixels `first..first +
/// history.len()` of a frame, as [`update_frame_range`]: `inputs`, `history` and `cv`
/// hold that range only.
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
/// use spvg::texel::{update_frame_ocv, update_frame_ocv_range};
/// use spvg::SpvgConfig;
/// let config = SpvgConfig::<f32>::published();
/// let pixel = PixelController::new(config, Ocv::with_weight(0.05).unwrap());
/// let enc = TexelEncoding::new(config.target_variance()).unwrap();
/// let n = 130;
/// let radiance: Vec<f32> = (0..n).map(|i| (i % 5) as f32 * 0.2).collect();
/// let (b, gamma) = (vec![1.0_f32; n], vec![0.5_f32; n]);
/// let (count, valid) = (vec![16_u32; n], vec![0_u8; n]);
/// let inputs = |s: usize, e: usize| FrameInputs {
///     radiance: &radiance[s..e],
///     preintegrated: &b[s..e],
///     gamma: &gamma[s..e],
///     count: &count[s..e],
///     valid: &valid[s..e],
/// };
/// let r = Rounding::Stochastic(7);
/// let (mut h1, mut j1) = (vec![SpvgTexel16::default(); n], vec![CvTexel16::default(); n]);
/// update_frame_ocv(&pixel, &enc, r, &inputs(0, n), &mut h1, &mut j1).unwrap();
/// let (mut h2, mut j2) = (vec![SpvgTexel16::default(); n], vec![CvTexel16::default(); n]);
/// for (s, e) in [(0, 7), (7, 100), (100, n)] {
///     update_frame_ocv_range(&pixel, &enc, r, s, &inputs(s, e), &mut h2[s..e], &mut j2[s..e])
///         .unwrap();
/// }
/// assert_eq!((h1, j1), (h2, j2));
/// ```
pub fn update_frame_ocv_range<H, C>(
    pixel: &PixelController<f32, Ocv<f32>>,
    enc: &TexelEncoding,
    rounding: Rounding,
    first: usize,
    inputs: &FrameInputs<'_>,
    history: &mut [H],
    cv: &mut [C],
) -> Result<(), Error>
where
    H: Texel<History = SpvgHistory<f32>>,
    C: Texel<History = CvHistory<f32>>,
{
    inputs.check_with_cv(history.len(), cv.len())?;
    OcvUpdate::new(pixel, enc, rounding).run(inputs, history, cv, first);
    Ok(())
}
