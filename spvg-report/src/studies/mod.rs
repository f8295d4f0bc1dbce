//! The timing studies, which judge nothing: the component's steps against a copy kernel
//! moving the same bytes ([`gpu_readiness`]), and the subsurface pass's steps timed apart
//! at 1920x1080 ([`pass_breakdown`]). Each is a subcommand of `spvg-report`, and
//! `spvg-report --full` runs both.

pub mod gpu_readiness;
pub mod pass_breakdown;
