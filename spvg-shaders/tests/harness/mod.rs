//! The compute harness of `tests/equality.rs`: runs a WGSL snippet that calls the library
//! once per case on a wgpu adapter and compares the output words with the core crate's.

use std::sync::OnceLock;

use spvg_gpu_test::{GpuDevice, GpuTest, Skip};
use spvg_shaders::{Params, WGSL};

/// The harness's device (the workspace's GPU test helper acquires it).
pub(crate) type Gpu = GpuDevice;

/// The shared device, or `None` after printing why the harness is skipped
/// ([`spvg_gpu_test::GpuTest`]'s policy: a failure under `SPVG_REQUIRE_GPU=1`).
pub(crate) fn gpu(test: &str) -> Option<&'static GpuDevice> {
    static GPU: OnceLock<Result<GpuDevice, Skip>> = OnceLock::new();
    let test = GpuTest::new(test);
    test.outcome(GPU.get_or_init(|| test.try_device()).as_ref())
}

/// A batch of cases run under one parameter block: `inw` input words per case.
pub(crate) struct Batch {
    pub(crate) params: Params,
    pub(crate) input: Vec<u32>,
}

/// The host shader around a function body. The body reads case words with `f(b + k)`
/// (as f32) and `w(b + k)` (as u32), and writes output words with `o(r + k, x)` (f32)
/// or `ou(r + k, x)` (u32); `P` is the parameter block.
fn kernel(body: &str, inw: usize, outw: usize) -> String {
    format!(
        "{WGSL}
@group(0) @binding(0) var<uniform> P: spvg_Params;
@group(0) @binding(1) var<storage, read> inp: array<u32>;
@group(0) @binding(2) var<storage, read_write> outp: array<u32>;
fn f(k: u32) -> f32 {{ return bitcast<f32>(inp[k]); }}
fn w(k: u32) -> u32 {{ return inp[k]; }}
fn o(k: u32, v: f32) {{ outp[k] = bitcast<u32>(v); }}
fn ou(k: u32, v: u32) {{ outp[k] = v; }}
fn ob(k: u32, v: bool) {{ outp[k] = select(0u, 1u, v); }}
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    let i = id.x;
    // Every kernel binds P, whether the function under test reads it or not.
    _ = P.young;
    if (i >= arrayLength(&outp) / {outw}u) {{ return; }}
    let b = i * {inw}u;
    let r = i * {outw}u;
    {body}
}}
"
    )
}

/// The harness's one operation on its device.
pub(crate) trait Run {
    /// Runs `body` on every batch; returns the output words of each batch.
    fn run(&self, body: &str, inw: usize, outw: usize, batches: &[Batch]) -> Vec<Vec<u32>>;
}

impl Run for Gpu {
    fn run(&self, body: &str, inw: usize, outw: usize, batches: &[Batch]) -> Vec<Vec<u32>> {
        let d = &self.device;
        let src = kernel(body, inw, outw);
        let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("equality"),
            source: wgpu::ShaderSource::Wgsl(src.into()),
        });
        let pipeline = d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: None,
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        batches
            .iter()
            .map(|batch| {
                let n = batch.input.len() / inw;
                let buffer = |size: u64, usage| {
                    d.create_buffer(&wgpu::BufferDescriptor {
                        label: None,
                        size,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                let uniform = buffer(
                    size_of::<Params>() as u64,
                    wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                );
                self.queue
                    .write_buffer(&uniform, 0, bytemuck::bytes_of(&batch.params));
                let in_bytes = (batch.input.len().max(1) * 4) as u64;
                let input = buffer(
                    in_bytes,
                    wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                );
                self.queue
                    .write_buffer(&input, 0, bytemuck::cast_slice(&batch.input));
                let out_bytes = (n * outw * 4) as u64;
                let output = buffer(
                    out_bytes,
                    wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                );
                let read = buffer(
                    out_bytes,
                    wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                );
                let bg = d.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: None,
                    layout: &pipeline.get_bind_group_layout(0),
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: uniform.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: input.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: output.as_entire_binding(),
                        },
                    ],
                });
                let mut enc = d.create_command_encoder(&Default::default());
                {
                    let mut pass = enc.begin_compute_pass(&Default::default());
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &bg, &[]);
                    pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
                }
                enc.copy_buffer_to_buffer(&output, 0, &read, 0, out_bytes);
                self.queue.submit([enc.finish()]);
                read.slice(..)
                    .map_async(wgpu::MapMode::Read, |r| assert!(r.is_ok(), "map failed"));
                d.poll(wgpu::PollType::wait_indefinitely()).expect("poll");
                let words: Vec<u32> = bytemuck::pod_collect_to_vec(
                    &read.slice(..).get_mapped_range().expect("mapped"),
                );
                read.unmap();
                words
            })
            .collect()
    }
}

