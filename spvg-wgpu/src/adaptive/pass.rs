//! The component on a wgpu device: its pipelines, its textures (histories, count, link)
//! and uniform blocks, and its settings. The recorded steps are in `record.rs`.

use spvg::texel::TexelEncoding;
use spvg_shaders::StoreRounding;
use wgpu::util::DeviceExt as _;
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use super::classify::{CLASS_BOUNDS, ClassBuffers, ClassPipelines};
use super::inputs::{COUNT_FORMAT, HISTORY_FORMAT, check_size};
use super::layout::{dilate_entries, estimate_entries, one_pass_entries, update_entries};
use super::params::{
    AdaptiveParams, FLAG_BORDER_MAXIMUM, FLAG_BORDER_PRIOR, FLAG_CONTROL, FLAG_FOOTPRINT,
    FLAG_NEIGHBOUR_PRIOR, PARAMS_BLOCKS, STORE_ROUNDING, component_ocv, params_flags, retargeted,
};
use super::settings::{Derived, derive};
use super::{AdaptiveError, AdaptiveSettings, CLASSIFIED_WGSL, Control, shader_source};
use crate::util::{compute_pipeline, shader_module, texture_2d as texture};

/// The per-size resources: ping-pong histories, count, link and the uniform blocks for the
/// sixteen combinations of optional inputs.
#[derive(Debug)]
pub(super) struct Frame {
    pub(super) history: [wgpu::Texture; 2],
    pub(super) cv: Option<[wgpu::Texture; 2]>,
    pub(super) count: wgpu::Texture,
    /// The estimate's counts before dilation; only with a dilation radius.
    pub(super) raw_count: Option<wgpu::Texture>,
    pub(super) link: wgpu::Texture,
    /// This frame's depth, written by the estimate for the update's same-surface test of
    /// the spatial variance (`spvg::controller::young`); 1x1 and unused while that rule
    /// is off.
    pub(super) surface: wgpu::Texture,
    /// Each pixel's real count under fractional counts (`spvg::controller::fractional`),
    /// written by the estimate for the update; 1x1 and unused while they are off.
    pub(super) real: wgpu::Texture,
    /// Indexed by `params_index(flags)` (masks, gamma, reprojected depth, guide bound).
    pub(super) params: [wgpu::Buffer; PARAMS_BLOCKS],
    /// The count classification's buffers; only with the classified dispatch.
    pub(super) classes: Option<ClassBuffers>,
}

/// Whether the neighbour prior acts: it runs in the dilation's step.
fn prior_acts(s: &AdaptiveSettings) -> bool {
    s.neighbour_prior && s.dilation > 0
}

/// Whether this frame's depth is kept for the update or the dilation (the spatial
/// variance of young histories, the neighbour prior): the surface texture's full size.
fn keeps_surface(s: &AdaptiveSettings) -> bool {
    prior_acts(s) || s.config.spatial_variance() > 0
}

