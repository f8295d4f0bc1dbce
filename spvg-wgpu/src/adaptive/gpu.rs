//! The component on a wgpu device: layouts, pipelines, history textures, input checks and
//! the two recorded steps.

use spvg::SpvgConfig;
use spvg::reproject::Reprojection;
use spvg::texel::TexelEncoding;
use wgpu::util::DeviceExt as _;
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use super::params::{
    AdaptiveParams, FLAG_BORDER_MAXIMUM, FLAG_BORDER_PRIOR, FLAG_CONTROL, FLAG_FOOTPRINT,
    FLAG_GAMMA, FLAG_MASKS, controller_block, retargeted,
};
use super::{AdaptiveError, Control, shader_source};

/// Formats accepted for the motion vectors.
pub const MOTION_FORMATS: &[Tf] = &[Tf::Rg32Float, Tf::Rg16Float];
/// Formats accepted for depths, the distant-energy ratio, the monitored and control values.
pub const SCALAR_FORMATS: &[Tf] = &[Tf::R32Float, Tf::R16Float];
/// Formats accepted for masks (any non-zero value is "set").
pub const MASK_FORMATS: &[Tf] = &[Tf::R8Uint, Tf::R16Uint, Tf::R32Uint];
/// Format of the count texture the estimate writes.
pub const COUNT_FORMAT: Tf = Tf::R32Uint;
/// Format of the history textures (`spvg::texel::SpvgTexel16`, `CvTexel16`).
pub const HISTORY_FORMAT: Tf = Tf::Rgba16Float;

/// The current and previous frame's masks of the pass (where it runs: the subsurface
/// mask, the surface that is ambient-occluded, ...).
#[derive(Clone, Copy, Debug)]
pub struct Masks<M> {
    /// This frame's mask: the estimate gives count 0 where it is not set.
    pub current: M,
    /// The previous frame's mask: history is valid only where it is set at the reprojected
    /// texel.
    pub previous: M,
}

/// Inputs of [`AdaptivePass::record_estimate`]; each texture is the frame size, one mip
/// level or more (mip 0 is read), single-sampled, with `TEXTURE_BINDING` usage.
#[derive(Clone, Copy, Debug)]
pub struct EstimateInputs<'a> {
    /// Motion vectors in pixels, this frame's position minus the previous frame's
    /// (`spvg::reproject`): [`MOTION_FORMATS`].
    pub motion: &'a wgpu::Texture,
    /// This frame's linear depth (positive; see `spvg::reproject` for which depth):
    /// [`SCALAR_FORMATS`].
    pub depth: &'a wgpu::Texture,
    /// The previous frame's linear depth: [`SCALAR_FORMATS`].
    pub previous_depth: &'a wgpu::Texture,
    /// The pass masks, or `None` when every pixel is covered: [`MASK_FORMATS`].
    pub masks: Option<Masks<&'a wgpu::Texture>>,
    /// The per-pixel distant-energy ratio `gamma` (docs/algorithms.md §2.4), or `None` for
    /// passes without the near/far split (then `gamma = 1`): [`SCALAR_FORMATS`].
    pub gamma: Option<&'a wgpu::Texture>,
}

/// Inputs of [`AdaptivePass::record_update`]: the frame size, [`SCALAR_FORMATS`],
/// `TEXTURE_BINDING` usage.
#[derive(Clone, Copy, Debug)]
pub struct UpdateInputs<'a> {
    /// The monitored value: the luminance of the pass's Monte Carlo result, `fbar` (for
    /// passes with the near/far split, the distant part only).
    pub value: &'a wgpu::Texture,
    /// The control value `G` (CCV and OCV; ignored by AS).
    pub control: Option<&'a wgpu::Texture>,
}

/// The per-size resources: ping-pong histories, count, link and the uniform blocks for the
/// four combinations of optional inputs.
#[derive(Debug)]
struct Frame {
    history: [wgpu::Texture; 2],
    cv: Option<[wgpu::Texture; 2]>,
    count: wgpu::Texture,
    /// The estimate's counts before dilation; only with a dilation radius.
    raw_count: Option<wgpu::Texture>,
    link: wgpu::Texture,
    /// Indexed by `flags & (FLAG_MASKS | FLAG_GAMMA)`.
    params: [wgpu::Buffer; 4],
}

