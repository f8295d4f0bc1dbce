//! Timing one submission: two timestamp queries around its compute passes where the
//! adapter's are trusted, else wall time from submit to the wait's return.

use crate::error::ReportError;
use crate::wgpu_api::{GpuDevice, PassError};

/// Times one submission: by its two timestamps when there are queries, else by wall time
/// from submit to the wait's return.
pub(super) struct Timer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    pub(super) fallbacks: u32,
}

impl Timer {
    pub(super) fn new(d: &GpuDevice, timestamps: bool) -> Self {
        let queries = timestamps.then(|| {
            let set = d.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("readiness"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            });
            let buffer = |usage| {
                d.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("readiness timestamps"),
                    size: 16,
                    usage,
                    mapped_at_creation: false,
                })
            };
            let resolve = buffer(wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
            let read = buffer(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
            (set, resolve, read)
        });
        Self {
            queries,
            fallbacks: 0,
        }
    }

    /// Records with `record` (given the timestamp writes to pass on), submits, waits and
    /// returns the time in ms.
    pub(super) fn measure(
        &mut self,
        d: &GpuDevice,
        record: impl FnOnce(
            &mut wgpu::CommandEncoder,
            Option<wgpu::ComputePassTimestampWrites<'_>>,
        ) -> Result<(), ReportError>,
    ) -> Result<f64, ReportError> {
        let mut encoder = d
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("readiness"),
            });
        let writes = self
            .queries
            .as_ref()
            .map(|(set, _, _)| wgpu::ComputePassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: Some(0),
                end_of_pass_write_index: Some(1),
            });
        record(&mut encoder, writes)?;
        if let Some((set, resolve, read)) = &self.queries {
            encoder.resolve_query_set(set, 0..2, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16);
        }
        let device_error = |e: String| ReportError::Pass(PassError::Device(e));
        let start = std::time::Instant::now();
        d.queue.submit([encoder.finish()]);
        d.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| device_error(e.to_string()))?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        let Some((_, _, read)) = &self.queries else {
            return Ok(wall_ms);
        };
        let ticks = read_ticks(d, read).map_err(device_error)?;
        if ticks[1] > ticks[0] {
            let period = f64::from(d.queue.get_timestamp_period());
            Ok((ticks[1] - ticks[0]) as f64 * period * 1e-6)
        } else {
            self.fallbacks += 1;
            Ok(wall_ms)
        }
    }
}

/// Maps the readback buffer's two timestamps.
fn read_ticks(d: &GpuDevice, read: &wgpu::Buffer) -> Result<[u64; 2], String> {
    let slice = read.slice(0..16);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    d.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    rx.recv()
        .map_err(|e| e.to_string())?
        .map_err(|e| e.to_string())?;
    let ticks = {
        let mapped = slice.get_mapped_range().map_err(|e| e.to_string())?;
        let word = |k: usize| {
            let mut b = [0u8; 8];
            b.copy_from_slice(&mapped[8 * k..8 * k + 8]);
            u64::from_le_bytes(b)
        };
        [word(0), word(1)]
    };
    read.unmap();
    Ok(ticks)
}
