//! The motion section of the report on its own (the `spvg-report` binary runs it too):
//! `cargo run --release -p spvg-report --bin spvg-motion -- [--full] [--cpu] [--frames N]
//! [--sigma0-sq X] [--out DIR]`. Writes `motion.md`, `motion.csv`, `motion_runs.csv` and
//! the charts; exits 2 when an acceptance line fails. The default suite runs what every acceptance line needs;
//! `--full` adds every knob row, as `spvg-report --full` does.

use std::process::ExitCode;

use spvg_report::motion::{MotionOptions, runs::frames_to_render, write};
use spvg_report::progress::Progress;
use spvg_report::wgpu_api::acquire_device;

fn main() -> ExitCode {
    match run() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(2),
        Err(e) => {
            eprintln!("spvg-motion: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<bool, Box<dyn std::error::Error>> {
    let mut opts = MotionOptions::new()?;
    let mut out = std::path::PathBuf::from("out");
    let mut cpu = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |flag: &str| args.next().ok_or(format!("{flag} needs a value"));
        match a.as_str() {
            "--cpu" => cpu = true,
            "--full" => opts.full = true,
            "--frames" => {
                opts.frames = value("--frames")?
                    .parse()
                    .map_err(|e| format!("--frames: {e}"))?;
                if opts.frames < 2 {
                    return Err("--frames must be at least 2".into());
                }
            }
            "--sigma0-sq" => {
                let v: f32 = value("--sigma0-sq")?
                    .parse()
                    .map_err(|e| format!("--sigma0-sq: {e}"))?;
                opts.config = opts.config.to_builder().target_variance(v).build()?;
            }
            "--out" => out = value("--out")?.into(),
            other => return Err(format!("unknown argument {other:?}").into()),
        }
    }
    let dev = if cpu { None } else { acquire_device().ok() };
    let backend = dev
        .as_ref()
        .map_or("CPU twin".to_string(), |d| d.describe());
    eprintln!("spvg-motion: {backend}");
    let progress = Progress::new("spvg-motion", frames_to_render(&opts, dev.is_some()));
    let (md, lines) = write(&out, dev.as_ref(), &opts, &backend, &progress)?;
    progress.finish();
    println!("{md}");
    Ok(lines.iter().all(|c| c.pass))
}
