//! The update's TAA guide (`UpdateInputs::guide`, `UpdateData::guide`; the dissertation's
//! Eq. 4.4, docs/algorithms.md §8.5) on a moving scene: a camera pan of 1.5 pixels per
//! frame over a textured plane, with a block that moves against it (disocclusions), and
//! the guide a small TAA resolve of the monitored value (reprojected nearest, clamped to
//! the 3x3 neighbourhood, NaN where it has no history). The GPU equals the twin bit for
//! bit (counts, links, histories; AS and OCV; skipped without an adapter); the twin's
//! guided histories equal the core's `update_guided` of the decoded texels; the guide
//! changes the counts; a wrong guide is an error naming `guide`.

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg::cv::Ocv;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveTwin, Control, EstimateData, EstimateInputs, UpdateData,
    UpdateInputs,
};
use spvg_wgpu::util::read_texture;

const W: u32 = 24;
const H: u32 = 16;
const N: usize = (W * H) as usize;
const FRAMES: u32 = 12;
/// The camera pans this many pixels per frame (the plane moves left on screen).
const PAN: f32 = 1.5;

fn config() -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .target_variance(2e-4)
        .kappa(0.5)
        // the spatial variance off, so the guide alone moves young histories' variance.
        .spatial_variance(0)
        .build()
        .expect("valid config")
}

/// Whether pixel `(x, y)` sees the block at frame `t` (it moves right, 2 pixels a frame).
fn on_block(x: f32, y: f32, t: u32) -> bool {
    let left = 2.0 + 2.0 * t as f32;
    (left..left + 5.0).contains(&x) && (4.0..10.0).contains(&y)
}

/// One frame of the scene: motion (the convention of `spvg::reproject`), depth and
/// the monitored value (a texture on the plane plus per-frame noise).
struct Frame {
    motion: Vec<[f32; 2]>,
    depth: Vec<f32>,
    value: Vec<f32>,
}

fn frame(t: u32) -> Frame {
    let mut f = Frame {
        motion: Vec::with_capacity(N),
        depth: Vec::with_capacity(N),
        value: Vec::with_capacity(N),
    };
    for i in 0..N {
        let (x, y) = ((i % W as usize) as f32 + 0.5, (i / W as usize) as f32 + 0.5);
        let noise = {
            let h = (i as u32).wrapping_mul(2_654_435_761) ^ t.wrapping_mul(0x9e37_79b9);
            let h = (h ^ (h >> 15)).wrapping_mul(0x2c1b_3c6d);
            ((h >> 8) as f32 / 16_777_216.0 - 0.5) * (0.02 + 0.01 * (i % 5) as f32)
        };
        if on_block(x, y, t) {
            f.motion.push([2.0, 0.0]);
            f.depth.push(5.0);
            f.value.push(0.8 + noise);
        } else {
            // The plane point under the pixel, in the plane's own coordinates.
            let u = x + PAN * t as f32;
            f.motion.push([-PAN, 0.0]);
            f.depth.push(10.0);
            f.value.push(0.4 + 0.1 * (u * 0.7).sin() + noise);
        }
    }
    f
}

/// A minimal TAA resolve on the monitored value: the history at `p + 0.5 - v` (nearest
/// texel) where it lies in the frame and its depth agrees within 2%, clamped to this
/// frame's 3x3 min/max. Returns the guide `C_t` (NaN where there is no history) and
/// advances the history by the blend `C + 0.1 (S - C)`.
struct Resolve {
    history: Option<(Vec<f32>, Vec<f32>)>,
}

