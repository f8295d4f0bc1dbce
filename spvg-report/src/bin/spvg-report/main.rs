//! `spvg-report`: runs every scene with every sampling model, measures speed and accuracy
//! against converged references, and writes `report.md`, `runs.csv`, `frames.csv`, SVG
//! charts and captioned PNG frame images, then the motion section. The default suite
//! judges every acceptance check; `--full` adds the sweep of the target variance and
//! kappa and every motion knob row. `spvg-report --help` lists the flags.

mod cli;

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use spvg::burley::MaterialPreset;
use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_report::error::ReportError;
use spvg_report::evaluate::RunSpec;
use spvg_report::images::ImageWriter;
use spvg_report::motion::{self, MotionOptions};
use spvg_report::progress::Progress;
use spvg_report::report::{Report, ReportInputs, RunPlan, run_scenes, sweep_settings};
use spvg_report::scene::{Lighting, SceneKind};
use spvg_report::separable_section::{self, SectionOptions};
use spvg_report::timing;
use spvg_report::wgpu_api::{Backend, BackendChoice, Model, PassConfig};

use cli::{BackendArg, Cli, MaterialArg, SceneArg};

/// Fewest frames the motion section runs: it leaves out a 16-frame warm-up.
const MOTION_MIN_FRAMES: u32 = 32;

/// The scenes, runs and materials of the command line.
fn plan(cli: &Cli) -> (RunPlan, Vec<(String, PassConfig)>) {
    let material: MaterialPreset = match cli.material {
        MaterialArg::Skin1 => SKIN1,
        MaterialArg::Marble => MARBLE,
    };
    let defaults = PassConfig::default();
    // The command line's values were checked when parsed (parse_sigma0_sq,
    // parse_firefly_clamp); should the controller still refuse them together, the
    // defaults run and the report says so in its settings line.
    let spvg = defaults
        .spvg
        .to_builder()
        .target_variance(cli.sigma0_sq)
        .firefly_clamp(cli.firefly_clamp)
        .build()
        .unwrap_or(defaults.spvg);
    let base = PassConfig {
        spvg,
        afis: cli.afis,
        ..defaults
    };
    let settings = sweep_settings(base, cli.full && !cli.no_sweep);
    let mut specs = RunSpec::for_models(&cli.models(), &settings);
    // The equal-quality check is judged at the published target variance where it runs:
    // without the sweep, AS runs at it too (the sweep's label, so it is not a report run).
    let published = spvg::SpvgConfig::<f32>::published().target_variance();
    if cli.models().contains(&Model::As)
        && !settings
            .iter()
            .any(|(_, c)| c.spvg.target_variance() == published)
    {
        specs.push(RunSpec {
            model: Model::As,
            cfg: PassConfig {
                spvg: base
                    .spvg
                    .to_builder()
                    .target_variance(published)
                    .build()
                    .unwrap_or(base.spvg),
                ..base
            },
            label: format!("as s0^2={published:e}"),
            budget_spp: None,
            budget_gain: cli.budget_gain,
            guided: false,
        });
    }
    // AS with the TAA-guided update: judged on flash and switch, on every scene under
    // `--full` (RunPlan::specs_for).
    if cli.models().contains(&Model::As) {
        specs.push(RunSpec::guided(base));
    }
    if !cli.no_budget {
        specs.push(RunSpec::budget(base, cli.budget_spp, cli.budget_gain));
    }
    let scenes = cli
        .scenes()
        .iter()
        .map(|s| match s {
            SceneArg::Static => SceneKind::Static,
            SceneArg::Flash => SceneKind::Flash,
            SceneArg::Switch => SceneKind::Switch,
            SceneArg::Occluders => SceneKind::Occluders,
        })
        .collect();
    let plan = RunPlan {
        scenes,
        specs,
        material,
        lighting: if cli.gradient {
            Lighting::Gradient
        } else {
            Lighting::Constant
        },
        width: cli.width,
        height: cli.height,
        frames: cli.frames,
        image_frame: cli.image_frame.unwrap_or(63.min(cli.frames - 1)),
        reference: !cli.no_reference,
        budget_everywhere: cli.full,
        guide_everywhere: cli.full,
    };
    (plan, settings)
}

/// The suite this run holds, in one sentence for report.md.
fn suite(cli: &Cli) -> String {
    if cli.full {
        format!(
            "full (`--full`): every scene and model, the budget run on every scene, {}every motion scene, mode and knob row.",
            if cli.no_sweep {
                "no sweep (`--no-sweep`), "
            } else {
                "the sweep of sigma0^2 and kappa, "
            }
        )
    } else {
        "default: every acceptance check at the report setting (scenes static, flash, switch; fixed16, fixed64, AS, CCV, OCV; AS at the published sigma0^2 = 1e-4 for the equal-quality check; the budget run and AS with the TAA-guided update on flash and switch) and every motion line (AS, fixed16, fixed32 and fixed64 on every motion scene; the motion warm-up unscored); `--full` adds the occluders scene, fixed8 and fixed32, the budget run and the TAA-guided AS on every scene, the sweep of sigma0^2 and kappa (not judged), and in the motion section as-identity on every scene, the knob rows (as-beta-min, as-border-texel, as-no-dilation, as-nearest-only) and the warm-up's PSNR.".into()
    }
}

