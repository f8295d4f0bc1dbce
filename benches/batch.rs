//! Frame update throughput at 1920x1080 and 3840x2160: the chunked frame functions (serial
//! and multi-threaded) against a straightforward per-texel loop and against a plain copy of
//! the same bytes (the memory bandwidth bound).
//!
//! Run: `cargo bench --bench batch` (the portable build, which dispatches to AVX2/FMA/F16C
//! or AVX-512 at run time, `spvg::texel::selected_loop_variant`; `SPVG_MAX_LOOP_VARIANT`
//! caps it); `bash benches/native_vs_portable.sh` runs the acceptance subset of this
//! bench for the portable and a `-C target-cpu=native` build side by side in one run.
//! `python3 benches/batch_table.py` turns criterion's estimates
//! into ns per pixel, GB/s of history and input traffic, ratios to the copy and speed-ups
//! over the scalar loop. Bytes per pixel (read + written): inputs 17 (four `f32` and a
//! `u8`), AS/CCV history 8 + 8 (`f16`) or 16 + 16 (`f32`), OCV twice that; the estimate
//! reads the history, `gamma` and `valid` and writes a `u32` count.

use std::hint::black_box;

use std::time::Duration;

use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use spvg::cv::{As, Ccv, ControlModel, Ocv, PixelController, PixelFrame};
use spvg::texel::{
    ConstantCoefficient, CvTexel16, CvTexel32, FrameInputsBuf, Rounding, SpvgTexel16, SpvgTexel32,
    Texel, TexelEncoding, estimate_frame, update_frame, update_frame_ocv,
    update_frame_ocv_parallel, update_frame_parallel,
};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

use spvg_fixtures::workload::scalar_frame_ocv;

/// The benchmarked resolutions: name and pixel count.
const RESOLUTIONS: [(&str, usize); 2] = [("1080p", 1920 * 1080), ("2160p", 3840 * 2160)];

/// Threads of the parallel variants: every hardware thread.
fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

type Group<'a> = criterion::BenchmarkGroup<'a, criterion::measurement::WallTime>;

