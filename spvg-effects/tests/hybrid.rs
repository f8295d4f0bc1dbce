//! The hybrid pass: the adaptive count and the history only where tagged, the separable
//! filter elsewhere, the sampling work following the tags, the fixed count refused, and the
//! GPU equal to its twin. GPU tests skip cleanly without an adapter
//! (`SPVG_REQUIRE_GPU=1` makes that a failure).

mod common;

use half::f16;
use spvg::burley::presets::SKIN1;
use spvg_effects::sss::twin::{HybridSources, SeparableTwin};
use spvg_effects::sss::{
    FrameInputs, HybridPass, HybridTwin, Model, PassConfig, SeparableConfig, SeparablePass,
    SssTwin, TECHNIQUE_AFIS, technique_ids,
};

const W: u32 = 40;
const H: u32 = 24;

/// A lit surface with a shadow edge across the middle, a slanted plane 0.8 m to 1.2 m away
/// (smooth: with depth jumps of hundreds of millimetres between neighbours the ratio
/// estimator's weights reach the f32 subnormal range, which a device may flush to zero and
/// the CPU keeps; one such pixel differed by 4% between lavapipe and the twin), a few mask
/// holes; the lighting flickers a little with `t`.
fn inputs(t: u32) -> FrameInputs {
    common::frame(W, H, |x, y| {
        let base = if x < W / 2 { 1.0 } else { 0.1 };
        let l = base * (1.0 + 0.05 * ((x + y + t) % 3) as f32);
        let depth = 800.0 + 4.0 * (x + 2 * y) as f32;
        (
            [l, 0.7 * l, 0.5 * l],
            depth,
            !(x * 3 + y * 7).is_multiple_of(29),
        )
    })
}

/// A disc of radius 6 around (16, 12): about 12% of the frame.
fn region() -> Vec<u8> {
    (0..W * H)
        .map(|i| {
            let (dx, dy) = ((i % W) as f32 - 16.0, (i / W) as f32 - 12.0);
            u8::from(dx * dx + dy * dy < 36.0)
        })
        .collect()
}

fn config() -> PassConfig {
    PassConfig {
        afis: true,
        spvg: spvg::SpvgConfig::builder()
            .target_variance(1e-3)
            .build()
            .expect("valid target"),
        ..PassConfig::default()
    }
}

#[test]
fn samples_and_history_only_where_tagged() {
    let technique = technique_ids(&region(), W, H, None).unwrap();
    let sep = SeparableConfig::default()
        .params(&SKIN1, W, H, true)
        .unwrap();
    let mut hybrid = HybridTwin::new(Model::Ccv, W, H).unwrap();
    let mut whole = SssTwin::new(Model::Ccv, W, H);
    let (mut hybrid_samples, mut whole_samples, mut whole_in_region) = (0_u64, 0_u64, 0_u64);
    for t in 0..4 {
        let f = inputs(t);
        let p = hybrid.frame_params(&config(), &SKIN1, t).unwrap();
        let q = whole.frame_params(&config(), &SKIN1, t).unwrap();
        let out = hybrid.run_frame(&p, &sep, &f, &technique).unwrap();
        let all = whole.run_frame(&q, &f).unwrap();
        let history = hybrid.history();
        for (i, &tag) in technique.iter().enumerate() {
            if tag == 0 || f.mask[i] == 0 {
                assert_eq!(
                    out.frame.count[i], 0,
                    "frame {t} pixel {i}: count outside the tags"
                );
                assert_eq!(
                    history.h[i],
                    [f16::ZERO; 4],
                    "frame {t} pixel {i}: history kept"
                );
            } else {
                assert!(
                    out.frame.count[i] == 0 || (8..=64).contains(&out.frame.count[i]),
                    "frame {t} pixel {i}: count {}",
                    out.frame.count[i]
                );
                // P4: the tagged pixels keep the AFIS result, which has its samples.
                assert!(out.frame.result[i][0].to_f32() > 0.0, "pixel {i}: a result");
            }
        }
        hybrid_samples += out.frame.count.iter().map(|&c| u64::from(c)).sum::<u64>();
        whole_samples += all.count.iter().map(|&c| u64::from(c)).sum::<u64>();
        whole_in_region += all
            .count
            .iter()
            .zip(&technique)
            .filter(|&(_, &t)| t == 1)
            .map(|(&c, _)| u64::from(c))
            .sum::<u64>();
    }
    // The work follows the tags: the hybrid takes about the samples the whole-frame model
    // takes inside the region (the same controller on the same pixels), a fraction of its
    // total.
    let ratio = hybrid_samples as f64 / whole_in_region as f64;
    assert!(
        (0.7..=1.3).contains(&ratio),
        "hybrid {hybrid_samples} vs region {whole_in_region}"
    );
    assert!(
        hybrid_samples * 4 < whole_samples,
        "hybrid {hybrid_samples} vs whole frame {whole_samples}"
    );
}

