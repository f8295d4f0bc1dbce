//! Texture and buffer readback: blocking for native tools and tests ([`read_buffer`],
//! [`read_texture`]), asynchronous for a browser, which cannot block
//! ([`read_buffer_async`], [`read_texture_async`]).
//!
//! Both forms map the buffer with `map_async`; they differ only in how they wait for the
//! map's callback. The blocking form polls the device until the work is done, which a
//! native backend allows. The async form is a future that completes when the callback
//! runs: on WebGPU the browser runs it from its event loop while the page's code awaits;
//! on a native backend nothing runs callbacks unless the device is polled, so each poll
//! of the future polls the device once without blocking and asks to be polled again.

use std::future::Future;
use std::pin::Pin;
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Context, Poll, Waker};

use crate::adaptive::AdaptiveError;

fn device_error(e: impl ToString) -> AdaptiveError {
    AdaptiveError::Device(e.to_string())
}

/// Maps the first `bytes` of `buffer` (with `MAP_READ` usage), waits for the device and
/// returns them as values of type `T`; the buffer is unmapped again.
///
/// On wasm32 it waits for nothing: a browser cannot block, so it returns
/// [`AdaptiveError::Device`] at once; use [`read_buffer_async`] there.
///
/// # Errors
///
/// [`AdaptiveError::Device`] with the device's or the mapping's error message.
pub fn read_buffer<T: bytemuck::Pod>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<T>, AdaptiveError> {
    if cfg!(target_arch = "wasm32") {
        return Err(device_error(
            "a blocking readback cannot wait in a browser: use read_buffer_async",
        ));
    }
    let slice = buffer.slice(0..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(device_error)?;
    rx.recv().map_err(device_error)?.map_err(device_error)?;
    take_mapped(buffer, bytes)
}

/// [`read_buffer`] without blocking: maps the first `bytes` of `buffer` (with `MAP_READ`
/// usage) and completes with them as values of type `T` once the map's callback has
/// run; the buffer is unmapped again. On a native backend each poll of the future polls
/// the device once (without waiting) and wakes itself; in a browser the callback wakes
/// it.
///
/// # Errors
///
/// [`AdaptiveError::Device`] with the mapping's error message.
pub async fn read_buffer_async<T: bytemuck::Pod>(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<T>, AdaptiveError> {
    let mapped = MapFuture::new(device.clone());
    let state = Arc::clone(&mapped.state);
    buffer
        .slice(0..bytes)
        .map_async(wgpu::MapMode::Read, move |r| {
            let mut s = state.lock().unwrap_or_else(PoisonError::into_inner);
            s.result = Some(r.map_err(device_error));
            if let Some(w) = s.waker.take() {
                w.wake();
            }
        });
    mapped.await?;
    take_mapped(buffer, bytes)
}

/// Copies the mapped first `bytes` of `buffer` out and unmaps it.
fn take_mapped<T: bytemuck::Pod>(
    buffer: &wgpu::Buffer,
    bytes: u64,
) -> Result<Vec<T>, AdaptiveError> {
    let out = {
        let mapped = buffer
            .slice(0..bytes)
            .get_mapped_range()
            .map_err(device_error)?;
        bytemuck::pod_collect_to_vec(&mapped)
    };
    buffer.unmap();
    Ok(out)
}

/// What the map's callback and the future share.
#[derive(Default)]
struct MapState {
    result: Option<Result<(), AdaptiveError>>,
    waker: Option<Waker>,
}

/// Completes when a `map_async` callback has stored its result.
struct MapFuture {
    device: wgpu::Device,
    state: Arc<Mutex<MapState>>,
}

impl MapFuture {
    fn new(device: wgpu::Device) -> Self {
        Self {
            device,
            state: Arc::default(),
        }
    }
}

impl Future for MapFuture {
    type Output = Result<(), AdaptiveError>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        // Native backends run callbacks from `poll` only; on WebGPU this does nothing.
        if let Err(e) = self.device.poll(wgpu::PollType::Poll) {
            return Poll::Ready(Err(device_error(e)));
        }
        let mut s = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(r) = s.result.take() {
            return Poll::Ready(r);
        }
        s.waker = Some(cx.waker().clone());
        if cfg!(not(target_arch = "wasm32")) {
            // Nothing else will run the callback on a native backend: come back.
            cx.waker().wake_by_ref();
        }
        Poll::Pending
    }
}

/// A texture copy on its way to the host: the mappable buffer and its row layout.
struct TextureCopy {
    buffer: wgpu::Buffer,
    /// Bytes per row in the buffer (padded to `COPY_BYTES_PER_ROW_ALIGNMENT`).
    row: u32,
    /// Bytes per row of texels.
    tight: u32,
    height: u32,
}

impl TextureCopy {
    /// Checks `texture` against `T`, and records and submits the copy of its mip 0.
    fn submit<T>(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        texture: &wgpu::Texture,
    ) -> Result<Self, AdaptiveError> {
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
        let tight = s.width * texel;
        let row = tight.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(row) * u64::from(s.height),
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
        Ok(Self {
            buffer,
            row,
            tight,
            height: s.height,
        })
    }

    fn bytes(&self) -> u64 {
        u64::from(self.row) * u64::from(self.height)
    }

    /// The mapped rows without their padding, as texels of type `T`.
    fn unpack<T: bytemuck::Pod>(&self, padded: &[u8]) -> Vec<T> {
        let tight = self.tight as usize;
        let mut packed = Vec::with_capacity(tight * self.height as usize);
        for line in padded.chunks(self.row as usize) {
            packed.extend_from_slice(line.get(..tight).unwrap_or(line));
        }
        bytemuck::pod_collect_to_vec(&packed)
    }
}

/// Copies mip 0 of `texture` (with `COPY_SRC` usage) back to the host as tightly packed
/// texels of type `T` (`T` the texel's size: `u32` for `R32Uint`, `[half::f16; 4]` for
/// `Rgba16Float`, ...). Blocks until the copy is done; on wasm32 it returns
/// [`AdaptiveError::Device`] at once instead (use [`read_texture_async`] there).
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
    let copy = TextureCopy::submit::<T>(device, queue, texture)?;
    let padded: Vec<u8> = read_buffer(device, &copy.buffer, copy.bytes())?;
    Ok(copy.unpack(&padded))
}

/// [`read_texture`] without blocking, for wasm32 (a browser's WebGPU) and async native
/// code: submits the copy at once (so it sees the work submitted before the call) and
/// completes with the texels when the mapping is done ([`read_buffer_async`] says how it
/// waits on each platform).
///
/// # Errors
///
/// As [`read_texture`].
///
/// # Examples
///
/// In a browser, inside the page's async frame loop:
///
/// ```no_run
/// # async fn frame(device: &wgpu::Device, queue: &wgpu::Queue, count: &wgpu::Texture)
/// #     -> Result<(), spvg_wgpu::adaptive::AdaptiveError> {
/// let counts: Vec<u32> = spvg_wgpu::util::read_texture_async(device, queue, count).await?;
/// # let _ = counts; Ok(()) }
/// ```
pub fn read_texture_async<'a, T: bytemuck::Pod>(
    device: &'a wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> impl Future<Output = Result<Vec<T>, AdaptiveError>> + use<'a, T> {
    // The copy is recorded and submitted now, not when the future is first polled, so
    // that readbacks issued one after another see the queue in the order of the calls.
    let copy = TextureCopy::submit::<T>(device, queue, texture);
    async move {
        let copy = copy?;
        let padded: Vec<u8> = read_buffer_async(device, &copy.buffer, copy.bytes()).await?;
        Ok(copy.unpack(&padded))
    }
}
