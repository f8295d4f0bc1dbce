//! GPU readiness: the adaptive component's two steps (AS, with the count dilation the
//! report runs) timed at 1080p and 2160p against a copy kernel that moves the same bytes
//! on the same device, and the ratio of the two. The ratio says how far each step is from
//! the bandwidth floor of its own memory traffic; on a software adapter both figures are
//! CPU time, so only the ratio means anything there.
//!
//! Byte count: each step moves, per pixel, the texels of the frame-size textures it
//! binds ([`estimate_bytes`], [`update_bytes`]); the 1x1 placeholders bound for the
//! inputs this run leaves out (masks, gamma, reprojected depth, control) are not counted.
//! Every texel is counted once, although the estimate reads the history and previous
//! depth at a reprojected texel: the floor is one pass over each texture. The copy kernel
//! reads that many bytes from `R32Uint` textures (texture loads) and writes that many into
//! `R32Uint` storage textures, over the frame in 8x8 workgroups like the steps.

use std::fmt::Write as _;

use spvg::SpvgConfig;
use spvg_wgpu::adaptive::UpdateInputs;
use spvg_wgpu::adaptive::{AdaptivePass, COUNT_FORMAT, Control, EstimateInputs, HISTORY_FORMAT};
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use crate::error::ReportError;
use crate::timing::ms;
use crate::wgpu_api::{GpuDevice, PassError};

/// The table's heading (with its blank line), also where the table is not run.
pub const HEADING: &str = "## GPU readiness: the component's steps against a copy kernel\n\n";

/// The motion-vector format this run feeds the estimate (one of the accepted ones).
pub const MOTION_FORMAT: Tf = Tf::Rg32Float;
/// The format of the depths and the monitored value this run feeds the steps.
pub const SCALAR_FORMAT: Tf = Tf::R32Float;
/// The format of the component's link texture (estimate to update).
pub const LINK_FORMAT: Tf = Tf::R32Uint;

/// Bytes a step moves per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepBytes {
    /// Bytes read per pixel.
    pub read: u64,
    /// Bytes written per pixel.
    pub written: u64,
}

impl StepBytes {
    /// Read plus written.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.read + self.written
    }
}

fn texel(format: Tf) -> u64 {
    u64::from(format.block_copy_size(None).unwrap_or(0))
}

/// The estimate's bytes per pixel: it reads the history, the motion, the depth and the
/// previous depth, and writes the count and the link; with a dilation (`dilated`) it
/// writes the count before dilation instead, and its second pass reads that and writes
/// the dilated count.
#[must_use]
pub fn estimate_bytes(dilated: bool) -> StepBytes {
    let read = texel(HISTORY_FORMAT) + texel(MOTION_FORMAT) + 2 * texel(SCALAR_FORMAT);
    let written = texel(COUNT_FORMAT) + texel(LINK_FORMAT);
    if dilated {
        StepBytes {
            read: read + texel(COUNT_FORMAT),
            written: written + texel(COUNT_FORMAT),
        }
    } else {
        StepBytes { read, written }
    }
}

/// The update's bytes per pixel (AS: no control value, no CV history): it reads the
/// history, the monitored value, the count and the link, and writes the other history.
#[must_use]
pub fn update_bytes() -> StepBytes {
    StepBytes {
        read: texel(HISTORY_FORMAT)
            + texel(SCALAR_FORMAT)
            + texel(COUNT_FORMAT)
            + texel(LINK_FORMAT),
        written: texel(HISTORY_FORMAT),
    }
}

/// What the command runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadinessOptions {
    /// Frame sizes, `[width, height]`.
    pub sizes: Vec<[u32; 2]>,
    /// Measured frames per size (at least 1).
    pub frames: u32,
    /// Frames run first and not measured (shader compilation, first-touch allocation).
    pub warmup: u32,
    /// Count dilation radius of the component (the report's AS runs use 1).
    pub dilation: u32,
}

impl Default for ReadinessOptions {
    /// 1920x1080 and 3840x2160, 20 frames after 3 warm-up frames, dilation radius 1.
    fn default() -> Self {
        Self {
            sizes: vec![[1920, 1080], [3840, 2160]],
            frames: 20,
            warmup: 3,
            dilation: 1,
        }
    }
}

/// How the times were taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clock {
    /// GPU timestamp queries around each step's compute passes.
    Timestamps,
    /// Wall time from submit to the wait's return on a hardware adapter without
    /// timestamp queries.
    HardwareWallClock,
    /// Wall time from submit to the wait's return on a software adapter: CPU time.
    SoftwareCpuTime,
}

