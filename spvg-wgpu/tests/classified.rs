//! The count-classified dispatch (`AdaptiveSettings::classified_dispatch`): on a device,
//! the classes (compacted tile lists per class) and the tiles' pixel orders the estimate
//! writes equal the twin's, with the counts, on a noisy panning scene wider than one
//! scatter chunk and not a multiple of the tile; and a consumer recorded with
//! `dispatch_classified` takes every pixel of the frame exactly once, in the order the
//! twin gives. GPU tests skip cleanly without an adapter.

mod common;

use spvg::SpvgConfig;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveSettings, AdaptiveTwin, EstimateData, EstimateInputs,
    UpdateData, UpdateInputs,
};
use spvg_wgpu::util::{read_texture, texture_2d, view};

// 76 tiles per row: a row of the scatter pass spans two chunks of 64 tiles; 5 tile rows,
// the last partial.
const W: u32 = 603;
const H: u32 = 37;

/// A deterministic value in [0, 1) per (pixel, frame, stream).
fn noise(i: u32, t: u32, k: u32) -> f32 {
    let mut x = u64::from(i) << 32 | u64::from(t) << 8 | u64::from(k);
    x = x.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    x ^= x >> 29;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x ^= x >> 32;
    (x & 0xff_ffff) as f32 / 16_777_216.0
}

/// Frame `t`: a pan of 0.7 px per frame, depth a ramp with a step, and a value whose
/// noise amplitude varies from band to band (so the counts spread over the classes).
struct Frame {
    motion: Vec<[f32; 2]>,
    depth: Vec<f32>,
    value: Vec<f32>,
}

fn frame(t: u32) -> Frame {
    let n = W * H;
    let amplitude = |i: u32| [0.0, 0.01, 0.05, 0.2, 0.6][((i % W) / 37 % 5) as usize];
    Frame {
        motion: vec![[0.7, 0.0]; n as usize],
        depth: (0..n)
            .map(|i| if i % W > 400 { 3.0 } else { 2.0 } + 1e-3 * (i % W) as f32)
            .collect(),
        value: (0..n)
            .map(|i| 0.5 + amplitude(i) * (noise(i, t, 0) - 0.5))
            .collect(),
    }
}

fn settings() -> AdaptiveSettings {
    AdaptiveSettings {
        config: SpvgConfig::builder()
            .target_variance(1e-3)
            .budget(1, 96)
            .build()
            .expect("valid config"),
        dilation: 1,
        classified_dispatch: true,
        ..AdaptiveSettings::default()
    }
}

#[test]
fn classified_lists_and_pixel_orders_equal_the_twin() {
    let Some(d) =
        spvg_gpu_test::GpuTest::new("classified_lists_and_pixel_orders_equal_the_twin").device()
    else {
        return;
    };
    let mut gpu = AdaptivePass::new(&d.device, settings(), W, H).expect("pass");
    let mut twin = AdaptiveTwin::new(settings(), W, H).expect("twin");
    let mut prev = frame(0);
    let mut classes_seen = [false; AdaptivePass::CLASS_BOUNDS.len() + 1];
    for t in 0..8 {
        let cur = frame(t);
        let (motion, depth, previous_depth, value) = (
            common::upload(&d, wgpu::TextureFormat::Rg32Float, [W, H], &cur.motion),
            common::upload(&d, wgpu::TextureFormat::R32Float, [W, H], &cur.depth),
            common::upload(&d, wgpu::TextureFormat::R32Float, [W, H], &prev.depth),
            common::upload(&d, wgpu::TextureFormat::R32Float, [W, H], &cur.value),
        );
        let mut enc = d.device.create_command_encoder(&Default::default());
        let inputs = EstimateInputs::new(&motion, &depth, &previous_depth);
        gpu.record_estimate(&mut enc, &inputs).expect("estimate");
        d.queue.submit([enc.finish()]);
        twin.estimate(&EstimateData::new(&cur.motion, &cur.depth, &prev.depth))
            .expect("twin estimate");
        let counts: Vec<u32> =
            read_texture(&d.device, &d.queue, gpu.count_texture()).expect("counts");
        assert_eq!(counts, twin.counts(), "frame {t}: counts");
        let (classes, orders) = gpu.read_classes(&d.queue).expect("classes");
        assert_eq!(classes, twin.classes(), "frame {t}: class lists");
        assert_eq!(orders, twin.pixel_orders(), "frame {t}: pixel orders");
        let tiles = W.div_ceil(8) * H.div_ceil(8);
        assert_eq!(
            classes.iter().map(Vec::len).sum::<usize>(),
            tiles as usize,
            "frame {t}: every tile in one class"
        );
        for (c, list) in classes.iter().enumerate() {
            classes_seen[c] |= !list.is_empty();
        }
        let mut enc = d.device.create_command_encoder(&Default::default());
        gpu.record_update(&mut enc, &UpdateInputs::new(&value))
            .expect("update");
        d.queue.submit([enc.finish()]);
        twin.update(&UpdateData::new(&cur.value))
            .expect("twin update");
        prev = cur;
    }
    // The scene reaches the classes of 1, 5-8, 9-16 and beyond, so the lists are not
    // trivially one class.
    let seen = classes_seen.iter().filter(|&&s| s).count();
    assert!(seen >= 4, "classes seen: {classes_seen:?}");
}

