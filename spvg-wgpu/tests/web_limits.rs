//! The component on the web: on a device requested with `wgpu::Limits::default()`
//! (WebGPU's defaults, what every browser grants: 4 storage textures, 16 sampled textures
//! and 8 storage buffers per shader stage), every step it records builds and runs, equal
//! to its twin bit for bit, with the widest settings (the estimate's four storage
//! textures: counts, links, the kept depth of the spatial variance and the neighbour
//! prior, the real counts of fractional counts; OCV's second history; the count
//! dilation; the count-classified dispatch's buffers). The results come back through the
//! async readback a browser uses (`read_texture_async`), here polled on the native device,
//! and equal the blocking one's.

use half::f16;
use spvg::SpvgConfig;
use spvg::cv::Ocv;
use spvg_gpu_test::{GpuDevice, GpuTest};
use spvg_wgpu::adaptive::{
    AdaptivePass, AdaptiveSettings, AdaptiveTwin, Control, EstimateData, EstimateInputs,
    UpdateData, UpdateInputs,
};
use spvg_wgpu::util::{block_on, read_texture, read_texture_async};

/// A small integer hash (splitmix-style) in [0, 1).
fn hash(mut x: u64) -> f32 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((x ^ (x >> 31)) >> 40) as f32 / (1u64 << 24) as f32
}

/// One frame: a surface panned at 1.25 px per frame along x (sub-pixel reprojection),
/// a disc at half its depth crossing it at 2 px per frame along y (disocclusion), noise
/// whose amplitude varies over the surface, and the control value of CCV/OCV.
struct Frame {
    motion: Vec<[f32; 2]>,
    depth: Vec<f32>,
    value: Vec<f32>,
    control: Vec<f32>,
}

fn frame(w: u32, h: u32, t: u32) -> Frame {
    let pan = |t: u32| 1.25 * t as f32;
    let disc = |t: u32| [20.0, 2.0 * t as f32];
    let (c, cp) = (pan(t), pan(t.saturating_sub(1)));
    let (o, op) = (disc(t), disc(t.saturating_sub(1)));
    let mut f = Frame {
        motion: Vec::new(),
        depth: Vec::new(),
        value: Vec::new(),
        control: Vec::new(),
    };
    for y in 0..h {
        for x in 0..w {
            let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
            let wx = px + c;
            let in_disc = (px - o[0]).powi(2) + (py - o[1]).powi(2) < 36.0;
            let (motion, depth, cell) = if in_disc {
                ([0.0, o[1] - op[1]], 0.5, 1 << 40)
            } else {
                (
                    [cp - c, 0.0],
                    1.0 + 0.002 * wx,
                    (wx.floor() as u64) << 20 | u64::from(y),
                )
            };
            let base = 0.5 + 0.3 * (0.2 * wx).sin();
            let amp = 0.02 + 0.3 * hash(cell / 3);
            f.motion.push(motion);
            f.depth.push(depth);
            f.control.push(0.8 * base);
            f.value
                .push(0.8 * base + amp * (hash(cell ^ u64::from(t) << 48) - 0.5));
        }
    }
    f
}

fn upload<T: bytemuck::Pod>(
    dev: &GpuDevice,
    format: wgpu::TextureFormat,
    size: [u32; 2],
    data: &[T],
) -> wgpu::Texture {
    use wgpu::util::DeviceExt as _;
    dev.device.create_texture_with_data(
        &dev.queue,
        &spvg_wgpu::util::texture_2d_desc(
            "upload",
            format,
            size,
            wgpu::TextureUsages::TEXTURE_BINDING,
        ),
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(data),
    )
}

fn bits(v: &[[f16; 4]]) -> Vec<[u16; 4]> {
    v.iter().map(|t| t.map(f16::to_bits)).collect()
}

