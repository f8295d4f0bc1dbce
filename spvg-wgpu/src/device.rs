//! Adapter and device acquisition, split from the pass so tests can pass their own device.

use crate::adaptive::gpu::block_on;
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

/// A wgpu device with the adapter description it came from.
#[derive(Clone, Debug)]
pub struct GpuDevice {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter's description (name, type, backend).
    pub info: wgpu::AdapterInfo,
    /// Whether timestamp queries are enabled on the device.
    pub timestamps: bool,
}

impl GpuDevice {
    /// One line naming the adapter, e.g. `llvmpipe (LLVM 15.0.6) [Cpu, Vulkan]`.
    #[must_use]
    pub fn describe(&self) -> String {
        format!(
            "{} [{:?}, {:?}], timing: {}",
            self.info.name,
            self.info.device_type,
            self.info.backend,
            if self.is_software() {
                "CPU wall time (submit to poll wait; a software rasterizer's timestamps do not bracket multi-pass work)"
            } else if self.timestamps {
                "GPU timestamp queries"
            } else {
                "CPU wall time (submit to poll wait; no timestamp queries)"
            }
        )
    }
}

impl GpuDevice {
    /// Whether the adapter is a software rasterizer (adapter type `Cpu`, e.g. lavapipe):
    /// its pass times are CPU time.
    #[must_use]
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// Checks that a `width x height` pass fits this device; see [`check_frame_size`].
    ///
    /// # Errors
    ///
    /// [`PassError::FrameTooLarge`] naming the limit.
    pub fn check_frame(&self, width: u32, height: u32) -> Result<(), PassError> {
        check_frame_size(&self.device, width, height)
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

fn rank(t: wgpu::DeviceType) -> u32 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

/// Creates a device on the best wgpu adapter: hardware GPUs first, then software Vulkan
/// (lavapipe). Requests timestamp queries when the adapter has them.
///
/// # Errors
///
/// [`PassError::NoAdapter`] when no adapter exists, [`PassError::RequestDevice`] when the
/// adapter refuses the device.
pub fn acquire_device() -> Result<GpuDevice, PassError> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let mut adapters = block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    adapters.sort_by_key(|a| rank(a.get_info().device_type));
    let Some(adapter) = adapters.into_iter().next() else {
        return Err(PassError::NoAdapter(
            "no wgpu adapter found (install mesa-vulkan-drivers for lavapipe)".into(),
        ));
    };
    let info = adapter.get_info();
    let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
    let required_features = if timestamps {
        wgpu::Features::TIMESTAMP_QUERY
    } else {
        wgpu::Features::empty()
    };
    let desc = wgpu::DeviceDescriptor {
        label: Some("spvg-wgpu"),
        required_features,
        required_limits: adapter.limits(),
        ..Default::default()
    };
    let (device, queue) = block_on(adapter.request_device(&desc))
        .map_err(|e| PassError::RequestDevice(e.to_string()))?;
    Ok(GpuDevice {
        device,
        queue,
        info,
        timestamps,
    })
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
            BackendChoice::Gpu => acquire_device().map(|d| Self::Gpu(Box::new(d))),
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
            Self::Gpu(d) => d.check_frame(width, height),
            Self::Cpu => Ok(()),
        }
    }
}
