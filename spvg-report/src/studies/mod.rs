//! The studies, which judge nothing: the component's steps against a copy kernel moving
//! the same bytes ([`gpu_readiness`]), the subsurface pass's steps timed apart at
//! 1920x1080 ([`pass_breakdown`]) (both run by `spvg-report --full`), and the sweep of
//! fractional floors and the resolved-image rule after TAA ([`floor`]). Each is a
//! subcommand of `spvg-report`.

pub mod floor;
pub mod gpu_readiness;
pub mod pass_breakdown;
