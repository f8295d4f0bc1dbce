//! The render-world side of one camera: its `AdaptivePass`, the converted inputs, the
//! value textures, and what the user's pass reads and marks.

use bevy::ecs::component::Component;
use bevy::render::render_resource::{Texture, TextureView};
use bevy::render::renderer::RenderDevice;
use spvg_wgpu::adaptive::{AdaptiveError, AdaptivePass, EstimateInputs, Masks, UpdateInputs};

use crate::AdaptiveSampling;
use crate::configure::{Configured, build, configure};
use crate::convert::{
    ConvertBindings, ConvertBlock, ConvertPipeline, LINEAR_DEPTH_FORMAT, MASK_FORMAT,
    MOTION_PIXELS_FORMAT, VALUE_FORMAT, texture,
};

/// The monitored value (and, for CCV and OCV, the control value) of a view, registered by
/// the user's render-world code on the view entity: the plugin's update step reads these
/// instead of [`SpvgView::value_target`]. Each is the view's frame size
/// ([`SpvgView::size`], the viewport), `R32Float` or `R16Float`, with `TEXTURE_BINDING`
/// usage. The update still runs only on frames marked with
/// [`SpvgView::mark_value_written`].
#[derive(Component, Clone, Debug)]
pub struct SpvgValue {
    /// The monitored value `fbar` per pixel.
    pub value: Texture,
    /// The control value `G` (CCV, OCV), or `None`.
    pub control: Option<Texture>,
}

/// Where a view sits on its render target, in physical pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Geometry {
    /// The viewport's origin on the target.
    pub(crate) origin: [u32; 2],
    /// The viewport's size: the pass's frame size.
    pub(crate) size: [u32; 2],
    /// The render target's size (Bevy's prepass and main textures).
    pub(crate) target: [u32; 2],
}

impl Geometry {
    fn covers_target(&self) -> bool {
        self.origin == [0, 0] && self.size == self.target
    }
}

/// The frame-size textures of a view (the viewport's size).
#[derive(Debug)]
struct FrameTextures {
    count: Texture,
    count_view: TextureView,
    /// Ping-pong converted depths and masks (see [`SpvgView`] for which is which).
    depth: [(Texture, TextureView); 2],
    mask: [(Texture, TextureView); 2],
    motion: (Texture, TextureView),
    /// The pass's link texture and a view of it.
    link: (Texture, TextureView),
    /// Views of the pass's two history textures (it alternates between them), made as
    /// each is first read.
    history: Vec<(wgpu::Texture, TextureView)>,
}

impl FrameTextures {
    fn new(device: &RenderDevice, pass: &AdaptivePass, geometry: Geometry) -> Self {
        let size = geometry.size;
        let count = Texture::from(pass.count_texture().clone());
        let count_view = count.create_view(&Default::default());
        let link = Texture::from(pass.link_texture().clone());
        let link_view = link.create_view(&Default::default());
        let pair = |label, format| {
            [
                texture(device, label, format, size),
                texture(device, label, format, size),
            ]
        };
        Self {
            count,
            count_view,
            depth: pair("spvg-bevy linear depth", LINEAR_DEPTH_FORMAT),
            mask: pair("spvg-bevy mask", MASK_FORMAT),
            motion: texture(device, "spvg-bevy motion", MOTION_PIXELS_FORMAT, size),
            link: (link, link_view),
            history: Vec::with_capacity(2),
        }
    }
}

/// The frame-size value the update reads, copied out of the value target's viewport;
/// `None` when the viewport is the whole target and the update reads the value target
/// itself.
fn frame_value(device: &RenderDevice, geometry: Geometry) -> Option<Texture> {
    (!geometry.covers_target())
        .then(|| texture(device, "spvg-bevy value", VALUE_FORMAT, geometry.size).0)
}

