//! The component's inputs: the textures a renderer passes to each step, their accepted
//! formats, and the checks that name a wrong one before anything is bound.

use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

use super::AdaptiveError;

/// Formats accepted for the motion vectors.
pub(crate) const MOTION_FORMATS: &[Tf] = &[Tf::Rg32Float, Tf::Rg16Float];
/// Formats accepted for depths, the distant-energy ratio, the monitored and control values.
pub(crate) const SCALAR_FORMATS: &[Tf] = &[Tf::R32Float, Tf::R16Float];
/// Formats accepted for masks (any non-zero value is "set").
pub(crate) const MASK_FORMATS: &[Tf] = &[Tf::R8Uint, Tf::R16Uint, Tf::R32Uint];
/// Format of the count texture the estimate writes.
pub(crate) const COUNT_FORMAT: Tf = Tf::R32Uint;
/// Format of the history textures (`spvg::texel::SpvgTexel16`, `CvTexel16`).
pub(crate) const HISTORY_FORMAT: Tf = Tf::Rgba16Float;

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

/// Inputs of [`AdaptivePass::record_estimate`](super::AdaptivePass::record_estimate);
/// each texture is the frame size, one mip level or more (mip 0 is read), single-sampled,
/// with `TEXTURE_BINDING` usage.
///
/// Built with [`new`](Self::new) from the three required textures, each optional input
/// added with its `with_*` method; the struct is `#[non_exhaustive]`, so an input added in
/// a later version (as `resolve_weight` was) is `None` for code that does not set it
/// instead of a compile error in every literal. The fields stay public for reading and
/// assignment.
///
/// ```no_run
/// # fn f<'a>(motion: &'a wgpu::Texture, depth: &'a wgpu::Texture, previous_depth: &'a wgpu::Texture,
/// #          gamma: &'a wgpu::Texture) -> spvg_wgpu::adaptive::EstimateInputs<'a> {
/// use spvg_wgpu::adaptive::EstimateInputs;
/// EstimateInputs::new(motion, depth, previous_depth).with_gamma(Some(gamma))
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct EstimateInputs<'a> {
    /// Motion vectors in the convention of `spvg::reproject`: `Rg32Float` or
    /// `Rg16Float`.
    pub motion: &'a wgpu::Texture,
    /// This frame's linear depth (positive; see `spvg::reproject` for which depth):
    /// `R32Float` or `R16Float`.
    pub depth: &'a wgpu::Texture,
    /// The previous frame's linear depth: `R32Float` or `R16Float`.
    pub previous_depth: &'a wgpu::Texture,
    /// The reprojected depth, or `None`: per pixel, the linear depth of this pixel's
    /// surface point as the previous camera saw it (the previous frame's view applied to
    /// this frame's world position, the point moved back along its own motion where it
    /// moves). Where it is given, the depth test compares it, instead of `depth`, with
    /// `previous_depth` at the reprojected texel (`spvg::reproject`), so a dolly or zoom
    /// that changes the depth by more than the tolerance per frame keeps its histories:
    /// `R32Float` or `R16Float`.
    pub reprojected_depth: Option<&'a wgpu::Texture>,
    /// The pass masks, or `None` when every pixel is covered: `R8Uint`, `R16Uint` or `R32Uint`.
    pub masks: Option<Masks<&'a wgpu::Texture>>,
    /// The per-pixel distant-energy ratio `gamma` (docs/algorithms.md §2.4), or `None` for
    /// passes without the near/far split (then `gamma = 1`): `R32Float` or `R16Float`.
    pub gamma: Option<&'a wgpu::Texture>,
    /// The resolve's weight on this frame per pixel, or `None`: for the resolved-image
    /// rule (`spvg::SpvgConfigBuilder::resolve_weight`, docs/algorithms.md §8.7), the
    /// weight the renderer's temporal resolve will give the current frame at the pixel
    /// (its blend weight; 1 where it rejected its history). A texel in `(0, 1]` is taken
    /// as it is (above 1 as 1); NaN, 0 or less and infinities mean "none" there, and the
    /// history's age stands in for it, as everywhere when this is `None`. Read only where
    /// the rule is on: `R32Float` or `R16Float`.
    pub resolve_weight: Option<&'a wgpu::Texture>,
}

