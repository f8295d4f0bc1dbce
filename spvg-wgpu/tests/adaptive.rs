//! The adaptive component: its WGSL validated by naga (no GPU needed), its CPU twin against
//! independent properties of reprojection, and the GPU against the twin, bit for bit, on
//! moving scenes (pans at fractional speeds, an occluder crossing the surface, a mask hole,
//! the zero-sample rule, non-finite inputs; and with the firefly clamp on, 100x outliers).
//! GPU tests skip cleanly without an adapter.

mod common;

use common::scene::{Frame, MovingScene, Textures, data, hash, textures};

use half::f16;
use spvg::SpvgConfig;
use spvg::cv::Ocv;
use spvg::reproject::{BorderCount, Reprojection};
use spvg::texel::{SpvgTexel16, TexelEncoding};
use spvg_wgpu::adaptive::AdaptiveSettings;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveTwin, Control, EstimateData, EstimateInputs, Masks,
    UpdateData, UpdateInputs,
};
use spvg_wgpu::util::read_texture;

fn config() -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .target_variance(1e-3)
        .kappa(0.5)
        // the papers' rules (the seed keeps sigma0^2); the young-history tests switch theirs on.
        .spatial_variance(0)
        .build()
        .expect("valid config")
}

fn controls() -> [Control; 3] {
    [
        Control::As,
        Control::Ccv,
        Control::Ocv(Ocv::with_weight(0.2).expect("valid eta_cv")),
    ]
}

#[test]
fn gpu_matches_twin_on_moving_scene() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("adaptive gpu_matches_twin_on_moving_scene").device()
    else {
        return;
    };
    gpu_matches_twin(&dev, config(), false);
}

/// The firefly clamp on (`k` = 4, through the pass's `spvg_Params`), in the moving scene
/// with 100x outliers on every seventh pixel in frames 6 and 9: the pass equals the twin
/// bit for bit, and the clamp changed the twin's histories (against a twin without it).
#[test]
fn gpu_matches_twin_with_the_firefly_clamp() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("adaptive gpu_matches_twin_with_the_firefly_clamp").device()
    else {
        return;
    };
    let clamped = config()
        .to_builder()
        .firefly_clamp(Some(4.0))
        .build()
        .expect("valid config");
    gpu_matches_twin(&dev, clamped, true);
}

/// The young-history rules on (the age-aware weight and the spatial variance for ages up
/// to 2, through the pass's `spvg_Params`), in the moving scene: the pass equals the twin
/// bit for bit (the ages in the spare channel included), and the rules changed the twin's
/// histories (against a twin without them).
#[test]
fn gpu_matches_twin_with_the_young_history_rules() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("adaptive gpu_matches_twin_with_the_young_history_rules")
            .device()
    else {
        return;
    };
    let young = config()
        .to_builder()
        .age_weight(true)
        .spatial_variance(2)
        .build()
        .expect("valid config");
    gpu_matches_twin(&dev, young, false);
}

/// The depth-aware neighbour prior under count dilation (radius 1), with the young-history
/// rules: the pass equals the twin bit for bit, and the prior raised the counts of pixels
/// without history (against a twin without it).
#[test]
fn gpu_matches_twin_with_the_neighbour_prior() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("adaptive gpu_matches_twin_with_the_neighbour_prior").device()
    else {
        return;
    };
    let young = config()
        .to_builder()
        .age_weight(true)
        .spatial_variance(2)
        .build()
        .expect("valid config");
    PRIOR.with(|p| p.set(true));
    gpu_matches_twin(&dev, young, false);
    PRIOR.with(|p| p.set(false));
}

thread_local! {
    /// Whether `gpu_matches_twin` runs with count dilation 1 and the neighbour prior.
    static PRIOR: core::cell::Cell<bool> = const { core::cell::Cell::new(false) };
}

/// Frame `t` of the moving scene, with 100x outliers on every seventh pixel in frames 6
/// and 9 when `outliers`.
fn scene_frame(scene: &MovingScene, t: u32, outliers: bool) -> Frame {
    let mut f = scene.frame(t);
    if outliers && (t == 6 || t == 9) {
        for v in f.value.iter_mut().step_by(7) {
            *v *= 100.0;
        }
    }
    f
}

fn gpu_matches_twin(dev: &spvg_gpu_test::GpuDevice, config: SpvgConfig<f32>, outliers: bool) {
    gpu_matches_twin_for(dev, config, outliers, 14);
}

