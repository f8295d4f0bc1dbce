//! Headless runs of `SpvgPlugin` inside Bevy on a wgpu adapter (software Vulkan in CI):
//! a scene of spheres over a ground plane, a moving camera, Bevy's TAA, and the example's
//! soft-shadow effect reading spvg's counts.
//!
//! Without an adapter the tests skip, unless `SPVG_REQUIRE_GPU=1` (CI), where they fail.

#[path = "../examples/soft_shadows/effect.rs"]
#[allow(dead_code, missing_docs)]
mod effect;
#[path = "../examples/soft_shadows/scene.rs"]
#[allow(dead_code, missing_docs)]
mod scene;

use bevy::anti_alias::taa::TemporalAntiAliasing;
use bevy::core_pipeline::prepass::MotionVectorPrepass;
use bevy::prelude::*;
use bevy::render::RenderApp;
use bevy::render::view::Msaa;
use effect::SoftShadows;
use half::f16;
use scene::{Frame, Targets, add_capture, app, camera_pose, spawn_camera, spawn_scene};
use spvg::SpvgConfig;
use spvg_bevy::spvg_wgpu::adaptive::{AdaptiveTwin, Control, EstimateData, Masks, UpdateData};
use spvg_bevy::{AdaptiveSampling, SpvgStatus};

const W: u32 = 96;
const H: u32 = 64;
/// The count dilation radius of the adaptive camera (`AdaptivePass::set_count_dilation`).
const DILATION: u32 = 2;

/// Whether a wgpu adapter exists; panics without one under `SPVG_REQUIRE_GPU=1`.
fn adapter_or_skip(test: &str) -> bool {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle());
    let found =
        bevy::tasks::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
            .is_ok();
    if !found {
        assert!(
            std::env::var("SPVG_REQUIRE_GPU").as_deref() != Ok("1"),
            "{test}: no wgpu adapter and SPVG_REQUIRE_GPU=1"
        );
        eprintln!("{test}: skipped, no wgpu adapter");
    }
    found
}

fn config() -> SpvgConfig<f32> {
    SpvgConfig::<f32>::builder()
        .target_variance(2e-3)
        .min_samples(2)
        .max_samples(64)
        .build()
        .expect("valid configuration")
}

fn psnr(a: &[f32], reference: &[f32], mask: &[u32]) -> f64 {
    let (mut se, mut n) = (0.0_f64, 0_u64);
    for ((x, r), m) in a.iter().zip(reference).zip(mask) {
        if *m != 0 {
            se += f64::from(x - r).powi(2);
            n += 1;
        }
    }
    let mse = se / n.max(1) as f64;
    10.0 * (1.0 / mse.max(1e-12)).log10()
}

/// Renders `frames` frames with three cameras on one path: spvg's counts, a fixed count
/// and a 256-sample reference; returns the captured frames.
fn run(frames: usize, fixed: u32) -> Vec<Frame> {
    let mut app = app();
    let captures = add_capture(&mut app);
    app.finish();
    app.cleanup();
    let world = app.world_mut();
    spawn_scene(world, false);
    let adaptive = Some(AdaptiveSampling {
        dilation: DILATION,
        ..AdaptiveSampling::new(config())
    });
    let (a, ha) = spawn_camera(world, [W, H], Some(SoftShadows::Adaptive), adaptive);
    let (f, hf) = spawn_camera(world, [W, H], Some(SoftShadows::Fixed(fixed)), None);
    let (r, hr) = spawn_camera(world, [W, H], Some(SoftShadows::Reference(256)), None);
    let targets = Targets(vec![ha, hf, hr]);
    app.insert_resource(targets.clone());
    app.sub_app_mut(RenderApp).insert_resource(targets);
    for t in 0..frames {
        for e in [a, f, r] {
            *app.world_mut().get_mut::<Transform>(e).expect("camera") = camera_pose(t as f32);
        }
        app.update();
    }
    assert_eq!(
        app.world().get::<SpvgStatus>(a),
        Some(&SpvgStatus::Running),
        "the adaptive camera runs"
    );
    captures.0.lock().expect("lock").clone()
}

