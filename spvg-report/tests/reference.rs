//! The CPU twin's estimator converges to the independent f64 quadrature reference, and the
//! reference is linear in the lighting (what the per-basis references rely on).

use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_report::metrics::rgb;
use spvg_report::reference::{Quadrature, reference_bases};
use spvg_report::scene::{Lighting, Scene, SceneKind};
use spvg_report::wgpu_api::{Model, PassConfig, SssTwin, luminance};

#[test]
fn twin_converges_to_quadrature_reference() {
    for (material, lighting) in [(SKIN1, Lighting::Constant), (MARBLE, Lighting::Gradient)] {
        let scene = Scene {
            lighting,
            ..Scene::new(SceneKind::Static, 24, 24)
        };
        let cfg = PassConfig::default();
        let lights = scene.lights(0);
        let geo = scene.geometry(lights.state);
        let refs = reference_bases(
            24,
            24,
            &geo,
            &scene.bases(lights.state),
            &material,
            &cfg,
            Quadrature::default(),
        );
        let inputs = scene.inputs(0);
        let model = Model::Fixed(4096);
        let mut twin = SssTwin::new(model, 24, 24);
        let p = twin.frame_params(&cfg, &material, 0).expect("valid params");
        let out = twin.run_frame(&p, &inputs).expect("frame");
        let (mut se, mut n, mut worst) = (0.0_f64, 0, 0.0_f32);
        for i in 0..inputs.len() {
            if inputs.mask[i] == 0 {
                continue;
            }
            let want: [f32; 3] = core::array::from_fn(|c| {
                refs.iter()
                    .zip(&lights.intensities)
                    .map(|(b, k)| k * b[i][c])
                    .sum()
            });
            let d = luminance(rgb(out.result[i])) - luminance(want);
            se += f64::from(d * d);
            worst = worst.max(d.abs());
            n += 1;
        }
        let rmse = (se / f64::from(n)).sqrt();
        // 4096 R2 samples against the 64 x 64-node quadrature of a piecewise-smooth
        // integrand, plus f16 storage of the lighting and the result (relative 2^-11).
        // Measured in release: quadrature 32^2 / 64^2 / 128^2 nodes with 16384 samples give
        // rmse 1.2e-3 / 4.6e-4 / 2.0e-4, so the 64^2 reference is good to about 5e-4.
        let tol = 1e-3;
        eprintln!(
            "{} {lighting:?}: rmse {rmse:.2e}, worst {worst:.2e}",
            material.name
        );
        assert!(
            rmse <= tol,
            "{} {lighting:?}: rmse {rmse} > {tol} (worst {worst})",
            material.name
        );
    }
}

#[test]
fn reference_is_linear_in_lighting() {
    let scene = Scene::new(SceneKind::Switch, 20, 16);
    let cfg = PassConfig::default();
    let geo = scene.geometry(0);
    let bases = scene.bases(0);
    let q = Quadrature {
        radial: 8,
        angular: 8,
    };
    let each = reference_bases(20, 16, &geo, &bases, &SKIN1, &cfg, q);
    let k = [0.3_f32, 1.7, 0.9];
    let sum: Vec<[f32; 3]> = (0..bases[0].len())
        .map(|i| core::array::from_fn(|c| bases.iter().zip(k).map(|(b, w)| w * b[i][c]).sum()))
        .collect();
    let combined = reference_bases(20, 16, &geo, &[sum], &SKIN1, &cfg, q);
    for i in 0..combined[0].len() {
        for c in 0..3 {
            let want: f32 = each.iter().zip(k).map(|(r, w)| w * r[i][c]).sum();
            let got = combined[0][i][c];
            assert!(
                (got - want).abs() <= 1e-5 * (1.0 + want.abs()),
                "pixel {i} channel {c}: {got} != {want}"
            );
        }
    }
}