#[test]
fn component_runs_under_webgpu_default_limits_equal_to_its_twin() {
    let limits = wgpu::Limits::default();
    assert_eq!(
        (
            limits.max_storage_textures_per_shader_stage,
            limits.max_sampled_textures_per_shader_stage
        ),
        (4, 16),
        "wgpu's default limits are WebGPU's"
    );
    let Some(dev) = GpuTest::new("component_runs_under_webgpu_default_limits")
        .limits(limits.clone())
        .device()
    else {
        return;
    };
    assert_eq!(
        dev.device.limits().max_storage_textures_per_shader_stage,
        4,
        "the device holds the default limits, not the adapter's"
    );
    let (w, h) = (45, 26); // not multiples of the 8x8 workgroup
    let config = SpvgConfig::builder()
        .target_variance(1e-3)
        .fractional_floor(Some(0.5))
        .build()
        .expect("valid config");
    let ocv = Control::Ocv(Ocv::with_weight(0.2).expect("valid eta_cv"));
    for control in [Control::As, ocv] {
        let settings = AdaptiveSettings {
            config,
            control,
            dilation: 1,
            neighbour_prior: true,
            classified_dispatch: true,
            ..AdaptiveSettings::default()
        };
        let name = control.name();
        let mut gpu = AdaptivePass::new(&dev.device, settings, w, h).expect("gpu pass");
        let mut twin = AdaptiveTwin::new(settings, w, h).expect("twin");
        let mut prev: Option<(Frame, wgpu::Texture)> = None;
        let (mut disoccluded, mut above_min) = (0, 0);
        for t in 0..8 {
            let cur = frame(w, h, t);
            let motion = upload(&dev, wgpu::TextureFormat::Rg32Float, [w, h], &cur.motion);
            let depth = upload(&dev, wgpu::TextureFormat::R32Float, [w, h], &cur.depth);
            let value = upload(&dev, wgpu::TextureFormat::R32Float, [w, h], &cur.value);
            let cv = upload(&dev, wgpu::TextureFormat::R32Float, [w, h], &cur.control);
            let previous_depth = prev.as_ref().map_or(&depth, |(_, d)| d);
            let mut enc = dev.device.create_command_encoder(&Default::default());
            gpu.record_estimate(
                &mut enc,
                &EstimateInputs::new(&motion, &depth, previous_depth),
            )
            .expect("estimate");
            gpu.record_update(&mut enc, &UpdateInputs::new(&value).with_control(Some(&cv)))
                .expect("update");
            dev.queue.submit([enc.finish()]);
            let count: Vec<u32> = block_on(read_texture_async(
                &dev.device,
                &dev.queue,
                gpu.count_texture(),
            ))
            .expect("async readback");
            let history: Vec<[f16; 4]> = block_on(read_texture_async(
                &dev.device,
                &dev.queue,
                gpu.history_texture(),
            ))
            .expect("async readback");
            let prev_depth = prev.as_ref().map_or(&cur.depth, |(f, _)| &f.depth);
            let want = twin
                .estimate(&EstimateData::new(&cur.motion, &cur.depth, prev_depth))
                .expect("twin estimate")
                .to_vec();
            disoccluded += twin.valid().iter().filter(|v| !**v).count();
            above_min += want.iter().filter(|&&n| n > 8).count();
            twin.update(&UpdateData::new(&cur.value).with_control(Some(&cur.control)))
                .expect("twin update");
            let differ = count.iter().zip(&want).filter(|(a, b)| a != b).count();
            assert_eq!(differ, 0, "{name} frame {t}: {differ} counts differ");
            assert_eq!(
                bits(&history),
                bits(twin.history()),
                "{name} frame {t}: history texels"
            );
            if let Some(cv_texture) = gpu.cv_history_texture() {
                let cv_history: Vec<[f16; 4]> =
                    block_on(read_texture_async(&dev.device, &dev.queue, cv_texture))
                        .expect("async readback");
                assert_eq!(
                    bits(&cv_history),
                    bits(twin.cv_history().expect("an OCV twin keeps a CV history")),
                    "{name} frame {t}: CV history texels"
                );
            }
            // The classified dispatch's lists were built on this device too.
            let (classes, orders) = gpu
                .read_classes(&dev.queue)
                .expect("the classification is on");
            assert_eq!(classes, twin.classes(), "{name} frame {t}: tile classes");
            assert_eq!(
                orders,
                twin.pixel_orders(),
                "{name} frame {t}: pixel orders"
            );
            prev = Some((cur, depth));
        }
        // Both paths of the estimate ran, or the equality proves little.
        assert!(
            disoccluded > 100 && above_min > 100,
            "{name}: {disoccluded} disoccluded pixel-frames, {above_min} counts above beta_min"
        );
    }
}

/// The async readback returns what the blocking one does: rows whose texels do not fill
/// the 256-byte copy alignment (45 texels of 4 and of 8 bytes), and a texel type of the
/// wrong size is refused before anything is copied.
#[test]
fn async_readback_equals_the_blocking_one() {
    let Some(dev) = GpuTest::new("async_readback_equals_the_blocking_one").device() else {
        return;
    };
    let (w, h): (u32, u32) = (45, 7);
    let size = [w, h];
    let words: Vec<u32> = (0..w * h).map(|i| i.wrapping_mul(2_654_435_761)).collect();
    let texels: Vec<[f16; 4]> = (0..w * h)
        .map(|i| [0, 1, 2, 3].map(|c| f16::from_f32(i as f32 * 0.25 - c as f32)))
        .collect();
    let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
    let make = |format, bytes: &[u8]| {
        use wgpu::util::DeviceExt as _;
        dev.device.create_texture_with_data(
            &dev.queue,
            &spvg_wgpu::util::texture_2d_desc("readback test", format, size, usage),
            wgpu::util::TextureDataOrder::LayerMajor,
            bytes,
        )
    };
    let r32 = make(wgpu::TextureFormat::R32Uint, bytemuck::cast_slice(&words));
    let rgba16 = make(
        wgpu::TextureFormat::Rgba16Float,
        bytemuck::cast_slice(&texels),
    );
    let got: Vec<u32> = block_on(read_texture_async(&dev.device, &dev.queue, &r32)).expect("async");
    assert_eq!(got, words, "R32Uint through the async readback");
    let blocking: Vec<u32> = read_texture(&dev.device, &dev.queue, &r32).expect("blocking");
    assert_eq!(got, blocking, "async and blocking readbacks agree");
    let got: Vec<[f16; 4]> =
        block_on(read_texture_async(&dev.device, &dev.queue, &rgba16)).expect("async");
    assert_eq!(
        bits(&got),
        bits(&texels),
        "Rgba16Float through the async readback"
    );
    let wrong = block_on(read_texture_async::<[f16; 4]>(
        &dev.device,
        &dev.queue,
        &r32,
    ));
    assert!(
        matches!(
            wrong,
            Err(spvg_wgpu::adaptive::AdaptiveError::TextureFormat { .. })
        ),
        "an 8-byte texel type for a 4-byte format: {wrong:?}"
    );
}
