//! # spvg-report: the speed/accuracy report of the spvg-wgpu pass
//!
//! The procedural dynamic-lighting scenes of docs/algorithms.md §7 ([`scene`]), their
//! converged quadrature references ([`reference`]), the per-frame metrics ([`metrics`]),
//! runs of a scene through a model on a backend ([`evaluate`]), and the plots. The
//! `spvg-report` binary runs every scene with every model and writes the report.

pub mod error;
pub mod evaluate;
pub mod metrics;
pub mod plot;
pub mod reference;
pub mod scene;