fn history<T: Texel>(enc: &TexelEncoding, h: T::History, n: usize) -> Vec<T> {
    vec![enc.encode(&h, Rounding::Nearest); n]
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
    frame: &FrameInputsBuf,
    history: &mut [T],
    cv: &mut [<M as ControlModel<f32>>::State],
) where
    M: ControlModel<f32>,
    T: Texel<History = SpvgHistory<f32>>,
{
    let frame = frame.inputs();
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

fn rounding_of(layout: &str) -> Rounding {
    if layout.ends_with("sr") {
        Rounding::Stochastic(7)
    } else {
        Rounding::Nearest
    }
}

/// Times one frame update per iteration.
fn bench_update(
    g: &mut Group<'_>,
    id: BenchmarkId,
    mut update: impl FnMut() -> Result<(), spvg::Error>,
) {
    g.bench_function(id, |b| b.iter(|| update().unwrap()));
}

fn bench_constant<M, T>(
    g: &mut Group<'_>,
    name: &str,
    layout: &str,
    model: M,
    frame: &FrameInputsBuf,
) where
    M: ConstantCoefficient + Sync,
    T: Texel<History = SpvgHistory<f32>> + Send,
{
    let config = SpvgConfig::<f32>::published();
    let pixel = PixelController::new(config, model);
    let enc = TexelEncoding::new(config.target_variance()).unwrap();
    let mut h: Vec<T> = history(&enc, SEED_H, frame.len());
    let inputs = frame.inputs();
    let rounding = rounding_of(layout);
    bench_update(g, BenchmarkId::new(format!("{name}/batch"), layout), || {
        update_frame(
            &pixel,
            &enc,
            rounding,
            black_box(&inputs),
            black_box(&mut h),
        )
    });
    if layout.ends_with("sr") {
        return;
    }
    let threads = threads();
    bench_update(
        g,
        BenchmarkId::new(format!("{name}/parallel"), layout),
        || {
            update_frame_parallel(
                &pixel,
                &enc,
                rounding,
                black_box(&inputs),
                black_box(&mut h),
                threads,
            )
        },
    );
    let mut units = vec![(); frame.len()];
    g.bench_function(BenchmarkId::new(format!("{name}/scalar"), layout), |b| {
        b.iter(|| {
            scalar_frame(
                &pixel,
                &enc,
                black_box(frame),
                black_box(&mut h),
                &mut units,
            );
        });
    });
}

fn bench_ocv<T, C>(g: &mut Group<'_>, layout: &str, frame: &FrameInputsBuf)
where
    T: Texel<History = SpvgHistory<f32>> + Send,
    C: Texel<History = CvHistory<f32>> + Send,
{
    let config = SpvgConfig::<f32>::published();
    // f16 CV texels take the model with f16 inputs, as they should (see `Ocv`).
    let ocv = Ocv::with_weight(0.05)
        .unwrap()
        .with_f16_inputs(layout.starts_with("f16"));
    let pixel = PixelController::new(config, ocv);
    let enc = TexelEncoding::new(config.target_variance()).unwrap();
    let mut h: Vec<T> = history(&enc, SEED_H, frame.len());
    let mut j: Vec<C> = history(&enc, SEED_J, frame.len());
    let inputs = frame.inputs();
    let rounding = rounding_of(layout);
    bench_update(g, BenchmarkId::new("ocv/batch", layout), || {
        update_frame_ocv(
            &pixel,
            &enc,
            rounding,
            black_box(&inputs),
            black_box(&mut h),
            &mut j,
        )
    });
    if layout.ends_with("sr") {
        return;
    }
    let threads = threads();
    bench_update(g, BenchmarkId::new("ocv/parallel", layout), || {
        let inputs = black_box(&inputs);
        update_frame_ocv_parallel(
            &pixel,
            &enc,
            rounding,
            inputs,
            black_box(&mut h),
            &mut j,
            threads,
        )
    });
    g.bench_function(BenchmarkId::new("ocv/scalar", layout), |b| {
        b.iter(|| {
            let inputs = black_box(frame).inputs();
            scalar_frame_ocv(&pixel, &enc, &inputs, black_box(&mut h), &mut j);
        });
    });
}

/// Copies `history_bytes` of history to another buffer and reads the frame's inputs: the
/// bytes a frame update must read and write.
fn bench_copy(g: &mut Group<'_>, name: &str, history_bytes: usize, frame: &FrameInputsBuf) {
    let src = vec![1_u8; history_bytes];
    let mut dst = vec![0_u8; history_bytes];
    let frame = frame.inputs();
    g.bench_function(BenchmarkId::new("copy", name), |b| {
        b.iter(|| {
            dst.copy_from_slice(black_box(&src));
            // Read every input byte (a wrapping sum over 8-byte words vectorises and
            // keeps the read from being optimised away).
            let mut sum = 0_u64;
            for s in [
                bytemuck::cast_slice::<f32, u8>(frame.radiance),
                bytemuck::cast_slice(frame.preintegrated),
                bytemuck::cast_slice(frame.gamma),
                bytemuck::cast_slice(frame.count),
                frame.valid,
            ] {
                let words = black_box(s).chunks_exact(8);
                let tail = words.remainder().iter().map(|&b| u64::from(b));
                sum = words
                    .map(|w| u64::from_le_bytes(w.try_into().unwrap()))
                    .chain(tail)
                    .fold(sum, u64::wrapping_add);
            }
            black_box((&dst, sum));
        });
    });
}

/// [`bench_copy`] split over the parallel variants' threads (scoped, spawned per
/// iteration as theirs are), each copying and reading a contiguous part: what the memory
/// system gives that many threads, the reference for whether a threaded update is bound
/// by memory. The "of copy bandwidth" ratios stay against the one-thread copy.
fn bench_copy_parallel(
    g: &mut Group<'_>,
    name: &str,
    history_bytes: usize,
    frame: &FrameInputsBuf,
) {
    let src = vec![1_u8; history_bytes];
    let mut dst = vec![0_u8; history_bytes];
    let frame = frame.inputs();
    let n = frame.valid.len();
    let threads = threads();
    // Pixels per thread, a multiple of 8 so that every part's history bytes split evenly.
    let per = n.div_ceil(threads).div_ceil(8) * 8;
    let bytes_per_pixel = history_bytes / n;
    g.bench_function(BenchmarkId::new("copy/parallel", name), |b| {
        b.iter(|| {
            std::thread::scope(|scope| {
                let parts = dst
                    .chunks_mut(per * bytes_per_pixel)
                    .zip(src.chunks(per * bytes_per_pixel))
                    .enumerate();
                for (t, (d, s)) in parts {
                    let (lo, hi) = (t * per, ((t + 1) * per).min(n));
                    scope.spawn(move || {
                        d.copy_from_slice(black_box(s));
                        let mut sum = 0_u64;
                        for s in [
                            bytemuck::cast_slice::<f32, u8>(&frame.radiance[lo..hi]),
                            bytemuck::cast_slice(&frame.preintegrated[lo..hi]),
                            bytemuck::cast_slice(&frame.gamma[lo..hi]),
                            bytemuck::cast_slice(&frame.count[lo..hi]),
                            &frame.valid[lo..hi],
                        ] {
                            let words = black_box(s).chunks_exact(8);
                            let tail = words.remainder().iter().map(|&b| u64::from(b));
                            sum = words
                                .map(|w| u64::from_le_bytes(w.try_into().unwrap()))
                                .chain(tail)
                                .fold(sum, u64::wrapping_add);
                        }
                        black_box(sum);
                    });
                }
            });
            black_box(&dst);
        });
    });
}

fn bench_estimate(g: &mut Group<'_>, frame: &FrameInputsBuf) {
    let config = SpvgConfig::<f32>::published();
    let enc = TexelEncoding::new(config.target_variance()).unwrap();
    let n = frame.len();
    let h16: Vec<SpvgTexel16> = history(&enc, SEED_H, n);
    let h32: Vec<SpvgTexel32> = history(&enc, SEED_H, n);
    let mut counts = vec![0_u32; n];
    let frame = frame.inputs();
    g.bench_function(BenchmarkId::new("estimate/batch", "f16"), |b| {
        b.iter(|| {
            estimate_frame(
                &config,
                &enc,
                black_box(&h16),
                frame.gamma,
                frame.valid,
                &mut counts,
            )
            .unwrap();
        });
    });
    g.bench_function(BenchmarkId::new("estimate/batch", "f32"), |b| {
        b.iter(|| {
            estimate_frame(
                &config,
                &enc,
                black_box(&h32),
                frame.gamma,
                frame.valid,
                &mut counts,
            )
            .unwrap();
        });
    });
    g.bench_function(BenchmarkId::new("estimate/scalar", "f16"), |b| {
        b.iter(|| {
            for i in 0..n {
                counts[i] = config.estimate_with_validity(
                    &enc.decode(h16[i]),
                    frame.gamma[i],
                    frame.valid[i] != 0,
                );
            }
        });
    });
}

fn frame_update(c: &mut Criterion) {
    for (res, n) in RESOLUTIONS {
        let frame = workload(n);
        let mut g = c.benchmark_group(format!("frame_update_{res}"));
        g.throughput(Throughput::Elements(n as u64));
        // A frame takes milliseconds to a second: few samples of one or a few iterations
        // each keep the default run short.
        g.sample_size(10)
            .sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_secs(2));
        bench_copy(&mut g, "h16", n * 8, &frame);
        bench_copy(&mut g, "h16+j16", n * 16, &frame);
        bench_copy(&mut g, "h32+j32", n * 32, &frame);
        bench_copy_parallel(&mut g, "h16", n * 8, &frame);
        bench_copy_parallel(&mut g, "h16+j16", n * 16, &frame);
        bench_constant::<As, SpvgTexel16>(&mut g, "as", "f16", As, &frame);
        bench_constant::<As, SpvgTexel16>(&mut g, "as", "f16-sr", As, &frame);
        bench_constant::<As, SpvgTexel32>(&mut g, "as", "f32", As, &frame);
        bench_constant::<Ccv, SpvgTexel16>(&mut g, "ccv", "f16", Ccv, &frame);
        bench_constant::<Ccv, SpvgTexel32>(&mut g, "ccv", "f32", Ccv, &frame);
        bench_ocv::<SpvgTexel16, CvTexel16>(&mut g, "f16", &frame);
        bench_ocv::<SpvgTexel16, CvTexel16>(&mut g, "f16-sr", &frame);
        bench_ocv::<SpvgTexel32, CvTexel32>(&mut g, "f32", &frame);
        bench_estimate(&mut g, &frame);
        g.finish();
    }
}

criterion_group! {
    name = benches;
    // Plots of 50 big-frame benchmarks take longer than the measurements.
    config = Criterion::default().without_plots();
    targets = frame_update
}
criterion_main!(benches);

/// The fixtures' workload of `n` pixels as the frame buffer the updates read.
fn workload(n: usize) -> FrameInputsBuf {
    let mut f = FrameInputsBuf::with_capacity(n);
    for (pixel, count, valid) in spvg_fixtures::workload::frame(n) {
        f.push(pixel, count, valid);
    }
    f
}
