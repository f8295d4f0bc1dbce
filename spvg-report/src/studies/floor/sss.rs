//! Fractional counts below the floor (docs/algorithms.md §8.6) on the subsurface effect's
//! static scene, measured after a temporal resolve: the fractional floor against fixed
//! counts from 1 to 64 and against AS [8, 64], as [`super::ao`] does for ambient
//! occlusion.
//!
//! The scene, the material (`SKIN1`) and the quadrature reference are the report's
//! (`crate::scene`, `crate::reference::static_reference`), at 128x96; every
//! run goes through the subsurface effect's CPU twin (`SssTwin`; the GPU pass equals it in
//! its counts, fractional decisions included, and in its histories to the Burley
//! sampling's few ulps: `spvg-effects/tests/sss_consumer.rs`) with the AS model. The resolve is the
//! AO study's ([`super::ao`]) on a static camera: each pixel's previous resolved luminance, clamped
//! to the 3x3 min/max of the subsurface pixels' shown values, blended with weight
//! `a = 0.1`. A pixel that skipped this frame (a fractional decision of 0 samples) has no
//! value: it keeps its history, and its history stands in its neighbours' boxes. A pixel
//! that the zero-sample rule left without distant samples has a value (the near part is
//! all there is) and blends it.
//!
//! Figures over frames 16..63 of 64, on the subsurface pixels: spp, PSNR after TAA of the
//! luminance (peak 1, the report's), flicker `|x_t - x_(t-1)|` after TAA (the reference
//! does not change), the count oscillation `|n_t - n_(t-1)|` (realised counts) and
//! `|c_t - c_(t-1)|` (real counts), and the equal-quality ratio against the fixed counts
//! (log2 spp interpolated linearly in PSNR).
//!
//! `spvg-report floor --effect sss` runs floors of 0.25, 0.125 and 0 over nine targets and
//! AS [8, 64] at the published target `1e-4` and at `5e-7` (the report's), each floor with
//! and without the resolved-image rule ([`super::FloorOptions`] says which flags change
//! them), and writes `floor_sss.md`.

use std::fmt::Write as _;

use half::f16;
use spvg::SpvgConfig;
use spvg::burley::presets::SKIN1;

use super::options::{self, FloorOptions, TAA_WEIGHT};
use crate::error::ReportError as Error;
use crate::metrics::psnr_of_pairs;
use crate::progress::Progress;
use crate::reference::static_reference;
use crate::scene::{Scene, SceneKind};
use crate::wgpu_api::{FrameInputs, Model, PassConfig, SssTwin, luminance};

const SIZE: [u32; 2] = [128, 96];
const FRAMES: u32 = 64;
const WARM: u32 = 16;

/// The figures of one run.
#[derive(Clone, Debug)]
struct Figures {
    label: String,
    spp: f64,
    psnr: f64,
    flicker: f64,
    osc_n: f64,
    osc_c: f64,
}

/// The static camera's resolve over the subsurface pixels.
struct Resolve {
    resolved: Vec<f32>,
}

impl Resolve {
    /// Resolves one frame: `value` where the pixel took samples or the zero-sample rule
    /// decided, nothing where `skipped`.
    fn frame(&mut self, mask: &[u8], value: &[f32], skipped: &[bool]) -> &[f32] {
        let (w, h) = (SIZE[0] as usize, SIZE[1] as usize);
        if self.resolved.is_empty() {
            self.resolved = value.to_vec();
            return &self.resolved;
        }
        let shown: Vec<Option<f32>> = (0..value.len())
            .map(|i| {
                (mask[i] != 0).then(|| {
                    if skipped[i] {
                        self.resolved[i]
                    } else {
                        value[i]
                    }
                })
            })
            .collect();
        let mut out = self.resolved.clone();
        for i in 0..value.len() {
            if mask[i] == 0 {
                out[i] = value[i];
                continue;
            }
            let (x, y) = (i % w, i / w);
            let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
            for ny in y.saturating_sub(1)..=(y + 1).min(h - 1) {
                for nx in x.saturating_sub(1)..=(x + 1).min(w - 1) {
                    if let Some(v) = shown[ny * w + nx] {
                        lo = lo.min(v);
                        hi = hi.max(v);
                    }
                }
            }
            let hist = self.resolved[i].clamp(lo, hi);
            out[i] = if skipped[i] {
                hist
            } else {
                hist + TAA_WEIGHT * (value[i] - hist)
            };
        }
        self.resolved = out;
        &self.resolved
    }
}

