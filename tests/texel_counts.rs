//! How much f16 storage changes the sample counts, against f64 state (figures printed
//! with `cargo test --test texel_counts -- --nocapture`).
//!
//! Scene: one pixel, 300 frames at 60 fps, the docs/algorithms.md §7 *switch* lighting (a light on for
//! 3 s, then off leaving 10% ambient) with a small 7 Hz flicker of 2%, `gamma = 0.5`,
//! `B = I(t)`, a distant estimate with mean `1.2 I(t)` and per-sample relative standard
//! deviation 0.1 (so about 36 samples reach the target at full light). The Monte Carlo
//! error of the frame is `sd / sqrt(n) z_t` with one standard normal `z_t` per frame
//! shared by every run (common random numbers), so runs differ only through their counts.
//! The luminance scale `k` multiplies all radiances and `sigma0^2 = 1e-4 k^2`, so the
//! controller behaves the same at every scale in exact arithmetic and any difference is
//! storage precision: `k = 1e-4` puts the dark phase (1e-5) in f16's subnormals, `k = 1e4`
//! puts the lit phase near f16's top (65504). OCV uses `eta_cv = 0.05` and
//! `eps_a = 1e-6 k^2` (an absolute regulariser must scale with the variances, or OCV
//! becomes CCV at `k = 1e-4` whatever the storage).

use spvg::cv::{As, Ccv, Ocv, PixelController, PixelFrame};
use spvg::texel::{
    CvTexel16, CvTexel32, FrameInputs, Rounding, SpvgTexel16, SpvgTexel32, Texel, TexelEncoding,
    estimate_frame, update_frame, update_frame_ocv,
};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

const FRAMES: usize = 300;

#[derive(Clone, Copy, Debug)]
enum Model {
    As,
    Ccv,
    Ocv,
}

/// Standard normals from a fixed xorshift stream (Box-Muller).
fn normals(n: usize) -> Vec<f64> {
    let mut s = 0x853c_49e6_748f_ea9b_u64;
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let (a, b) = (u(), u());
            (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
        })
        .collect()
}

fn light(t: usize) -> f64 {
    let base = if t < 180 { 1.0 } else { 0.1 };
    base * (1.0 + 0.02 * (std::f64::consts::TAU * 7.0 * t as f64 / 60.0).sin())
}

/// `(L_o, B, gamma)` of frame `t` with `n` samples at luminance scale `k`.
fn frame(t: usize, n: u32, z: f64, k: f64) -> (f64, f64, f64) {
    let i = light(t) * k;
    let gamma = 0.5;
    let ls = 1.2 * i * (1.0 + 0.1 * z / f64::from(n.max(1)).sqrt());
    ((1.0 - gamma) * i + gamma * ls, i, gamma)
}

fn config<T: num_traits::Float>(k: f64) -> SpvgConfig<T> {
    SpvgConfig::builder()
        .target_variance(T::from(1e-4 * k * k).unwrap())
        .build()
        .unwrap()
}

/// Counts with f64 state, straight through the per-pixel controller.
fn run_f64(model: Model, k: f64, z: &[f64]) -> Vec<u32> {
    let c = config::<f64>(k);
    let mut h = SpvgHistory::<f64>::default();
    let mut j = CvHistory::<f64>::default();
    let mut out = Vec::with_capacity(FRAMES);
    for (t, &zt) in z.iter().enumerate() {
        let valid = t > 0;
        let (l, b, gamma) = frame(t, 0, 0.0, k);
        let _ = l;
        let n = c.estimate_with_validity(&h, gamma, valid);
        let (l, b2, _) = frame(t, n, zt, k);
        debug_assert!(b == b2, "B does not depend on the count");
        let f = PixelFrame {
            radiance: l,
            preintegrated: b,
            gamma,
        };
        match model {
            Model::As => PixelController::new(c, As).update(&mut h, &mut (), f, n, valid),
            Model::Ccv => PixelController::new(c, Ccv).update(&mut h, &mut (), f, n, valid),
            Model::Ocv => PixelController::new(c, Ocv::new(0.05, 1e-6 * k * k, 1.0).unwrap())
                .update(&mut h, &mut j, f, n, valid),
        };
        out.push(n);
    }
    out
}