/// A render-world component on each view whose camera has [`AdaptiveSampling`] (and
/// runs): the view's [`AdaptivePass`], its inputs, and what a user's pass reads and writes.
///
/// # Writing your own pass
///
/// An [`AdaptiveEffect`](crate::AdaptiveEffect) does all of this for you. A pass of your
/// own is a `Core3d` system `.in_set(SpvgSystems::Effect)` (after the estimate and the main
/// pass, before the update and Bevy's TAA) that queries `ViewQuery<&mut SpvgView>` and:
///
/// 1. reads [`count_texture`](Self::count_texture) at the **viewport** pixel (the fragment
///    position minus the viewport origin, [`origin`](Self::origin));
/// 2. writes the luminance of its Monte Carlo result to
///    [`value_target`](Self::value_target) at the **render target** pixel, the same texel
///    as its colour (the value target is the size of the target, so it can be a second
///    colour attachment beside Bevy's main texture), or registers its own frame-size
///    textures with [`SpvgValue`];
/// 3. calls [`mark_value_written`](Self::mark_value_written) once it has recorded that
///    write. The update runs only on marked frames: a pass that returns early (its
///    pipeline still compiling, say) leaves the frame unmarked, and the history, the
///    previous depth and the previous mask stay those of the last updated frame.
///
/// It is created at the view's physical viewport size, resized with the viewport (the
/// histories start over, the pipelines are kept), rebuilt when the settings change (a new
/// target variance, dilation or reprojection rule is applied in place) and dropped with the
/// camera, or when the camera loses [`AdaptiveSampling`] or a requirement.
#[derive(Component, Debug)]
pub struct SpvgView {
    pass: AdaptivePass,
    settings: AdaptiveSampling,
    geometry: Geometry,
    frame: FrameTextures,
    frame_value: Option<Texture>,
    /// The render-target-size value texture the user's pass writes.
    value_target: (Texture, TextureView),
    convert: ConvertBindings,
    /// The ping-pong slot of the last updated frame, and this frame's (the other one once
    /// the estimate started the frame).
    committed: usize,
    current: usize,
    estimated: bool,
    value_written: bool,
    frames: u64,
    updates: u64,
}

impl SpvgView {
    pub(crate) fn new(
        device: &RenderDevice,
        settings: &AdaptiveSampling,
        geometry: Geometry,
    ) -> Result<Self, AdaptiveError> {
        let pass = build(device.wgpu_device(), settings, geometry.size)?;
        Ok(Self::with_pass(device, pass, settings, geometry))
    }

    fn with_pass(
        device: &RenderDevice,
        pass: AdaptivePass,
        settings: &AdaptiveSampling,
        geometry: Geometry,
    ) -> Self {
        Self {
            frame: FrameTextures::new(device, &pass, geometry),
            frame_value: frame_value(device, geometry),
            value_target: texture(
                device,
                "spvg-bevy value target",
                VALUE_FORMAT,
                geometry.target,
            ),
            convert: ConvertBindings::new(device.wgpu_device()),
            pass,
            settings: settings.clone(),
            geometry,
            committed: 1,
            current: 0,
            estimated: false,
            value_written: false,
            frames: 0,
            updates: 0,
        }
    }

    /// Follows the camera's viewport and target: a new viewport size resizes the pass (the
    /// histories start over) and makes the frame textures anew; a new target size makes
    /// the value target anew; a new origin only moves where the conversion reads.
    pub(crate) fn set_geometry(
        &mut self,
        device: &RenderDevice,
        geometry: Geometry,
    ) -> Result<(), AdaptiveError> {
        let old = self.geometry;
        if geometry.size != old.size {
            self.pass.resize(geometry.size[0], geometry.size[1])?;
            // The resize invalidated every history: no previous slot to keep either.
            (self.committed, self.current) = (1, 0);
            self.frame = FrameTextures::new(device, &self.pass, geometry);
            self.convert.clear();
        }
        if geometry.size != old.size || geometry.covers_target() != old.covers_target() {
            self.frame_value = frame_value(device, geometry);
        }
        if geometry.target != old.target {
            self.value_target = texture(
                device,
                "spvg-bevy value target",
                VALUE_FORMAT,
                geometry.target,
            );
        }
        self.geometry = geometry;
        Ok(())
    }

    /// Applies new settings: `Ok(None)` when they were applied in place (or deferred to the
    /// next frame), `Ok(Some(view))` with a new view when they need a new pass.
    pub(crate) fn apply(
        &mut self,
        device: &RenderDevice,
        settings: &AdaptiveSampling,
    ) -> Result<Option<Self>, AdaptiveError> {
        if *settings == self.settings {
            return Ok(None);
        }
        match configure(
            device.wgpu_device(),
            Some(&mut self.pass),
            settings,
            self.geometry.size,
        )? {
            Configured::Applied => {
                self.settings = settings.clone();
                Ok(None)
            }
            Configured::Deferred => Ok(None),
            Configured::New(pass) => Ok(Some(Self::with_pass(
                device,
                *pass,
                settings,
                self.geometry,
            ))),
        }
    }

    /// Starts a frame: this frame's converted inputs go to the slot after the last updated
    /// frame's, and nothing is estimated or written yet.
    pub(crate) fn begin_frame(&mut self) {
        self.current = self.committed ^ 1;
        self.estimated = false;
        self.value_written = false;
    }

