//! The component's rules for odd input and odd calls: absurd
//! motion vectors are a disocclusion (the motion bound of `spvg::reproject`), negative
//! monitored values are taken as they are, a second estimate replaces the first, and a
//! resize between the steps is an error that names it. On the twin, and on the GPU
//! against the twin bit for bit (skipped without an adapter).

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveTwin, Control, EstimateData, EstimateInputs, UpdateData,
    UpdateInputs,
};
use spvg_wgpu::util::read_texture;

const W: u32 = 12;
const H: u32 = 9;
const N: usize = (W * H) as usize;

fn config() -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .target_variance(1e-3)
        .kappa(0.5)
        // the papers' seed (sigma0^2): the bad-input cases compare counts against it.
        .spatial_variance(0)
        .build()
        .expect("valid config")
}

/// Deterministic noise in [-1, 1) (splitmix-style hash).
fn noise(mut x: u64) -> f32 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^= x >> 31;
    (x >> 40) as f32 / (1u64 << 23) as f32 - 1.0
}

/// A static surface whose Monte Carlo mean of `n` samples has variance `SIGMA_SQ / n`
/// (uniform noise): the controller settles at about 8.8 spp, just above `beta_min`, the
/// regime of the outside renderer's report (where one absurd frame kept the mean above
/// 12 spp for four frames).
const SIGMA_SQ: f32 = 6.5e-3;

fn value(i: usize, t: u32, n: u32) -> f32 {
    let u = noise((u64::from(t) << 32) | i as u64);
    // Uniform on [-a, a] has variance a^2 / 3.
    let a = (3.0 * SIGMA_SQ / n.max(1) as f32).sqrt();
    0.5 + a * u
}

/// One frame on the twin with motion `v` everywhere: the counts, then the update with the
/// scene's values for those counts (scaled by `sign`).
fn twin_frame(twin: &mut AdaptiveTwin, v: [f32; 2], t: u32, sign: f32) -> Vec<u32> {
    let depth = [1.0_f32; N];
    let motion = [v; N];
    let counts = twin
        .estimate(&EstimateData::new(&motion, &depth, &depth))
        .expect("twin estimate")
        .to_vec();
    let values: Vec<f32> = (0..N).map(|i| sign * value(i, t, counts[i])).collect();
    twin.update(&UpdateData::new(&values)).expect("twin update");
    counts
}

fn mean(c: &[u32]) -> f64 {
    c.iter().map(|&n| f64::from(n)).sum::<f64>() / c.len() as f64
}

/// Absurd finite motion (`1e30`, `f32::MAX`, `-3e9`) is what NaN motion is: a
/// disocclusion, not a pan with the border prior's `beta_max`. The frame after such a
/// frame spends within 10% of the frame before.
#[test]
fn absurd_motion_is_a_disocclusion() {
    let settle = 40;
    let run = |bad: [f32; 2]| {
        let mut twin =
            AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
        let mut means = Vec::new();
        let mut frames = Vec::new();
        for t in 0..settle + 6 {
            let v = if t == settle { bad } else { [0.0, 0.0] };
            let c = twin_frame(&mut twin, v, t, 1.0);
            if t == settle {
                assert!(
                    twin.links().iter().all(|&l| l == 0),
                    "{bad:?}: a history kept"
                );
            }
            means.push(mean(&c));
            frames.push(c);
        }
        (means, frames, twin.history().to_vec())
    };
    let (nan_means, nan_frames, nan_history) = run([f32::NAN, 0.0]);
    let beta_min = config().min_samples();
    assert!(
        nan_frames[settle as usize].iter().all(|&n| n == beta_min),
        "NaN motion: the disocclusion count"
    );
    let before = nan_means[settle as usize - 1];
    assert!(
        before > 8.5,
        "the scene must settle above beta_min: {before}"
    );
    for bad in [
        [1e30_f32, 0.0],
        [0.0, 1e30],
        [f32::MAX, f32::MAX],
        [-3e9, 0.0],
        [3e9, -3e9],
        [f32::MIN, 0.0],
    ] {
        let (means, frames, history) = run(bad);
        // Identical to NaN motion, frame by frame and in the stored history.
        assert_eq!(frames, nan_frames, "{bad:?}: counts differ from NaN motion");
        assert_eq!(
            history
                .iter()
                .map(|t| t.map(f16::to_bits))
                .collect::<Vec<_>>(),
            nan_history
                .iter()
                .map(|t| t.map(f16::to_bits))
                .collect::<Vec<_>>(),
            "{bad:?}"
        );
        let after = means[settle as usize + 1];
        // The frame after the disocclusion estimates from the f16-stored seed: exactly the
        // seeded count (`beta_min`), not one more from the f16 rounding of the target.
        assert!(
            frames[settle as usize + 1].iter().all(|&n| n == beta_min),
            "{bad:?}: the seed asks for its count"
        );
        eprintln!(
            "{bad:?}: mean spp before {before:.2}, bad frame {:.2}, after {after:.2}",
            means[settle as usize]
        );
        assert!(
            (after - before).abs() <= 0.1 * before,
            "{bad:?}: the frame after spends {after:.2} against {before:.2} before"
        );
    }
}

