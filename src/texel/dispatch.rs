//! Run-time CPU dispatch of the frame loops (`std` builds on x86-64).
//!
//! The portable build (x86-64 baseline, SSE2) compiles the frame loops twice: as they
//! are, and inside functions marked `#[target_feature(enable = "avx2,fma,f16c")]`, where
//! the inlined lane code vectorises 8 wide and the F16C conversions are available. The
//! first frame call detects the features once (`is_x86_feature_detected!`, cached by
//! `std`) and every call after takes the AVX2 loop on CPUs that have them. The two
//! variants compute the same IEEE operations in the same order (Rust never fuses a
//! multiply and an add into an FMA on its own), so their results are bit-identical;
//! `tests/texel_batch.rs` ties both to the per-pixel controller.
//!
//! Where the features are compiled in already (`-C target-cpu=native` on such a CPU),
//! on other architectures (aarch64 keeps its baseline NEON loop) and in `no_std` builds
//! there is nothing to dispatch: [`with_avx2`] returns `false` and the caller runs its
//! loop as compiled.
//!
//! # Unsafe code
//!
//! This is the crate's only module with `unsafe`: calling a `#[target_feature]`
//! function is `unsafe` because it would be undefined behaviour on a CPU without the
//! features. Each call sits right after the check that the features are present, which
//! is the whole safety argument, and the module stays small so that it can be read at a
//! glance.
#![allow(
    unsafe_code,
    reason = "calls #[target_feature] functions after run-time detection; see the module docs"
)]

/// Runs `run` compiled for AVX2/FMA/F16C when this CPU has those features and they are
/// not compiled in already, and returns `true`; returns `false` (without running it)
/// otherwise. `run` must be an `#[inline(always)]` closure over `#[inline(always)]` code
/// (the frame loops' `run_lanes`), so that it is compiled inside the `#[target_feature]`
/// function.
#[inline(always)]
pub(super) fn with_avx2(run: impl FnOnce()) -> bool {
    #[cfg(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(
            target_feature = "avx2",
            target_feature = "fma",
            target_feature = "f16c"
        ))
    ))]
    {
        #[target_feature(enable = "avx2,fma,f16c")]
        fn avx2(run: impl FnOnce()) {
            run();
        }
        // `std` caches each detection.
        if std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
            && std::arch::is_x86_feature_detected!("f16c")
        {
            // SAFETY: the CPU has AVX2, FMA and F16C (checked just above).
            unsafe { avx2(run) };
            return true;
        }
    }
    let _ = run;
    false
}

#[cfg(test)]
mod tests {
    use super::super::batch::{ConstantUpdate, OcvUpdate};
    use super::super::{
        CvTexel16, CvTexel32, FrameInputsBuf, Rounding, SpvgTexel16, SpvgTexel32, TexelEncoding,
    };
    use crate::SpvgConfig;
    use crate::cv::{Ccv, Ocv, PixelController, PixelFrame};

    /// Inputs with every kind of pixel: ordinary, disoccluded, refused, non-finite.
    fn inputs(n: usize) -> FrameInputsBuf {
        let mut x = 0x9e37_79b9_u32;
        let mut u = move || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            f64::from(x) as f32 / 4.294_967e9
        };
        let mut f = FrameInputsBuf::with_capacity(n);
        for i in 0..n {
            let b = 3.0 * u();
            let radiance = if i % 97 == 0 {
                f32::NAN
            } else {
                b * (0.5 + u())
            };
            let pixel = PixelFrame {
                radiance,
                preintegrated: b,
                gamma: u(),
            };
            let count = if i % 41 == 0 {
                0
            } else {
                8 + (u() * 56.0) as u32
            };
            f.push(pixel, count, u() > 0.05);
        }
        f
    }

    /// The dispatched loop (the AVX2 variant on CPUs that have it) gives the bits of the
    /// loop as compiled (the baseline variant), frame after frame.
    #[test]
    fn dispatched_loops_match_the_baseline_loops() {
        let n = 1000;
        let buf = inputs(n);
        let frame = buf.inputs();
        let config = SpvgConfig::<f32>::published();
        let enc = TexelEncoding::new(config.target_variance()).expect("valid target");
        for rounding in [Rounding::Nearest, Rounding::Stochastic(5)] {
            let update = ConstantUpdate::new(&PixelController::new(config, Ccv), &enc, rounding);
            let (mut h1, mut h2) = (
                vec![SpvgTexel16::default(); n],
                vec![SpvgTexel16::default(); n],
            );
            let ocv = Ocv::with_weight(0.05)
                .expect("valid weight")
                .with_f16_inputs(true);
            let ocv_update = OcvUpdate::new(&PixelController::new(config, ocv), &enc, rounding);
            let (mut j1, mut j2) = (vec![CvTexel16::default(); n], vec![CvTexel16::default(); n]);
            let (mut k1, mut k2) = (
                vec![SpvgTexel32::default(); n],
                vec![SpvgTexel32::default(); n],
            );
            let (mut m1, mut m2) = (vec![CvTexel32::default(); n], vec![CvTexel32::default(); n]);
            for first in [0, 3, 64] {
                update.run(&frame, &mut h1, first);
                update.run_lanes(&frame, &mut h2, first);
                ocv_update.run(&frame, &mut k1, &mut j1, first);
                ocv_update.run_lanes(&frame, &mut k2, &mut j2, first);
                let (mut t1, mut t2) = (h1.clone(), h2.clone());
                ocv_update.run(&frame, &mut t1, &mut m1, first);
                ocv_update.run_lanes(&frame, &mut t2, &mut m2, first);
                assert_eq!(t1, t2, "OCV f16 history with f32 CV texels, {rounding:?}");
            }
            assert_eq!(h1, h2, "CCV f16 texels, {rounding:?}");
            assert_eq!((k1, j1), (k2, j2), "OCV f32 and f16 texels, {rounding:?}");
            assert_eq!(m1, m2, "OCV f32 CV texels, {rounding:?}");
        }
    }
}
