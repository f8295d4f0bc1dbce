//! The AO consumer: its WGSL validated by naga, its scene geometry against hand-derived
//! facts, and the GPU renderer (G-buffer, component, AO sampling) against the CPU twins on
//! the moving scenes.

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg_effects::ao::{AoFrame, AoMode, AoPass, AoScene, AoTwin, Motion, ao_source, twin};
use spvg_wgpu::adaptive::{AdaptiveSettings, AdaptiveTwin, EstimateData, UpdateData};
use spvg_wgpu::util::read_texture;

#[test]
fn wgsl_validates_without_a_gpu() {
    let module = naga::front::wgsl::parse_str(&ao_source()).expect("ao WGSL parses");
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .expect("ao WGSL validates");
}

#[test]
fn geometry_facts() {
    let scene = AoScene {
        width: 64,
        height: 48,
        motion: Motion::Static,
    };
    let p = scene.params(3);
    // Cell spheres stay inside their 64 px cell's middle half, radius 4..12.
    for (ix, iy) in [(0, 0), (-3, 5), (100, -100)] {
        let c = twin::cell_sphere(ix, iy);
        let (x0, y0) = (ix as f32 * 64.0, iy as f32 * 64.0);
        assert!(
            c[0] >= x0 + 16.0 && c[0] < x0 + 48.0,
            "x of cell ({ix}, {iy}): {c:?}"
        );
        assert!(
            c[1] >= y0 + 16.0 && c[1] < y0 + 48.0,
            "y of cell ({ix}, {iy}): {c:?}"
        );
        assert!((4.0..12.0).contains(&c[3]), "radius {c:?}");
        assert!(c[2] >= -0.5 * c[3] && c[2] <= c[3], "height {c:?}");
        // The top of the sphere is its centre plus its radius.
        let s = twin::surface(&p, c[0], c[1]);
        if c[2] + c[3] > 0.0 {
            assert_eq!(s.position[2], c[2] + c[3], "top of {c:?}");
            let n = s.normal;
            assert!(
                n[0] == 0.0 && n[1] == 0.0 && (n[2] - 1.0).abs() <= 2.0 * f32::EPSILON,
                "normal at the top of {c:?}: {n:?} (r * (1/r) may round one ulp below 1)"
            );
        }
    }
    // A static camera has zero motion everywhere; a pan moves every static point by
    // (-speed, 0) per frame.
    for g in twin::gbuffer(&p) {
        assert_eq!(g.motion, [0.0, 0.0], "static motion");
        assert!(g.depth > 0.0 && g.depth <= 100.0, "depth {}", g.depth);
    }
    let pan = AoScene {
        motion: Motion::Pan { speed: 5.0 },
        ..scene
    };
    for g in twin::gbuffer(&pan.params(7)) {
        assert!(g.motion == [-5.0, 0.0], "pan motion {:?}", g.motion);
    }
    // The moving sphere's surface moves with it.
    let obj = AoScene {
        motion: Motion::MovingSphere { speed: 3.0 },
        ..scene
    };
    let q = obj.params(10);
    let on_mover = twin::gbuffer(&q)
        .into_iter()
        .filter(|g| g.surface.moving)
        .collect::<Vec<_>>();
    assert!(
        on_mover.len() > 200,
        "mover covers {} pixels",
        on_mover.len()
    );
    for g in on_mover {
        assert!(
            (g.motion[0] - 3.0).abs() < 1e-4 && g.motion[1].abs() < 1e-4,
            "{:?}",
            g.motion
        );
    }
}

