//! The motion section of the report on its own (the `spvg-report` binary runs it too):
//! `cargo run --release -p spvg-report --bin spvg-motion -- [--full] [--cpu] [--frames N]
//! [--sigma0-sq X] [--out DIR]`. Writes `motion.md`, `motion.csv`, `motion_runs.csv` and
//! the charts; exits 2 when an acceptance line fails. The default suite runs what every acceptance line needs;
//! `--full` adds every knob row, as `spvg-report --full` does.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use spvg_report::motion::{MotionOptions, runs::frames_to_render, write};
use spvg_report::progress::Progress;
use spvg_report::wgpu_api::acquire_device;

/// The motion section of the spvg report on its own: the adaptive component with
/// motion-vector reprojection on the AO consumer under pans, a rotation, a moving sphere,
/// several faster moving objects and a dolly, against static cameras and fixed counts,
/// with its acceptance lines.
///
/// Writes motion.md, motion.csv, motion_runs.csv and the charts into --out; exits 2 when
/// an acceptance line fails.
#[derive(Debug, Parser)]
#[command(name = "spvg-motion", version, about, long_about)]
struct Cli {
    /// The whole suite: as-identity on every scene and every knob row.
    #[arg(long)]
    full: bool,
    /// Run on the CPU twin instead of a GPU adapter.
    #[arg(long)]
    cpu: bool,
    /// Frames per run [2, 100000] (the first 16 are the unscored warm-up).
    #[arg(long, value_name = "N", default_value_t = 48, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(2..=100_000))]
    frames: u32,
    /// Target variance sigma0^2 of the adaptive runs: finite, > 0.
    #[arg(
        long = "sigma0-sq",
        value_name = "X",
        default_value_t = 1e-4,
        allow_negative_numbers = true
    )]
    sigma0_sq: f32,
    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(2),
        Err(e) => {
            eprintln!("spvg-motion: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: &Cli) -> Result<bool, Box<dyn std::error::Error>> {
    let mut opts = MotionOptions::new()?;
    opts.full = cli.full;
    opts.frames = cli.frames;
    opts.config = opts
        .config
        .to_builder()
        .target_variance(cli.sigma0_sq)
        .build()
        .map_err(|e| format!("--sigma0-sq: {e}"))?;
    let dev = if cli.cpu { None } else { acquire_device().ok() };
    let backend = dev
        .as_ref()
        .map_or("CPU twin".to_string(), |d| d.describe());
    eprintln!("spvg-motion: {backend}");
    let progress = Progress::new("spvg-motion", frames_to_render(&opts, dev.is_some()));
    let (md, lines) = write(&cli.out, dev.as_ref(), &opts, &backend, &progress)?;
    progress.finish();
    println!("{md}");
    Ok(lines.iter().all(|c| c.pass))
}