/// [`gpu_matches_twin`] over `frames` frames; returns, per control model, the pixel-frames
/// that skipped a frame under a fractional count (no sample, a continued history) and
/// those whose count was a fractional decision.
fn gpu_matches_twin_for(
    dev: &spvg_gpu_test::GpuDevice,
    config: SpvgConfig<f32>,
    outliers: bool,
    frames: u32,
) -> Vec<(usize, usize)> {
    let (w, h) = (45, 26); // not multiples of the 8x8 workgroup
    let scene = MovingScene { w, h };
    let mut fractional = Vec::new();
    for control in controls() {
        let mut gpu = AdaptivePass::new(&dev.device, common::settings(config, control), w, h)
            .expect("gpu pass");
        let mut twin = AdaptiveTwin::new(common::settings(config, control), w, h).expect("twin");
        // The same twin without the clamp and the young-history rules: where they act,
        // the histories differ.
        let unclamped = config
            .to_builder()
            .firefly_clamp(None)
            .age_weight(false)
            .spatial_variance(0)
            .build();
        let mut plain =
            AdaptiveTwin::new(common::settings(unclamped.expect("valid"), control), w, h)
                .expect("twin");
        let prior = PRIOR.with(core::cell::Cell::get);
        let mut raised = 0;
        if prior {
            gpu.set_settings(AdaptiveSettings {
                dilation: 1,
                ..*gpu.settings()
            })
            .expect("radius");
            gpu.set_settings(AdaptiveSettings {
                neighbour_prior: true,
                ..*gpu.settings()
            })
            .expect("settings");
            twin.set_settings(AdaptiveSettings {
                dilation: 1,
                ..*twin.settings()
            })
            .expect("radius");
            twin.set_settings(AdaptiveSettings {
                neighbour_prior: true,
                ..*twin.settings()
            })
            .expect("settings");
            plain
                .set_settings(AdaptiveSettings {
                    dilation: 1,
                    ..*plain.settings()
                })
                .expect("radius");
            plain
                .set_settings(AdaptiveSettings {
                    neighbour_prior: false,
                    ..*plain.settings()
                })
                .expect("settings");
        }
        let mut clamp_acted = 0;
        let (mut prev, mut prev_tex) = (scene.frame(0), None::<Textures>);
        let (mut invalid_seen, mut above_min) = (0, 0);
        let (mut skipped, mut decided) = (0, 0);
        for t in 0..frames {
            let cur = scene_frame(&scene, t, outliers);
            let tex = textures(dev, &cur, w, h);
            let ptex = prev_tex.as_ref().unwrap_or(&tex);
            let mut enc = dev.device.create_command_encoder(&Default::default());
            gpu.record_estimate(
                &mut enc,
                &EstimateInputs::new(&tex.motion, &tex.depth, &ptex.depth)
                    .with_masks(Some(Masks {
                        current: &tex.mask,
                        previous: &ptex.mask,
                    }))
                    .with_gamma(Some(&tex.gamma))
                    .with_resolve_weight(Some(&tex.resolve)),
            )
            .expect("estimate inputs are valid");
            gpu.record_update(
                &mut enc,
                &UpdateInputs::new(&tex.value).with_control(Some(&tex.control)),
            )
            .expect("update inputs are valid");
            dev.queue.submit([enc.finish()]);
            let count_gpu: Vec<u32> =
                read_texture(&dev.device, &dev.queue, gpu.count_texture()).expect("readback");
            let hist_gpu: Vec<[f16; 4]> =
                read_texture(&dev.device, &dev.queue, gpu.history_texture()).expect("readback");

            let count_cpu = twin.estimate(&data(&cur, &prev)).expect("twin").to_vec();
            invalid_seen += twin
                .valid()
                .iter()
                .zip(&cur.mask)
                .filter(|(v, m)| !**v && **m != 0)
                .count();
            above_min += count_cpu.iter().filter(|&&n| n > 8).count();
            let real = twin.real_counts();
            decided += real.iter().filter(|&&c| c >= 0.0).count();
            skipped += real
                .iter()
                .zip(&count_cpu)
                .zip(twin.links())
                .filter(|((c, n), l)| **c >= 0.0 && **n == 0 && **l != 0)
                .count();
            twin.update(&UpdateData::new(&cur.value).with_control(Some(&cur.control)))
                .expect("twin");
            let plain_counts = plain.estimate(&data(&cur, &prev)).expect("twin").to_vec();
            if prior {
                raised += count_cpu
                    .iter()
                    .zip(&plain_counts)
                    .zip(twin.valid())
                    .filter(|((a, b), v)| !*v && a > b)
                    .count();
            }
            plain
                .update(&UpdateData::new(&cur.value).with_control(Some(&cur.control)))
                .expect("twin");
            if t == 6 {
                clamp_acted = common::bits(twin.history())
                    .iter()
                    .zip(common::bits(plain.history()))
                    .filter(|(a, b)| **a != *b)
                    .count();
            }
            let name = control.name();
            let differ = count_gpu
                .iter()
                .zip(&count_cpu)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(differ, 0, "{name} frame {t}: {differ} counts differ");
            let differ = common::bits(&hist_gpu)
                .iter()
                .zip(common::bits(twin.history()))
                .filter(|(a, b)| **a != *b)
                .count();
            assert_eq!(
                differ, 0,
                "{name} frame {t}: {differ} history texels differ"
            );
            if let Some(cv) = gpu.cv_history_texture() {
                let cv_gpu: Vec<[f16; 4]> =
                    read_texture(&dev.device, &dev.queue, cv).expect("readback");
                let cv_cpu = twin.cv_history().expect("OCV twin has a CV history");
                assert_eq!(
                    common::bits(&cv_gpu),
                    common::bits(cv_cpu),
                    "{name} frame {t}: CV history"
                );
            }
            (prev, prev_tex) = (cur, Some(tex));
        }
        eprintln!(
            "{}: {invalid_seen} invalid-history pixel-frames, {above_min} counts above the minimum",
            control.name()
        );
        if config.firefly_clamp().is_some() || config.age_weight() {
            eprintln!(
                "{}: the clamp or the young rules changed {clamp_acted} texels in frame 6",
                control.name()
            );
            assert!(
                clamp_acted > 50,
                "{}: the clamp changed only {clamp_acted} texels",
                control.name()
            );
        }
        if prior {
            eprintln!("{}: the prior raised {raised} counts", control.name());
            assert!(
                raised > 50,
                "{}: the prior raised only {raised} counts",
                control.name()
            );
        }
        // The scene must exercise both paths, or the equality above proves little.
        assert!(
            invalid_seen > 200,
            "{}: only {invalid_seen} disoccluded pixel-frames",
            control.name()
        );
        assert!(
            above_min > 500,
            "{}: only {above_min} counts above the minimum",
            control.name()
        );
        fractional.push((skipped, decided));
    }
    fractional
}

