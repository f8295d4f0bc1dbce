//! The wgpu pass against its CPU twin on small scenes, every model, a few frames.
//!
//! What must be equal, and the one documented exception. The twin mirrors the WGSL op by
//! op, rounds every stored texel to f16 the same way (the shader rounds explicitly to
//! nearest-even before the store, because lavapipe's own f32 -> f16 store conversion
//! truncates), and uses polynomial sin/cos. So:
//!
//! - every count, on every pixel of every frame, is equal;
//! - every result texel is bit-identical except on at most [`MAX_RESULT_TEXELS`] of them,
//!   each by at most one f16 ulp: the f16 store rounds away the drivers' few-ulp
//!   `exp`/`log`/`pow`/`sqrt` differences in the sample weights, except where one falls
//!   across an f16 rounding boundary (measured on lavapipe: 1 texel of 1600, in one
//!   channel, the switch scene with AFIS at frame 1);
//! - every history texel is bit-identical except in its channels that run on the frame's
//!   luminances (`H`: mean and scaled variance; `J`, whose four channels all do:
//!   covariance, control variance and the means of both luminances), and there on
//!   at most [`MAX_MOMENT_TEXELS`] of the texels, each by at most [`MAX_MOMENT_ULPS`] f16
//!   ulps. Why (measured on lavapipe, 48x48 and 40x40, 4-5 frames: 0 to 6 texels of 2304
//!   per model, 1-3 ulps in the mean, 1-10 in the variance): the update reads the
//!   frame's monitored luminance in f32, before any f16 store, so a driver `exp` a few f32
//!   ulps off the core's moves a running mean across an f16 rounding boundary on a few
//!   texels; the variance is a difference of nearly equal moments, which turns one such
//!   step into several f16 ulps. The counts stay equal because the estimate reads the
//!   rounded history, and these texels' ratios to the target stay on the same side of
//!   every integer.

mod common;

use half::f16;
use spvg::burley::MaterialPreset;
use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_report::scene::{Scene, SceneKind};
use spvg_report::wgpu_api::{Model, PassConfig, SssTwin};

/// Most result texels (fraction) that may differ, each by one f16 ulp in a channel.
const MAX_RESULT_TEXELS: f64 = 0.002;

/// Most history texels (fraction) whose moment channels may differ.
const MAX_MOMENT_TEXELS: f64 = 0.005;

/// Largest difference of a moment channel, in f16 ulps (units in the last place of the
/// stored value: steps between adjacent f16 values of the same sign).
const MAX_MOMENT_ULPS: i32 = 16;

/// The channels of `H` that run on the frame's luminances (the exception above); its
/// third, the mean count, runs on the counts, which are equal.
const H_MOMENT_CHANNELS: &[usize] = &[0, 1];

/// The channels of `J` that run on the frame's luminances: all four.
const J_MOMENT_CHANNELS: &[usize] = &[0, 1, 2, 3];

/// Steps between two f16 values of the same sign (`i32::MAX` across signs).
fn ulps(a: f16, b: f16) -> i32 {
    if a == b {
        return 0;
    }
    let (x, y) = (a.to_bits() as i16, b.to_bits() as i16);
    if (x < 0) != (y < 0) {
        return i32::MAX;
    }
    (i32::from(x) - i32::from(y)).abs()
}

/// Checks one history buffer against the exception; returns the number of texels whose
/// moment channels differ.
fn check_history(
    what: &str,
    moment_channels: &[usize],
    gpu: &[[f16; 4]],
    twin: &[[f16; 4]],
) -> usize {
    assert_eq!(gpu.len(), twin.len(), "{what}: sizes");
    let mut differing = 0;
    for (i, (g, t)) in gpu.iter().zip(twin).enumerate() {
        let mut moment_differs = false;
        for c in 0..4 {
            let d = ulps(g[c], t[c]);
            if moment_channels.contains(&c) {
                assert!(
                    d <= MAX_MOMENT_ULPS,
                    "{what} texel {i} channel {c}: {} vs twin {} ({d} ulps > {MAX_MOMENT_ULPS})",
                    g[c],
                    t[c]
                );
                moment_differs |= d != 0;
            } else {
                assert_eq!(
                    g[c].to_bits(),
                    t[c].to_bits(),
                    "{what} texel {i} channel {c}: {} vs twin {}",
                    g[c],
                    t[c]
                );
            }
        }
        differing += usize::from(moment_differs);
    }
    let fraction = differing as f64 / gpu.len().max(1) as f64;
    eprintln!(
        "{what}: moment channels differ on {differing} of {} texels",
        gpu.len()
    );
    assert!(
        fraction <= MAX_MOMENT_TEXELS,
        "{what}: moment channels differ on {differing} of {} texels (> {MAX_MOMENT_TEXELS})",
        gpu.len()
    );
    differing
}

