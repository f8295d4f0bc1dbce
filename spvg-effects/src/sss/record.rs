//! What one frame of the subsurface pass records: the fixed count's `sss_fixed`, or the
//! adaptive models' `sss_gamma` -> `sss_sample_one_pass` (the component inside the
//! sampling: its one-pass form), or `sss_gamma` -> the component's estimate ->
//! `sss_sample` -> the component's update (its two-pass form), each pass with its own
//! timestamp pair.

use spvg_wgpu::adaptive::{AdaptivePass, EstimateInputs, Masks, UpdateInputs};

use crate::error::PassError;
use crate::gpu::{bind_group, dispatch_8x8, shader_module, view};
use crate::sss::tiles::SssTiles;
use crate::sss::{PassParams, sss_one_pass_source};

/// The fixed-count baseline: its entry point and the counts it writes.
#[derive(Debug)]
pub(super) struct Fixed {
    /// `sss_fixed`.
    pub(super) pipeline: wgpu::ComputePipeline,
    /// The counts of `sss_fixed` (also sampled: the budget reduction reads them).
    pub(super) count: wgpu::Texture,
}

/// What the adaptive models add to the pass: their two entry points and the textures they
/// exchange with the component, and the component itself.
#[derive(Debug)]
pub(super) struct Adaptive {
    pub(super) passes: AdaptivePasses,
    /// Built by the first [`SssPass::frame_params`](crate::sss::SssPass::frame_params)
    /// from its settings; later ones change its settings between frames.
    pub(super) component: Option<AdaptivePass>,
    /// `sss_sample_one_pass`, built for the component's control model at the first
    /// one-pass frame.
    pub(super) one_pass: Option<OnePass>,
}

/// The group of the component's bindings in the one-pass module: group 0 is the pass's
/// own, group 1 the tile lists' (`sss.wgsl`).
pub(crate) const ONE_PASS_GROUP: u32 = 2;

/// `sss_sample_one_pass` and its own group's layout (group 0; the component's is group
/// [`ONE_PASS_GROUP`]).
#[derive(Debug)]
pub(super) struct OnePass {
    pipeline: wgpu::ComputePipeline,
    own: wgpu::BindGroupLayout,
}

impl OnePass {
    pub(super) fn new(device: &wgpu::Device, component: &AdaptivePass) -> Self {
        let source = sss_one_pass_source(&component.one_pass_wgsl(ONE_PASS_GROUP));
        let module = shader_module(device, "sss_one_pass.wgsl", source);
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let texture = |sample_type| wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let float = texture(wgpu::TextureSampleType::Float { filterable: false });
        let own = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sss_sample_one_pass"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                entry(1, float),
                entry(2, float),
                entry(3, texture(wgpu::TextureSampleType::Uint)),
                entry(
                    4,
                    wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: wgpu::TextureFormat::Rgba16Float,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                ),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sss_sample_one_pass"),
            bind_group_layouts: &[Some(&own), None, Some(component.one_pass_layout())],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sss_sample_one_pass"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("sss_sample_one_pass"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        Self { pipeline, own }
    }

    /// Records `sss_sample_one_pass` (timestamp pair 1) with the component's group of the
    /// frame.
    pub(super) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        component: &wgpu::BindGroup,
        stamps: Option<&wgpu::QuerySet>,
    ) {
        let own = bind_group(
            f.device,
            Some("sss_sample_one_pass"),
            &self.own,
            &[(0, f.params)],
            &[
                (1, f.lighting.create_view(&Default::default())),
                (2, view(f.depth[0])),
                (3, view(f.mask[0])),
                (4, view(f.result)),
            ],
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("sss_sample_one_pass"),
            timestamp_writes: stamp(stamps, 1),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &own, &[]);
        pass.set_bind_group(ONE_PASS_GROUP, component, &[]);
        let [w, h] = f.size;
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }
}

/// The adaptive models' entry points and the textures they exchange with the component.
#[derive(Debug)]
pub(super) struct AdaptivePasses {
    pub(super) gamma_pipeline: wgpu::ComputePipeline,
    pub(super) sample_pipeline: wgpu::ComputePipeline,
    /// `sss_sample_classified`, for the component's count-classified dispatch.
    pub(super) sample_classified_pipeline: wgpu::ComputePipeline,
    /// Zero motion (`Rg16Float`): the subsurface scenes have a static camera.
    pub(super) motion: wgpu::Texture,
    /// The distant-energy ratio `sss_gamma` writes (`R32Float`).
    pub(super) gamma: wgpu::Texture,
    /// The monitored and control luminances `sss_sample` writes (`R32Float`).
    pub(super) value: wgpu::Texture,
    pub(super) control: wgpu::Texture,
    /// The TAA guide of a guided frame (`R32Float`, uploaded between the sampling and the
    /// update: [`SssPass::run_frame_guided`](crate::sss::SssPass::run_frame_guided)).
    pub(super) guide: wgpu::Texture,
}

