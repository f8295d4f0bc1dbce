//! The reprojected-depth input of the estimate (`EstimateInputs::reprojected_depth`): the
//! depth test compares each pixel's surface point as the previous camera saw it with the
//! previous frame's depth. On a camera that moves towards a plane by more than the 2%
//! tolerance per frame, every history survives with it and none without it, while an
//! object that appears in front of the plane is still a disocclusion. On the twin against
//! the scene's geometry, and on the GPU against the twin bit for bit (skipped without an
//! adapter); wrong inputs are errors naming `reprojected_depth`.

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveTwin, Control, EstimateData, EstimateInputs, UpdateData,
    UpdateInputs,
};
use spvg_wgpu::util::read_texture;

const W: u32 = 20;
const H: u32 = 12;
const N: usize = (W * H) as usize;
/// The camera moves this far towards the plane per frame: 3% of the plane's depth at the
/// start, more as it comes closer; the tolerance is 2%.
const STEP: f32 = 3.0;
/// The frame the disc appears in front of the plane (and stays).
const DISC_FRAME: u32 = 5;
const FRAMES: u32 = 10;

fn config() -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .target_variance(1e-3)
        .kappa(0.5)
        .build()
        .expect("valid config")
}

/// The camera's height above the plane at frame `t` (orthographic, looking down).
fn camera(t: u32) -> f32 {
    100.0 - STEP * t as f32
}

/// Whether pixel `i` sees the disc (height 50 above the plane) at frame `t`.
fn on_disc(i: usize, t: u32) -> bool {
    let (x, y) = ((i % W as usize) as f32 + 0.5, (i / W as usize) as f32 + 0.5);
    t >= DISC_FRAME && (x - 10.0).powi(2) + (y - 6.0).powi(2) < 9.0
}

/// The height of the surface pixel `i` sees at frame `t`.
fn height(i: usize, t: u32) -> f32 {
    if on_disc(i, t) { 50.0 } else { 0.0 }
}

/// One frame: this frame's depth, the reprojected depth (the same point seen from the
/// previous camera: the camera does not move sideways, the scene does not move) and the
/// monitored values (noise whose amplitude varies over the frame).
struct Frame {
    depth: Vec<f32>,
    reprojected: Vec<f32>,
    value: Vec<f32>,
}

fn frame(t: u32) -> Frame {
    let before = camera(t.saturating_sub(1));
    Frame {
        depth: (0..N).map(|i| camera(t) - height(i, t)).collect(),
        reprojected: (0..N).map(|i| before - height(i, t)).collect(),
        value: (0..N)
            .map(|i| {
                let amp = 0.02 + 0.01 * (i % 7) as f32;
                let phase = ((i as u32).wrapping_mul(2_654_435_761) ^ t.wrapping_mul(40_503)) % 97;
                0.5 + amp * (phase as f32 / 48.0 - 1.0)
            })
            .collect(),
    }
}

/// Runs the scene on the twin with or without the reprojected depth; per frame the links
/// and the counts.
fn run_twin(with: bool) -> Vec<(Vec<u32>, Vec<u32>)> {
    let mut twin = AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
    let motion = vec![[0.0_f32; 2]; N];
    let mut previous = frame(0).depth;
    let mut out = Vec::new();
    for t in 0..FRAMES {
        let f = frame(t);
        let counts = twin
            .estimate(
                &EstimateData::new(&motion, &f.depth, &previous)
                    .with_reprojected_depth(with.then_some(&f.reprojected[..])),
            )
            .expect("twin estimate")
            .to_vec();
        out.push((twin.links().to_vec(), counts));
        twin.update(&UpdateData::new(&f.value))
            .expect("twin update");
        previous = f.depth;
    }
    out
}

#[test]
fn a_dolly_keeps_its_histories_with_the_reprojected_depth() {
    for (t, (links, _)) in run_twin(true).iter().enumerate().skip(1) {
        let t = t as u32;
        for (i, &l) in links.iter().enumerate() {
            // The disc's first frame: last frame the plane was there, 50 units deeper.
            let appeared = on_disc(i, t) && !on_disc(i, t - 1);
            assert_eq!(
                l == 0,
                appeared,
                "frame {t}, pixel {i}: link {l} (disc appeared: {appeared})"
            );
            if l != 0 {
                assert_eq!(
                    l as usize,
                    i + 1,
                    "static scene: the history of the same pixel"
                );
            }
        }
    }
}

#[test]
fn a_dolly_drops_every_history_without_it() {
    let beta_min = config().min_samples();
    for (t, (links, counts)) in run_twin(false).iter().enumerate().skip(1) {
        // |d_prev - d| = STEP > 0.02 d for every depth below 150: every test fails.
        assert!(links.iter().all(|&l| l == 0), "frame {t}: a history kept");
        assert!(
            counts.iter().all(|&n| n == beta_min),
            "frame {t}: every pixel is a disocclusion, at beta_min"
        );
    }
    // With the input the controller follows each pixel's noise instead.
    let with = run_twin(true);
    let (_, last) = with.last().expect("frames");
    assert!(
        last.iter().any(|&n| n > beta_min),
        "with the reprojected depth some pixel asks for more than beta_min"
    );
}