/// The moving objects: three spheres and a bar, each surface point moving with its own
/// object (+x, -x, +y at 5 px per frame, the bar +x), the bar exactly 3 px wide with
/// edges on pixel boundaries, and its slab test against hand-solved rays.
#[test]
fn moving_objects_geometry() {
    let scene = AoScene {
        width: 128,
        height: 96,
        motion: Motion::MovingObjects { speed: 5.0 },
    };
    let allowed = [[5.0, 0.0], [-5.0, 0.0], [0.0, 5.0]];
    let mut seen = [false; 3];
    let mut uncovered = 0;
    let mut before: Option<Vec<bool>> = None;
    for t in 1..60 {
        let p = scene.params(t);
        let g = twin::gbuffer(&p);
        for gp in &g {
            if !gp.surface.moving {
                assert_eq!(gp.surface.velocity, [0.0; 3], "frame {t}: static surface");
                continue;
            }
            let m = gp.motion;
            // Re-entering objects point far outside the previous frame.
            if m[0].abs() > 1.0e6 {
                continue;
            }
            let k = allowed
                .iter()
                .position(|a| (m[0] - a[0]).abs() < 1e-3 && (m[1] - a[1]).abs() < 1e-3)
                .unwrap_or_else(|| panic!("frame {t}: motion {m:?} of a moving object"));
            seen[k] = true;
        }
        let now: Vec<bool> = g.iter().map(|x| x.surface.moving).collect();
        if let Some(b) = &before {
            uncovered += b.iter().zip(&now).filter(|(b, n)| **b && !**n).count();
        }
        before = Some(now);
        // The bar, where it is wholly inside the frame: its top (z 14, level) covers
        // exactly three columns.
        let (lo, hi) = (p.bar_min, p.bar_max);
        if lo[0] > -24.0 && hi[0] < 104.0 {
            assert_eq!(hi[0] - lo[0], 3.0, "frame {t}: bar width");
            let cols: Vec<usize> = g
                .iter()
                .enumerate()
                .filter(|(_, x)| x.surface.position[2] == 14.0 && x.surface.moving)
                .map(|(i, _)| i % 128)
                .collect();
            let (a, b) = (cols.iter().min(), cols.iter().max());
            assert!(
                cols.len() >= 3 * 20 && b.zip(a).is_some_and(|(b, a)| b - a == 2),
                "frame {t}: bar pixels in columns {a:?}..{b:?}, {} of them",
                cols.len()
            );
        }
    }
    assert_eq!(seen, [true; 3], "every direction of motion on screen");
    assert!(uncovered > 1000, "only {uncovered} uncovered pixels");
    // The slab test: a bar from (10, 0, 11) to (13, 40, 14).
    let mut p = scene.params(0);
    p.bar_min = [10.0, 0.0, 11.0, 0.0];
    p.bar_max = [13.0, 40.0, 14.0, 0.0];
    let up = [0.0, 0.0, 1.0];
    // Straight up from the ground under it: hits the bottom at t = 11 < 16.
    assert!(twin::hits_bar(&p, [11.0, 20.0, 0.001], up));
    // Straight up beside it: parallel to the x slab and outside it.
    assert!(!twin::hits_bar(&p, [14.0, 20.0, 0.001], up));
    // Towards it from 2 px beside it along (-1, 0, 6): reaches x = 13 at t = 2 sqrt(37)
    // (12.2 < 16) at height 12, inside; from 3 px, at t = 3 sqrt(37) (18.2), out of reach.
    let n = 37.0_f32.sqrt();
    let d = [-1.0 / n, 0.0, 6.0 / n];
    assert!(twin::hits_bar(&p, [15.0, 20.0, 0.001], d));
    assert!(!twin::hits_bar(&p, [16.0, 20.0, 0.001], d));
    // Along (-1, 0, 1) it passes under the bar (height 2..5 across it).
    let d = [
        -core::f32::consts::FRAC_1_SQRT_2,
        0.0,
        core::f32::consts::FRAC_1_SQRT_2,
    ];
    assert!(!twin::hits_bar(&p, [15.0, 20.0, 0.001], d));
    // From above, downwards: the top at t = 6; away from it, never.
    assert!(twin::hits_bar(&p, [11.0, 20.0, 20.0], [0.0, 0.0, -1.0]));
    assert!(!twin::hits_bar(&p, [11.0, 20.0, 20.0], up));
    // No bar when the corners are equal (the other scenes).
    let q = AoScene {
        motion: Motion::MovingSphere { speed: 3.0 },
        ..scene
    }
    .params(5);
    assert!(!twin::hits_bar(&q, [0.0, 0.0, 0.001], up));
}

