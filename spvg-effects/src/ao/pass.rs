//! The AO renderer on a wgpu device ([`AoPass`]): G-buffer, then the AO sampling with the
//! adaptive component inside it (its one-pass form), or around it (its two-pass form), one
//! command encoder per frame.

use wgpu::TextureFormat as Tf;
use wgpu::TextureUsages as Tu;
use wgpu::util::DeviceExt as _;

use super::{AoParams, ONE_PASS_GROUP, ao_one_pass_source, ao_source};
use spvg_wgpu::adaptive::{
    AdaptiveError, AdaptivePass, AdaptiveSettings, Control, EstimateInputs, UpdateInputs,
};

use crate::gpu::{
    bind_group, compute_pipeline, dispatch_8x8, read_texture, shader_module, texture_2d as texture,
    texture_2d_desc, view, write_scalar,
};

/// The renderer's TAA guide of a guided frame ([`AoPass::run_frame_guided`],
/// [`AoTwin::run_frame_guided`](super::AoTwin::run_frame_guided)): called after the
/// sampling with the frame's AO values (the monitored value itself), it returns the guide
/// `C_t` per pixel, the renderer's TAA history reprojected and clamped against this frame
/// before its blend (docs/algorithms.md §8.5); NaN where the resolve has no history.
pub type AoGuide<'a> = dyn FnMut(&[f32]) -> Vec<f32> + 'a;

/// How the AO renderer chooses its counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AoMode {
    /// The same count everywhere (baseline; no history).
    Fixed(u32),
    /// The adaptive component (AS) with reprojection along the G-buffer's motion vectors.
    Adaptive,
    /// The adaptive component with the identity history: zero motion vectors and no depth
    /// test (what a renderer without reprojection does).
    Identity,
}

impl AoMode {
    /// Short name (`fixed64`, `as`, `as-identity`).
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            Self::Fixed(n) => format!("fixed{n}"),
            Self::Adaptive => "as".into(),
            Self::Identity => "as-identity".into(),
        }
    }
}

/// One rendered frame, read back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AoFrame {
    /// Samples per pixel.
    pub count: Vec<u32>,
    /// The AO estimate per pixel.
    pub value: Vec<f32>,
    /// Per pixel, the estimates of its first `prefixes[j]` samples in channel `j` (0 where
    /// `prefixes[j]` is 0 or above the pixel's count): empty unless prefix counts are set
    /// ([`AoPass::set_prefix_counts`]).
    pub prefixes: Vec<[f32; 4]>,
}

/// `ao_sample_one_pass`, the sampling pass with the component inside it (its one-pass
/// form), and its own group's layout (group 0; the component's is group
/// [`ONE_PASS_GROUP`]).
#[derive(Debug)]
struct OnePass {
    pipeline: wgpu::ComputePipeline,
    own: wgpu::BindGroupLayout,
}

impl OnePass {
    fn new(device: &wgpu::Device, adaptive: &AdaptivePass) -> Self {
        let source = ao_one_pass_source(&adaptive.one_pass_wgsl(ONE_PASS_GROUP));
        let module = shader_module(device, "ao_one_pass.wgsl", source);
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty,
            count: None,
        };
        let texture = wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let storage = |format| wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        };
        let own = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ao_sample_one_pass"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                entry(6, texture),
                entry(7, texture),
                entry(8, storage(Tf::R32Float)),
                entry(10, storage(Tf::Rgba32Float)),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("ao_sample_one_pass"),
            bind_group_layouts: &[Some(&own), Some(adaptive.one_pass_layout())],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("ao_sample_one_pass"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("ao_sample_one_pass"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        Self { pipeline, own }
    }
}