/// Whether the motion section runs, and the options it runs with.
fn motion_options(cli: &Cli) -> Result<Option<MotionOptions>, ReportError> {
    if cli.no_motion || cli.no_reference {
        return Ok(None);
    }
    if cli.frames < MOTION_MIN_FRAMES {
        eprintln!("spvg-report: motion section skipped (fewer than {MOTION_MIN_FRAMES} frames)");
        return Ok(None);
    }
    let mut opts = if cli.full {
        MotionOptions::full()
    } else {
        MotionOptions::new()
    }
    .map_err(|e| ReportError::Usage(format!("motion options: {e}")))?;
    opts.frames = opts.frames.min(cli.frames);
    Ok(Some(opts))
}

fn run(cli: &Cli) -> Result<(), ReportError> {
    cli::validate(cli)?;
    let started = Instant::now();
    let (plan, settings) = plan(cli);
    let backend = Backend::resolve(match cli.backend {
        BackendArg::Auto => BackendChoice::Auto,
        BackendArg::Gpu => BackendChoice::Gpu,
        BackendArg::Cpu => BackendChoice::Cpu,
    })?;
    cli::check_frame(&backend, cli)?;
    eprintln!("spvg-report: backend {}", backend.describe());
    let dev = match &backend {
        Backend::Gpu(d) => Some(&**d),
        Backend::Cpu => None,
    };
    let motion = motion_options(cli)?;
    let progress = Progress::new("spvg-report", plan.frames_to_render());
    if let Some(opts) = &motion {
        progress.add_frames(motion::runs::frames_to_render(opts, dev.is_some()));
    }
    let mut report = Report::new(ReportInputs {
        width: cli.width,
        height: cli.height,
        frames: cli.frames,
        material: plan.material.name,
        lighting: plan.lighting,
        afis: cli.afis,
        sigma0_sq: cli.sigma0_sq,
        reference: !cli.no_reference,
        image_frame: plan.image_frame,
        backend: backend.describe(),
        timing: timing::Timing::of(&backend),
        settings,
        budget_spp: (!cli.no_budget).then_some(cli.budget_spp),
        budget_gain: cli.budget_gain,
        suite: suite(cli),
    });
    let mut images = ImageWriter::new(&cli.out);
    run_scenes(&backend, &plan, &mut report, &mut images, &progress)?;
    let motion_md = match &motion {
        Some(opts) => Some(motion::write(
            &cli.out,
            dev,
            opts,
            &backend.describe(),
            &progress,
        )?),
        None => None,
    };
    let separable_md = if cli.no_separable || cli.no_reference {
        None
    } else {
        Some(separable_section::write(
            &cli.out,
            dev,
            &SectionOptions::new(cli.full),
            &progress,
        )?)
    };
    progress.finish();
    if let Some((_, checks)) = &motion_md {
        report.push_section_checks("motion", checks);
    }
    if let Some((_, groups)) = &separable_md {
        for (name, checks) in groups {
            report.push_section_checks(name, checks);
        }
    }
    report.finish(&cli.out, started.elapsed().as_secs_f64(), images.skipped)?;
    print!("{}", report.stdout_summary());
    if let Some((md, checks)) = motion_md {
        append_section(cli, "motion", &md, checks.iter().all(|c| c.pass))?;
    }
    if let Some((md, groups)) = separable_md {
        let ok = groups.iter().flat_map(|(_, c)| c).all(|c| c.pass);
        append_section(cli, "separable", &md, ok)?;
    }
    println!("wrote {}", cli.out.join("report.md").display());
    Ok(())
}

/// Appends the section `name` (its file `name.md`) to `report.md` and says whether every
/// line passed.
fn append_section(cli: &Cli, name: &str, md: &str, ok: bool) -> Result<(), ReportError> {
    let path = cli.out.join("report.md");
    let mut text = std::fs::read_to_string(&path).map_err(|e| ReportError::io(&path, e))?;
    text.push('\n');
    text.push_str(md);
    std::fs::write(&path, text).map_err(|e| ReportError::io(&path, e))?;
    println!(
        "{name} section: {} (details in {})",
        if ok {
            "every line passes"
        } else {
            "some lines fail"
        },
        cli.out.join(format!("{name}.md")).display()
    );
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
