//! The component's wgpu utilities, written once here and called by its consumers too
//! (`ao`, `sss`: they depend on the component, not the other way round): 2D textures,
//! views, WGSL assembly, compute pipelines, bind groups, 8x8 dispatches, buffer mapping
//! and texture readback, and a blocking executor for wgpu's futures.

use std::sync::Arc;
use std::task::{Context, Poll, Wake, Waker};

use super::AdaptiveError;

/// A 2D texture of one mip level and one sample.
pub(crate) fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    format: wgpu::TextureFormat,
    size: [u32; 2],
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&texture_2d_desc(label, format, size, usage))
}

/// The descriptor of [`texture_2d`] (for `create_texture_with_data`).
pub(crate) fn texture_2d_desc(
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
pub(crate) fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        base_mip_level: 0,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

/// Uploads `data`, tightly packed rows of `texel_bytes`-byte texels, to the whole of mip
/// `mip_level` of `texture`, which is `[w, h]` texels.
pub(crate) fn write_texture_level(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    mip_level: u32,
    data: &[u8],
    texel_bytes: u32,
    [w, h]: [u32; 2],
) {
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * texel_bytes),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

/// One WGSL module source from its parts, in order (a plain concatenation: the library
/// first, then the files that call it), each preceded by a comment naming it.
pub(crate) fn assemble(parts: &[(&str, &str)]) -> String {
    let mut s = String::new();
    for (name, src) in parts {
        s.push_str("// ---- ");
        s.push_str(name);
        s.push('\n');
        s.push_str(src);
    }
    s
}

/// Compiles a WGSL module source.
pub(crate) fn shader_module(
    device: &wgpu::Device,
    label: &str,
    source: String,
) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// The compute pipeline of `entry` in `module`, labelled with the entry point's name; its
/// layout is `layout`'s single bind group (group 0), or derived from the shader (`None`).
pub(crate) fn compute_pipeline(
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
pub(crate) fn bind_group(
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
pub(crate) fn dispatch_8x8(
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
/// The device's or the mapping's error message.
pub(crate) fn map_buffer<T: bytemuck::Pod>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<T>, String> {
    let slice = buffer.slice(0..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    rx.recv()
        .map_err(|e| e.to_string())?
        .map_err(|e| e.to_string())?;
    let out = {
        let mapped = slice.get_mapped_range().map_err(|e| e.to_string())?;
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
    let padded: Vec<u8> = map_buffer(device, &buffer, bytes).map_err(AdaptiveError::Device)?;
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
pub(crate) fn block_on<F: Future>(future: F) -> F::Output {
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

/// Writes one `R32Float` image of `size`.
pub(crate) fn write_scalar(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    size: [u32; 2],
    data: &[f32],
) {
    write_texture_level(queue, texture, 0, bytemuck::cast_slice(data), 4, size);
}