#[test]
fn the_fixed_count_and_a_plain_block_are_refused() {
    assert!(
        HybridTwin::new(Model::Fixed(16), 4, 4).is_err(),
        "fixed count"
    );
    let mut twin = HybridTwin::new(Model::As, W, H).unwrap();
    let plain = SeparableConfig::default()
        .params(&SKIN1, W, H, false)
        .unwrap();
    let p = twin.frame_params(&config(), &SKIN1, 0).unwrap();
    let technique = technique_ids(&region(), W, H, Some(8)).unwrap();
    let e = twin
        .run_frame(&p, &plain, &inputs(0), &technique)
        .unwrap_err();
    assert!(e.to_string().contains("hybrid"), "{e}");
    assert!(technique_ids(&region(), W, H, Some(0)).is_err(), "tile 0");
    assert!(technique_ids(&[1, 0], W, H, None).is_err(), "region size");
}

#[test]
fn gpu_hybrid_equals_its_twin() {
    let Some(d) = spvg_gpu_test::GpuTest::new("gpu_hybrid_equals_its_twin").device() else {
        return;
    };
    let technique = technique_ids(&region(), W, H, Some(8)).unwrap();
    let sep = SeparableConfig::default()
        .params(&SKIN1, W, H, true)
        .unwrap();
    for model in [Model::As, Model::Ccv] {
        let mut gpu = HybridPass::new(&d.device, &d.queue, W, H, model).unwrap();
        let mut cpu = HybridTwin::new(model, W, H).unwrap();
        for t in 0..3 {
            let f = inputs(t);
            let p = gpu.frame_params(&config(), &SKIN1, t).unwrap();
            let q = cpu.frame_params(&config(), &SKIN1, t).unwrap();
            let a = gpu.run_frame(&p, &sep, &f, &technique).unwrap();
            let b = cpu.run_frame(&q, &sep, &f, &technique).unwrap();
            assert_eq!(a.frame.count, b.frame.count, "{model:?} frame {t}: counts");
            // The Burley sampling is within 2e-5 of the core's (device exp/log), so the
            // AFIS results, and the separable pixels that read them, may differ by a
            // rounding step of the f16 store or a few.
            let ulps = common::max_f16_ulps(&a.frame.result, &b.frame.result);
            assert!(
                ulps <= common::SAMPLING_ULPS,
                "{model:?} frame {t}: {ulps} ulps"
            );
            let (ha, hb) = (gpu.history().unwrap(), cpu.history());
            let h_ulps = common::max_f16_ulps(&ha.h, &hb.h);
            assert!(
                h_ulps <= common::SAMPLING_ULPS,
                "{model:?} frame {t}: history {h_ulps}"
            );
        }
    }
}

/// A disc of radius 5 around `(cx, cy)`: per pixel, so its 8 x 8 tiles are partly tagged.
fn disc(cx: f32, cy: f32) -> Vec<u8> {
    (0..W * H)
        .map(|i| {
            let (dx, dy) = ((i % W) as f32 - cx, (i / W) as f32 - cy);
            u8::from(dx * dx + dy * dy < 25.0)
        })
        .collect()
}

