//! # spvg-report: the speed/accuracy report of the spvg-wgpu pass
//!
//! Module map, one concept each:
//!
//! - scenes: the procedural dynamic-lighting scenes of docs/algorithms.md §7 ([`scene`])
//!   and their converged quadrature references ([`reference`](mod@reference));
//! - runs: a scene through a model on a backend, measured frame by frame ([`evaluate`],
//!   with the metrics of [`metrics`] and the timings of [`timing`]), every scene and run of
//!   the report ([`report::runs`]), the damped policy on the core's circle scenario
//!   ([`damped`]), the firefly clamp's recovery from an outlier on the core ([`firefly`]);
//! - the final image: a TAA resolve after each consumer ([`taa`]), and the equal-quality
//!   figures against the fixed runs ([`equal_quality`]);
//! - acceptance: the one acceptance-line format ([`acceptance`]) and the report's checks
//!   ([`report::acceptance`]);
//! - markdown and CSV: `report.md` ([`report::markdown`], [`report::notes`]),
//!   `runs.csv` and `frames.csv` ([`report::csv`]);
//! - charts and images: SVG charts drawn with `plotters` ([`charts`],
//!   [`report::charts`]) and captioned PNG frame images ([`images`]);
//! - separable: the separable profile's fit per preset and the focus-region scene run
//!   separable-only, AFIS-only and hybrid ([`separable`](mod@separable));
//! - the budget table: fixed against adaptive counts at budgets 64, 128 and 512 on the
//!   static scene ([`budget_table`]);
//! - the per-pass time table: estimate, sampling and update timed apart at 1080p
//!   ([`pass_breakdown`]);
//! - GPU readiness: the component's estimate and update at 1080p and 2160p against a
//!   copy kernel moving the same bytes ([`gpu_readiness`]);
//! - motion: scenes with motion through the adaptive component and the second consumer,
//!   split the same way ([`motion`]).
//!
//! [`progress`] draws the progress bars, [`error`] holds the error type, and [`wgpu_api`]
//! names every `spvg-wgpu` item the crate uses. The `spvg-report` binary runs every scene
//! with every model and writes the report; `spvg-motion` runs the motion section alone,
//! `spvg-gpu-readiness` the GPU-readiness table. The first two run a default suite that
//! judges every acceptance check, and the whole suite with `--full`; `spvg-report --help`
//! lists the flags.

pub mod acceptance;
pub mod budget_table;
pub mod charts;
pub mod damped;
pub mod equal_quality;
pub mod error;
pub mod evaluate;
pub mod firefly;
pub mod gpu_readiness;
pub mod images;
pub mod metrics;
pub mod motion;
pub mod pass_breakdown;
pub mod progress;
pub mod reference;
pub mod report;
pub mod scene;
pub mod separable;
pub mod separable_section;
pub mod taa;
pub mod timing;
pub mod wgpu_api;
