//! `spvg-report`: runs every scene with every sampling model (and a sweep of the target
//! variance and kappa), measures speed and accuracy against converged references, and
//! writes `report.md`, `runs.csv`, `frames.csv`, SVG charts and captioned PNG frame images.
//! `spvg-report --help` lists the flags.

use std::io::IsTerminal as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use spvg::burley::MaterialPreset;
use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_report::error::ReportError;
use spvg_report::evaluate::{ReferenceCache, RunSpec, run_scene};
use spvg_report::reference::Quadrature;
use spvg_report::report::{Report, ReportInputs, SceneRuns, sweep_settings};
use spvg_report::scene::{Lighting, Scene, SceneKind};
use spvg_report::{images, timing};
use spvg_wgpu::sss::{Model, PassConfig};
use spvg_wgpu::{Backend, BackendChoice};

/// Largest fixed sample count (the core's budget limit).
const MAX_FIXED: u32 = 1024;

/// Largest frame side the command line accepts; the adapter's own limit is checked once
/// the device exists (lavapipe: 16384).
const MAX_SIDE: u32 = 32768;

/// Largest frame the CPU twin runs (pixels): its frame buffers are host memory.
const MAX_CPU_PIXELS: u64 = 1 << 25;

/// Speed and accuracy report of the spvg subsurface-scattering pass.
///
/// Runs each scene with each model on the best backend found (a GPU adapter, else Mesa's
/// software Vulkan, else the CPU twin), compares every frame with a converged quadrature
/// reference, and writes report.md, runs.csv, frames.csv, SVG charts and PNG frame images
/// into --out.
#[derive(Debug, Parser)]
#[command(name = "spvg-report", version, about, long_about)]
struct Cli {
    /// Frame width in pixels [1, 32768]; the adapter's texture and buffer limits also apply.
    #[arg(long, value_name = "PX", default_value_t = 128, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    width: u32,

    /// Frame height in pixels [1, 32768]; the adapter's texture and buffer limits also apply.
    #[arg(long, value_name = "PX", default_value_t = 96, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    height: u32,

    /// Frames per run [2, 100000]; frame 0 (shader compilation) is left out of the timings.
    #[arg(long, value_name = "N", default_value_t = 96, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(2..=100_000))]
    frames: u32,

    /// Which implementation runs the pass.
    #[arg(long, value_enum, default_value_t = BackendArg::Auto)]
    backend: BackendArg,

    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,

    /// Subsurface material preset.
    #[arg(long, value_enum, default_value_t = MaterialArg::Skin1)]
    material: MaterialArg,

    /// Frame whose images are written [0, frames - 1] (default: 63, or the last frame of
    /// shorter runs).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    image_frame: Option<u32>,

    /// Target variance sigma0^2 of the adaptive models: finite, > 0 (the library default is
    /// the published 1e-4; the report's 5e-7 is explained in ARCHITECTURE.md).
    #[arg(long, value_name = "X", default_value = "5e-7", allow_negative_numbers = true, value_parser = parse_sigma0_sq)]
    sigma0_sq: f32,