/// The hybrid pass once its first step runs over the tagged tiles only (from the third
/// frame with the same tags) and after the tags move (the tiles change): per pixel, the
/// tagged pixels hold the AFIS result of the subsurface twin sampling that region, the
/// others the separable twin fed with that result, and the untagged pixels out of the
/// kernel's reach of every tag the separable-only result; counts and history are the
/// twin's, zero outside the tags. The per-step run gives the same frames.
#[test]
fn tagged_tiles_equal_the_twins_across_a_tag_change() {
    let Some(d) =
        spvg_gpu_test::GpuTest::new("tagged_tiles_equal_the_twins_across_a_tag_change").device()
    else {
        return;
    };
    let n = (W * H) as usize;
    let sep = SeparableConfig::default()
        .params(&SKIN1, W, H, true)
        .unwrap();
    let plain = SeparableConfig::default()
        .params(&SKIN1, W, H, false)
        .unwrap();
    // The kernel's reach in pixels at the nearest depth (800 mm), plus the interpolation's
    // second texel.
    let reach_mm = sep.kernel[..sep.samples as usize]
        .iter()
        .map(|k| k[0].abs())
        .fold(0.0_f32, f32::max);
    let reach = (reach_mm / (800.0 * sep.w_px.min(sep.h_px))).ceil() as i64 + 1;
    for model in [Model::As, Model::Ccv, Model::Ocv] {
        let mut gpu = HybridPass::new(&d.device, &d.queue, W, H, model).unwrap();
        let mut steps = HybridPass::new(&d.device, &d.queue, W, H, model).unwrap();
        let mut afis = SssTwin::new(model, W, H);
        for t in 0..7 {
            let region = if t < 4 {
                disc(13.0, 9.0)
            } else {
                disc(27.0, 14.0)
            };
            let technique = technique_ids(&region, W, H, None).unwrap();
            let f = inputs(t);
            let p = gpu.frame_params(&config(), &SKIN1, t).unwrap();
            assert_eq!(
                steps.frame_params(&config(), &SKIN1, t).unwrap(),
                p,
                "one block"
            );
            let q = afis.frame_params(&config(), &SKIN1, t).unwrap();
            let a = gpu.run_frame(&p, &sep, &f, &technique).unwrap();
            let (b, times) = steps.run_frame_per_pass(&p, &sep, &f, &technique).unwrap();
            assert_eq!(
                a.frame.result, b.frame.result,
                "{model:?} frame {t}: per step"
            );
            assert_eq!(
                a.frame.count, b.frame.count,
                "{model:?} frame {t}: per step"
            );
            assert!(times.total_ms() > 0.0 && times.total_ms().is_finite());
            let sampled = afis.run_frame_in(&q, &f, Some(&region)).unwrap();
            let composed = SeparableTwin
                .run_frame(
                    &sep,
                    &f,
                    Some(HybridSources {
                        technique: &technique,
                        afis: &sampled.result,
                    }),
                )
                .unwrap();
            let alone = SeparableTwin.run_frame(&plain, &f, None).unwrap();
            assert_eq!(a.frame.count, sampled.count, "{model:?} frame {t}: counts");
            let history = gpu.history().unwrap();
            let h_ulps = common::max_f16_ulps(&history.h, &afis.history().h);
            assert!(
                h_ulps <= common::SAMPLING_ULPS,
                "{model:?} frame {t}: history"
            );
            let near = |i: usize| {
                let (x, y) = ((i % W as usize) as i64, (i / W as usize) as i64);
                region.iter().enumerate().any(|(k, &r)| {
                    let (kx, ky) = ((k % W as usize) as i64, (k / W as usize) as i64);
                    r != 0 && (kx - x).abs().max((ky - y).abs()) <= reach
                })
            };
            let mut far = 0;
            for (i, &tag) in region.iter().enumerate() {
                let got = [a.frame.result[i]];
                if tag != 0 {
                    assert_eq!(a.frame.count[i], sampled.count[i]);
                    let ulps = common::max_f16_ulps(&got, &[sampled.result[i]]);
                    let what = "tagged pixel: the AFIS result";
                    assert!(ulps <= common::SAMPLING_ULPS, "{model:?} {t} {i}: {what}");
                    continue;
                }
                assert_eq!(a.frame.count[i], 0, "{model:?} frame {t} pixel {i}: count");
                assert_eq!(history.h[i], [f16::ZERO; 4], "{model:?} {t} {i}: history");
                let ulps = common::max_f16_ulps(&got, &[composed.result[i]]);
                let what = "untagged pixel: the separable filter";
                assert!(ulps <= common::SAMPLING_ULPS, "{model:?} {t} {i}: {what}");
                if !near(i) {
                    far += 1;
                    let what = "out of reach: separable-only";
                    let ulps = common::max_f16_ulps(&got, &[alone.result[i]]);
                    assert!(ulps <= 1, "{model:?} {t} {i}: {what} ({ulps} ulps)");
                }
            }
            assert!(
                far > n / 4,
                "{model:?} frame {t}: {far} pixels out of reach"
            );
        }
    }
}

/// Tags with every kind of 8 x 8 tile: tiles (1, 0) and (1, 1) wholly tagged (mask holes
/// included), a disc of radius 7 around (29, 12) that tags parts of six tiles, the rest
/// untagged.
fn mixed_tags() -> Vec<u8> {
    (0..W * H)
        .map(|i| {
            let (x, y) = (i % W, i / W);
            let (dx, dy) = (x as f32 - 29.0, y as f32 - 12.0);
            let block = (8..16).contains(&x) && y < 16;
            u8::from(block || dx * dx + dy * dy < 49.0)
        })
        .collect()
}

