//! The range form of the frame functions gives the whole-frame call's bits for random
//! splits of the frame at any pixel (not only chunk multiples), ranges run in a random
//! order, both layouts, and stochastic rounding (whose words depend on the global pixel
//! index). With the `rayon` feature the pooled functions are checked the same way.

mod common;

use bytemuck::Zeroable;
use common::splitmix::SplitMix64;
use spvg::cv::{As, Ccv, Ocv, PixelController, PixelFrame};
use spvg::texel::{
    ConstantCoefficient, CvTexel16, CvTexel32, FrameInputs, FrameInputsBuf, Rounding, SpvgTexel16,
    SpvgTexel32, Texel, TexelEncoding, update_frame, update_frame_ocv, update_frame_ocv_range,
    update_frame_range,
};
use spvg::{CvHistory, SpvgConfig, SpvgHistory};

/// A frame of varied inputs (some disoccluded, refused or non-finite pixels).
fn frame(n: usize, seed: u64) -> FrameInputsBuf {
    let mut rng = SplitMix64(seed);
    let mut u = move || rng.next_f64() as f32;
    let mut f = FrameInputsBuf::with_capacity(n);
    for i in 0..n {
        let b = 4.0 * u();
        let l = if i % 631 == 0 {
            f32::INFINITY
        } else {
            b * (0.5 + u())
        };
        let gamma = u();
        let count = if i % 89 == 0 {
            0
        } else {
            8 + (u() * 56.0) as u32
        };
        let pixel = PixelFrame {
            radiance: l,
            preintegrated: b,
            gamma,
        };
        f.push(pixel, count, u() > 0.05);
    }
    f
}

/// Random cut points of `0..n` (sorted, with 0 and `n`), and a random order of the
/// ranges between them.
fn split(n: usize, rng: &mut SplitMix64) -> Vec<(usize, usize)> {
    let cuts = (rng.next_u64() % 12) as usize;
    let mut points: Vec<usize> = (0..cuts)
        .map(|_| (rng.next_u64() % (n as u64 + 1)) as usize)
        .collect();
    points.extend([0, n]);
    points.sort_unstable();
    let mut ranges: Vec<(usize, usize)> = points.windows(2).map(|w| (w[0], w[1])).collect();
    // Fisher-Yates with splitmix64.
    for i in (1..ranges.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        ranges.swap(i, j);
    }
    ranges
}

fn cut<'a>(f: &FrameInputs<'a>, s: usize, e: usize) -> FrameInputs<'a> {
    FrameInputs {
        radiance: &f.radiance[s..e],
        preintegrated: &f.preintegrated[s..e],
        gamma: &f.gamma[s..e],
        count: &f.count[s..e],
        valid: &f.valid[s..e],
    }
}

const ROUNDINGS: [Rounding; 2] = [Rounding::Nearest, Rounding::Stochastic(0xc0ffee)];

fn check_constant<M, H>(model: M, seed: u64)
where
    M: ConstantCoefficient + Sync,
    H: Texel<History = SpvgHistory<f32>> + Send + PartialEq,
{
    let config = SpvgConfig::<f32>::published();
    let pixel = PixelController::new(config, model);
    let enc = TexelEncoding::new(config.target_variance()).expect("published sigma0^2 is valid");
    let mut rng = SplitMix64(seed);
    for n in [1_usize, 63, 64, 65, 1000, 20_011] {
        let frames = [frame(n, seed), frame(n, seed + 1), frame(n, seed + 2)];
        for rounding in ROUNDINGS {
            let mut whole = vec![H::zeroed(); n];
            let mut ranged = whole.clone();
            for f in &frames {
                let inputs = f.inputs();
                update_frame(&pixel, &enc, rounding, &inputs, &mut whole).expect("lengths");
                for (s, e) in split(n, &mut rng) {
                    let part = cut(&inputs, s, e);
                    update_frame_range(&pixel, &enc, rounding, s, &part, &mut ranged[s..e])
                        .expect("lengths");
                }
            }
            let diff = whole.iter().zip(&ranged).position(|(a, b)| a != b);
            assert!(
                diff.is_none(),
                "{n} pixels, {rounding:?}: first difference {diff:?}"
            );
            #[cfg(feature = "rayon")]
            {
                let mut pooled = vec![H::zeroed(); n];
                for f in &frames {
                    spvg::texel::update_frame_rayon(
                        &pixel,
                        &enc,
                        rounding,
                        &f.inputs(),
                        &mut pooled,
                    )
                    .expect("lengths");
                }
                assert!(whole == pooled, "rayon, {n} pixels, {rounding:?}");
            }
        }
    }
}

