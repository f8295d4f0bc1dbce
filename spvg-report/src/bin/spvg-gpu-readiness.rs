//! The GPU-readiness command: `cargo run --release -p spvg-report --bin
//! spvg-gpu-readiness -- [--frames N] [--warmup N] [--out DIR]`. Times the adaptive
//! component's estimate and update (AS, count dilation radius 1) at 1920x1080 and
//! 3840x2160 against a copy kernel moving the same bytes on the same device, prints the
//! table with the ratio and writes it to `gpu_readiness.md`. Runs unchanged on a
//! hardware GPU (timestamp queries where the adapter has them); on a software adapter it
//! says the figures are CPU time.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use spvg_report::error::ReportError;
use spvg_report::gpu_readiness::{ReadinessOptions, markdown, run};
use spvg_report::wgpu_api::acquire_device;

/// Times the adaptive component's estimate and update at 1920x1080 and 3840x2160 against
/// a copy kernel that reads and writes the same bytes per pixel on the same device, and
/// prints step / copy.
///
/// Uses GPU timestamp queries when the adapter has them, else the wall time from submit to
/// completion (CPU time on a software adapter such as lavapipe). Writes gpu_readiness.md
/// into --out.
#[derive(Debug, Parser)]
#[command(name = "spvg-gpu-readiness", version, about, long_about)]
struct Cli {
    /// Measured frames per size [1, 10000]; the table gives the median.
    #[arg(long, value_name = "N", default_value_t = 20, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    frames: u32,
    /// Frames run before the measured ones [0, 1000] (shader compilation, first touch).
    #[arg(long, value_name = "N", default_value_t = 3, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(0..=1_000))]
    warmup: u32,
    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match go(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("spvg-gpu-readiness: {e}");
            ExitCode::FAILURE
        }
    }
}

fn go(cli: &Cli) -> Result<(), ReportError> {
    let device = acquire_device()?;
    eprintln!("spvg-gpu-readiness: {}", device.describe());
    let opts = ReadinessOptions {
        frames: cli.frames,
        warmup: cli.warmup,
        ..ReadinessOptions::default()
    };
    let md = markdown(&run(&device, &opts)?);
    std::fs::create_dir_all(&cli.out).map_err(|e| ReportError::io(&cli.out, e))?;
    let path = cli.out.join("gpu_readiness.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    println!("{md}");
    Ok(())
}
