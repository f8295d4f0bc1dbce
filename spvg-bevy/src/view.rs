//! The render-world side of one camera: its `AdaptivePass`, the converted inputs and the
//! value texture, and what the user's pass reads from them.

use bevy::ecs::component::Component;
use bevy::math::Mat4;
use spvg_wgpu::adaptive::{AdaptiveError, AdaptivePass};

use crate::AdaptiveSampling;
use crate::convert::{
    LINEAR_DEPTH_FORMAT, MASK_FORMAT, MOTION_PIXELS_FORMAT, VALUE_FORMAT, texture,
};

/// The monitored value (and, for CCV and OCV, the control value) of a view, registered by
/// the user's render-world code on the view entity: the plugin's update step reads these
/// instead of [`SpvgView::value_texture`]. Each is the view size, `R32Float` or
/// `R16Float`, with `TEXTURE_BINDING` usage.
#[derive(Component, Clone, Debug)]
pub struct SpvgValue {
    /// The monitored value `fbar` per pixel.
    pub value: wgpu::Texture,
    /// The control value `G` (CCV, OCV), or `None`.
    pub control: Option<wgpu::Texture>,
}

/// A render-world component on each view whose camera has [`AdaptiveSampling`] (and runs):
/// the view's [`AdaptivePass`] and its inputs. The user's pass queries it (for example
/// `ViewQuery<&SpvgView>` in a `Core3d` system ordered
/// `.after(SpvgSystems::Estimate).before(SpvgSystems::Update)`) and reads
/// [`count_texture`](Self::count_texture).
///
/// It is created at the view's physical viewport size, resized with the viewport (the
/// histories start over, the pipelines are kept), rebuilt when the settings change (a new
/// target variance or dilation is applied in place) and dropped with the camera, or when
/// the camera loses [`AdaptiveSampling`] or a requirement.
#[derive(Component, Debug)]
pub struct SpvgView {
    pass: AdaptivePass,
    settings: AdaptiveSampling,
    /// Ping-pong converted depths and masks; `current` indexes this frame's.
    depth: [wgpu::Texture; 2],
    mask: [wgpu::Texture; 2],
    motion: wgpu::Texture,
    value: wgpu::Texture,
    count_view: wgpu::TextureView,
    current: usize,
    pub(crate) view_from_clip: Mat4,
    frames: u64,
}

impl SpvgView {
    pub(crate) fn new(
        device: &wgpu::Device,
        settings: &AdaptiveSampling,
        size: [u32; 2],
    ) -> Result<Self, AdaptiveError> {
        let mut pass =
            AdaptivePass::new(device, settings.config, settings.control, size[0], size[1])?;
        pass.set_reprojection(settings.reprojection);
        pass.set_count_dilation(settings.dilation)?;
        let count_view = pass.count_texture().create_view(&Default::default());
        let pair = |label: &str, format| {
            [
                texture(device, &format!("{label} a"), format, size),
                texture(device, &format!("{label} b"), format, size),
            ]
        };
        Ok(Self {
            depth: pair("spvg-bevy linear depth", LINEAR_DEPTH_FORMAT),
            mask: pair("spvg-bevy mask", MASK_FORMAT),
            motion: texture(device, "spvg-bevy motion", MOTION_PIXELS_FORMAT, size),
            value: texture(device, "spvg-bevy value", VALUE_FORMAT, size),
            count_view,
            pass,
            settings: settings.clone(),
            current: 0,
            view_from_clip: Mat4::IDENTITY,
            frames: 0,
        })
    }

    /// Resizes to a new viewport size: the pass's histories start over (its frame size
    /// changed), the converted inputs and the value texture are made anew; the pipelines
    /// are kept.
    pub(crate) fn resize(
        &mut self,
        device: &wgpu::Device,
        size: [u32; 2],
    ) -> Result<(), AdaptiveError> {
        self.pass.resize(size[0], size[1])?;
        let fresh = |label: &str, format| texture(device, label, format, size);
        self.depth = [
            fresh("spvg-bevy linear depth a", LINEAR_DEPTH_FORMAT),
            fresh("spvg-bevy linear depth b", LINEAR_DEPTH_FORMAT),
        ];
        self.mask = [
            fresh("spvg-bevy mask a", MASK_FORMAT),
            fresh("spvg-bevy mask b", MASK_FORMAT),
        ];
        self.motion = fresh("spvg-bevy motion", MOTION_PIXELS_FORMAT);
        self.value = fresh("spvg-bevy value", VALUE_FORMAT);
        self.count_view = self.pass.count_texture().create_view(&Default::default());
        Ok(())
    }