#[test]
fn adaptive_shadows_under_taa() {
    if !adapter_or_skip("adaptive_shadows_under_taa") {
        return;
    }
    let config = config();
    // First pass: the adaptive run gives the mean spp the fixed camera is matched to.
    const FRAMES: usize = 40;
    const WARM: usize = 10;
    let probe = run(FRAMES, 8);
    let covered = |f: &Frame| f.mask.iter().filter(|m| **m != 0).count();
    assert!(
        probe.len() >= FRAMES - 2,
        "frames captured: {}",
        probe.len()
    );
    let measured = &probe[probe.len() - (FRAMES - WARM)..];
    let (mut spent, mut pixels) = (0_u64, 0_u64);
    for f in measured {
        spent += f.count.iter().map(|c| u64::from(*c)).sum::<u64>();
        pixels += covered(f) as u64;
    }
    assert!(pixels > 0, "the prepass wrote geometry");
    let mean_spp = spent as f64 / pixels as f64;
    let fixed = mean_spp.ceil() as u32;
    eprintln!("mean spp {mean_spp:.3} over {pixels} covered pixel-frames; fixed count {fixed}");

    let frames = run(FRAMES, fixed);
    assert!(
        frames.len() >= FRAMES - 2,
        "frames captured: {}",
        frames.len()
    );

    // Counts in the budget; no non-finite history.
    for (k, f) in frames.iter().enumerate() {
        for (c, m) in f.count.iter().zip(&f.mask) {
            if *m == 0 {
                assert_eq!(*c, 0, "frame {k}: count outside the mask");
            } else {
                assert!(
                    (config.min_samples()..=config.max_samples()).contains(c),
                    "frame {k}: count {c} outside [{}, {}]",
                    config.min_samples(),
                    config.max_samples()
                );
            }
        }
        assert!(
            f.history
                .iter()
                .flatten()
                .all(|h| f16::from_bits(*h).is_finite()),
            "frame {k}: non-finite history"
        );
        assert!(
            f.value.iter().all(|v| v.is_finite()),
            "frame {k}: non-finite value"
        );
    }

    // The twin on the same inputs, from the pass's first frame.
    let mut twin = AdaptiveTwin::new(config, Control::As, W, H).expect("twin");
    twin.set_count_dilation(DILATION).expect("dilation radius");
    let (mut agree, mut total) = (0_u64, 0_u64);
    for (k, f) in frames.iter().enumerate() {
        let to_u8 = |m: &[u32]| m.iter().map(|x| u8::from(*x != 0)).collect::<Vec<u8>>();
        let (mask, previous) = (to_u8(&f.mask), to_u8(&f.previous_mask));
        let counts = twin
            .estimate(&EstimateData {
                motion: &f.motion,
                depth: &f.depth,
                previous_depth: &f.previous_depth,
                reprojected_depth: None,
                masks: Some(Masks {
                    current: &mask,
                    previous: &previous,
                }),
                gamma: None,
            })
            .expect("twin estimate")
            .to_vec();
        let same = counts.iter().zip(&f.count).filter(|(a, b)| a == b).count();
        agree += same as u64;
        total += counts.len() as u64;
        assert_eq!(
            same,
            counts.len(),
            "frame {k}: GPU counts differ from the twin's"
        );
        twin.update(&UpdateData {
            value: &f.value,
            control: None,
            guide: None,
        })
        .expect("twin update");
    }

    // After TAA: adaptive vs fixed at (at least) the adaptive mean spp, against the reference.
    let (mut pa, mut pf) = (0.0, 0.0);
    let measured = &frames[frames.len() - (FRAMES - WARM)..];
    for f in measured {
        assert_eq!(f.images.len(), 3, "three images");
        // The images are grey (white unlit materials times the visibility): the red channel.
        let red = |k: usize| f.images[k].iter().map(|p| p[0]).collect::<Vec<f32>>();
        pa += psnr(&red(0), &red(2), &f.mask);
        pf += psnr(&red(1), &red(2), &f.mask);
    }
    let n = measured.len() as f64;
    let (pa, pf) = (pa / n, pf / n);
    let (mut spent, mut pixels) = (0_u64, 0_u64);
    for f in measured {
        spent += f.count.iter().map(|c| u64::from(*c)).sum::<u64>();
        pixels += covered(f) as u64;
    }
    let mean_spp = spent as f64 / pixels as f64;
    eprintln!(
        "spvg-bevy headless: {} frames ({} measured) at {W}x{H}; mean spp {mean_spp:.3}; \
         PSNR after TAA vs the 256-spp reference: adaptive {pa:.2} dB, fixed {fixed} spp \
         {pf:.2} dB; twin agreement {agree}/{total} counts",
        frames.len(),
        measured.len()
    );
    assert!(
        f64::from(fixed) >= mean_spp,
        "the fixed count {fixed} is at least the adaptive mean {mean_spp:.3}"
    );
    assert!(
        pa > pf,
        "adaptive ({pa:.2} dB at {mean_spp:.3} spp) does not beat fixed ({pf:.2} dB at {fixed} spp)"
    );
}

