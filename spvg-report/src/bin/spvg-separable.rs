//! The separable section on its own (the `spvg-report` binary runs it too):
//! `cargo run --release -p spvg-report --bin spvg-separable -- [--full] [--cpu]
//! [--only-budget] [--frames N] [--size WxH] [--out DIR]`. Prints the fit table per preset, the
//! focus-region scene (separable-only, AS, CCV, hybrid), the budget table (fixed against
//! adaptive at 64, 128 and 512) and, with `--full`, the per-pass times at 1920x1080
//! (needs a device); writes `separable.md`; exits 2 when an acceptance line fails.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use spvg_report::budget_table;
use spvg_report::progress::Progress;
use spvg_report::separable_section::{SectionOptions, write};
use spvg_report::wgpu_api::{GpuDevice, acquire_device};

/// The separable section of the spvg report on its own: the separable subsurface profile
/// fitted to Burley, the hybrid pass on a focus-region scene, the sample-budget table and
/// (with --full) the per-pass times at 1920x1080.
///
/// Writes separable.md into --out; exits 2 when an acceptance line fails.
#[derive(Debug, Parser)]
#[command(name = "spvg-separable", version, about, long_about)]
struct Cli {
    /// The whole suite: the budget table at 160x120 and 16 frames, and the per-pass table.
    #[arg(long)]
    full: bool,
    /// Run on the CPU twins instead of a GPU adapter (no per-pass table then).
    #[arg(long)]
    cpu: bool,
    /// Frames per run of the focus scene [2, 100000]; its metrics average the second half.
    #[arg(long, value_name = "N", default_value_t = 16, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(2..=100_000))]
    frames: u32,
    /// Frame size of the focus scene, WxH, each side in [1, 8192].
    #[arg(long, value_name = "WxH", default_value = "160x120", value_parser = parse_size)]
    size: [u32; 2],
    /// Only the budget table (no fit, no focus scene, no per-pass table); prints its
    /// markdown and writes it to budget.md.
    #[arg(long)]
    only_budget: bool,
    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
}

fn parse_size(s: &str) -> Result<[u32; 2], String> {
    let (w, h) = s.split_once('x').ok_or("takes WxH, e.g. 160x120")?;
    let side = |v: &str| match v.parse::<u32>() {
        Ok(n) if (1..=8192).contains(&n) => Ok(n),
        _ => Err(format!("{v:?} is not a side in [1, 8192]")),
    };
    Ok([side(w)?, side(h)?])
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(2),
        Err(e) => {
            eprintln!("spvg-separable: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: &Cli) -> Result<bool, Box<dyn std::error::Error>> {
    let mut opts = SectionOptions::new(cli.full);
    opts.focus.frames = cli.frames;
    opts.focus.size = cli.size;
    let dev = if cli.cpu { None } else { acquire_device().ok() };
    eprintln!(
        "spvg-separable: {}",
        dev.as_ref()
            .map_or("CPU twin".to_string(), |d| d.describe())
    );
    if cli.only_budget {
        let cpu_time = dev.as_ref().is_none_or(GpuDevice::is_software);
        let rows = budget_table::run_budgets(dev.as_ref(), &opts.budgets)?;
        let md = budget_table::markdown(&rows, &opts.budgets, cpu_time);
        std::fs::create_dir_all(&cli.out)?;
        std::fs::write(cli.out.join("budget.md"), &md)?;
        println!("{md}");
        return Ok(budget_table::checks(&rows).iter().all(|c| c.pass));
    }
    let progress = Progress::new("spvg-separable", 0);
    let (md, groups) = write(&cli.out, dev.as_ref(), &opts, &progress)?;
    progress.finish();
    println!("{md}");
    Ok(groups.iter().flat_map(|(_, c)| c).all(|c| c.pass))
}