/// The dolly: the camera moves 3 units per frame from height 100 to 61 and back, zooming
/// with its height (pixels per world unit 100 / height), so a static point's motion points
/// away from the frame centre by `(1 - h_t / h_(t-1))` of its distance from it, every
/// depth changes by more than the 2% of the depth test per frame, and the reprojected
/// depth is the previous camera's height minus the point's height.
#[test]
fn dolly_geometry() {
    let (w, h) = (64_u32, 48_u32);
    let scene = AoScene {
        width: w,
        height: h,
        motion: Motion::Dolly { rate: 3.0 },
    };
    let heights: Vec<f32> = (0..30).map(|t| scene.params(t).lens[0]).collect();
    assert_eq!(
        (heights[0], heights[13], heights[26]),
        (100.0, 61.0, 100.0),
        "{heights:?}"
    );
    for t in 1..30 {
        assert_eq!((heights[t] - heights[t - 1]).abs(), 3.0, "frame {t}");
    }
    let p = scene.params(5);
    let (now, before) = (85.0_f32, 88.0_f32);
    assert_eq!((p.lens[0], p.previous_lens[0]), (now, before));
    let k = 1.0 - now / before;
    for (i, g) in twin::gbuffer(&p).into_iter().enumerate() {
        let z = g.surface.position[2];
        assert_eq!(g.depth, now - z, "pixel {i}: depth");
        assert_eq!(
            g.reprojected_depth,
            before - z,
            "pixel {i}: reprojected depth"
        );
        assert!(
            (g.reprojected_depth - g.depth).abs() > 0.02 * g.depth,
            "pixel {i}: the depth changes by more than 2%"
        );
        let q = [
            (i as u32 % w) as f32 + 0.5 - 0.5 * w as f32,
            (i as u32 / w) as f32 + 0.5 - 0.5 * h as f32,
        ];
        for a in 0..2 {
            assert!(
                (g.motion[a] - q[a] * k).abs() < 1e-3,
                "pixel {i}: motion {:?} against {:?}",
                g.motion,
                [q[0] * k, q[1] * k]
            );
        }
    }
}

#[test]
fn open_plane_is_unoccluded_and_a_ring_around_a_sphere_is_not() {
    let p = AoScene {
        width: 64,
        height: 48,
        motion: Motion::Static,
    }
    .params(0);
    let c = twin::cell_sphere(1, 1);
    // A cell corner is at least 16 px (in x and in y) from every centre: check that the
    // nearby spheres are out of reach of the 16 px rays there, then it sees the whole sky.
    let corner = [128.0_f32, 128.0];
    let clear = (0..3)
        .flat_map(|i| (0..3).map(move |j| twin::cell_sphere(i, j)))
        .all(|s| ((s[0] - corner[0]).hypot(s[1] - corner[1])) > s[3] + twin::RANGE + 0.01);
    let s = twin::surface(&p, corner[0], corner[1]);
    if clear {
        assert_eq!(twin::estimate(&p, [0, 0], &s, 64), 1.0, "open plane");
    }
    // Next to a sphere that rises above the plane, part of the sky is blocked.
    if c[2] + c[3] > 2.0 {
        let foot = twin::surface(&p, c[0] + c[3] + 0.5, c[1]);
        let ao = twin::estimate(&p, [1, 1], &foot, 256);
        assert!(ao < 0.95 && ao > 0.2, "AO next to {c:?}: {ao}");
    }
}

