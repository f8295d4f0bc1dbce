//! The one-pass form of the component (`AdaptivePass::one_pass_wgsl`, `one_pass_group`):
//! a renderer's own compute shader, written here as an outsider would, joins the module,
//! calls `spvg_one_pass_begin` and `spvg_one_pass_end` around its "sampling" (it reads the
//! moving scene's value and control), and must give the twin's counts and histories bit
//! for bit on every frame: each control model, the count dilation with the neighbour
//! prior at radii 1, 2 and the largest (the halo of workgroup memory), fractional counts,
//! the young-history rules, the TAA guide, and the two forms alternating frame by frame on
//! one component.

mod common;

use common::scene::{Frame, MovingScene, Textures, data, textures};
use half::f16;
use spvg::SpvgConfig;
use spvg::cv::Ocv;
use spvg_gpu_test::GpuDevice;
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveSettings, AdaptiveTwin, Control, EstimateInputs, Masks,
    UpdateData, UpdateInputs,
};
use spvg_wgpu::util::read_texture;

/// The group the test's shader gives the component (its own bindings are group 0).
const GROUP: u32 = 1;

/// The renderer's entry point: its value and control per pixel come from textures (the
/// scene's), its guide too; it takes no samples of its own, so the counts it is given
/// decide only whether it reports a value, as a renderer's loop would.
const CONSUMER: &str = r"
@group(0) @binding(0) var value_in: texture_2d<f32>;
@group(0) @binding(1) var control_in: texture_2d<f32>;
@group(0) @binding(2) var guide_in: texture_2d<f32>;
@group(0) @binding(3) var<uniform> guided: vec4<u32>;
@group(0) @binding(4) var moment_in: texture_2d<f32>;

@compute @workgroup_size(8, 8, 1)
fn sample(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(local_invocation_id) lid: vec3<u32>) {
    let s = spvg_one_pass_begin(gid, lid);
    var value = 0.0;
    var control = 0.0;
    var guide = 0.0;
    var moment = 0.0;
    if (s.inside) {
        value = textureLoad(value_in, s.pixel, 0).x;
        control = textureLoad(control_in, s.pixel, 0).x;
        guide = textureLoad(guide_in, s.pixel, 0).x;
        moment = textureLoad(moment_in, s.pixel, 0).x;
    }
    if (guided.x == 2u) {
        spvg_one_pass_end_moment(s, value, control, guide, moment);
    } else if (guided.x != 0u) {
        spvg_one_pass_end_guided(s, value, control, guide);
    } else {
        spvg_one_pass_end(s, value, control);
    }
}
";

fn config() -> SpvgConfig<f32> {
    SpvgConfig::builder()
        .target_variance(1e-3)
        .kappa(0.5)
        .age_weight(true)
        .spatial_variance(2)
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

/// How the frames of a run are recorded.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Form {
    OnePass,
    /// Even frames in the two-pass form, odd frames in one pass.
    Alternating,
}

/// The renderer: its pipeline (group 0 its own, group `GROUP` the component's) and its
/// group-0 layout.
struct Renderer {
    pipeline: wgpu::ComputePipeline,
    own: wgpu::BindGroupLayout,
    size: [u32; 2],
}

