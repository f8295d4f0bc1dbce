//! Route 2 of docs/integrating.md against Route 1: the renderer's own pass
//! (`examples/route2`: estimate, dilation with the neighbour prior, sampling and update
//! with the spatial moments of young histories, in four dispatches calling the library)
//! and `AdaptivePass` run the same moving scene (sub-pixel pans, pixels entering at the
//! edges, a disc uncovering the surface behind it) with the component's default settings,
//! without and with count dilation; the counts, the links and the history texels must be
//! equal, bit for bit, every frame. A second test switches each part of the reprojection
//! rule off, which the pass hands the library through `spvg_shaders::ReprojectionRule`.
//!
//! Twins of the component with one rule switched off (`AdaptiveTwin`, equal to the
//! component by tests/adaptive.rs) run beside it: where their counts or histories differ
//! from the default twin's, the scene exercised that rule, so a pass that left it out
//! could not have matched.

#[path = "../examples/route2/pass.rs"]
mod pass;
#[path = "../examples/route2/scene.rs"]
mod scene;

use half::f16;
use pass::{Inputs, Route2Pass};
use scene::Scene;
use spvg::reproject::{BorderCount, Reprojection};
use spvg_gpu_test::GpuDevice;
use spvg_wgpu::adaptive::{
    AdaptivePass, AdaptiveSettings, AdaptiveTwin, EstimateData, EstimateInputs, UpdateData,
    UpdateInputs,
};
use spvg_wgpu::util::read_texture;

/// Frames of each run.
const FRAMES: u32 = 8;

/// Not multiples of the 8x8 workgroup.
const SCENE: Scene = Scene {
    width: 45,
    height: 29,
};

/// What a run saw, over frames 1 to `FRAMES - 1` (frame 0 has no history anywhere).
#[derive(Debug)]
struct Run {
    /// Pixel-frames without a history to continue (disoccluded or entering).
    unlinked: usize,
    /// Pixel-frames at `beta_max`, and above `beta_min`.
    at_max: usize,
    above_min: usize,
    /// Per variant: pixel-frames whose count, and whose history texel, differ from the
    /// run's own twin.
    counts_differ: Vec<usize>,
    histories_differ: Vec<usize>,
}

/// The index of the first differing element and the two values, for the messages.
fn first_difference<T: PartialEq + Copy>(a: &[T], b: &[T]) -> Option<(usize, T, T)> {
    a.iter()
        .zip(b)
        .position(|(x, y)| x != y)
        .map(|i| (i, a[i], b[i]))
}

/// Runs the scene through the Route 2 pass and the component with `settings`, and asserts
/// that counts, links and history texels are equal every frame; twins with each of
/// `variants` run beside them on the same values.
fn run(dev: &GpuDevice, settings: AdaptiveSettings, variants: &[AdaptiveSettings]) -> Run {
    let (device, queue) = (&dev.device, &dev.queue);
    let (w, h) = (SCENE.width, SCENE.height);
    let mut route2 = Route2Pass::new(device, &settings.config, w, h).expect("route 2 pass");
    route2.set_reprojection(&settings.reprojection);
    route2.set_count_dilation(settings.dilation);
    let mut component = AdaptivePass::new(device, settings, w, h).expect("component");
    let mut twin = AdaptiveTwin::new(settings, w, h).expect("twin");
    let mut others: Vec<AdaptiveTwin> = variants
        .iter()
        .map(|&s| AdaptiveTwin::new(s, w, h).expect("variant twin"))
        .collect();
    let mut seen = Run {
        unlinked: 0,
        at_max: 0,
        above_min: 0,
        counts_differ: vec![0; variants.len()],
        histories_differ: vec![0; variants.len()],
    };
    let (mut previous, mut previous_textures) = (SCENE.frame(0), None);
    let at = |t: u32, what: &str, i: usize| {
        format!(
            "dilation {}, {:?}, frame {t}: {what} differ first at pixel ({}, {})",
            settings.dilation,
            settings.reprojection,
            i as u32 % w,
            i as u32 / w
        )
    };
    for t in 0..FRAMES {
        let frame = SCENE.frame(t);
        let textures = SCENE.upload(device, queue, &frame);
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
                &EstimateInputs::new(motion, depth, previous_depth),
            )
            .expect("estimate inputs");
        component
            .record_update(&mut encoder, &UpdateInputs::new(route2.value_texture()))
            .expect("update inputs");
        queue.submit([encoder.finish()]);
        let read_u32 =
            |t: &wgpu::Texture| -> Vec<u32> { read_texture(device, queue, t).expect("readback") };
        let read_history = |t: &wgpu::Texture| -> Vec<[u16; 4]> {
            let v: Vec<[f16; 4]> = read_texture(device, queue, t).expect("readback");
            v.iter().map(|x| x.map(f16::to_bits)).collect()
        };
        let counts = read_u32(route2.count_texture());
        if let Some((i, ours, theirs)) =
            first_difference(&counts, &read_u32(component.count_texture()))
        {
            panic!("{}: route 2 {ours}, component {theirs}", at(t, "counts", i));
        }
        if let Some((i, ours, theirs)) = first_difference(
            &read_u32(route2.link_texture()),
            &read_u32(component.link_texture()),
        ) {
            panic!("{}: route 2 {ours}, component {theirs}", at(t, "links", i));
        }
        let history = read_history(route2.history_texture());
        if let Some((i, ours, theirs)) =
            first_difference(&history, &read_history(component.history_texture()))
        {
            panic!(
                "{}: route 2 {ours:04x?}, component {theirs:04x?}",
                at(t, "history texels", i)
            );
        }

        let values: Vec<f32> =
            read_texture(device, queue, route2.value_texture()).expect("readback");
        let data = EstimateData::new(&frame.motion, &frame.depth, &previous.depth);
        let update = UpdateData::new(&values);
        assert_eq!(
            twin.estimate(&data).expect("twin estimate"),
            counts,
            "frame {t}: the twin's counts"
        );
        twin.update(&update).expect("twin update");
        let (config, twin_history) = (settings.config, twin.history());
        for (k, other) in others.iter_mut().enumerate() {
            let differ = (other.estimate(&data).expect("variant estimate").iter())
                .zip(&counts)
                .filter(|(a, b)| a != b)
                .count();
            other.update(&update).expect("variant update");
            seen.counts_differ[k] += differ;
            seen.histories_differ[k] += (other.history().iter().zip(twin_history))
                .filter(|(a, b)| a.map(f16::to_bits) != b.map(f16::to_bits))
                .count();
        }
        if t > 0 {
            seen.unlinked += twin.links().iter().filter(|&&l| l == 0).count();
            seen.at_max += counts
                .iter()
                .filter(|&&n| n == config.max_samples())
                .count();
            seen.above_min += counts.iter().filter(|&&n| n > config.min_samples()).count();
        }
        (previous, previous_textures) = (frame, Some(textures));
    }
    seen
}

