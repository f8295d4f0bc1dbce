//! Per-call cost of the sampling primitives: exact and approximate inverse cdf, truncated
//! sampling, pcg3d16 and R2 points. Run with `cargo bench --bench burley`.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use spvg::burley::{APPROX_C_PAPER, BurleyProfile};
use spvg::sequence::{pcg3d16, r2_point, to_unit_f32};

/// A fixed set of `xi` spread over (0, 1), both halves of the exact inverse included.
fn xis() -> Vec<f64> {
    (0..1024).map(|i| (f64::from(i) + 0.5) / 1024.0).collect()
}

fn inverse(c: &mut Criterion) {
    let mut group = c.benchmark_group("burley_inverse");
    // Each iteration sweeps 1024 values: ns per call = reported time / 1024, and the
    // throughput line reads calls per second.
    group.throughput(Throughput::Elements(1024));
    let xs = xis();
    let xs32: Vec<f32> = xs.iter().map(|&x| x as f32).collect();
    let p64 = BurleyProfile::from_shape(0.8_f64, 1.0).expect("valid");
    let p32 = BurleyProfile::from_shape(0.8_f32, 1.0).expect("valid");
    group.bench_function(BenchmarkId::new("exact", "f64"), |b| {
        b.iter(|| {
            xs.iter()
                .map(|&x| p64.inverse_cdf(black_box(x)))
                .sum::<f64>()
        });
    });
    group.bench_function(BenchmarkId::new("exact", "f32"), |b| {
        b.iter(|| {
            xs32.iter()
                .map(|&x| p32.inverse_cdf(black_box(x)))
                .sum::<f32>()
        });
    });
    group.bench_function(BenchmarkId::new("approx", "f64"), |b| {
        b.iter(|| {
            xs.iter()
                .map(|&x| p64.approx_inverse_cdf(black_box(x), APPROX_C_PAPER))
                .sum::<f64>()
        });
    });
    group.bench_function(BenchmarkId::new("approx", "f32"), |b| {
        let c = APPROX_C_PAPER as f32;
        b.iter(|| {
            xs32.iter()
                .map(|&x| p32.approx_inverse_cdf(black_box(x), c))
                .sum::<f32>()
        });
    });
    group.bench_function(BenchmarkId::new("distant", "f32"), |b| {
        b.iter(|| {
            xs32.iter()
                .map(|&x| p32.sample_distant(black_box(x), 0.5).radius)
                .sum::<f32>()
        });
    });
    group.finish();
}

fn sequence(c: &mut Criterion) {
    let mut group = c.benchmark_group("sequence");
    group.throughput(Throughput::Elements(1024));
    group.bench_function("pcg3d16", |b| {
        b.iter(|| (0..1024u32).fold(0u32, |acc, i| acc ^ pcg3d16(black_box([i, 7, 3]))[0]));
    });
    group.bench_function("r2_point", |b| {
        b.iter(|| (0..1024u32).fold(0u32, |acc, i| acc ^ r2_point(black_box([5, 9]), i)[1]));
    });
    group.bench_function("r2_point_to_unit_f32", |b| {
        b.iter(|| {
            (0..1024u32)
                .map(|i| to_unit_f32(r2_point(black_box([5, 9]), i)[0]))
                .sum::<f32>()
        });
    });
    group.finish();
}

criterion_group!(benches, inverse, sequence);
criterion_main!(benches);