/// Inputs of [`AdaptivePass::record_update`](super::AdaptivePass::record_update): the
/// frame size, `R32Float` or `R16Float`, `TEXTURE_BINDING` usage.
///
/// Built with [`new`](Self::new) from the monitored value, each optional input added with
/// its `with_*` method; `#[non_exhaustive]` for the reason given on [`EstimateInputs`].
///
/// ```no_run
/// # fn f<'a>(value: &'a wgpu::Texture, control: &'a wgpu::Texture) -> spvg_wgpu::adaptive::UpdateInputs<'a> {
/// use spvg_wgpu::adaptive::UpdateInputs;
/// UpdateInputs::new(value).with_control(Some(control))
/// # }
/// ```
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct UpdateInputs<'a> {
    /// The monitored value: the luminance of the pass's Monte Carlo result, `fbar` (for
    /// passes with the near/far split, the distant part only). Negative values are taken
    /// as they are (see [`record_update`](super::AdaptivePass::record_update)).
    pub value: &'a wgpu::Texture,
    /// The control value `G` (CCV and OCV; ignored by AS).
    pub control: Option<&'a wgpu::Texture>,
    /// The TAA guide, or `None`: per pixel the renderer's resolved temporal history `C_t`
    /// (reprojected, rejected on disocclusion and clamped to this frame's neighbourhood,
    /// before its blend with this frame), in the space of `value`. Where it is given the
    /// variance follows `value - guide` instead of the deviation from the history's own
    /// mean (`spvg::SpvgConfig::update_guided`, docs/algorithms.md §8.5); a non-finite
    /// guide texel falls back to the unguided update there: `R32Float` or `R16Float`.
    pub guide: Option<&'a wgpu::Texture>,
}

impl<'a> EstimateInputs<'a> {
    /// The required textures: the motion vectors, this frame's and the previous frame's
    /// linear depth ([`motion`](Self::motion), [`depth`](Self::depth),
    /// [`previous_depth`](Self::previous_depth)); every optional input is `None`.
    #[must_use]
    pub fn new(
        motion: &'a wgpu::Texture,
        depth: &'a wgpu::Texture,
        previous_depth: &'a wgpu::Texture,
    ) -> Self {
        Self {
            motion,
            depth,
            previous_depth,
            reprojected_depth: None,
            masks: None,
            gamma: None,
            resolve_weight: None,
        }
    }

    /// Sets [`reprojected_depth`](Self::reprojected_depth) (`None`, the default, leaves
    /// the depth test on `depth`).
    #[must_use]
    pub fn with_reprojected_depth(mut self, reprojected_depth: Option<&'a wgpu::Texture>) -> Self {
        self.reprojected_depth = reprojected_depth;
        self
    }

    /// Sets [`masks`](Self::masks) (`None`, the default: every pixel is covered).
    #[must_use]
    pub fn with_masks(mut self, masks: Option<Masks<&'a wgpu::Texture>>) -> Self {
        self.masks = masks;
        self
    }

    /// Sets [`gamma`](Self::gamma) (`None`, the default: `gamma = 1`).
    #[must_use]
    pub fn with_gamma(mut self, gamma: Option<&'a wgpu::Texture>) -> Self {
        self.gamma = gamma;
        self
    }

    /// Sets [`resolve_weight`](Self::resolve_weight) (`None`, the default: the history's
    /// age stands in for it).
    #[must_use]
    pub fn with_resolve_weight(mut self, resolve_weight: Option<&'a wgpu::Texture>) -> Self {
        self.resolve_weight = resolve_weight;
        self
    }
}

impl<'a> UpdateInputs<'a> {
    /// The required texture: the monitored [`value`](Self::value); every optional input is
    /// `None`.
    #[must_use]
    pub fn new(value: &'a wgpu::Texture) -> Self {
        Self {
            value,
            control: None,
            guide: None,
        }
    }

    /// Sets [`control`](Self::control) (`None`, the default; CCV and OCV need it).
    #[must_use]
    pub fn with_control(mut self, control: Option<&'a wgpu::Texture>) -> Self {
        self.control = control;
        self
    }

    /// Sets [`guide`](Self::guide) (`None`, the default: the unguided update).
    #[must_use]
    pub fn with_guide(mut self, guide: Option<&'a wgpu::Texture>) -> Self {
        self.guide = guide;
        self
    }
}

/// Checks an input texture before it is bound.
pub(super) fn check(
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

/// Checks a frame size against the device (or, for the twin, `u16::MAX`).
pub(crate) fn check_size(width: u32, height: u32, max: u32) -> Result<(), AdaptiveError> {
    let pixels = u64::from(width) * u64::from(height);
    if width == 0 || height == 0 || width > max || height > max || pixels >= u64::from(u32::MAX) {
        return Err(AdaptiveError::FrameSize { width, height, max });
    }
    Ok(())
}