    /// Scenes to run, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        value_name = "LIST",
        default_value = "static,flash,switch,occluders"
    )]
    scenes: Vec<SceneArg>,

    /// Models to run, comma-separated: fixedN (N in [1, 1024]), as, ccv, ocv.
    #[arg(long, value_delimiter = ',', value_name = "LIST", default_value = "fixed8,fixed16,fixed32,fixed64,as,ccv,ocv", value_parser = parse_model)]
    models: Vec<Model>,

    /// Skip the sweep of the target variance and kappa.
    #[arg(long)]
    no_sweep: bool,

    /// Frame budget of the `budget` run (CCV under the frame budget governor, one per
    /// scene), in samples per subsurface pixel: [beta_min, beta_max] = [8, 64], the
    /// totals the controller can reach.
    #[arg(long, value_name = "SPP", default_value_t = 16.0, allow_negative_numbers = true, value_parser = parse_budget_spp)]
    budget_spp: f64,

    /// Integral gain of the budget governor in (0, 1] (spvg::budget; 0.25 is critically
    /// damped with two frames of feedback latency; the report reads back synchronously,
    /// one frame).
    #[arg(long, value_name = "G", default_value_t = 0.25, allow_negative_numbers = true, value_parser = parse_budget_gain)]
    budget_gain: f64,

    /// Skip the `budget` run.
    #[arg(long)]
    no_budget: bool,

    /// Timing only: no quadrature reference, no PSNR, no acceptance checks, no charts (for
    /// large frames, where the reference would dominate the run time).
    #[arg(long)]
    no_reference: bool,

    /// Lights with a smooth spatial variation instead of constant lighting.
    #[arg(long)]
    gradient: bool,

    /// Read the lighting through its mip chain (filtered sampling, AFIS); references stay
    /// unfiltered.
    #[arg(long)]
    afis: bool,

    /// Skip the motion section (the adaptive component with reprojection on the ambient
    /// occlusion consumer: pans, a rotation, a moving object, at its own frame sizes, up to
    /// 48 frames; written to motion.md and appended to report.md). Also skipped by
    /// --no-reference and by runs of fewer than 32 frames (the section leaves out a 16-frame
    /// warm-up).
    #[arg(long)]
    no_motion: bool,
}

/// `--backend`.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum BackendArg {
    /// A hardware GPU, then software Vulkan (lavapipe), then the CPU twin.
    Auto,
    /// Any wgpu adapter; an error if there is none.
    Gpu,
    /// The multi-threaded CPU twin.
    Cpu,
}

/// `--material`.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum MaterialArg {
    /// Skin (Christensen & Burley's skin1).
    Skin1,
    /// Marble.
    Marble,
}

/// `--scenes`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum SceneArg {
    /// Constant lighting, a shadow edge and a depth step.
    Static,
    /// The key light flashes at 5 Hz.
    Flash,
    /// The key light switches off and on every 3 s, a small light flickers.
    Switch,
    /// A moving shadow and a moving occluder (disocclusion).
    Occluders,
}

fn parse_sigma0_sq(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|e| format!("{e}; expected a number, finite and > 0"))?;
    let cfg = PassConfig {
        sigma0_sq: v,
        ..PassConfig::default()
    };
    cfg.validate()
        .and_then(|()| cfg.encoding().map(|_| ()))
        .map_err(|_| format!("{v} is out of range: must be finite and > 0"))?;
    Ok(v)
}

fn parse_budget_spp(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|e| format!("{e}; expected a number of samples per pixel in [8, 64]"))?;
    let c = PassConfig::default();
    let (lo, hi) = (f64::from(c.beta_min), f64::from(c.beta_max));
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!(
            "{v} is out of range: the budget per pixel must lie in [beta_min, beta_max] = [{lo}, {hi}]"
        ))
    }
}

fn parse_budget_gain(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|e| format!("{e}; expected a gain in (0, 1]"))?;
    spvg::budget::BudgetConfig::builder(1.0)
        .gain(v)
        .build()
        .map_err(|_| format!("{v} is out of range: the gain must lie in (0, 1]"))?;
    Ok(v)
}

fn parse_model(s: &str) -> Result<Model, String> {
    match s.trim() {
        "as" => Ok(Model::As),
        "ccv" => Ok(Model::Ccv),
        "ocv" => Ok(Model::Ocv),
        other => {
            let n = other.strip_prefix("fixed").ok_or(format!(
                "unknown model {other:?}: expected fixedN (N in [1, {MAX_FIXED}]), as, ccv or ocv"
            ))?;
            let n: u32 = n
                .parse()
                .map_err(|_| format!("{other:?}: fixedN needs an integer N in [1, {MAX_FIXED}]"))?;
            if (1..=MAX_FIXED).contains(&n) {
                Ok(Model::Fixed(n))
            } else {
                Err(format!(
                    "{other}: N = {n} is outside [1, {MAX_FIXED}] (the sample budget limit)"
                ))
            }
        }
    }
}