/// A consumer that writes, per pixel, one more than the invocation index that took it.
const CONSUMER: &str = "
@group(0) @binding(0) var taken: texture_storage_2d<r32uint, write>;
@group(0) @binding(1) var<uniform> size: vec4<u32>;
@compute @workgroup_size(8, 8, 1)
fn take(@builtin(workgroup_id) wg: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>,
        @builtin(local_invocation_index) index: u32) {
    let p = adaptive_class_pixel(wg, groups, index);
    if (p.z == 0u && p.x < size.x && p.y < size.y) {
        textureStore(taken, vec2<i32>(p.xy), vec4<u32>(index + 1u, 0u, 0u, 0u));
    }
}
";

#[test]
fn classified_dispatch_takes_every_pixel_once_in_the_twins_order() {
    let Some(d) = spvg_gpu_test::GpuTest::new(
        "classified_dispatch_takes_every_pixel_once_in_the_twins_order",
    )
    .device() else {
        return;
    };
    let (mut gpu, mut twin) = (
        AdaptivePass::new(&d.device, settings(), W, H).expect("pass"),
        AdaptiveTwin::new(settings(), W, H).expect("twin"),
    );
    let module = spvg_wgpu::util::shader_module(
        &d.device,
        "classified consumer",
        format!("{}{CONSUMER}", AdaptivePass::CLASSIFIED_WGSL),
    );
    let pipeline = spvg_wgpu::util::compute_pipeline(&d.device, &module, "take", None);
    let taken = texture_2d(
        &d.device,
        "taken",
        wgpu::TextureFormat::R32Uint,
        [W, H],
        wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
    );
    let size = {
        use wgpu::util::DeviceExt as _;
        d.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: bytemuck::cast_slice(&[W, H, 0, 0]),
                usage: wgpu::BufferUsages::UNIFORM,
            })
    };
    let group = spvg_wgpu::util::bind_group(
        &d.device,
        None,
        &pipeline.get_bind_group_layout(0),
        &[(1, &size)],
        &[(0, view(&taken))],
    );
    // Two frames, so the second has counts above beta_min.
    let (f0, f1) = (frame(0), frame(1));
    for (cur, prev) in [(&f0, &f0), (&f1, &f0)] {
        let motion = common::upload(&d, wgpu::TextureFormat::Rg32Float, [W, H], &cur.motion);
        let depth = common::upload(&d, wgpu::TextureFormat::R32Float, [W, H], &cur.depth);
        let previous = common::upload(&d, wgpu::TextureFormat::R32Float, [W, H], &prev.depth);
        let value = common::upload(&d, wgpu::TextureFormat::R32Float, [W, H], &cur.value);
        let mut enc = d.device.create_command_encoder(&Default::default());
        let inputs = EstimateInputs::new(&motion, &depth, &previous);
        gpu.record_estimate(&mut enc, &inputs).expect("estimate");
        gpu.dispatch_classified(&mut enc, "take", &pipeline, &group, None)
            .expect("classified dispatch");
        let update = UpdateInputs::new(&value);
        gpu.record_update(&mut enc, &update).expect("update");
        d.queue.submit([enc.finish()]);
        let data = EstimateData::new(&cur.motion, &cur.depth, &prev.depth);
        twin.estimate(&data).expect("twin estimate");
        twin.update(&UpdateData::new(&cur.value))
            .expect("twin update");
    }
    let got: Vec<u32> = read_texture(&d.device, &d.queue, &taken).expect("taken");
    let tiles_x = W.div_ceil(8);
    let mut reordered = false;
    for (tile, order) in twin.pixel_orders().iter().enumerate() {
        let (tx, ty) = (tile as u32 % tiles_x, tile as u32 / tiles_x);
        for (k, &o) in order.iter().enumerate() {
            let (x, y) = (tx * 8 + u32::from(o) % 8, ty * 8 + u32::from(o) / 8);
            if x < W && y < H {
                let at = got[(y * W + x) as usize];
                assert_eq!(
                    at,
                    k as u32 + 1,
                    "pixel ({x}, {y}) taken by invocation {}",
                    at - 1
                );
                reordered |= usize::from(o) != k;
            }
        }
    }
    assert!(
        reordered,
        "some tile's order differs from the natural one (the counts differ within tiles)"
    );
}

#[test]
fn dispatch_classified_needs_the_setting() {
    let Some(d) = spvg_gpu_test::GpuTest::new("dispatch_classified_needs_the_setting").device()
    else {
        return;
    };
    let off = AdaptiveSettings {
        classified_dispatch: false,
        ..settings()
    };
    let mut gpu = AdaptivePass::new(&d.device, off, W, H).expect("pass");
    assert!(matches!(
        gpu.read_classes(&d.queue),
        Err(AdaptiveError::MissingInput { .. })
    ));
    let mut twin = AdaptiveTwin::new(off, W, H).expect("twin");
    let f = frame(0);
    twin.estimate(&EstimateData::new(&f.motion, &f.depth, &f.depth))
        .expect("twin estimate");
    assert!(twin.classes().is_empty() && twin.pixel_orders().is_empty());
    // Switching it on between frames builds the classification.
    gpu.set_settings(settings()).expect("on");
    assert!(
        gpu.read_classes(&d.queue).is_ok(),
        "classes readable once on"
    );
}