/// Fractional counts (a floor of 0.25; docs/algorithms.md §8.6) with the young-history
/// rules, without and with the count dilation and its neighbour prior: the dithered
/// decision (the count realised
/// from the real count with the pixel's and frame's threshold), the real counts the
/// update records, skipped frames (their histories carried with a new mean count, the
/// CV state carried) and the span weight give the same counts and history texels on the
/// GPU as on the twin, bit for bit, on every frame; and the scene reaches them: thousands
/// of fractional decisions and hundreds of skipped frames per control model.
#[test]
fn gpu_equals_twin_for_the_dithered_decision() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("adaptive gpu_equals_twin_for_the_dithered_decision").device()
    else {
        return;
    };
    let fractional = config()
        .to_builder()
        .target_variance(4e-3)
        .age_weight(true)
        .spatial_variance(3)
        .fractional_floor(Some(0.25))
        .build()
        .expect("valid config");
    for prior in [false, true] {
        PRIOR.with(|p| p.set(prior));
        let seen = gpu_matches_twin_for(&dev, fractional, false, 24);
        PRIOR.with(|p| p.set(false));
        for ((skipped, decided), control) in seen.iter().zip(controls()) {
            eprintln!(
                "{} (dilation {}): {decided} fractional decisions, {skipped} skipped frames",
                control.name(),
                u32::from(prior)
            );
            assert!(
                *decided > 5000,
                "{}: only {decided} decisions",
                control.name()
            );
            assert!(
                *skipped > 300,
                "{}: only {skipped} skipped frames",
                control.name()
            );
        }
    }
}