impl Resolve {
    fn guide(&mut self, f: &Frame) -> Vec<f32> {
        let (w, h) = (W as i32, H as i32);
        let mut c = vec![f32::NAN; N];
        if let Some((prev, prev_depth)) = &self.history {
            for (i, ci) in c.iter_mut().enumerate() {
                let (x, y) = ((i as i32 % w), (i as i32 / w));
                let [vx, vy] = f.motion[i];
                let px = (x as f32 + 0.5 - vx).floor() as i32;
                let py = (y as f32 + 0.5 - vy).floor() as i32;
                if px < 0 || py < 0 || px >= w || py >= h {
                    continue;
                }
                let k = (py * w + px) as usize;
                if (prev_depth[k] - f.depth[i]).abs() > 0.02 * f.depth[i] {
                    continue;
                }
                let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (qx, qy) = ((x + dx).clamp(0, w - 1), (y + dy).clamp(0, h - 1));
                        let v = f.value[(qy * w + qx) as usize];
                        (lo, hi) = (lo.min(v), hi.max(v));
                    }
                }
                *ci = prev[k].clamp(lo, hi);
            }
        }
        let blended = c
            .iter()
            .zip(&f.value)
            .map(|(&c, &s)| if c.is_finite() { c + 0.1 * (s - c) } else { s })
            .collect();
        self.history = Some((blended, f.depth.clone()));
        c
    }
}

/// Runs the twin over the scene with or without the guide: per frame the counts.
fn run_twin(control: Control, guided: bool) -> Vec<Vec<u32>> {
    let mut twin = AdaptiveTwin::new(common::settings(config(), control), W, H).expect("twin");
    let mut resolve = Resolve { history: None };
    let mut previous = frame(0).depth;
    let mut counts = Vec::new();
    for t in 0..FRAMES {
        let f = frame(t);
        let n = twin
            .estimate(&estimate_data(&f, &previous))
            .expect("estimate")
            .to_vec();
        counts.push(n);
        let guide = resolve.guide(&f);
        let control_value = vec![0.3_f32; N];
        twin.update(
            &UpdateData::new(&f.value)
                .with_control(control.needs_control().then_some(&control_value[..]))
                .with_guide(guided.then_some(&guide[..])),
        )
        .expect("update");
        previous = f.depth;
    }
    counts
}

fn estimate_data<'a>(f: &'a Frame, previous: &'a [f32]) -> EstimateData<'a> {
    EstimateData::new(&f.motion, &f.depth, previous)
}

#[test]
fn the_guide_changes_the_counts_on_the_moving_scene() {
    let (plain, guided) = (run_twin(Control::As, false), run_twin(Control::As, true));
    assert_eq!(plain[0], guided[0], "frame 0 has no history to guide");
    let differ: usize = plain
        .iter()
        .zip(&guided)
        .map(|(a, b)| a.iter().zip(b).filter(|(x, y)| x != y).count())
        .sum();
    assert!(
        differ > N / 4,
        "only {differ} counts differ over {FRAMES} frames"
    );
}

#[test]
fn twin_names_a_guide_of_the_wrong_length() {
    let mut twin = AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
    let f = frame(0);
    twin.estimate(&estimate_data(&f, &f.depth))
        .expect("estimate");
    let short = vec![0.5_f32; N - 1];
    let err = twin
        .update(&UpdateData::new(&f.value).with_guide(Some(&short)))
        .unwrap_err();
    assert_eq!(
        err,
        AdaptiveError::SliceLength {
            input: "guide",
            expected: N,
            got: N - 1
        }
    );
}