/// The model's own entry points and state: a model is one or the other for the pass's
/// whole life, so a frame never meets a pass without its pipelines.
#[derive(Debug)]
pub(super) enum Kind {
    Fixed(Fixed),
    Adaptive(Box<Adaptive>),
}

/// The textures of one frame's passes: this frame's depth and mask and the previous
/// frame's, the result, the lighting, the uniform block.
pub(super) struct FrameTextures<'a> {
    pub(super) device: &'a wgpu::Device,
    pub(super) params: &'a wgpu::Buffer,
    pub(super) lighting: &'a wgpu::Texture,
    pub(super) depth: [&'a wgpu::Texture; 2],
    pub(super) mask: [&'a wgpu::Texture; 2],
    /// The mask the adaptive component controls the count under (this frame's and the
    /// previous): the subsurface mask, or its part inside the caller's sampling region.
    pub(super) count_mask: [&'a wgpu::Texture; 2],
    pub(super) result: &'a wgpu::Texture,
    pub(super) size: [u32; 2],
}

impl Fixed {
    /// Records `sss_fixed`.
    pub(super) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        stamps: Option<&wgpu::QuerySet>,
    ) {
        let views = [
            (1, f.lighting.create_view(&Default::default())),
            (2, view(f.depth[0])),
            (3, view(f.mask[0])),
            (4, view(f.result)),
            (5, view(&self.count)),
        ];
        let group = sss_group(f, &self.pipeline, &views);
        let stamp = stamp(stamps, 0);
        dispatch_8x8(encoder, "sss_fixed", &self.pipeline, &group, stamp, f.size);
    }
}

/// The component of a frame whose block is `p`: the frame's block must be the one
/// [`SssPass::frame_params`](crate::sss::SssPass::frame_params) built, whose controller is
/// the component's.
pub(super) fn component_for<'a>(
    slot: &'a mut Option<AdaptivePass>,
    p: &PassParams,
) -> Result<&'a mut AdaptivePass, PassError> {
    match slot {
        Some(a) if *a.params_block() == p.spvg => Ok(a),
        _ => Err(PassError::Param(spvg::Error::InconsistentParameters {
            names: "params.spvg",
            expected: "the block of this pass's frame_params (its component's controller)",
        })),
    }
}