/// The resolved-image rule (docs/algorithms.md §8.7: the resolve weight derived from each
/// history's age where the renderer's per-pixel weight reads "none", the weight itself
/// elsewhere; steady weight 0.1) at floor 0, whose revisit count keeps converged
/// pixels sampling: the same counts and history texels on the GPU as on the twin, bit
/// for bit, on every frame, with the scene reaching the rule (thousands of fractional
/// decisions, hundreds of skipped frames per control model).
#[test]
fn gpu_equals_twin_with_the_resolved_image_rule() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("adaptive gpu_equals_twin_with_the_resolved_image_rule")
            .device()
    else {
        return;
    };
    let resolved = config()
        .to_builder()
        .target_variance(4e-3)
        .fractional_floor(Some(0.0))
        .resolve_weight(Some(0.1))
        .build()
        .expect("valid config");
    let seen = gpu_matches_twin_for(&dev, resolved, false, 24);
    for ((skipped, decided), control) in seen.iter().zip(controls()) {
        eprintln!(
            "{}: {decided} fractional decisions, {skipped} skipped frames",
            control.name()
        );
        assert!(
            *decided > 5000,
            "{}: only {decided} decisions",
            control.name()
        );
        assert!(
            *skipped > 300,
            "{}: only {skipped} skipped frames",
            control.name()
        );
    }
}

/// The renderer's resolve weight of 1 at every pixel is the per-frame rule: the twin with
/// the resolved-image rule fed that input takes the counts of the twin without the rule
/// on every frame, while the same rule without the input (the history's age) takes
/// fewer samples once histories settle.
#[test]
fn a_resolve_weight_of_one_is_the_per_frame_rule() {
    let (w, h) = (45, 26);
    let scene = MovingScene { w, h };
    let build = |resolve: Option<f32>| {
        config()
            .to_builder()
            .target_variance(4e-3)
            .fractional_floor(Some(0.0))
            .resolve_weight(resolve)
            .build()
            .expect("valid config")
    };
    let twin = |c| AdaptiveTwin::new(common::settings(c, Control::As), w, h).expect("twin");
    let (mut per_frame, mut with_one, mut by_age) = (
        twin(build(None)),
        twin(build(Some(0.1))),
        twin(build(Some(0.1))),
    );
    let ones = vec![1.0_f32; (w * h) as usize];
    let mut prev = scene.frame(0);
    let (mut spent_per_frame, mut spent_by_age) = (0_u64, 0_u64);
    for t in 0..16 {
        let cur = scene.frame(t);
        let d = data(&cur, &prev);
        let a = per_frame
            .estimate(&d.with_resolve_weight(None))
            .expect("twin")
            .to_vec();
        let b = with_one
            .estimate(&d.with_resolve_weight(Some(&ones)))
            .expect("twin")
            .to_vec();
        let c = by_age
            .estimate(&d.with_resolve_weight(None))
            .expect("twin")
            .to_vec();
        assert_eq!(a, b, "frame {t}: a weight of 1 is the per-frame rule");
        spent_per_frame += a.iter().map(|&n| u64::from(n)).sum::<u64>();
        spent_by_age += c.iter().map(|&n| u64::from(n)).sum::<u64>();
        let update = UpdateData::new(&cur.value);
        for twin in [&mut per_frame, &mut with_one, &mut by_age] {
            twin.update(&update).expect("twin");
        }
        prev = cur;
    }
    assert!(
        2 * spent_by_age < spent_per_frame,
        "the age alone spends {spent_by_age} samples, the per-frame rule {spent_per_frame}"
    );
}

/// Runs `frames` frames of a scene defined in world space on `twin`, the camera at integer
/// offset `pan(t)`, returning the twin. Every pixel's value depends only on the world
/// point and the frame, so a valid reprojection makes the panned history equal the
/// world-anchored one.
fn run_world(twin: &mut AdaptiveTwin, w: u32, h: u32, frames: u32, pan: impl Fn(u32) -> [i32; 2]) {
    for t in 0..frames {
        let (c, cp) = (pan(t), pan(t.saturating_sub(1)));
        let n = (w * h) as usize;
        let v = [(cp[0] - c[0]) as f32, (cp[1] - c[1]) as f32];
        let motion = vec![v; n];
        let depth = vec![2.0_f32; n];
        let value: Vec<f32> = (0..n as u32)
            .map(|i| {
                let (wx, wy) = ((i % w) as i32 + c[0], (i / w) as i32 + c[1]);
                let cell = ((wx + 500) * 2048 + wy + 500) as u64;
                0.4 + 0.3 * hash(cell) * hash(cell * 977 + u64::from(t))
            })
            .collect();
        let d = EstimateData::new(&motion, &depth, &depth);
        twin.estimate(&d).expect("twin estimate");
        twin.update(&UpdateData::new(&value)).expect("twin update");
    }
}