fn check_ocv<H, C>(seed: u64)
where
    H: Texel<History = SpvgHistory<f32>> + Send + PartialEq,
    C: Texel<History = CvHistory<f32>> + Send + PartialEq,
{
    let config = SpvgConfig::<f32>::published();
    let ocv = Ocv::with_weight(0.05)
        .expect("valid weight")
        .with_f16_inputs(true);
    let pixel = PixelController::new(config, ocv);
    let enc = TexelEncoding::new(config.target_variance()).expect("published sigma0^2 is valid");
    let mut rng = SplitMix64(seed);
    for n in [1_usize, 64, 129, 20_011] {
        let frames = [frame(n, seed), frame(n, seed + 1), frame(n, seed + 2)];
        for rounding in ROUNDINGS {
            let (mut h1, mut j1) = (vec![H::zeroed(); n], vec![C::zeroed(); n]);
            let (mut h2, mut j2) = (h1.clone(), j1.clone());
            for f in &frames {
                let inputs = f.inputs();
                update_frame_ocv(&pixel, &enc, rounding, &inputs, &mut h1, &mut j1)
                    .expect("lengths");
                for (s, e) in split(n, &mut rng) {
                    let part = cut(&inputs, s, e);
                    let (hs, js) = (&mut h2[s..e], &mut j2[s..e]);
                    update_frame_ocv_range(&pixel, &enc, rounding, s, &part, hs, js)
                        .expect("lengths");
                }
            }
            let dh = h1.iter().zip(&h2).position(|(a, b)| a != b);
            let dj = j1.iter().zip(&j2).position(|(a, b)| a != b);
            assert!(
                dh.is_none() && dj.is_none(),
                "{n} pixels, {rounding:?}: first differences {dh:?} {dj:?}"
            );
            #[cfg(feature = "rayon")]
            {
                let (mut h3, mut j3) = (vec![H::zeroed(); n], vec![C::zeroed(); n]);
                for f in &frames {
                    spvg::texel::update_frame_ocv_rayon(
                        &pixel,
                        &enc,
                        rounding,
                        &f.inputs(),
                        &mut h3,
                        &mut j3,
                    )
                    .expect("lengths");
                }
                assert!(h1 == h3 && j1 == j3, "rayon OCV, {n} pixels, {rounding:?}");
            }
        }
    }
}

#[test]
fn random_splits_match_the_whole_frame() {
    check_constant::<As, SpvgTexel16>(As, 11);
    check_constant::<Ccv, SpvgTexel16>(Ccv, 12);
    check_constant::<Ccv, SpvgTexel32>(Ccv, 13);
}

#[test]
fn random_ocv_splits_match_the_whole_frame() {
    check_ocv::<SpvgTexel16, CvTexel16>(21);
    check_ocv::<SpvgTexel32, CvTexel32>(22);
}

#[test]
fn ranges_refuse_mismatched_lengths() {
    let config = SpvgConfig::<f32>::published();
    let enc = TexelEncoding::new(config.target_variance()).expect("valid");
    let f = frame(100, 1);
    let inputs = f.inputs();
    let mut h = vec![SpvgTexel16::zeroed(); 99];
    let pixel = PixelController::new(config, As);
    let r = update_frame_range(&pixel, &enc, Rounding::Nearest, 5, &inputs, &mut h);
    assert!(r.is_err(), "99 texels for 100 inputs");
    assert!(
        h.iter().all(|t| *t == SpvgTexel16::zeroed()),
        "nothing written"
    );
}
