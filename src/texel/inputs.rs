//! The per-pixel inputs of a frame update ([`FrameInputs`], and with `std` their owned
//! form [`FrameInputsBuf`]), their length checks, and their chunk-wise copies into
//! fixed-width lanes for the frame functions.

use super::encoding::CHUNK;
use crate::Error;
#[cfg(feature = "std")]
use crate::cv::PixelFrame;

/// A frame's per-pixel inputs, structure of arrays: element `i` of every slice belongs to
/// pixel `i`. All slices must have the history's length.
#[derive(Clone, Copy, Debug)]
pub struct FrameInputs<'a> {
    /// Luminance of the shaded result `L_o`.
    pub radiance: &'a [f32],
    /// Luminance of the pre-integrated lighting `B(p)`.
    pub preintegrated: &'a [f32],
    /// Distant energy ratio `gamma`.
    pub gamma: &'a [f32],
    /// The count the pixel used this frame (from the estimate).
    pub count: &'a [u32],
    /// History validity: non-zero when the pixel's history is valid (no disocclusion).
    pub valid: &'a [u8],
}

/// A frame's per-pixel inputs in owned vectors of equal length (feature `std`): the owned
/// form of [`FrameInputs`], as `Vec<T>` is of `&[T]`. Filled one pixel at a time with
/// the arguments of [`PixelController::update`](crate::cv::PixelController::update), so
/// the slices of [`inputs`](Self::inputs) always match in length; [`clear`](Self::clear)
/// keeps the allocations for the next frame.
///
/// # Examples
///
/// ```
/// use spvg::cv::PixelFrame;
/// use spvg::texel::FrameInputsBuf;
/// let mut frame = FrameInputsBuf::with_capacity(2);
/// frame.push(PixelFrame { radiance: 1.5, preintegrated: 1.0, gamma: 0.5 }, 8, true);
/// frame.push(PixelFrame { radiance: 2.0, preintegrated: 1.0, gamma: 1.0 }, 0, false);
/// let inputs = frame.inputs();
/// assert_eq!((inputs.radiance, inputs.gamma), (&[1.5, 2.0][..], &[0.5, 1.0][..]));
/// assert_eq!((inputs.count, inputs.valid), (&[8, 0][..], &[1, 0][..]));
/// assert_eq!(frame.len(), 2);
/// frame.clear();
/// assert!(frame.is_empty() && frame.inputs().preintegrated.is_empty());
/// ```
#[cfg(feature = "std")]
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameInputsBuf {
    radiance: Vec<f32>,
    preintegrated: Vec<f32>,
    gamma: Vec<f32>,
    count: Vec<u32>,
    valid: Vec<u8>,
}

#[cfg(feature = "std")]
impl FrameInputsBuf {
    /// An empty frame with room for `pixels` pixels.
    #[must_use]
    pub fn with_capacity(pixels: usize) -> Self {
        Self {
            radiance: Vec::with_capacity(pixels),
            preintegrated: Vec::with_capacity(pixels),
            gamma: Vec::with_capacity(pixels),
            count: Vec::with_capacity(pixels),
            valid: Vec::with_capacity(pixels),
        }
    }

    /// Appends a pixel: its luminances and `gamma`, the count it used this frame, and
    /// whether its history is valid (stored as `1` or `0`).
    pub fn push(&mut self, frame: PixelFrame<f32>, count: u32, valid: bool) {
        self.radiance.push(frame.radiance);
        self.preintegrated.push(frame.preintegrated);
        self.gamma.push(frame.gamma);
        self.count.push(count);
        self.valid.push(u8::from(valid));
    }

    /// The inputs as slices, for the frame functions.
    #[inline]
    #[must_use]
    pub fn inputs(&self) -> FrameInputs<'_> {
        FrameInputs {
            radiance: &self.radiance,
            preintegrated: &self.preintegrated,
            gamma: &self.gamma,
            count: &self.count,
            valid: &self.valid,
        }
    }

    /// The number of pixels.
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.valid.len()
    }

    /// Whether there are no pixels.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.valid.is_empty()
    }

    /// Removes every pixel, keeping the allocations.
    pub fn clear(&mut self) {
        self.radiance.clear();
        self.preintegrated.clear();
        self.gamma.clear();
        self.count.clear();
        self.valid.clear();
    }
}

pub(crate) fn mismatch() -> Error {
    Error::InconsistentParameters {
        names: "frame slices",
        expected: "every per-pixel slice must have the history's length",
    }
}