/// How one output word is compared.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Word {
    /// An integer or a flag: equal bits.
    U32,
    /// An f32: equal bits, except that every NaN equals every NaN (IEEE leaves the payload
    /// and sign of a produced NaN open).
    F32,
    /// An f32 from device transcendentals (exp, log, asinh, sinh, cosh): equal bits, or
    /// both NaN, or both finite within `rel * |cpu| + abs`.
    Approx { rel: f32, abs: f32 },
}

/// Whether the device's word `g` stands for the core's word `c`, and the relative error
/// of an `Approx` pair that is not bit-identical (0 otherwise).
fn same(kind: Word, g: u32, c: u32) -> (bool, f64) {
    let (gf, cf) = (f32::from_bits(g), f32::from_bits(c));
    match kind {
        Word::U32 => (g == c, 0.0),
        Word::F32 => (g == c || (gf.is_nan() && cf.is_nan()), 0.0),
        Word::Approx { rel, abs } => {
            if g == c || (gf.is_nan() && cf.is_nan()) {
                return (true, 0.0);
            }
            if !(gf.is_finite() && cf.is_finite()) {
                return (false, f64::INFINITY);
            }
            let err = (f64::from(gf) - f64::from(cf)).abs();
            let bound = f64::from(rel) * f64::from(cf).abs() + f64::from(abs);
            (err <= bound, err / f64::from(cf).abs().max(f64::from(abs)))
        }
    }
}

/// The outcome of one function's comparison.
pub(crate) struct Outcome {
    pub(crate) cases: usize,
    pub(crate) identical: usize,
    pub(crate) within_bound: usize,
    pub(crate) worst_relative: f64,
    pub(crate) excluded: usize,
}

/// Runs `body` on every batch and compares each case's words with `expect(batch, case)`.
/// Panics listing the first mismatches; prints the counts.
pub(crate) fn compare(
    gpu: &Gpu,
    name: &str,
    body: &str,
    inw: usize,
    kinds: &[Word],
    batches: &[Batch],
    expect: impl Fn(usize, &[u32]) -> Vec<u32>,
) -> Outcome {
    compare_or(gpu, name, body, inw, kinds, batches, |b, c| {
        (expect(b, c), None)
    })
}

/// [`compare`] where a case may also match a documented alternative (counted as within
/// the documented bound); an empty alternative excludes the case from the comparison
/// (counted and printed as excluded).
pub(crate) fn compare_or(
    gpu: &Gpu,
    name: &str,
    body: &str,
    inw: usize,
    kinds: &[Word],
    batches: &[Batch],
    expect: impl Fn(usize, &[u32]) -> (Vec<u32>, Option<Vec<u32>>),
) -> Outcome {
    let outw = kinds.len();
    let got = gpu.run(body, inw, outw, batches);
    let mut out = Outcome {
        cases: 0,
        identical: 0,
        within_bound: 0,
        worst_relative: 0.0,
        excluded: 0,
    };
    let mut bad = Vec::new();
    for (bi, (batch, g)) in batches.iter().zip(&got).enumerate() {
        for (case, gw) in batch.input.chunks(inw).zip(g.chunks(outw)) {
            out.cases += 1;
            let (cw, alt) = expect(bi, case);
            assert_eq!(cw.len(), outw, "{name}: oracle word count");
            if gw == cw.as_slice() {
                out.identical += 1;
                continue;
            }
            if alt.as_deref() == Some(gw) {
                out.within_bound += 1;
                continue;
            }
            if alt.as_ref().is_some_and(Vec::is_empty) {
                out.excluded += 1;
                continue;
            }
            let mut ok = true;
            for ((k, &gv), &cv) in kinds.iter().zip(gw).zip(&cw) {
                let (s, err) = same(*k, gv, cv);
                ok &= s;
                if s {
                    out.worst_relative = out.worst_relative.max(err);
                }
            }
            if ok {
                let exact = kinds
                    .iter()
                    .zip(gw.iter().zip(&cw))
                    .all(|(k, (g, c))| same(*k, *g, *c).1 == 0.0);
                if exact {
                    out.identical += 1;
                } else {
                    out.within_bound += 1;
                }
            } else if bad.len() < 8 {
                let show = |v: &[u32]| {
                    v.iter()
                        .map(|x| format!("{x:#010x} ({:e})", f32::from_bits(*x)))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                bad.push(format!(
                    "batch {bi}: in [{}]\n  gpu  [{}]\n  core [{}]",
                    show(case),
                    show(gw),
                    show(&cw)
                ));
            }
        }
    }
    eprintln!(
        "{name}: {} cases, {} bit-identical, {} within the documented bound (worst relative error {:.2e}), {} excluded",
        out.cases, out.identical, out.within_bound, out.worst_relative, out.excluded
    );
    assert!(
        bad.is_empty(),
        "{name}: {} or more cases differ from the core:\n{}",
        bad.len(),
        bad.join("\n")
    );
    out
}
