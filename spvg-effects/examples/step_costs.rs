//! Where the adaptive component's own time goes: its estimate and update steps timed
//! alone (each submitted and waited for, median over the frames after a warm-up) under
//! one rule switched at a time, on the GPU-readiness inputs (a pan of 1.5 px right and
//! 0.5 px up over a sloped surface, two noisy monitored values in turn, no masks).
//!
//! Rows: the papers' rules (no count dilation, no spatial variance of young histories);
//! then each default rule added alone: the spatial variance of young histories (3x3
//! moments, the estimate also writing this frame's depth), count dilation radius 1
//! without and with the neighbour prior, and the count classification; then the
//! component's defaults with dilation 1 (what the effects run). The rows run interleaved
//! frame by frame; the difference to the first row is what the rule costs.
//!
//! `cargo run --release -p spvg-effects --example step_costs -- [--width W] [--height H]
//! [--frames N] [--warmup K]` (defaults 1920 x 1080, 6 frames, 2 of warm-up).

use std::process::ExitCode;
use std::time::Instant;

use spvg::SpvgConfig;
use spvg_wgpu::adaptive::{AdaptivePass, AdaptiveSettings, EstimateInputs, UpdateInputs};
use spvg_wgpu::util::{GpuDevice, acquire_device};
use wgpu::{TextureFormat as Tf, TextureUsages as Tu};

fn upload(d: &GpuDevice, format: Tf, [w, h]: [u32; 2], data: &[f32]) -> wgpu::Texture {
    let t = d.device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: Tu::TEXTURE_BINDING | Tu::COPY_DST,
        view_formats: &[],
    });
    d.queue.write_texture(
        t.as_image_copy(),
        bytemuck::cast_slice(data),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * format.block_copy_size(None).unwrap_or(0)),
            rows_per_image: Some(h),
        },
        t.size(),
    );
    t
}

fn noise(x: u32, y: u32, seed: u32) -> f32 {
    let mut v = x.wrapping_mul(0x9E37_79B9) ^ y.wrapping_mul(0x85EB_CA6B) ^ seed;
    v ^= v >> 16;
    v = v.wrapping_mul(0x7FEB_352D);
    v ^= v >> 15;
    (v >> 8) as f32 / (1u32 << 24) as f32
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

fn wait(d: &GpuDevice, encoder: wgpu::CommandEncoder) -> Result<f64, String> {
    let start = Instant::now();
    d.queue.submit([encoder.finish()]);
    d.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    Ok(start.elapsed().as_secs_f64() * 1e3)
}

fn parse() -> Result<[u32; 4], String> {
    let mut a = [1920, 1080, 6, 2];
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let k = match flag.as_str() {
            "--width" => 0,
            "--height" => 1,
            "--frames" => 2,
            "--warmup" => 3,
            _ => return Err(format!("unknown argument {flag:?}")),
        };
        let v = it.next().ok_or(format!("{flag} needs a value"))?;
        a[k] = v
            .parse()
            .map_err(|_| format!("{flag}: {v:?} is not a whole number"))?;
    }
    if a[0] == 0 || a[1] == 0 || a[2] == 0 {
        return Err("--width, --height and --frames must be positive".into());
    }
    Ok(a)
}

fn run([w, h, frames, warmup]: [u32; 4]) -> Result<(), String> {
    let d = acquire_device().map_err(|e| e.to_string())?;
    println!(
        "{}, {w} x {h}, {frames} frames after {warmup} of warm-up, each step alone",
        d.describe()
    );
    let px = |f: &dyn Fn(u32, u32) -> Vec<f32>| -> Vec<f32> {
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .flat_map(|(x, y)| f(x, y))
            .collect()
    };
    let motion = upload(&d, Tf::Rg32Float, [w, h], &px(&|_, _| vec![1.5, -0.5]));
    let depth = upload(
        &d,
        Tf::R32Float,
        [w, h],
        &px(&|x, y| vec![2.0 + 3.0 * y as f32 / h as f32 + 0.5 * x as f32 / w as f32]),
    );
    let value = [1, 2].map(|s| {
        upload(
            &d,
            Tf::R32Float,
            [w, h],
            &px(&|x, y| vec![0.4 + 0.2 * noise(x, y, s)]),
        )
    });
    let config = |spatial: u32| {
        SpvgConfig::builder()
            .target_variance(1e-4)
            .spatial_variance(spatial)
            .build()
            .map_err(|e| e.to_string())
    };
    let papers = AdaptiveSettings {
        config: config(0)?,
        dilation: 0,
        neighbour_prior: false,
        ..AdaptiveSettings::default()
    };
    let rows: Vec<(&str, AdaptiveSettings)> = vec![
        ("papers' rules", papers),
        (
            "+ spatial variance (3x3)",
            AdaptiveSettings {
                config: config(3)?,
                ..papers
            },
        ),
        (
            "+ dilation 1",
            AdaptiveSettings {
                dilation: 1,
                ..papers
            },
        ),
        (
            "+ dilation 1 and prior",
            AdaptiveSettings {
                dilation: 1,
                neighbour_prior: true,
                ..papers
            },
        ),
        (
            "+ classification",
            AdaptiveSettings {
                classified_dispatch: true,
                ..papers
            },
        ),
        (
            "defaults, dilation 1",
            AdaptiveSettings {
                config: config(3)?,
                dilation: 1,
                ..AdaptiveSettings::default()
            },
        ),
    ];
    // All rows interleaved frame by frame, so that they see the same machine load.
    let mut passes = Vec::new();
    for (_, settings) in &rows {
        passes.push(AdaptivePass::new(&d.device, *settings, w, h).map_err(|e| e.to_string())?);
    }
    let mut times = vec![(Vec::new(), Vec::new()); rows.len()];
    for f in 0..warmup + frames {
        for (pass, (est, upd)) in passes.iter_mut().zip(&mut times) {
            let mut e = d.device.create_command_encoder(&Default::default());
            pass.record_estimate(&mut e, &EstimateInputs::new(&motion, &depth, &depth))
                .map_err(|e| e.to_string())?;
            let te = wait(&d, e)?;
            let mut e = d.device.create_command_encoder(&Default::default());
            pass.record_update(&mut e, &UpdateInputs::new(&value[(f % 2) as usize]))
                .map_err(|e| e.to_string())?;
            let tu = wait(&d, e)?;
            if f >= warmup {
                est.push(te);
                upd.push(tu);
            }
        }
    }
    println!("| rules | estimate (ms) | update (ms) |\n| --- | --- | --- |");
    let (be, bu) = (median(&times[0].0), median(&times[0].1));
    for ((name, _), (est, upd)) in rows.iter().zip(&times) {
        let (e, u) = (median(est), median(upd));
        println!(
            "| {name} | {e:.1} ({:+.1}) | {u:.1} ({:+.1}) |",
            e - be,
            u - bu
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    match parse().and_then(run) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