/// GPU against the twins, frame by frame, without and with count dilation (radius 2:
/// windows clipped at every edge). The component's twin is fed the GPU's AO values, so its
/// counts must equal the GPU's on every pixel. The one exception is the AO sampling's
/// value: WGSL lets a driver fuse a multiply-add in the ray tests, which can flip a grazing
/// ray, so each pixel's AO may differ from the twin's by one ray of its count (and on
/// lavapipe it does not).
#[test]
fn gpu_matches_twin_on_moving_scenes() {
    let Some(dev) = spvg_gpu_test::GpuTest::new("ao gpu_matches_twin_on_moving_scenes").device()
    else {
        return;
    };
    let config = SpvgConfig::builder()
        .target_variance(2e-3)
        .build()
        .expect("valid config");
    let (w, h) = (40, 28);
    let motions = [
        Motion::Pan { speed: 2.5 },
        Motion::Rotate { degrees: 1.5 },
        Motion::MovingSphere { speed: 3.0 },
        Motion::Dolly { rate: 3.0 },
        Motion::MovingObjects { speed: 5.0 },
    ];
    let runs = [false, true]
        .into_iter()
        .flat_map(|one_pass| [0, 2].map(|r| (one_pass, r)))
        .flat_map(|(one_pass, r)| motions.map(|m| (one_pass, r, m)));
    for (one_pass, radius, motion) in runs {
        let scene = AoScene {
            width: w,
            height: h,
            motion,
        };
        let settings = AdaptiveSettings {
            config,
            dilation: radius,
            ..AdaptiveSettings::default()
        };
        let mut gpu = AoPass::new(&dev.device, &dev.queue, w, h, AoMode::Adaptive, settings)
            .expect("renderer");
        gpu.set_one_pass(one_pass);
        let mut cpu = AdaptiveTwin::new(settings, w, h).expect("twin");
        let mut prev_depth: Option<Vec<f32>> = None;
        for t in 0..10 {
            let p = scene.params(t);
            let a = gpu.run_frame(&p).expect("gpu frame");
            let g = twin::gbuffer(&p);
            let depth: Vec<f32> = g.iter().map(|x| x.depth).collect();
            let mv: Vec<[f32; 2]> = g.iter().map(|x| x.motion).collect();
            let reprojected: Vec<f32> = g.iter().map(|x| x.reprojected_depth).collect();
            let previous = prev_depth.clone().unwrap_or_else(|| vec![0.0; depth.len()]);
            let count = cpu
                .estimate(
                    &EstimateData::new(&mv, &depth, &previous)
                        .with_reprojected_depth(Some(&reprojected)),
                )
                .expect("twin")
                .to_vec();
            let value = twin::sample(&p, &g, &count);
            cpu.update(&UpdateData::new(&a.value)).expect("twin");
            let form = if one_pass { "one pass" } else { "two passes" };
            let name = format!("{} dilation {radius}, {form}", motion.name());
            let equal = a.value.iter().zip(&value).filter(|(x, y)| x == y).count();
            eprintln!(
                "{name} frame {t}: AO equal on {equal} of {} pixels",
                value.len()
            );
            assert_eq!(a.count, count, "{name} frame {t}: counts");
            for (i, ((x, y), c)) in a.value.iter().zip(&value).zip(&count).enumerate() {
                assert!(
                    (x - y).abs() <= 1.0 / (*c).max(1) as f32 + 1e-6,
                    "{name} frame {t} pixel {i}: AO {x} against the twin's {y} at {c} rays"
                );
            }
            prev_depth = Some(depth);
        }
    }
}

/// Disocclusion by motion: every pixel the floating sphere uncovers is rejected by the
/// depth test and takes the first-observation count, beta_min.
#[test]
fn pixels_uncovered_by_the_moving_sphere_take_the_minimum() {
    let config = SpvgConfig::builder()
        .target_variance(1e-4)
        .build()
        .expect("valid config");
    let scene = AoScene {
        width: 64,
        height: 48,
        motion: Motion::MovingSphere { speed: 3.0 },
    };
    // With count dilation too: without the neighbour prior (on by default), a pixel
    // without history keeps beta_min, whatever its neighbours spend.
    for radius in [0, 1] {
        uncovered_pixels_take_the_minimum(config, scene, radius);
    }
}

fn uncovered_pixels_take_the_minimum(config: SpvgConfig<f32>, scene: AoScene, radius: u32) {
    use spvg_effects::ao::AoTwin;
    let settings = AdaptiveSettings {
        config,
        dilation: radius,
        neighbour_prior: false,
        ..AdaptiveSettings::default()
    };
    let mut cpu = AoTwin::new(64, 48, AoMode::Adaptive, settings).expect("twin");
    let mut before: Option<Vec<bool>> = None;
    let mut uncovered = 0;
    let mut above_minimum = 0;
    for t in 0..20 {
        let p = scene.params(t);
        let f = cpu.run_frame(&p).expect("frame");
        let g = twin::gbuffer(&p);
        if let Some(b) = &before {
            for (i, gp) in g.iter().enumerate() {
                if b[i] && !gp.surface.moving {
                    uncovered += 1;
                    assert_eq!(
                        f.count[i],
                        8,
                        "radius {radius} frame {t} pixel ({}, {}) depth {} motion {:?}",
                        i % 64,
                        i / 64,
                        gp.depth,
                        gp.motion
                    );
                } else if f.count[i] > 8 {
                    above_minimum += 1;
                }
            }
        }
        before = Some(g.iter().map(|x| x.surface.moving).collect());
    }
    assert!(uncovered > 50, "only {uncovered} uncovered pixels");
    assert!(
        above_minimum > 1000,
        "radius {radius}: the scene has noisy pixels"
    );
}

