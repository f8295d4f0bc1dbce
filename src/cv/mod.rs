//! Control variates for temporally stable sample counts (SPEC section 3).

mod history;

pub use history::CvHistory;
