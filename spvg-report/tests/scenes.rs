//! Scene definitions against docs/algorithms.md §7.

use spvg_report::scene::{Scene, SceneKind};

#[test]
fn flash_intensity_is_sin_5hz_plus_one() {
    let s = Scene::new(SceneKind::Flash, 8, 8);
    for t in 0..60 {
        let want = (2.0 * std::f64::consts::PI * 5.0 * f64::from(t) / 60.0).sin() + 1.0;
        let got = f64::from(s.lights(t).intensities[0]);
        assert!((got - want).abs() <= 1e-5, "frame {t}: {got} != {want}");
    }
}

#[test]
fn switch_toggles_every_three_seconds() {
    let s = Scene::new(SceneKind::Switch, 8, 8);
    let on = |t: u32| s.lights(t).intensities[0] > 0.5;
    assert!(on(0) && on(59), "on before t = 1 s");
    assert!(!on(60) && !on(239), "off from 1 s to 4 s");
    assert!(on(240) && on(419), "on from 4 s to 7 s");
    let flicker: Vec<f32> = (0..10).map(|t| s.lights(t).intensities[2]).collect();
    assert!(
        flicker.iter().all(|f| (0.6..=1.0).contains(f)),
        "flicker in [0.6, 1]: {flicker:?}"
    );
    assert!(
        flicker.windows(2).any(|w| w[0] != w[1]),
        "the small light flickers: {flicker:?}"
    );
}

#[test]
fn occluders_move_and_uncover_surface() {
    let s = Scene::new(SceneKind::Occluders, 64, 48);
    let a = s.inputs(0);
    let b = s.inputs(20);
    let uncovered = a
        .mask
        .iter()
        .zip(&b.mask)
        .filter(|(x, y)| **x == 0 && **y == 1)
        .count();
    assert!(uncovered > 0, "the disc uncovers surface (disocclusion)");
    assert_ne!(a.lighting, b.lighting, "the shadow bar moves");
    assert_eq!(s.inputs(20), b, "scenes are deterministic");
}

#[test]
fn static_scene_has_shadow_edge_and_depth_step() {
    let s = Scene::new(SceneKind::Static, 64, 48);
    let f = s.inputs(0);
    let depths: std::collections::BTreeSet<u32> = f.depth.iter().map(|z| z.to_bits()).collect();
    assert!(depths.len() >= 2, "a depth discontinuity");
    let lum: Vec<f32> = f.lighting.iter().map(|t| t[0].to_f32()).collect();
    let (lo, hi) = lum
        .iter()
        .fold((f32::MAX, 0.0_f32), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(hi > 5.0 * lo, "a shadow edge: lit {hi} vs shadowed {lo}");
    assert_eq!(s.inputs(0), s.inputs(7), "static lighting is constant");
}
