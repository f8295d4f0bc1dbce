//! The separable section on its own: `cargo run --release -p spvg-report --bin
//! spvg-separable -- [--full] [--cpu] [--frames N] [--size WxH] [--out DIR]`. Prints the
//! fit table per preset, the focus-region scene (separable-only, AS, CCV, hybrid) and the
//! budget table (fixed against adaptive at 64, 128 and 512; 96x72 and 8 frames, 160x120 and
//! 16 with `--full`) and the per-pass times at 1920x1080 (fixed 64 and AS, 3 frames; needs
//! a device), writes `separable.md` to the output folder, and exits 2 when an
//! acceptance line fails. `--frames` and `--size` set the focus scene.

use std::process::ExitCode;

use spvg_report::budget_table::{self, BudgetOptions, run_budgets};
use spvg_report::pass_breakdown::{self, run_breakdown};
use spvg_report::separable::{FocusOptions, checks, fit_rows, markdown, run_focus};
use spvg_report::wgpu_api::acquire_device;

fn main() -> ExitCode {
    match run() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(2),
        Err(e) => {
            eprintln!("spvg-separable: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<bool, Box<dyn std::error::Error>> {
    let mut opts = FocusOptions::default();
    let mut out = std::path::PathBuf::from("out");
    let mut cpu = false;
    let mut budgets = BudgetOptions::default();
    let mut full = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |flag: &str| args.next().ok_or(format!("{flag} needs a value"));
        match a.as_str() {
            "--cpu" => cpu = true,
            "--full" => full = true,
            "--frames" => {
                opts.frames = value("--frames")?
                    .parse()
                    .map_err(|e| format!("--frames: {e}"))?;
                if opts.frames < 2 {
                    return Err("--frames must be at least 2".into());
                }
            }
            "--size" => {
                let v = value("--size")?;
                let (w, h) = v.split_once('x').ok_or("--size takes WxH")?;
                opts.size = [
                    w.parse().map_err(|e| format!("--size: {e}"))?,
                    h.parse().map_err(|e| format!("--size: {e}"))?,
                ];
                if opts.size.contains(&0) {
                    return Err("--size must be at least 1x1".into());
                }
            }
            "--out" => out = value("--out")?.into(),
            other => return Err(format!("unknown argument {other:?}").into()),
        }
    }
    let dev = if cpu { None } else { acquire_device().ok() };
    eprintln!(
        "spvg-separable: {}",
        dev.as_ref()
            .map_or("CPU twin".to_string(), |d| d.describe())
    );
    let fits = fit_rows()?;
    let result = run_focus(dev.as_ref(), &opts)?;
    if full {
        budgets.size = [160, 120];
        budgets.frames = 16;
    }
    let rows = run_budgets(dev.as_ref(), &budgets)?;
    let (bsize, bframes) = ([1920, 1080], 3);
    let breakdown = run_breakdown(dev.as_ref(), bsize, bframes)?;
    let mut md = markdown(&fits, &result, &opts);
    md.push('\n');
    md.push_str(&budget_table::markdown(&rows, &budgets, result.cpu_time));
    md.push('\n');
    md.push_str(&pass_breakdown::markdown(
        breakdown.as_deref(),
        bsize,
        bframes,
        result.cpu_time,
    ));
    std::fs::create_dir_all(&out)?;
    std::fs::write(out.join("separable.md"), &md)?;
    println!("{md}");
    let all = checks(&result)
        .into_iter()
        .chain(budget_table::checks(&rows));
    Ok(all.into_iter().all(|c| c.pass))
}