/// A hybrid frame runs its separable passes over the tiles holding an untagged pixel only
/// (a wholly tagged tile gets the first pass's values from the composition step and keeps
/// the AFIS result, into whose texture the second pass writes; only the tiles holding both
/// kinds read the technique id), which must not change the image: per frame, across tag changes (a partly tagged frame while the
/// first step settles and after, every pixel tagged: no separable tile, none tagged: no
/// AFIS tile), the hybrid result equals bit for bit the whole-frame separable passes on
/// the same device fed the same AFIS result at the tagged pixels (the host-composed
/// [`SeparablePass::run_frame`]), and the twin within the sampling tolerance.
#[test]
fn restricted_separable_passes_equal_the_whole_frame_ones() {
    let Some(d) =
        spvg_gpu_test::GpuTest::new("restricted_separable_passes_equal_the_whole_frame_ones")
            .device()
    else {
        return;
    };
    let n = (W * H) as usize;
    let sep = SeparableConfig::default()
        .params(&SKIN1, W, H, true)
        .unwrap();
    let mixed = technique_ids(&mixed_tags(), W, H, None).unwrap();
    // The tile kinds the test needs, counted by brute force over the tiles.
    let tile_tags = |tx: u32, ty: u32| {
        let tags: Vec<u8> = (0..n)
            .filter(|&i| (i as u32 % W) / 8 == tx && (i as u32 / W) / 8 == ty)
            .map(|i| mixed[i])
            .collect();
        (
            tags.iter().all(|&t| t == TECHNIQUE_AFIS),
            tags.contains(&TECHNIQUE_AFIS),
        )
    };
    let kinds: Vec<(bool, bool)> = (0..H / 8)
        .flat_map(|ty| (0..W / 8).map(move |tx| (tx, ty)))
        .map(|(tx, ty)| tile_tags(tx, ty))
        .collect();
    assert!(
        kinds.iter().filter(|k| k.0).count() >= 2,
        "wholly tagged tiles"
    );
    assert!(
        kinds.iter().filter(|k| k.1 && !k.0).count() >= 4,
        "partly tagged tiles"
    );
    assert!(kinds.iter().filter(|k| !k.1).count() >= 4, "untagged tiles");
    let all = vec![TECHNIQUE_AFIS; n];
    let none = vec![0_u8; n];
    let mut whole = SeparablePass::new(&d.device, &d.queue, W, H);
    for model in [Model::Ccv, Model::Ocv] {
        let mut gpu = HybridPass::new(&d.device, &d.queue, W, H, model).unwrap();
        let mut steps = HybridPass::new(&d.device, &d.queue, W, H, model).unwrap();
        let mut cpu = HybridTwin::new(model, W, H).unwrap();
        for t in 0..8 {
            let technique = match t {
                5 => &all,
                6 => &none,
                _ => &mixed,
            };
            let f = inputs(t);
            let p = gpu.frame_params(&config(), &SKIN1, t).unwrap();
            assert_eq!(
                steps.frame_params(&config(), &SKIN1, t).unwrap(),
                p,
                "one block"
            );
            let q = cpu.frame_params(&config(), &SKIN1, t).unwrap();
            let a = gpu.run_frame(&p, &sep, &f, technique).unwrap();
            let (b, _) = steps.run_frame_per_pass(&p, &sep, &f, technique).unwrap();
            assert_eq!(a.frame.result, b.frame.result, "{model:?} frame {t}: steps");
            // The P4 copy: the hybrid's result at the tagged pixels is the AFIS result the
            // passes read there.
            let w = whole
                .run_frame(
                    &sep,
                    &f,
                    Some(HybridSources {
                        technique,
                        afis: &a.frame.result,
                    }),
                )
                .unwrap();
            let differ = (0..n).filter(|&i| a.frame.result[i] != w.result[i]).count();
            assert_eq!(
                differ, 0,
                "{model:?} frame {t}: pixels unlike the whole frame"
            );
            let c = cpu.run_frame(&q, &sep, &f, technique).unwrap();
            let ulps = common::max_f16_ulps(&a.frame.result, &c.frame.result);
            assert!(
                ulps <= common::SAMPLING_ULPS,
                "{model:?} frame {t}: {ulps} ulps from the twin"
            );
        }
    }
}
