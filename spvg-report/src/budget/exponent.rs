//! The allocation exponent under the frame budget (`SpvgConfig::allocation_exponent`,
//! docs/algorithms.md §8.2), on the core crate alone: the AO static camera's converged
//! image taken as each pixel's probability `q` that a binary AO ray escapes, so that a
//! pixel's samples are exactly the AO pass's in distribution (0 or 1, per-sample variance
//! `q (1 - q)`), drawn from a fixed `SplitMix64` stream; the core's controller and
//! [`Governor`] (clamp-aware feed-forward and integral feedback) hold the frame's total at
//! [`BUDGET_SPP`] per pixel for `p` = 1, 0.75 and 0.5; fixed counts give the PSNR curve
//! that turns each run's PSNR into the fixed count of equal quality. The component runs
//! `p = 1` only (the exponent is CPU-only), so nothing here runs a pass.

use spvg::budget::{BudgetConfig, DemandCurve, Governor};
use spvg::{SpvgConfig, SpvgHistory};
use spvg_fixtures::splitmix::SplitMix64;

use crate::acceptance::Check;
use crate::equal_quality::{FixedPoint, equal_spp};
use crate::error::ReportError;
use crate::motion::reference::reference;
use crate::wgpu_api::{AoScene, Motion};

/// The frame size: the motion section's static camera.
pub const SIZE: [u32; 2] = [128, 96];
/// Directions per axis of the reference quadrature (the motion section's).
pub const GRID: u32 = 32;
/// The frame budget, samples per pixel.
pub const BUDGET_SPP: f64 = 12.0;
/// The exponents run: the equalising default, the judged one, Neyman's.
pub const EXPONENTS: [f64; 3] = [1.0, 0.75, 0.5];
/// The fixed counts of the equal-quality curve.
pub const FIXED: [u32; 8] = [4, 6, 8, 12, 16, 24, 32, 64];
/// Frames per run; the first [`WARM_UP`] are not scored.
pub const FRAMES: u32 = 48;
/// Unscored frames from a cold history.
pub const WARM_UP: u32 = 16;
/// The per-pixel budget `[beta_min, beta_max]`: the published maximum, and a minimum of
/// one sample (the published 8 would fix two thirds of a 12-spp budget before any
/// allocation).
pub const COUNT_RANGE: [u32; 2] = [4, 64];

/// One run's scores over the scored frames.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExponentRun {
    /// The allocation exponent (0 for a fixed count).
    pub p: f64,
    /// Mean samples per pixel.
    pub spp: f64,
    /// PSNR of the mean squared error over pixels and frames (peak 1).
    pub psnr: f64,
    /// The worst decile's pixel error: RMSE over the 10% of pixels with the largest
    /// mean squared error.
    pub worst_decile: f64,
}

/// The ideal savings at equal mean squared error against a fixed count, for exact
/// per-sample variances `v = q (1 - q)` and counts `n ∝ v^p` without floor or cap:
/// `mean(v) / (mean(v^(1-p)) mean(v^p))` (with `v^0` = 1 where `v > 0`, 0 where `v = 0`:
/// a converged pixel takes no sample and has no error). `p = 1` gives `1 / f`, `p = 1/2`
/// the Cauchy-Schwarz bound `mean(v) / mean(sqrt v)^2`.
///
/// ```
/// use spvg_report::budget::exponent::ideal_saving;
/// // Half the pixels converged, half at q = 1/2: 1/f = 2 at every p.
/// assert!((ideal_saving(&[0.0, 0.5, 1.0, 0.5], 1.0) - 2.0).abs() < 1e-12);
/// assert!((ideal_saving(&[0.0, 0.5, 1.0, 0.5], 0.5) - 2.0).abs() < 1e-12);
/// ```
#[must_use]
pub fn ideal_saving(q: &[f32], p: f64) -> f64 {
    let pow = |v: f64, e: f64| if v > 0.0 { v.powf(e) } else { 0.0 };
    let n = q.len().max(1) as f64;
    let (mut m, mut a, mut b) = (0.0, 0.0, 0.0);
    for &q in q {
        let q = f64::from(q).clamp(0.0, 1.0);
        let v = q * (1.0 - q);
        m += v / n;
        a += pow(v, 1.0 - p) / n;
        b += pow(v, p) / n;
    }
    m / (a * b)
}

/// The static AO camera's converged image at `size` (the motion section's `static`
/// scene and quadrature).
#[must_use]
pub fn static_ao(size: [u32; 2], grid: u32) -> Vec<f32> {
    let scene = AoScene {
        width: size[0],
        height: size[1],
        motion: Motion::Static,
    };
    reference(&scene.params(0), grid)
}

/// The mean of `n` binary samples of probability `q`.
fn binary_mean(rng: &mut SplitMix64, q: f32, n: u32) -> f32 {
    let hits = (0..n).filter(|_| rng.next_f64() < f64::from(q)).count();
    hits as f32 / n.max(1) as f32
}

/// Accumulates one frame's squared errors per pixel.
fn score_frame(err: &mut [f64], image: &[f32], q: &[f32]) {
    for ((e, &x), &q) in err.iter_mut().zip(image).zip(q) {
        let d = f64::from(x) - f64::from(q);
        *e += d * d;
    }
}

/// The scores of a run from its per-pixel summed squared errors over `frames` frames.
fn scores(p: f64, spp: f64, err: &[f64], frames: f64) -> ExponentRun {
    let mut mse: Vec<f64> = err.iter().map(|e| e / frames).collect();
    let mean = mse.iter().sum::<f64>() / mse.len().max(1) as f64;
    mse.sort_by(|a, b| b.total_cmp(a));
    let decile = &mse[..mse.len().div_ceil(10)];
    ExponentRun {
        p,
        spp,
        psnr: -10.0 * mean.log10(),
        worst_decile: (decile.iter().sum::<f64>() / decile.len().max(1) as f64).sqrt(),
    }
}