/// A negative monitored value is taken as it is: the values `-x` give the counts of `x`
/// (the variance does not depend on the sign, and `f16` rounding is symmetric) and the
/// history of `x` with the mean negated.
#[test]
fn negative_values_are_taken_as_they_are() {
    let mut pos = AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
    let mut neg = pos.clone();
    for t in 0..12 {
        let v = [0.0, 0.0];
        assert_eq!(
            twin_frame(&mut pos, v, t, 1.0),
            twin_frame(&mut neg, v, t, -1.0),
            "frame {t}"
        );
        for (p, n) in pos.history().iter().zip(neg.history()) {
            assert_eq!((-p[0]).to_bits(), n[0].to_bits(), "mean negated");
            assert_eq!(&p[1..], &n[1..], "variance, count, flag");
        }
    }
    assert!(
        neg.history().iter().all(|t| t[0].to_f32() < 0.0),
        "negative means are stored"
    );
}

/// Two estimates in a row: the second replaces the first (the history is read, not
/// advanced, by the estimate), so estimate(a), estimate(b), update is estimate(b), update.
#[test]
fn a_second_estimate_replaces_the_first() {
    let mut once = AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
    for t in 0..6 {
        twin_frame(&mut once, [0.0, 0.0], t, 1.0);
    }
    let mut twice = once.clone();
    let depth = [1.0_f32; N];
    // A first estimate with other inputs (a pan and a different depth), then the real one.
    let (motion, other) = ([[0.0_f32, 0.0]; N], [[2.5_f32, -1.0]; N]);
    let deeper = [2.0_f32; N];
    let first = EstimateData::new(&other, &deeper, &depth);
    twice.estimate(&first).expect("first estimate");
    let data = EstimateData::new(&motion, &depth, &depth);
    let a = once.estimate(&data).expect("estimate").to_vec();
    let b = twice.estimate(&data).expect("second estimate").to_vec();
    assert_eq!(a, b);
    let values: Vec<f32> = (0..N).map(|i| value(i, 99, a[i])).collect();
    let update = UpdateData::new(&values);
    once.update(&update).expect("update");
    twice.update(&update).expect("update after two estimates");
    assert_eq!(once.history(), twice.history());
}

/// A resize between the steps discards the estimate and the update names the resize; a
/// new estimate at the new size clears it.
#[test]
fn a_resize_between_the_steps_is_named() {
    let mut twin = AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
    twin_frame(&mut twin, [0.0, 0.0], 0, 1.0);
    let depth = [1.0_f32; N];
    let motion = [[0.0_f32; 2]; N];
    twin.estimate(&EstimateData::new(&motion, &depth, &depth))
        .expect("estimate");
    twin.resize(4, 4).expect("resize");
    let small = [0.5_f32; 16];
    let update = UpdateData::new(&small);
    assert_eq!(
        twin.update(&update),
        Err(AdaptiveError::ResizedBetweenSteps)
    );
    assert!(
        AdaptiveError::ResizedBetweenSteps
            .to_string()
            .contains("resized"),
        "the message names the resize"
    );
    // Without an estimate in the frame at all, the old error.
    let mut fresh = AdaptiveTwin::new(common::settings(config(), Control::As), 4, 4).expect("twin");
    fresh.resize(5, 5).expect("resize");
    assert_eq!(
        fresh.update(&UpdateData::new(&[0.5; 25])),
        Err(AdaptiveError::UpdateWithoutEstimate)
    );
    let (d, m) = ([1.0_f32; 16], [[0.0_f32; 2]; 16]);
    twin.estimate(&EstimateData::new(&m, &d, &d))
        .expect("estimate at the new size");
    twin.update(&update).expect("update after a new estimate");
}

