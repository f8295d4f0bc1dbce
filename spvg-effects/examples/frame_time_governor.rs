//! The frame-time governor on a real pass: a target in milliseconds for the sampling
//! pass, the governor learning its cost online and steering the budget governor, which
//! sets the adaptive component's target variance every frame
//! (`spvg::frame_time::FrameTimeSteering`).
//!
//! - `--effect sss` (scenes `static`, `flash`, `switch`: the report's scenes, rebuilt
//!   here): the time is the subsurface sampling step's own (`SssPass::run_frame_per_pass`,
//!   submitted alone), the total the counts under the subsurface mask.
//! - `--effect ao` (scenes `static`, `pan`): the time is the whole AO frame's
//!   (`AoPass::last_frame_ms`: G-buffer, estimate, sampling, update), the total the frame's
//!   counts; the fixed part is learnt as such.
//!
//! Prints each frame (budget, total, time, the learnt cost) and then the band: the share
//! of frames after the warm-up whose time is within 10% of the target, and whether the
//! target is reachable (`Reach`). A target below the time of the least count everywhere
//! shows `BelowFloor`.
//!
//! `cargo run --release -p spvg-effects --example frame_time_governor -- [--effect sss|ao]
//! [--scene NAME] [--target-ms MS] [--frames N] [--warmup K] [--width W] [--height H]
//! [--classified] [--csv FILE]` (defaults sss, flash, 40 ms, 60 frames, 10 of warm-up,
//! 480 x 270).

use std::fmt::Write as _;
use std::process::ExitCode;

use half::f16;
use spvg::SpvgConfig;
use spvg::budget::{BudgetConfig, Governor};
use spvg::burley::presets::SKIN1;
use spvg::frame_time::{FrameTimeConfig, FrameTimeGovernor, FrameTimeSteering};
use spvg_effects::ao::{AoMode, AoPass, AoScene, Motion};
use spvg_effects::sss::{FrameInputs, Model, PassConfig, SssPass};
use spvg_wgpu::adaptive::AdaptiveSettings;
use spvg_wgpu::util::acquire_device;

struct Args {
    ao: bool,
    scene: String,
    target_ms: f64,
    frames: u32,
    warmup: u32,
    width: u32,
    height: u32,
    classified: bool,
    csv: Option<String>,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        ao: false,
        scene: "flash".into(),
        target_ms: 40.0,
        frames: 60,
        warmup: 10,
        width: 480,
        height: 270,
        classified: false,
        csv: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or(format!("{flag} needs a value"));
        let number = |v: String| {
            v.parse::<u32>()
                .map_err(|_| format!("{flag}: {v:?} is not a whole number"))
        };
        match flag.as_str() {
            "--effect" => match value()?.as_str() {
                "sss" => a.ao = false,
                "ao" => a.ao = true,
                v => return Err(format!("--effect: {v:?} is not sss or ao")),
            },
            "--scene" => a.scene = value()?,
            "--target-ms" => {
                let v = value()?;
                a.target_ms = v
                    .parse()
                    .ok()
                    .filter(|t: &f64| t.is_finite() && *t > 0.0)
                    .ok_or(format!("--target-ms: {v:?} is not a positive number"))?;
            }
            "--frames" => a.frames = number(value()?)?,
            "--warmup" => a.warmup = number(value()?)?,
            "--width" => a.width = number(value()?)?,
            "--height" => a.height = number(value()?)?,
            "--classified" => a.classified = true,
            "--csv" => a.csv = Some(value()?),
            _ => return Err(format!("unknown argument {flag:?}")),
        }
    }
    let scenes: &[&str] = if a.ao {
        &["static", "pan"]
    } else {
        &["static", "flash", "switch"]
    };
    if !scenes.contains(&a.scene.as_str()) {
        return Err(format!("--scene: {:?} is not one of {scenes:?}", a.scene));
    }
    if a.width == 0 || a.height == 0 {
        return Err("--width and --height must be positive".into());
    }
    if a.frames <= a.warmup {
        return Err("--frames must exceed --warmup".into());
    }
    Ok(a)
}

/// The report's subsurface scenes (`spvg-report`'s `Scene` with constant lighting) at
/// frame `t` (60 fps): static, flash (`I(t) = sin(2 pi 5 t) + 1`), switch (on for the
/// first second, then toggled every 3 s, plus a small light flickering every frame).
fn sss_inputs(scene: &str, width: u32, height: u32, t: u32) -> FrameInputs {
    let (w, h) = (width as f32, height as f32);
    let time = t as f32 / 60.0;
    let (key_i, flicker) = match scene {
        "flash" => ((2.0 * core::f32::consts::PI * 5.0 * time).sin() + 1.0, 0.0),
        "switch" => {
            let on = time < 1.0 || ((time - 1.0) / 3.0).floor() as i64 % 2 == 1;
            let f = 0.6 + 0.4 * spvg::sequence::pcg3d16([t, 7, 11])[0] as f32 / 65535.0;
            (if on { 1.0 } else { 0.0 }, f)
        }
        _ => (1.0, 0.0),
    };
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
        let key = key_i * if x + 0.5 * y < 0.5 * w { 1.0 } else { 0.08 };
        let (cx, cy, r) = (0.3 * w, 0.3 * h, 0.08 * w);
        let g = (-((x - cx).powi(2) + (y - cy).powi(2)) / (r * r)).exp();
        let small = flicker * 0.6 * g;
        let c = [
            key + 0.05 + small,
            0.85 * key + 0.055 + 0.7 * small,
            0.75 * key + 0.065 + 0.4 * small,
        ];
        f.lighting.push([
            f16::from_f32(c[0]),
            f16::from_f32(c[1]),
            f16::from_f32(c[2]),
            f16::ONE,
        ]);
    }
    f
}