#[test]
fn gpu_matches_twin_with_the_guide_on_a_moving_scene() {
    use wgpu::TextureFormat as F;
    let Some(dev) = spvg_gpu_test::GpuTest::new("guide gpu_matches_twin").device() else {
        return;
    };
    let ocv = Control::Ocv(Ocv::new(0.2, 1e-6, 0.0).expect("ocv"));
    for control in [Control::As, ocv] {
        let mut gpu =
            AdaptivePass::new(&dev.device, common::settings(config(), control), W, H).expect("gpu");
        let mut twin = AdaptiveTwin::new(common::settings(config(), control), W, H).expect("twin");
        let mut resolve = Resolve { history: None };
        let mut previous = frame(0).depth;
        let control_value = vec![0.3_f32; N];
        let control_tex = common::upload(&dev, F::R32Float, [W, H], &control_value);
        for t in 0..FRAMES {
            let f = frame(t);
            let guide = resolve.guide(&f);
            let motion = common::upload(&dev, F::Rg32Float, [W, H], &f.motion);
            let depth = common::upload(&dev, F::R32Float, [W, H], &f.depth);
            let prev = common::upload(&dev, F::R32Float, [W, H], &previous);
            let value = common::upload(&dev, F::R32Float, [W, H], &f.value);
            let guide_tex = common::upload(&dev, F::R32Float, [W, H], &guide);
            let mut enc = dev.device.create_command_encoder(&Default::default());
            gpu.record_estimate(&mut enc, &EstimateInputs::new(&motion, &depth, &prev))
                .expect("estimate");
            gpu.record_update(
                &mut enc,
                &UpdateInputs::new(&value)
                    .with_control(control.needs_control().then_some(&control_tex))
                    .with_guide(Some(&guide_tex)),
            )
            .expect("update");
            dev.queue.submit([enc.finish()]);
            let read = |tex: &wgpu::Texture| -> Vec<u32> {
                read_texture(&dev.device, &dev.queue, tex).expect("readback")
            };
            let (count_gpu, link_gpu) = (read(gpu.count_texture()), read(gpu.link_texture()));
            let hist_gpu: Vec<[f16; 4]> =
                read_texture(&dev.device, &dev.queue, gpu.history_texture()).expect("readback");
            let count_cpu = twin
                .estimate(&estimate_data(&f, &previous))
                .expect("twin")
                .to_vec();
            assert_eq!(count_gpu, count_cpu, "{control:?}, frame {t}: counts");
            assert_eq!(link_gpu, twin.links(), "{control:?}, frame {t}: links");
            if t > 2 {
                let kept = link_gpu.iter().filter(|&&l| l != 0).count();
                let lost = N - kept;
                assert!(
                    kept > N / 2 && lost > 0,
                    "frame {t}: {kept} kept, {lost} lost"
                );
            }
            twin.update(
                &UpdateData::new(&f.value)
                    .with_control(control.needs_control().then_some(&control_value[..]))
                    .with_guide(Some(&guide)),
            )
            .expect("twin");
            assert_eq!(
                common::bits(&hist_gpu),
                common::bits(twin.history()),
                "{control:?}, frame {t}: history"
            );
            previous = f.depth;
        }
    }
}

#[test]
fn gpu_names_a_wrong_guide() {
    use wgpu::TextureFormat as F;
    let Some(dev) = spvg_gpu_test::GpuTest::new("guide gpu_names_a_wrong_guide").device() else {
        return;
    };
    let mut gpu =
        AdaptivePass::new(&dev.device, common::settings(config(), Control::As), W, H).expect("gpu");
    let f = frame(0);
    let motion = common::upload(&dev, F::Rg32Float, [W, H], &f.motion);
    let depth = common::upload(&dev, F::R32Float, [W, H], &f.depth);
    let value = common::upload(&dev, F::R32Float, [W, H], &f.value);
    let wide = common::upload(
        &dev,
        F::R32Float,
        [W + 1, H],
        &vec![0.5_f32; N + H as usize],
    );
    let uint = common::upload(&dev, F::R32Uint, [W, H], &vec![0_u32; N]);
    let mut enc = dev.device.create_command_encoder(&Default::default());
    let estimate = EstimateInputs::new(&motion, &depth, &depth);
    gpu.record_estimate(&mut enc, &estimate).expect("estimate");
    let update = |g| UpdateInputs::new(&value).with_guide(Some(g));
    assert!(matches!(
        gpu.record_update(&mut enc, &update(&wide)),
        Err(AdaptiveError::TextureSize { input: "guide", .. })
    ));
    assert!(matches!(
        gpu.record_update(&mut enc, &update(&uint)),
        Err(AdaptiveError::TextureFormat { input: "guide", .. })
    ));
}
