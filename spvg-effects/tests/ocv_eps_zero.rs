//! OCV with `eps_a = 0` (accepted by validation) at pass level: a dark, faintly
//! flickering surface drives `Sigma_yy` to 0 in the f16 J texel while `Sigma_xy` stays
//! non-zero, so the raw coefficient `Sigma_xy / 0` is infinite. The core saturates it (the
//! bound of D then applies), and the library's WGSL does the same: the GPU and the twin
//! agree on every pixel's count.

mod common;

use half::f16;
use spvg::burley::presets::SKIN1;
use spvg::cv::Ocv;
use spvg::texel::{CvTexel16, Texel};
use spvg_effects::sss::{FrameInputs, Model, PassConfig, SssPass, SssTwin};

const N: u32 = 16;

/// Mostly dark lighting (about 1e-3, where one f16 step is 1e-6) with a one-step flicker
/// on alternate frames, and a bright pixel in seven: the dark pixels' distant estimates
/// pick up the bright ones' light, so their residual (and count) depends on the
/// coefficient while their control barely moves.
fn inputs(t: u32) -> FrameInputs {
    let n = (N * N) as usize;
    let lighting = (0..n)
        .map(|i| {
            let base = if i % 7 == 0 {
                0.5
            } else {
                1e-3 * (1.0 + (i % 5) as f32 * 0.15)
            };
            let v = f16::from_f32(base);
            let v = if t % 2 == 1 {
                f16::from_bits(v.to_bits() + 1)
            } else {
                v
            };
            [v, v, v, f16::ONE]
        })
        .collect();
    FrameInputs {
        width: N,
        height: N,
        lighting,
        depth: vec![500.0; n],
        mask: vec![1; n],
    }
}

#[test]
fn ocv_with_eps_a_zero_matches_the_twin() {
    let cfg = PassConfig {
        ocv: Ocv::new(0.2, 0.0, 1.0).expect("eps_a = 0 is valid"),
        ..PassConfig::default()
    };
    let mut cpu = SssTwin::new(Model::Ocv, N, N);
    let dev = spvg_gpu_test::GpuTest::new("ocv_with_eps_a_zero_matches_the_twin").device();
    let mut gpu = dev
        .as_ref()
        .map(|d| SssPass::for_device(d, Model::Ocv, N, N));
    let (mut saturated, mut differ, mut above_min) = (0_usize, 0_usize, 0_usize);
    for t in 0..90 {
        let p = cpu.frame_params(&cfg, &SKIN1, t).expect("valid params");
        let enc = cpu.adaptive().expect("OCV runs the component").encoding();
        // The twin's J before this frame: how many raw coefficients are infinite ratios.
        saturated += cpu
            .history()
            .j
            .iter()
            .filter(|j| {
                let state = CvTexel16(**j).decode(&enc);
                state.var_g == 0.0 && state.cov_fg != 0.0
            })
            .count();
        let frame = inputs(t);
        let b = cpu.run_frame(&p, &frame).expect("cpu frame");
        above_min += b.count.iter().filter(|&&n| n > 8).count();
        if let Some(g) = gpu.as_mut() {
            let gp = g.frame_params(&cfg, &SKIN1, t).expect("valid params");
            let a = g.run_frame(&gp, &frame).expect("gpu frame");
            differ += a.count.iter().zip(&b.count).filter(|(x, y)| x != y).count();
        }
    }
    eprintln!(
        "{saturated} pixel-frames with Sigma_yy = 0 and Sigma_xy != 0, {above_min} counts above the minimum; {differ} counts differ"
    );
    assert!(
        above_min > 0,
        "the counts must depend on the monitored residual"
    );
    assert!(
        saturated > 0,
        "the scene must reach the infinite-ratio case"
    );
    assert_eq!(
        differ, 0,
        "GPU and twin counts differ on {differ} pixel-frames"
    );
}
