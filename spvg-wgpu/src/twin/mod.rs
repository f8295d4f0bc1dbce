//! The CPU twin of the WGSL pass: the test oracle and the `cpu` backend.
//!
//! [`math`] mirrors `shaders/shared/*.wgsl` function by function; [`pass`] has one function
//! per entry point of `shaders/sss.wgsl` (the adaptive models' count control is the
//! component's twin, [`crate::adaptive::AdaptiveTwin`]), [`reduce`] the entry point of
//! `shaders/reduce.wgsl`.

pub mod math;
pub mod pass;
pub mod reduce;

pub use math::*;
pub use pass::{
    Mip, PixelEstimate, SampleOutput, estimate_pixel, filtered_mip_index, pixel_gamma_s, sss_fixed,
    sss_gamma, sss_sample,
};
pub use reduce::{REDUCE_TILE, reduce_demand};
