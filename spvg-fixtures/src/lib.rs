//! # spvg-fixtures: what the workspace's tests, examples, benches and report share
//!
//! Deterministic random numbers ([`splitmix`]), the docs/algorithms.md §7 circle scenario
//! ([`circle`]) and the frame-update benchmarks' workload ([`workload`]). One copy of each,
//! depended on by the crates that use them, instead of files included by path.

pub mod circle;
pub mod splitmix;
pub mod workload;