/// The reusable adaptive-sampling component: SPVG count control with motion-vector
/// reprojection and disocclusion, recorded into the caller's command encoder. See the
/// [module docs](super) for the bindings, formats and per-frame order.
#[derive(Debug)]
pub struct AdaptivePass {
    device: wgpu::Device,
    config: SpvgConfig<f32>,
    control: Control,
    /// The target the history's variance encoding was fixed by (the configuration's at
    /// construction).
    encoding_target: f32,
    encoding: TexelEncoding,
    reprojection: Reprojection<f32>,
    /// Radius of the count dilation; 0 = off.
    dilation: u32,
    width: u32,
    height: u32,
    controller: wgpu::Buffer,
    estimate_layout: wgpu::BindGroupLayout,
    update_layout: wgpu::BindGroupLayout,
    dilate_layout: wgpu::BindGroupLayout,
    estimate: wgpu::ComputePipeline,
    dilate: wgpu::ComputePipeline,
    update: wgpu::ComputePipeline,
    dummy_uint: wgpu::Texture,
    dummy_float: wgpu::Texture,
    frame: Frame,
    /// Index of the history read this frame.
    read: usize,
    estimated: bool,
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

const FLOAT: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: false };
const UINT: wgpu::TextureSampleType = wgpu::TextureSampleType::Uint;

fn storage_entry(binding: u32, format: Tf) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// The estimate step's bind group layout (group 0); see the module docs' table.
fn estimate_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_entry(2, FLOAT),
        texture_entry(3, FLOAT),
        texture_entry(4, FLOAT),
        texture_entry(5, FLOAT),
        texture_entry(6, UINT),
        texture_entry(7, UINT),
        texture_entry(8, FLOAT),
        storage_entry(9, COUNT_FORMAT),
        storage_entry(10, Tf::R32Uint),
    ]
}

/// The dilation's bind group layout: the estimate's counts in (13), the dilated out (9).
fn dilate_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_entry(13, UINT),
        storage_entry(9, COUNT_FORMAT),
    ]
}

/// The update step's bind group layout (group 0); bindings 16 and 17 for OCV only.
fn update_entries(ocv: bool) -> Vec<wgpu::BindGroupLayoutEntry> {
    let mut e = vec![
        uniform_entry(0),
        uniform_entry(1),
        texture_entry(2, FLOAT),
        texture_entry(11, FLOAT),
        texture_entry(12, FLOAT),
        texture_entry(13, UINT),
        texture_entry(14, UINT),
        storage_entry(15, HISTORY_FORMAT),
    ];
    if ocv {
        e.push(texture_entry(16, FLOAT));
        e.push(storage_entry(17, HISTORY_FORMAT));
    }
    e
}

/// Checks an input texture before it is bound.
fn check(
    input: &'static str,
    t: &wgpu::Texture,
    size: [u32; 2],
    allowed: &'static [Tf],
) -> Result<(), AdaptiveError> {
    if t.dimension() != wgpu::TextureDimension::D2 {
        return Err(AdaptiveError::TextureKind {
            input,
            reason: "must be a 2D texture",
        });
    }
    if t.sample_count() != 1 {
        return Err(AdaptiveError::TextureKind {
            input,
            reason: "must be single-sampled",
        });
    }
    let s = t.size();
    if [s.width, s.height] != size || s.depth_or_array_layers != 1 {
        return Err(AdaptiveError::TextureSize {
            input,
            expected: size,
            got: [s.width, s.height, s.depth_or_array_layers],
        });
    }
    if !allowed.contains(&t.format()) {
        return Err(AdaptiveError::TextureFormat {
            input,
            got: t.format(),
            allowed,
        });
    }
    if !t.usage().contains(Tu::TEXTURE_BINDING) {
        return Err(AdaptiveError::TextureUsage {
            input,
            missing: Tu::TEXTURE_BINDING,
        });
    }
    Ok(())
}

fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&wgpu::TextureViewDescriptor {
        base_mip_level: 0,
        mip_level_count: Some(1),
        ..Default::default()
    })
}

/// Checks a frame size against the device (or, for the twin, `u16::MAX`).
pub(crate) fn check_size(width: u32, height: u32, max: u32) -> Result<(), AdaptiveError> {
    let pixels = u64::from(width) * u64::from(height);
    if width == 0 || height == 0 || width > max || height > max || pixels >= u64::from(u32::MAX) {
        return Err(AdaptiveError::FrameSize { width, height, max });
    }
    Ok(())
}

impl AdaptivePass {
    /// Builds the component on `device` for a `width x height` frame: validates the
    /// controller configuration (the [`Spvg`](spvg::controller::CountPolicy::Spvg) count
    /// policy), creates the layouts, pipelines and zeroed (invalid) histories. The depth
    /// tolerance is [`Reprojection::default`] (2%) until
    /// [`set_reprojection`](Self::set_reprojection). The history's variance encoding is
    /// fixed here by `config`'s target for the component's life (see
    /// [`set_target_variance`](Self::set_target_variance)).
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::UnsupportedPolicy`], [`AdaptiveError::Param`] (an encoding the
    /// texel layout cannot hold), [`AdaptiveError::FrameSize`].
    pub fn new(
        device: &wgpu::Device,
        config: SpvgConfig<f32>,
        control: Control,
        width: u32,
        height: u32,
    ) -> Result<Self, AdaptiveError> {
        let encoding_target = config.target_variance();
        let block = controller_block(&config, &control, encoding_target)?;
        check_size(width, height, device.limits().max_texture_dimension_2d)?;
        let controller = controller_buffer(device, &block.spvg);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("adaptive.wgsl"),
            source: wgpu::ShaderSource::Wgsl(shader_source().into()),
        });
        let ocv = matches!(control, Control::Ocv(_));
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let estimate_layout = layout("adaptive estimate", &estimate_entries());
        let update_layout = layout("adaptive update", &update_entries(ocv));
        let dilate_layout = layout("adaptive dilate", &dilate_entries());
        let pipeline = |bgl: &wgpu::BindGroupLayout, entry: &str| {
            let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry),
                bind_group_layouts: &[Some(bgl)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        let estimate = pipeline(&estimate_layout, "adaptive_estimate");
        let dilate = pipeline(&dilate_layout, "adaptive_dilate");
        let update = pipeline(
            &update_layout,
            if ocv {
                "adaptive_update_ocv"
            } else {
                "adaptive_update"
            },
        );
        let reprojection = Reprojection::default();
        let frame = Self::make_frame(device, &control, &reprojection, 0, width, height);
        Ok(Self {
            dummy_uint: texture(
                device,
                "adaptive unused mask",
                Tf::R8Uint,
                [1, 1],
                Tu::TEXTURE_BINDING,
            ),
            dummy_float: texture(
                device,
                "adaptive unused scalar",
                Tf::R32Float,
                [1, 1],
                Tu::TEXTURE_BINDING,
            ),
            device: device.clone(),
            config,
            control,
            encoding_target,
            encoding: encoding_of(&block.spvg)?,
            reprojection,
            dilation: 0,
            width,
            height,
            controller,
            estimate_layout,
            update_layout,
            dilate_layout,
            estimate,
            dilate,
            update,
            frame,
            read: 0,
            estimated: false,
        })
    }

    fn make_frame(
        device: &wgpu::Device,
        control: &Control,
        reprojection: &Reprojection<f32>,
        dilation: u32,
        width: u32,
        height: u32,
    ) -> Frame {
        let hist_usage = Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING | Tu::COPY_SRC;
        let pair = |label: &str| {
            [
                texture(
                    device,
                    &format!("{label} a"),
                    HISTORY_FORMAT,
                    [width, height],
                    hist_usage,
                ),
                texture(
                    device,
                    &format!("{label} b"),
                    HISTORY_FORMAT,
                    [width, height],
                    hist_usage,
                ),
            ]
        };
        let params = core::array::from_fn(|k| {
            let mut flags = k as u32;
            if matches!(control, Control::Ccv) {
                flags |= FLAG_CONTROL;
            }
            if reprojection.border_prior() {
                flags |= FLAG_BORDER_PRIOR;
            }
            if reprojection.footprint_search() {
                flags |= FLAG_FOOTPRINT;
            }
            if reprojection.border_count() == spvg::reproject::BorderCount::Maximum {
                flags |= FLAG_BORDER_MAXIMUM;
            }
            let p = AdaptiveParams {
                width,
                height,
                depth_tolerance: reprojection.depth_tolerance(),
                flags,
                dilation,
                pad: [0; 3],
            };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("AdaptiveParams"),
                contents: bytemuck::bytes_of(&p),
                usage: wgpu::BufferUsages::UNIFORM,
            })
        });
        Frame {
            history: pair("adaptive history"),
            cv: matches!(control, Control::Ocv(_)).then(|| pair("adaptive cv history")),
            count: texture(
                device,
                "adaptive count",
                COUNT_FORMAT,
                [width, height],
                hist_usage,
            ),
            raw_count: (dilation > 0).then(|| {
                texture(
                    device,
                    "adaptive count before dilation",
                    COUNT_FORMAT,
                    [width, height],
                    Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING,
                )
            }),
            link: texture(
                device,
                "adaptive link",
                Tf::R32Uint,
                [width, height],
                Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING,
            ),
            params,
        }
    }

    /// Sets the target variance `sigma0^2` of the steps recorded from now on (a frame
    /// budget governor, `spvg::budget::Governor`, moves it every frame). Every other
    /// controller setting stays, and so does the history's variance encoding: it was fixed
    /// at construction by the configuration's target, so the stored variances keep their
    /// meaning when the target crosses a power of two (docs/algorithms.md §8.2), and the
    /// history stays valid. Call it before [`record_estimate`](Self::record_estimate):
    /// both steps of a frame run one target.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::Param`] for a target the controller rejects (not finite and
    /// positive), [`AdaptiveError::TargetBetweenSteps`] after a frame's estimate and
    /// before its update; the component is unchanged then.
    pub fn set_target_variance(&mut self, sigma0_sq: f32) -> Result<(), AdaptiveError> {
        let config = retargeted(&self.config, self.estimated, sigma0_sq)?;
        if config != self.config {
            let block = controller_block(&config, &self.control, self.encoding_target)?;
            // A new buffer rather than a queue write: steps already recorded keep the
            // block they were recorded with, and recording needs no queue.
            self.controller = controller_buffer(&self.device, &block.spvg);
            self.config = config;
        }
        Ok(())
    }

    /// The history's texel encoding (`spvg::texel`): the variance scale fixed at
    /// construction and, for OCV, the CV scale. Decode [`history_texture`](Self::history_texture)
    /// with it.
    #[must_use]
    pub fn encoding(&self) -> TexelEncoding {
        self.encoding
    }

    /// Sets the reprojection rule (depth tolerance, border prior). The history stays valid.
    pub fn set_reprojection(&mut self, reprojection: Reprojection<f32>) {
        self.reprojection = reprojection;
        // Only the uniform blocks depend on it; the new frame's textures are zeroed, so
        // keep the old ones.
        let fresh = Self::make_frame(
            &self.device,
            &self.control,
            &reprojection,
            self.dilation,
            self.width,
            self.height,
        );
        self.frame.params = fresh.params;
    }

    /// Sets the radius of the count dilation (`spvg::dilation`, docs/algorithms.md §2.5):
    /// after the estimate, each covered pixel takes the largest count within `radius`
    /// pixels, which catches rare events and sub-pixel reprojection drift that a pixel's
    /// own history misses. 0 (the default) is the papers' per-pixel count. The history
    /// stays valid; with a radius the estimate step records a second compute pass and the
    /// component keeps one more `R32Uint` texture. It applies from the next recorded
    /// estimate (the update does not depend on it).
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::Param`] naming `radius` above `spvg::dilation::MAX_RADIUS`; the
    /// component is unchanged then.
    pub fn set_count_dilation(&mut self, radius: u32) -> Result<(), AdaptiveError> {
        spvg::dilation::check_radius(radius)?;
        let fresh = Self::make_frame(
            &self.device,
            &self.control,
            &self.reprojection,
            radius,
            self.width,
            self.height,
        );
        self.frame.params = fresh.params;
        self.frame.raw_count = fresh.raw_count;
        self.dilation = radius;
        Ok(())
    }

    /// The count dilation radius (0: off).
    #[must_use]
    pub fn count_dilation(&self) -> u32 {
        self.dilation
    }

    /// Resizes the frame. Every history is invalid afterwards (docs/algorithms.md §2.3a:
    /// the frame size changed), so the next frame takes the disocclusion path everywhere.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::FrameSize`]; the component is unchanged then.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), AdaptiveError> {
        check_size(width, height, self.device.limits().max_texture_dimension_2d)?;
        self.frame = Self::make_frame(
            &self.device,
            &self.control,
            &self.reprojection,
            self.dilation,
            width,
            height,
        );
        (self.width, self.height, self.read, self.estimated) = (width, height, 0, false);
        Ok(())
    }

    /// Invalidates every history (a camera cut): new zeroed textures, as after a resize.
    pub fn reset_history(&mut self) {
        self.frame = Self::make_frame(
            &self.device,
            &self.control,
            &self.reprojection,
            self.dilation,
            self.width,
            self.height,
        );
        (self.read, self.estimated) = (0, false);
    }

    /// Frame size `[width, height]`.
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        [self.width, self.height]
    }

    /// The controller configuration (its target the latest
    /// [`set_target_variance`](Self::set_target_variance)).
    #[must_use]
    pub fn config(&self) -> &SpvgConfig<f32> {
        &self.config
    }

    /// The control model.
    #[must_use]
    pub fn control(&self) -> &Control {
        &self.control
    }

    /// The reprojection rule.
    #[must_use]
    pub fn reprojection(&self) -> &Reprojection<f32> {
        &self.reprojection
    }

    /// The count texture (`R32Uint`, frame size, `TEXTURE_BINDING | COPY_SRC`) that
    /// [`record_estimate`](Self::record_estimate) writes and the renderer's sampling pass
    /// reads (`texture_2d<u32>`, `textureLoad(count, p, 0).x`).
    #[must_use]
    pub fn count_texture(&self) -> &wgpu::Texture {
        &self.frame.count
    }

    /// The history texture holding the latest history (after an update: the one it wrote),
    /// `Rgba16Float`, `COPY_SRC`: the `spvg::texel::SpvgTexel16` layout with the spare
    /// channel 1 where the texel was written.
    #[must_use]
    pub fn history_texture(&self) -> &wgpu::Texture {
        &self.frame.history[self.read]
    }

    /// The CV history texture holding the latest CV history (OCV only):
    /// `spvg::texel::CvTexel16`.
    #[must_use]
    pub fn cv_history_texture(&self) -> Option<&wgpu::Texture> {
        self.frame.cv.as_ref().map(|c| &c[self.read])
    }

    fn params(&self, flags: u32) -> &wgpu::Buffer {
        let k = (flags & (FLAG_MASKS | FLAG_GAMMA)) as usize;
        &self.frame.params[k]
    }

    fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        group: &wgpu::BindGroup,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(self.width.div_ceil(8), self.height.div_ceil(8), 1);
    }

    /// Records the estimate step into `encoder`: reprojects the history, decides its
    /// validity once per pixel, and writes [`count_texture`](Self::count_texture) (0
    /// outside the mask and where the zero-sample rule holds) and the link the update reads.
    ///
    /// # Errors
    ///
    /// An input of the wrong size, format, usage or kind; nothing is recorded then.
    pub fn record_estimate(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &EstimateInputs<'_>,
    ) -> Result<(), AdaptiveError> {
        self.record_estimate_timed(encoder, inputs, None)
    }

    /// [`record_estimate`](Self::record_estimate) with timestamp writes on its compute
    /// pass (the device needs `wgpu::Features::TIMESTAMP_QUERY`), for a renderer that
    /// times its passes.
    ///
    /// # Errors
    ///
    /// As [`record_estimate`](Self::record_estimate).
    pub fn record_estimate_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &EstimateInputs<'_>,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), AdaptiveError> {
        let size = self.size();
        check("motion", inputs.motion, size, MOTION_FORMATS)?;
        check("depth", inputs.depth, size, SCALAR_FORMATS)?;
        check(
            "previous_depth",
            inputs.previous_depth,
            size,
            SCALAR_FORMATS,
        )?;
        let mut flags = 0;
        if let Some(m) = &inputs.masks {
            check("masks.current", m.current, size, MASK_FORMATS)?;
            check("masks.previous", m.previous, size, MASK_FORMATS)?;
            flags |= FLAG_MASKS;
        }
        if let Some(g) = inputs.gamma {
            check("gamma", g, size, SCALAR_FORMATS)?;
            flags |= FLAG_GAMMA;
        }
        let (mask, prev_mask) = match &inputs.masks {
            Some(m) => (m.current, m.previous),
            None => (&self.dummy_uint, &self.dummy_uint),
        };
        let views = [
            (2, view(&self.frame.history[self.read])),
            (3, view(inputs.motion)),
            (4, view(inputs.depth)),
            (5, view(inputs.previous_depth)),
            (6, view(mask)),
            (7, view(prev_mask)),
            (8, view(inputs.gamma.unwrap_or(&self.dummy_float))),
            (
                9,
                view(self.frame.raw_count.as_ref().unwrap_or(&self.frame.count)),
            ),
            (10, view(&self.frame.link)),
        ];
        let group = self.bind_group("adaptive estimate", &self.estimate_layout, flags, &views);
        let Some(raw) = &self.frame.raw_count else {
            self.dispatch(
                encoder,
                "adaptive estimate",
                &self.estimate,
                &group,
                timestamp_writes,
            );
            self.estimated = true;
            return Ok(());
        };
        // Two passes: the timestamps bracket both.
        let (first, second) = match timestamp_writes {
            Some(t) => (
                Some(wgpu::ComputePassTimestampWrites {
                    end_of_pass_write_index: None,
                    ..t.clone()
                }),
                Some(wgpu::ComputePassTimestampWrites {
                    beginning_of_pass_write_index: None,
                    ..t
                }),
            ),
            None => (None, None),
        };
        self.dispatch(encoder, "adaptive estimate", &self.estimate, &group, first);
        let views = [(13, view(raw)), (9, view(&self.frame.count))];
        let group = self.bind_group("adaptive dilate", &self.dilate_layout, 0, &views);
        self.dispatch(encoder, "adaptive dilate", &self.dilate, &group, second);
        self.estimated = true;
        Ok(())
    }

    /// Records the update step into `encoder`: folds the renderer's monitored value (and
    /// for CCV/OCV the control value) into the history read through the estimate's link,
    /// writes the other ping-pong texture, and makes it the current history.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::UpdateWithoutEstimate`], [`AdaptiveError::MissingInput`] for CCV or
    /// OCV without a control value, or an input of the wrong size, format, usage or kind;
    /// nothing is recorded then.
    pub fn record_update(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &UpdateInputs<'_>,
    ) -> Result<(), AdaptiveError> {
        self.record_update_timed(encoder, inputs, None)
    }

    /// [`record_update`](Self::record_update) with timestamp writes on its compute pass
    /// (the device needs `wgpu::Features::TIMESTAMP_QUERY`), for a renderer that times
    /// its passes.
    ///
    /// # Errors
    ///
    /// As [`record_update`](Self::record_update).
    pub fn record_update_timed(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &UpdateInputs<'_>,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), AdaptiveError> {
        if !self.estimated {
            return Err(AdaptiveError::UpdateWithoutEstimate);
        }
        let size = self.size();
        check("value", inputs.value, size, SCALAR_FORMATS)?;
        let control = match (inputs.control, self.control.needs_control()) {
            (Some(c), true) => {
                check("control", c, size, SCALAR_FORMATS)?;
                c
            }
            (None, true) => {
                return Err(AdaptiveError::MissingInput {
                    input: "control",
                    reason: "CCV and OCV monitor fbar - alpha G",
                });
            }
            (_, false) => &self.dummy_float,
        };
        let (r, w) = (self.read, 1 - self.read);
        let mut views = vec![
            (2, view(&self.frame.history[r])),
            (11, view(inputs.value)),
            (12, view(control)),
            (13, view(&self.frame.count)),
            (14, view(&self.frame.link)),
            (15, view(&self.frame.history[w])),
        ];
        if let Some(cv) = &self.frame.cv {
            views.push((16, view(&cv[r])));
            views.push((17, view(&cv[w])));
        }
        let group = self.bind_group("adaptive update", &self.update_layout, 0, &views);
        self.dispatch(
            encoder,
            "adaptive update",
            &self.update,
            &group,
            timestamp_writes,
        );
        self.read = w;
        self.estimated = false;
        Ok(())
    }

    fn bind_group(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        flags: u32,
        views: &[(u32, wgpu::TextureView)],
    ) -> wgpu::BindGroup {
        let params = self.params(flags);
        crate::resources::bind_group(
            &self.device,
            Some(label),
            layout,
            &[(0, &self.controller), (1, params)],
            views,
        )
    }
}