fn run(a: &Args) -> Result<String, String> {
    let d = acquire_device().map_err(|e| e.to_string())?;
    let config = SpvgConfig::published();
    let pixels = f64::from(a.width) * f64::from(a.height);
    let (beta_min, beta_max) = (
        f64::from(config.min_samples_f()),
        f64::from(config.max_samples_f()),
    );
    // The subsurface pass counts the masked pixels; AO every pixel.
    let counted = if a.ao {
        pixels
    } else {
        let m = sss_inputs(&a.scene, a.width, a.height, 0).mask;
        m.iter().filter(|&&v| v != 0).count() as f64
    };
    let time = FrameTimeConfig::builder(a.target_ms, beta_min * counted, beta_max * counted)
        .build()
        .map_err(|e| e.to_string())?;
    let initial = (8.0 * counted).clamp(beta_min * counted, beta_max * counted);
    let time = FrameTimeGovernor::new(time, initial).map_err(|e| e.to_string())?;
    let sigma0 = f64::from(config.target_variance());
    let spp = Governor::new(
        // Gain 1: the loop here reads the frame's total back before the next frame
        // (latency 1), where the budget governor's integral is deadbeat for a total
        // proportional to 1 / sigma0^2, and slower (not unstable) where counts sit at
        // their bounds.
        BudgetConfig::builder(initial)
            .gain(1.0)
            .target_range(sigma0 * 1e-4, sigma0 * 1e6)
            .build()
            .map_err(|e| e.to_string())?,
        sigma0,
    )
    .map_err(|e| e.to_string())?;
    let mut steer = FrameTimeSteering::new(time, spp).map_err(|e| e.to_string())?;
    println!(
        "{}, {} {} at {} x {}, target {} ms, budgets [{:.0}, {:.0}] samples{}",
        d.describe(),
        if a.ao { "ao" } else { "sss" },
        a.scene,
        a.width,
        a.height,
        a.target_ms,
        beta_min * counted,
        beta_max * counted,
        if a.classified {
            ", classified dispatch"
        } else {
            ""
        }
    );
    let mut csv = String::from("frame,budget,samples,ms,fixed_ms,ms_per_msample,target_variance\n");
    let mut inside = 0;
    let mut sss = (!a.ao).then(|| SssPass::for_device(&d, Model::As, a.width, a.height));
    let mut ao = if a.ao {
        let settings = AdaptiveSettings {
            classified_dispatch: a.classified,
            ..AdaptiveSettings::default()
        };
        Some(
            AoPass::new(
                &d.device,
                &d.queue,
                a.width,
                a.height,
                AoMode::Adaptive,
                settings,
            )
            .map_err(|e| e.to_string())?,
        )
    } else {
        None
    };
    let scene = AoScene {
        width: a.width,
        height: a.height,
        motion: if a.scene == "pan" {
            Motion::Pan { speed: 2.0 }
        } else {
            Motion::Static
        },
    };
    for t in 0..a.frames {
        let target = steer.target() as f32;
        let (samples, ms) = if let Some(pass) = &mut sss {
            let cfg = PassConfig {
                spvg: config
                    .to_builder()
                    .target_variance(target)
                    .build()
                    .map_err(|e| e.to_string())?,
                classified_dispatch: a.classified,
                ..PassConfig::default()
            };
            let inputs = sss_inputs(&a.scene, a.width, a.height, t);
            let p = pass
                .frame_params(&cfg, &SKIN1, t)
                .map_err(|e| e.to_string())?;
            let (out, times) = pass
                .run_frame_per_pass(&p, &inputs)
                .map_err(|e| e.to_string())?;
            let n: f64 = out
                .count
                .iter()
                .zip(&inputs.mask)
                .filter(|(_, m)| **m != 0)
                .map(|(c, _)| f64::from(*c))
                .sum();
            (n, times.sampling_ms)
        } else if let Some(pass) = &mut ao {
            if let Some(c) = pass.adaptive_mut() {
                c.set_target_variance(target).map_err(|e| e.to_string())?;
            }
            let f = pass
                .run_frame(&scene.params(t))
                .map_err(|e| e.to_string())?;
            let n: f64 = f.count.iter().map(|&c| f64::from(c)).sum();
            (n, pass.last_frame_ms())
        } else {
            return Err("no pass".into());
        };
        let budget = steer.time().budget();
        steer.after_frame(samples, ms);
        let m = steer.time().model();
        let (fixed, rate) = m.map_or((f64::NAN, f64::NAN), |m| {
            (m.fixed_ms, m.ms_per_sample * 1e6)
        });
        if t >= a.warmup && (ms / a.target_ms - 1.0).abs() <= 0.1 {
            inside += 1;
        }
        println!(
            "  frame {t:>3}: sigma0^2 {target:.2e}, budget {:>6.2} spp, took {:>6.2} spp, {ms:>8.2} ms; cost {fixed:.2} ms + {rate:.3} ms per Msample",
            budget / counted,
            samples / counted
        );
        let _ = writeln!(
            csv,
            "{t},{budget:.0},{samples:.0},{ms:.3},{fixed:.4},{rate:.5},{target:e}"
        );
    }
    let measured = a.frames - a.warmup;
    println!(
        "band: {inside} of {measured} frames after the warm-up within 10% of {} ms ({:.0}%); reach: {:?}",
        a.target_ms,
        100.0 * f64::from(inside) / f64::from(measured),
        steer.time().reach()
    );
    let _ = writeln!(
        csv,
        "band,{inside},{measured},,,,\"{:?}\"",
        steer.time().reach()
    );
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