/// The AO renderer: G-buffer pass, then the AO sampling with [`AdaptivePass`] inside it
/// (one pass) or around it (two passes), or at a fixed count.
#[derive(Debug)]
pub struct AoPass {
    device: wgpu::Device,
    queue: wgpu::Queue,
    width: u32,
    height: u32,
    mode: AoMode,
    gbuffer: wgpu::ComputePipeline,
    sample: wgpu::ComputePipeline,
    /// `ao_sample_classified`, for the component's count-classified dispatch.
    sample_classified: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    /// Ping-pong: this frame's and the previous frame's depth.
    depth: [wgpu::Texture; 2],
    /// This frame's surface points' depths as the previous camera saw them.
    reprojected_depth: wgpu::Texture,
    /// Whether the component's depth test compares the reprojected depth.
    use_reprojected_depth: bool,
    motion: wgpu::Texture,
    zero_motion: wgpu::Texture,
    position: wgpu::Texture,
    normal: wgpu::Texture,
    value: wgpu::Texture,
    /// The estimates of the first `prefixes` samples (`AoFrame::prefixes`).
    prefix: wgpu::Texture,
    prefixes: [u32; 4],
    /// The TAA guide of a guided frame, uploaded between the sampling and the update.
    guide: wgpu::Texture,
    /// The renderer's resolve weight ([`AoPass::set_resolve_weight`]), uploaded when set.
    resolve_weight: wgpu::Texture,
    /// Whether the estimate reads [`AoPass::set_resolve_weight`]'s texture.
    use_resolve_weight: bool,
    fixed: wgpu::Texture,
    adaptive: Option<AdaptivePass>,
    /// The one-pass form's pipeline (adaptive modes only).
    one_pass: Option<OnePass>,
    /// Whether the adaptive modes run their frames in one pass where they can
    /// ([`AoPass::set_one_pass`]).
    use_one_pass: bool,
    /// Whether the update takes the rays' second moment ([`AoPass::set_second_moment`]).
    use_second_moment: bool,
    cur: usize,
    /// The last frame's time ([`AoPass::last_frame_ms`]).
    last_ms: f64,
}

