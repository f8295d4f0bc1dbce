//! The update's second moment (`AdaptivePass::record_update_with_moment`,
//! `AdaptiveTwin::update_with_moment`, docs/algorithms.md §8.8) on a jittered static
//! scene of binary rays: an edge whose occlusion flips between 0.1 and 0.9 from frame to
//! frame (sub-pixel jitter) beside smooth pixels, each frame casting the twin's counts.
//! The GPU equals the twin bit for bit (counts, links, histories) under the integer rule,
//! under fractional counts with the resolved-image rule, with the TAA guide, with NaN
//! moments at some pixels, and with OCV (where the moment is ignored); the twin's counts
//! on the edge stay near the closed-form `p (1 - p) / sigma0^2` where without the moment
//! they run to the budget's maximum; a wrong moment is an error naming `moment`.

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg::cv::Ocv;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveTwin, Control, EstimateData, EstimateInputs, UpdateData,
    UpdateInputs,
};
use spvg_wgpu::util::read_texture;

const W: u32 = 16;
const H: u32 = 8;
const N: usize = (W * H) as usize;

fn config(fractional: bool) -> SpvgConfig<f32> {
    let b = SpvgConfig::builder().target_variance(2e-3).budget(4, 512);
    let b = if fractional {
        b.fractional_floor(Some(0.5)).resolve_weight(Some(0.1))
    } else {
        b
    };
    b.build().expect("valid config")
}

/// The occlusion probability of pixel `i` at frame `t`: the left half is an edge under
/// jitter (0.1 and 0.9 on alternate frames), the right half a smooth ramp.
fn occlusion(i: usize, t: u32) -> f64 {
    let x = i % W as usize;
    if x < W as usize / 2 {
        if (t + i as u32).is_multiple_of(2) {
            0.1
        } else {
            0.9
        }
    } else {
        0.05 + 0.8 * (i % 7) as f64 / 7.0
    }
}