/// One fixed-count run with prefix counts yields the fixed runs of those counts, bit for
/// bit: on the GPU against separate GPU runs, and on the twin against separate twin runs
/// (the sample sequence does not depend on the count). A prefix above the count reads 0.
#[test]
fn prefix_estimates_equal_fixed_runs_of_those_counts() {
    let config = SpvgConfig::builder()
        .target_variance(2e-3)
        .build()
        .expect("valid config");
    let (w, h) = (24, 20);
    let scene = AoScene {
        width: w,
        height: h,
        motion: Motion::Pan { speed: 2.0 },
    };
    let prefixes = [4, 16, 0, 40];
    let settings = AdaptiveSettings {
        config,
        ..AdaptiveSettings::default()
    };
    // The twin: independent of a device.
    let mut ladder = AoTwin::new(w, h, AoMode::Fixed(32), settings).expect("twin");
    ladder.set_prefix_counts(prefixes);
    let mut singles: Vec<AoTwin> = [4, 16]
        .map(|n| AoTwin::new(w, h, AoMode::Fixed(n), settings).expect("twin"))
        .to_vec();
    for t in 0..3 {
        let p = scene.params(t);
        let l = ladder.run_frame(&p).expect("twin frame");
        assert_eq!(l.prefixes.len(), (w * h) as usize);
        for (j, s) in singles.iter_mut().enumerate() {
            let f = s.run_frame(&p).expect("twin frame");
            assert!(f.prefixes.is_empty(), "no prefixes asked");
            let got: Vec<f32> = l.prefixes.iter().map(|x| x[j]).collect();
            assert_eq!(got, f.value, "twin frame {t}: prefix {}", prefixes[j]);
        }
        assert!(l.prefixes.iter().all(|x| x[2] == 0.0 && x[3] == 0.0));
    }
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("ao prefix_estimates_equal_fixed_runs_of_those_counts")
            .device()
    else {
        return;
    };
    let gpu = |mode| AoPass::new(&dev.device, &dev.queue, w, h, mode, settings);
    let mut ladder = gpu(AoMode::Fixed(32)).expect("renderer");
    ladder.set_prefix_counts(prefixes);
    let mut singles: Vec<AoPass> = [4, 16]
        .map(|n| gpu(AoMode::Fixed(n)).expect("renderer"))
        .into_iter()
        .collect();
    for t in 0..3 {
        let p = scene.params(t);
        let l = ladder.run_frame(&p).expect("gpu frame");
        for (j, s) in singles.iter_mut().enumerate() {
            let f = s.run_frame(&p).expect("gpu frame");
            let got: Vec<f32> = l.prefixes.iter().map(|x| x[j]).collect();
            assert_eq!(got, f.value, "gpu frame {t}: prefix {}", prefixes[j]);
        }
        assert!(l.prefixes.iter().all(|x| x[2] == 0.0 && x[3] == 0.0));
    }
}

