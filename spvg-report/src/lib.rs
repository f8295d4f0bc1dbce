//! # spvg-report: the speed/accuracy report of the spvg passes
//!
//! The `spvg-report` binary runs the report's sections as subcommands (`all`, the
//! default, runs every section); `spvg-report --help` lists them and the flags.
//!
//! A folder per section, each split into its runs, acceptance, markdown and charts, and
//! none importing another section:
//!
//! - [`subsurface`]: the dynamic-lighting scenes of docs/algorithms.md §7 ([`scene`]) on
//!   the subsurface pass against their quadrature references ([`reference`](mod@reference)),
//!   every model, the frame budget, the TAA guide, and the core's damped policy and
//!   firefly clamp ([`policies`]);
//! - [`motion`]: scenes with motion through the adaptive component and the second consumer
//!   (ambient occlusion), every GPU frame held against the CPU twin;
//! - [`separable`]: the separable profile's fit per preset and the focus-region scene run
//!   separable-only, AS, CCV and hybrid, with the work each dispatches;
//! - [`budget`]: fixed against adaptive counts at budgets 64, 128 and 512 on the static
//!   scene;
//! - [`cost`]: the component's cost, an adaptive frame's time against the fixed-count
//!   line at its own count, in each form of the component;
//! - [`studies`]: the timing studies, which judge nothing (GPU readiness, the per-pass
//!   breakdown).
//!
//! What the sections share: the one acceptance-line format ([`acceptance`]), the sections
//! and the verdict over them ([`section`]), the backend ([`backend`]), the metrics
//! ([`metrics`]), the TAA resolve run after each consumer ([`taa`]), the equal-quality
//! interpolation ([`equal_quality`]), the one chart module ([`charts`]), frame images
//! ([`images`]), timings ([`timing`]), progress bars ([`progress`]), the error type
//! ([`error`]), and [`wgpu_api`], every `spvg-wgpu` name the crate uses.

pub mod acceptance;
pub mod backend;
pub mod budget;
pub mod charts;
pub mod cost;
pub mod equal_quality;
pub mod error;
pub mod governor;
pub mod images;
pub mod mesh;
pub mod metrics;
pub mod motion;
pub mod policies;
pub mod progress;
pub mod reference;
pub mod scene;
pub mod section;
pub mod separable;
pub mod studies;
pub mod subsurface;
pub mod taa;
pub mod timing;
pub mod wgpu_api;
