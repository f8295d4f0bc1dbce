//! Fractional counts below the floor (docs/algorithms.md §8.6), measured after a temporal
//! resolve on the ambient-occlusion effect: the fractional floor against fixed counts
//! from 1 to 64 and against AS [8, 64], on the static camera, the 4 px/frame pan and the
//! floating sphere (`pan4`, `object3`).
//!
//! Every run goes through the CPU twins (`AoTwin`, the component's `AdaptiveTwin`),
//! which equal the GPU bit for bit (`spvg-effects/tests/ao.rs`,
//! `spvg-wgpu/tests/adaptive.rs`). The resolve is this study's own, the simplest TAA
//! that the acceptance asks for: the previous resolved image read at the texel the core's
//! reprojection (`spvg::reproject`, the component's own rule) continues, clamped to the
//! current frame's 3x3 min/max over the pixels that took samples, blended with weight
//! `a = 0.1`; where the reprojection finds no history (disocclusion, entering pixels) the
//! pixel takes its current value. A pixel that took no sample this frame has no value to
//! blend in: it keeps its reprojected history, clamped to its sampled neighbours (not
//! clamped where none of them sampled). The
//! reference is a 32x32 midpoint quadrature of the cosine-weighted hemisphere at each
//! pixel's visible point (the integrand the twin samples).
//!
//! Figures, over frames 16..47 of 48 (the report's warm-up and length):
//! - spp: mean samples per pixel;
//! - PSNR: of the resolved image against the reference (AO in [0, 1], peak 1), mean over
//!   frames;
//! - flicker: the mean over pixels with a reprojected history of
//!   `|(x_t - x_(t-1)) - (ref_t - ref_(t-1))|` along the motion;
//! - oscillation: the mean over pixels with a continued SPVG history of
//!   `|n_t - n_(t-1)|` (the realised counts) and of `|c_t - c_(t-1)|` (the real counts,
//!   the realised ones where the integer rule decided), along the motion;
//! - eq.: the fixed count reaching the run's PSNR (log2 spp interpolated linearly in PSNR
//!   between the fixed runs that bracket it) over the run's spp; fixed flicker: the fixed
//!   runs' flicker interpolated at the same PSNR.
//!
//! `spvg-report floor --effect ao` runs the three scenes with a floor of 0.25, count
//! dilation 1 and ten targets from 3.2e-2 to 6.25e-5 ([`super::FloorOptions`] says which
//! flags change them), and writes `floor_ao.md`.

use std::fmt::Write as _;

use spvg::SpvgConfig;
use spvg::reproject::{PreviousSample, Reprojection};

use super::options::{self, FloorOptions, SparseBox, TAA_WEIGHT};
use crate::error::ReportError as Error;
use crate::motion::reference::reference_where;
use crate::progress::Progress;
use crate::wgpu_api::ao_twin::{self as twin, GPixel};
use crate::wgpu_api::{AdaptiveSettings, AoMode, AoParams, AoScene, AoTwin, Motion};

const FRAMES: u32 = 48;
const WARM: usize = 16;
/// Directions per axis of the reference quadrature.
const GRID: u32 = 32;

/// The reference of one frame at the pixels where `todo` holds (elsewhere `base`): the
/// report's quadrature of the cosine-weighted hemisphere on a `GRID x GRID` stratification.
fn quadrature(
    p: &AoParams,
    g: &[GPixel],
    todo: &(dyn Fn(usize) -> bool + Sync),
    base: &[f32],
) -> Vec<f32> {
    reference_where(p, g, GRID, todo, base)
}