/// The guided frame (`AoPass::run_frame_guided`): the renderer's guide, here a TAA-like
/// history of the AO values (the previous frame's value at the pixel the motion came from,
/// NaN where it left the frame), reaches the component's update. The GPU's counts equal
/// the component twin's fed the same values and guides, on a pan, frame by frame.
#[test]
fn gpu_guided_frames_match_the_twin_on_a_pan() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("ao gpu_guided_frames_match_the_twin_on_a_pan").device()
    else {
        return;
    };
    let config = SpvgConfig::builder()
        .target_variance(2e-3)
        .build()
        .expect("valid config");
    let (w, h) = (40, 28);
    let scene = AoScene {
        width: w,
        height: h,
        motion: Motion::Pan { speed: 2.5 },
    };
    let settings = AdaptiveSettings {
        config,
        ..AdaptiveSettings::default()
    };
    let mut gpu =
        AoPass::new(&dev.device, &dev.queue, w, h, AoMode::Adaptive, settings).expect("renderer");
    let mut cpu = AdaptiveTwin::new(settings, w, h).expect("twin");
    let mut prev: Option<(Vec<f32>, Vec<f32>)> = None;
    let mut guided_counts_differ = 0;
    let mut plain = AdaptiveTwin::new(settings, w, h).expect("twin");
    for t in 0..10 {
        let p = scene.params(t);
        let g = twin::gbuffer(&p);
        let depth: Vec<f32> = g.iter().map(|x| x.depth).collect();
        let mv: Vec<[f32; 2]> = g.iter().map(|x| x.motion).collect();
        let reprojected: Vec<f32> = g.iter().map(|x| x.reprojected_depth).collect();
        let mut sent = Vec::new();
        let history = prev.as_ref().map(|(v, _)| v.clone());
        let mut guide = |value: &[f32]| {
            let c: Vec<f32> = (0..value.len())
                .map(|i| {
                    let (x, y) = ((i as u32 % w) as f32 + 0.5, (i as u32 / w) as f32 + 0.5);
                    let (px, py) = ((x - mv[i][0]).floor(), (y - mv[i][1]).floor());
                    match &history {
                        Some(hv) if px >= 0.0 && py >= 0.0 && px < w as f32 && py < h as f32 => {
                            hv[(py as u32 * w + px as u32) as usize]
                        }
                        _ => f32::NAN,
                    }
                })
                .collect();
            sent.clone_from(&c);
            c
        };
        let a = gpu
            .run_frame_guided(&p, Some(&mut guide))
            .expect("gpu frame");
        let previous = prev
            .as_ref()
            .map_or_else(|| vec![0.0; depth.len()], |(_, d)| d.clone());
        let data =
            EstimateData::new(&mv, &depth, &previous).with_reprojected_depth(Some(&reprojected));
        let count = cpu.estimate(&data).expect("twin").to_vec();
        assert_eq!(a.count, count, "frame {t}: counts");
        let unguided = plain.estimate(&data).expect("twin").to_vec();
        guided_counts_differ += count.iter().zip(&unguided).filter(|(x, y)| x != y).count();
        assert_eq!(
            sent.len(),
            a.value.len(),
            "frame {t}: the guide was asked for"
        );
        cpu.update(&UpdateData::new(&a.value).with_guide(Some(&sent)))
            .expect("twin");
        plain.update(&UpdateData::new(&a.value)).expect("twin");
        prev = Some((a.value, depth));
    }
    assert!(
        guided_counts_differ > 0,
        "the guide never changed a count: it did not reach the update"
    );
}

/// Fractional counts on the AO effect (a floor of 0.25, `sigma0^2 = 4e-3`, count
/// dilation 1 with the neighbour prior, as the floor measurement runs them): on the pan
/// and the floating sphere the GPU renderer equals its twin bit for bit on every frame
/// (counts with the dithered decisions and skipped pixels, AO values, history texels),
/// and the scenes reach the fractional path (a third of the pixel-frames and more skip
/// the frame).
#[test]
fn gpu_matches_twin_with_fractional_counts() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("ao gpu_matches_twin_with_fractional_counts").device()
    else {
        return;
    };
    let settings = AdaptiveSettings {
        config: SpvgConfig::builder()
            .target_variance(4e-3)
            .fractional_floor(Some(0.25))
            .build()
            .expect("valid config"),
        dilation: 1,
        ..AdaptiveSettings::default()
    };
    let (w, h) = (64, 48);
    for motion in [
        Motion::Pan { speed: 4.0 },
        Motion::MovingSphere { speed: 3.0 },
    ] {
        let scene = AoScene {
            width: w,
            height: h,
            motion,
        };
        let mut gpu = AoPass::new(&dev.device, &dev.queue, w, h, AoMode::Adaptive, settings)
            .expect("renderer");
        let mut cpu = AoTwin::new(w, h, AoMode::Adaptive, settings).expect("twin");
        let (mut skipped, mut samples) = (0, 0_u64);
        for t in 0..24 {
            let p = scene.params(t);
            let a = gpu.run_frame(&p).expect("gpu frame");
            let b = cpu.run_frame(&p).expect("twin frame");
            let name = format!("{} frame {t}", motion.name());
            assert_bit_equal(&dev, (&gpu, &a), (&cpu, &b), &name);
            if t >= 12 {
                let links = cpu.adaptive().expect("adaptive").links();
                skipped += b
                    .count
                    .iter()
                    .zip(links)
                    .filter(|(n, l)| **n == 0 && **l != 0)
                    .count();
                samples += b.count.iter().map(|&n| u64::from(n)).sum::<u64>();
            }
        }
        let spp = samples as f64 / f64::from(12 * w * h);
        let share = skipped as f64 / f64::from(12 * w * h);
        eprintln!(
            "{}: {skipped} skipped pixel-frames ({share:.2} of them), {spp:.2} spp",
            motion.name()
        );
        assert!(share > 0.3, "{}: only {skipped} skipped", motion.name());
    }
}