#[test]
fn integer_pan_carries_the_history_with_the_surface() {
    // Independent reference: the same world-anchored values seen by a static camera over
    // a larger frame. After an integer pan, every pixel that stayed on screen holds
    // exactly the static run's history of its world point.
    let (w, h, frames) = (16, 10, 12);
    let pan = |t: u32| [(t / 2) as i32, -((t / 3) as i32)];
    let mut moving =
        AdaptiveTwin::new(common::settings(config(), Control::As), w, h).expect("twin");
    run_world(&mut moving, w, h, frames, pan);
    let (sw, sh) = (w + frames, h + frames);
    let origin = [0, -((frames as i32) / 2)];
    let mut fixed =
        AdaptiveTwin::new(common::settings(config(), Control::As), sw, sh).expect("twin");
    run_world(&mut fixed, sw, sh, frames, |_| origin);
    let c = pan(frames - 1);
    let mut compared = 0;
    for y in 0..h {
        for x in 0..w {
            // Pixels whose world point entered the frame during the pan are younger.
            let entered = x as i32 + c[0] >= w as i32 || y as i32 + c[1] < 0;
            if entered {
                continue;
            }
            let (wx, wy) = (x as i32 + c[0] - origin[0], y as i32 + c[1] - origin[1]);
            let s = fixed.history()[(wy as u32 * sw + wx as u32) as usize];
            let m = moving.history()[(y * w + x) as usize];
            assert_eq!(
                m.map(f16::to_bits),
                s.map(f16::to_bits),
                "pixel ({x}, {y}) world ({wx}, {wy})"
            );
            compared += 1;
        }
    }
    assert!(compared > 60, "only {compared} pixels compared");
}

#[test]
fn identity_history_differs_from_reprojected_under_a_pan() {
    // With zero motion vectors fed during a pan (today's identity history), pixels keep
    // the statistics of whatever slid under them: the histories disagree with the
    // reprojected run, which matches the world-anchored reference above.
    let (w, h, frames) = (12, 8, 10);
    let pan = |t: u32| [t as i32, 0];
    let mut right = AdaptiveTwin::new(common::settings(config(), Control::As), w, h).expect("twin");
    run_world(&mut right, w, h, frames, pan);
    let mut identity =
        AdaptiveTwin::new(common::settings(config(), Control::As), w, h).expect("twin");
    let n = (w * h) as usize;
    for t in 0..frames {
        let c = pan(t);
        let value: Vec<f32> = (0..n as u32)
            .map(|i| {
                let (wx, wy) = ((i % w) as i32 + c[0], (i / w) as i32 + c[1]);
                let cell = ((wx + 500) * 2048 + wy + 500) as u64;
                0.4 + 0.3 * hash(cell) * hash(cell * 977 + u64::from(t))
            })
            .collect();
        let depth = vec![2.0_f32; n];
        let still = vec![[0.0, 0.0]; n];
        let d = EstimateData::new(&still, &depth, &depth);
        identity.estimate(&d).expect("twin");
        identity.update(&UpdateData::new(&value)).expect("twin");
    }
    let differ = right
        .history()
        .iter()
        .zip(identity.history())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > n / 2, "only {differ} of {n} histories differ");
}

#[test]
fn disoccluded_pixels_are_seeded_from_their_first_observation() {
    // A 6x1 surface; an occluder (depth 0.5) covers pixels 2..4 in frame 0 and leaves in
    // frame 1. The uncovered pixels' histories were the occluder's: rejected by the depth
    // test, they take beta_min and are seeded with mean = S, variance = sigma0^2, count.
    let c = config();
    let mut twin = AdaptiveTwin::new(common::settings(c, Control::As), 6, 1).expect("twin");
    let d0 = [1.0, 1.0, 0.5, 0.5, 1.0, 1.0];
    let d1 = [1.0_f32; 6];
    let zero = [[0.0_f32, 0.0]; 6];
    for (t, (depth, prev)) in [(&d0, &d0), (&d0, &d0), (&d1, &d0)].into_iter().enumerate() {
        let n = twin
            .estimate(&EstimateData::new(&zero, depth, prev))
            .expect("twin")
            .to_vec();
        let value = [0.1, 0.9, 0.3, 0.7, 0.2, 0.8].map(|v: f32| v + 0.05 * t as f32);
        if t == 2 {
            assert_eq!(twin.valid(), [true, true, false, false, true, true]);
            assert_eq!(&n[2..4], &[8, 8], "uncovered pixels take beta_min");
        }
        twin.update(&UpdateData::new(&value)).expect("twin");
        if t == 2 {
            let enc = TexelEncoding::for_config(&c).expect("encoding");
            for (i, &v) in value.iter().enumerate().take(4).skip(2) {
                let got = enc.decode(SpvgTexel16(twin.history()[i]));
                assert_eq!(got.mean, f16::from_f32(v).to_f32(), "mean of {i}");
                // The seed is the target as the f16 texel stores it: not above it, at most
                // one f16 step (2^-10 of it) below (TexelEncoding::storable_config).
                let target = c.target_variance();
                assert!(
                    got.variance <= target && got.variance >= target * (1.0 - 2f32.powi(-10)),
                    "variance of {i}: {} for {target}",
                    got.variance
                );
                assert_eq!(got.mean_count, 8.0, "count of {i}");
            }
        }
    }
}