/// Whether a ray from `s` can reach a moving sphere of `p` (or `s` is on one).
fn near_a_mover(p: &AoParams, s: [f32; 3]) -> bool {
    let reach = twin::RANGE + 0.5;
    [p.mover, p.extra_movers[0], p.extra_movers[1]]
        .iter()
        .any(|m| {
            let d = [s[0] - m[0], s[1] - m[1], s[2] - m[2]];
            m[3] > 0.0 && (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() < m[3] + reach
        })
}

/// The references of every frame of `scene`: the static camera once, the moving sphere
/// recomputed near it, a pan at an integer speed as windows of one wide strip (the pixel
/// centres stay on the world's half-integer grid), anything else every frame.
fn references(scene: &AoScene) -> Vec<Vec<f32>> {
    let all = |_: usize| true;
    if let Motion::Pan { speed } = scene.motion
        && speed.fract() == 0.0
    {
        let extra = (speed * FRAMES as f32) as u32;
        let wide = AoScene {
            width: scene.width + extra,
            height: scene.height,
            motion: Motion::Static,
        };
        let mut p = wide.params(0);
        // Centre the strip so that its column k is the pan's column k at frame 0.
        p.camera[0] += 0.5 * extra as f32;
        let strip = quadrature(&p, &twin::gbuffer(&p), &all, &[]);
        let (w, pitch) = (scene.width as usize, wide.width as usize);
        return (0..FRAMES)
            .map(|t| {
                let shift = (speed * t as f32) as usize;
                (0..w * scene.height as usize)
                    .map(|i| strip[(i / w) * pitch + i % w + shift])
                    .collect()
            })
            .collect();
    }
    let base = quadrature(
        &scene.params(0),
        &twin::gbuffer(&scene.params(0)),
        &all,
        &[],
    );
    (0..FRAMES)
        .map(|t| {
            let p = scene.params(t);
            match scene.motion {
                Motion::Static => base.clone(),
                Motion::MovingSphere { .. } => {
                    let g = twin::gbuffer(&p);
                    let near = |i: usize| near_a_mover(&p, g[i].surface.position);
                    quadrature(&p, &g, &near, &base)
                }
                _ => quadrature(&p, &twin::gbuffer(&p), &all, &[]),
            }
        })
        .collect()
}

/// The resolve's state: the previous resolved image and depth.
struct Taa {
    sparse: SparseBox,
    resolved: Vec<f32>,
    depth: Vec<f32>,
}

/// One resolved frame and, per pixel, the previous frame's texel it continued.
struct Resolved {
    value: Vec<f32>,
    from: Vec<Option<usize>>,
}

impl Taa {
    fn new(sparse: SparseBox) -> Self {
        Self {
            sparse,
            resolved: Vec::new(),
            depth: Vec::new(),
        }
    }

    fn resolve(&mut self, g: &[GPixel], size: [u32; 2], value: &[f32], count: &[u32]) -> Resolved {
        let (w, h) = (size[0] as usize, size[1] as usize);
        let rule = Reprojection::<f32>::default();
        let first = self.resolved.is_empty();
        let from: Vec<Option<usize>> = (0..g.len())
            .map(|i| {
                if first {
                    return None;
                }
                let previous = |q: [u32; 2]| PreviousSample {
                    mask: true,
                    depth: self.depth[q[1] as usize * w + q[0] as usize],
                };
                rule.locate(
                    [(i % w) as u32, (i / w) as u32],
                    g[i].motion,
                    g[i].reprojected_depth,
                    size,
                    size,
                    previous,
                )
                .update_texel()
                .map(|q| q[1] as usize * w + q[0] as usize)
            })
            .collect();
        // This frame's value where the pixel sampled; where it did not, its reprojected
        // history (SparseBox::History) or nothing.
        let shown: Vec<Option<f32>> = (0..g.len())
            .map(|i| match (count[i], from[i], self.sparse) {
                (0, Some(q), SparseBox::History) => Some(self.resolved[q]),
                (0, _, _) => None,
                _ => Some(value[i]),
            })
            .collect();
        let mut out = vec![0.0; g.len()];
        for i in 0..g.len() {
            let (x, y) = (i % w, i / w);
            out[i] = match from[i] {
                Some(q) => {
                    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
                    for ny in y.saturating_sub(1)..=(y + 1).min(h - 1) {
                        for nx in x.saturating_sub(1)..=(x + 1).min(w - 1) {
                            if let Some(v) = shown[ny * w + nx] {
                                lo = lo.min(v);
                                hi = hi.max(v);
                            }
                        }
                    }
                    // Nothing in the box: nothing to clamp against.
                    let hist = if lo <= hi {
                        self.resolved[q].clamp(lo, hi)
                    } else {
                        self.resolved[q]
                    };
                    if count[i] == 0 {
                        hist
                    } else {
                        hist + TAA_WEIGHT * (value[i] - hist)
                    }
                }
                // Without history the pixel always samples (its count comes from the
                // integer rule).
                None => value[i],
            };
        }
        self.resolved.clone_from(&out);
        self.depth = g.iter().map(|p| p.depth).collect();
        Resolved { value: out, from }
    }
}

/// The figures of one run.
#[derive(Clone, Debug, Default)]
struct Figures {
    label: String,
    spp: f64,
    psnr: f64,
    psnr_single: f64,
    flicker: f64,
    osc_n: f64,
    osc_c: f64,
}

/// Accumulates one series (a run, or a prefix of a fixed run) frame by frame.
struct Series {
    taa: Taa,
    previous: Option<(Vec<f32>, Vec<f32>)>,
    sums: [f64; 4],
    frames: usize,
}

impl Series {
    fn new(sparse: SparseBox) -> Self {
        Self {
            taa: Taa::new(sparse),
            previous: None,
            sums: [0.0; 4],
            frames: 0,
        }
    }

    fn frame(
        &mut self,
        t: usize,
        g: &[GPixel],
        size: [u32; 2],
        value: &[f32],
        count: &[u32],
        reference: &[f32],
    ) {
        let r = self.taa.resolve(g, size, value, count);
        if t >= WARM {
            let n = value.len() as f64;
            let mse = |x: &[f32]| {
                x.iter()
                    .zip(reference)
                    .map(|(a, b)| f64::from(a - b).powi(2))
                    .sum::<f64>()
                    / n
            };
            let (mut flick, mut m) = (0.0, 0_u64);
            if let Some((prev, prev_ref)) = &self.previous {
                for (i, q) in r.from.iter().enumerate() {
                    if let Some(q) = *q {
                        flick +=
                            f64::from((r.value[i] - prev[q]) - (reference[i] - prev_ref[q])).abs();
                        m += 1;
                    }
                }
            }
            self.sums[0] += f64::from(count.iter().map(|&c| c as u64).sum::<u64>() as f32) / n;
            self.sums[1] += -10.0 * mse(&r.value).log10();
            self.sums[2] += -10.0 * mse(value).log10();
            self.sums[3] += flick / m.max(1) as f64;
            self.frames += 1;
        }
        self.previous = Some((r.value, reference.to_vec()));
    }

    fn figures(&self, label: String, osc: (f64, f64)) -> Figures {
        let k = self.frames.max(1) as f64;
        Figures {
            label,
            spp: self.sums[0] / k,
            psnr: self.sums[1] / k,
            psnr_single: self.sums[2] / k,
            flicker: self.sums[3] / k,
            osc_n: osc.0,
            osc_c: osc.1,
        }
    }
}

/// A fixed count, and the smaller counts its prefixes give.
fn run_fixed(
    scene: &AoScene,
    refs: &[Vec<f32>],
    n: u32,
    prefixes: [u32; 4],
    sparse: SparseBox,
) -> Result<Vec<Figures>, Error> {
    let size = [scene.width, scene.height];
    let mut tw = AoTwin::new(
        scene.width,
        scene.height,
        AoMode::Fixed(n),
        AdaptiveSettings::default(),
    )?;
    tw.set_prefix_counts(prefixes);
    let k = prefixes.iter().filter(|&&c| c > 0).count();
    let mut series: Vec<Series> = (0..=k).map(|_| Series::new(sparse)).collect();
    for t in 0..FRAMES {
        let p = scene.params(t);
        let g = twin::gbuffer(&p);
        let f = tw.run_frame(&p)?;
        series[0].frame(t as usize, &g, size, &f.value, &f.count, &refs[t as usize]);
        for (j, s) in series.iter_mut().enumerate().skip(1) {
            let v: Vec<f32> = f.prefixes.iter().map(|x| x[j - 1]).collect();
            let c = vec![prefixes[j - 1]; v.len()];
            s.frame(t as usize, &g, size, &v, &c, &refs[t as usize]);
        }
    }
    let counts = std::iter::once(n).chain(prefixes.into_iter().take(k));
    Ok(series
        .iter()
        .zip(counts)
        .map(|(s, c)| s.figures(format!("fixed{c}"), (0.0, 0.0)))
        .collect())
}

/// An adaptive run of the component's twin.
fn run_adaptive(
    scene: &AoScene,
    refs: &[Vec<f32>],
    label: &str,
    settings: AdaptiveSettings,
    sparse: SparseBox,
) -> Result<Figures, Error> {
    let size = [scene.width, scene.height];
    let mut tw = AoTwin::new(scene.width, scene.height, AoMode::Adaptive, settings)?;
    let mut series = Series::new(sparse);
    let mut prev: Option<(Vec<u32>, Vec<f32>)> = None;
    let (mut osc_n, mut osc_c, mut frames) = (0.0, 0.0, 0);
    for t in 0..FRAMES {
        let p = scene.params(t);
        let g = twin::gbuffer(&p);
        let f = tw.run_frame(&p)?;
        let a = tw.adaptive().ok_or_else(|| {
            Error::Corrupt("the AO twin of an adaptive run has no adaptive component".into())
        })?;
        let real: Vec<f32> = if a.real_counts().is_empty() {
            f.count.iter().map(|&c| c as f32).collect()
        } else {
            a.real_counts()
                .iter()
                .zip(&f.count)
                .map(|(&r, &c)| if r >= 0.0 { r } else { c as f32 })
                .collect()
        };
        if let Some((pn, pc)) = &prev
            && t as usize >= WARM
        {
            let (mut sn, mut sc, mut m) = (0.0, 0.0, 0_u64);
            for (i, &l) in a.links().iter().enumerate() {
                if l != 0 {
                    let q = (l - 1) as usize;
                    sn += (f64::from(f.count[i]) - f64::from(pn[q])).abs();
                    sc += f64::from(real[i] - pc[q]).abs();
                    m += 1;
                }
            }
            osc_n += sn / m.max(1) as f64;
            osc_c += sc / m.max(1) as f64;
            frames += 1;
        }
        series.frame(t as usize, &g, size, &f.value, &f.count, &refs[t as usize]);
        prev = Some((f.count, real));
    }
    let k = f64::from(frames.max(1));
    Ok(series.figures(label.to_owned(), (osc_n / k, osc_c / k)))
}

/// `log2(spp)` of `curve` (sorted by spp) at `psnr`, and the flicker there
/// ([`options::at_psnr`]).
fn at_psnr(curve: &[Figures], psnr: f64) -> Option<(f64, f64)> {
    options::at_psnr(curve, psnr, |f| [f.spp, f.psnr, f.flicker])
}

fn settings(config: SpvgConfig<f32>, dilation: u32) -> AdaptiveSettings {
    AdaptiveSettings {
        config,
        dilation,
        ..AdaptiveSettings::default()
    }
}

fn print_table(md: &mut String, fixed: &[Figures], rows: &[Figures]) {
    say!(
        md,
        "| run | spp | PSNR single | PSNR after TAA | flicker after TAA | osc n | osc c | eq. after TAA | fixed flicker at that PSNR |"
    );
    say!(md, "|---|---|---|---|---|---|---|---|---|");
    for f in fixed.iter().chain(rows) {
        let (ratio, ff) = match at_psnr(fixed, f.psnr) {
            Some((spp, fl)) => (format!("{:.2}x", spp / f.spp), format!("{fl:.2e}")),
            None => ("outside".to_owned(), "-".to_owned()),
        };
        // A fractional run's frame holds no value where a pixel skipped: its single-frame
        // PSNR measures nothing.
        let single = if f.label.starts_with("floor") {
            "-".to_owned()
        } else {
            format!("{:.2}", f.psnr_single)
        };
        say!(
            md,
            "| {} | {:.3} | {single} | {:.2} | {:.2e} | {:.3} | {:.3} | {ratio} | {ff} |",
            f.label,
            f.spp,
            f.psnr,
            f.flicker,
            f.osc_n,
            f.osc_c
        );
    }
}

/// Runs the AO study of `opts` and returns its markdown.
pub(super) fn markdown(opts: &FloorOptions, progress: &Progress) -> Result<String, Error> {
    let mut md = String::new();
    let md = &mut md;
    let floors = opts.floors.clone().unwrap_or_else(|| vec![0.25]);
    let targets = opts.targets.clone().unwrap_or_else(|| {
        if opts.quick {
            vec![8e-3, 2e-3, 5e-4]
        } else {
            vec![
                3.2e-2, 1.6e-2, 8e-3, 4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5,
            ]
        }
    });
    let scenes = [
        AoScene {
            width: 128,
            height: 96,
            motion: Motion::Static,
        },
        AoScene {
            width: 384,
            height: 192,
            motion: Motion::Pan { speed: 4.0 },
        },
        AoScene {
            width: 128,
            height: 96,
            motion: Motion::MovingSphere { speed: 3.0 },
        },
    ];
    for scene in scenes {
        let name = scene.motion.name();
        if opts.scene.as_ref().is_some_and(|o| *o != name) {
            continue;
        }
        progress.stage(&format!("{name}: references"));
        let refs = references(&scene);
        progress.stage(&format!("{name}: fixed counts"));
        let mut fixed = run_fixed(&scene, &refs, 64, [1, 2, 4, 8], opts.sparse)?;
        fixed.extend(run_fixed(&scene, &refs, 32, [16, 0, 0, 0], opts.sparse)?);
        fixed.sort_by(|a, b| a.spp.total_cmp(&b.spp));
        let mut rows = Vec::new();
        // The published rule with its floor of 8, and with integer floors 4 and 1: the
        // seed's oscillation.
        for floor in [8, 4, 1] {
            progress.stage(&format!("{name}: AS [{floor}, 64]"));
            let config = SpvgConfig::builder()
                .target_variance(1e-4)
                .budget(floor, 64)
                .build()?;
            rows.push(run_adaptive(
                &scene,
                &refs,
                &format!("AS [{floor},64]"),
                settings(config, 1),
                opts.sparse,
            )?);
        }
        let as_run = rows[0].clone();
        let mut curves: Vec<(String, Vec<Figures>)> = Vec::new();
        for &floor in &floors {
            for &dilation in &opts.dilations {
                for &resolve in &opts.resolves {
                    let rule = options::rule_label(resolve);
                    let mut curve = Vec::new();
                    for &s in &targets {
                        let label = format!("floor {floor} r{dilation}{rule} s0^2 {s:e}");
                        progress.stage(&format!("{name}: {label}"));
                        let config = SpvgConfig::builder()
                            .target_variance(s)
                            .budget(8, opts.max_samples)
                            .fractional_floor(Some(floor))
                            .resolve_weight((resolve > 0.0).then_some(resolve))
                            .build()?;
                        curve.push(run_adaptive(
                            &scene,
                            &refs,
                            &label,
                            settings(config, dilation),
                            opts.sparse,
                        )?);
                    }
                    curve.sort_by(|a, b| a.spp.total_cmp(&b.spp));
                    rows.extend(curve.iter().cloned());
                    curves.push((format!("floor {floor} r{dilation}{rule}"), curve));
                }
            }
        }
        say!(
            md,
            "\n### {name} ({}x{}, frames {WARM}..{})\n",
            scene.width,
            scene.height,
            FRAMES - 1
        );
        print_table(md, &fixed, &rows);
        say!(md);
        for (label, curve) in &curves {
            match at_psnr(curve, as_run.psnr) {
                Some((spp, fl)) => say!(
                    md,
                    "- {label}: at AS [8,64]'s PSNR after TAA ({:.2} dB) {spp:.2} spp = {:.2}x AS's {:.2} spp; flicker {fl:.2e} (AS {:.2e})",
                    as_run.psnr,
                    spp / as_run.spp,
                    as_run.spp,
                    as_run.flicker
                ),
                None => say!(
                    md,
                    "- {label}: AS [8,64]'s PSNR after TAA ({:.2} dB) is outside the sweep",
                    as_run.psnr
                ),
            }
        }
    }
    Ok(std::mem::take(md))
}
