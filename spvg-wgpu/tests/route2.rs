//! Route 2 of docs/integrating.md against Route 1: the renderer's own single pass
//! (`examples/route2_pass`, the library's `spvg_reproject_locate`, `spvg_estimate_texel`,
//! `spvg_reproject_entering_count`, `spvg_dilation_*` and `spvg_update_young_texel`)
//! and `AdaptivePass` run the same moving scene (sub-pixel pans, pixels entering at the
//! edges, a disc uncovering the surface behind it), with and without count dilation; the
//! counts and the histories must be equal, pixel for pixel, every frame.

#[path = "../examples/route2_pass/mod.rs"]
mod route2_pass;

use half::f16;
use route2_pass::{Inputs, Route2Pass, Scene};
use spvg::SpvgConfig;
use spvg::reproject::Reprojection;
use spvg_wgpu::adaptive::{
    AdaptivePass, AdaptiveSettings, AdaptiveTwin, EstimateData, EstimateInputs, UpdateData,
    UpdateInputs,
};
use spvg_wgpu::util::read_texture;

fn config() -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .target_variance(1e-3)
        .kappa(0.5)
        // route 2's single fused pass has no neighbourhood of this frame: the spatial variance off, as docs/integrating.md says.
        .spatial_variance(0)
        .build()
        .expect("valid config")
}

#[test]
fn route2_counts_equal_the_component_every_frame() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("route2_counts_equal_the_component_every_frame").device()
    else {
        return;
    };
    let (device, queue) = (&dev.device, &dev.queue);
    // Not multiples of the 8x8 workgroup.
    let scene = Scene {
        width: 45,
        height: 29,
    };
    let (w, h) = (scene.width, scene.height);
    for dilation in [0, 1] {
        let mut route2 = Route2Pass::new(device, &config(), w, h).expect("route 2 pass");
        route2.set_count_dilation(dilation);
        // Route 2's fused pass dilates without the neighbour prior.
        let settings = AdaptiveSettings {
            config: config(),
            dilation,
            neighbour_prior: false,
            ..AdaptiveSettings::default()
        };
        let mut component = AdaptivePass::new(device, settings, w, h).expect("component");
        // The twin (equal to the component by tests/adaptive.rs) says which paths the
        // scene took.
        let mut twin = AdaptiveTwin::new(settings, w, h).expect("twin");
        // The same without the footprint search: where it finds no history and the twin
        // does, the footprint search was taken.
        let nearest = AdaptiveSettings {
            reprojection: Reprojection::default().with_footprint_search(false),
            ..settings
        };
        let mut nearest_only = AdaptiveTwin::new(nearest, w, h).expect("twin");
        let (mut previous, mut previous_textures) = (scene.frame(0), None);
        let (mut disoccluded, mut at_max, mut above_min, mut footprint) = (0, 0, 0, 0);
        for t in 0..8 {
            let frame = scene.frame(t);
            let textures = scene.upload(device, queue, &frame);
            let [motion, depth, radiance] = &textures;
            let previous_depth = previous_textures
                .as_ref()
                .map_or(depth, |p: &[wgpu::Texture; 3]| &p[1]);
            let mut encoder = device.create_command_encoder(&Default::default());
            // Route 2 first: its values (the mean of its samples) feed the component's
            // update, so both histories see the same frame where the counts agree.
            route2.record(
                device,
                queue,
                &mut encoder,
                &Inputs {
                    motion,
                    depth,
                    previous_depth,
                    radiance,
                },
            );
            component
                .record_estimate(
                    &mut encoder,
                    &EstimateInputs {
                        motion,
                        depth,
                        previous_depth,
                        reprojected_depth: None,
                        masks: None,
                        gamma: None,
                    },
                )
                .expect("estimate inputs");
            component
                .record_update(
                    &mut encoder,
                    &UpdateInputs {
                        value: route2.value_texture(),
                        control: None,
                        guide: None,
                    },
                )
                .expect("update inputs");
            queue.submit([encoder.finish()]);
            let read_counts = |t: &wgpu::Texture| -> Vec<u32> {
                read_texture(device, queue, t).expect("readback")
            };
            let read_history = |t: &wgpu::Texture| -> Vec<[u16; 4]> {
                let v: Vec<[f16; 4]> = read_texture(device, queue, t).expect("readback");
                v.iter().map(|x| x.map(f16::to_bits)).collect()
            };
            let (ours, theirs) = (
                read_counts(route2.count_texture()),
                read_counts(component.count_texture()),
            );
            let differ: Vec<usize> = (0..ours.len()).filter(|&i| ours[i] != theirs[i]).collect();
            assert!(
                differ.is_empty(),
                "dilation {dilation}, frame {t}: {} counts differ, first at pixel {:?}: route 2 {}, component {}",
                differ.len(),
                differ.first().map(|&i| (i as u32 % w, i as u32 / w)),
                differ.first().map_or(0, |&i| ours[i]),
                differ.first().map_or(0, |&i| theirs[i]),
            );
            let (hr, hc) = (
                read_history(route2.history_texture()),
                read_history(component.history_texture()),
            );
            let differ = hr.iter().zip(&hc).filter(|(a, b)| a != b).count();
            assert_eq!(
                differ, 0,
                "dilation {dilation}, frame {t}: history texels differ"
            );

            let values: Vec<f32> =
                read_texture(device, queue, route2.value_texture()).expect("readback");
            let data = EstimateData {
                motion: &frame.motion,
                depth: &frame.depth,
                previous_depth: &previous.depth,
                reprojected_depth: None,
                masks: None,
                gamma: None,
            };
            let counts = twin.estimate(&data).expect("twin estimate").to_vec();
            assert_eq!(counts, ours, "the twin agrees too");
            nearest_only.estimate(&data).expect("twin estimate");
            if t > 0 {
                disoccluded += twin.valid().iter().filter(|v| !**v).count();
                footprint += (twin.valid().iter().zip(nearest_only.valid()))
                    .filter(|(a, b)| **a && !*b)
                    .count();
                at_max += counts
                    .iter()
                    .filter(|&&n| n == config().max_samples())
                    .count();
                above_min += counts
                    .iter()
                    .filter(|&&n| n > config().min_samples())
                    .count();
            }
            let update = UpdateData {
                value: &values,
                control: None,
                guide: None,
            };
            twin.update(&update).expect("twin update");
            nearest_only.update(&update).expect("twin update");
            (previous, previous_textures) = (frame, Some(textures));
        }
        eprintln!(
            "route 2: dilation {dilation}: 8 frames of {w}x{h} equal; {disoccluded} pixel-frames with no history to continue (disoccluded or entering), {footprint} continued by the footprint search, {at_max} at beta_max, {above_min} above beta_min"
        );
        // The scene must take every path, or the equality proves little.
        assert!(
            disoccluded > 100,
            "only {disoccluded} pixel-frames without history"
        );
        assert!(footprint > 0, "the footprint search was never taken");
        assert!(at_max > 20, "only {at_max} pixel-frames at beta_max");
        assert!(
            above_min > 500,
            "only {above_min} pixel-frames above beta_min"
        );
    }
}
