//! Where an effect runs: a wgpu device (from [`spvg_wgpu::util::acquire_device`]) or the
//! CPU twin, and the frame-size check against the device's limits.

use spvg_wgpu::util::{GpuDevice, acquire_device};

use crate::error::PassError;

/// Which implementation runs the pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackendChoice {
    /// A hardware GPU adapter if present, then software Vulkan (lavapipe, adapter type
    /// `Cpu`), then the CPU twin.
    Auto,
    /// Any wgpu adapter (hardware preferred); an error if there is none.
    Gpu,
    /// The multi-threaded CPU twin.
    Cpu,
}

impl core::str::FromStr for BackendChoice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "auto" => Ok(Self::Auto),
            "gpu" => Ok(Self::Gpu),
            "cpu" => Ok(Self::Cpu),
            _ => Err(format!("unknown backend {s:?}: expected auto, gpu or cpu")),
        }
    }
}

/// Checks that the pass's textures and buffers for a `width x height` frame fit the
/// device's limits (largest 2D texture side, largest buffer, largest dispatch), so that an
/// oversized frame is a typed error here instead of a wgpu validation panic later. Call it
/// before [`SssPass::for_device`](crate::sss::SssPass::for_device) /
/// [`SssPass::new`](crate::sss::SssPass::new) with sizes you did not choose.
///
/// # Errors
///
/// [`PassError::FrameTooLarge`] naming the first limit exceeded.
pub fn check_frame_size(device: &wgpu::Device, width: u32, height: u32) -> Result<(), PassError> {
    let limits = device.limits();
    let too_large = |limit, needed: u64, allowed: u64| {
        if needed > allowed {
            Err(PassError::FrameTooLarge {
                width,
                height,
                limit,
                needed,
                allowed,
            })
        } else {
            Ok(())
        }
    };
    let side = u64::from(width.max(height));
    too_large(
        "max_texture_dimension_2d",
        side,
        u64::from(limits.max_texture_dimension_2d),
    )?;
    // The largest buffer is the readback of the 8-byte result texels, rows padded to the
    // copy alignment.
    let row = (u64::from(width.max(1)) * 8)
        .next_multiple_of(u64::from(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT));
    too_large(
        "max_buffer_size",
        row * u64::from(height.max(1)),
        limits.max_buffer_size,
    )?;
    // 8 x 8 workgroups.
    too_large(
        "max_compute_workgroups_per_dimension",
        u64::from(width.max(height).div_ceil(8)),
        u64::from(limits.max_compute_workgroups_per_dimension),
    )
}

/// The resolved backend: a wgpu device, or the CPU twin (a consumer builds its pass on
/// it: [`Backend::pass`] for the subsurface pass).
#[derive(Clone, Debug)]
pub enum Backend {
    /// A wgpu device.
    Gpu(Box<GpuDevice>),
    /// The CPU twin.
    Cpu,
}

impl Backend {
    /// Resolves a [`BackendChoice`]: `auto` falls back to the CPU twin when no wgpu adapter
    /// can be created.
    ///
    /// # Errors
    ///
    /// With `gpu`, when no wgpu device can be created.
    pub fn resolve(choice: BackendChoice) -> Result<Self, PassError> {
        match choice {
            BackendChoice::Cpu => Ok(Self::Cpu),
            BackendChoice::Gpu => acquire_device()
                .map(|d| Self::Gpu(Box::new(d)))
                .map_err(|e| PassError::NoAdapter(e.to_string())),
            BackendChoice::Auto => {
                Ok(acquire_device().map_or(Self::Cpu, |d| Self::Gpu(Box::new(d))))
            }
        }
    }

    /// One line saying which implementation runs.
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Self::Gpu(d) => format!("wgpu: {}", d.describe()),
            Self::Cpu => format!(
                "CPU twin ({} threads), timing: CPU wall time",
                std::thread::available_parallelism().map_or(1, usize::from)
            ),
        }
    }

    /// Checks that a `width x height` frame fits the backend: the device's limits
    /// ([`check_frame_size`]) on a GPU; the CPU twin takes any size that fits in memory.
    ///
    /// # Errors
    ///
    /// [`PassError::FrameTooLarge`] naming the limit.
    pub fn check_frame(&self, width: u32, height: u32) -> Result<(), PassError> {
        match self {
            Self::Gpu(d) => check_frame_size(&d.device, width, height),
            Self::Cpu => Ok(()),
        }
    }
}
