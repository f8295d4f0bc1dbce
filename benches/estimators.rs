//! Cost of one update of each estimator (f32 and f64), and of one frame of per-pixel EMV
//! updates over 1,000,000 pixels (criterion reports the time per pixel).
//!
//! `cargo bench --bench estimators -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use half::f16;
use num_traits::Float;
use spvg::stats::{Ema, Emc, Emcm, Emv, Ewma, Weight};

fn weight<T: Float>() -> Weight<T> {
    T::from(0.05)
        .and_then(|eta| Weight::new(eta).ok())
        .unwrap_or_else(Weight::one)
}

fn c<T: Float>(v: f64) -> T {
    T::from(v).unwrap_or_else(T::zero)
}

/// One benchmark per type: a single update from a fixed state, so every iteration does
/// the same work.
macro_rules! single_update {
    ($crit:expr, $group:literal, |$t:ident| $state:expr, |$s:ident, $w:ident| $update:expr) => {{
        let mut group = $crit.benchmark_group($group);
        {
            type $t = f32;
            let state = $state;
            let $w = weight::<$t>();
            group.bench_function(BenchmarkId::from_parameter("f32"), |b| {
                b.iter(|| {
                    let mut $s = black_box(state);
                    $update;
                    $s
                })
            });
        }
        {
            type $t = f64;
            let state = $state;
            let $w = weight::<$t>();
            group.bench_function(BenchmarkId::from_parameter("f64"), |b| {
                b.iter(|| {
                    let mut $s = black_box(state);
                    $update;
                    $s
                })
            });
        }
        group.finish();
    }};
}

fn estimators(crit: &mut Criterion) {
    single_update!(crit, "Ema", |T| Ema::<T>::seeded(c(0.5)), |s, w| s
        .update(black_box(&w), black_box(c(0.7))));
    single_update!(
        crit,
        "Emv",
        |T| Emv::<T>::from_parts(c(0.5), c(0.01)),
        |s, w| s.update(black_box(&w), black_box(c(0.7)))
    );
    single_update!(
        crit,
        "Emc",
        |T| Emc::<T>::from_parts(c(0.5), c(0.2), c(0.01)),
        |s, w| s.update(black_box(&w), black_box(c(0.7)), black_box(c(0.1)))
    );
    single_update!(
        crit,
        "Emcm<2>",
        |T| Emcm::<T, 2>::seeded([c(0.5), c(0.2)]),
        |s, w| s.update(black_box(&w), black_box([c(0.7), c(0.1)]))
    );
    single_update!(
        crit,
        "Emcm<3>",
        |T| Emcm::<T, 3>::seeded([c(0.5), c(0.2), c(0.9)]),
        |s, w| s.update(black_box(&w), black_box([c(0.7), c(0.1), c(0.8)]))
    );
    single_update!(
        crit,
        "Ewma<2>",
        |T| Ewma::<T, 2>::seeded([c(0.5), c(0.2)]),
        |s, w| s.update(black_box(&w), black_box([c(0.7), c(0.1)]))
    );
}

const PIXELS: usize = 1_000_000;

/// A deterministic frame of luminance-like samples.
fn frame<T: Float>() -> Vec<T> {
    (0..PIXELS)
        .map(|i| c::<T>(0.5 + 0.25 * ((i % 97) as f64 / 97.0 - 0.5)))
        .collect()
}

fn frame_of_emv(crit: &mut Criterion) {
    let mut group = crit.benchmark_group("Emv frame (1M pixels)");
    group.throughput(Throughput::Elements(PIXELS as u64));
    group.sample_size(20);
    {
        let (w, xs) = (weight::<f32>(), frame::<f32>());
        let mut states = vec![Emv::<f32>::from_parts(0.5, 0.01); PIXELS];
        group.bench_function(BenchmarkId::from_parameter("f32"), |b| {
            b.iter(|| {
                for (s, &x) in states.iter_mut().zip(&xs) {
                    s.update(black_box(&w), x);
                }
            });
        });
    }
    {
        let (w, xs) = (weight::<f64>(), frame::<f64>());
        let mut states = vec![Emv::<f64>::from_parts(0.5, 0.01); PIXELS];
        group.bench_function(BenchmarkId::from_parameter("f64"), |b| {
            b.iter(|| {
                for (s, &x) in states.iter_mut().zip(&xs) {
                    s.update(black_box(&w), x);
                }
            });
        });
    }
    {
        // A half-float history texture: f16 storage, f32 arithmetic.
        let (w, xs) = (weight::<f32>(), frame::<f32>());
        let mut texels = vec![[f16::from_f32(0.5), f16::from_f32(0.01)]; PIXELS];
        group.bench_function(BenchmarkId::from_parameter("f32 compute, f16 store"), |b| {
            b.iter(|| {
                for (t, &x) in texels.iter_mut().zip(&xs) {
                    let mut s = Emv::from_parts(t[0].to_f32(), t[1].to_f32());
                    s.update(black_box(&w), x);
                    *t = [f16::from_f32(s.mean()), f16::from_f32(s.variance())];
                }
            });
        });
    }
    group.finish();
}

criterion_group!(benches, estimators, frame_of_emv);
criterion_main!(benches);