/// The component's block for a `size` frame under `settings`, with the flags of the
/// optional inputs (and the one-pass switches) `flags` and those the settings decide.
pub(super) fn params_block(
    settings: &AdaptiveSettings,
    [width, height]: [u32; 2],
    flags: u32,
) -> AdaptiveParams {
    let reprojection = &settings.reprojection;
    let mut flags = flags;
    if settings.control == Control::Ccv {
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
    if prior_acts(settings) {
        flags |= FLAG_NEIGHBOUR_PRIOR;
    }
    AdaptiveParams {
        width,
        height,
        depth_tolerance: reprojection.depth_tolerance(),
        flags,
        dilation: settings.dilation,
        pad: [0; 3],
    }
}

/// Whether the settings run fractional counts: the real-count texture's full size.
fn fractional(s: &AdaptiveSettings) -> bool {
    s.config.fractional_floor().is_some()
}

/// The reusable adaptive-sampling component: SPVG count control with motion-vector
/// reprojection and disocclusion, recorded into the caller's command encoder. See the
/// [module docs](super) for the bindings, formats and per-frame order.
///
/// Every `f16` history store rounds to nearest, ties to even
/// ([`STORE_ROUNDING`](Self::STORE_ROUNDING), `spvg::texel::Rounding::Nearest`): the
/// shader rounds explicitly (`spvg_to_f16`) before the store, so the stored bits do not
/// depend on the driver's own f32-to-f16 conversion (lavapipe's truncates), and
/// [`AdaptiveTwin`](super::AdaptiveTwin) stores the same bits.
#[derive(Debug)]
pub struct AdaptivePass {
    pub(super) device: wgpu::Device,
    pub(super) settings: AdaptiveSettings,
    /// The target the history's variance encoding was fixed by (the settings' at
    /// construction).
    pub(super) encoding_target: f32,
    /// The block and controller derived from `settings`.
    pub(super) derived: Derived,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) controller: wgpu::Buffer,
    pub(super) estimate_layout: wgpu::BindGroupLayout,
    pub(super) update_layout: wgpu::BindGroupLayout,
    pub(super) dilate_layout: wgpu::BindGroupLayout,
    /// The one-pass form's bind group layout (`one_pass_layout`).
    pub(super) one_pass_layout: wgpu::BindGroupLayout,
    /// Whether the one-pass form stores the counts (`set_one_pass_counts`).
    pub(super) one_pass_counts: bool,
    /// Whether the one-pass form orders its invocations by count (`set_one_pass_order`).
    pub(super) one_pass_order: bool,
    pub(super) estimate: wgpu::ComputePipeline,
    pub(super) dilate: wgpu::ComputePipeline,
    pub(super) update: wgpu::ComputePipeline,
    /// The count classification's pipelines, built when the classified dispatch is
    /// first switched on.
    pub(super) classify: Option<ClassPipelines>,
    pub(super) dummy_uint: wgpu::Texture,
    pub(super) dummy_float: wgpu::Texture,
    pub(super) frame: Frame,
    /// Index of the history read this frame.
    pub(super) read: usize,
    pub(super) estimated: bool,
    /// A resize discarded this frame's estimate (the update then names the resize).
    pub(super) resized_between_steps: bool,
    /// The updates recorded so far: the frame index of the dither threshold of fractional
    /// counts (the twin counts its updates the same way).
    pub(super) frame_index: u32,
}

impl AdaptivePass {
    /// The format of [`count_texture`](Self::count_texture): `R32Uint`.
    pub const COUNT_FORMAT: wgpu::TextureFormat = COUNT_FORMAT;

    /// The format of [`history_texture`](Self::history_texture) and
    /// [`cv_history_texture`](Self::cv_history_texture): `Rgba16Float`
    /// (`spvg::texel::SpvgTexel16`, `spvg::texel::CvTexel16`).
    pub const HISTORY_FORMAT: wgpu::TextureFormat = HISTORY_FORMAT;

    /// How every `f16` history store rounds: to nearest, ties to even, explicitly in the
    /// shader (`spvg_to_f16`), so the stored bits do not depend on the driver's own
    /// f32-to-f16 conversion (lavapipe's truncates), and the twin stores the same bits. A
    /// renderer that builds its own `spvg_shaders::Storage` for the component's texels
    /// uses it.
    pub const STORE_ROUNDING: StoreRounding = STORE_ROUNDING;

    /// The classes of the count-classified dispatch
    /// ([`AdaptiveSettings::classified_dispatch`]), by a tile's largest count: class `k`
    /// holds the tiles whose largest count is above `CLASS_BOUNDS[k - 1]` and at most
    /// `CLASS_BOUNDS[k]`, class 0 the tiles of count 0 only, the last class those above
    /// the last bound (8 classes: 0, 1, 2 to 4, 5 to 8, 9 to 16, 17 to 32, 33 to 64, more).
    pub const CLASS_BOUNDS: [u32; 7] = CLASS_BOUNDS;