fn compare(kind: SceneKind, size: u32, frames: u32, material: &MaterialPreset, cfg: PassConfig) {
    let Some(dev) = common::device("gpu_matches_cpu_twin") else {
        return;
    };
    let scene = Scene::new(kind, size, size);
    for model in [Model::Fixed(16), Model::As, Model::Ccv, Model::Ocv] {
        let mut gpu = common::sss_pass(&dev, model, size, size);
        let mut twin = SssTwin::new(model, size, size);
        for t in 0..frames {
            let inputs = scene.inputs(t);
            let p = gpu.frame_params(&cfg, material, t).expect("valid params");
            let q = twin.frame_params(&cfg, material, t).expect("valid params");
            assert_eq!(p, q, "one block");
            let a = gpu.run_frame(&p, &inputs).expect("gpu frame");
            let b = twin.run_frame(&q, &inputs).expect("twin frame");
            let what = format!("{} {} frame {t}", kind.name(), model.name());
            let counts = a.count.iter().zip(&b.count).position(|(x, y)| x != y);
            assert_eq!(
                counts,
                None,
                "{what}: first differing count at that pixel ({:?} vs twin {:?})",
                counts.map(|i| a.count[i]),
                counts.map(|i| b.count[i])
            );
            let worst = |x: &[f16; 4], y: &[f16; 4]| (0..4).map(|c| ulps(x[c], y[c])).max();
            let far = a
                .result
                .iter()
                .zip(&b.result)
                .position(|(x, y)| worst(x, y) > Some(1));
            assert_eq!(
                far,
                None,
                "{what}: result more than one f16 ulp off at that pixel ({:?} vs twin {:?})",
                far.map(|i| a.result[i]),
                far.map(|i| b.result[i])
            );
            let off = a
                .result
                .iter()
                .zip(&b.result)
                .filter(|(x, y)| worst(x, y) == Some(1))
                .count();
            assert!(
                off as f64 <= MAX_RESULT_TEXELS * a.result.len() as f64,
                "{what}: {off} of {} result texels one ulp off",
                a.result.len()
            );
        }
        let (ha, hb) = (gpu.history().expect("history"), twin.history());
        let what = format!("{} {}", kind.name(), model.name());
        check_history(&format!("{what} H"), H_MOMENT_CHANNELS, &ha.h, &hb.h);
        check_history(&format!("{what} J"), J_MOMENT_CHANNELS, &ha.j, &hb.j);
    }
}

#[test]
fn gpu_matches_cpu_twin_flash() {
    compare(SceneKind::Flash, 48, 5, &SKIN1, PassConfig::default());
}

#[test]
fn gpu_matches_cpu_twin_occluders() {
    compare(SceneKind::Occluders, 48, 5, &MARBLE, PassConfig::default());
}

/// The scanned mesh's inputs (faceted irradiance, a masked-out ground, the bunny's depth
/// edges) through the pass.
#[test]
fn gpu_matches_cpu_twin_bunny() {
    compare(SceneKind::Mesh, 48, 5, &SKIN1, PassConfig::default());
}

#[test]
fn gpu_matches_cpu_twin_with_filtered_sampling() {
    let cfg = PassConfig {
        afis: true,
        ..PassConfig::default()
    };
    compare(SceneKind::Switch, 40, 4, &SKIN1, cfg);
}

/// The ulp distance the exception is measured in, against hand-counted f16 steps.
#[test]
fn ulps_count_f16_steps() {
    let one = f16::ONE;
    let next = f16::from_bits(one.to_bits() + 1);
    assert_eq!(ulps(one, one), 0);
    assert_eq!(ulps(one, next), 1);
    assert_eq!(
        ulps(f16::from_f32(2.0), f16::from_f32(1.0)),
        1024,
        "one binade"
    );
    assert_eq!(ulps(f16::from_f32(-1.0), f16::from_f32(1.0)), i32::MAX);
    assert_eq!(ulps(f16::ZERO, f16::NEG_ZERO), 0, "signed zeros are equal");
}
