//! A frame run step by step (`SssPass::run_frame_per_pass`, for the per-pass time table)
//! renders what the one-submit frame renders: the same counts, results and history, frame
//! after frame, for the fixed count and the adaptive models. Skips cleanly without an
//! adapter (`SPVG_REQUIRE_GPU=1` makes that a failure).

mod common;

use spvg::burley::presets::SKIN1;
use spvg_effects::sss::{FrameInputs, Model, PassConfig, SssPass};

fn inputs(t: u32) -> FrameInputs {
    let (w, h) = (24_u32, 16_u32);
    common::frame(w, h, |x, y| {
        let l = if x < w / 2 { 1.0 } else { 0.1 } * (1.0 + 0.1 * ((x + y + t) % 4) as f32);
        (
            [l; 3],
            900.0 + 5.0 * (x + y) as f32,
            !(x * 7 + y * 3).is_multiple_of(17),
        )
    })
}

#[test]
fn step_by_step_equals_one_submit() {
    let Some(d) = spvg_gpu_test::GpuTest::new("step_by_step_equals_one_submit").device() else {
        return;
    };
    for model in [Model::Fixed(16), Model::As, Model::Ccv] {
        let mut one = SssPass::new(&d.device, &d.queue, 24, 16, model, false);
        let mut steps = SssPass::new(&d.device, &d.queue, 24, 16, model, false);
        for t in 0..4 {
            let f = inputs(t);
            let cfg = PassConfig::default();
            let p = one.frame_params(&cfg, &SKIN1, t).unwrap();
            assert_eq!(steps.frame_params(&cfg, &SKIN1, t).unwrap(), p, "one block");
            let a = one.run_frame(&p, &f).unwrap();
            let (b, times) = steps.run_frame_per_pass(&p, &f).unwrap();
            assert_eq!(a.count, b.count, "{model:?} frame {t}: counts");
            assert_eq!(a.result, b.result, "{model:?} frame {t}: results");
            assert_eq!(
                one.history().unwrap(),
                steps.history().unwrap(),
                "{model:?} frame {t}: history"
            );
            assert!(times.sampling_ms > 0.0, "{model:?}: sampling timed");
            let adaptive = !matches!(model, Model::Fixed(_));
            assert_eq!(times.update_ms > 0.0, adaptive, "{model:?}: update timed");
        }
    }
}
