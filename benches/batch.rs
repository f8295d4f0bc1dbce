//! Frame update throughput at 1920x1080: the chunked frame functions against a
//! straightforward per-texel loop and against a plain copy of the same bytes (the memory
//! bandwidth bound).
//!
//! Run: `cargo bench --bench batch -- --warm-up-time 1 --measurement-time 3`
//! (add `RUSTFLAGS="-C target-cpu=native"` to compile F16C conversions in).

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::texel::{
    ConstantCoefficient, CvTexel16, CvTexel32, FrameInputs, Rounding, SpvgTexel16, SpvgTexel32,
    Texel, TexelEncoding, estimate_frame, update_frame, update_frame_ocv,
};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

const W: usize = 1920;
const H: usize = 1080;
const N: usize = W * H;

struct Frame {
    radiance: Vec<f32>,
    preintegrated: Vec<f32>,
    gamma: Vec<f32>,
    count: Vec<u32>,
    valid: Vec<u8>,
}

impl Frame {
    fn new() -> Self {
        let mut s = 0x2545_f491_u32;
        let mut u = || {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            s as f32 / u32::MAX as f32
        };
        let mut f = Frame {
            radiance: Vec::with_capacity(N),
            preintegrated: Vec::with_capacity(N),
            gamma: Vec::with_capacity(N),
            count: Vec::with_capacity(N),
            valid: Vec::with_capacity(N),
        };
        for _ in 0..N {
            let b = 0.5 + u();
            f.preintegrated.push(b);
            f.radiance.push(b * (0.9 + 0.2 * u()));
            f.gamma.push(0.2 + 0.8 * u());
            f.count.push(8 + (u() * 56.0) as u32);
            // About 2% disoccluded pixels.
            f.valid.push(u8::from(u() > 0.02));
        }
        f
    }

    fn inputs(&self) -> FrameInputs<'_> {
        FrameInputs {
            radiance: &self.radiance,
            preintegrated: &self.preintegrated,
            gamma: &self.gamma,
            count: &self.count,
            valid: &self.valid,
        }
    }

    fn input_bytes(&self) -> usize {
        N * (4 * 4 + 1)
    }
}

fn history<T: Texel>(enc: &TexelEncoding, h: T::History) -> Vec<T> {
    vec![enc.encode(&h, Rounding::Nearest); N]
}

const SEED_H: SpvgHistory<f32> = SpvgHistory {
    mean: 0.4,
    variance: 2e-4,
    mean_count: 24.0,
};
const SEED_J: CvHistory<f32> = CvHistory {
    cov_fg: 1e-3,
    var_g: 8e-4,
    mean_f: 0.5,
    mean_g: 0.4,
};

/// The straightforward scalar version: per-texel decode (`f16::to_f32` per channel), the
/// per-pixel controller in f32, per-value encode (`f16::from_f32`).
fn scalar_frame<M, T>(
    pixel: &PixelController<f32, M>,
    enc: &TexelEncoding,
    frame: &Frame,
    history: &mut [T],
    cv: &mut [<M as ControlModel<f32>>::State],
) where
    M: ControlModel<f32>,
    T: Texel<History = SpvgHistory<f32>>,
{
    for i in 0..history.len() {
        let mut h = enc.decode(history[i]);
        let f = PixelFrame {
            radiance: frame.radiance[i],
            preintegrated: frame.preintegrated[i],
            gamma: frame.gamma[i],
        };
        pixel.update(&mut h, &mut cv[i], f, frame.count[i], frame.valid[i] != 0);
        history[i] = enc.encode(&h, Rounding::Nearest);
    }
}

fn scalar_frame_ocv<T: Texel<History = SpvgHistory<f32>>, C: Texel<History = CvHistory<f32>>>(
    pixel: &PixelController<f32, Ocv<f32>>,
    enc: &TexelEncoding,
    frame: &Frame,
    history: &mut [T],
    cv: &mut [C],
) {
    for i in 0..history.len() {
        let mut h = enc.decode(history[i]);
        let mut j = enc.decode(cv[i]);
        let f = PixelFrame {
            radiance: frame.radiance[i],
            preintegrated: frame.preintegrated[i],
            gamma: frame.gamma[i],
        };
        pixel.update(&mut h, &mut j, f, frame.count[i], frame.valid[i] != 0);
        history[i] = enc.encode(&h, Rounding::Nearest);
        cv[i] = enc.encode(&j, Rounding::Nearest);
    }
}

fn bench_constant<M: ConstantCoefficient, T: Texel<History = SpvgHistory<f32>>>(
    c: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    layout: &str,
    model: M,
    frame: &Frame,
) {
    let config = SpvgConfig::<f32>::published();
    let pixel = PixelController::new(config, model);
    let enc = TexelEncoding::new(config.target_variance()).unwrap();
    let mut h: Vec<T> = history(&enc, SEED_H);
    let inputs = frame.inputs();
    let rounding = if layout.ends_with("sr") {
        Rounding::Stochastic(7)
    } else {
        Rounding::Nearest
    };
    c.bench_function(BenchmarkId::new(format!("{name}/batch"), layout), |b| {
        b.iter(|| {
            update_frame(
                &pixel,
                &enc,
                rounding,
                black_box(&inputs),
                black_box(&mut h),
            )
            .unwrap()
        })
    });
    if !layout.ends_with("sr") {
        let mut units = vec![(); N];
        c.bench_function(BenchmarkId::new(format!("{name}/scalar"), layout), |b| {
            b.iter(|| {
                scalar_frame(
                    &pixel,
                    &enc,
                    black_box(frame),
                    black_box(&mut h),
                    &mut units,
                )
            })
        });
    }
}