#[test]
fn twin_names_a_reprojected_depth_of_the_wrong_length() {
    let mut twin = AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
    let (motion, depth) = (vec![[0.0_f32; 2]; N], vec![1.0_f32; N]);
    let short = vec![1.0_f32; N - 1];
    let err = twin
        .estimate(&EstimateData::new(&motion, &depth, &depth).with_reprojected_depth(Some(&short)))
        .unwrap_err();
    assert_eq!(
        err,
        AdaptiveError::SliceLength {
            input: "reprojected_depth",
            expected: N,
            got: N - 1
        }
    );
}

#[test]
fn gpu_matches_twin_with_and_without_the_reprojected_depth() {
    use wgpu::TextureFormat as F;
    let Some(dev) = spvg_gpu_test::GpuTest::new("reprojected_depth gpu_matches_twin").device()
    else {
        return;
    };
    for with in [true, false] {
        let mut gpu = AdaptivePass::new(&dev.device, common::settings(config(), Control::As), W, H)
            .expect("gpu");
        let mut twin =
            AdaptiveTwin::new(common::settings(config(), Control::As), W, H).expect("twin");
        let motion_data = vec![[0.0_f32; 2]; N];
        let motion = common::upload(&dev, F::Rg32Float, [W, H], &motion_data);
        let mut previous = frame(0).depth;
        for t in 0..FRAMES {
            let f = frame(t);
            let depth = common::upload(&dev, F::R32Float, [W, H], &f.depth);
            let prev = common::upload(&dev, F::R32Float, [W, H], &previous);
            let reprojected = common::upload(&dev, F::R32Float, [W, H], &f.reprojected);
            let value = common::upload(&dev, F::R32Float, [W, H], &f.value);
            let mut enc = dev.device.create_command_encoder(&Default::default());
            gpu.record_estimate(
                &mut enc,
                &EstimateInputs::new(&motion, &depth, &prev)
                    .with_reprojected_depth(with.then_some(&reprojected)),
            )
            .expect("estimate");
            gpu.record_update(&mut enc, &UpdateInputs::new(&value))
                .expect("update");
            dev.queue.submit([enc.finish()]);
            let read = |tex: &wgpu::Texture| -> Vec<u32> {
                read_texture(&dev.device, &dev.queue, tex).expect("readback")
            };
            let (count_gpu, link_gpu) = (read(gpu.count_texture()), read(gpu.link_texture()));
            let hist_gpu: Vec<[f16; 4]> =
                read_texture(&dev.device, &dev.queue, gpu.history_texture()).expect("readback");
            let count_cpu = twin
                .estimate(
                    &EstimateData::new(&motion_data, &f.depth, &previous)
                        .with_reprojected_depth(with.then_some(&f.reprojected[..])),
                )
                .expect("twin")
                .to_vec();
            assert_eq!(count_gpu, count_cpu, "with {with}, frame {t}: counts");
            assert_eq!(link_gpu, twin.links(), "with {with}, frame {t}: links");
            twin.update(&UpdateData::new(&f.value)).expect("twin");
            assert_eq!(
                common::bits(&hist_gpu),
                common::bits(twin.history()),
                "with {with}, frame {t}: history"
            );
            previous = f.depth;
        }
    }
}

#[test]
fn gpu_names_a_wrong_reprojected_depth() {
    use wgpu::TextureFormat as F;
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("reprojected_depth gpu_names_a_wrong_input").device()
    else {
        return;
    };
    let scope = dev.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut gpu =
        AdaptivePass::new(&dev.device, common::settings(config(), Control::As), W, H).expect("gpu");
    let motion = common::upload(&dev, F::Rg32Float, [W, H], &vec![[0.0_f32; 2]; N]);
    let depth = common::upload(&dev, F::R32Float, [W, H], &vec![1.0_f32; N]);
    let wide = common::upload(
        &dev,
        F::R32Float,
        [W + 1, H],
        &vec![1.0_f32; N + H as usize],
    );
    let mut enc = dev.device.create_command_encoder(&Default::default());
    let inputs = |r| EstimateInputs::new(&motion, &depth, &depth).with_reprojected_depth(Some(r));
    assert_eq!(
        gpu.record_estimate(&mut enc, &inputs(&wide)).unwrap_err(),
        AdaptiveError::TextureSize {
            input: "reprojected_depth",
            expected: [W, H],
            got: [W + 1, H, 1]
        }
    );
    assert!(matches!(
        gpu.record_estimate(&mut enc, &inputs(&motion)),
        Err(AdaptiveError::TextureFormat {
            input: "reprojected_depth",
            got: F::Rg32Float,
            ..
        })
    ));
    gpu.record_estimate(&mut enc, &inputs(&depth))
        .expect("a valid reprojected depth");
    dev.queue.submit([enc.finish()]);
    let err = pollster::block_on(scope.pop());
    assert!(err.is_none(), "wgpu validation error: {err:?}");
}
