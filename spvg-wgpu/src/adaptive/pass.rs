//! The component on a wgpu device: its pipelines, its textures (histories, count, link)
//! and uniform blocks, and its settings. The recorded steps are in `record.rs`.

use spvg::SpvgConfig;
use spvg::reproject::Reprojection;
use spvg::texel::TexelEncoding;
use wgpu::util::DeviceExt as _;
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use super::controller::Controller;
use super::gpu::{compute_pipeline, shader_module, texture_2d as texture};
use super::inputs::{COUNT_FORMAT, HISTORY_FORMAT, check_size};
use super::layout::{dilate_entries, estimate_entries, update_entries};
use super::params::{
    AdaptiveParams, FLAG_BORDER_MAXIMUM, FLAG_BORDER_PRIOR, FLAG_CONTROL, FLAG_FOOTPRINT,
    FLAG_NEIGHBOUR_PRIOR, PARAMS_BLOCKS, component_ocv, controller_block, params_flags, retargeted,
};
use super::{AdaptiveError, Control, shader_source};

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
    /// Indexed by `params_index(flags)` (masks, gamma, reprojected depth, guide bound).
    pub(super) params: [wgpu::Buffer; PARAMS_BLOCKS],
}

/// What the per-size resources depend on besides the size.
#[derive(Clone, Copy, Debug)]
pub(super) struct FrameSettings {
    /// The count dilation radius.
    dilation: u32,
    /// The depth-aware neighbour prior.
    prior: bool,
    /// Whether this frame's depth is kept for the update or the dilation (the spatial
    /// variance of young histories, the neighbour prior): the surface texture's full size.
    surface: bool,
}