    /// Whether this frame's estimate was recorded (the counts are this frame's).
    #[must_use]
    pub fn estimated(&self) -> bool {
        self.estimated
    }

    /// Whether the update will run this frame: an estimate, and a value marked written.
    pub(crate) fn ready_for_update(&self) -> bool {
        self.estimated && self.value_written
    }

    /// Ends a frame; `updated`: its update was recorded, so its inputs become the previous
    /// frame's of the next estimate.
    pub(crate) fn end_frame(&mut self, updated: bool) {
        if updated {
            self.committed = self.current;
            self.updates += 1;
        }
        self.estimated = false;
        self.value_written = false;
    }

    pub(crate) fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// Writes the conversion's uniform block for this frame's estimate.
    pub(crate) fn write_convert(&mut self, queue: &wgpu::Queue, block: ConvertBlock) {
        self.convert.write(queue, block);
    }

    /// Records the conversion of Bevy's prepass outputs (`[depth, motion]`) into this
    /// frame's slot, then the component's estimate.
    pub(crate) fn record_estimate(
        &mut self,
        convert: &ConvertPipeline,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        prepass: [&TextureView; 2],
    ) -> Result<(), AdaptiveError> {
        let (now, before) = (self.current, self.current ^ 1);
        let f = &self.frame;
        let out = [&f.depth[now].1, &f.motion.1, &f.mask[now].1];
        convert.record(device, encoder, &mut self.convert, now, prepass, out);
        let inputs = EstimateInputs::new(&f.motion.0, &f.depth[now].0, &f.depth[before].0)
            .with_masks(Some(Masks {
                current: &f.mask[now].0,
                previous: &f.mask[before].0,
            }));
        self.pass.record_estimate(encoder, &inputs)?;
        self.estimated = true;
        self.frames += 1;
        Ok(())
    }