/// Six frames of a static 8x1 surface at depth 1 whose every pixel has the value
/// `value(t)` at frame `t`, then a pan of 3 px (pixels 5..8 enter from the right): the
/// counts of the pan's frame.
fn counts_after_a_pan(twin: &mut AdaptiveTwin, value: impl Fn(u32) -> f32) -> Vec<u32> {
    let depth = [1.0_f32; 8];
    let mut counts = Vec::new();
    for t in 0..7_u32 {
        let v = if t == 6 { -3.0 } else { 0.0 };
        counts = twin
            .estimate(&EstimateData::new(&[[v, 0.0]; 8], &depth, &depth))
            .expect("twin")
            .to_vec();
        twin.update(&UpdateData::new(&[value(t); 8])).expect("twin");
    }
    counts
}

#[test]
fn pixels_entering_the_frame_take_the_border_count() {
    // An 8x1 surface, noisy enough (values alternating 0 / 1: variance 0.25 per frame
    // against sigma0^2 = 1e-3) that every pixel asks for beta_max = 64 after a few static
    // frames. Then the camera pans 3 px: pixels 5..8 enter from the right. With the border
    // prior and BorderCount::Texel they take the count of border texel 4's history (64,
    // as every steady pixel), and are still seeded as disoccluded; without it they take
    // beta_min.
    let c = config();
    let run = |prior: bool| {
        let mut twin = AdaptiveTwin::new(common::settings(c, Control::As), 8, 1).expect("twin");
        twin.set_settings(AdaptiveSettings {
            reprojection: Reprojection::default()
                .with_border_prior(prior)
                .with_border_count(BorderCount::Texel),
            ..*twin.settings()
        })
        .expect("settings");
        let counts = counts_after_a_pan(&mut twin, |t| (t % 2) as f32);
        (counts, twin.valid(), twin.history().to_vec())
    };
    let (on, valid, hist) = run(true);
    let (off, valid_off, _) = run(false);
    assert_eq!(&on[..5], &[64; 5], "steady pixels");
    assert_eq!(&on[5..], &[64; 3], "entering pixels with the border prior");
    assert_eq!(&off[5..], &[8; 3], "entering pixels without it: beta_min");
    assert_eq!(valid, valid_off, "the prior does not make a history valid");
    assert_eq!(valid, [true, true, true, true, true, false, false, false]);
    let enc = TexelEncoding::for_config(&c).expect("encoding");
    for (i, t) in hist.iter().enumerate().skip(5) {
        let h = enc.decode(SpvgTexel16(*t));
        assert_eq!(h.mean, 0.0, "seeded mean of {i}: the frame-6 value");
        assert_eq!(h.mean_count, 64.0, "seeded count of {i}: the count used");
    }
}