/// The default settings, counts and histories equal; the twins without the border prior,
/// the footprint search, the spatial variance of young histories and (with a radius) the
/// neighbour prior must each differ somewhere, so the scene tests every rule the pass
/// carries.
#[test]
fn route2_equals_the_component_with_default_settings() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("route2_equals_the_component_with_default_settings").device()
    else {
        return;
    };
    for dilation in [0, 1] {
        let settings = AdaptiveSettings {
            dilation,
            ..AdaptiveSettings::default()
        };
        let without_spatial = (settings.config.to_builder())
            .spatial_variance(0)
            .build()
            .expect("valid config");
        let reprojection = settings.reprojection;
        let mut variants = vec![
            (
                "border prior",
                AdaptiveSettings {
                    reprojection: reprojection.with_border_prior(false),
                    ..settings
                },
            ),
            (
                "footprint search",
                AdaptiveSettings {
                    reprojection: reprojection.with_footprint_search(false),
                    ..settings
                },
            ),
            (
                "spatial variance",
                AdaptiveSettings {
                    config: without_spatial,
                    ..settings
                },
            ),
        ];
        if dilation > 0 {
            variants.push((
                "neighbour prior",
                AdaptiveSettings {
                    neighbour_prior: false,
                    ..settings
                },
            ));
        }
        let only: Vec<_> = variants.iter().map(|v| v.1).collect();
        let seen = run(&dev, settings, &only);
        eprintln!("route 2, dilation {dilation}: {FRAMES} frames equal; {seen:?}");
        for (k, (rule, _)) in variants.iter().enumerate() {
            eprintln!(
                "  without the {rule}: {} counts and {} history texels differ",
                seen.counts_differ[k], seen.histories_differ[k]
            );
        }
        // The scene must take every path, or the equality proves little.
        assert!(
            seen.unlinked > 100,
            "only {} pixel-frames without history",
            seen.unlinked
        );
        assert!(
            seen.at_max > 20,
            "only {} pixel-frames at beta_max",
            seen.at_max
        );
        assert!(
            seen.above_min > 500,
            "only {} pixel-frames above beta_min",
            seen.above_min
        );
        for (k, (rule, _)) in variants.iter().enumerate() {
            assert!(
                seen.counts_differ[k] > 0,
                "dilation {dilation}: the {rule} changes no count in this scene"
            );
        }
    }
}

/// Each switch of the reprojection rule off in turn (count dilation 1, the rest default):
/// the pass hands `ReprojectionRule::new(&rule)` to the library, the component its own
/// flags; counts, links and histories must still be equal, and each switch must change
/// the counts of this scene.
#[test]
fn route2_equals_the_component_under_each_reprojection_switch() {
    let Some(dev) =
        spvg_gpu_test::GpuTest::new("route2_equals_the_component_under_each_reprojection_switch")
            .device()
    else {
        return;
    };
    let default = AdaptiveSettings {
        dilation: 1,
        ..AdaptiveSettings::default()
    };
    let rule = Reprojection::default();
    for (switch, reprojection) in [
        ("border prior off", rule.with_border_prior(false)),
        (
            "border texel's count",
            rule.with_border_count(BorderCount::Texel),
        ),
        ("footprint search off", rule.with_footprint_search(false)),
    ] {
        let settings = AdaptiveSettings {
            reprojection,
            ..default
        };
        let seen = run(&dev, settings, &[default]);
        eprintln!(
            "route 2, {switch}: {FRAMES} frames equal; {} counts differ from the default rule's",
            seen.counts_differ[0]
        );
        assert!(
            seen.counts_differ[0] > 0,
            "{switch}: no count differs from the default rule's in this scene"
        );
    }
}