#[test]
fn missing_prepass_is_reported_not_fatal() {
    if !adapter_or_skip("missing_prepass_is_reported_not_fatal") {
        return;
    }
    let mut app = app();
    app.finish();
    app.cleanup();
    spawn_scene(app.world_mut(), false);
    let adaptive = Some(AdaptiveSampling::new(config()));
    let (camera, _) = spawn_camera(
        app.world_mut(),
        [W, H],
        Some(SoftShadows::Adaptive),
        adaptive,
    );
    // TAA requires the prepasses; take it off with them.
    app.world_mut()
        .entity_mut(camera)
        .remove::<(TemporalAntiAliasing, MotionVectorPrepass)>();
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(
        app.world().get::<SpvgStatus>(camera),
        Some(&SpvgStatus::MissingPrepass {
            depth: false,
            motion_vectors: true
        }),
        "the status names the missing prepass"
    );
    let msaa = app.world_mut().spawn((
        Camera3d::default(),
        Msaa::Sample4,
        AdaptiveSampling::default(),
    ));
    let msaa = msaa.id();
    app.update();
    assert_eq!(
        app.world().get::<SpvgStatus>(msaa),
        Some(&SpvgStatus::Multisampled),
        "the status names MSAA"
    );
    // A setting the component refuses: a failure status naming it, kept (not retried
    // every frame) while the settings stay.
    let refused = AdaptiveSampling {
        dilation: 1000,
        ..AdaptiveSampling::new(config())
    };
    let (bad, _) = spawn_camera(app.world_mut(), [W, H], None, Some(refused));
    for _ in 0..3 {
        app.update();
    }
    let status = app.world().get::<SpvgStatus>(bad).cloned();
    assert!(
        matches!(&status, Some(SpvgStatus::Failed(e)) if e.contains("radius")),
        "the status names the refused setting: {status:?}"
    );
}

#[test]
fn pass_follows_the_view_size_and_the_camera() {
    if !adapter_or_skip("pass_follows_the_view_size_and_the_camera") {
        return;
    }
    let mut app = app();
    let captures = add_capture(&mut app);
    app.finish();
    app.cleanup();
    spawn_scene(app.world_mut(), false);
    let adaptive = Some(AdaptiveSampling::new(config()));
    let (camera, image) = spawn_camera(
        app.world_mut(),
        [W, H],
        Some(SoftShadows::Adaptive),
        adaptive,
    );
    for _ in 0..2 {
        app.update();
    }
    let size = |c: &scene::Captures| c.0.lock().expect("lock").last().map(|f| f.count.len());
    assert_eq!(
        size(&captures),
        Some((W * H) as usize),
        "the pass has the view's size"
    );
    let (w2, h2) = (64, 40);
    app.world_mut()
        .resource_mut::<Assets<Image>>()
        .get_mut(&image)
        .expect("target image")
        .resize(bevy::render::render_resource::Extent3d {
            width: w2,
            height: h2,
            depth_or_array_layers: 1,
        });
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(
        size(&captures),
        Some((w2 * h2) as usize),
        "the pass follows the resized view"
    );
    assert_eq!(
        app.world().get::<SpvgStatus>(camera),
        Some(&SpvgStatus::Running),
        "still running after the resize"
    );
    app.world_mut().despawn(camera);
    app.update();
    let render = app.sub_app_mut(RenderApp).world_mut();
    let left = render.query::<&spvg_bevy::SpvgView>().iter(render).count();
    assert_eq!(left, 0, "the pass is dropped with the camera");
}
