//! The one place where a camera's [`AdaptiveSampling`] reaches its `AdaptivePass`: at
//! construction ([`build`]) and between frames when the settings change ([`configure`]).

use spvg_wgpu::adaptive::{AdaptiveError, AdaptivePass};

use crate::AdaptiveSampling;

/// What [`configure`] did.
#[derive(Debug)]
pub(crate) enum Configured {
    /// The settings were handed to the existing pass.
    Applied,
    /// The existing pass has this frame's estimate waiting for an update that was skipped
    /// (no value written), and the component refuses new settings between the two steps.
    /// Nothing was changed; the caller keeps the old settings and tries again next frame,
    /// after the next update.
    Deferred,
    /// A new pass: there was none.
    New(Box<AdaptivePass>),
}

/// Hands `settings` to `current`'s pass (`AdaptivePass::set_settings`: histories kept,
/// except under a new control model), or builds a pass at `size` where there is none.
pub(crate) fn configure(
    device: &wgpu::Device,
    current: Option<&mut AdaptivePass>,
    settings: &AdaptiveSampling,
    size: [u32; 2],
) -> Result<Configured, AdaptiveError> {
    match current {
        Some(pass) => match pass.set_settings(settings.settings) {
            Ok(()) => Ok(Configured::Applied),
            Err(AdaptiveError::SettingsBetweenSteps) => Ok(Configured::Deferred),
            Err(e) => Err(e),
        },
        None => build(device, settings, size).map(|pass| Configured::New(Box::new(pass))),
    }
}

/// A new pass for `settings` at `size`.
pub(crate) fn build(
    device: &wgpu::Device,
    settings: &AdaptiveSampling,
    size: [u32; 2],
) -> Result<AdaptivePass, AdaptiveError> {
    AdaptivePass::new(device, settings.settings, size[0], size[1])
}
