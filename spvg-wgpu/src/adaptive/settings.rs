//! The component's settings ([`AdaptiveSettings`]): one value for the pass, its twin and
//! the Bevy plugin, validated once, and what the component derives from it once per
//! change (the controller block its WGSL reads, the controller its twin runs).

use spvg::SpvgConfig;
use spvg::controller::CountPolicy;
use spvg::reproject::Reprojection;
use spvg::texel::{Layout, TexelEncoding};
use spvg_shaders::{Params, Storage};

use super::controller::Controller;
use super::params::{STORE_ROUNDING, component_ocv};
use super::{AdaptiveError, Control};

/// Everything that decides the component's counts and histories: the controller, the
/// control model, the reprojection, the count dilation and the neighbour prior.
///
/// [`AdaptivePass`](super::AdaptivePass) and [`AdaptiveTwin`](super::AdaptiveTwin) take it
/// at construction and from [`set_settings`](super::AdaptivePass::set_settings) between
/// frames; they validate it then ([`validate`](Self::validate)), and a renderer that wraps
/// the component hands it through unchanged.
///
/// The defaults are the library's published controller (`SpvgConfig::published`: `eta`
/// 0.2, `sigma0^2` 1e-4, `kappa` 0.2, budget [8, 64], the young-history rules and the
/// firefly clamp as the core crate defaults them), plain adaptive sampling, the default
/// reprojection (2% depth tolerance, border prior, footprint search), no count dilation,
/// the neighbour prior on (it acts only with a dilation radius), and no count-classified
/// dispatch.
///
/// # Examples
///
/// ```
/// use spvg::SpvgConfig;
/// use spvg_wgpu::adaptive::{AdaptiveSettings, Control};
///
/// let settings = AdaptiveSettings {
///     config: SpvgConfig::builder().target_variance(1e-3).build().unwrap(),
///     control: Control::Ccv,
///     dilation: 1,
///     ..AdaptiveSettings::default()
/// };
/// assert!(settings.validate().is_ok());
/// let too_wide = AdaptiveSettings { dilation: 1000, ..settings };
/// assert!(too_wide.validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveSettings {
    /// The controller (docs/algorithms.md §2): `eta`, the target variance `sigma0^2`,
    /// `kappa`, the budget `[beta_min, beta_max]`, `eps_u`, the young-history rules
    /// (`SpvgConfig::age_weight`, `SpvgConfig::spatial_variance`) and the firefly clamp
    /// (`SpvgConfig::firefly_clamp`). Its count policy must be SPVG's.
    pub config: SpvgConfig<f32>,
    /// The control model of the monitored value (docs/algorithms.md §3). The component
    /// runs OCV with f16 inputs whatever the model was built with, because its CV history
    /// is stored in f16 (`spvg::cv::Ocv::with_f16_inputs`).
    pub control: Control,
    /// The reprojection rule: depth tolerance, border prior, footprint search
    /// (`spvg::reproject`).
    pub reprojection: Reprojection<f32>,
    /// Radius of the count dilation (`spvg::dilation`, docs/algorithms.md §2.5): each
    /// covered pixel with history spends the largest count within this many pixels. 0 is
    /// off; at most `spvg::dilation::MAX_RADIUS`.
    pub dilation: u32,
    /// The dilation's depth-aware neighbour prior: a pixel without history takes the mean
    /// count of its same-surface neighbours with history
    /// (`spvg::dilation::dilated_count_with_prior`). It acts only with a dilation radius.
    pub neighbour_prior: bool,
    /// Count-classified dispatch: after the estimate (and the dilation), the estimate
    /// step also sorts the frame's 8 x 8 tiles into classes by their largest count and
    /// writes, per class, a compacted tile list and indirect dispatch arguments, and per
    /// tile the order of its pixels by the class of their counts; the renderer records its sampling pass with
    /// [`AdaptivePass::dispatch_classified`](super::AdaptivePass::dispatch_classified),
    /// so that a SIMD group runs similar counts. Off by default; the counts and histories
    /// do not depend on it.
    pub classified_dispatch: bool,
}

impl Default for AdaptiveSettings {
    fn default() -> Self {
        Self {
            config: SpvgConfig::published(),
            control: Control::As,
            reprojection: Reprojection::default(),
            dilation: 0,
            neighbour_prior: true,
            classified_dispatch: false,
        }
    }
}

impl AdaptiveSettings {
    /// Checks what the component cannot run: a count policy other than SPVG's, an
    /// allocation exponent other than 1 (`SpvgConfig::allocation_exponent`, CPU-only), a
    /// dilation radius above `spvg::dilation::MAX_RADIUS`, or a target variance or OCV
    /// model whose history encoding the f16 texel cannot hold.
    ///
    /// # Errors
    ///
    /// [`AdaptiveError::UnsupportedPolicy`], or [`AdaptiveError::Param`] naming the
    /// parameter.
    pub fn validate(&self) -> Result<(), AdaptiveError> {
        derive(self, self.config.target_variance()).map(|_| ())
    }
}

/// What the component derives from its settings, once per change: the controller block
/// of its WGSL and the same controller for its twin.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Derived {
    /// The library's parameter block (`spvg_Params`), binding 0 of both steps.
    pub(crate) block: Params,
    /// The core crate's controller, OCV and texel encoding the block was built from.
    pub(crate) controller: Controller,
}

/// Validates `settings` and derives the block and the controller: the history in f16
/// texels rounded to nearest ([`STORE_ROUNDING`]), the variance stored relative to the
/// power of two nearest `encoding_target` (fixed for a component's life, so the stored
/// variances keep their meaning when the target moves), and the target replaced by the
/// largest variance not above it that the f16 texel stores exactly
/// (`TexelEncoding::storable_config`: the seed of a disoccluded pixel then estimates
/// exactly its seeded count).
pub(crate) fn derive(
    settings: &AdaptiveSettings,
    encoding_target: f32,
) -> Result<Derived, AdaptiveError> {
    let config = &settings.config;
    if config.policy() != CountPolicy::Spvg {
        return Err(AdaptiveError::UnsupportedPolicy(config.policy()));
    }
    // The WGSL library has no allocation exponent: `x^p` has no correctly rounded WGSL
    // form that the twin could equal bit for bit, so the component runs p = 1 only.
    let p = config.allocation_exponent();
    if p != 1.0 {
        return Err(AdaptiveError::Param(spvg::Error::invalid(
            "allocation_exponent",
            f64::from(p),
            "the GPU component and its twin run the equalising allocation only (1); the exponent is CPU-only",
        )));
    }
    spvg::dilation::check_radius(settings.dilation)?;
    let enc = TexelEncoding::new(encoding_target)?;
    let ocv = component_ocv(&settings.control);
    let (encoding, model) = match ocv {
        Some(o) => (enc.for_ocv(&o)?, Control::Ocv(o)),
        None => (enc, settings.control),
    };
    let storage = Storage {
        encoding,
        layout: Layout::F16,
        rounding: STORE_ROUNDING,
    };
    let spvg = encoding.storable_config(config, Layout::F16)?;
    Ok(Derived {
        block: Params::new(&spvg, model, &storage),
        controller: Controller::new(spvg, model, encoding),
    })
}
