//! Small wgpu helpers the component is built with, public so that a renderer's own passes,
//! tests and tools use them instead of copies: 2D textures and their mip-0 views, compute
//! pipelines of one bind group, bind groups of whole buffers and views, 8x8 dispatches,
//! texture and buffer readback (blocking, and async for the web), and on native targets a
//! blocking executor for wgpu's futures.
//!
//! On wasm32 nothing here blocks or needs threads: a browser can neither. The blocking
//! readbacks and [`acquire_device`] return [`AdaptiveError::Device`] there at once, and
//! [`block_on`] does not exist; a page awaits [`read_texture_async`] and requests its
//! adapter and device with wgpu's async calls.

#[cfg(not(target_arch = "wasm32"))]
use std::sync::Arc;
#[cfg(not(target_arch = "wasm32"))]
use std::task::{Context, Poll, Wake, Waker};

use crate::adaptive::AdaptiveError;

mod readback;
pub use readback::{read_buffer, read_buffer_async, read_texture, read_texture_async};

/// A 2D texture of one mip level and one sample.
pub fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    size: [u32; 2],
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&texture_2d_desc(label, format, size, usage))
}

/// The descriptor of [`texture_2d`] (for `create_texture_with_data`).
pub fn texture_2d_desc(
    label: &str,
    format: wgpu::TextureFormat,
    [width, height]: [u32; 2],
    usage: wgpu::TextureUsages,
) -> wgpu::TextureDescriptor<'_> {
    wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    }
}

/// A view of mip 0 alone (the passes read and write level 0; a caller's input texture may
/// carry more levels).
pub fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        base_mip_level: 0,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

/// Compiles a WGSL module source.
pub fn shader_module(device: &wgpu::Device, label: &str, source: String) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// The compute pipeline of `entry` in `module`, labelled with the entry point's name; its
/// layout is `layout`'s single bind group (group 0), or derived from the shader (`None`).
pub fn compute_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry: &str,
    layout: Option<&wgpu::BindGroupLayout>,
) -> wgpu::ComputePipeline {
    let pipeline_layout = layout.map(|bgl| {
        device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(entry),
            bind_group_layouts: &[Some(bgl)],
            immediate_size: 0,
        })
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: pipeline_layout.as_ref(),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions::default(),
        cache: None,
    })
}

/// A bind group of whole buffers and texture views, each at its binding index.
pub fn bind_group(
    device: &wgpu::Device,
    label: Option<&str>,
    layout: &wgpu::BindGroupLayout,
    buffers: &[(u32, &wgpu::Buffer)],
    views: &[(u32, wgpu::TextureView)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
        .iter()
        .map(|&(binding, buffer)| wgpu::BindGroupEntry {
            binding,
            resource: buffer.as_entire_binding(),
        })
        .chain(views.iter().map(|(binding, view)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: wgpu::BindingResource::TextureView(view),
        }))
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label,
        layout,
        entries: &entries,
    })
}

/// Records one compute pass of `pipeline` with `group` at group 0 over a `width x height`
/// frame in 8x8 workgroups (the workgroup size of every entry point of the crate's WGSL).
pub fn dispatch_8x8(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::ComputePipeline,
    group: &wgpu::BindGroup,
    timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    [width, height]: [u32; 2],
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, group, &[]);
    pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
}

/// Wakes the thread that blocks on a future.
#[cfg(not(target_arch = "wasm32"))]
struct ThreadWaker(std::thread::Thread);

#[cfg(not(target_arch = "wasm32"))]
impl Wake for ThreadWaker {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.0.unpark();
    }
}

/// Runs a future to completion on the calling thread, parking it between polls (wgpu's
/// adapter and device requests; what `pollster::block_on` does, on std alone). Native
/// targets only: a browser's thread cannot park.
#[cfg(not(target_arch = "wasm32"))]
pub fn block_on<F: Future>(future: F) -> F::Output {
    let mut future = std::pin::pin!(future);
    let waker = Waker::from(Arc::new(ThreadWaker(std::thread::current())));
    let mut cx = Context::from_waker(&waker);
    loop {
        match future.as_mut().poll(&mut cx) {
            Poll::Ready(out) => return out,
            Poll::Pending => std::thread::park(),
        }
    }
}

/// A wgpu device with the adapter description it came from ([`acquire_device`]).
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
    /// Whether the adapter is a software rasterizer (adapter type `Cpu`, e.g. lavapipe):
    /// its pass times are CPU time.
    #[must_use]
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// One line naming the adapter and how its passes can be timed, e.g.
    /// `llvmpipe (LLVM 15.0.6, 256 bits) [Cpu, Vulkan], timing: CPU wall time ...`.
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

/// The order adapters are preferred in: hardware first, software (lavapipe) last.
#[cfg(not(target_arch = "wasm32"))]
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
/// (lavapipe), with the adapter's own limits and timestamp queries where the adapter has
/// them. It blocks until the device exists; on wasm32 it returns an error at once (a
/// page requests its adapter and device with wgpu's async calls).
///
/// # Errors
///
/// [`AdaptiveError::Device`] saying that no adapter exists (and how to install Mesa's
/// software Vulkan), or why the adapter refused the device.
pub fn acquire_device() -> Result<GpuDevice, AdaptiveError> {
    acquire(wgpu::Adapter::limits)
}

/// [`acquire_device`] with `limits` instead of the adapter's own:
/// `wgpu::Limits::default()` are WebGPU's defaults, what every browser grants, so a
/// test on such a device holds a pass to what a web page gets.
///
/// # Errors
///
/// As [`acquire_device`]; the adapter refuses limits above its own.
pub fn acquire_device_with_limits(limits: wgpu::Limits) -> Result<GpuDevice, AdaptiveError> {
    acquire(|_| limits)
}

#[cfg(target_arch = "wasm32")]
fn acquire(
    _limits: impl FnOnce(&wgpu::Adapter) -> wgpu::Limits,
) -> Result<GpuDevice, AdaptiveError> {
    Err(AdaptiveError::Device(
        "a browser cannot block on the device request: request the adapter and device \
         asynchronously"
            .into(),
    ))
}

#[cfg(not(target_arch = "wasm32"))]
fn acquire(
    limits: impl FnOnce(&wgpu::Adapter) -> wgpu::Limits,
) -> Result<GpuDevice, AdaptiveError> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let mut adapters = block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    adapters.sort_by_key(|a| rank(a.get_info().device_type));
    let Some(adapter) = adapters.into_iter().next() else {
        return Err(AdaptiveError::Device(
            "no wgpu adapter found (install a GPU driver, or Mesa's software Vulkan: \
             mesa-vulkan-drivers)"
                .into(),
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
        label: Some("spvg"),
        required_features,
        required_limits: limits(&adapter),
        ..Default::default()
    };
    let (device, queue) = block_on(adapter.request_device(&desc))
        .map_err(|e| AdaptiveError::Device(format!("{}: {e}", info.name)))?;
    Ok(GpuDevice {
        device,
        queue,
        info,
        timestamps,
    })
}