    /// The WGSL a renderer's sampling entry point includes to run under
    /// [`dispatch_classified`](Self::dispatch_classified): the bindings of group 1 (the
    /// class's tile list and the tiles' pixel orders, `var<storage, read>`) and
    /// `adaptive_class_pixel(workgroup_id, num_workgroups, local_invocation_index) ->
    /// vec3<u32>`, the pixel an invocation takes (`z = 1` past the list's end). The entry
    /// point is `@workgroup_size(8, 8, 1)`, calls it first and then runs its whole-frame
    /// body for that pixel, bounds check included:
    ///
    /// ```wgsl
    /// @compute @workgroup_size(8, 8, 1)
    /// fn my_sample_classified(@builtin(workgroup_id) wg: vec3<u32>,
    ///                         @builtin(num_workgroups) groups: vec3<u32>,
    ///                         @builtin(local_invocation_index) index: u32) {
    ///     let p = adaptive_class_pixel(wg, groups, index);
    ///     if (p.z == 0u) { my_sample_at(p); }
    /// }
    /// ```
    pub const CLASSIFIED_WGSL: &str = CLASSIFIED_WGSL;

    /// Builds the component on `device` for a `width x height` frame with `settings`:
    /// validates them, creates the layouts, pipelines and zeroed (invalid) histories. The
    /// history's variance encoding is fixed here by the settings' target for the
    /// component's life (see [`set_target_variance`](Self::set_target_variance)).
    ///
    /// # Errors
    ///
    /// As [`AdaptiveSettings::validate`]; [`AdaptiveError::FrameSize`].
    pub fn new(
        device: &wgpu::Device,
        settings: AdaptiveSettings,
        width: u32,
        height: u32,
    ) -> Result<Self, AdaptiveError> {
        let encoding_target = settings.config.target_variance();
        let derived = derive(&settings, encoding_target)?;
        check_size(width, height, device.limits().max_texture_dimension_2d)?;
        let controller = controller_buffer(device, &derived.block);
        let ocv = component_ocv(&settings.control).is_some();
        let module = shader_module(device, "adaptive.wgsl", shader_source(ocv));
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let estimate_layout = layout("adaptive estimate", &estimate_entries());
        let update_layout = layout("adaptive update", &update_entries(ocv));
        let dilate_layout = layout("adaptive dilate", &dilate_entries());
        let pipeline = |bgl: &wgpu::BindGroupLayout, entry| {
            compute_pipeline(device, &module, entry, Some(bgl))
        };
        let estimate = pipeline(&estimate_layout, "adaptive_estimate");
        let dilate = pipeline(&dilate_layout, "adaptive_dilate");
        let update = pipeline(&update_layout, "adaptive_update");
        let one_pass_layout = layout("adaptive one pass", &one_pass_entries(ocv));
        let classify = settings
            .classified_dispatch
            .then(|| ClassPipelines::new(device, &module));
        let frame = Self::make_frame(device, &settings, [width, height]);
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
            settings,
            encoding_target,
            derived,
            width,
            height,
            controller,
            estimate_layout,
            update_layout,
            dilate_layout,
            one_pass_layout,
            one_pass_counts: false,
            one_pass_order: true,
            estimate,
            dilate,
            update,
            classify,
            frame,
            read: 0,
            estimated: false,
            resized_between_steps: false,
            frame_index: 0,
        })
    }

    fn make_frame(
        device: &wgpu::Device,
        settings: &AdaptiveSettings,
        [width, height]: [u32; 2],
    ) -> Frame {
        let dilation = settings.dilation;
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
            let p = params_block(settings, [width, height], params_flags(k));
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("AdaptiveParams"),
                contents: bytemuck::bytes_of(&p),
                usage: wgpu::BufferUsages::UNIFORM,
            })
        });
        Frame {
            history: pair("adaptive history"),
            cv: component_ocv(&settings.control)
                .is_some()
                .then(|| pair("adaptive cv history")),
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
                // COPY_SRC: `link_texture` lets a renderer read it back (a debug view).
                Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING | Tu::COPY_SRC,
            ),
            surface: texture(
                device,
                "adaptive surface depth",
                Tf::R32Float,
                if keeps_surface(settings) {
                    [width, height]
                } else {
                    [1, 1]
                },
                Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING,
            ),
            real: texture(
                device,
                "adaptive real count",
                Tf::R32Float,
                if fractional(settings) {
                    [width, height]
                } else {
                    [1, 1]
                },
                Tu::STORAGE_BINDING | Tu::TEXTURE_BINDING,
            ),
            params,
            classes: settings
                .classified_dispatch
                .then(|| ClassBuffers::new(device, [width, height])),
        }
    }

    /// The settings the component runs (its target the latest
    /// [`set_target_variance`](Self::set_target_variance)).
    #[must_use]
    pub fn settings(&self) -> &AdaptiveSettings {
        &self.settings
    }

    /// Changes the settings for the steps recorded from now on. The histories stay valid
    /// and keep their variance encoding, except when the control model changes: what the
    /// history monitors then changes (and OCV keeps a second history), so the component
    /// starts over as [`new`](Self::new) builds it, with the new target fixing the
    /// encoding. A new count dilation radius, neighbour prior, reprojection rule or
    /// controller setting applies from the next recorded estimate.
    ///
    /// # Errors
    ///
    /// As [`AdaptiveSettings::validate`]; [`AdaptiveError::SettingsBetweenSteps`] after a
    /// frame's estimate and before its update (both steps of a frame run one setting).
    /// The component is unchanged then.
    pub fn set_settings(&mut self, settings: AdaptiveSettings) -> Result<(), AdaptiveError> {
        settings.validate()?;
        if self.estimated {
            return Err(AdaptiveError::SettingsBetweenSteps);
        }
        if settings == self.settings {
            return Ok(());
        }
        if settings.control != self.settings.control {
            *self = Self::new(&self.device, settings, self.width, self.height)?;
            return Ok(());
        }
        let derived = derive(&settings, self.encoding_target)?;
        if derived.block != self.derived.block {
            // A new buffer rather than a queue write: steps already recorded keep the
            // block they were recorded with, and recording needs no queue.
            self.controller = controller_buffer(&self.device, &derived.block);
        }
        // Only the uniform blocks and the dilation's own textures depend on the rest;
        // the new frame's histories are zeroed, so keep the old ones.
        let fresh = Self::make_frame(&self.device, &settings, self.size());
        self.frame.params = fresh.params;
        self.frame.raw_count = fresh.raw_count;
        if settings.classified_dispatch != self.settings.classified_dispatch {
            self.frame.classes = fresh.classes;
        }
        if settings.classified_dispatch && self.classify.is_none() {
            let ocv = component_ocv(&self.settings.control).is_some();
            let module = shader_module(&self.device, "adaptive.wgsl", shader_source(ocv));
            self.classify = Some(ClassPipelines::new(&self.device, &module));
        }
        if keeps_surface(&settings) != keeps_surface(&self.settings) {
            self.frame.surface = fresh.surface;
        }
        if fractional(&settings) != fractional(&self.settings) {
            self.frame.real = fresh.real;
        }
        (self.settings, self.derived) = (settings, derived);
        Ok(())
    }

    /// Sets the target variance `sigma0^2` of the steps recorded from now on (a frame
    /// budget governor, `spvg::budget::Governor`, moves it every frame):
    /// [`set_settings`](Self::set_settings) with that target and every other setting
    /// kept. The history's variance encoding stays as construction fixed it, so the stored
    /// variances keep their meaning when the target crosses a power of two
    /// (docs/algorithms.md §8.2), and the history stays valid.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::Param`] for a target the controller rejects (not finite and
    /// positive), [`AdaptiveError::SettingsBetweenSteps`] after a frame's estimate and
    /// before its update; the component is unchanged then.
    pub fn set_target_variance(&mut self, sigma0_sq: f32) -> Result<(), AdaptiveError> {
        let config = retargeted(&self.settings.config, sigma0_sq)?;
        self.set_settings(AdaptiveSettings {
            config,
            ..self.settings
        })
    }

    /// The history's texel encoding (`spvg::texel`): the variance scale fixed at
    /// construction and, for OCV, the CV scale. Decode [`history_texture`](Self::history_texture)
    /// with it.
    #[must_use]
    pub fn encoding(&self) -> TexelEncoding {
        self.derived.controller.enc
    }

    /// The controller block the component's steps read (`spvg_Params` of spvg-shaders),
    /// built from the settings: a renderer's own shader that calls the library with the
    /// component's controller (its zero-sample test, a demand curve over the component's
    /// histories) binds a copy of it.
    #[must_use]
    pub fn params_block(&self) -> &spvg_shaders::Params {
        &self.derived.block
    }

    /// Resizes the frame. Every history is invalid afterwards (docs/algorithms.md §2.3a:
    /// the frame size changed), so the next frame takes the disocclusion path everywhere.
    /// A resize between a frame's estimate and its update discards that estimate: the
    /// update then fails with [`AdaptiveError::ResizedBetweenSteps`] until a new estimate
    /// is recorded.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::FrameSize`]; the component is unchanged then.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), AdaptiveError> {
        check_size(width, height, self.device.limits().max_texture_dimension_2d)?;
        self.frame = Self::make_frame(&self.device, &self.settings, [width, height]);
        self.resized_between_steps = self.estimated || self.resized_between_steps;
        (self.width, self.height, self.read, self.estimated) = (width, height, 0, false);
        Ok(())
    }

    /// Invalidates every history (a camera cut): new zeroed textures, as after a resize.
    pub fn reset_history(&mut self) {
        self.frame = Self::make_frame(&self.device, &self.settings, self.size());
        (self.read, self.estimated) = (0, false);
    }

    /// Frame size `[width, height]`.
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        [self.width, self.height]
    }

    /// The count texture (`R32Uint`, frame size, `TEXTURE_BINDING | COPY_SRC`) that
    /// [`record_estimate`](Self::record_estimate) writes and the renderer's sampling pass
    /// reads (`texture_2d<u32>`, `textureLoad(count, p, 0).x`).
    #[must_use]
    pub fn count_texture(&self) -> &wgpu::Texture {
        &self.frame.count
    }

    /// The history texture holding the latest history (after an update: the one it wrote),
    /// `Rgba16Float`, `COPY_SRC`: the `spvg::texel::SpvgTexel16` layout with the history's
    /// age in the spare channel (0 where it was never written).
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

    /// The link texture the last [`record_estimate`](Self::record_estimate) wrote
    /// (`R32Uint`, frame size, `TEXTURE_BINDING | COPY_SRC`): per pixel one more than the
    /// row-major index of the previous frame's texel whose history the update continues,
    /// or 0 where the pixel has no valid history (disoccluded, entering the frame, outside
    /// the mask, or entering under the border prior, which lends only a count). Its twin
    /// is [`AdaptiveTwin::links`](super::AdaptiveTwin::links); read it for a debug view of
    /// the reprojection with [`util::read_texture`](crate::util::read_texture).
    #[must_use]
    pub fn link_texture(&self) -> &wgpu::Texture {
        &self.frame.link
    }
}

/// The controller's uniform buffer (binding 0 of both steps).
fn controller_buffer(device: &wgpu::Device, block: &spvg_shaders::Params) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("adaptive controller"),
        contents: bytemuck::bytes_of(block),
        usage: wgpu::BufferUsages::UNIFORM,
    })
}
