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

/// The `f16 <-> f32` conversions of a chunk loop, by the instruction set it is compiled
/// for: [`Baseline`] (the build's own) or [`Avx2`] (the run-time dispatched variant).
/// Both are bit-identical to `half::f16::{to_f32, from_f32}` on their domain. A `pub`
/// trait in a private module because `Chunked`'s methods are generic over it.
pub trait Isa: Copy {
    /// `dst[i] = f16::from_bits(src[i]).to_f32()`, exactly. `N` is a multiple of 8.
    fn widen<const N: usize>(self, src: &[u16; N], dst: &mut [f32; N]);
    /// `dst[i] = f16::from_f32(src[i]).to_bits()` (round to nearest, ties to even) for
    /// `src[i]` in `[-65504, 65504]`, not NaN. `N` is a multiple of 8.
    fn narrow<const N: usize>(self, src: &[f32; N], dst: &mut [u16; N]);
}

/// The loop as compiled: F16C instructions where F16C is compiled in
/// (`-C target-feature=+f16c`, `target-cpu=native`), `half`'s slice conversion where
/// F16C is detected at run time (`std` on x86: a baseline loop on a CPU with F16C but
/// without AVX2 or FMA), otherwise the branch-free conversion of `rounding.rs`, which
/// vectorises with SSE2 or NEON.
#[derive(Clone, Copy, Debug)]
pub(super) struct Baseline;

impl Isa for Baseline {
    #[inline(always)]
    fn widen<const N: usize>(self, src: &[u16; N], dst: &mut [f32; N]) {
        #[cfg(all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "f16c"
        ))]
        {
            // SAFETY: F16C is compiled in, so every CPU this binary runs on has it.
            unsafe { f16c::widen(src, dst) };
        }
        #[cfg(not(all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "f16c"
        )))]
        {
            #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
            if std::arch::is_x86_feature_detected!("f16c") {
                let src: &[half::f16] = bytemuck::cast_slice(src);
                half::slice::HalfFloatSliceExt::convert_to_f32_slice(src, dst);
                return;
            }
            for (d, &s) in dst.iter_mut().zip(src) {
                *d = super::rounding::widen_bits(s);
            }
        }
    }

    #[inline(always)]
    fn narrow<const N: usize>(self, src: &[f32; N], dst: &mut [u16; N]) {
        #[cfg(all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "f16c"
        ))]
        {
            // SAFETY: F16C is compiled in, so every CPU this binary runs on has it.
            unsafe { f16c::narrow(src, dst) };
        }
        #[cfg(not(all(
            any(target_arch = "x86", target_arch = "x86_64"),
            target_feature = "f16c"
        )))]
        {
            #[cfg(all(feature = "std", any(target_arch = "x86", target_arch = "x86_64")))]
            if std::arch::is_x86_feature_detected!("f16c") {
                let dst: &mut [half::f16] = bytemuck::cast_slice_mut(dst);
                half::slice::HalfFloatSliceExt::convert_from_f32_slice(dst, src);
                return;
            }
            for (d, &s) in dst.iter_mut().zip(src) {
                *d = super::rounding::narrow_bits(s);
            }
        }
    }
}

/// Proof that the CPU has AVX2, FMA and F16C: made only by [`with_avx2`] after the
/// detection, and handed to the loop it compiles for those features. Its conversions are
/// F16C instructions inlined into that loop (8 values per instruction).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(
    not(all(
        feature = "std",
        target_arch = "x86_64",
        not(all(
            target_feature = "avx2",
            target_feature = "fma",
            target_feature = "f16c"
        ))
    )),
    allow(dead_code, reason = "made only where with_avx2 dispatches")
)]
pub(super) struct Avx2 {
    _detected: (),
}

impl Isa for Avx2 {
    #[inline(always)]
    fn widen<const N: usize>(self, src: &[u16; N], dst: &mut [f32; N]) {
        // SAFETY: an `Avx2` exists only on a CPU with F16C (see `with_avx2`).
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        unsafe {
            f16c::widen(src, dst);
        }
        #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
        Baseline.widen(src, dst);
    }

    #[inline(always)]
    fn narrow<const N: usize>(self, src: &[f32; N], dst: &mut [u16; N]) {
        // SAFETY: an `Avx2` exists only on a CPU with F16C (see `with_avx2`).
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        unsafe {
            f16c::narrow(src, dst);
        }
        #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
        Baseline.narrow(src, dst);
    }
}