fn bench_ocv<T: Texel<History = SpvgHistory<f32>>, C: Texel<History = CvHistory<f32>>>(
    c: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    layout: &str,
    frame: &Frame,
) {
    let config = SpvgConfig::<f32>::published();
    let pixel = PixelController::new(config, Ocv::with_weight(0.05).unwrap());
    let enc = TexelEncoding::new(config.target_variance()).unwrap();
    let mut h: Vec<T> = history(&enc, SEED_H);
    let mut j: Vec<C> = history(&enc, SEED_J);
    let inputs = frame.inputs();
    let rounding = if layout.ends_with("sr") {
        Rounding::Stochastic(7)
    } else {
        Rounding::Nearest
    };
    c.bench_function(BenchmarkId::new("ocv/batch", layout), |b| {
        b.iter(|| {
            update_frame_ocv(
                &pixel,
                &enc,
                rounding,
                black_box(&inputs),
                black_box(&mut h),
                &mut j,
            )
            .unwrap()
        })
    });
    if !layout.ends_with("sr") {
        c.bench_function(BenchmarkId::new("ocv/scalar", layout), |b| {
            b.iter(|| scalar_frame_ocv(&pixel, &enc, black_box(frame), black_box(&mut h), &mut j))
        });
    }
}

/// Copies `history_bytes` of history and the frame's inputs: the bytes a frame update
/// must read, and the history it must write.
fn bench_copy(
    c: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    history_bytes: usize,
    frame: &Frame,
) {
    let src = vec![1_u8; history_bytes];
    let mut dst = vec![0_u8; history_bytes];
    let mut inputs = vec![0_u8; frame.input_bytes()];
    let mut _sum = 0_u64;
    c.bench_function(BenchmarkId::new("copy", name), |b| {
        b.iter(|| {
            dst.copy_from_slice(black_box(&src));
            let mut off = 0;
            for s in [
                bytemuck::cast_slice::<f32, u8>(&frame.radiance),
                bytemuck::cast_slice(&frame.preintegrated),
                bytemuck::cast_slice(&frame.gamma),
                bytemuck::cast_slice(&frame.count),
                &frame.valid,
            ] {
                inputs[off..off + s.len()].copy_from_slice(black_box(s));
                off += s.len();
            }
            black_box((&dst, &inputs));
        })
    });
}

fn frame_update(c: &mut Criterion) {
    let frame = Frame::new();
    let mut g = c.benchmark_group("frame_update_1080p");
    g.throughput(Throughput::Elements(N as u64));
    g.sample_size(10);
    bench_copy(&mut g, "h16", N * 8, &frame);
    bench_copy(&mut g, "h16+j16", N * 16, &frame);
    bench_copy(&mut g, "h32+j32", N * 32, &frame);
    bench_constant::<As, SpvgTexel16>(&mut g, "as", "f16", As, &frame);
    bench_constant::<As, SpvgTexel16>(&mut g, "as", "f16-sr", As, &frame);
    bench_constant::<As, SpvgTexel32>(&mut g, "as", "f32", As, &frame);
    bench_constant::<Ccv, SpvgTexel16>(&mut g, "ccv", "f16", Ccv, &frame);
    bench_constant::<Ccv, SpvgTexel32>(&mut g, "ccv", "f32", Ccv, &frame);
    bench_ocv::<SpvgTexel16, CvTexel16>(&mut g, "f16", &frame);
    bench_ocv::<SpvgTexel16, CvTexel16>(&mut g, "f16-sr", &frame);
    bench_ocv::<SpvgTexel32, CvTexel32>(&mut g, "f32", &frame);

    let config = SpvgConfig::<f32>::published();
    let enc = TexelEncoding::new(config.target_variance()).unwrap();
    let h16: Vec<SpvgTexel16> = history(&enc, SEED_H);
    let h32: Vec<SpvgTexel32> = history(&enc, SEED_H);
    let mut counts = vec![0_u32; N];
    g.bench_function(BenchmarkId::new("estimate/batch", "f16"), |b| {
        b.iter(|| {
            estimate_frame(
                &config,
                &enc,
                black_box(&h16),
                &frame.gamma,
                &frame.valid,
                &mut counts,
            )
            .unwrap()
        })
    });
    g.bench_function(BenchmarkId::new("estimate/batch", "f32"), |b| {
        b.iter(|| {
            estimate_frame(
                &config,
                &enc,
                black_box(&h32),
                &frame.gamma,
                &frame.valid,
                &mut counts,
            )
            .unwrap()
        })
    });
    g.bench_function(BenchmarkId::new("estimate/scalar", "f16"), |b| {
        b.iter(|| {
            for i in 0..N {
                counts[i] = config.estimate_with_validity(
                    &enc.decode(h16[i]),
                    frame.gamma[i],
                    frame.valid[i] != 0,
                );
            }
        })
    });
    g.finish();
}

criterion_group!(benches, frame_update);
criterion_main!(benches);
