//! Does the time follow the samples? The subsurface pass and ambient occlusion on a static
//! scene, fixed64 against the adaptive component (AS) with the count-classified dispatch
//! off and on, run interleaved frame by frame so that all three see the same machine load.
//!
//! Per effect it prints each configuration's mean spp (of the last frame, over the
//! subsurface mask / over the frame) and its median frame time over the frames after the
//! warm-up, then the line "time follows samples": the time ratio fixed64 / AS over the spp
//! ratio 64 / spp(AS), 1 when halving the samples halves the time.
//!
//! The subsurface scene is the report's static scene (constant key light with a diagonal
//! shadow edge, an ambient light, a depth step at 62% of the width, no subsurface material
//! in the bottom 12%); the AO scene is `AoScene` with `Motion::Static`. Times are the
//! passes' own (`FrameOutput::time_ms`, `AoPass::last_frame_ms`): GPU timestamps where the
//! subsurface pass has them on a hardware adapter, else submit-to-completion wall time.
//!
//! `cargo run --release -p spvg-effects --example time_follows_samples -- [--width W]
//! [--height H] [--frames N] [--warmup K] [--effect sss|ao|both] [--csv FILE]
//! [--per-pass] [--fixed N,M,..]` (defaults 1920 x 1080, 12 frames, 4 of warm-up, both effects).
//! `--per-pass` submits and times the subsurface pass's steps one by one
//! (`SssPass::run_frame_per_pass`: estimate with the classification, sampling, update)
//! and prints their medians too: a breakdown, each step paying its own submit and wait.
//! `--fixed` adds fixed counts to the interleaved runs (fixed1: the frame at `beta_min`,
//! against which the component's steps are an overhead; a fixed count at the adaptive
//! mean: what the same samples cost without divergence).

use std::fmt::Write as _;
use std::process::ExitCode;

use half::f16;
use spvg::burley::presets::SKIN1;
use spvg_effects::ao::{AoMode, AoPass, AoScene, Motion};
use spvg_effects::sss::{FrameInputs, Model, PassConfig, SssPass};
use spvg_wgpu::adaptive::AdaptiveSettings;
use spvg_wgpu::util::acquire_device;

struct Args {
    width: u32,
    height: u32,
    frames: u32,
    warmup: u32,
    sss: bool,
    ao: bool,
    csv: Option<String>,
    per_pass: bool,
    /// Further fixed counts to run interleaved with the three (`--fixed 1,9`).
    fixed: Vec<u32>,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        width: 1920,
        height: 1080,
        frames: 12,
        warmup: 4,
        sss: true,
        ao: true,
        csv: None,
        per_pass: false,
        fixed: Vec::new(),
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        let number = |v: String| {
            v.parse::<u32>()
                .map_err(|_| format!("{flag}: {v:?} is not a whole number"))
        };
        match flag.as_str() {
            "--width" => a.width = number(value()?)?,
            "--height" => a.height = number(value()?)?,
            "--frames" => a.frames = number(value()?)?,
            "--warmup" => a.warmup = number(value()?)?,
            "--effect" => match value()?.as_str() {
                "sss" => (a.sss, a.ao) = (true, false),
                "ao" => (a.sss, a.ao) = (false, true),
                "both" => (a.sss, a.ao) = (true, true),
                v => return Err(format!("--effect: {v:?} is not sss, ao or both")),
            },
            "--csv" => a.csv = Some(value()?),
            "--per-pass" => a.per_pass = true,
            "--fixed" => {
                for v in value()?.split(',') {
                    match number(v.to_string())? {
                        0 => return Err("--fixed: a count of 0 takes no sample".into()),
                        n => a.fixed.push(n),
                    }
                }
            }
            _ => return Err(format!("unknown argument {flag:?}")),
        }
    }
    if a.width == 0 || a.height == 0 {
        return Err("--width and --height must be positive".into());
    }
    if a.frames <= a.warmup {
        return Err(format!(
            "--frames ({}) must exceed --warmup ({})",
            a.frames, a.warmup
        ));
    }
    Ok(a)
}