/// Counts with texel storage between frames, through the frame functions on one pixel.
fn run_texel<H, C>(model: Model, k: f64, z: &[f64], stochastic: bool) -> Vec<u32>
where
    H: Texel<History = SpvgHistory<f32>> + Default,
    C: Texel<History = CvHistory<f32>> + Default,
{
    let c = config::<f32>(k);
    let enc = TexelEncoding::new(c.target_variance()).unwrap();
    let mut h = [H::default()];
    let mut j = [C::default()];
    let mut out = Vec::with_capacity(FRAMES);
    for (t, &zt) in z.iter().enumerate() {
        let valid = [u8::from(t > 0)];
        let gamma = [0.5_f32];
        let mut n = [0_u32];
        estimate_frame(&c, &enc, &h, &gamma, &valid, &mut n).unwrap();
        let (l, b, _) = frame(t, n[0], zt, k);
        let (l, b) = ([l as f32], [b as f32]);
        let inputs = FrameInputs {
            radiance: &l,
            preintegrated: &b,
            gamma: &gamma,
            count: &n,
            valid: &valid,
        };
        let r = if stochastic {
            Rounding::Stochastic((t as u32).wrapping_mul(0x9e37_79b9))
        } else {
            Rounding::Nearest
        };
        match model {
            Model::As => update_frame(&PixelController::new(c, As), &enc, r, &inputs, &mut h),
            Model::Ccv => update_frame(&PixelController::new(c, Ccv), &enc, r, &inputs, &mut h),
            Model::Ocv => update_frame_ocv(
                &PixelController::new(c, Ocv::new(0.05, (1e-6 * k * k) as f32, 1.0).unwrap()),
                &enc,
                r,
                &inputs,
                &mut h,
                &mut j,
            ),
        }
        .unwrap();
        out.push(n[0]);
    }
    out
}

struct Diff {
    mean_abs: f64,
    max: u32,
    frac: f64,
    mean_count: f64,
}

fn diff(a: &[u32], reference: &[u32]) -> Diff {
    let d: Vec<u32> = a
        .iter()
        .zip(reference)
        .map(|(x, y)| x.abs_diff(*y))
        .collect();
    Diff {
        mean_abs: d.iter().map(|&v| f64::from(v)).sum::<f64>() / d.len() as f64,
        max: d.iter().copied().max().unwrap_or(0),
        frac: d.iter().filter(|&&v| v != 0).count() as f64 / d.len() as f64,
        mean_count: a.iter().map(|&v| f64::from(v)).sum::<f64>() / a.len() as f64,
    }
}

#[test]
fn f16_storage_count_error_against_f64_state() {
    let z = normals(FRAMES);
    println!("scale  model layout      mean_n  ref_n  mean|dn|  max|dn|  frames_diff");
    for k in [1.0, 1e-4, 1e4] {
        for model in [Model::As, Model::Ccv, Model::Ocv] {
            let reference = run_f64(model, k, &z);
            let runs = [
                (
                    "f32",
                    run_texel::<SpvgTexel32, CvTexel32>(model, k, &z, false),
                ),
                (
                    "f16 RN",
                    run_texel::<SpvgTexel16, CvTexel16>(model, k, &z, false),
                ),
                (
                    "f16 SR",
                    run_texel::<SpvgTexel16, CvTexel16>(model, k, &z, true),
                ),
            ];
            let ref_mean = diff(&reference, &reference).mean_count;
            for (name, counts) in &runs {
                let d = diff(counts, &reference);
                println!(
                    "{k:>6.0e} {model:>5?} {name:<8} {:>8.2} {ref_mean:>6.2} {:>9.3} {:>8} {:>11.3}",
                    d.mean_count, d.mean_abs, d.max, d.frac
                );
                // Bounds: storage must not shift the average count by more than one
                // sample, nor the mean absolute difference exceed 2 samples (3% of the
                // budget); f32 state must stay within one sample nearly always.
                let shift = (d.mean_count - ref_mean).abs();
                assert!(
                    shift <= 1.0,
                    "{k} {model:?} {name}: mean count {} vs {ref_mean}",
                    d.mean_count
                );
                assert!(
                    d.mean_abs <= 2.0,
                    "{k} {model:?} {name}: mean |dn| {} (tol 2)",
                    d.mean_abs
                );
                if *name == "f32" {
                    assert!(
                        d.mean_abs <= 0.1,
                        "{k} {model:?} f32: mean |dn| {} (tol 0.1)",
                        d.mean_abs
                    );
                }
            }
        }
    }
}