/// The F16C conversions, 8 values per instruction (`vcvtph2ps`, `vcvtps2ph` with
/// round-to-nearest-even: the instructions `half` itself uses when it detects F16C).
/// `#[inline(always)]` without `#[target_feature]`: inlined into a loop compiled with
/// F16C (the `avx2` function below, or a build with F16C compiled in), the intrinsics
/// inline too.
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
mod f16c {
    #[cfg(target_arch = "x86")]
    use core::arch::x86::{
        _MM_FROUND_TO_NEAREST_INT, _mm_loadu_si128, _mm_storeu_si128, _mm256_cvtph_ps,
        _mm256_cvtps_ph, _mm256_loadu_ps, _mm256_storeu_ps,
    };
    #[cfg(target_arch = "x86_64")]
    use core::arch::x86_64::{
        _MM_FROUND_TO_NEAREST_INT, _mm_loadu_si128, _mm_storeu_si128, _mm256_cvtph_ps,
        _mm256_cvtps_ph, _mm256_loadu_ps, _mm256_storeu_ps,
    };

    /// # Safety
    ///
    /// The CPU has F16C and AVX.
    #[inline(always)]
    pub(super) unsafe fn widen<const N: usize>(src: &[u16; N], dst: &mut [f32; N]) {
        const { assert!(N % 8 == 0, "whole groups of 8 values") };
        for (d, s) in dst.chunks_exact_mut(8).zip(src.chunks_exact(8)) {
            // SAFETY: `s` holds 8 `u16` (16 bytes) and `d` 8 `f32` (32 bytes); unaligned
            // loads and stores; the caller guarantees the features.
            unsafe {
                let h = _mm_loadu_si128(s.as_ptr().cast());
                _mm256_storeu_ps(d.as_mut_ptr(), _mm256_cvtph_ps(h));
            }
        }
    }

    /// # Safety
    ///
    /// The CPU has F16C and AVX.
    #[inline(always)]
    pub(super) unsafe fn narrow<const N: usize>(src: &[f32; N], dst: &mut [u16; N]) {
        const { assert!(N % 8 == 0, "whole groups of 8 values") };
        for (d, s) in dst.chunks_exact_mut(8).zip(src.chunks_exact(8)) {
            // SAFETY: as in `widen`.
            unsafe {
                let v = _mm256_loadu_ps(s.as_ptr());
                let h = _mm256_cvtps_ph::<_MM_FROUND_TO_NEAREST_INT>(v);
                _mm_storeu_si128(d.as_mut_ptr().cast(), h);
            }
        }
    }
}

/// Runs `run` compiled for AVX2/FMA/F16C, with the [`Avx2`] token, when this CPU has
/// those features and they are not compiled in already, and returns `true`; returns
/// `false` (without running it) otherwise: the caller then runs its loop with
/// [`Baseline`]. `run` must be an `#[inline(always)]` closure over `#[inline(always)]`
/// code (the frame loops' `run_lanes`), so that it is compiled inside the
/// `#[target_feature]` function.
#[inline(always)]
pub(super) fn with_avx2(run: impl FnOnce(Avx2)) -> bool {
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
        fn avx2(run: impl FnOnce(Avx2)) {
            run(Avx2 { _detected: () });
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
                update.run_lanes(super::Baseline, &frame, &mut h2, first);
                ocv_update.run(&frame, &mut k1, &mut j1, first);
                ocv_update.run_lanes(super::Baseline, &frame, &mut k2, &mut j2, first);
                let (mut t1, mut t2) = (h1.clone(), h2.clone());
                ocv_update.run(&frame, &mut t1, &mut m1, first);
                ocv_update.run_lanes(super::Baseline, &frame, &mut t2, &mut m2, first);
                assert_eq!(t1, t2, "OCV f16 history with f32 CV texels, {rounding:?}");
            }
            assert_eq!(h1, h2, "CCV f16 texels, {rounding:?}");
            assert_eq!((k1, j1), (k2, j2), "OCV f32 and f16 texels, {rounding:?}");
            assert_eq!(m1, m2, "OCV f32 CV texels, {rounding:?}");
        }
    }
}