/// Copies a chunk's per-pixel inputs into a fixed-width array, so that the lane loops
/// run a fixed trip count without bounds checks (lanes past `src.len()` keep stale values
/// that are computed on but never stored).
#[inline(always)]
pub(super) fn fill<T: Copy>(dst: &mut [T; CHUNK], src: &[T]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}

/// The (at most) `CHUNK` elements of `s` from `start`.
#[inline(always)]
fn part<T>(s: &[T], start: usize) -> &[T] {
    s.get(start..).unwrap_or(&[])
}

/// A chunk of per-pixel inputs as fixed-width arrays, borrowed from the frame.
#[derive(Clone, Copy)]
pub(super) struct Lanes<'a> {
    pub(super) radiance: &'a [f32; CHUNK],
    pub(super) preintegrated: &'a [f32; CHUNK],
    pub(super) gamma: &'a [f32; CHUNK],
    pub(super) count: &'a [u32; CHUNK],
    pub(super) valid: &'a [u8; CHUNK],
}

/// Owned lanes, for a frame's last, partial chunk: lanes past the frame's end keep stale
/// values that are computed on but never stored.
pub(super) struct PaddedLanes {
    radiance: [f32; CHUNK],
    preintegrated: [f32; CHUNK],
    gamma: [f32; CHUNK],
    count: [u32; CHUNK],
    valid: [u8; CHUNK],
}

impl PaddedLanes {
    pub(super) fn new() -> Self {
        Self {
            radiance: [0.0; CHUNK],
            preintegrated: [0.0; CHUNK],
            gamma: [0.0; CHUNK],
            count: [0; CHUNK],
            valid: [0; CHUNK],
        }
    }

    /// The lanes of pixels `start..` (at most `CHUNK`): borrowed straight from the frame
    /// when a whole chunk is there (no copy), otherwise copied into `self`.
    #[inline(always)]
    pub(super) fn lanes<'a>(&'a mut self, inputs: &FrameInputs<'a>, start: usize) -> Lanes<'a> {
        #[inline(always)]
        fn whole<T>(s: &[T], start: usize) -> Option<&[T; CHUNK]> {
            s.get(start..start.checked_add(CHUNK)?)?.try_into().ok()
        }
        if let (Some(radiance), Some(preintegrated), Some(gamma), Some(count), Some(valid)) = (
            whole(inputs.radiance, start),
            whole(inputs.preintegrated, start),
            whole(inputs.gamma, start),
            whole(inputs.count, start),
            whole(inputs.valid, start),
        ) {
            return Lanes {
                radiance,
                preintegrated,
                gamma,
                count,
                valid,
            };
        }
        fill(&mut self.radiance, part(inputs.radiance, start));
        fill(&mut self.preintegrated, part(inputs.preintegrated, start));
        fill(&mut self.gamma, part(inputs.gamma, start));
        fill(&mut self.count, part(inputs.count, start));
        fill(&mut self.valid, part(inputs.valid, start));
        Lanes {
            radiance: &self.radiance,
            preintegrated: &self.preintegrated,
            gamma: &self.gamma,
            count: &self.count,
            valid: &self.valid,
        }
    }
}

impl<'a> FrameInputs<'a> {
    /// The inputs of pixels `start..start + len` (slices cut short where they end).
    #[cfg(feature = "std")]
    pub(super) fn range(&self, start: usize, len: usize) -> FrameInputs<'a> {
        fn cut<T>(s: &[T], start: usize, len: usize) -> &[T] {
            let s = s.get(start..).unwrap_or(&[]);
            s.get(..len).unwrap_or(s)
        }
        FrameInputs {
            radiance: cut(self.radiance, start, len),
            preintegrated: cut(self.preintegrated, start, len),
            gamma: cut(self.gamma, start, len),
            count: cut(self.count, start, len),
            valid: cut(self.valid, start, len),
        }
    }

    pub(super) fn check(&self, len: usize) -> Result<(), Error> {
        let ok = self.radiance.len() == len
            && self.preintegrated.len() == len
            && self.gamma.len() == len
            && self.count.len() == len
            && self.valid.len() == len;
        if ok { Ok(()) } else { Err(mismatch()) }
    }

    /// [`check`](Self::check), and that the CV history has the history's length.
    pub(super) fn check_with_cv(&self, len: usize, cv_len: usize) -> Result<(), Error> {
        self.check(len)?;
        if cv_len == len {
            Ok(())
        } else {
            Err(mismatch())
        }
    }
}
