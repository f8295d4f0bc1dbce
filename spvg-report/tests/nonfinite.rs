//! Nothing non-finite enters the history, on the GPU and in the twin, with NaN and
//! infinities in the lighting and the depth.

mod common;

use half::f16;
use spvg::burley::presets::SKIN1;
use spvg_report::scene::{Scene, SceneKind};
use spvg_report::wgpu_api::{FrameInputs, History, Model, PassConfig, SssTwin};

fn poisoned(t: u32) -> FrameInputs {
    let mut f = Scene::new(SceneKind::Static, 32, 32).inputs(t);
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
    for (k, i) in (0..f.len()).step_by(7).enumerate() {
        let v = bad[k % 3];
        if k % 2 == 0 {
            f.lighting[i] = [f16::from_f32(v), f16::ONE, f16::from_f32(v), f16::ONE];
        } else {
            f.depth[i] = v;
        }
    }
    // A huge but finite lighting value whose variance overflows f16.
    f.lighting[5] = [f16::MAX; 4];
    f
}

fn assert_finite(h: &History, what: &str) {
    for (i, t) in h.h.iter().chain(&h.j).enumerate() {
        assert!(
            t.iter().all(|v| v.is_finite()),
            "{what}: non-finite history texel {i}: {t:?}"
        );
    }
}

#[test]
fn history_stays_finite() {
    let cfg = PassConfig::default();
    let dev = common::device("history_stays_finite");
    for model in [Model::As, Model::Ccv, Model::Ocv] {
        let mut cpu = SssTwin::new(model, 32, 32);
        let mut gpu = dev.as_ref().map(|d| common::sss_pass(d, model, 32, 32));
        for t in 0..4 {
            let inputs = poisoned(t);
            let p = cpu.frame_params(&cfg, &SKIN1, t).expect("valid params");
            let out = cpu.run_frame(&p, &inputs).expect("cpu frame");
            assert!(
                out.count.iter().all(|c| *c <= 64),
                "{model:?}: count over budget"
            );
            assert_finite(&cpu.history(), &format!("cpu {model:?} frame {t}"));
            if let Some(g) = gpu.as_mut() {
                let q = g.frame_params(&cfg, &SKIN1, t).expect("valid params");
                let out = g.run_frame(&q, &inputs).expect("gpu frame");
                assert!(
                    out.count.iter().all(|c| *c <= 64),
                    "{model:?}: gpu count over budget"
                );
                assert_finite(
                    &g.history().expect("history"),
                    &format!("gpu {model:?} frame {t}"),
                );
            }
        }
    }
}