impl Clock {
    /// The clock of `device`: timestamps on a hardware adapter that has them; a software
    /// rasterizer's timestamps are not trusted (see `SssPass::for_device`).
    #[must_use]
    pub fn of(device: &GpuDevice) -> Self {
        if device.is_software() {
            Self::SoftwareCpuTime
        } else if device.timestamps {
            Self::Timestamps
        } else {
            Self::HardwareWallClock
        }
    }

    /// One sentence for the table.
    #[must_use]
    pub fn sentence(&self) -> &'static str {
        match self {
            Self::Timestamps => {
                "GPU timestamp queries bracketing each step's compute passes (GPU time)."
            }
            Self::HardwareWallClock => {
                "wall time from submit to completion, each step submitted alone (the adapter has no timestamp queries; submission overhead included)."
            }
            Self::SoftwareCpuTime => {
                "wall time from submit to completion on a software adapter: the figures are CPU time on this machine, and only the ratio means anything for a GPU."
            }
        }
    }
}

/// Which step a row times.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// The estimate (with the dilation pass when the radius is above 0).
    Estimate,
    /// The update.
    Update,
}

impl Step {
    /// Its name in the table.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Estimate => "estimate",
            Self::Update => "update",
        }
    }
}

/// One table row: a step at a size against its copy kernel (median times, ms).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Frame size.
    pub size: [u32; 2],
    /// The step.
    pub step: Step,
    /// Its bytes per pixel, which the copy kernel moves too.
    pub bytes: StepBytes,
    /// Median step time (ms).
    pub step_ms: f64,
    /// Median copy-kernel time (ms).
    pub copy_ms: f64,
}

impl Row {
    /// Step time over copy time.
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.step_ms / self.copy_ms
    }
}

/// The command's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Readiness {
    /// The adapter, in words.
    pub adapter: String,
    /// How the times were taken.
    pub clock: Clock,
    /// Timed samples where the timestamps came back unordered and the wall time stood in.
    pub wall_fallbacks: u32,
    /// What ran.
    pub options: ReadinessOptions,
    /// The rows, per size the estimate then the update.
    pub rows: Vec<Row>,
}

/// Runs the steps and their copy kernels on `device` at each size of `opts`.
///
/// # Errors
///
/// [`ReportError::Usage`] for no frames or a size the device cannot hold (naming it), a
/// component error, or a device failure.
pub fn run(device: &GpuDevice, opts: &ReadinessOptions) -> Result<Readiness, ReportError> {
    if opts.frames == 0 {
        return Err(ReportError::Usage(
            "frames: at least 1 measured frame".into(),
        ));
    }
    let clock = Clock::of(device);
    let mut timer = Timer::new(device, clock == Clock::Timestamps);
    let mut rows = Vec::new();
    for &size in &opts.sizes {
        device.check_frame(size[0], size[1])?;
        rows.extend(run_size(device, &mut timer, size, opts)?);
    }
    Ok(Readiness {
        adapter: format!(
            "{} [{:?}, {:?}]",
            device.info.name, device.info.device_type, device.info.backend
        ),
        clock,
        wall_fallbacks: timer.fallbacks,
        options: opts.clone(),
        rows,
    })
}

