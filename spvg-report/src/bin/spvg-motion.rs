//! The motion report on its own: `cargo run --release -p spvg-report --bin spvg-motion --
//! [--cpu] [--frames N] [--out DIR]`. Writes `motion.md` and `motion.csv`.

use std::process::ExitCode;

use spvg_report::motion::{MotionOptions, markdown, report};

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
        match a.as_str() {
            "--cpu" => cpu = true,
            "--frames" => opts.frames = args.next().ok_or("--frames needs a value")?.parse()?,
            "--sigma0-sq" => {
                let v: f32 = args.next().ok_or("--sigma0-sq needs a value")?.parse()?;
                opts.config = opts.config.to_builder().target_variance(v).build()?;
            }
            "--out" => out = args.next().ok_or("--out needs a value")?.into(),
            other => return Err(format!("unknown argument {other:?}").into()),
        }
    }
    let dev = if cpu {
        None
    } else {
        spvg_wgpu::acquire_device().ok()
    };
    let backend = dev
        .as_ref()
        .map_or("CPU twin".to_string(), |d| d.describe());
    eprintln!("spvg-motion: {backend}");
    let rep = report(dev.as_ref(), &opts, |s| eprintln!("  {s}"))?;
    let (md, csv) = markdown(&rep, &opts, &backend);
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    std::fs::write(out.join("motion.md"), &md)?;
    std::fs::write(out.join("motion.csv"), &csv)?;
    println!("{md}");
    Ok(rep.lines.iter().all(|(_, ok)| *ok))
}
