//! # spvg-report: the speed/accuracy report of the spvg-wgpu pass
//!
//! The procedural dynamic-lighting scenes of docs/algorithms.md §7 ([`scene`]), their
//! converged quadrature references ([`reference`](mod@reference)), the per-frame metrics ([`metrics`]),
//! runs of a scene through a model on a backend ([`evaluate`]), charts drawn with
//! `plotters` ([`charts`]), captioned frame images ([`images`]) and the documents
//! ([`report`]); scenes with motion through the adaptive component and the second consumer
//! ([`motion`]). The `spvg-report` binary runs every scene with every model and writes
//! the report; `spvg-report --help` lists its flags.

pub mod charts;
pub mod damped;
pub mod error;
pub mod evaluate;
pub mod images;
pub mod metrics;
pub mod motion;
pub mod reference;
pub mod report;
pub mod scene;
pub mod timing;