/// The rays' second moment (`AoPass::set_second_moment`, docs/algorithms.md §8.8): the
/// GPU renderer (two-pass form, whole frame and count-classified) and its twin give the
/// same counts on a pan and on moving objects, each AO value within one ray; and the
/// moment changes the counts (the twin without it differs).
#[test]
fn gpu_matches_twin_with_the_second_moment() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("ao gpu_matches_twin_with_the_second_moment").device()
    else {
        return;
    };
    let config = SpvgConfig::builder()
        .target_variance(2e-3)
        .build()
        .expect("valid config");
    let (w, h) = (40, 28);
    for (motion, classified) in [
        (Motion::Pan { speed: 2.5 }, false),
        (Motion::MovingObjects { speed: 5.0 }, false),
        (Motion::Pan { speed: 2.5 }, true),
    ] {
        let scene = AoScene {
            width: w,
            height: h,
            motion,
        };
        let settings = AdaptiveSettings {
            config,
            classified_dispatch: classified,
            ..AdaptiveSettings::default()
        };
        let mut gpu = AoPass::new(&dev.device, &dev.queue, w, h, AoMode::Adaptive, settings)
            .expect("renderer");
        gpu.set_second_moment(true);
        gpu.set_one_pass(true); // refused for a frame with the moment: two passes
        let mut cpu = AoTwin::new(w, h, AoMode::Adaptive, settings).expect("twin");
        cpu.set_second_moment(true);
        let mut plain = AoTwin::new(w, h, AoMode::Adaptive, settings).expect("twin");
        let mut differ = 0;
        for t in 0..10 {
            let p = scene.params(t);
            let a = gpu.run_frame(&p).expect("gpu frame");
            let b = cpu.run_frame(&p).expect("twin frame");
            let c = plain.run_frame(&p).expect("twin frame");
            let name = format!("{} classified {classified} frame {t}", motion.name());
            assert_eq!(a.count, b.count, "{name}: counts");
            for ((x, y), n) in a.value.iter().zip(&b.value).zip(&b.count) {
                assert!(
                    (x - y).abs() <= 1.0 / (*n).max(1) as f32 + 1e-6,
                    "{name}: AO {x} against the twin's {y}"
                );
            }
            differ += b.count.iter().zip(&c.count).filter(|(x, y)| x != y).count();
        }
        assert!(differ > 0, "{}: the moment changed no count", motion.name());
    }
}

