//! Small wgpu helpers the component is built with, public so that a renderer's own passes,
//! tests and tools use them instead of copies: 2D textures and their mip-0 views, compute
//! pipelines of one bind group, bind groups of whole buffers and views, 8x8 dispatches,
//! texture and buffer readback, and a blocking executor for wgpu's futures.

use std::sync::Arc;
use std::task::{Context, Poll, Wake, Waker};

use crate::adaptive::AdaptiveError;

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

/// Maps the first `bytes` of `buffer` (with `MAP_READ` usage), waits for the device and
/// returns them as values of type `T`; the buffer is unmapped again.
///
/// # Errors
///
/// [`AdaptiveError::Device`] with the device's or the mapping's error message.
pub fn read_buffer<T: bytemuck::Pod>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<T>, AdaptiveError> {
    let device_error = |e: String| AdaptiveError::Device(e);
    let slice = buffer.slice(0..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| device_error(e.to_string()))?;
    rx.recv()
        .map_err(|e| device_error(e.to_string()))?
        .map_err(|e| device_error(e.to_string()))?;
    let out = {
        let mapped = slice
            .get_mapped_range()
            .map_err(|e| device_error(e.to_string()))?;
        bytemuck::pod_collect_to_vec(&mapped)
    };
    buffer.unmap();
    Ok(out)
}

/// Copies mip 0 of `texture` (with `COPY_SRC` usage) back to the host as tightly packed
/// texels of type `T` (`T` the texel's size: `u32` for `R32Uint`, `[half::f16; 4]` for
/// `Rgba16Float`, ...). Blocks until the copy is done.
///
/// # Errors
///
/// [`AdaptiveError::TextureUsage`] without `COPY_SRC`, [`AdaptiveError::TextureFormat`]
/// when `T` is not the texel size, [`AdaptiveError::Device`] when the device fails.
pub fn read_texture<T: bytemuck::Pod>(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<T>, AdaptiveError> {
    if !texture.usage().contains(wgpu::TextureUsages::COPY_SRC) {
        return Err(AdaptiveError::TextureUsage {
            input: "texture",
            missing: wgpu::TextureUsages::COPY_SRC,
        });
    }
    let texel = texture.format().block_copy_size(None).unwrap_or(0);
    if texel as usize != size_of::<T>() {
        return Err(AdaptiveError::TextureFormat {
            input: "texture",
            got: texture.format(),
            allowed: &[],
        });
    }
    let s = texture.size();
    let row = (s.width * texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let bytes = u64::from(row) * u64::from(s.height);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(s.height),
            },
        },
        wgpu::Extent3d {
            depth_or_array_layers: 1,
            ..s
        },
    );
    queue.submit([encoder.finish()]);
    let padded: Vec<u8> = read_buffer(device, &buffer, bytes)?;
    let tight = (s.width * texel) as usize;
    let mut packed = Vec::with_capacity(tight * s.height as usize);
    for line in padded.chunks(row as usize) {
        packed.extend_from_slice(line.get(..tight).unwrap_or(line));
    }
    Ok(bytemuck::pod_collect_to_vec(&packed))
}

/// Wakes the thread that blocks on a future.
struct ThreadWaker(std::thread::Thread);

impl Wake for ThreadWaker {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.0.unpark();
    }
}

/// Runs a future to completion on the calling thread, parking it between polls (wgpu's
/// adapter and device requests; what `pollster::block_on` does, on std alone).
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
/// them.
///
/// # Errors
///
/// [`AdaptiveError::Device`] saying that no adapter exists (and how to install Mesa's
/// software Vulkan), or why the adapter refused the device.
pub fn acquire_device() -> Result<GpuDevice, AdaptiveError> {
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
        required_limits: adapter.limits(),
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
