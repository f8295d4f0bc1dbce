//! Errors of the adaptive component: every wrong input is named, and none reaches wgpu.

use core::fmt;

use spvg::controller::CountPolicy;

/// What the adaptive component rejects. Inputs are checked (size, format, usage, kind)
/// before any bind group is created, so a wrong texture is this error, never a wgpu
/// validation panic.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum AdaptiveError {
    /// A controller or reprojection parameter failed validation.
    Param(spvg::Error),
    /// The GPU steps implement the SPVG count rule only.
    UnsupportedPolicy(CountPolicy),
    /// A frame size of zero, above the device's 2D texture limit, or with more than
    /// `u32::MAX - 1` pixels.
    FrameSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The device's `max_texture_dimension_2d` (the twin uses `u16::MAX`).
        max: u32,
    },
    /// An input texture whose mip 0 is not the frame size.
    TextureSize {
        /// The input's field name.
        input: &'static str,
        /// The frame size `[width, height]`.
        expected: [u32; 2],
        /// The texture's `[width, height, depth_or_array_layers]`.
        got: [u32; 3],
    },
    /// An input texture of a format the step cannot read.
    TextureFormat {
        /// The input's field name.
        input: &'static str,
        /// The texture's format.
        got: wgpu::TextureFormat,
        /// The formats accepted there.
        allowed: &'static [wgpu::TextureFormat],
    },
    /// An input texture created without a usage the step needs.
    TextureUsage {
        /// The input's field name.
        input: &'static str,
        /// The usages it lacks.
        missing: wgpu::TextureUsages,
    },
    /// An input texture that is not a single-sampled 2D texture with one layer.
    TextureKind {
        /// The input's field name.
        input: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// An input the control model needs was not given (the control value for CCV and
    /// OCV).
    MissingInput {
        /// The input's field name.
        input: &'static str,
        /// Why it is needed.
        reason: &'static str,
    },
    /// A CPU-twin input slice of the wrong length.
    SliceLength {
        /// The input's field name.
        input: &'static str,
        /// Pixels in the frame.
        expected: usize,
        /// Elements in the slice.
        got: usize,
    },
    /// `update` was recorded without an `estimate` for the same frame before it.
    UpdateWithoutEstimate,
    /// The frame was resized between its `estimate` and its `update`: the resize
    /// discarded the estimate (its counts and links belong to the old size), so the
    /// update has nothing to continue. Record a new estimate at the new size first.
    ResizedBetweenSteps,
    /// The settings (the target variance among them) were changed between a frame's
    /// `estimate` and its `update`: both steps of a frame run one setting.
    SettingsBetweenSteps,
    /// A one-pass frame was asked for between a two-pass frame's `estimate` and its
    /// `update`: record the update first (both forms advance the same history).
    OnePassBetweenSteps,
    /// Waiting for the device or mapping a readback buffer failed.
    Device(String),
}

impl fmt::Display for AdaptiveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Param(e) => write!(f, "{e}"),
            Self::UnsupportedPolicy(p) => write!(
                f,
                "count policy {p:?} is not supported by the adaptive pass (only Spvg)"
            ),
            Self::FrameSize { width, height, max } => write!(
                f,
                "frame size {width}x{height}: each side must be in 1..={max} and the frame \
                 below 2^32 - 1 pixels"
            ),
            Self::TextureSize {
                input,
                expected,
                got,
            } => write!(
                f,
                "`{input}` is {}x{}x{}, expected {}x{}x1 (the frame size)",
                got[0], got[1], got[2], expected[0], expected[1]
            ),
            Self::TextureFormat {
                input,
                got,
                allowed,
            } => write!(
                f,
                "`{input}` has format {got:?}, expected one of {allowed:?}"
            ),
            Self::TextureUsage { input, missing } => {
                write!(f, "`{input}` was created without usage {missing:?}")
            }
            Self::TextureKind { input, reason } => write!(f, "`{input}`: {reason}"),
            Self::MissingInput { input, reason } => write!(f, "`{input}` is required: {reason}"),
            Self::SliceLength {
                input,
                expected,
                got,
            } => write!(
                f,
                "`{input}` holds {got} values, the frame has {expected} pixels"
            ),
            Self::UpdateWithoutEstimate => {
                write!(f, "update recorded without an estimate for this frame")
            }
            Self::ResizedBetweenSteps => write!(
                f,
                "the frame was resized between its estimate and its update; record a new \
                 estimate at the new size"
            ),
            Self::SettingsBetweenSteps => write!(
                f,
                "settings changed between a frame's estimate and its update; change them \
                 before the estimate"
            ),
            Self::OnePassBetweenSteps => write!(
                f,
                "a one-pass frame between a two-pass frame's estimate and its update; record \
                 that update first"
            ),
            Self::Device(e) => write!(f, "device error: {e}"),
        }
    }
}

impl std::error::Error for AdaptiveError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Param(e) => Some(e),
            _ => None,
        }
    }
}

impl From<spvg::Error> for AdaptiveError {
    fn from(e: spvg::Error) -> Self {
        Self::Param(e)
    }
}
