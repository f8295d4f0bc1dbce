//! The GPU form of the frame budget governor's inputs (`spvg::budget`,
//! docs/algorithms.md §8.2): a reduction pass (`sss/shaders/reduce.wgsl`) that sums, over a
//! frame, the counts the frame used and the clamped [`DemandCurve`] of the history the
//! next frame reads: at each of the `CURVE_POINTS` candidate targets the governor
//! chose ([`Governor::curve_targets`](spvg::budget::Governor::curve_targets)), the counts
//! the next frame's pixels would take there ([`spvg::budget::count_at`]).
//!
//! # Latency
//!
//! Frame `t` is rendered with the target `sigma0^2_t`. Right after its update pass the
//! reduction reads the history it wrote (`H_t`, what frame `t + 1` reads) and its counts,
//! and writes one [`DemandPartial`] per 8x8 workgroup; the partials come back with frame
//! `t`'s results and are summed on the CPU ([`FrameSums::from_partials`]). Then,
//! before frame `t + 1` is submitted, `Governor::observe(N_t)` and
//! `Governor::plan_curve(curve(H_t))` give `sigma0^2_{t+1}`. So the feed-forward sees exactly
//! the history the next frame estimates from (no latency), and a frame's total first acts
//! on the next frame's target (feedback latency 1, the pole `1 - g` of
//! docs/algorithms.md §8.2). This costs one GPU-CPU round trip per frame; a renderer that
//! pipelines frames and reads the partials back one frame later plans `t + 2` from them
//! (feedback latency 2, feed-forward one frame stale), which the default gain 1/4 still
//! handles without overshoot.
//!
//! The zero-sample rule of the next frame needs its distant ratio, which depends on its
//! depth; the reduction uses frame `t`'s depth and mask and reads each pixel's own texel
//! (the subsurface scenes have a static camera, so the component reprojects every pixel
//! onto itself; a pixel whose depth or mask changes next frame is counted as the history
//! says, one frame of latency like the feedback).
//!
//! The H texels are the adaptive component's ([`spvg_wgpu::adaptive::AdaptivePass::history_texture`],
//! `spvg::texel::SpvgTexel16` with the spare channel 1 where the texel was written): the
//! reduction decodes them with the block's scales (which the pass checks equal the
//! component's, [`spvg_wgpu::adaptive::AdaptivePass::encoding`]) and takes the spare channel as
//! the validity flag, as the component's estimate does.
//!
//! # Scope
//!
//! [`ReducePass`] takes the depth, mask, count and history textures, the subsurface
//! pass's uniform block and the candidate targets. It belongs to the subsurface pass: the
//! next frame's zero-sample rule needs each pixel's distant-energy ratio, which it
//! computes with the pass's own `pixel_gamma_s` (the Burley profiles of
//! [`PassParams`]) and the assumption that each pixel reprojects onto itself (a static
//! camera). Another consumer needs its own gamma and reprojection in the reduction.

use half::f16;
use spvg::SpvgConfig;
use spvg::budget::{CURVE_POINTS, DemandCurve};
use spvg::texel::TexelEncoding;

use crate::error::PassError;
use crate::gpu::{bind_group, compute_pipeline, dispatch_8x8, read_buffer, shader_module, view};
use crate::sss::twin::{self, BlockTwin, REDUCE_TILE};
use crate::sss::{FrameInputs, FrameOutput, PassParams, SssPass, SssRunner, reduce_source};

/// One workgroup's partial sums: the counts of its pixels at each candidate target (the
/// clamped demand curve of the next frame) and the counts the frame used, each
/// saturating at `u32::MAX`.
///
/// WGSL twin: `struct DemandPartial` in `sss/shaders/reduce.wgsl`, same field order, 68 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DemandPartial {
    /// At candidate `j`, the sum of [`spvg::budget::count_at`] over the workgroup's
    /// pixels.
    pub curve: [u32; CURVE_POINTS],
    /// The counts the frame used.
    pub count: u32,
}

const _: () = assert!(
    size_of::<DemandPartial>() == 4 * (CURVE_POINTS + 1),
    "DemandPartial must match the 68-byte WGSL struct"
);

/// The reduced inputs of the governor for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSums {
    /// The clamped demand curve of the history the next frame reads.
    pub curve: DemandCurve<f64>,
    /// The frame's total sample count.
    pub total: u64,
}