fn run_size(
    d: &GpuDevice,
    timer: &mut Timer,
    size: [u32; 2],
    opts: &ReadinessOptions,
) -> Result<[Row; 2], ReportError> {
    let [w, h] = size;
    let config = SpvgConfig::builder().target_variance(1e-4).build()?;
    let mut pass =
        AdaptivePass::new(&d.device, config, Control::As, w, h).map_err(PassError::from)?;
    pass.set_count_dilation(opts.dilation)
        .map_err(PassError::from)?;
    let inputs = Inputs::new(d, size);
    let est = estimate_bytes(opts.dilation > 0);
    let upd = update_bytes();
    let est_copy = CopyKernel::new(d, size, est)?;
    let upd_copy = CopyKernel::new(d, size, upd)?;
    let mut times: [Vec<f64>; 4] = Default::default();
    for f in 0..opts.warmup + opts.frames {
        let e = timer.measure(d, |enc, stamps| {
            let i = EstimateInputs {
                motion: &inputs.motion,
                depth: &inputs.depth,
                previous_depth: &inputs.depth,
                reprojected_depth: None,
                masks: None,
                gamma: None,
            };
            pass.record_estimate_timed(enc, &i, stamps)
                .map_err(|e| PassError::from(e).into())
        })?;
        let value = &inputs.value[(f % 2) as usize];
        let u = timer.measure(d, |enc, stamps| {
            let i = UpdateInputs {
                value,
                control: None,
            };
            pass.record_update_timed(enc, &i, stamps)
                .map_err(|e| PassError::from(e).into())
        })?;
        let ce = timer.measure(d, |enc, stamps| {
            est_copy.record(enc, stamps);
            Ok(())
        })?;
        let cu = timer.measure(d, |enc, stamps| {
            upd_copy.record(enc, stamps);
            Ok(())
        })?;
        if f >= opts.warmup {
            for (v, t) in times.iter_mut().zip([e, u, ce, cu]) {
                v.push(t);
            }
        }
    }
    let [e, u, ce, cu] = times.map(median);
    Ok([
        Row {
            size,
            step: Step::Estimate,
            bytes: est,
            step_ms: e,
            copy_ms: ce,
        },
        Row {
            size,
            step: Step::Update,
            bytes: upd,
            step_ms: u,
            copy_ms: cu,
        },
    ])
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// The steps' inputs: a pan of 1.5 px right and 0.5 px up over a sloped surface (so most
/// histories stay valid, as in a moving camera), and two noisy monitored values taken in
/// turn (so the controller sees variance).
struct Inputs {
    motion: wgpu::Texture,
    depth: wgpu::Texture,
    value: [wgpu::Texture; 2],
}

/// A hash in [0, 1) of a pixel and a seed (plausible noise, not a quality RNG).
fn noise(x: u32, y: u32, seed: u32) -> f32 {
    let mut v = x.wrapping_mul(0x9E37_79B9) ^ y.wrapping_mul(0x85EB_CA6B) ^ seed;
    v ^= v >> 16;
    v = v.wrapping_mul(0x7FEB_352D);
    v ^= v >> 15;
    (v >> 8) as f32 / (1u32 << 24) as f32
}

impl Inputs {
    fn new(d: &GpuDevice, [w, h]: [u32; 2]) -> Self {
        let pixels = |f: &dyn Fn(u32, u32) -> Vec<f32>| -> Vec<u8> {
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .flat_map(|(x, y)| f(x, y))
                .flat_map(f32::to_le_bytes)
                .collect()
        };
        let motion = upload(
            d,
            "readiness motion",
            MOTION_FORMAT,
            [w, h],
            &pixels(&|_, _| vec![1.5, -0.5]),
        );
        let depth = upload(
            d,
            "readiness depth",
            SCALAR_FORMAT,
            [w, h],
            &pixels(&|x, y| vec![2.0 + 3.0 * y as f32 / h as f32 + 0.5 * x as f32 / w as f32]),
        );
        let value = [1, 2].map(|seed| {
            upload(
                d,
                "readiness value",
                SCALAR_FORMAT,
                [w, h],
                &pixels(&|x, y| vec![0.4 + 0.2 * noise(x, y, seed)]),
            )
        });
        Self {
            motion,
            depth,
            value,
        }
    }
}

fn texture(d: &GpuDevice, label: &str, format: Tf, [w, h]: [u32; 2], usage: Tu) -> wgpu::Texture {
    d.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A sampled texture holding `data` (tightly packed rows).
fn upload(d: &GpuDevice, label: &str, format: Tf, [w, h]: [u32; 2], data: &[u8]) -> wgpu::Texture {
    let t = texture(d, label, format, [w, h], Tu::TEXTURE_BINDING | Tu::COPY_DST);
    d.queue.write_texture(
        t.as_image_copy(),
        data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * format.block_copy_size(None).unwrap_or(0)),
            rows_per_image: Some(h),
        },
        t.size(),
    );
    t
}

/// The copy kernel of one step: `read / 4` source planes and `written / 4` destination
/// planes, `R32Uint`, the frame size; each invocation loads its texel of every source,
/// folds them (so no load is dead) and stores into every destination.
struct CopyKernel {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    size: [u32; 2],
}

/// The copy kernel's WGSL for `sources` and `destinations` planes.
fn copy_wgsl(sources: u32, destinations: u32) -> String {
    let mut s = String::new();
    for k in 0..sources {
        let _ = writeln!(s, "@group(0) @binding({k}) var src{k}: texture_2d<u32>;");
    }
    for k in 0..destinations {
        let _ = writeln!(
            s,
            "@group(0) @binding({}) var dst{k}: texture_storage_2d<r32uint, write>;",
            sources + k
        );
    }
    s.push_str(
        "@compute @workgroup_size(8, 8)\nfn copy(@builtin(global_invocation_id) id: vec3<u32>) {\n\
         \x20   let size = textureDimensions(dst0);\n\
         \x20   if (id.x >= size.x || id.y >= size.y) { return; }\n\
         \x20   let p = vec2<i32>(id.xy);\n\
         \x20   var acc = 0u;\n",
    );
    for k in 0..sources {
        let _ = writeln!(s, "    acc ^= textureLoad(src{k}, p, 0).x;");
    }
    for k in 0..destinations {
        let _ = writeln!(
            s,
            "    textureStore(dst{k}, p, vec4<u32>(acc + {k}u, 0u, 0u, 0u));"
        );
    }
    s.push_str("}\n");
    s
}