/// A command-line error: which flag, and why.
fn flag_error(flag: &str, why: impl std::fmt::Display) -> ReportError {
    ReportError::Usage(format!("{flag}: {why}"))
}

/// Checks what clap's per-flag parsers cannot (relations between flags, the output folder)
/// and creates the output folder: everything before a device is requested.
fn validate(cli: &Cli) -> Result<(), ReportError> {
    if let Some(n) = cli.image_frame.filter(|n| *n >= cli.frames) {
        return Err(flag_error(
            "--image-frame",
            format!(
                "{n} is outside [0, {}] (--frames {})",
                cli.frames - 1,
                cli.frames
            ),
        ));
    }
    if cli.scenes.is_empty() {
        return Err(flag_error("--scenes", "needs at least one scene"));
    }
    if cli.models.is_empty() {
        return Err(flag_error("--models", "needs at least one model"));
    }
    std::fs::create_dir_all(&cli.out)
        .map_err(|e| flag_error("--out", format!("cannot create {}: {e}", cli.out.display())))?;
    let probe = cli.out.join(".spvg-report-write-test");
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .map_err(|e| {
            flag_error(
                "--out",
                format!("cannot write into {}: {e}", cli.out.display()),
            )
        })?;
    Ok(())
}

/// Checks the frame size against the resolved backend, before any resource exists.
fn check_frame(backend: &Backend, cli: &Cli) -> Result<(), ReportError> {
    let flags = format!("--width {} --height {}", cli.width, cli.height);
    match backend {
        Backend::Gpu(_) => backend
            .check_frame(cli.width, cli.height)
            .map_err(|e| flag_error(&flags, e)),
        Backend::Cpu => {
            let pixels = u64::from(cli.width) * u64::from(cli.height);
            if pixels > MAX_CPU_PIXELS {
                Err(flag_error(
                    &flags,
                    format!("{pixels} pixels exceed the CPU twin's limit of {MAX_CPU_PIXELS}"),
                ))
            } else {
                Ok(())
            }
        }
    }
}