impl FrameSums {
    /// Sums the partials (exactly, in `u64`) of a reduction that ran with the candidate
    /// targets `targets`.
    #[must_use]
    pub fn from_partials(partials: &[DemandPartial], targets: &[f32; CURVE_POINTS]) -> Self {
        let mut curve = [0_u64; CURVE_POINTS];
        let mut total = 0_u64;
        for p in partials {
            for (s, c) in curve.iter_mut().zip(p.curve) {
                *s += u64::from(c);
            }
            total += u64::from(p.count);
        }
        Self {
            // u64 -> f64 is exact below 2^53 (more than 2^26 pixels at 2^27 samples).
            curve: DemandCurve {
                targets: targets.map(f64::from),
                totals: curve.map(|n| n as f64),
            },
            total,
        }
    }
}

/// The reduction pipeline on one device for a `width x height` image.
#[derive(Debug)]
pub struct ReducePass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    width: u32,
    height: u32,
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    candidates: wgpu::Buffer,
    partials: wgpu::Buffer,
    readback: wgpu::Buffer,
}

/// The textures the reduction reads, all `width x height`: depth (`R32Float`), mask
/// (`R8Uint`), the frame's counts (`R32Uint`) and the H history the next frame reads
/// (`Rgba16Float`); each needs `TEXTURE_BINDING` usage.
#[derive(Clone, Copy, Debug)]
pub struct ReduceInputs<'a> {
    /// Depth of the frame.
    pub depth: &'a wgpu::Texture,
    /// Subsurface mask of the frame.
    pub mask: &'a wgpu::Texture,
    /// Counts the frame used.
    pub count: &'a wgpu::Texture,
    /// SPVG history texels written by the frame.
    pub history: &'a wgpu::Texture,
}

impl ReducePass {
    /// Builds the pipeline and buffers. Creates no adapter.
    #[must_use]
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, width: u32, height: u32) -> Self {
        let module = shader_module(device, "reduce.wgsl", reduce_source());
        let pipeline = compute_pipeline(device, &module, "reduce_demand", None);
        let groups = u64::from(width.div_ceil(REDUCE_TILE).max(1))
            * u64::from(height.div_ceil(REDUCE_TILE).max(1));
        let bytes = groups * size_of::<DemandPartial>() as u64;
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            device: device.clone(),
            queue: queue.clone(),
            width,
            height,
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("reduce PassParams"),
                size: size_of::<PassParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            candidates: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("reduce candidate targets"),
                size: size_of::<[f32; CURVE_POINTS]>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            partials: buffer(
                "demand partials",
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "demand partials readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            pipeline,
        }
    }

    /// Records the reduction and the copy of its partials into `encoder` (after the
    /// frame's update pass, in the same submission) and writes `params` (the frame's
    /// block; only its controller fields, texel scales, profile and size are read) and
    /// the candidate targets `targets` (non-decreasing, e.g.
    /// `Governor::curve_targets` rounded to `f32`) to the queue. Read the partials with
    /// [`read_partials`](Self::read_partials) once the submission is done.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        params: &PassParams,
        targets: &[f32; CURVE_POINTS],
        inputs: ReduceInputs<'_>,
    ) {
        let mut p = *params;
        p.width = self.width;
        p.height = self.height;
        self.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        self.queue
            .write_buffer(&self.candidates, 0, bytemuck::bytes_of(targets));
        let views = [
            (2, view(inputs.depth)),
            (3, view(inputs.mask)),
            (4, view(inputs.count)),
            (5, view(inputs.history)),
        ];
        let group = bind_group(
            &self.device,
            Some("reduce"),
            &self.pipeline.get_bind_group_layout(0),
            &[
                (0, &self.params),
                (6, &self.partials),
                (7, &self.candidates),
            ],
            &views,
        );
        // REDUCE_TILE = 8: one workgroup per 8x8 tile.
        let size = [self.width, self.height];
        dispatch_8x8(encoder, "reduce_demand", &self.pipeline, &group, None, size);
        encoder.copy_buffer_to_buffer(&self.partials, 0, &self.readback, 0, self.partials.size());
    }

    /// Maps the partials copied by the last [`encode`](Self::encode) (waits for the
    /// device).
    ///
    /// # Errors
    ///
    /// [`PassError::Device`] when the device is lost or the mapping fails.
    pub fn read_partials(&self) -> Result<Vec<DemandPartial>, PassError> {
        read_buffer(&self.device, &self.readback, self.readback.size()).map_err(PassError::from)
    }

    /// Encodes, submits and reads back the reduction in one call.
    ///
    /// # Errors
    ///
    /// As [`read_partials`](Self::read_partials).
    pub fn run(
        &self,
        params: &PassParams,
        targets: &[f32; CURVE_POINTS],
        inputs: ReduceInputs<'_>,
    ) -> Result<Vec<DemandPartial>, PassError> {
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reduce"),
            });
        self.encode(&mut encoder, params, targets, inputs);
        self.queue.submit([encoder.finish()]);
        self.read_partials()
    }
}