/// The report's static subsurface scene (`spvg-report`'s `Scene::new(Static, ..)` with
/// constant lighting): depths in mm, the texel 1e-3 of the depth.
fn static_scene(width: u32, height: u32) -> FrameInputs {
    let (w, h) = (width as f32, height as f32);
    let n = width as usize * height as usize;
    let mut f = FrameInputs {
        width,
        height,
        lighting: Vec::with_capacity(n),
        depth: Vec::with_capacity(n),
        mask: Vec::with_capacity(n),
    };
    for i in 0..n {
        let x = (i % width as usize) as f32 + 0.5;
        let y = (i / width as usize) as f32 + 0.5;
        f.depth.push(if x >= 0.62 * w { 1080.0 } else { 1000.0 });
        f.mask.push(u8::from(y < 0.88 * h));
        let key = if x + 0.5 * y < 0.5 * w { 1.0 } else { 0.08 };
        let c = [key + 0.05, 0.85 * key + 0.055, 0.75 * key + 0.065];
        f.lighting.push([
            f16::from_f32(c[0]),
            f16::from_f32(c[1]),
            f16::from_f32(c[2]),
            f16::ONE,
        ]);
    }
    f
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    match s.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => s[n / 2],
        n => 0.5 * (s[n / 2 - 1] + s[n / 2]),
    }
}