impl Renderer {
    fn new(dev: &GpuDevice, pass: &AdaptivePass) -> Self {
        let source = format!(
            "{}{}{CONSUMER}",
            spvg_shaders::WGSL,
            pass.one_pass_wgsl(GROUP)
        );
        let module = dev
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("one-pass consumer"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
        let texture = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Float { filterable: false },
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let own = dev
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("consumer"),
                entries: &[
                    texture(0),
                    texture(1),
                    texture(2),
                    texture(4),
                    wgpu::BindGroupLayoutEntry {
                        binding: 3,
                        visibility: wgpu::ShaderStages::COMPUTE,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: false,
                            min_binding_size: None,
                        },
                        count: None,
                    },
                ],
            });
        let layout = dev
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("one-pass consumer"),
                bind_group_layouts: &[Some(&own), Some(pass.one_pass_layout())],
                immediate_size: 0,
            });
        let pipeline = dev
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("one-pass consumer"),
                layout: Some(&layout),
                module: &module,
                entry_point: Some("sample"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            });
        Self {
            pipeline,
            own,
            size: pass.size(),
        }
    }

    /// Records one frame of the consumer with the component's group `adaptive`.
    #[allow(
        clippy::too_many_arguments,
        reason = "the consumer's inputs and the component's group"
    )]
    fn record(
        &self,
        dev: &GpuDevice,
        enc: &mut wgpu::CommandEncoder,
        tex: &Textures,
        guide: &wgpu::Texture,
        mode: u32,
        moment: &wgpu::Texture,
        adaptive: &wgpu::BindGroup,
    ) {
        use wgpu::util::DeviceExt as _;
        let flag = dev
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("guided"),
                contents: bytemuck::bytes_of(&[mode, 0, 0, 0]),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let (value, control, guide) = (view(&tex.value), view(&tex.control), view(guide));
        let moment = view(moment);
        let own = dev.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("consumer"),
            layout: &self.own,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&value),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&control),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&guide),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: flag.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&moment),
                },
            ],
        });
        let mut cpass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("one-pass consumer"),
            timestamp_writes: None,
        });
        cpass.set_pipeline(&self.pipeline);
        cpass.set_bind_group(0, &own, &[]);
        cpass.set_bind_group(GROUP, adaptive, &[]);
        let [w, h] = self.size;
        cpass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
}

/// The renderer's TAA guide of frame `t`: a smooth field near the values, NaN on every
/// eleventh pixel (where the resolve has no history).
fn guide_of(f: &Frame, t: u32) -> Vec<f32> {
    f.value
        .iter()
        .enumerate()
        .map(|(i, v)| {
            if (i as u32 + t).is_multiple_of(11) {
                f32::NAN
            } else {
                0.9 * v + 0.05
            }
        })
        .collect()
}

/// The samples' second moment of frame `t` (docs/algorithms.md §8.8): the value squared
/// plus a spread that varies by pixel and frame, NaN (none) on every thirteenth pixel.
fn moment_of(f: &Frame, t: u32) -> Vec<f32> {
    f.value
        .iter()
        .enumerate()
        .map(|(i, v)| {
            if (i as u32 + 3 * t).is_multiple_of(13) {
                f32::NAN
            } else {
                v * v + 0.002 * ((i as u32 + t) % 9) as f32
            }
        })
        .collect()
}

/// Runs the moving scene for `frames` frames in `form` under `settings` on the GPU and on
/// the twin, and requires the same counts, history texels and CV history texels on every
/// frame. Returns the pixel-frames whose dilated count differs from the estimate's (the
/// halo at work), and those the prior raised.
fn run(
    dev: &GpuDevice,
    settings: AdaptiveSettings,
    form: Form,
    guided: bool,
    frames: u32,
) -> usize {
    run_moment(dev, settings, form, guided, false, frames)
}

