//! Fractional counts below the floor (docs/algorithms.md §8.6) on the subsurface effect's
//! static scene, measured after a temporal resolve: the fractional floor against fixed
//! counts from 1 to 64 and against AS [8, 64], as the `floor` example does for ambient
//! occlusion.
//!
//! The scene, the material (`SKIN1`) and the quadrature reference are the report's
//! (`spvg_report::scene`, `spvg_report::reference::static_reference`), at 128x96; every
//! run goes through the subsurface effect's CPU twin (`SssTwin`; the GPU pass equals it in
//! its counts, fractional decisions included, and in its histories to the Burley
//! sampling's few ulps: `spvg-effects/tests/sss_consumer.rs`) with the AS model. The resolve is the
//! `floor` example's on a static camera: each pixel's previous resolved luminance, clamped
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
//! `cargo run --release -p spvg-effects --example floor_sss` runs floors of 0.25, 0.125 and
//! 0 over nine targets and AS [8, 64] at the published target `1e-4` and at `5e-7` (the
//! report's); `--floors` and `--targets` (comma-separated) change the sweep, and
//! `--resolve` (the resolved-image rule's steady weights, 0 for the per-frame target;
//! default `0,0.1`) runs each floor with and without the rule.

use half::f16;
use spvg::SpvgConfig;
use spvg::burley::presets::SKIN1;
use spvg_effects::sss::{FrameInputs, Model, PassConfig, SssTwin, luminance};
use spvg_report::metrics::psnr_of_pairs;
use spvg_report::reference::static_reference;
use spvg_report::scene::{Scene, SceneKind};

const SIZE: [u32; 2] = [128, 96];
const FRAMES: u32 = 64;
const WARM: u32 = 16;
/// The resolve's blend weight of the current frame.
const TAA_WEIGHT: f32 = 0.1;

type Error = Box<dyn std::error::Error>;

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

/// `log2(spp)` of `curve` (sorted by spp, PSNR rising) interpolated linearly in PSNR at
/// `psnr`, and the flicker interpolated the same way; `None` outside the curve.
fn at_psnr(curve: &[Figures], psnr: f64) -> Option<(f64, f64)> {
    curve.windows(2).find_map(|w| {
        let (a, b) = (&w[0], &w[1]);
        let (lo, hi) = (a.psnr.min(b.psnr), a.psnr.max(b.psnr));
        (psnr >= lo && psnr <= hi && hi > lo).then(|| {
            let s = (psnr - a.psnr) / (b.psnr - a.psnr);
            let l = a.spp.log2() + s * (b.spp.log2() - a.spp.log2());
            (l.exp2(), a.flicker + s * (b.flicker - a.flicker))
        })
    })
}

fn list(args: &[String], flag: &str) -> Option<Vec<f32>> {
    let k = args.iter().position(|a| a == flag)?;
    let v = args.get(k + 1)?;
    Some(v.split(',').filter_map(|x| x.parse().ok()).collect())
}

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let floors = list(&args, "--floors").unwrap_or_else(|| vec![0.25, 0.125, 0.0]);
    let resolves = list(&args, "--resolve").unwrap_or_else(|| vec![0.0, TAA_WEIGHT]);
    let targets = list(&args, "--targets").unwrap_or_else(|| {
        vec![
            1e-3, 2.5e-4, 6.25e-5, 1.6e-5, 4e-6, 1e-6, 2.5e-7, 6.25e-8, 1.6e-8,
        ]
    });
    let scene = Scene::new(SceneKind::Static, SIZE[0], SIZE[1]);
    let frames: Vec<FrameInputs> = (0..FRAMES).map(|t| scene.inputs(t)).collect();
    eprintln!("static: reference");
    let reference: Vec<f32> = static_reference(&scene, &SKIN1, &PassConfig::default())
        .into_iter()
        .map(luminance)
        .collect();
    let published = SpvgConfig::published();
    let mut fixed = Vec::new();
    for n in [1, 2, 4, 8, 16, 32, 64] {
        eprintln!("static: fixed {n}");
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
        eprintln!("static: AS [8,64] s0^2 {s:e}");
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
            let rule = if resolve > 0.0 {
                format!(" resolved {resolve}")
            } else {
                String::new()
            };
            let mut curve = Vec::new();
            for &s in &targets {
                let label = format!("floor {floor}{rule} s0^2 {s:e}");
                eprintln!("static: {label}");
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
    println!(
        "\n### subsurface static ({}x{}, frames {WARM}..{})\n",
        SIZE[0],
        SIZE[1],
        FRAMES - 1
    );
    println!(
        "| run | spp | PSNR after TAA | flicker after TAA | osc n | osc c | eq. after TAA | fixed flicker at that PSNR |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for f in fixed.iter().chain(&rows) {
        let (ratio, ff) = match at_psnr(&fixed, f.psnr) {
            Some((spp, fl)) => (format!("{:.2}x", spp / f.spp), format!("{fl:.2e}")),
            None => ("outside".to_owned(), "-".to_owned()),
        };
        println!(
            "| {} | {:.3} | {:.2} | {:.2e} | {:.3} | {:.3} | {ratio} | {ff} |",
            f.label, f.spp, f.psnr, f.flicker, f.osc_n, f.osc_c
        );
    }
    println!();
    for a in &as_rows {
        for (label, curve) in &curves {
            match at_psnr(curve, a.psnr) {
                Some((spp, fl)) => println!(
                    "- {label}: at {}'s PSNR after TAA ({:.2} dB) {spp:.2} spp = {:.2}x its {:.2} spp; flicker {fl:.2e} ({:.2e})",
                    a.label,
                    a.psnr,
                    spp / a.spp,
                    a.spp,
                    a.flicker
                ),
                None => println!(
                    "- {label}: {}'s PSNR after TAA ({:.2} dB) is outside the sweep",
                    a.label, a.psnr
                ),
            }
        }
    }
    Ok(())
}
