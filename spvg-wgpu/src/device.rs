//! Adapter and device acquisition, split from the pass so tests can pass their own device.

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
            if self.timestamps {
                "GPU timestamp queries"
            } else {
                "CPU wall time (submit to poll wait; no timestamp queries)"
            }
        )
    }
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
    let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
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
    let (device, queue) = pollster::block_on(adapter.request_device(&desc))
        .map_err(|e| PassError::RequestDevice(e.to_string()))?;
    Ok(GpuDevice {
        device,
        queue,
        info,
        timestamps,
    })
}