/// [`run`] with the samples' second moment where `with_moment` (`moment_of`; the one-pass
/// form's `spvg_one_pass_end_moment`, the split form's `record_update_with_moment`, the
/// twin's `update_with_moment`, all with the guide).
fn run_moment(
    dev: &GpuDevice,
    settings: AdaptiveSettings,
    form: Form,
    guided: bool,
    with_moment: bool,
    frames: u32,
) -> usize {
    let (w, h) = (45, 26); // not multiples of the 8x8 workgroup
    let scene = MovingScene { w, h };
    let mut gpu = AdaptivePass::new(&dev.device, settings, w, h).expect("gpu pass");
    gpu.set_one_pass_counts(true);
    let mut twin = AdaptiveTwin::new(settings, w, h).expect("twin");
    // The same twin without the dilation: where the counts differ, the tile's halo in
    // workgroup memory decided them.
    let mut undilated = AdaptiveTwin::new(
        AdaptiveSettings {
            dilation: 0,
            ..settings
        },
        w,
        h,
    )
    .expect("twin");
    let renderer = Renderer::new(dev, &gpu);
    let (mut prev, mut prev_tex) = (scene.frame(0), None::<Textures>);
    let mut dilated = 0;
    let name = settings.control.name();
    for t in 0..frames {
        let cur = scene.frame(t);
        let tex = textures(dev, &cur, w, h);
        let guide = guide_of(&cur, t);
        let guide_tex = common::upload(dev, wgpu::TextureFormat::R32Float, [w, h], &guide);
        let moment = moment_of(&cur, t);
        let moment_tex = common::upload(dev, wgpu::TextureFormat::R32Float, [w, h], &moment);
        let mode = if with_moment { 2 } else { u32::from(guided) };
        let guided = guided || with_moment;
        let ptex = prev_tex.as_ref().unwrap_or(&tex);
        let inputs = EstimateInputs::new(&tex.motion, &tex.depth, &ptex.depth)
            .with_masks(Some(Masks {
                current: &tex.mask,
                previous: &ptex.mask,
            }))
            .with_gamma(Some(&tex.gamma))
            .with_resolve_weight(Some(&tex.resolve));
        let mut enc = dev.device.create_command_encoder(&Default::default());
        if form == Form::Alternating && t % 2 == 0 {
            gpu.record_estimate(&mut enc, &inputs).expect("estimate");
            let update = UpdateInputs::new(&tex.value)
                .with_control(Some(&tex.control))
                .with_guide(guided.then_some(&guide_tex));
            if with_moment {
                gpu.record_update_with_moment(&mut enc, &update, &moment_tex)
            } else {
                gpu.record_update(&mut enc, &update)
            }
            .expect("update");
        } else {
            let group = gpu.one_pass_group(&inputs).expect("one-pass inputs");
            renderer.record(dev, &mut enc, &tex, &guide_tex, mode, &moment_tex, &group);
        }
        dev.queue.submit([enc.finish()]);
        let count_gpu: Vec<u32> =
            read_texture(&dev.device, &dev.queue, gpu.count_texture()).expect("readback");
        let hist_gpu: Vec<[f16; 4]> =
            read_texture(&dev.device, &dev.queue, gpu.history_texture()).expect("readback");
        let count_cpu = twin.estimate(&data(&cur, &prev)).expect("twin").to_vec();
        let plain = undilated
            .estimate(&data(&cur, &prev))
            .expect("twin")
            .to_vec();
        dilated += count_cpu.iter().zip(&plain).filter(|(a, b)| a != b).count();
        let update = UpdateData::new(&cur.value)
            .with_control(Some(&cur.control))
            .with_guide(guided.then_some(&guide[..]));
        if with_moment {
            twin.update_with_moment(&update, &moment).expect("twin");
            undilated
                .update_with_moment(&update, &moment)
                .expect("twin");
        } else {
            twin.update(&update).expect("twin");
            undilated.update(&update).expect("twin");
        }
        let differ = count_gpu
            .iter()
            .zip(&count_cpu)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differ, 0,
            "{name} {form:?} frame {t}: {differ} counts differ"
        );
        let differ = common::bits(&hist_gpu)
            .iter()
            .zip(common::bits(twin.history()))
            .filter(|(a, b)| **a != *b)
            .count();
        assert_eq!(
            differ, 0,
            "{name} {form:?} frame {t}: {differ} history texels differ"
        );
        if let Some(cv) = gpu.cv_history_texture() {
            let cv_gpu: Vec<[f16; 4]> =
                read_texture(&dev.device, &dev.queue, cv).expect("readback");
            let cv_cpu = twin.cv_history().expect("OCV twin has a CV history");
            assert_eq!(
                common::bits(&cv_gpu),
                common::bits(cv_cpu),
                "{name} {form:?} frame {t}: CV history"
            );
        }
        (prev, prev_tex) = (cur, Some(tex));
    }
    dilated
}

fn device(name: &str) -> Option<GpuDevice> {
    spvg_gpu_test::GpuTest::new(name).device()
}