fn run(cli: &Cli) -> Result<(), ReportError> {
    validate(cli)?;
    let image_frame = cli.image_frame.unwrap_or(63.min(cli.frames - 1));
    let material: MaterialPreset = match cli.material {
        MaterialArg::Skin1 => SKIN1,
        MaterialArg::Marble => MARBLE,
    };
    let base = PassConfig {
        sigma0_sq: cli.sigma0_sq,
        afis: cli.afis,
        ..PassConfig::default()
    };
    let settings = sweep_settings(base, !cli.no_sweep);
    let mut specs = RunSpec::for_models(&cli.models, &settings);
    if !cli.no_budget {
        specs.push(RunSpec::budget(base, cli.budget_spp, cli.budget_gain));
    }
    let scenes: Vec<SceneKind> = cli
        .scenes
        .iter()
        .map(|s| match s {
            SceneArg::Static => SceneKind::Static,
            SceneArg::Flash => SceneKind::Flash,
            SceneArg::Switch => SceneKind::Switch,
            SceneArg::Occluders => SceneKind::Occluders,
        })
        .collect();
    let lighting = if cli.gradient {
        Lighting::Gradient
    } else {
        Lighting::Constant
    };

    let backend = Backend::resolve(match cli.backend {
        BackendArg::Auto => BackendChoice::Auto,
        BackendArg::Gpu => BackendChoice::Gpu,
        BackendArg::Cpu => BackendChoice::Cpu,
    })?;
    check_frame(&backend, cli)?;
    let timing = timing::Timing::of(&backend);
    let started = Instant::now();
    let terminal = std::io::stderr().is_terminal();
    eprintln!("spvg-report: backend {}", backend.describe());

    let runs_total = (specs.len() * scenes.len()) as u64;
    let bar = ProgressBar::with_draw_target(
        Some(runs_total * u64::from(cli.frames)),
        if terminal {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{wide_bar}] {pos}/{len} frames, ETA {eta} {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );

    let mut report = Report::new(ReportInputs {
        width: cli.width,
        height: cli.height,
        frames: cli.frames,
        material: material.name,
        lighting,
        afis: cli.afis,
        sigma0_sq: cli.sigma0_sq,
        reference: !cli.no_reference,
        image_frame,
        backend: backend.describe(),
        timing,
        settings: settings.clone(),
        budget_spp: (!cli.no_budget).then_some(cli.budget_spp),
        budget_gain: cli.budget_gain,
    });
    let mut images = images::ImageWriter::new(&cli.out);
    let mut run_no = 0;
    for &kind in &scenes {
        let scene = Scene {
            lighting,
            ..Scene::new(kind, cli.width, cli.height)
        };
        let mut refs = ReferenceCache::new(
            scene,
            material,
            PassConfig::default(),
            Quadrature::default(),
        );
        let mut scene_runs = SceneRuns::new(kind);
        for spec in &specs {
            run_no += 1;
            bar.set_message(format!("{} {}", kind.name(), spec.label));
            let default_run = !spec.is_sweep();
            let mut shot = None;
            let (records, summary) = run_scene(
                &backend,
                scene,
                &material,
                spec,
                cli.frames,
                (!cli.no_reference).then_some(&mut refs),
                |t, out, reference, mask| {
                    bar.inc(1);
                    if t == image_frame && default_run {
                        shot = Some((out.clone(), reference.to_vec(), mask.to_vec()));
                    }
                },
            )?;
            if let Some((out, reference, mask)) = shot {
                scene_runs.frame_images(
                    &mut images,
                    &spec.label,
                    image_frame,
                    scene,
                    &out,
                    &reference,
                    &mask,
                )?;
            }
            if !terminal {
                eprintln!(
                    "spvg-report: [{run_no}/{runs_total}] {} {}: {:.1} spp, PSNR {:.2} dB, p50 {}, {:.0} s",
                    kind.name(),
                    spec.label,
                    summary.mean_spp,
                    summary.mean_psnr,
                    timing::ms(summary.p50_ms),
                    started.elapsed().as_secs_f64()
                );
            }
            scene_runs.push(spec, records, summary);
        }
        report.push_scene(scene_runs);
    }
    bar.finish_and_clear();
    report.finish(&cli.out, started.elapsed().as_secs_f64(), images.skipped)?;
    print!("{}", report.stdout_summary());
    if !(cli.no_motion || cli.no_reference) {
        if cli.frames >= 32 {
            motion_section(cli, &backend)?;
        } else {
            eprintln!("spvg-report: motion section skipped (fewer than 32 frames)");
        }
    }
    println!("wrote {}", cli.out.join("report.md").display());
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("spvg-report: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs the motion section and appends it to `report.md`.
fn motion_section(cli: &Cli, backend: &Backend) -> Result<(), ReportError> {
    let mut opts = spvg_report::motion::MotionOptions::new()
        .map_err(|e| ReportError::Usage(format!("motion options: {e}")))?;
    opts.frames = opts.frames.min(cli.frames).max(2);
    let dev = match backend {
        Backend::Gpu(d) => Some(&**d),
        Backend::Cpu => None,
    };
    eprintln!("spvg-report: motion section ({} frames)", opts.frames);
    let (md, ok) = spvg_report::motion::write(&cli.out, dev, &opts, &backend.describe(), |s| {
        eprintln!("spvg-report: motion: {s}");
    })?;
    let path = cli.out.join("report.md");
    let mut text = std::fs::read_to_string(&path).map_err(|e| ReportError::io(&path, e))?;
    text.push('\n');
    text.push_str(&md);
    std::fs::write(&path, text).map_err(|e| ReportError::io(&path, e))?;
    println!(
        "motion section: {} (details in {})",
        if ok {
            "every line passes"
        } else {
            "some lines fail"
        },
        cli.out.join("motion.md").display()
    );
    Ok(())
}