impl CopyKernel {
    fn new(d: &GpuDevice, size: [u32; 2], bytes: StepBytes) -> Result<Self, ReportError> {
        let word = texel(Tf::R32Uint);
        if !bytes.read.is_multiple_of(word)
            || !bytes.written.is_multiple_of(word)
            || bytes.written == 0
        {
            return Err(ReportError::Usage(format!(
                "copy kernel: {} bytes read and {} written per pixel are not whole, non-zero \
                 4-byte words",
                bytes.read, bytes.written
            )));
        }
        let (sources, destinations) = ((bytes.read / word) as u32, (bytes.written / word) as u32);
        let module = d.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("readiness copy"),
            source: wgpu::ShaderSource::Wgsl(copy_wgsl(sources, destinations).into()),
        });
        let pipeline = d
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("readiness copy"),
                layout: None,
                module: &module,
                entry_point: Some("copy"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            });
        // Sources filled with noise, so a GPU cannot skip the reads of cleared memory.
        let [w, h] = size;
        let words: Vec<u8> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .flat_map(|(x, y)| noise(x, y, 7).to_bits().to_le_bytes())
            .collect();
        let planes: Vec<wgpu::Texture> = (0..sources)
            .map(|_| upload(d, "readiness copy source", Tf::R32Uint, size, &words))
            .chain((0..destinations).map(|_| {
                texture(
                    d,
                    "readiness copy destination",
                    Tf::R32Uint,
                    size,
                    Tu::STORAGE_BINDING,
                )
            }))
            .collect();
        let views: Vec<wgpu::TextureView> = planes
            .iter()
            .map(|t| t.create_view(&wgpu::TextureViewDescriptor::default()))
            .collect();
        let entries: Vec<wgpu::BindGroupEntry<'_>> = views
            .iter()
            .zip(0..)
            .map(|(v, binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(v),
            })
            .collect();
        let group = d.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("readiness copy"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        Ok(Self {
            pipeline,
            group,
            size,
        })
    }

    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let [w, h] = self.size;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("readiness copy"),
            timestamp_writes,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
}

/// Times one submission: by its two timestamps when there are queries, else by wall time
/// from submit to the wait's return.
struct Timer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    fallbacks: u32,
}

impl Timer {
    fn new(d: &GpuDevice, timestamps: bool) -> Self {
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
    fn measure(
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

/// The table's markdown, headed `## GPU readiness`.
#[must_use]
pub fn markdown(r: &Readiness) -> String {
    let mut s = String::new();
    let o = &r.options;
    let e = estimate_bytes(o.dilation > 0);
    let u = update_bytes();
    let _ = writeln!(
        s,
        "## GPU readiness: the component's steps against a copy kernel\n"
    );
    let _ = writeln!(
        s,
        "Adapter: {}. Times: {} The component runs AS with count dilation radius {}; {} \
         measured frames per size (after {} warm-up), each step submitted alone, the \
         median per step. \
         The copy kernel reads from `R32Uint` textures and writes `R32Uint` storage \
         textures, over the frame in 8x8 workgroups, the bytes of the frame-size textures \
         each step binds, per pixel: the estimate {} read + {} written (reads the history \
         `Rgba16Float` 8, motion `Rg32Float` 8, depth and previous depth `R32Float` 4 + 4{}; \
         writes {}), the update {} read + {} written (reads the history 8, the value \
         `R32Float` 4, the count and the link `R32Uint` 4 + 4; writes the other history 8). \
         Ratio = step / copy: how far the step is from moving its bytes alone.\n",
        r.adapter,
        r.clock.sentence(),
        o.dilation,
        o.frames,
        o.warmup,
        e.read,
        e.written,
        if o.dilation > 0 {
            ", the count before dilation `R32Uint` 4"
        } else {
            ""
        },
        if o.dilation > 0 {
            "the count before dilation, the link and the dilated count `R32Uint` 4 + 4 + 4"
        } else {
            "the count and the link `R32Uint` 4 + 4"
        },
        u.read,
        u.written,
    );
    if r.wall_fallbacks > 0 {
        let _ = writeln!(
            s,
            "{} timed samples came back with unordered timestamps; their wall time stands \
             in.\n",
            r.wall_fallbacks
        );
    }
    let _ = writeln!(
        s,
        "| size | step | bytes/pixel | step (ms) | copy (ms) | ratio (step / copy) |"
    );
    let _ = writeln!(s, "| --- | --- | --- | --- | --- | --- |");
    for row in &r.rows {
        let [w, h] = row.size;
        let _ = writeln!(
            s,
            "| {w}x{h} | {} | {} | {} | {} | {:.2} |",
            row.step.name(),
            row.bytes.total(),
            ms(row.step_ms),
            ms(row.copy_ms),
            row.ratio()
        );
    }
    s
}
