//! The component's steps over a tile list (`AdaptiveTiles`): the tile entry points validated
//! by naga (no GPU needed), a list of the wrong size refused by name, and on a device the
//! restricted steps giving the whole-frame steps' counts and history bit for bit when the
//! unlisted pixels are outside the mask and the whole-frame steps ran for the two frames
//! after the list was set (a pan, so the reprojection reads history away from each pixel).
//! GPU tests skip cleanly without an adapter.

mod common;

use half::f16;
use spvg::SpvgConfig;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveTiles, Control, EstimateInputs, Masks, UpdateInputs,
};
use spvg_wgpu::util::read_texture;
use wgpu::util::DeviceExt as _;

const W: u32 = 37; // not a multiple of the 8 x 8 tile
const H: u32 = 29;

/// Region: a disc of radius 7 around (12, 13), so some 8 x 8 tiles are partly inside.
fn region() -> Vec<u8> {
    (0..W * H)
        .map(|i| {
            let (dx, dy) = ((i % W) as f32 - 12.0, (i / W) as f32 - 13.0);
            u8::from(dx * dx + dy * dy < 49.0)
        })
        .collect()
}

/// A deterministic value in [0, 1) per (pixel, frame, stream).
fn noise(i: u32, t: u32, k: u32) -> f32 {
    let mut x = u64::from(i) << 32 | u64::from(t) << 8 | u64::from(k);
    x = x.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    x ^= x >> 29;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x ^= x >> 32;
    (x & 0xff_ffff) as f32 / 16_777_216.0
}

fn texture<T: bytemuck::Pod>(
    d: &spvg_gpu_test::GpuDevice,
    format: wgpu::TextureFormat,
    data: &[T],
) -> wgpu::Texture {
    d.device.create_texture_with_data(
        &d.queue,
        &wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d {
                width: W,
                height: H,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(data),
    )
}

/// One frame's inputs: a pan of 0.6 px per frame to the right (motion points back), the
/// region's mask, a depth ramp, noisy monitored and control values.
struct Inputs {
    motion: wgpu::Texture,
    depth: wgpu::Texture,
    mask: wgpu::Texture,
    value: wgpu::Texture,
    control: wgpu::Texture,
}

fn inputs(d: &spvg_gpu_test::GpuDevice, t: u32) -> Inputs {
    use wgpu::TextureFormat as F;
    let n = W * H;
    let motion: Vec<[f16; 2]> = vec![[f16::from_f32(-0.6), f16::ZERO]; n as usize];
    let depth: Vec<f32> = (0..n).map(|i| 900.0 + (i % W) as f32).collect();
    let value: Vec<f32> = (0..n).map(|i| 0.5 + 0.3 * noise(i, t, 0)).collect();
    let control: Vec<f32> = (0..n).map(|i| 0.4 + 0.2 * noise(i, t, 1)).collect();
    Inputs {
        motion: texture(d, F::Rg16Float, &motion),
        depth: texture(d, F::R32Float, &depth),
        mask: texture(d, F::R8Uint, &region()),
        value: texture(d, F::R32Float, &value),
        control: texture(d, F::R32Float, &control),
    }
}

#[test]
fn listed_tiles_give_the_whole_frame_steps_outside_the_mask() {
    let Some(d) =
        spvg_gpu_test::GpuTest::new("listed_tiles_give_the_whole_frame_steps_outside_the_mask")
            .device()
    else {
        return;
    };
    let config = SpvgConfig::builder().build().expect("default config");
    let ocv = Control::Ocv(spvg::cv::Ocv::with_weight(0.2).expect("valid eta_cv"));
    for control in [Control::As, Control::Ccv, ocv] {
        let new =
            || AdaptivePass::new(&d.device, common::settings(config, control), W, H).expect("pass");
        let (mut whole, mut listed) = (new(), new());
        let mut tiles = AdaptiveTiles::new(&listed);
        assert!(tiles.set_region(&region()).expect("region size"));
        assert!(!tiles.set_region(&region()).expect("same region"));
        let mut prev: Option<Inputs> = None;
        for t in 0..6 {
            let cur = inputs(&d, t);
            let p = prev.as_ref().unwrap_or(&cur);
            let est =
                EstimateInputs::new(&cur.motion, &cur.depth, &p.depth).with_masks(Some(Masks {
                    current: &cur.mask,
                    previous: &p.mask,
                }));
            let upd = UpdateInputs::new(&cur.value).with_control(Some(&cur.control));
            let mut enc = d.device.create_command_encoder(&Default::default());
            whole.record_estimate(&mut enc, &est).expect("estimate");
            whole.record_update(&mut enc, &upd).expect("update");
            // The first two frames over the whole frame: both history halves get the
            // unlisted pixels' zeros.
            if t < 2 {
                listed.record_estimate(&mut enc, &est).expect("estimate");
                listed.record_update(&mut enc, &upd).expect("update");
            } else {
                let e = listed.record_estimate_tiles(&mut enc, &est, &tiles, None);
                e.expect("estimate over tiles");
                let u = listed.record_update_tiles(&mut enc, &upd, &tiles, None);
                u.expect("update over tiles");
            }
            d.queue.submit([enc.finish()]);
            let read = |p: &AdaptivePass| {
                let c: Vec<u32> = read_texture(&d.device, &d.queue, p.count_texture()).unwrap();
                let h: Vec<[f16; 4]> =
                    read_texture(&d.device, &d.queue, p.history_texture()).unwrap();
                (c, h.iter().map(|x| x.map(f16::to_bits)).collect::<Vec<_>>())
            };
            let ((ca, ha), (cb, hb)) = (read(&whole), read(&listed));
            assert_eq!(ca, cb, "{control:?} frame {t}: counts");
            assert_eq!(ha, hb, "{control:?} frame {t}: history");
            assert!(ca.iter().any(|&c| c > 0), "{control:?} frame {t}: samples");
            prev = Some(cur);
        }
        // A list of another size is refused by name, and so is a wrong region.
        let other = AdaptivePass::new(&d.device, common::settings(config, control), W + 1, H)
            .expect("pass");
        let mut enc = d.device.create_command_encoder(&Default::default());
        let cur = inputs(&d, 0);
        let upd = UpdateInputs::new(&cur.value).with_control(Some(&cur.control));
        let err = listed.record_update_tiles(&mut enc, &upd, &AdaptiveTiles::new(&other), None);
        assert!(
            matches!(err, Err(AdaptiveError::TextureSize { input: "tiles", .. })),
            "{err:?}"
        );
        let err = tiles.set_region(&[1; 5]);
        assert!(
            matches!(
                err,
                Err(AdaptiveError::SliceLength {
                    input: "region",
                    ..
                })
            ),
            "{err:?}"
        );
    }
}