/// The GPU follows the same rules bit for bit: absurd motion, negative values, two
/// estimates in a row, and a resize between the steps.
#[test]
fn gpu_follows_the_twin_on_odd_input_and_calls() {
    use wgpu::TextureFormat as F;
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("adaptive_robustness gpu_follows_the_twin").device()
    else {
        return;
    };
    let mut gpu = AdaptivePass::new(&dev.device, common::settings(config(), Control::As), W, H)
        .expect("pass");
    let mut twin = AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
    let depth_data = [1.0_f32; N];
    let depth = common::upload(&dev, F::R32Float, [W, H], &depth_data);
    let motions = [
        [0.0_f32, 0.0],
        [1e30, 0.0],
        [0.0, 0.0],
        [f32::MAX, -3e9],
        [0.0, 0.0],
        [0.0, 0.0],
    ];
    for (t, &v) in motions.iter().enumerate() {
        let t = t as u32;
        let sign = if t.is_multiple_of(2) { -1.0 } else { 1.0 };
        let motion_data = [v; N];
        let motion = common::upload(&dev, F::Rg32Float, [W, H], &motion_data);
        let mut enc = dev.device.create_command_encoder(&Default::default());
        let inputs = EstimateInputs::new(&motion, &depth, &depth);
        if t == 4 {
            // A first estimate with a pan: replaced by the second.
            let pan = common::upload(&dev, F::Rg32Float, [W, H], &[[2.0_f32, 1.0]; N]);
            let mut first = inputs;
            first.motion = &pan;
            gpu.record_estimate(&mut enc, &first)
                .expect("first estimate");
        }
        gpu.record_estimate(&mut enc, &inputs).expect("estimate");
        dev.queue.submit([enc.finish()]);
        let counts: Vec<u32> =
            read_texture(&dev.device, &dev.queue, gpu.count_texture()).expect("readback");
        let values: Vec<f32> = (0..N).map(|i| sign * value(i, t, counts[i])).collect();
        let value_tex = common::upload(&dev, F::R32Float, [W, H], &values);
        let mut enc = dev.device.create_command_encoder(&Default::default());
        gpu.record_update(&mut enc, &UpdateInputs::new(&value_tex))
            .expect("update");
        dev.queue.submit([enc.finish()]);
        let history: Vec<[f16; 4]> =
            read_texture(&dev.device, &dev.queue, gpu.history_texture()).expect("readback");

        let twin_counts = twin
            .estimate(&EstimateData::new(&motion_data, &depth_data, &depth_data))
            .expect("twin")
            .to_vec();
        assert_eq!(counts, twin_counts, "frame {t}: counts");
        twin.update(&UpdateData::new(&values)).expect("twin");
        assert_eq!(
            common::bits(&history),
            common::bits(twin.history()),
            "frame {t}: history"
        );
        if v[0] != 0.0 {
            assert!(
                counts.iter().all(|&n| n == config().min_samples()),
                "frame {t}: disocclusion"
            );
        }
    }
    let mut enc = dev.device.create_command_encoder(&Default::default());
    let motion = common::upload(&dev, F::Rg32Float, [W, H], &[[0.0_f32; 2]; N]);
    gpu.record_estimate(&mut enc, &EstimateInputs::new(&motion, &depth, &depth))
        .expect("estimate");
    gpu.resize(W + 1, H).expect("resize");
    let value = common::upload(&dev, F::R32Float, [W, H], &[0.5_f32; N]);
    assert_eq!(
        gpu.record_update(&mut enc, &UpdateInputs::new(&value))
            .unwrap_err(),
        AdaptiveError::ResizedBetweenSteps
    );
}
