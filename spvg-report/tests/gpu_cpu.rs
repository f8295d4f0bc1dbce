//! The wgpu pass against its CPU twin on small scenes, every model, a few frames.
//!
//! Tolerances and why: the twin mirrors the WGSL op by op, rounds every stored texel to
//! f16 the same way (the shader rounds explicitly to nearest-even before the store, because
//! lavapipe's own f32 -> f16 store conversion truncates), and uses polynomial sin/cos, so
//! the remaining differences come from the drivers' exp/log/pow/sqrt (a few ulp). Those can
//! move a sample across a texel boundary or `n_hat` across an integer, after which the
//! pixel's history legitimately diverges. So: counts equal on >= 99% of pixels per frame,
//! and result luminance within 2e-3 on >= 99% of pixels.

mod common;

use spvg::burley::MaterialPreset;
use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_report::metrics::rgb;
use spvg_report::scene::{Scene, SceneKind};
use spvg_wgpu::sss::luminance;
use spvg_wgpu::sss::{Model, PassConfig, SssPass, SssTwin};

const TOL: f32 = 2e-3;
const MIN_AGREE: f64 = 0.99;

/// The fraction of pixels where `agree` holds between the GPU's and the twin's values.
fn agreeing<T>(gpu: &[T], cpu: &[T], agree: impl Fn(&T, &T) -> bool) -> f64 {
    gpu.iter().zip(cpu).filter(|(x, y)| agree(x, y)).count() as f64 / gpu.len().max(1) as f64
}

fn compare(kind: SceneKind, size: u32, frames: u32, material: &MaterialPreset, cfg: PassConfig) {
    let Some(dev) = common::device("gpu_matches_cpu_twin") else {
        return;
    };
    let scene = Scene::new(kind, size, size);
    for model in [Model::Fixed(16), Model::As, Model::Ccv, Model::Ocv] {
        let mut gpu = SssPass::for_device(&dev, model, size, size);
        let mut cpu = SssTwin::new(model, (size * size) as usize);
        for t in 0..frames {
            let inputs = scene.inputs(t);
            let p = cfg
                .params(model, material, size, size, t)
                .expect("valid params");
            let a = gpu.run_frame(&p, &inputs).expect("gpu frame");
            let b = cpu.run_frame(&p, &inputs).expect("cpu frame");
            let same = agreeing(&a.count, &b.count, |x, y| x == y);
            let lum_diff = |x: &[half::f16; 4], y: &[half::f16; 4]| {
                (luminance(rgb(*x)) - luminance(rgb(*y))).abs()
            };
            let close = agreeing(&a.result, &b.result, |x, y| lum_diff(x, y) <= TOL);
            let identical = agreeing(&a.result, &b.result, |x, y| x == y);
            let max_diff = a
                .result
                .iter()
                .zip(&b.result)
                .map(|(x, y)| lum_diff(x, y))
                .fold(0.0_f32, f32::max);
            eprintln!(
                "{} {} frame {t}: counts equal {same:.4}, results within {TOL} {close:.4}, bit-identical {identical:.4}, max |dlum| {max_diff:.2e}",
                kind.name(),
                model.name(),
            );
            assert!(
                same >= MIN_AGREE,
                "{kind:?} {model:?} frame {t}: counts equal on {same} < {MIN_AGREE}"
            );
            assert!(
                close >= MIN_AGREE,
                "{kind:?} {model:?} frame {t}: results close on {close} < {MIN_AGREE}"
            );
        }
        let (ha, hb) = (gpu.history().expect("history"), cpu.history());
        assert_eq!(ha.h.len(), hb.h.len(), "{model:?}: history sizes");
        assert_eq!(ha.j.len(), hb.j.len(), "{model:?}: J sizes");
        // History: bit-identical on most texels; where the GPU's own rounding (fused
        // multiply-adds, few-ulp exp/log) differs, CCV's monitored value is a difference of
        // nearly equal numbers, so low bits of its mean and variance can differ; and a pixel
        // whose result legitimately diverged (a sample across a texel boundary, see above)
        // carries the difference into its variance, so closeness is asked of >= 99% of the
        // texels like the results, not of every one.
        for (name, a, b) in [("H", &ha.h, &hb.h), ("J", &ha.j, &hb.j)] {
            if a.is_empty() {
                continue;
            }
            let same = agreeing(a, b, |x, y| x == y);
            let diff = |x: &[half::f16; 4], y: &[half::f16; 4]| {
                let mut d = [0.0_f32; 4];
                for c in 0..4 {
                    d[c] = (x[c].to_f32() - y[c].to_f32()).abs() / y[c].to_f32().abs().max(1.0);
                }
                d
            };
            let close = agreeing(a, b, |x, y| diff(x, y).iter().all(|v| *v <= 0.05));
            let mut worst = [0.0_f32; 4];
            for (x, y) in a.iter().zip(b.iter()) {
                let d = diff(x, y);
                for c in 0..4 {
                    worst[c] = worst[c].max(d[c]);
                }
            }
            eprintln!(
                "{} {} {name}: texels bit-identical {same:.4}, within 0.05 {close:.4}, worst relative channel diff {worst:?}",
                kind.name(),
                model.name()
            );
            assert!(
                same >= 0.9,
                "{kind:?} {model:?} {name}: identical on {same} < 0.9"
            );
            assert!(
                close >= MIN_AGREE,
                "{kind:?} {model:?} {name}: within 0.05 on {close} < {MIN_AGREE} (worst {worst:?})"
            );
        }
    }
}

#[test]
fn gpu_matches_cpu_twin_flash() {
    compare(SceneKind::Flash, 48, 5, &SKIN1, PassConfig::default());
}

#[test]
fn gpu_matches_cpu_twin_occluders() {
    compare(SceneKind::Occluders, 48, 5, &MARBLE, PassConfig::default());
}

#[test]
fn gpu_matches_cpu_twin_with_filtered_sampling() {
    let cfg = PassConfig {
        afis: true,
        ..PassConfig::default()
    };
    compare(SceneKind::Switch, 40, 4, &SKIN1, cfg);
}
