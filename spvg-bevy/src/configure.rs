//! The one place where a camera's [`AdaptiveSampling`] becomes `AdaptivePass` settings:
//! at construction ([`build`]) and in place when the settings change ([`configure`]).
//! Every other part of the plugin goes through these two and never calls the pass's
//! constructor or setters itself.

use spvg_wgpu::adaptive::{AdaptiveError, AdaptivePass};

use crate::AdaptiveSampling;

/// What [`configure`] did.
#[derive(Debug)]
pub(crate) enum Configured {
    /// The settings were applied to the existing pass; its histories are kept.
    Applied,
    /// The existing pass has this frame's estimate waiting for an update that was skipped
    /// (no value written), and the component refuses a new target variance between the two
    /// steps. Nothing was changed; the caller keeps the old settings and tries again next
    /// frame, after the next update.
    Deferred,
    /// A new pass: there was none, or the settings cannot be applied in place.
    New(Box<AdaptivePass>),
}

/// Applies `settings` to `current` (the pass and the settings it runs with), or builds a
/// new pass at `size` where there is none or the change needs one.
///
/// In place (histories kept): the target variance (`AdaptivePass::set_target_variance`),
/// the count dilation, the reprojection rule and `skip_background` (the conversion's, not
/// the pass's). Anything else in the configuration, or another control model, builds a new
/// pass: the history's encoding and layout depend on them.
pub(crate) fn configure(
    device: &wgpu::Device,
    current: Option<(&mut AdaptivePass, &AdaptiveSampling)>,
    settings: &AdaptiveSampling,
    size: [u32; 2],
) -> Result<Configured, AdaptiveError> {
    if let Some((pass, old)) = current {
        let target = settings.config.target_variance();
        let same_but_target = old
            .config
            .to_builder()
            .target_variance(target)
            .build()
            .is_ok_and(|c| c == settings.config);
        if same_but_target && settings.control == old.control {
            // The target first: it is the only setter refused between a frame's two steps,
            // and it changes nothing when it refuses.
            match pass.set_target_variance(target) {
                Err(AdaptiveError::TargetBetweenSteps) => return Ok(Configured::Deferred),
                other => other?,
            }
            pass.set_count_dilation(settings.dilation)?;
            if settings.reprojection != old.reprojection {
                pass.set_reprojection(settings.reprojection);
            }
            return Ok(Configured::Applied);
        }
    }
    build(device, settings, size).map(|pass| Configured::New(Box::new(pass)))
}

/// A new pass for `settings` at `size`.
pub(crate) fn build(
    device: &wgpu::Device,
    settings: &AdaptiveSampling,
    size: [u32; 2],
) -> Result<AdaptivePass, AdaptiveError> {
    let mut pass = AdaptivePass::new(device, settings.config, settings.control, size[0], size[1])?;
    pass.set_reprojection(settings.reprojection);
    pass.set_count_dilation(settings.dilation)?;
    Ok(pass)
}
