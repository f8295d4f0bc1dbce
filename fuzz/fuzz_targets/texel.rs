//! Fuzz target: `spvg_fuzz::check_texel` (invariants documented there).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| spvg_fuzz::check_texel(data));