impl AdaptivePasses {
    /// Records `sss_gamma`, the component's estimate, `sss_sample` and the component's
    /// update, each with its timestamp pair: over the whole frame, or over the listed
    /// tiles of `tiles`.
    pub(super) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        component: &mut AdaptivePass,
        stamps: Option<&wgpu::QuerySet>,
        tiles: Option<&SssTiles>,
    ) -> Result<(), PassError> {
        self.record_sampling(encoder, f, component, stamps, tiles)?;
        self.record_update(encoder, component, None, stamps, tiles)
    }

    /// Records `sss_gamma`, the component's estimate and `sss_sample` (timestamp pairs 0
    /// to 2): everything before the update.
    pub(super) fn record_sampling(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        component: &mut AdaptivePass,
        stamps: Option<&wgpu::QuerySet>,
        tiles: Option<&SssTiles>,
    ) -> Result<(), PassError> {
        self.record_estimate(encoder, f, component, stamps, tiles)?;
        self.record_sample(encoder, f, component, stamps, tiles)
    }

    /// `sss_gamma` and the component's estimate (timestamp pairs 0 and 1).
    pub(super) fn record_estimate(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        component: &mut AdaptivePass,
        stamps: Option<&wgpu::QuerySet>,
        tiles: Option<&SssTiles>,
    ) -> Result<(), PassError> {
        self.record_gamma(encoder, f, stamps, tiles);
        let inputs = self.estimate_inputs(f);
        match tiles {
            Some(t) => component.record_estimate_tiles(encoder, &inputs, &t.list, stamp(stamps, 1)),
            None => component.record_estimate_timed(encoder, &inputs, stamp(stamps, 1)),
        }?;
        Ok(())
    }

    /// `sss_gamma` (timestamp pair 0): the distant-energy ratio the component's estimate
    /// reads.
    pub(super) fn record_gamma(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        stamps: Option<&wgpu::QuerySet>,
        tiles: Option<&SssTiles>,
    ) {
        let views = [(2, view(f.depth[0])), (7, view(&self.gamma))];
        let gamma = tiles.map_or(&self.gamma_pipeline, |t| &t.gamma);
        let group = sss_group(f, gamma, &views);
        match tiles {
            Some(t) => t
                .list
                .dispatch(encoder, "sss_gamma_tiles", gamma, &group, stamp(stamps, 0)),
            None => dispatch_8x8(
                encoder,
                "sss_gamma",
                gamma,
                &group,
                stamp(stamps, 0),
                f.size,
            ),
        }
    }

    /// The component's estimate inputs of the frame: zero motion (a static camera), this
    /// frame's and the previous frame's depth and count mask, the distant-energy ratio.
    pub(super) fn estimate_inputs<'a>(&'a self, f: &FrameTextures<'a>) -> EstimateInputs<'a> {
        EstimateInputs::new(&self.motion, f.depth[0], f.depth[1])
            .with_masks(Some(Masks {
                current: f.count_mask[0],
                previous: f.count_mask[1],
            }))
            .with_gamma(Some(&self.gamma))
    }

    /// `sss_sample` (timestamp pair 2): over the listed tiles of `tiles`, else once per
    /// class of tiles with the component's count-classified dispatch on, else over the
    /// frame.
    pub(super) fn record_sample(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameTextures<'_>,
        component: &AdaptivePass,
        stamps: Option<&wgpu::QuerySet>,
        tiles: Option<&SssTiles>,
    ) -> Result<(), PassError> {
        let views = [
            (1, f.lighting.create_view(&Default::default())),
            (2, view(f.depth[0])),
            (3, view(f.mask[0])),
            (4, view(f.result)),
            (6, view(component.count_texture())),
            (8, view(&self.value)),
            (9, view(&self.control)),
        ];
        let classified = tiles.is_none() && component.settings().classified_dispatch;
        let sample = match tiles {
            Some(t) => &t.sample,
            None if classified => &self.sample_classified_pipeline,
            None => &self.sample_pipeline,
        };
        let group = sss_group(f, sample, &views);
        match tiles {
            Some(t) => t.list.dispatch(
                encoder,
                "sss_sample_tiles",
                sample,
                &group,
                stamp(stamps, 2),
            ),
            None if classified => component.dispatch_classified(
                encoder,
                "sss_sample_classified",
                sample,
                &group,
                stamp(stamps, 2),
            )?,
            None => dispatch_8x8(
                encoder,
                "sss_sample",
                sample,
                &group,
                stamp(stamps, 2),
                f.size,
            ),
        }
        Ok(())
    }

    /// Records the component's update (timestamp pair 3), with `guide` as its TAA guide.
    pub(super) fn record_update(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        component: &mut AdaptivePass,
        guide: Option<&wgpu::Texture>,
        stamps: Option<&wgpu::QuerySet>,
        tiles: Option<&SssTiles>,
    ) -> Result<(), PassError> {
        let control = component
            .settings()
            .control
            .needs_control()
            .then_some(&self.control);
        let inputs = UpdateInputs::new(&self.value)
            .with_control(control)
            .with_guide(guide);
        match tiles {
            Some(t) => component.record_update_tiles(encoder, &inputs, &t.list, stamp(stamps, 3)),
            None => component.record_update_timed(encoder, &inputs, stamp(stamps, 3)),
        }?;
        Ok(())
    }
}

/// The timestamp writes of pass `k` of a frame: its own begin/end pair.
fn stamp(set: Option<&wgpu::QuerySet>, k: u32) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
    set.map(|query_set| wgpu::ComputePassTimestampWrites {
        query_set,
        beginning_of_pass_write_index: Some(2 * k),
        end_of_pass_write_index: Some(2 * k + 1),
    })
}

/// The bind group of one `sss.wgsl` entry point (its layout holds only the bindings it
/// uses): the uniform block at 0 and `views`.
fn sss_group(
    f: &FrameTextures<'_>,
    pipeline: &wgpu::ComputePipeline,
    views: &[(u32, wgpu::TextureView)],
) -> wgpu::BindGroup {
    let layout = pipeline.get_bind_group_layout(0);
    bind_group(f.device, Some("sss"), &layout, &[(0, f.params)], views)
}