/// The reusable adaptive-sampling component: SPVG count control with motion-vector
/// reprojection and disocclusion, recorded into the caller's command encoder. See the
/// [module docs](super) for the bindings, formats and per-frame order.
///
/// Every `f16` history store rounds to nearest, ties to even
/// ([`STORE_ROUNDING`](super::STORE_ROUNDING), `spvg::texel::Rounding::Nearest`): the
/// shader rounds explicitly (`spvg_to_f16`) before the store, so the stored bits do not
/// depend on the driver's own f32-to-f16 conversion (lavapipe's truncates), and
/// [`AdaptiveTwin`](super::AdaptiveTwin) stores the same bits.
#[derive(Debug)]
pub struct AdaptivePass {
    pub(super) device: wgpu::Device,
    pub(super) config: SpvgConfig<f32>,
    pub(super) control: Control,
    /// The target the history's variance encoding was fixed by (the configuration's at
    /// construction).
    pub(super) encoding_target: f32,
    pub(super) encoding: TexelEncoding,
    pub(super) reprojection: Reprojection<f32>,
    /// Radius of the count dilation; 0 = off.
    pub(super) dilation: u32,
    /// The depth-aware neighbour prior of the dilation (`spvg::dilation::dilated_count_with_prior`).
    pub(super) neighbour_prior: bool,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) controller: wgpu::Buffer,
    pub(super) estimate_layout: wgpu::BindGroupLayout,
    pub(super) update_layout: wgpu::BindGroupLayout,
    pub(super) dilate_layout: wgpu::BindGroupLayout,
    pub(super) estimate: wgpu::ComputePipeline,
    pub(super) dilate: wgpu::ComputePipeline,
    pub(super) update: wgpu::ComputePipeline,
    pub(super) dummy_uint: wgpu::Texture,
    pub(super) dummy_float: wgpu::Texture,
    pub(super) frame: Frame,
    /// Index of the history read this frame.
    pub(super) read: usize,
    pub(super) estimated: bool,
    /// A resize discarded this frame's estimate (the update then names the resize).
    pub(super) resized_between_steps: bool,
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
        let controller = controller_buffer(device, &block);
        let module = shader_module(device, "adaptive.wgsl", shader_source());
        let ocv = component_ocv(&control).is_some();
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
        let update_entry = if ocv {
            "adaptive_update_ocv"
        } else {
            "adaptive_update"
        };
        let update = pipeline(&update_layout, update_entry);
        let reprojection = Reprojection::default();
        let settings = FrameSettings {
            dilation: 0,
            prior: false,
            surface: config.spatial_variance() > 0,
        };
        let frame = Self::make_frame(device, &control, &reprojection, settings, [width, height]);
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
            encoding: Controller::new(&block)?.enc,
            reprojection,
            dilation: 0,
            neighbour_prior: true,
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
            resized_between_steps: false,
        })
    }

    fn make_frame(
        device: &wgpu::Device,
        control: &Control,
        reprojection: &Reprojection<f32>,
        settings: FrameSettings,
        [width, height]: [u32; 2],
    ) -> Frame {
        let FrameSettings {
            dilation,
            prior,
            surface,
        } = settings;
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
            let mut flags = params_flags(k);
            if *control == Control::Ccv {
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
            if prior {
                flags |= FLAG_NEIGHBOUR_PRIOR;
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
            cv: component_ocv(control)
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
                if surface { [width, height] } else { [1, 1] },
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
            self.controller = controller_buffer(&self.device, &block);
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
            self.frame_settings(),
            self.size(),
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
            FrameSettings {
                dilation: radius,
                ..self.frame_settings()
            },
            self.size(),
        );
        self.frame.params = fresh.params;
        self.frame.raw_count = fresh.raw_count;
        self.dilation = radius;
        Ok(())
    }

    /// Turns the depth-aware neighbour prior on or off (docs/algorithms.md §2.5, on by
    /// default, measured in §8.4): under count dilation, a pixel without history takes the mean count of
    /// the pixels within `spvg::dilation::PRIOR_RADIUS` (or the dilation's radius, if
    /// larger) that have history and pass the reprojection's depth test against its depth
    /// (`spvg::dilation::dilated_count_with_prior`), instead of its own `beta_min`. It
    /// acts only with a dilation radius (it runs in the dilation's step); the component
    /// then keeps this frame's depth in one more `R32Float` texture. The history stays
    /// valid; it applies from the next recorded estimate.
    pub fn set_neighbour_prior(&mut self, on: bool) {
        self.neighbour_prior = on;
        let fresh = Self::make_frame(
            &self.device,
            &self.control,
            &self.reprojection,
            self.frame_settings(),
            self.size(),
        );
        self.frame.params = fresh.params;
        self.frame.surface = fresh.surface;
    }

    /// Whether the depth-aware neighbour prior is on.
    #[must_use]
    pub fn neighbour_prior(&self) -> bool {
        self.neighbour_prior
    }

    /// The frame resources' settings of the component as it is now set.
    fn frame_settings(&self) -> FrameSettings {
        FrameSettings {
            dilation: self.dilation,
            prior: self.neighbour_prior,
            surface: self.neighbour_prior || self.config.spatial_variance() > 0,
        }
    }

    /// The count dilation radius (0: off).
    #[must_use]
    pub fn count_dilation(&self) -> u32 {
        self.dilation
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
        self.frame = Self::make_frame(
            &self.device,
            &self.control,
            &self.reprojection,
            self.frame_settings(),
            [width, height],
        );
        self.resized_between_steps = self.estimated || self.resized_between_steps;
        (self.width, self.height, self.read, self.estimated) = (width, height, 0, false);
        Ok(())
    }

    /// Invalidates every history (a camera cut): new zeroed textures, as after a resize.
    pub fn reset_history(&mut self) {
        self.frame = Self::make_frame(
            &self.device,
            &self.control,
            &self.reprojection,
            self.frame_settings(),
            self.size(),
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

    /// The link texture the last [`record_estimate`](Self::record_estimate) wrote
    /// (`R32Uint`, frame size, `TEXTURE_BINDING | COPY_SRC`): per pixel one more than the
    /// row-major index of the previous frame's texel whose history the update continues,
    /// or 0 where the pixel has no valid history (disoccluded, entering the frame, outside
    /// the mask, or entering under the border prior, which lends only a count). Its twin
    /// is [`AdaptiveTwin::links`](super::AdaptiveTwin::links); read it for a debug view of
    /// the reprojection with [`read_texture`](super::read_texture).
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