/// The one-pass form on a device that holds WebGPU's default limits (four storage
/// textures per stage): OCV with its counts stored (the count, the history and the CV
/// history: three storage textures) and the TAA guide, equal to the twin on every frame.
#[test]
fn one_pass_runs_under_webgpu_default_limits() {
    let Some(dev) = spvg_gpu_test::GpuTest::new("one_pass_runs_under_webgpu_default_limits")
        .limits(wgpu::Limits::default())
        .device()
    else {
        return;
    };
    assert_eq!(dev.device.limits().max_storage_textures_per_shader_stage, 4);
    let ocv = controls()[2];
    assert!(
        matches!(ocv, Control::Ocv(_)),
        "OCV: three storage textures"
    );
    let settings = AdaptiveSettings {
        config: config(),
        control: ocv,
        dilation: 1,
        ..AdaptiveSettings::default()
    };
    let dilated = run(&dev, settings, Form::OnePass, true, 8);
    assert!(dilated > 100, "the dilation acted on {dilated} counts");
}

/// Each control model with the young-history rules, without a dilation radius (no halo)
/// and with radius 1 and the neighbour prior (a halo of four pixels): the one-pass form
/// equals the twin on every frame, and with the radius the halo's estimates changed
/// counts.
#[test]
fn one_pass_equals_the_twin_for_each_model() {
    let Some(dev) = device("one_pass_equals_the_twin_for_each_model") else {
        return;
    };
    for control in controls() {
        for dilation in [0, 1] {
            let settings = AdaptiveSettings {
                config: config(),
                control,
                dilation,
                ..AdaptiveSettings::default()
            };
            let dilated = run(&dev, settings, Form::OnePass, false, 12);
            eprintln!(
                "{} radius {dilation}: {dilated} counts set by the dilation",
                control.name()
            );
            if dilation > 0 {
                assert!(dilated > 200, "the dilation acted on {dilated} counts");
            }
        }
    }
}

/// The halo at radius 2 and at the largest radius (8: a 24 x 24 region of workgroup
/// memory for an 8 x 8 tile), with the neighbour prior: equal to the twin.
#[test]
fn one_pass_equals_the_twin_with_wide_halos() {
    let Some(dev) = device("one_pass_equals_the_twin_with_wide_halos") else {
        return;
    };
    for dilation in [2, spvg::dilation::MAX_RADIUS] {
        let settings = AdaptiveSettings {
            config: config(),
            dilation,
            ..AdaptiveSettings::default()
        };
        let dilated = run(&dev, settings, Form::OnePass, false, 8);
        assert!(dilated > 200, "radius {dilation}: {dilated} dilated counts");
    }
}

/// Fractional counts (floor 0.25) with the dilation and the prior, and the TAA guide
/// (NaN on every eleventh pixel), each model, without and with the resolved-image rule
/// (steady weight 0.1, the weight from each history's age): equal to the twin.
#[test]
fn one_pass_equals_the_twin_with_fractional_counts_and_the_guide() {
    let Some(dev) = device("one_pass_equals_the_twin_with_fractional_counts_and_the_guide") else {
        return;
    };
    for resolve in [None, Some(0.1)] {
        let fractional = config()
            .to_builder()
            .fractional_floor(Some(0.25))
            .resolve_weight(resolve)
            .build()
            .expect("valid config");
        for control in controls() {
            let settings = AdaptiveSettings {
                config: fractional,
                control,
                dilation: 1,
                ..AdaptiveSettings::default()
            };
            run(&dev, settings, Form::OnePass, true, 12);
        }
    }
}

/// The two forms on one component, alternating frame by frame (two-pass on even frames,
/// one pass on odd ones), with the guide: the histories one form writes are the ones the
/// other continues, and every frame equals the twin.
#[test]
fn the_two_forms_alternate_on_one_component() {
    let Some(dev) = device("the_two_forms_alternate_on_one_component") else {
        return;
    };
    for control in controls() {
        let settings = AdaptiveSettings {
            config: config(),
            control,
            dilation: 1,
            ..AdaptiveSettings::default()
        };
        run(&dev, settings, Form::Alternating, true, 12);
    }
}