/// One run of `model` under `spvg` against the reference luminance `reference`.
fn run(
    label: String,
    model: Model,
    spvg: SpvgConfig<f32>,
    frames: &[FrameInputs],
    reference: &[f32],
) -> Result<Figures, Error> {
    let cfg = PassConfig {
        spvg,
        ..PassConfig::default()
    };
    let [w, h] = SIZE;
    let mut twin = SssTwin::new(model, w, h);
    let mut resolve = Resolve {
        resolved: Vec::new(),
    };
    let mut previous: Option<(Vec<f32>, Vec<u32>, Vec<f32>)> = None;
    let (mut spp, mut psnr, mut flicker, mut osc_n, mut osc_c, mut k) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (t, inputs) in (0..FRAMES).zip(frames) {
        let params = twin.frame_params(&cfg, &SKIN1, t)?;
        let out = twin.run_frame(&params, inputs)?;
        let value: Vec<f32> = out
            .result
            .iter()
            .map(|p| luminance([p[0], p[1], p[2]].map(f16::to_f32)))
            .collect();
        // A fractional decision of 0 samples is a skip; the integer rule's 0 (the
        // zero-sample rule) is not.
        let (real, links): (Vec<f32>, Vec<u32>) = match twin.adaptive() {
            Some(a) if !a.real_counts().is_empty() => {
                (a.real_counts().to_vec(), a.links().to_vec())
            }
            Some(a) => (vec![-1.0; value.len()], a.links().to_vec()),
            None => (vec![-1.0; value.len()], vec![0; value.len()]),
        };
        let skipped: Vec<bool> = out
            .count
            .iter()
            .zip(&real)
            .map(|(&n, &c)| n == 0 && c >= 0.0)
            .collect();
        let resolved = resolve.frame(&inputs.mask, &value, &skipped).to_vec();
        let real: Vec<f32> = real
            .iter()
            .zip(&out.count)
            .map(|(&c, &n)| if c >= 0.0 { c } else { n as f32 })
            .collect();
        if t >= WARM {
            let sub: Vec<usize> = (0..value.len()).filter(|&i| inputs.mask[i] != 0).collect();
            let m = sub.len().max(1) as f64;
            spp += sub.iter().map(|&i| f64::from(out.count[i])).sum::<f64>() / m;
            psnr += psnr_of_pairs(
                sub.iter()
                    .map(|&i| (f64::from(resolved[i]), f64::from(reference[i]))),
            );
            if let Some((prev, pn, pc)) = &previous {
                flicker += sub
                    .iter()
                    .map(|&i| f64::from((resolved[i] - prev[i]).abs()))
                    .sum::<f64>()
                    / m;
                let (mut sn, mut sc, mut l) = (0.0, 0.0, 0_u64);
                for &i in &sub {
                    if links[i] != 0 {
                        let q = (links[i] - 1) as usize;
                        sn += (f64::from(out.count[i]) - f64::from(pn[q])).abs();
                        sc += f64::from((real[i] - pc[q]).abs());
                        l += 1;
                    }
                }
                osc_n += sn / l.max(1) as f64;
                osc_c += sc / l.max(1) as f64;
            }
            k += 1.0;
        }
        previous = Some((resolved, out.count, real));
    }
    let k: f64 = k;
    Ok(Figures {
        label,
        spp: spp / k,
        psnr: psnr / k,
        flicker: flicker / k,
        osc_n: osc_n / k,
        osc_c: osc_c / k,
    })
}

/// `log2(spp)` of `curve` (sorted by spp) at `psnr`, and the flicker there
/// ([`options::at_psnr`]).
fn at_psnr(curve: &[Figures], psnr: f64) -> Option<(f64, f64)> {
    options::at_psnr(curve, psnr, |f| [f.spp, f.psnr, f.flicker])
}

