//! The SPVG per-pixel sample-count controller (SPEC section 2).

mod history;

pub use history::SpvgHistory;
