//! The subsurface pass on a wgpu device: textures, ping-pong history, dispatch, readback.

use half::f16;

use crate::error::PassError;
use crate::frame::{FrameInputs, FrameOutput, History, Timer};
use crate::params::{Model, PassParams};
use crate::shaders;

const FMT_RGBA16F: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The subsurface pass bound to one device, image size and model. History textures are
/// allocated by model: none for a fixed count, one pair (read + write, ping-pong) for AS
/// and CCV, two pairs for OCV.
#[derive(Debug)]
pub struct GpuPass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    width: u32,
    height: u32,
    model: Model,
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    lighting: wgpu::Texture,
    depth: wgpu::Texture,
    mask: wgpu::Texture,
    result: wgpu::Texture,
    count: wgpu::Texture,
    /// `[pair][ping-pong]`: pair 0 the H texels, pair 1 the J texels (OCV).
    history: Vec<[wgpu::Texture; 2]>,
    /// Index of the history texture read this frame.
    read: usize,
    readback: wgpu::Buffer,
    timestamps: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
}

fn padded_row(width: u32, bytes_per_texel: u32) -> u32 {
    (width * bytes_per_texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
}

impl GpuPass {
    /// Builds the pipeline and textures for `model` on a `width x height` image.
    /// Creates no adapter: the caller passes its device (see [`crate::acquire_device`]).
    #[must_use]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
        model: Model,
        timestamps: bool,
    ) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sss.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shaders::sss_source().into()),
        });
        let entry = match model {
            Model::Fixed(_) => "sss_fixed",
            Model::As | Model::Ccv => "sss_adaptive",
            Model::Ocv => "sss_ocv",
        };
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: None,
            module: &module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        let levels = 32 - width.max(height).max(1).leading_zeros();
        let tex_mips = |label: &str, format, usage, mips: u32| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: width.max(1),
                    height: height.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: mips,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let tex = |label: &str, format, usage| tex_mips(label, format, usage, 1);
        let input = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
        let output = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let hist_usage = output | wgpu::TextureUsages::TEXTURE_BINDING;
        let history = (0..model.history_texels())
            .map(|k| {
                [
                    tex(&format!("history{k}a"), FMT_RGBA16F, hist_usage),
                    tex(&format!("history{k}b"), FMT_RGBA16F, hist_usage),
                ]
            })
            .collect();
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("PassParams"),
            size: size_of::<PassParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row(width.max(1), 8)) * u64::from(height.max(1)),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let timestamps = timestamps.then(|| {
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            });
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            (set, resolve, read)
        });
        Self {
            device: device.clone(),
            queue: queue.clone(),
            width,
            height,
            model,
            pipeline,
            params,
            lighting: tex_mips("lighting B", FMT_RGBA16F, input, levels),
            depth: tex("depth", wgpu::TextureFormat::R32Float, input),
            mask: tex("mask", wgpu::TextureFormat::R8Uint, input),
            result: tex("result", FMT_RGBA16F, output),
            // Also sampled: the budget reduction (`crate::reduce`) reads the counts.
            count: tex(
                "count",
                wgpu::TextureFormat::R32Uint,
                output | wgpu::TextureUsages::TEXTURE_BINDING,
            ),
            history,
            read: 0,
            readback,
            timestamps,
        }
    }

    /// The model this pass runs.
    #[must_use]
    pub fn model(&self) -> Model {
        self.model
    }

    /// The device the pass runs on.
    #[must_use]
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue the pass submits to.
    #[must_use]
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// Depth, mask and counts of the last frame and the H history the next frame reads
    /// (for `crate::reduce`); `None` without history.
    pub(crate) fn reduce_textures(
        &self,
    ) -> Option<(
        &wgpu::Texture,
        &wgpu::Texture,
        &wgpu::Texture,
        &wgpu::Texture,
    )> {
        let pair = self.history.first()?;
        Some((&self.depth, &self.mask, &self.count, &pair[self.read]))
    }

    fn upload<T: bytemuck::Pod>(&self, texture: &wgpu::Texture, data: &[T], texel_bytes: u32) {
        self.queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(self.width * texel_bytes),
                rows_per_image: Some(self.height),
            },
            self.extent(),
        );
    }

    fn extent(&self) -> wgpu::Extent3d {
        wgpu::Extent3d {
            width: self.width,
            height: self.height,
            depth_or_array_layers: 1,
        }
    }

    fn view(t: &wgpu::Texture) -> wgpu::TextureView {
        t.create_view(&wgpu::TextureViewDescriptor::default())
    }

    /// Runs one frame: uploads the inputs, dispatches, reads back the result and the
    /// counts, and swaps the history ping-pong.
    ///
    /// # Errors
    ///
    /// [`PassError::InputSize`] for inputs of another size, [`PassError::Device`] when the
    /// device is lost or a readback fails.
    pub fn run_frame(
        &mut self,
        params: &PassParams,
        inputs: &FrameInputs,
    ) -> Result<FrameOutput, PassError> {
        let n = self.width as usize * self.height as usize;
        if !inputs.is_consistent() || inputs.len() != n || inputs.width != self.width {
            return Err(PassError::InputSize {
                expected: n,
                got: inputs.lighting.len(),
            });
        }
        if n == 0 {
            return Ok(FrameOutput::default());
        }
        let mut p = *params;
        p.width = self.width;
        p.height = self.height;
        self.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        self.upload(&self.lighting, &inputs.lighting, 8);
        if p.afis != 0 {
            for (k, (mw, mh, texels)) in inputs.lighting_mips().iter().enumerate() {
                self.queue.write_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &self.lighting,
                        mip_level: k as u32 + 1,
                        origin: wgpu::Origin3d::ZERO,
                        aspect: wgpu::TextureAspect::All,
                    },
                    bytemuck::cast_slice(texels),
                    wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(mw * 8),
                        rows_per_image: Some(*mh),
                    },
                    wgpu::Extent3d {
                        width: *mw,
                        height: *mh,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
        self.upload(&self.depth, &inputs.depth, 4);
        self.upload(&self.mask, &inputs.mask, 1);

        let (r, w) = (self.read, 1 - self.read);
        let mut entries_views = vec![
            (1, Self::view(&self.lighting)),
            (2, Self::view(&self.depth)),
            (3, Self::view(&self.mask)),
            (4, Self::view(&self.result)),
            (5, Self::view(&self.count)),
        ];
        for (k, pair) in self.history.iter().enumerate() {
            let base = 6 + 2 * k as u32;
            entries_views.push((base, Self::view(&pair[r])));
            entries_views.push((base + 1, Self::view(&pair[w])));
        }
        let bind_group = crate::resources::bind_group(
            &self.device,
            Some("sss"),
            &self.pipeline.get_bind_group_layout(0),
            &[(0, &self.params)],
            &entries_views,
        );

        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("sss") });
        {
            let timestamp_writes =
                self.timestamps
                    .as_ref()
                    .map(|(set, _, _)| wgpu::ComputePassTimestampWrites {
                        query_set: set,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sss"),
                timestamp_writes,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
        }
        if let Some((set, resolve, read)) = &self.timestamps {
            encoder.resolve_query_set(set, 0..2, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16);
        }
        let start = std::time::Instant::now();
        self.queue.submit([encoder.finish()]);
        self.wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;

        let (time_ms, timer) = match &self.timestamps {
            Some((_, _, read)) => {
                let ticks: Vec<u64> = self.map_read(read, 16)?;
                let period = f64::from(self.queue.get_timestamp_period());
                match ticks.as_slice() {
                    [t0, t1] if t1 > t0 => ((t1 - t0) as f64 * period * 1e-6, Timer::GpuTimestamp),
                    _ => (wall_ms, Timer::WallClock),
                }
            }
            None => (wall_ms, Timer::WallClock),
        };
        let result: Vec<[f16; 4]> = self.read_texture(&self.result, 8)?;
        let count: Vec<u32> = self.read_texture(&self.count, 4)?;
        if !self.history.is_empty() {
            self.read = w;
        }
        Ok(FrameOutput {
            result,
            count,
            time_ms,
            timer,
        })
    }

    /// Reads back the history written by the last frame.
    ///
    /// # Errors
    ///
    /// [`PassError::Device`] when a readback fails.
    pub fn history(&self) -> Result<History, PassError> {
        let mut h = History::default();
        if let Some(pair) = self.history.first() {
            h.h = self.read_texture(&pair[self.read], 8)?;
        }
        if let Some(pair) = self.history.get(1) {
            h.j = self.read_texture(&pair[self.read], 8)?;
        }
        Ok(h)
    }

    fn wait(&self) -> Result<(), PassError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| PassError::Device(e.to_string()))
    }

    fn map_read<T: bytemuck::Pod>(
        &self,
        buffer: &wgpu::Buffer,
        bytes: u64,
    ) -> Result<Vec<T>, PassError> {
        let slice = buffer.slice(0..bytes);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.wait()?;
        rx.recv()
            .map_err(|e| PassError::Device(e.to_string()))?
            .map_err(|e| PassError::Device(e.to_string()))?;
        let out = {
            let view = slice
                .get_mapped_range()
                .map_err(|e| PassError::Device(e.to_string()))?;
            bytemuck::pod_collect_to_vec(&view)
        };
        buffer.unmap();
        Ok(out)
    }

    fn read_texture<T: bytemuck::Pod>(
        &self,
        texture: &wgpu::Texture,
        texel_bytes: u32,
    ) -> Result<Vec<T>, PassError> {
        let row = padded_row(self.width, texel_bytes);
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("readback"),
            });
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(self.height),
                },
            },
            self.extent(),
        );
        self.queue.submit([encoder.finish()]);
        let bytes: Vec<u8> =
            self.map_read(&self.readback, u64::from(row) * u64::from(self.height))?;
        let tight = (self.width * texel_bytes) as usize;
        let mut packed = Vec::with_capacity(tight * self.height as usize);
        for line in bytes.chunks(row as usize) {
            packed.extend_from_slice(line.get(..tight).unwrap_or(line));
        }
        Ok(bytemuck::pod_collect_to_vec(&packed))
    }
}
