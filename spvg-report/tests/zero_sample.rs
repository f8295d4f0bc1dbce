//! The zero-sample rule (docs/algorithms.md §2.4): where the distant ratio of the sampling profile is
//! below eps_u, the pixel takes no samples and returns the near part `(1 - gamma) B`, on
//! the GPU and in the twin, and its history is left cold.

mod common;

use spvg::burley::ShapeFit;
use spvg::burley::presets::SKIN1;
use spvg_report::scene::{Scene, SceneKind};
use spvg_report::wgpu_api::{Model, PassConfig, SssTwin};

#[test]
fn far_pixels_take_zero_samples() {
    let mut inputs = Scene::new(SceneKind::Static, 16, 16).inputs(0);
    // Left half far away: footprint radius 0.5 * 1e5 * sqrt(2) * 1e-3 = 70 mm, where even the
    // widest skin1 profile (d ~ 1.07 mm) keeps 0.75 e^{-70 / 3.2} ~ 2e-10 of its energy.
    for (i, z) in inputs.depth.iter_mut().enumerate() {
        if i % 16 < 8 {
            *z = 1e5;
        }
    }
    let cfg = PassConfig::default();
    let profiles = SKIN1
        .profiles::<f64>(ShapeFit::DiffuseMeanFreePath)
        .expect("preset");
    let dev = common::device("far_pixels_take_zero_samples");
    for model in [Model::Fixed(16), Model::As, Model::Ocv] {
        let mut twin = SssTwin::new(model, 16, 16);
        let p = twin.frame_params(&cfg, &SKIN1, 0).expect("valid params");
        let mut outs = vec![twin.run_frame(&p, &inputs).expect("cpu")];
        if let Some(d) = dev.as_ref() {
            let mut gpu = common::sss_pass(d, model, 16, 16);
            let q = gpu.frame_params(&cfg, &SKIN1, 0).expect("valid params");
            outs.push(gpu.run_frame(&q, &inputs).expect("gpu"));
        }
        for out in &outs {
            for i in 0..256 {
                if inputs.mask[i] == 0 {
                    continue;
                }
                let far = i % 16 < 8;
                assert_eq!(
                    out.count[i] == 0,
                    far,
                    "{model:?} pixel {i}: count {}",
                    out.count[i]
                );
                if far {
                    let r0 = 0.5 * 1e5 * (2.0_f64).sqrt() * 1e-3;
                    for (c, profile) in profiles.iter().enumerate() {
                        let gamma = profile.distant_ratio(r0);
                        let want = (1.0 - gamma) * f64::from(inputs.lighting[i][c].to_f32());
                        let got = f64::from(out.result[i][c].to_f32());
                        assert!(
                            (got - want).abs() <= 1e-3 * want.max(1e-3),
                            "{model:?} pixel {i}: {got} != {want}"
                        );
                    }
                }
            }
        }
    }
}