use crate::resources::texture_2d as texture;

/// The controller's uniform buffer (binding 0 of both steps).
fn controller_buffer(device: &wgpu::Device, block: &spvg_shaders::Params) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("adaptive controller"),
        contents: bytemuck::bytes_of(block),
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

/// The texel encoding a controller block stores with (its scales are powers of two, so
/// rebuilding the encoding from them is exact).
pub(crate) fn encoding_of(block: &spvg_shaders::Params) -> Result<TexelEncoding, AdaptiveError> {
    Ok(TexelEncoding::new(block.var_scale)?.with_cv_scale(block.cv_scale)?)
}

/// Copies mip 0 of `texture` (with `COPY_SRC` usage) back to the host as tightly packed
/// texels of type `T` (`T` the texel's size: `u32` for `R32Uint`, `[half::f16; 4]` for
/// `Rgba16Float`, ...). Blocks until the copy is done.
///
/// # Errors
///
/// [`AdaptiveError::TextureUsage`] without `COPY_SRC`, [`AdaptiveError::TextureFormat`]
/// when `T` is not the texel size, [`AdaptiveError::Device`] when the device fails.
pub fn read_texture<T: bytemuck::Pod>(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<T>, AdaptiveError> {
    if !texture.usage().contains(Tu::COPY_SRC) {
        return Err(AdaptiveError::TextureUsage {
            input: "texture",
            missing: Tu::COPY_SRC,
        });
    }
    let texel = texture.format().block_copy_size(None).unwrap_or(0);
    if texel as usize != size_of::<T>() {
        return Err(AdaptiveError::TextureFormat {
            input: "texture",
            got: texture.format(),
            allowed: &[],
        });
    }
    let s = texture.size();
    let row = (s.width * texel).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("adaptive readback"),
        size: u64::from(row) * u64::from(s.height),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("adaptive readback"),
    });
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(s.height),
            },
        },
        wgpu::Extent3d {
            depth_or_array_layers: 1,
            ..s
        },
    );
    queue.submit([encoder.finish()]);
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    let device_error = |e: String| AdaptiveError::Device(e);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| device_error(e.to_string()))?;
    rx.recv()
        .map_err(|e| device_error(e.to_string()))?
        .map_err(|e| device_error(e.to_string()))?;
    let tight = (s.width * texel) as usize;
    let mut packed = Vec::with_capacity(tight * s.height as usize);
    {
        let mapped = slice
            .get_mapped_range()
            .map_err(|e| device_error(e.to_string()))?;
        for line in mapped.chunks(row as usize) {
            packed.extend_from_slice(line.get(..tight).unwrap_or(line));
        }
    }
    buffer.unmap();
    Ok(bytemuck::pod_collect_to_vec(&packed))
}