impl AoPass {
    /// Builds the renderer for a `width x height` frame; an adaptive mode runs the
    /// component with `settings` (a fixed count ignores them).
    ///
    /// # Errors
    ///
    /// As [`AdaptivePass::new`]; [`AdaptiveError::MissingInput`] naming `control` for a
    /// control model other than AS (the effect has no control value: it monitors its AO
    /// estimate).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        width: u32,
        height: u32,
        mode: AoMode,
        settings: AdaptiveSettings,
    ) -> Result<Self, AdaptiveError> {
        let adaptive = match mode {
            AoMode::Fixed(_) => None,
            AoMode::Adaptive | AoMode::Identity => {
                check_control(&settings)?;
                let mut a = AdaptivePass::new(device, settings, width, height)?;
                // Every frame's counts are read back (`AoFrame::count`).
                a.set_one_pass_counts(true);
                Some(a)
            }
        };
        let one_pass = adaptive.as_ref().map(|a| OnePass::new(device, a));
        let module = shader_module(device, "ao.wgsl", ao_source());
        let pipeline = |entry: &str| compute_pipeline(device, &module, entry, None);
        let size = [width, height];
        let rw = Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING | Tu::COPY_SRC;
        let fixed_count = match mode {
            AoMode::Fixed(n) => n,
            _ => 0,
        };
        let n = (width * height) as usize;
        let fixed = device.create_texture_with_data(
            queue,
            &texture_2d_desc(
                "fixed count",
                Tf::R32Uint,
                size,
                Tu::TEXTURE_BINDING | Tu::COPY_SRC,
            ),
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(&vec![fixed_count; n]),
        );
        Ok(Self {
            gbuffer: pipeline("ao_gbuffer"),
            sample: pipeline("ao_sample"),
            sample_classified: pipeline("ao_sample_classified"),
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("AoParams"),
                size: size_of::<AoParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            depth: [
                texture(device, "depth a", Tf::R32Float, size, rw),
                texture(device, "depth b", Tf::R32Float, size, rw),
            ],
            reprojected_depth: texture(device, "reprojected depth", Tf::R32Float, size, rw),
            use_reprojected_depth: true,
            motion: texture(device, "motion", Tf::Rg32Float, size, rw),
            zero_motion: texture(
                device,
                "zero motion",
                Tf::Rg32Float,
                size,
                Tu::TEXTURE_BINDING,
            ),
            position: texture(device, "position", Tf::Rgba32Float, size, rw),
            normal: texture(device, "normal", Tf::Rgba32Float, size, rw),
            value: texture(device, "ao value", Tf::R32Float, size, rw),
            prefix: texture(device, "ao prefix values", Tf::Rgba32Float, size, rw),
            prefixes: [0; 4],
            guide: texture(
                device,
                "taa guide",
                Tf::R32Float,
                size,
                Tu::TEXTURE_BINDING | Tu::COPY_DST,
            ),
            resolve_weight: texture(
                device,
                "resolve weight",
                Tf::R32Float,
                size,
                Tu::TEXTURE_BINDING | Tu::COPY_DST,
            ),
            use_resolve_weight: false,
            fixed,
            adaptive,
            one_pass,
            use_one_pass: false,
            device: device.clone(),
            queue: queue.clone(),
            width,
            height,
            mode,
            use_second_moment: false,
            cur: 0,
            last_ms: 0.0,
        })
    }

    fn bind(
        &self,
        pipeline: &wgpu::ComputePipeline,
        views: &[(u32, wgpu::TextureView)],
    ) -> wgpu::BindGroup {
        bind_group(
            &self.device,
            None,
            &pipeline.get_bind_group_layout(0),
            &[(0, &self.params)],
            views,
        )
    }

    /// The adaptive component (`None` for a fixed count): its settings, and its count,
    /// history and link textures after a frame.
    #[must_use]
    pub fn adaptive(&self) -> Option<&AdaptivePass> {
        self.adaptive.as_ref()
    }

    /// The adaptive component to change its settings between frames
    /// ([`AdaptivePass::set_settings`]); `None` for a fixed count.
    #[must_use]
    pub fn adaptive_mut(&mut self) -> Option<&mut AdaptivePass> {
        self.adaptive.as_mut()
    }

    /// Whether the adaptive component's depth test compares the reprojected depth the
    /// G-buffer writes (each pixel's surface point as the previous camera saw it:
    /// `EstimateInputs::reprojected_depth`; on by default) or this frame's depth (off: a
    /// renderer that does not compute it; a dolly then drops its histories). The identity
    /// history ([`AoMode::Identity`]) never passes it.
    pub fn set_reprojected_depth(&mut self, on: bool) {
        self.use_reprojected_depth = on;
    }

    /// Whether the adaptive modes run a frame in the component's one-pass form: the
    /// estimate, the rays and the update in one dispatch (`ao_sample_one_pass`). Off by
    /// default: on software Vulkan the two-pass form measured no slower (BENCHMARKS.md,
    /// the component's cost), as its barriers are costly there. Off, or for a frame one pass cannot serve (the
    /// count-classified dispatch, which needs the counts before the sampling dispatch; a
    /// guided frame, whose guide is computed after the sampling), they run the two-pass
    /// form: the component's estimate, `ao_sample`, the component's update. Both give the
    /// same counts, values and histories.
    pub fn set_one_pass(&mut self, on: bool) {
        self.use_one_pass = on;
    }

    /// Whether the adaptive modes hand the component the rays' second moment
    /// (`AdaptivePass::record_update_with_moment`, docs/algorithms.md §8.8), so that the
    /// count follows the per-sample variance and not the temporal variance of the pixel's
    /// mean (sub-pixel jitter at edges, motion). A ray is open or occluded, so the mean of
    /// the squares is the AO estimate itself: the value texture is the moment. Off by
    /// default. A frame with it runs the two-pass form.
    pub fn set_second_moment(&mut self, on: bool) {
        self.use_second_moment = on;
    }

    /// The renderer's temporal resolve weight per pixel for the estimates of the frames
    /// that follow (one value per pixel, row-major), or `None` (the default) for none: the
    /// component's [`EstimateInputs::resolve_weight`], read by the resolved-image rule
    /// (`spvg::SpvgConfigBuilder::resolve_weight`, docs/algorithms.md §8.7) and ignored
    /// without it. A value in `(0, 1]` is the weight the resolve gives the frame at the
    /// pixel (1 where it rejects or clamps away its history); above 1 counts as 1; NaN, 0
    /// or less and infinities mean none there, and the history's age stands in. It is
    /// uploaded now and stays until set again, so a renderer whose resolve runs after the
    /// sampling sets, before each frame, the weights its resolve gave the previous one.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::SliceLength`] naming `resolve_weight` for a slice that is not one
    /// value per pixel (the previous setting is kept).
    pub fn set_resolve_weight(&mut self, weight: Option<&[f32]>) -> Result<(), AdaptiveError> {
        let n = self.width as usize * self.height as usize;
        match weight {
            Some(w) if w.len() != n => Err(AdaptiveError::SliceLength {
                input: "resolve_weight",
                expected: n,
                got: w.len(),
            }),
            Some(w) => {
                write_scalar(
                    &self.queue,
                    &self.resolve_weight,
                    [self.width, self.height],
                    w,
                );
                self.use_resolve_weight = true;
                Ok(())
            }
            None => {
                self.use_resolve_weight = false;
                Ok(())
            }
        }
    }

    /// Also writes, per pixel, the estimates of its first `prefixes[j]` samples
    /// ([`AoFrame::prefixes`]; all 0, the default, turns it off). They equal what fixed
    /// counts of `prefixes[j]` give on the same frame, bit for bit (the sample sequence does
    /// not depend on the count), so a fixed-count run at the largest count yields the runs
    /// of the smaller ones for the cost of one.
    pub fn set_prefix_counts(&mut self, prefixes: [u32; 4]) {
        self.prefixes = prefixes;
    }

    /// The last frame's time in milliseconds: CPU wall time from the start of
    /// [`run_frame`](Self::run_frame) to the queue's completion of its work, before the
    /// readbacks (a guided frame includes the guide's round trip). For measuring what
    /// the passes cost, not for the frame's results.
    #[must_use]
    pub fn last_frame_ms(&self) -> f64 {
        self.last_ms
    }

    /// Records `ao_sample` over the frame, or with the component's count-classified
    /// dispatch on ([`AdaptiveSettings::classified_dispatch`]) `ao_sample_classified` once
    /// per class of tiles: the same values, each pixel's samples in a SIMD group of
    /// similar counts.
    fn record_sample(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), AdaptiveError> {
        let classified = self
            .adaptive
            .as_ref()
            .filter(|a| a.settings().classified_dispatch);
        let pipeline = if classified.is_some() {
            &self.sample_classified
        } else {
            &self.sample
        };
        let count = self
            .adaptive
            .as_ref()
            .map_or(&self.fixed, |a| a.count_texture());
        let s = self.bind(
            pipeline,
            &[
                (5, view(count)),
                (6, view(&self.position)),
                (7, view(&self.normal)),
                (8, view(&self.value)),
                (10, view(&self.prefix)),
            ],
        );
        match classified {
            Some(a) => a.dispatch_classified(encoder, "ao_sample_classified", pipeline, &s, None),
            None => {
                let size = [self.width, self.height];
                dispatch_8x8(encoder, "ao_sample", pipeline, &s, None, size);
                Ok(())
            }
        }
    }

    /// Renders one frame (`params` from [`AoScene::params`](super::AoScene::params)) and
    /// reads back the counts and the AO estimate.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::Device`] when a readback fails.
    pub fn run_frame(&mut self, params: &AoParams) -> Result<AoFrame, AdaptiveError> {
        self.run_frame_guided(params, None)
    }

    /// [`run_frame`](Self::run_frame) with the renderer's TAA guide: an adaptive mode
    /// submits the sampling, reads back the AO values, calls `guide` with them, uploads
    /// what it returns as the component's
    /// [`UpdateInputs::guide`](spvg_wgpu::adaptive::UpdateInputs::guide) and submits the
    /// update. A fixed count ignores `guide`.
    ///
    /// # Errors
    ///
    /// As [`run_frame`](Self::run_frame); [`AdaptiveError::SliceLength`] naming `guide`
    /// for a guide that is not one value per pixel.
    pub fn run_frame_guided(
        &mut self,
        params: &AoParams,
        mut guide: Option<&mut AoGuide<'_>>,
    ) -> Result<AoFrame, AdaptiveError> {
        let start = std::time::Instant::now();
        let mut p = *params;
        (p.width, p.height) = (self.width, self.height);
        p.prefixes = self.prefixes;
        self.queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&p));
        let (cur, prev) = (self.cur, 1 - self.cur);
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let g = self.bind(
            &self.gbuffer,
            &[
                (1, view(&self.depth[cur])),
                (2, view(&self.motion)),
                (3, view(&self.position)),
                (4, view(&self.normal)),
                (9, view(&self.reprojected_depth)),
            ],
        );
        let size = [self.width, self.height];
        dispatch_8x8(&mut encoder, "ao_gbuffer", &self.gbuffer, &g, None, size);
        let identity = self.mode == AoMode::Identity;
        let inputs = EstimateInputs::new(
            if identity {
                &self.zero_motion
            } else {
                &self.motion
            },
            &self.depth[cur],
            if identity {
                &self.depth[cur]
            } else {
                &self.depth[prev]
            },
        )
        .with_reprojected_depth(
            (self.use_reprojected_depth && !identity).then_some(&self.reprojected_depth),
        )
        .with_resolve_weight(self.use_resolve_weight.then_some(&self.resolve_weight));
        let one_pass = self.use_one_pass
            && guide.is_none()
            && !self.use_second_moment
            && self
                .adaptive
                .as_ref()
                .is_some_and(|a| !a.settings().classified_dispatch);
        if let (true, Some(a), Some(op)) = (one_pass, &mut self.adaptive, &self.one_pass) {
            // The pipeline was built for AS (the effect's model); a model changed through
            // `adaptive_mut` is refused as at construction.
            check_control(a.settings())?;
            let component = a.one_pass_group(&inputs)?;
            let own = bind_group(
                &self.device,
                Some("ao_sample_one_pass"),
                &op.own,
                &[(0, &self.params)],
                &[
                    (6, view(&self.position)),
                    (7, view(&self.normal)),
                    (8, view(&self.value)),
                    (10, view(&self.prefix)),
                ],
            );
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("ao_sample_one_pass"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&op.pipeline);
            pass.set_bind_group(0, &own, &[]);
            pass.set_bind_group(ONE_PASS_GROUP, &component, &[]);
            pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
        } else {
            if let Some(a) = &mut self.adaptive {
                a.record_estimate(&mut encoder, &inputs)?;
            }
            self.record_sample(&mut encoder)?;
            let mut guided = false;
            if let (Some(g), Some(_)) = (guide.as_mut(), &self.adaptive) {
                // The update waits for the renderer's guide: submit the sampling first.
                self.queue.submit([encoder.finish()]);
                let value: Vec<f32> = read_texture(&self.device, &self.queue, &self.value)?;
                let c = g(&value);
                if c.len() != value.len() {
                    return Err(AdaptiveError::SliceLength {
                        input: "guide",
                        expected: value.len(),
                        got: c.len(),
                    });
                }
                write_scalar(&self.queue, &self.guide, size, &c);
                encoder = self.device.create_command_encoder(&Default::default());
                guided = true;
            }
            if let Some(a) = &mut self.adaptive {
                let update =
                    UpdateInputs::new(&self.value).with_guide(guided.then_some(&self.guide));
                if self.use_second_moment {
                    // Binary rays: the mean of the squares is the mean.
                    a.record_update_with_moment(&mut encoder, &update, &self.value)?;
                } else {
                    a.record_update(&mut encoder, &update)?;
                }
            }
        }
        self.queue.submit([encoder.finish()]);
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| AdaptiveError::Device(e.to_string()))?;
        self.last_ms = start.elapsed().as_secs_f64() * 1e3;
        self.cur = prev;
        let count = self
            .adaptive
            .as_ref()
            .map_or(&self.fixed, |a| a.count_texture());
        Ok(AoFrame {
            count: read_texture(&self.device, &self.queue, count)?,
            value: read_texture(&self.device, &self.queue, &self.value)?,
            prefixes: if self.prefixes == [0; 4] {
                Vec::new()
            } else {
                read_texture(&self.device, &self.queue, &self.prefix)?
            },
        })
    }
}

/// The AO effect monitors its estimate alone: it runs the component with AS.
pub(super) fn check_control(settings: &AdaptiveSettings) -> Result<(), AdaptiveError> {
    if settings.control == Control::As {
        Ok(())
    } else {
        Err(AdaptiveError::MissingInput {
            input: "control",
            reason: "the AO effect has no control value: it runs the component with AS",
        })
    }
}