/// A fixed count of `n` samples per pixel on `q`.
#[must_use]
pub fn run_fixed(q: &[f32], n: u32) -> ExponentRun {
    let mut rng = SplitMix64(0xb0d9e7 ^ u64::from(n));
    let mut err = vec![0.0; q.len()];
    for t in 0..FRAMES {
        let image: Vec<f32> = q.iter().map(|&q| binary_mean(&mut rng, q, n)).collect();
        if t >= WARM_UP {
            score_frame(&mut err, &image, q);
        }
    }
    scores(0.0, f64::from(n), &err, f64::from(FRAMES - WARM_UP))
}

/// The published controller (budget `[8, 64]`) with allocation exponent `p` under the
/// governor at [`BUDGET_SPP`] on `q`.
///
/// # Errors
///
/// A configuration the core rejects (an exponent outside `(0, 1]`, named).
pub fn run_budget(q: &[f32], p: f64) -> Result<ExponentRun, ReportError> {
    let base = SpvgConfig::<f64>::builder()
        .allocation_exponent(p)
        .build()?;
    let budget = BUDGET_SPP * q.len() as f64;
    let mut governor = Governor::new(
        BudgetConfig::builder(budget).build()?,
        base.target_variance(),
    )?;
    let mut rng = SplitMix64(0xb0d9e7);
    let mut hist = vec![SpvgHistory::<f64>::default(); q.len()];
    let mut err = vec![0.0; q.len()];
    let mut spp = 0.0;
    for t in 0..FRAMES {
        let valid = t > 0;
        let curve = DemandCurve::from_pixels(
            &base,
            governor.curve_targets(),
            hist.iter().map(|h| (h, 1.0, valid)),
        );
        let target = governor.plan_curve(&curve);
        let config = base.to_builder().target_variance(target).build()?;
        let mut total = 0_u64;
        let mut image = Vec::with_capacity(q.len());
        for (h, &q) in hist.iter_mut().zip(q) {
            let n = config.estimate_with_validity(h, 1.0, valid);
            let s = binary_mean(&mut rng, q, n);
            config.update(h, f64::from(s), n, valid);
            total += u64::from(n);
            image.push(s);
        }
        governor.observe(total as f64);
        if t >= WARM_UP {
            score_frame(&mut err, &image, q);
            spp += total as f64 / q.len() as f64;
        }
    }
    let frames = f64::from(FRAMES - WARM_UP);
    Ok(scores(p, spp / frames, &err, frames))
}

/// Every run of the line: the budget runs in [`EXPONENTS`] order, then the fixed counts.
///
/// # Errors
///
/// As [`run_budget`].
pub fn run_all(q: &[f32]) -> Result<(Vec<ExponentRun>, Vec<ExponentRun>), ReportError> {
    let budget = EXPONENTS
        .iter()
        .map(|&p| run_budget(q, p))
        .collect::<Result<_, _>>()?;
    Ok((budget, FIXED.iter().map(|&n| run_fixed(q, n)).collect()))
}

/// Samples per pixel a run saves against the fixed counts at its PSNR (NaN outside the
/// fixed curve).
#[must_use]
pub fn saved(run: &ExponentRun, fixed: &[ExponentRun]) -> f64 {
    let curve: Vec<FixedPoint> = fixed
        .iter()
        .map(|f| FixedPoint {
            spp: f.spp,
            psnr: f.psnr,
        })
        .collect();
    equal_spp(&curve, run.psnr)
        .value()
        .map_or(f64::NAN, |f| f - run.spp)
}

/// The judged line: `p = 0.75` saves at least 1.10x the samples `p = 1` saves at equal
/// PSNR, with a worst-decile pixel error at most 2x `p = 1`'s; `p = 0.5` and the ideal
/// savings ([`ideal_saving`]) quoted.
#[must_use]
pub fn check(q: &[f32], budget: &[ExponentRun], fixed: &[ExponentRun]) -> Check {
    let get = |p: f64| {
        budget
            .iter()
            .find(|r| r.p == p)
            .copied()
            .unwrap_or_default()
    };
    let (one, judged, neyman) = (get(1.0), get(0.75), get(0.5));
    let (s1, s75, s5) = (
        saved(&one, fixed),
        saved(&judged, fixed),
        saved(&neyman, fixed),
    );
    let ideal = |p: f64| BUDGET_SPP * (ideal_saving(q, p) - 1.0);
    let ratio = s75 / s1;
    let worst = judged.worst_decile / one.worst_decile;
    let run = |r: &ExponentRun, s: f64| {
        format!(
            "{:.2} spp, {:.2} dB, saves {s:.2} spp, worst decile {:.2e}",
            r.spp, r.psnr, r.worst_decile
        )
    };
    Check::new(
        ratio >= 1.10 && worst <= 2.0,
        format!(
            "allocation exponent, {BUDGET_SPP}-spp frame budget, AO static's image as binary samples (core controller and governor, published [8, 64]): p = 1 {}; p = 0.75 {}; p = 0.5 {}; p = 0.75 saves {ratio:.2}x p = 1's (need >= 1.10x), worst decile {worst:.2}x (need <= 2x); ideal savings (exact variances, no floor or cap) {:.2}, {:.2} and {:.2} spp",
            run(&one, s1),
            run(&judged, s75),
            run(&neyman, s5),
            ideal(1.0),
            ideal(0.75),
            ideal(0.5),
        ),
    )
}
