//! Both effects under the component's count-classified dispatch
//! (`AdaptiveSettings::classified_dispatch`: the sampling pass recorded once per class of
//! tiles, each tile's pixels taken by the class of their counts) give what the whole-frame dispatch gives, bit
//! for bit: the subsurface pass (`sss_sample_classified`) in AS, CCV and OCV on frames with
//! changing light, moving mask holes and the zero-sample rule; ambient occlusion
//! (`ao_sample_classified`) under a pan with count dilation, prefix estimates included,
//! with integer and with fractional counts.
//! GPU tests skip cleanly without an adapter.

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg::burley::presets::SKIN1;
use spvg_effects::ao::{AoMode, AoPass, AoScene, Motion};
use spvg_effects::sss::{FrameInputs, Model, PassConfig, SssPass};
use spvg_wgpu::adaptive::{AdaptivePass, AdaptiveSettings};
use spvg_wgpu::util::read_texture;

// Not a multiple of the 8 x 8 tile: partial tiles on two sides.
const W: u32 = 61;
const H: u32 = 43;

/// Frames with structure: lighting with a moving shadow edge that changes with `t`,
/// depths from 0.3 m to 3 m (the nearest below the zero-sample threshold), and mask holes
/// that move every frame.
fn inputs(t: u32) -> FrameInputs {
    common::frame(W, H, |x, y| {
        let lit = if x + y / 2 < 20 + 3 * t { 1.0 } else { 0.1 };
        let l = lit * (0.3 + 0.6 * ((x * 7 + y * 3 + t * 11) % 23) as f32 / 23.0);
        let depth = 300.0 + 2700.0 * ((x + 2 * y) % 31) as f32 / 31.0;
        (
            [l, 0.7 * l, 0.5 * l],
            depth,
            !(x * 5 + y * 11 + t).is_multiple_of(9),
        )
    })
}

#[derive(Debug, PartialEq)]
struct SssFrame {
    result: Vec<[u16; 4]>,
    count: Vec<u32>,
    history: Vec<[u16; 4]>,
    cv: Vec<[u16; 4]>,
}

fn bits(v: &[[f16; 4]]) -> Vec<[u16; 4]> {
    v.iter().map(|t| t.map(f16::to_bits)).collect()
}

#[test]
fn sss_classified_dispatch_equals_the_whole_frame_dispatch() {
    let Some(d) =
        spvg_gpu_test::GpuTest::new("sss_classified_dispatch_equals_the_whole_frame_dispatch")
            .device()
    else {
        return;
    };
    for model in [Model::As, Model::Ccv, Model::Ocv] {
        let run = |classified_dispatch: bool| {
            let cfg = PassConfig {
                spvg: SpvgConfig::builder()
                    .target_variance(1e-3)
                    .build()
                    .expect("valid target"),
                classified_dispatch,
                ..PassConfig::default()
            };
            let mut pass = SssPass::new(&d.device, &d.queue, W, H, model, false);
            let mut classes_used = 0;
            let frames: Vec<SssFrame> = (0..6)
                .map(|t| {
                    let p = pass.frame_params(&cfg, &SKIN1, t).expect("params");
                    let out = pass.run_frame(&p, &inputs(t)).expect("frame");
                    let h = pass.history().expect("history");
                    if classified_dispatch {
                        let a = pass.adaptive().expect("adaptive");
                        let (classes, _) = a.read_classes(&d.queue).expect("classes");
                        classes_used =
                            classes_used.max(classes.iter().filter(|c| !c.is_empty()).count());
                    }
                    SssFrame {
                        result: bits(&out.result),
                        count: out.count,
                        history: bits(&h.h),
                        cv: bits(&h.j),
                    }
                })
                .collect();
            (frames, classes_used)
        };
        let (whole, _) = run(false);
        let (classified, classes_used) = run(true);
        assert!(
            classes_used >= 2,
            "{model:?}: the counts fall into {classes_used} class(es)"
        );
        for (t, (a, b)) in whole.iter().zip(&classified).enumerate() {
            assert_eq!(a, b, "{model:?}, frame {t}: classified dispatch differs");
        }
    }
}

#[derive(Debug, PartialEq)]
struct AoBits {
    count: Vec<u32>,
    value: Vec<u32>,
    prefixes: Vec<[u32; 4]>,
    history: Vec<[u16; 4]>,
}

#[test]
fn ao_classified_dispatch_equals_the_whole_frame_dispatch() {
    let Some(d) =
        spvg_gpu_test::GpuTest::new("ao_classified_dispatch_equals_the_whole_frame_dispatch")
            .device()
    else {
        return;
    };
    let scene = AoScene {
        width: 75,
        height: 53,
        motion: Motion::Pan { speed: 2.0 },
    };
    // Integer counts, and fractional counts below a floor of 0.25 (pixels that skip
    // sampling keep their reprojected history).
    for fractional in [None, Some(0.25)] {
        let run = |classified_dispatch: bool| {
            let settings = AdaptiveSettings {
                config: SpvgConfig::builder()
                    .target_variance(1e-3)
                    .fractional_floor(fractional)
                    .build()
                    .expect("valid target"),
                dilation: 1,
                classified_dispatch,
                ..AdaptiveSettings::default()
            };
            let mut pass = AoPass::new(
                &d.device,
                &d.queue,
                scene.width,
                scene.height,
                AoMode::Adaptive,
                settings,
            )
            .expect("renderer");
            pass.set_prefix_counts([4, 8, 16, 0]);
            (0..6)
                .map(|t| {
                    let f = pass.run_frame(&scene.params(t)).expect("frame");
                    let a: &AdaptivePass = pass.adaptive().expect("adaptive");
                    let history: Vec<[f16; 4]> =
                        read_texture(&d.device, &d.queue, a.history_texture()).expect("history");
                    AoBits {
                        count: f.count,
                        value: f.value.iter().map(|v| v.to_bits()).collect(),
                        prefixes: f.prefixes.iter().map(|p| p.map(f32::to_bits)).collect(),
                        history: bits(&history),
                    }
                })
                .collect::<Vec<_>>()
        };
        let (whole, classified) = (run(false), run(true));
        let spread = whole
            .last()
            .map(|f| f.count.iter().copied().max() > f.count.iter().copied().min())
            .unwrap_or(false);
        assert!(
            spread,
            "{fractional:?}: the counts differ between pixels in the last frame"
        );
        for (t, (a, b)) in whole.iter().zip(&classified).enumerate() {
            assert_eq!(
                a, b,
                "{fractional:?}, frame {t}: classified dispatch differs"
            );
        }
    }
}