/// A hash of (pixel, frame, ray) to [0, 1).
fn uniform(i: usize, t: u32, k: u32) -> f64 {
    let mut h = (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ u64::from(t).wrapping_mul(0xbf58_476d_1ce4_e5b9)
        ^ u64::from(k).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^= h >> 31;
    h = h.wrapping_mul(0xd6e8_feb8_6659_fd93);
    h ^= h >> 32;
    (h >> 11) as f64 / (1u64 << 53) as f64
}

/// The frame's monitored value (mean of `n` binary rays) and second moment per pixel; a
/// NaN moment (none) at every 11th pixel.
fn sample(counts: &[u32], t: u32) -> (Vec<f32>, Vec<f32>) {
    let mut value = vec![0.0_f32; N];
    let mut moment = vec![0.0_f32; N];
    for (i, &n) in counts.iter().enumerate() {
        let hits = (0..n)
            .filter(|&k| uniform(i, t, k) < occlusion(i, t))
            .count();
        let mean = if n == 0 { 0.0 } else { hits as f32 / n as f32 };
        value[i] = mean;
        // Binary rays: the mean of the squares is the mean.
        moment[i] = if i % 11 == 5 { f32::NAN } else { mean };
    }
    (value, moment)
}

fn still() -> (Vec<[f32; 2]>, Vec<f32>) {
    (vec![[0.0, 0.0]; N], vec![10.0; N])
}

fn estimate_data<'a>(motion: &'a [[f32; 2]], depth: &'a [f32]) -> EstimateData<'a> {
    EstimateData::new(motion, depth, depth)
}

/// The twin's mean count over the edge pixels (the left half) over the last half of 80
/// frames, with or without the moment.
fn edge_count(with_moment: bool) -> f64 {
    let mut twin =
        AdaptiveTwin::new(common::settings(config(false), Control::As), W, H).expect("twin");
    let (motion, depth) = still();
    let (mut total, mut pixels) = (0.0, 0.0);
    for t in 0..80 {
        let counts = twin
            .estimate(&estimate_data(&motion, &depth))
            .expect("estimate")
            .to_vec();
        let (value, moment) = sample(&counts, t);
        let data = UpdateData::new(&value);
        if with_moment {
            twin.update_with_moment(&data, &moment).expect("update");
        } else {
            twin.update(&data).expect("update");
        }
        if t >= 40 {
            for (i, &n) in counts.iter().enumerate() {
                if (i % W as usize) < W as usize / 2 && i % 11 != 5 {
                    total += f64::from(n);
                    pixels += 1.0;
                }
            }
        }
    }
    total / pixels
}

#[test]
fn the_moment_keeps_the_edge_at_its_sampling_variance() {
    // Closed form: a binary ray at occlusion 0.1 or 0.9 has variance 0.09.
    let required = 0.09 / 2e-3;
    let (with, without) = (edge_count(true), edge_count(false));
    eprintln!("edge: required {required}, with the moment {with:.1}, without {without:.1}");
    assert!(
        with < required * 1.1 && with > required / 1.1,
        "with the moment {with}, required {required}"
    );
    assert!(without > 400.0, "without the moment {without}");
}

#[test]
fn twin_names_a_moment_of_the_wrong_length() {
    let mut twin =
        AdaptiveTwin::new(common::settings(config(false), Control::As), W, H).expect("twin");
    let (motion, depth) = still();
    twin.estimate(&estimate_data(&motion, &depth))
        .expect("estimate");
    let value = vec![0.5_f32; N];
    let short = vec![0.5_f32; N - 1];
    let err = twin
        .update_with_moment(&UpdateData::new(&value), &short)
        .unwrap_err();
    assert_eq!(
        err,
        AdaptiveError::SliceLength {
            input: "moment",
            expected: N,
            got: N - 1
        }
    );
}

#[test]
fn gpu_matches_twin_with_the_moment() {
    use wgpu::TextureFormat as F;
    let Some(dev) = spvg_gpu_test::GpuTest::new("moment gpu_matches_twin").device() else {
        return;
    };
    let ocv = Control::Ocv(Ocv::new(0.2, 1e-6, 0.0).expect("ocv"));
    let cases = [
        (Control::As, false, false),
        (Control::As, true, false),
        (Control::As, false, true),
        (Control::As, true, true),
        (ocv, false, false),
    ];
    for (control, fractional, guided) in cases {
        let settings = common::settings(config(fractional), control);
        let mut gpu = AdaptivePass::new(&dev.device, settings, W, H).expect("gpu");
        let mut twin = AdaptiveTwin::new(settings, W, H).expect("twin");
        let (motion, depth) = still();
        let control_value = vec![0.3_f32; N];
        let control_tex = common::upload(&dev, F::R32Float, [W, H], &control_value);
        let motion_tex = common::upload(&dev, F::Rg32Float, [W, H], &motion);
        let depth_tex = common::upload(&dev, F::R32Float, [W, H], &depth);
        let mut changed = 0;
        for t in 0..24 {
            let counts = twin
                .estimate(&estimate_data(&motion, &depth))
                .expect("twin")
                .to_vec();
            let (value, moment) = sample(&counts, t);
            let guide: Vec<f32> = value.iter().map(|v| v * 0.9 + 0.05).collect();
            let value_tex = common::upload(&dev, F::R32Float, [W, H], &value);
            let moment_tex = common::upload(&dev, F::R32Float, [W, H], &moment);
            let guide_tex = common::upload(&dev, F::R32Float, [W, H], &guide);
            let mut enc = dev.device.create_command_encoder(&Default::default());
            gpu.record_estimate(
                &mut enc,
                &EstimateInputs::new(&motion_tex, &depth_tex, &depth_tex),
            )
            .expect("estimate");
            gpu.record_update_with_moment(
                &mut enc,
                &UpdateInputs::new(&value_tex)
                    .with_control(control.needs_control().then_some(&control_tex))
                    .with_guide(guided.then_some(&guide_tex)),
                &moment_tex,
            )
            .expect("update");
            dev.queue.submit([enc.finish()]);
            let count_gpu: Vec<u32> =
                read_texture(&dev.device, &dev.queue, gpu.count_texture()).expect("readback");
            let hist_gpu: Vec<[f16; 4]> =
                read_texture(&dev.device, &dev.queue, gpu.history_texture()).expect("readback");
            assert_eq!(
                count_gpu, counts,
                "{control:?} {fractional} {guided}, frame {t}: counts"
            );
            let data = UpdateData::new(&value)
                .with_control(control.needs_control().then_some(&control_value[..]))
                .with_guide(guided.then_some(&guide[..]));
            // The same frame without the moment, for the check that the moment acts.
            let mut plain = twin.clone();
            plain.update(&data).expect("twin");
            twin.update_with_moment(&data, &moment).expect("twin");
            assert_eq!(
                common::bits(&hist_gpu),
                common::bits(twin.history()),
                "{control:?} {fractional} {guided}, frame {t}: history"
            );
            changed += common::bits(plain.history())
                .iter()
                .zip(common::bits(twin.history()))
                .filter(|(a, b)| **a != *b)
                .count();
        }
        if control.needs_control() {
            assert_eq!(changed, 0, "OCV ignores the moment");
        } else {
            assert!(
                changed > N,
                "{fractional} {guided}: only {changed} texels moved"
            );
        }
    }
}

#[test]
fn gpu_names_a_wrong_moment() {
    use wgpu::TextureFormat as F;
    let Some(dev) = spvg_gpu_test::GpuTest::new("moment gpu_names_a_wrong_moment").device() else {
        return;
    };
    let mut gpu = AdaptivePass::new(
        &dev.device,
        common::settings(config(false), Control::As),
        W,
        H,
    )
    .expect("gpu");
    let (motion, depth) = still();
    let motion = common::upload(&dev, F::Rg32Float, [W, H], &motion);
    let depth = common::upload(&dev, F::R32Float, [W, H], &depth);
    let value = common::upload(&dev, F::R32Float, [W, H], &vec![0.5_f32; N]);
    let wide = common::upload(
        &dev,
        F::R32Float,
        [W + 1, H],
        &vec![0.5_f32; N + H as usize],
    );
    let mut enc = dev.device.create_command_encoder(&Default::default());
    let estimate = EstimateInputs::new(&motion, &depth, &depth);
    gpu.record_estimate(&mut enc, &estimate).expect("estimate");
    let update = UpdateInputs::new(&value);
    assert!(matches!(
        gpu.record_update_with_moment(&mut enc, &update, &wide),
        Err(AdaptiveError::TextureSize {
            input: "moment",
            ..
        })
    ));
}