#[test]
fn pixels_entering_the_frame_take_beta_max_by_default() {
    // A quiet 8x1 surface (constant values: every pixel at beta_min = 8 after a few static
    // frames), then a pan of 3 px: pixels 5..8 enter from the right. The border texel 4 is
    // on the same surface: by default (BorderCount::Maximum) they take beta_max; with
    // BorderCount::Texel the border texel's count, 8; without the prior beta_min, 8.
    let c = config();
    let run = |r: Reprojection<f32>| {
        let mut twin = AdaptiveTwin::new(common::settings(c, Control::As), 8, 1).expect("twin");
        twin.set_settings(AdaptiveSettings {
            reprojection: r,
            ..*twin.settings()
        })
        .expect("settings");
        counts_after_a_pan(&mut twin, |_| 0.5)
    };
    let default = run(Reprojection::default());
    assert_eq!(default, [8, 8, 8, 8, 8, 64, 64, 64], "entering: beta_max");
    let texel = run(Reprojection::default().with_border_count(BorderCount::Texel));
    assert_eq!(texel, [8; 8], "entering: the border texel's count");
    let far = |_: [u32; 2]| spvg::reproject::PreviousSample {
        mask: true,
        depth: 2.0,
    };
    assert_eq!(
        Reprojection::<f32>::default().locate([6, 0], [-3.0, 0.0], 1.0, [8, 1], [8, 1], far),
        spvg::reproject::HistorySource::Disoccluded,
        "a border texel on another surface gives no prior, so beta_min"
    );
}

#[test]
fn resize_and_depth_tolerance() {
    let mut twin = AdaptiveTwin::new(common::settings(config(), Control::As), 4, 2).expect("twin");
    let d = [1.0_f32; 8];
    let step = |twin: &mut AdaptiveTwin, prev: &[f32], depth: &[f32]| {
        let n = twin.size().iter().product::<u32>() as usize;
        twin.estimate(&EstimateData::new(&vec![[0.0, 0.0]; n], depth, prev))
            .expect("twin");
        twin.update(&UpdateData::new(&vec![0.5; n])).expect("twin");
        twin.valid()
    };
    step(&mut twin, &d, &d);
    assert!(step(&mut twin, &d, &d).iter().all(|&v| v), "steady");
    // 3% deeper: rejected at the default 2%, accepted at 5%.
    let deeper = [1.03_f32; 8];
    assert!(
        step(&mut twin, &d, &deeper).iter().all(|&v| !v),
        "2% rejects 3%"
    );
    twin.set_settings(AdaptiveSettings {
        reprojection: Reprojection::new(0.05).expect("valid tolerance"),
        ..*twin.settings()
    })
    .expect("settings");
    assert!(
        step(&mut twin, &deeper, &d).iter().all(|&v| v),
        "5% accepts 3%"
    );
    twin.resize(2, 2).expect("resize");
    let small = [1.0_f32; 4];
    assert!(
        step(&mut twin, &small, &small).iter().all(|&v| !v),
        "resize invalidates"
    );
    assert!(matches!(
        twin.resize(0, 2),
        Err(AdaptiveError::FrameSize { width: 0, .. })
    ));
}

#[test]
fn twin_rejects_bad_inputs_by_name() {
    let mut twin = AdaptiveTwin::new(common::settings(config(), Control::Ccv), 4, 2).expect("twin");
    let d = [1.0_f32; 8];
    let m = [[0.0_f32; 2]; 8];
    assert_eq!(
        twin.update(&UpdateData::new(&d).with_control(Some(&d)))
            .unwrap_err(),
        AdaptiveError::UpdateWithoutEstimate
    );
    let short = EstimateData::new(&m[..7], &d, &d);
    assert!(matches!(
        twin.estimate(&short),
        Err(AdaptiveError::SliceLength {
            input: "motion",
            expected: 8,
            got: 7
        })
    ));
    let mut ok = short;
    ok.motion = &m;
    twin.estimate(&ok).expect("valid inputs");
    assert!(matches!(
        twin.update(&UpdateData::new(&d)),
        Err(AdaptiveError::MissingInput {
            input: "control",
            ..
        })
    ));
    let unreal = config()
        .with_policy(spvg::controller::CountPolicy::UnrealClamp)
        .expect("valid policy");
    assert!(matches!(
        AdaptiveTwin::new(common::settings(unreal, Control::As), 4, 2),
        Err(AdaptiveError::UnsupportedPolicy(_))
    ));
    // The allocation exponent is CPU-only: the component refuses p != 1 by name.
    let neyman = config()
        .to_builder()
        .allocation_exponent(0.5)
        .build()
        .expect("valid exponent");
    assert!(matches!(
        AdaptiveTwin::new(common::settings(neyman, Control::As), 4, 2),
        Err(AdaptiveError::Param(spvg::Error::InvalidParameter {
            name: "allocation_exponent",
            ..
        }))
    ));
    let too_wide = twin.set_settings(AdaptiveSettings {
        dilation: spvg::dilation::MAX_RADIUS + 1,
        ..*twin.settings()
    });
    assert!(
        matches!(
            too_wide,
            Err(AdaptiveError::Param(spvg::Error::InvalidParameter {
                name: "radius",
                ..
            }))
        ),
        "{too_wide:?}"
    );
    assert_eq!(
        twin.settings().dilation,
        0,
        "a refused radius changes nothing"
    );
}