fn mean_spp(count: &[u32], mask: Option<&[u8]>) -> f64 {
    let (sum, n) = count
        .iter()
        .enumerate()
        .filter(|(i, _)| mask.is_none_or(|m| m.get(*i).is_some_and(|&v| v != 0)))
        .fold((0.0, 0_usize), |(s, n), (_, &c)| (s + f64::from(c), n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// One configuration's figures.
struct Row {
    name: String,
    spp: f64,
    times: Vec<f64>,
    /// Per frame the subsurface pass's steps with `--per-pass`: estimate (with the
    /// classification), sampling, update.
    steps: Vec<[f64; 3]>,
}

/// Prints the rows and the two time-follows-samples lines; appends CSV rows to `csv`.
fn summarise(effect: &str, rows: &[Row], warmup: usize, csv: &mut String) {
    println!("{effect}:");
    let med: Vec<f64> = rows
        .iter()
        .map(|r| median(r.times.get(warmup..).unwrap_or(&[])))
        .collect();
    for (r, m) in rows.iter().zip(&med) {
        println!(
            "  {:<16} {:>7.2} spp  {:>10.1} ms (median)",
            r.name, r.spp, m
        );
        let _ = writeln!(csv, "{effect},{},{:.3},{:.3}", r.name, r.spp, m);
        if let Some(steps) = r.steps.get(warmup..).filter(|s| !s.is_empty()) {
            let step = |k: usize| median(&steps.iter().map(|s| s[k]).collect::<Vec<_>>());
            let (e, s, u) = (step(0), step(1), step(2));
            println!(
                "  {:<16} estimate {e:.1} ms, sampling {s:.1} ms, update {u:.1} ms (medians, each step submitted alone)",
                ""
            );
            for (k, v) in [("estimate", e), ("sampling", s), ("update", u)] {
                let _ = writeln!(csv, "{effect},{}:{k},,{v:.3}", r.name);
            }
        }
    }
    let (fixed, fixed_spp) = (med[0], rows[0].spp);
    for (r, m) in rows.iter().zip(&med).skip(1).take(2) {
        let time_ratio = fixed / m;
        let spp_ratio = fixed_spp / r.spp;
        let follows = time_ratio / spp_ratio;
        println!(
            "  time follows samples ({}): {time_ratio:.2}x less time for {spp_ratio:.2}x fewer samples = {follows:.2}",
            r.name
        );
        let _ = writeln!(
            csv,
            "{effect},follows:{},{spp_ratio:.3},{follows:.3}",
            r.name
        );
    }
}

fn run(a: &Args) -> Result<String, String> {
    let d = acquire_device().map_err(|e| e.to_string())?;
    println!(
        "{}, {} x {}, {} frames ({} of warm-up), interleaved",
        d.describe(),
        a.width,
        a.height,
        a.frames,
        a.warmup
    );
    let mut csv = String::from("effect,config,spp_or_spp_ratio,median_ms_or_follows\n");
    let warmup = a.warmup as usize;
    if a.sss {
        let inputs = static_scene(a.width, a.height);
        let mut configs: Vec<(String, Model, bool)> = vec![
            ("fixed64".into(), Model::Fixed(64), false),
            ("as".into(), Model::As, false),
            ("as classified".into(), Model::As, true),
        ];
        configs.extend(
            a.fixed
                .iter()
                .map(|&n| (format!("fixed{n}"), Model::Fixed(n), false)),
        );
        let mut passes: Vec<SssPass> = configs
            .iter()
            .map(|(_, m, _)| SssPass::for_device(&d, *m, a.width, a.height))
            .collect();
        let mut rows: Vec<Row> = configs
            .iter()
            .map(|(name, _, _)| Row {
                name: name.clone(),
                spp: 0.0,
                times: Vec::new(),
                steps: Vec::new(),
            })
            .collect();
        for t in 0..a.frames {
            // Rotate the order so that no configuration always runs first.
            for k in 0..configs.len() {
                let i = (k + t as usize) % configs.len();
                let cfg = PassConfig {
                    classified_dispatch: configs[i].2,
                    ..PassConfig::default()
                };
                let p = passes[i]
                    .frame_params(&cfg, &SKIN1, t)
                    .map_err(|e| e.to_string())?;
                let out = if a.per_pass {
                    let (out, s) = passes[i]
                        .run_frame_per_pass(&p, &inputs)
                        .map_err(|e| e.to_string())?;
                    rows[i]
                        .steps
                        .push([s.estimate_ms, s.sampling_ms, s.update_ms]);
                    out
                } else {
                    passes[i]
                        .run_frame(&p, &inputs)
                        .map_err(|e| e.to_string())?
                };
                rows[i].times.push(out.time_ms);
                rows[i].spp = mean_spp(&out.count, Some(&inputs.mask));
            }
        }
        summarise("sss static", &rows, warmup, &mut csv);
    }
    if a.ao {
        let scene = AoScene {
            width: a.width,
            height: a.height,
            motion: Motion::Static,
        };
        let mut configs: Vec<(String, AoMode, bool)> = vec![
            ("fixed64".into(), AoMode::Fixed(64), false),
            ("as".into(), AoMode::Adaptive, false),
            ("as classified".into(), AoMode::Adaptive, true),
        ];
        configs.extend(
            a.fixed
                .iter()
                .map(|&n| (format!("fixed{n}"), AoMode::Fixed(n), false)),
        );
        let mut passes = Vec::new();
        for &(_, mode, classified_dispatch) in &configs {
            let settings = AdaptiveSettings {
                classified_dispatch,
                ..AdaptiveSettings::default()
            };
            passes.push(
                AoPass::new(&d.device, &d.queue, a.width, a.height, mode, settings)
                    .map_err(|e| e.to_string())?,
            );
        }
        let mut rows: Vec<Row> = configs
            .iter()
            .map(|(name, _, _)| Row {
                name: name.clone(),
                spp: 0.0,
                times: Vec::new(),
                steps: Vec::new(),
            })
            .collect();
        for t in 0..a.frames {
            for k in 0..configs.len() {
                let i = (k + t as usize) % configs.len();
                let f = passes[i]
                    .run_frame(&scene.params(t))
                    .map_err(|e| e.to_string())?;
                rows[i].times.push(passes[i].last_frame_ms());
                rows[i].spp = mean_spp(&f.count, None);
            }
        }
        summarise("ao static", &rows, warmup, &mut csv);
    }
    Ok(csv)
}

fn main() -> ExitCode {
    let a = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    match run(&a) {
        Ok(csv) => {
            if let Some(path) = &a.csv
                && let Err(e) = std::fs::write(path, csv)
            {
                eprintln!("error: writing {path}: {e}");
                return ExitCode::FAILURE;
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
