//! Fuzz target: every streaming estimator on a decoded weight and stream.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| spvg_fuzz::check_estimators(data));