/// The renderer's resolve weight (`AoPass::set_resolve_weight`, docs/algorithms.md §8.7)
/// under the resolved-image rule (fractional floor 0.5, the constant weight 0.1 where a
/// texel says none): fed a per-pixel weight of mixed values (1, the blend weight 0.1,
/// 0.37, NaN, 0, -1, 2 and infinity, moved each frame), the GPU renderer equals its twin
/// bit for bit on every frame (counts, AO values, history texels) in its two-pass and
/// one-pass forms, on a pan and on moving objects; the weight changes the counts (a twin
/// without it differs); an all-NaN weight is no weight; and a slice of the wrong length
/// is refused.
#[test]
fn gpu_matches_twin_with_a_resolve_weight() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("ao gpu_matches_twin_with_a_resolve_weight").device()
    else {
        return;
    };
    let settings = AdaptiveSettings {
        config: SpvgConfig::builder()
            .target_variance(4e-3)
            .fractional_floor(Some(0.5))
            .resolve_weight(Some(0.1))
            .build()
            .expect("valid config"),
        dilation: 1,
        ..AdaptiveSettings::default()
    };
    let (w, h) = (48, 40);
    let n = (w * h) as usize;
    const MIXED: [f32; 8] = [1.0, 0.1, 0.37, f32::NAN, 0.0, -1.0, 2.0, f32::INFINITY];
    // Runs of 5 pixels per value, shifted each frame, so every value meets every pixel
    // kind (steady, uncovered, on an object) over the frames.
    let weight = |t: u32| -> Vec<f32> {
        (0..n)
            .map(|i| MIXED[(i / 5 + t as usize * 3) % MIXED.len()])
            .collect()
    };
    for (motion, one_pass) in [
        (Motion::Pan { speed: 2.5 }, false),
        (Motion::MovingObjects { speed: 5.0 }, false),
        (Motion::MovingObjects { speed: 5.0 }, true),
    ] {
        let scene = AoScene {
            width: w,
            height: h,
            motion,
        };
        let mut gpu = AoPass::new(&dev.device, &dev.queue, w, h, AoMode::Adaptive, settings)
            .expect("renderer");
        gpu.set_one_pass(one_pass);
        let mut cpu = AoTwin::new(w, h, AoMode::Adaptive, settings).expect("twin");
        let mut plain = AoTwin::new(w, h, AoMode::Adaptive, settings).expect("twin");
        let mut nan = AoTwin::new(w, h, AoMode::Adaptive, settings).expect("twin");
        nan.set_resolve_weight(Some(&vec![f32::NAN; n]))
            .expect("one value per pixel");
        assert!(
            gpu.set_resolve_weight(Some(&vec![0.5; n - 1])).is_err(),
            "a short slice"
        );
        assert!(cpu.set_resolve_weight(Some(&vec![0.5; n + 1])).is_err());
        let mut differ = 0;
        for t in 0..12 {
            let p = scene.params(t);
            // Frame 0 runs without a weight (a renderer's first frame has no resolve).
            let r = (t > 0).then(|| weight(t));
            gpu.set_resolve_weight(r.as_deref()).expect("weight");
            cpu.set_resolve_weight(r.as_deref()).expect("weight");
            let a = gpu.run_frame(&p).expect("gpu frame");
            let b = cpu.run_frame(&p).expect("twin frame");
            let c = plain.run_frame(&p).expect("twin frame");
            let d = nan.run_frame(&p).expect("twin frame");
            let name = format!("{} one pass {one_pass} frame {t}", motion.name());
            assert_bit_equal(&dev, (&gpu, &a), (&cpu, &b), &name);
            assert_eq!(c.count, d.count, "{name}: an all-NaN weight is none");
            differ += b.count.iter().zip(&c.count).filter(|(x, y)| x != y).count();
        }
        assert!(differ > 0, "{}: the weight changed no count", motion.name());
    }
}

/// A GPU frame against its twin's, bit for bit: the counts, the AO values and the
/// adaptive component's history texels (read back from the GPU).
fn assert_bit_equal(
    dev: &spvg_gpu_test::GpuDevice,
    (gpu, a): (&AoPass, &AoFrame),
    (cpu, b): (&AoTwin, &AoFrame),
    name: &str,
) {
    assert_eq!(a.count, b.count, "{name}: counts");
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.value), bits(&b.value), "{name}: AO values");
    let hist: Vec<[f16; 4]> = read_texture(
        &dev.device,
        &dev.queue,
        gpu.adaptive().expect("adaptive").history_texture(),
    )
    .expect("readback");
    let texels = |h: &[[f16; 4]]| h.iter().map(|t| t.map(f16::to_bits)).collect::<Vec<_>>();
    assert_eq!(
        texels(&hist),
        texels(cpu.adaptive().expect("adaptive").history()),
        "{name}: history texels"
    );
}
