//! Invariant checks shared by the fuzz targets (nightly, cargo-fuzz) and the stable replay
//! test of their seed corpora (`tests/replay.rs`).
//!
//! One module per component, each with one `check_*` function taking the raw fuzz input;
//! a target (`fuzz_targets/<name>.rs`) only calls its check. Each check decodes the bytes
//! without failing (missing bytes read as zero), runs the component in `f64` and `f32`,
//! and panics on a broken invariant, which libFuzzer reports as a crash.
//!
//! [`TARGETS`] maps every fuzz target (and so every `corpus/<name>/` directory) to its
//! check, so the replay test can run every corpus and refuse a corpus without a check.

mod burley;
mod control_variates;
mod controller;
mod estimators;
mod input;
mod texel;

pub use burley::check_burley;
pub use control_variates::check_control_variates;
pub use controller::check_controller;
pub use estimators::check_estimators;
pub use texel::check_texel;

/// A check: decodes one fuzz input and panics on a broken invariant.
pub type Check = fn(&[u8]);

/// Every fuzz target's name (its `[[bin]]` name and corpus directory) with its check.
pub const TARGETS: &[(&str, Check)] = &[
    ("burley", check_burley),
    ("control_variates", check_control_variates),
    ("controller", check_controller),
    ("estimators", check_estimators),
    ("texel", check_texel),
];