/// Nothing goes to memory but the histories unless asked: with the count store off, the
/// count texture keeps what the last two-pass estimate wrote; a one-pass frame between a
/// two-pass frame's estimate and its update is refused by name and changes nothing; a
/// wrong input is named.
#[test]
fn one_pass_writes_counts_only_when_asked_and_refuses_between_steps() {
    let Some(dev) = device("one_pass_writes_counts_only_when_asked_and_refuses_between_steps")
    else {
        return;
    };
    let (w, h) = (45, 26);
    let scene = MovingScene { w, h };
    let f = scene.frame(3);
    let tex = textures(&dev, &f, w, h);
    let inputs = EstimateInputs::new(&tex.motion, &tex.depth, &tex.depth);
    let mut gpu =
        AdaptivePass::new(&dev.device, AdaptiveSettings::default(), w, h).expect("gpu pass");
    let renderer = Renderer::new(&dev, &gpu);
    let guide = common::upload(
        &dev,
        wgpu::TextureFormat::R32Float,
        [w, h],
        &vec![0.0_f32; (w * h) as usize],
    );
    // A first frame seeds the histories; the second decides counts above the minimum.
    for _ in 0..2 {
        let mut enc = dev.device.create_command_encoder(&Default::default());
        let group = gpu.one_pass_group(&inputs).expect("inputs");
        renderer.record(&dev, &mut enc, &tex, &guide, 0, &guide, &group);
        dev.queue.submit([enc.finish()]);
    }
    let counts: Vec<u32> =
        read_texture(&dev.device, &dev.queue, gpu.count_texture()).expect("readback");
    assert!(
        counts.iter().all(|&n| n == 0),
        "the count texture is untouched without set_one_pass_counts"
    );
    let history: Vec<[f16; 4]> =
        read_texture(&dev.device, &dev.queue, gpu.history_texture()).expect("readback");
    assert!(
        history.iter().all(|t| t[3].to_f32() >= 1.0),
        "every pixel's history was written"
    );
    let mut enc = dev.device.create_command_encoder(&Default::default());
    gpu.record_estimate(&mut enc, &inputs).expect("estimate");
    assert_eq!(
        gpu.one_pass_group(&inputs).err(),
        Some(AdaptiveError::OnePassBetweenSteps)
    );
    gpu.record_update(&mut enc, &UpdateInputs::new(&tex.value))
        .expect("the two-pass frame goes on");
    dev.queue.submit([enc.finish()]);
    let wrong = common::upload(
        &dev,
        wgpu::TextureFormat::R32Float,
        [w + 1, h],
        &vec![0.0_f32; ((w + 1) * h) as usize],
    );
    let err = gpu
        .one_pass_group(&{
            let mut i = inputs;
            i.depth = &wrong;
            i
        })
        .err();
    assert!(
        matches!(err, Some(AdaptiveError::TextureSize { input: "depth", .. })),
        "{err:?}"
    );
}

/// The samples' second moment (docs/algorithms.md §8.8) in both forms, with the guide,
/// under the integer rule and fractional counts with the resolved-image rule, each model
/// (CCV and OCV ignore it), one pass and alternating with the split form: equal to the
/// twin's `update_with_moment`.
#[test]
fn one_pass_equals_the_twin_with_the_second_moment() {
    let Some(dev) = device("one_pass_equals_the_twin_with_the_second_moment") else {
        return;
    };
    let fractional = config()
        .to_builder()
        .fractional_floor(Some(0.25))
        .resolve_weight(Some(0.1))
        .build()
        .expect("valid config");
    for (config, form) in [
        (config(), Form::OnePass),
        (fractional, Form::OnePass),
        (config(), Form::Alternating),
    ] {
        for control in controls() {
            let settings = AdaptiveSettings {
                config,
                control,
                dilation: 1,
                ..AdaptiveSettings::default()
            };
            run_moment(&dev, settings, form, true, true, 10);
        }
    }
}