/// Runs the subsurface study of `opts` and returns its markdown.
pub(super) fn markdown(opts: &FloorOptions, progress: &Progress) -> Result<String, Error> {
    let mut md = String::new();
    let md = &mut md;
    let floors = opts
        .floors
        .clone()
        .unwrap_or_else(|| vec![0.25, 0.125, 0.0]);
    let resolves = opts.resolves.clone();
    let targets = opts.targets.clone().unwrap_or_else(|| {
        vec![
            1e-3, 2.5e-4, 6.25e-5, 1.6e-5, 4e-6, 1e-6, 2.5e-7, 6.25e-8, 1.6e-8,
        ]
    });
    let scene = Scene::new(SceneKind::Static, SIZE[0], SIZE[1]);
    let frames: Vec<FrameInputs> = (0..FRAMES).map(|t| scene.inputs(t)).collect();
    progress.stage("static: reference");
    let reference: Vec<f32> = static_reference(&scene, &SKIN1, &PassConfig::default())
        .into_iter()
        .map(luminance)
        .collect();
    let published = SpvgConfig::published();
    let mut fixed = Vec::new();
    for n in [1, 2, 4, 8, 16, 32, 64] {
        progress.stage(&format!("static: fixed {n}"));
        fixed.push(run(
            format!("fixed{n}"),
            Model::Fixed(n),
            published,
            &frames,
            &reference,
        )?);
    }
    let mut rows = Vec::new();
    for s in [1e-4, 5e-7] {
        progress.stage(&format!("static: AS [8,64] s0^2 {s:e}"));
        let config = published.to_builder().target_variance(s).build()?;
        rows.push(run(
            format!("AS [8,64] s0^2 {s:e}"),
            Model::As,
            config,
            &frames,
            &reference,
        )?);
    }
    let as_rows = rows.clone();
    let mut curves = Vec::new();
    for &floor in &floors {
        for &resolve in &resolves {
            let rule = options::rule_label(resolve);
            let mut curve = Vec::new();
            for &s in &targets {
                let label = format!("floor {floor}{rule} s0^2 {s:e}");
                progress.stage(&format!("static: {label}"));
                let config = published
                    .to_builder()
                    .target_variance(s)
                    .fractional_floor(Some(floor))
                    .resolve_weight((resolve > 0.0).then_some(resolve))
                    .build()?;
                curve.push(run(label, Model::As, config, &frames, &reference)?);
            }
            curve.sort_by(|a, b| a.spp.total_cmp(&b.spp));
            rows.extend(curve.iter().cloned());
            curves.push((format!("floor {floor}{rule}"), curve));
        }
    }
    say!(
        md,
        "\n### subsurface static ({}x{}, frames {WARM}..{})\n",
        SIZE[0],
        SIZE[1],
        FRAMES - 1
    );
    say!(
        md,
        "| run | spp | PSNR after TAA | flicker after TAA | osc n | osc c | eq. after TAA | fixed flicker at that PSNR |"
    );
    say!(md, "|---|---|---|---|---|---|---|---|");
    for f in fixed.iter().chain(&rows) {
        let (ratio, ff) = match at_psnr(&fixed, f.psnr) {
            Some((spp, fl)) => (format!("{:.2}x", spp / f.spp), format!("{fl:.2e}")),
            None => ("outside".to_owned(), "-".to_owned()),
        };
        say!(
            md,
            "| {} | {:.3} | {:.2} | {:.2e} | {:.3} | {:.3} | {ratio} | {ff} |",
            f.label,
            f.spp,
            f.psnr,
            f.flicker,
            f.osc_n,
            f.osc_c
        );
    }
    say!(md);
    for a in &as_rows {
        for (label, curve) in &curves {
            match at_psnr(curve, a.psnr) {
                Some((spp, fl)) => say!(
                    md,
                    "- {label}: at {}'s PSNR after TAA ({:.2} dB) {spp:.2} spp = {:.2}x its {:.2} spp; flicker {fl:.2e} ({:.2e})",
                    a.label,
                    a.psnr,
                    spp / a.spp,
                    a.spp,
                    a.flicker
                ),
                None => say!(
                    md,
                    "- {label}: {}'s PSNR after TAA ({:.2} dB) is outside the sweep",
                    a.label,
                    a.psnr
                ),
            }
        }
    }
    Ok(std::mem::take(md))
}