/// The reduction for a [`SssRunner`]: the wgpu pass for a GPU runner (on its
/// textures), the twin ([`twin::reduce_demand`]) for the CPU one.
#[derive(Debug)]
pub enum Reducer {
    /// On the runner's device.
    Gpu(Box<ReducePass>),
    /// The CPU twin.
    Cpu,
}

impl Reducer {
    /// The reduction matching `runner`, for its image size.
    #[must_use]
    pub fn for_runner(runner: &SssRunner, width: u32, height: u32) -> Self {
        match runner {
            SssRunner::Gpu(g) => Self::Gpu(Box::new(ReducePass::new(
                g.device(),
                g.queue(),
                width,
                height,
            ))),
            SssRunner::Cpu(_) => Self::Cpu,
        }
    }

    /// The partials of the frame `runner` has just run (`params` and `inputs` of that
    /// frame, `out` its output), over the history it wrote, at the candidate targets
    /// `targets`. A runner of a fixed-count model keeps no history: its pixels read as
    /// invalid histories.
    ///
    /// # Errors
    ///
    /// A GPU readback failure, or a block the twin rejects.
    pub fn partials(
        &self,
        runner: &SssRunner,
        params: &PassParams,
        targets: &[f32; CURVE_POINTS],
        inputs: &FrameInputs,
        out: &FrameOutput,
    ) -> Result<Vec<DemandPartial>, PassError> {
        match (self, runner) {
            (Self::Gpu(r), SssRunner::Gpu(g)) => match g.reduce_inputs() {
                Some(t) => r.run(params, targets, t),
                None => cpu_partials(
                    g.block_controller(),
                    params,
                    targets,
                    inputs,
                    &[],
                    &out.count,
                ),
            },
            (_, SssRunner::Cpu(c)) => cpu_partials(
                c.block_controller(),
                params,
                targets,
                inputs,
                &c.history().h,
                &out.count,
            ),
            (Self::Cpu, SssRunner::Gpu(g)) => {
                let h = g.history()?.h;
                cpu_partials(
                    g.block_controller(),
                    params,
                    targets,
                    inputs,
                    &h,
                    &out.count,
                )
            }
        }
    }
}

fn cpu_partials(
    controller: Option<(SpvgConfig<f32>, TexelEncoding)>,
    params: &PassParams,
    targets: &[f32; CURVE_POINTS],
    inputs: &FrameInputs,
    history: &[[f16; 4]],
    count: &[u32],
) -> Result<Vec<DemandPartial>, PassError> {
    let Some((config, enc)) = controller else {
        return Err(PassError::Param(spvg::Error::InconsistentParameters {
            names: "runner, params",
            expected: "a frame run from the runner's frame_params",
        }));
    };
    let mut p = *params;
    p.width = inputs.width;
    p.height = inputs.height;
    let tw = BlockTwin::new(&p, &config, enc)?;
    Ok(twin::reduce_demand(&tw, targets, inputs, history, count))
}

impl SssPass {
    /// The textures [`ReducePass`] reads after the last frame (its depth and mask, and the
    /// adaptive component's counts and current H history, what the next frame reads);
    /// `None` for a model without history or before the first frame.
    #[must_use]
    pub fn reduce_inputs(&self) -> Option<ReduceInputs<'_>> {
        let (depth, mask, count, history) = self.reduce_textures()?;
        Some(ReduceInputs {
            depth,
            mask,
            count,
            history,
        })
    }
}