    /// Records the component's update from the registered value, or from the viewport's
    /// part of the value target (copied out first when the viewport is not the whole
    /// target).
    pub(crate) fn record_update(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        registered: Option<&SpvgValue>,
    ) -> Result<(), AdaptiveError> {
        let value: &wgpu::Texture = match (registered, &self.frame_value) {
            (Some(v), _) => &v.value,
            (None, None) => &self.value_target.0,
            (None, Some(frame)) => {
                let [x, y] = self.geometry.origin;
                let [width, height] = self.geometry.size;
                encoder.copy_texture_to_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &self.value_target.0,
                        mip_level: 0,
                        origin: wgpu::Origin3d { x, y, z: 0 },
                        aspect: wgpu::TextureAspect::All,
                    },
                    frame.as_image_copy(),
                    wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                );
                frame
            }
        };
        let inputs =
            UpdateInputs::new(value).with_control(registered.and_then(|v| v.control.as_deref()));
        self.pass.record_update(encoder, &inputs)
    }

    /// Marks this frame's monitored value as written (to [`value_target`](Self::value_target)
    /// or to the registered [`SpvgValue`]): the update step runs this frame. Call it after
    /// recording the write, in a system ordered before `SpvgSystems::Update`
    /// (`.in_set(SpvgSystems::Effect)` does that). Without it the update skips the frame and
    /// every history stays as it was.
    pub fn mark_value_written(&mut self) {
        self.value_written = true;
    }

    /// The settings the pass runs with.
    #[must_use]
    pub fn settings(&self) -> &AdaptiveSampling {
        &self.settings
    }

    /// The view's [`AdaptivePass`] (its histories, link texture, encoding; its textures are
    /// `wgpu` types, [`spvg_bevy::wgpu`](crate::wgpu)).
    #[must_use]
    pub fn adaptive_pass(&self) -> &AdaptivePass {
        &self.pass
    }

    /// The frame size `[width, height]`: the camera's physical viewport size.
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        self.geometry.size
    }

    /// The viewport's origin on the render target, in physical pixels: a fragment at
    /// target pixel `q` reads its count at `q - origin`.
    #[must_use]
    pub fn origin(&self) -> [u32; 2] {
        self.geometry.origin
    }

    /// The render target's size in physical pixels (the size of Bevy's prepass and main
    /// textures, and of [`value_target`](Self::value_target)).
    #[must_use]
    pub fn target_size(&self) -> [u32; 2] {
        self.geometry.target
    }

    /// How many frames had an estimate since the pass was made.
    #[must_use]
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// How many frames had an update since the pass was made (those marked with
    /// [`mark_value_written`](Self::mark_value_written) after an estimate).
    #[must_use]
    pub fn updates(&self) -> u64 {
        self.updates
    }

    /// This frame's per-pixel sample counts, frame size (`R32Uint`, `TEXTURE_BINDING |
    /// COPY_SRC`; `texture_2d<u32>`, `textureLoad(count, q - origin, 0).x`): 0 outside the
    /// mask, else in `[min_samples, max_samples]` of the configuration (from 0 with a
    /// fractional floor, where a pixel with history skips a frame).
    #[must_use]
    pub fn count_texture(&self) -> &Texture {
        &self.frame.count
    }

    /// A view of [`count_texture`](Self::count_texture) for a bind group.
    #[must_use]
    pub fn count_view(&self) -> &TextureView {
        &self.frame.count_view
    }

    /// A view of the pass's link texture (`R32Uint`, frame size; `texture_2d<u32>`): per
    /// viewport pixel one more than the row-major index of the texel of
    /// [`history_view`](Self::history_view) whose history this frame continues, 0 where the
    /// pixel has none ([`AdaptivePass::link_texture`]). This frame's once estimated.
    #[must_use]
    pub fn link_view(&self) -> &TextureView {
        &self.frame.link.1
    }

    /// A view of the history the last update wrote (`Rgba16Float` or `Rgba32Float`, frame
    /// size; `texture_2d<f32>`, not filterable): channel 0 is each pixel's EMA of the
    /// monitored value (`spvg::texel::SpvgTexel16`). Between the estimate and the update
    /// it is the previous frame's, which [`link_view`](Self::link_view) indexes: a pixel
    /// whose count is 0 with a link (a fractional count's skipped frame) can show the
    /// mean there instead of a sample.
    pub fn history_view(&mut self) -> &TextureView {
        let current = self.pass.history_texture();
        let k = match self.frame.history.iter().position(|(t, _)| t == current) {
            Some(k) => k,
            None => {
                let view = Texture::from(current.clone()).create_view(&Default::default());
                // Two at most: the pass alternates between two textures.
                if self.frame.history.len() >= 2 {
                    self.frame.history.remove(0);
                }
                self.frame.history.push((current.clone(), view));
                self.frame.history.len() - 1
            }
        };
        &self.frame.history[k].1
    }

    /// The monitored-value texture the user's pass writes (unless a [`SpvgValue`] is
    /// registered): `R32Float`, the **render target's** size, `TEXTURE_BINDING |
    /// STORAGE_BINDING | RENDER_ATTACHMENT | COPY_SRC | COPY_DST`. Write the luminance of
    /// the Monte Carlo result at the target pixel (the texel of its colour); the plugin
    /// reads the viewport's part.
    #[must_use]
    pub fn value_target(&self) -> &Texture {
        &self.value_target.0
    }

    /// A view of [`value_target`](Self::value_target) for a colour attachment or bind group.
    #[must_use]
    pub fn value_target_view(&self) -> &TextureView {
        &self.value_target.1
    }

    /// The frame-size monitored value the update reads: the viewport's part of
    /// [`value_target`](Self::value_target) (that texture itself when the viewport is the
    /// whole target), complete once the update step has run.
    #[must_use]
    pub fn value_texture(&self) -> &Texture {
        self.frame_value.as_ref().unwrap_or(&self.value_target.0)
    }

    /// This frame's linear depth as the estimate read it (`R32Float`, positive; `1e30`
    /// where there is no geometry).
    #[must_use]
    pub fn linear_depth(&self) -> &Texture {
        &self.frame.depth[self.current].0
    }

    /// The linear depth of the last frame before this one that was updated: the previous
    /// depth of this frame's estimate.
    #[must_use]
    pub fn previous_linear_depth(&self) -> &Texture {
        &self.frame.depth[self.current ^ 1].0
    }

    /// This frame's motion vectors in pixels, current minus previous position, `+y` down
    /// (`Rg32Float`).
    #[must_use]
    pub fn motion_pixels(&self) -> &Texture {
        &self.frame.motion.0
    }

    /// This frame's mask (`R32Uint`, non-zero where the pass runs).
    #[must_use]
    pub fn mask(&self) -> &Texture {
        &self.frame.mask[self.current].0
    }

    /// The mask of the last updated frame before this one: the previous mask of this
    /// frame's estimate.
    #[must_use]
    pub fn previous_mask(&self) -> &Texture {
        &self.frame.mask[self.current ^ 1].0
    }
}
