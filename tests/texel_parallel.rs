//! The multi-threaded frame updates give the serial frame functions' bits (which
//! `tests/texel_batch.rs` ties to the per-pixel controller), for every thread count,
//! frame lengths that are not multiples of the chunk width, both layouts, and stochastic
//! rounding (whose random words depend on the global pixel index).

mod common;

use bytemuck::Zeroable;
use common::splitmix::SplitMix64;
use spvg::SpvgConfig;
use spvg::cv::{As, Ccv, Ocv, PixelController, PixelFrame};
use spvg::texel::{
    ConstantCoefficient, CvTexel16, CvTexel32, FrameInputs, FrameInputsBuf, Rounding, SpvgTexel16,
    SpvgTexel32, Texel, TexelEncoding, update_frame, update_frame_ocv, update_frame_ocv_parallel,
    update_frame_parallel,
};

/// A frame of varied inputs: ordinary values, some disoccluded or refused pixels, and a
/// few non-finite ones, from splitmix64.
fn frame(n: usize, seed: u32) -> FrameInputsBuf {
    let mut rng = SplitMix64(u64::from(seed));
    let mut u = move || rng.next_f64() as f32;
    let mut f = FrameInputsBuf::with_capacity(n);
    for i in 0..n {
        let b = 4.0 * u();
        let l = if i % 997 == 0 {
            f32::NAN
        } else {
            b * (0.5 + u())
        };
        let gamma = u();
        let count = if i % 101 == 0 {
            0
        } else {
            8 + (u() * 56.0) as u32
        };
        let valid = u() > 0.05;
        let pixel = PixelFrame {
            radiance: l,
            preintegrated: b,
            gamma,
        };
        f.push(pixel, count, valid);
    }
    f
}

const LENGTHS: [usize; 3] = [0, 777, 9_001];
const THREADS: [usize; 5] = [0, 1, 2, 3, 8];
const ROUNDINGS: [Rounding; 2] = [Rounding::Nearest, Rounding::Stochastic(0x5eed)];

fn check_constant<M, H>(model: M)
where
    M: ConstantCoefficient + Sync,
    H: Texel<History = spvg::SpvgHistory<f32>> + Send + PartialEq,
{
    let config = SpvgConfig::<f32>::published();
    let pixel = PixelController::new(config, model);
    let enc = TexelEncoding::new(config.target_variance()).expect("published sigma0^2 is valid");
    for n in LENGTHS {
        let frames = [frame(n, 1), frame(n, 2), frame(n, 3)];
        for rounding in ROUNDINGS {
            for threads in THREADS {
                let mut serial = vec![H::zeroed(); n];
                let mut threaded = serial.clone();
                // Several frames, so the histories are warm and varied.
                for f in &frames {
                    let inputs = f.inputs();
                    update_frame(&pixel, &enc, rounding, &inputs, &mut serial)
                        .expect("equal lengths");
                    update_frame_parallel(&pixel, &enc, rounding, &inputs, &mut threaded, threads)
                        .expect("equal lengths");
                }
                let diff = serial.iter().zip(&threaded).position(|(a, b)| a != b);
                assert!(
                    diff.is_none(),
                    "{n} pixels, {threads} threads, {rounding:?}: first difference at {diff:?}"
                );
            }
        }
    }
}

fn check_ocv<H, C>()
where
    H: Texel<History = spvg::SpvgHistory<f32>> + Send + PartialEq,
    C: Texel<History = spvg::CvHistory<f32>> + Send + PartialEq,
{
    let config = SpvgConfig::<f32>::published();
    let pixel = PixelController::new(config, Ocv::with_weight(0.05).expect("valid weight"));
    let enc = TexelEncoding::new(config.target_variance()).expect("published sigma0^2 is valid");
    for n in LENGTHS {
        let frames = [frame(n, 4), frame(n, 5), frame(n, 6)];
        for rounding in ROUNDINGS {
            for threads in THREADS {
                let (mut h1, mut j1) = (vec![H::zeroed(); n], vec![C::zeroed(); n]);
                let (mut h2, mut j2) = (h1.clone(), j1.clone());
                for f in &frames {
                    let inputs = f.inputs();
                    update_frame_ocv(&pixel, &enc, rounding, &inputs, &mut h1, &mut j1)
                        .expect("equal lengths");
                    update_frame_ocv_parallel(
                        &pixel, &enc, rounding, &inputs, &mut h2, &mut j2, threads,
                    )
                    .expect("equal lengths");
                }
                let dh = h1.iter().zip(&h2).position(|(a, b)| a != b);
                let dj = j1.iter().zip(&j2).position(|(a, b)| a != b);
                assert!(
                    dh.is_none() && dj.is_none(),
                    "{n} pixels, {threads} threads, {rounding:?}: first differences {dh:?} {dj:?}"
                );
            }
        }
    }
}

#[test]
fn parallel_as_and_ccv_match_serial() {
    check_constant::<As, SpvgTexel16>(As);
    check_constant::<Ccv, SpvgTexel16>(Ccv);
    check_constant::<Ccv, SpvgTexel32>(Ccv);
}

#[test]
fn parallel_ocv_matches_serial() {
    check_ocv::<SpvgTexel16, CvTexel16>();
    check_ocv::<SpvgTexel32, CvTexel32>();
}

#[test]
fn parallel_rejects_mismatched_lengths_without_writing() {
    let config = SpvgConfig::<f32>::published();
    let enc = TexelEncoding::new(config.target_variance()).expect("published sigma0^2 is valid");
    let f = frame(3000, 9);
    let full = f.inputs();
    let short = FrameInputs {
        count: &full.count[..2999],
        ..full
    };
    let mut h = vec![SpvgTexel16::zeroed(); 3000];
    let mut j = vec![CvTexel16::zeroed(); 3000];
    let pixel = PixelController::new(config, Ccv);
    let r = update_frame_parallel(&pixel, &enc, Rounding::Nearest, &short, &mut h, 2);
    assert!(r.is_err(), "a short count slice must be refused");
    let ocv = PixelController::new(config, Ocv::with_weight(0.05).expect("valid weight"));
    let r = update_frame_ocv_parallel(
        &ocv,
        &enc,
        Rounding::Nearest,
        &f.inputs(),
        &mut h,
        &mut j[..10],
        2,
    );
    assert!(r.is_err(), "a short CV slice must be refused");
    assert!(
        h.iter().all(|t| *t == SpvgTexel16::zeroed()),
        "nothing may be written on error"
    );
}