    /// Applies new settings: `Ok(true)` when they were applied in place, `Ok(false)` when
    /// the pass must be rebuilt.
    pub(crate) fn apply(&mut self, settings: &AdaptiveSampling) -> Result<bool, AdaptiveError> {
        if *settings == self.settings {
            return Ok(true);
        }
        let old = &self.settings;
        let target = settings.config.target_variance();
        let same_but_target = old
            .config
            .to_builder()
            .target_variance(target)
            .build()
            .is_ok_and(|c| c == settings.config);
        if !same_but_target
            || settings.control != old.control
            || settings.reprojection != old.reprojection
        {
            return Ok(false);
        }
        self.pass.set_target_variance(target)?;
        self.pass.set_count_dilation(settings.dilation)?;
        self.settings = settings.clone();
        Ok(true)
    }

    /// Moves to the next frame's ping-pong textures.
    pub(crate) fn advance(&mut self) {
        self.current ^= 1;
        self.frames += 1;
    }

    pub(crate) fn pass_mut(&mut self) -> &mut AdaptivePass {
        &mut self.pass
    }

    /// The settings the pass runs with.
    #[must_use]
    pub fn settings(&self) -> &AdaptiveSampling {
        &self.settings
    }

    /// The view's [`AdaptivePass`] (its histories, link texture, encoding).
    #[must_use]
    pub fn adaptive_pass(&self) -> &AdaptivePass {
        &self.pass
    }

    /// The frame size `[width, height]` (the camera's physical viewport size).
    #[must_use]
    pub fn size(&self) -> [u32; 2] {
        self.pass.size()
    }

    /// How many frames the estimate has converted inputs for since the pass was made.
    #[must_use]
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// This frame's per-pixel sample counts (`R32Uint`, `TEXTURE_BINDING | COPY_SRC`;
    /// `texture_2d<u32>`, `textureLoad(count, p, 0).x`): 0 outside the mask, else in
    /// `[min_samples, max_samples]` of the configuration.
    #[must_use]
    pub fn count_texture(&self) -> &wgpu::Texture {
        self.pass.count_texture()
    }

    /// A view of [`count_texture`](Self::count_texture) for a bind group.
    #[must_use]
    pub fn count_view(&self) -> &wgpu::TextureView {
        &self.count_view
    }

    /// The plugin-owned monitored-value texture the update step reads unless a
    /// [`SpvgValue`] is registered: `R32Float`, `TEXTURE_BINDING | STORAGE_BINDING |
    /// RENDER_ATTACHMENT | COPY_SRC`. The user's pass writes the luminance of its Monte
    /// Carlo result here.
    #[must_use]
    pub fn value_texture(&self) -> &wgpu::Texture {
        &self.value
    }

    /// This frame's linear depth as the estimate read it (`R32Float`, positive; `1e30`
    /// where there is no geometry).
    #[must_use]
    pub fn linear_depth(&self) -> &wgpu::Texture {
        &self.depth[self.current]
    }

    /// The previous frame's linear depth as the estimate read it.
    #[must_use]
    pub fn previous_linear_depth(&self) -> &wgpu::Texture {
        &self.depth[self.current ^ 1]
    }

    /// This frame's motion vectors in pixels, current minus previous position, `+y` down
    /// (`Rg32Float`).
    #[must_use]
    pub fn motion_pixels(&self) -> &wgpu::Texture {
        &self.motion
    }

    /// This frame's mask (`R32Uint`, non-zero where the pass runs).
    #[must_use]
    pub fn mask(&self) -> &wgpu::Texture {
        &self.mask[self.current]
    }

    /// The previous frame's mask.
    #[must_use]
    pub fn previous_mask(&self) -> &wgpu::Texture {
        &self.mask[self.current ^ 1]
    }
}
