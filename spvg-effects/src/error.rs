//! Errors of the consumers and of device acquisition (the component has its own,
//! [`spvg_wgpu::adaptive::AdaptiveError`]).

use core::fmt;

/// What can go wrong when acquiring a device or running a consumer's pass.
#[derive(Debug)]
pub enum PassError {
    /// No wgpu adapter of the requested kind.
    NoAdapter(String),
    /// The adapter refused the device.
    RequestDevice(String),
    /// Waiting for the device or mapping a buffer failed.
    Device(String),
    /// Frame inputs of the wrong size.
    InputSize {
        /// Pixels the pass was built for.
        expected: usize,
        /// What the inputs hold.
        got: usize,
    },
    /// A parameter failed validation.
    Param(spvg::Error),
    /// The adaptive component refused a setting or an input.
    Adaptive(spvg_wgpu::adaptive::AdaptiveError),
    /// The frame does not fit the device's limits (checked before any resource exists).
    FrameTooLarge {
        /// Frame width asked for.
        width: u32,
        /// Frame height asked for.
        height: u32,
        /// The limit exceeded, e.g. `max_texture_dimension_2d`.
        limit: &'static str,
        /// What the frame needs of it.
        needed: u64,
        /// What the device allows.
        allowed: u64,
    },
}

impl fmt::Display for PassError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoAdapter(s) => write!(f, "no wgpu adapter: {s}"),
            Self::RequestDevice(s) => write!(f, "device request failed: {s}"),
            Self::Device(s) => write!(f, "device error: {s}"),
            Self::InputSize { expected, got } => {
                write!(
                    f,
                    "frame inputs hold {got} pixels, the pass expects {expected}"
                )
            }
            Self::Param(e) => write!(f, "{e}"),
            Self::Adaptive(e) => write!(f, "adaptive component: {e}"),
            Self::FrameTooLarge {
                width,
                height,
                limit,
                needed,
                allowed,
            } => write!(
                f,
                "a {width}x{height} frame exceeds the device's {limit}: needs {needed}, the device allows {allowed}"
            ),
        }
    }
}

impl std::error::Error for PassError {}

impl From<spvg_wgpu::adaptive::AdaptiveError> for PassError {
    /// A device failure (the readbacks the consumers share with the component) stays a
    /// device failure; anything else the component refused is [`PassError::Adaptive`].
    fn from(e: spvg_wgpu::adaptive::AdaptiveError) -> Self {
        match e {
            spvg_wgpu::adaptive::AdaptiveError::Device(s) => Self::Device(s),
            e => Self::Adaptive(e),
        }
    }
}

impl From<spvg::Error> for PassError {
    fn from(e: spvg::Error) -> Self {
        Self::Param(e)
    }
}