#[test]
fn gpu_rejects_bad_textures_without_a_wgpu_error() {
    let Some(dev) = spvg_gpu_test::GpuTest::new("adaptive gpu_rejects_bad_textures").device()
    else {
        return;
    };
    let (w, h) = (8, 4);
    let f = MovingScene { w, h }.frame(1);
    let tex = textures(&dev, &f, w, h);
    let scope = dev.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut pass = AdaptivePass::new(&dev.device, common::settings(config(), Control::Ccv), w, h)
        .expect("pass");
    let mut enc = dev.device.create_command_encoder(&Default::default());
    let good = EstimateInputs::new(&tex.motion, &tex.depth, &tex.depth);
    assert_eq!(
        pass.record_update(
            &mut enc,
            &UpdateInputs::new(&tex.value).with_control(Some(&tex.control))
        )
        .unwrap_err(),
        AdaptiveError::UpdateWithoutEstimate
    );
    rejects_bad_estimate_inputs(&dev, &mut pass, &mut enc, &tex, good);
    pass.record_estimate(&mut enc, &good).expect("valid inputs");
    assert!(matches!(
        pass.record_update(&mut enc, &UpdateInputs::new(&tex.value)),
        Err(AdaptiveError::MissingInput {
            input: "control",
            ..
        })
    ));
    pass.record_update(
        &mut enc,
        &UpdateInputs::new(&tex.value).with_control(Some(&tex.control)),
    )
    .expect("valid inputs");
    dev.queue.submit([enc.finish()]);
    assert!(matches!(
        pass.resize(0, 4),
        Err(AdaptiveError::FrameSize { .. })
    ));
    assert!(matches!(
        AdaptivePass::new(
            &dev.device,
            common::settings(config(), Control::As),
            1 << 20,
            4
        ),
        Err(AdaptiveError::FrameSize { .. })
    ));
    let err = pollster::block_on(scope.pop());
    assert!(err.is_none(), "wgpu validation error: {err:?}");
}

/// Each wrong estimate input (size, format, mask format, usage) is its typed error, named.
fn rejects_bad_estimate_inputs(
    dev: &spvg_gpu_test::GpuDevice,
    pass: &mut AdaptivePass,
    enc: &mut wgpu::CommandEncoder,
    tex: &Textures,
    good: EstimateInputs<'_>,
) {
    use wgpu::TextureFormat as F;
    let [w, h] = pass.size();
    let wrong_size = common::upload(
        dev,
        F::R32Float,
        [w + 1, h],
        &vec![1.0_f32; ((w + 1) * h) as usize],
    );
    assert!(
        matches!(
            pass.record_estimate(enc, &{
                let mut i = good;
                i.depth = &wrong_size;
                i
            }),
            Err(AdaptiveError::TextureSize {
                input: "depth",
                expected: [8, 4],
                got: [9, 4, 1]
            })
        ),
        "a depth of the wrong size: TextureSize naming depth"
    );
    assert!(
        matches!(
            pass.record_estimate(enc, &{
                let mut i = good;
                i.motion = &tex.depth;
                i
            }),
            Err(AdaptiveError::TextureFormat {
                input: "motion",
                got: F::R32Float,
                ..
            })
        ),
        "a depth texture as motion: TextureFormat naming motion"
    );
    assert!(
        matches!(
            pass.record_estimate(
                enc,
                &good.with_masks(Some(Masks {
                    current: &tex.mask,
                    previous: &tex.depth
                }))
            ),
            Err(AdaptiveError::TextureFormat {
                input: "masks.previous",
                ..
            })
        ),
        "a float previous mask: TextureFormat naming masks.previous"
    );
    let no_binding = dev.device.create_texture(&spvg_wgpu::util::texture_2d_desc(
        "no binding",
        F::R32Float,
        [w, h],
        wgpu::TextureUsages::COPY_DST,
    ));
    assert!(
        matches!(
            pass.record_estimate(enc, &good.with_gamma(Some(&no_binding))),
            Err(AdaptiveError::TextureUsage { input: "gamma", .. })
        ),
        "gamma without TEXTURE_BINDING: TextureUsage naming gamma"
    );
}
