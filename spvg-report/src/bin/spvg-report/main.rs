//! `spvg-report`: the report's sections as subcommands (`all`, the default, runs every
//! section), on one backend, with one verdict over every judged line. Writes `report.md`
//! (the verdict first, then each section) and each section's own files into `--out`.
//! `spvg-report --help` lists the subcommands and flags.

mod cli;

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use spvg::burley::MaterialPreset;
use spvg::burley::presets::{MARBLE, SKIN1};
use spvg_report::backend::{self, Resolved};
use spvg_report::budget::{self, BudgetOptions};
use spvg_report::cost::{self, CostOptions};
use spvg_report::error::ReportError;
use spvg_report::governor::{self, DeviceEffect, GovernorOptions};
use spvg_report::images::ImageWriter;
use spvg_report::motion::{self, MotionOptions};
use spvg_report::progress::Progress;
use spvg_report::scene::{Lighting, SceneKind};
use spvg_report::section::{Section, Verdict};
use spvg_report::separable;
use spvg_report::studies::floor::{self, FloorEffects, FloorOptions, SparseBox};
use spvg_report::studies::{gpu_readiness, pass_breakdown};
use spvg_report::subsurface::run::RunSpec;
use spvg_report::subsurface::{Report, ReportInputs, RunPlan, run_scenes, sweep_settings};
use spvg_report::timing;
use spvg_report::wgpu_api::{Backend, GpuDevice, Model, PassConfig, check_frame_size};

use cli::{
    AllArgs, Cli, Command, FloorArgs, FloorEffectArg, Global, GovernorArgs, MaterialArg,
    MotionArgs, SUBSURFACE_FRAMES, SUBSURFACE_SIZE, SceneArg, SectionArg, SubsurfaceArgs,
    flag_error,
};

/// `size` with `--width` / `--height` where given.
fn sized(g: &Global, size: [u32; 2]) -> [u32; 2] {
    [g.width.unwrap_or(size[0]), g.height.unwrap_or(size[1])]
}

/// The size override of the flags, for the sections that take one size.
fn size_flag(g: &Global, default: [u32; 2]) -> Option<[u32; 2]> {
    (g.width.is_some() || g.height.is_some()).then(|| sized(g, default))
}

/// The governor section's options under the command line (`a`: its subcommand's flags).
fn governor_options(g: &Global, a: Option<&GovernorArgs>) -> Result<GovernorOptions, ReportError> {
    let mut o = GovernorOptions::for_command(size_flag(g, [480, 270]), g.frames);
    if let Some(a) = a {
        o.device_effect = DeviceEffect::parse(a.effect.name(), &a.scene)?;
        o.device_target_ms = a.target_ms;
        o.classified = a.classified;
    }
    Ok(o)
}

/// The floor study's options under its flags.
fn floor_options(a: &FloorArgs) -> FloorOptions {
    FloorOptions {
        effects: match a.effect {
            FloorEffectArg::Ao => FloorEffects::Ao,
            FloorEffectArg::Sss => FloorEffects::Sss,
            FloorEffectArg::Both => FloorEffects::Both,
        },
        scene: a.scene.clone(),
        floors: a.floors.clone(),
        targets: a.targets.clone(),
        dilations: a.dilations.clone(),
        resolves: a.resolve.clone(),
        max_samples: a.max,
        sparse: if a.sparse_box == "sampled" {
            SparseBox::Sampled
        } else {
            SparseBox::History
        },
        quick: a.quick,
    }
}

/// The subsurface section's runs and settings under the command line.
fn subsurface_plan(
    g: &Global,
    s: &SubsurfaceArgs,
) -> Result<(RunPlan, Vec<(String, PassConfig)>), ReportError> {
    let material: MaterialPreset = match s.material {
        MaterialArg::Skin1 => SKIN1,
        MaterialArg::Marble => MARBLE,
    };
    let defaults = PassConfig::default();
    // Each value was checked alone when parsed (parse_sigma0_sq, parse_firefly_clamp);
    // should the controller refuse them together, that is an error naming both.
    let spvg = defaults
        .spvg
        .to_builder()
        .target_variance(s.sigma0_sq)
        .firefly_clamp(s.firefly_clamp)
        .build()
        .map_err(|e| flag_error("--sigma0-sq with --firefly-clamp", e))?;
    let base = PassConfig {
        spvg,
        afis: s.afis,
        ..defaults
    };
    let settings = sweep_settings(base, g.full && !s.no_sweep);
    let models = s.models(g.full);
    let mut specs = RunSpec::for_models(&models, &settings);
    // The equal-quality check is judged at the published target variance where it runs:
    // without the sweep, AS runs at it too (the sweep's label, so it is not a report run).
    let published = spvg::SpvgConfig::<f32>::published().target_variance();
    if models.contains(&Model::As)
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
                    .map_err(|e| flag_error("--firefly-clamp", e))?,
                ..base
            },
            label: format!("as s0^2={published:e}"),
            budget_spp: None,
            budget_gain: s.budget_gain,
            guided: false,
        });
    }
    // AS with the TAA-guided update: judged on flash and switch, on every scene under
    // `--full` (RunPlan::specs_for).
    if models.contains(&Model::As) {
        specs.push(RunSpec::guided(base));
        // AS with the resolved-image rule: judged on the static scene, on every scene
        // under `--full`.
        specs.push(RunSpec::resolved(base).map_err(|e| flag_error("--sigma0-sq", e))?);
    }
    if !s.no_budget {
        specs.push(RunSpec::budget(base, s.budget_spp, s.budget_gain));
    }
    let scenes = s
        .scenes(g.full)
        .iter()
        .map(|k| match k {
            SceneArg::Static => SceneKind::Static,
            SceneArg::Flash => SceneKind::Flash,
            SceneArg::Switch => SceneKind::Switch,
            SceneArg::Occluders => SceneKind::Occluders,
            SceneArg::Bunny => SceneKind::Mesh,
        })
        .collect();
    let [width, height] = sized(g, SUBSURFACE_SIZE);
    let frames = g.frames.unwrap_or(SUBSURFACE_FRAMES);
    let plan = RunPlan {
        scenes,
        specs,
        material,
        lighting: if s.gradient {
            Lighting::Gradient
        } else {
            Lighting::Constant
        },
        width,
        height,
        frames,
        image_frame: s.image_frame.unwrap_or(63.min(frames - 1)),
        reference: !s.no_reference,
        budget_everywhere: g.full,
        guide_everywhere: g.full,
    };
    Ok((plan, settings))
}

/// The subsurface suite this command holds, in one sentence for its markdown.
fn suite(g: &Global, s: &SubsurfaceArgs) -> String {
    if g.full {
        format!(
            "full (`--full`): every scene and model, the budget run and the TAA-guided AS on every scene, {}.",
            if s.no_sweep {
                "no sweep (`--no-sweep`)"
            } else {
                "the sweep of sigma0^2 and kappa (shown, not judged)"
            }
        )
    } else {
        "default: every acceptance check at the report setting (scenes static, flash, switch; fixed16, fixed64, AS, CCV, OCV; AS at the published sigma0^2 = 1e-4 for the equal-quality check; the budget run and AS with the TAA-guided update on flash and switch); `--full` adds the occluders scene, fixed8 and fixed32, the budget run and the TAA-guided AS on every scene, and the sweep of sigma0^2 and kappa (not judged).".into()
    }
}

/// The motion section's options under the command line.
fn motion_options(g: &Global, m: &MotionArgs) -> Result<MotionOptions, ReportError> {
    let mut opts = if g.full {
        MotionOptions::full()
    } else {
        MotionOptions::new()
    }?;
    opts.pan_size = sized(g, opts.pan_size);
    opts.size = sized(g, opts.size);
    opts.mesh_size = sized(g, opts.mesh_size);
    opts.only_mesh = m.only_mesh;
    opts.split = !m.no_split;
    if let Some(f) = g.frames {
        opts.frames = f;
    }
    opts.config = opts
        .config
        .to_builder()
        .target_variance(m.ao_sigma0_sq)
        .build()
        .map_err(|e| flag_error("--ao-sigma0-sq", e))?;
    Ok(opts)
}

/// Whether a `size` frame fits the backend (the device's limits; the CPU twin's frame
/// buffers are host memory), in words where it does not.
fn fits(r: &Resolved, size: [u32; 2]) -> Result<(), String> {
    match &r.backend {
        Backend::Gpu(d) => check_frame_size(&d.device, size[0], size[1]).map_err(|e| e.to_string()),
        Backend::Cpu => {
            let pixels = u64::from(size[0]) * u64::from(size[1]);
            if pixels > 1 << 25 {
                Err(format!(
                    "{pixels} pixels exceed the CPU twin's limit of {}",
                    1_u64 << 25
                ))
            } else {
                Ok(())
            }
        }
    }
}

/// Checks a frame size the command will run against the backend, before any resource
/// exists; the error names the size flags.
fn check_frame(r: &Resolved, size: [u32; 2]) -> Result<(), ReportError> {
    fits(r, size).map_err(|e| flag_error(&format!("--width {} --height {}", size[0], size[1]), e))
}

/// One section a command runs.
enum Job<'a> {
    Subsurface(&'a SubsurfaceArgs),
    Motion(&'a MotionArgs),
    Separable,
    Budget,
    Cost,
    Governor(Option<&'a GovernorArgs>),
    Floor(&'a FloorArgs),
    Readiness(u32),
    Breakdown,
}

/// The sections `all` runs with `a`, in report order (`full`: the timing studies too).
fn all_jobs(a: &AllArgs, full: bool) -> Vec<Job<'_>> {
    let no_ref = a.subsurface.no_reference;
    let keep = |s: SectionArg| !a.skip.contains(&s);
    let mut v = Vec::new();
    if keep(SectionArg::Subsurface) {
        v.push(Job::Subsurface(&a.subsurface));
    }
    if keep(SectionArg::Motion) && !no_ref {
        v.push(Job::Motion(&a.motion));
    }
    if keep(SectionArg::Separable) && !no_ref {
        v.push(Job::Separable);
    }
    if keep(SectionArg::Budget) && !no_ref {
        v.push(Job::Budget);
    }
    if keep(SectionArg::Cost) {
        v.push(Job::Cost);
    }
    if keep(SectionArg::Governor) {
        v.push(Job::Governor(None));
    }
    if full {
        v.push(Job::Readiness(gpu_readiness::DEFAULT_WARMUP));
        v.push(Job::Breakdown);
    }
    v
}

/// The sections of the command, in report order.
fn jobs(cli: &Cli) -> Vec<Job<'_>> {
    match &cli.command {
        None => all_jobs(&cli.all, cli.global.full),
        Some(Command::All(a)) => all_jobs(a, cli.global.full),
        Some(Command::Subsurface(s)) => vec![Job::Subsurface(s)],
        Some(Command::Motion(m)) => vec![Job::Motion(m)],
        Some(Command::Separable) => vec![Job::Separable],
        Some(Command::Budget) => vec![Job::Budget],
        Some(Command::Cost) => vec![Job::Cost],
        Some(Command::Governor(a)) => vec![Job::Governor(Some(a))],
        Some(Command::Floor(a)) => vec![Job::Floor(a)],
        Some(Command::GpuReadiness(r)) => vec![Job::Readiness(r.warmup)],
        Some(Command::PassBreakdown) => vec![Job::Breakdown],
    }
}

/// The command's sections run on `r`.
struct Run<'a> {
    cli: &'a Cli,
    r: &'a Resolved,
    progress: &'a Progress,
}

impl Run<'_> {
    fn out(&self) -> &Path {
        &self.cli.global.out
    }

    fn subsurface(&self, s: &SubsurfaceArgs) -> Result<(Section, String), ReportError> {
        let g = &self.cli.global;
        let (plan, settings) = subsurface_plan(g, s)?;
        check_frame(self.r, [plan.width, plan.height])?;
        let mut report = Report::new(ReportInputs {
            width: plan.width,
            height: plan.height,
            frames: plan.frames,
            material: plan.material.name,
            lighting: plan.lighting,
            afis: s.afis,
            sigma0_sq: s.sigma0_sq,
            reference: !s.no_reference,
            image_frame: plan.image_frame,
            backend: self.r.description.clone(),
            timing: timing::Timing::of(&self.r.backend),
            settings,
            budget_spp: (!s.no_budget).then_some(s.budget_spp),
            budget_gain: s.budget_gain,
            suite: suite(g, s),
        });
        let mut images = ImageWriter::new(self.out());
        run_scenes(
            &self.r.backend,
            &plan,
            &mut report,
            &mut images,
            self.progress,
        )?;
        let section = report.finish(self.out(), images.skipped)?;
        Ok((section, report.stdout_summary()))
    }

    fn section(&self, job: &Job<'_>) -> Result<(Section, String), ReportError> {
        let g = &self.cli.global;
        let dev = self.r.device();
        let progress = self.progress;
        let plain = |s: Section| (s, String::new());
        match job {
            Job::Subsurface(s) => self.subsurface(s),
            Job::Motion(m) => {
                let opts = motion_options(g, m)?;
                check_frame(self.r, opts.pan_size)?;
                check_frame(self.r, opts.size)?;
                check_frame(self.r, opts.mesh_size)?;
                // The pans' baseline renders the strip they cross, wider with every frame.
                let (strip, _) = motion::reference::strip_scene(&opts, opts.pan_size);
                fits(self.r, [strip.width, strip.height]).map_err(|e| {
                    flag_error(
                        "--frames",
                        format!(
                            "the pans' strip (their static camera held at their poses) is {}x{} at this many frames: {e}",
                            strip.width, strip.height
                        ),
                    )
                })?;
                motion::write(self.out(), dev, &opts, &self.r.description, progress).map(plain)
            }
            Job::Separable => {
                let opts = separable::options(dev, size_flag(g, [160, 120]), g.frames, g.full);
                check_frame(self.r, opts.size)?;
                separable::write(self.out(), dev, &opts, progress).map(plain)
            }
            Job::Budget => {
                let opts = BudgetOptions::for_command(size_flag(g, [96, 72]), g.frames, g.full);
                check_frame(self.r, opts.size)?;
                budget::write(self.out(), dev, &opts, progress).map(plain)
            }
            Job::Cost => {
                let opts = CostOptions::for_command(size_flag(g, [480, 270]), g.frames, g.full);
                if dev.is_none() && matches!(self.cli.command, Some(Command::Cost)) {
                    return Err(ReportError::Device(
                        "cost times the effects' passes on a wgpu device: the CPU twin has none (--backend cpu, or no adapter)".into(),
                    ));
                }
                for run in &opts.runs {
                    check_frame(self.r, run.size)?;
                }
                cost::write(self.out(), &self.r.backend, &opts, progress).map(plain)
            }
            Job::Governor(a) => {
                let opts = governor_options(g, *a)?;
                if dev.is_some() {
                    check_frame(self.r, opts.device_size)?;
                }
                governor::write(self.out(), dev, &opts, progress).map(plain)
            }
            Job::Floor(a) => floor::write(self.out(), &floor_options(a), progress).map(plain),
            Job::Readiness(warmup) => {
                let opts = gpu_readiness::ReadinessOptions::for_command(
                    size_flag(g, [1920, 1080]),
                    g.frames,
                    *warmup,
                );
                if dev.is_none() && matches!(self.cli.command, Some(Command::GpuReadiness(_))) {
                    return Err(ReportError::Device(
                        "gpu-readiness times the component's passes on a wgpu device: the CPU twin has none (--backend cpu, or no adapter)".into(),
                    ));
                }
                gpu_readiness::write(self.out(), dev, &opts, progress).map(plain)
            }
            Job::Breakdown => {
                let (size, frames) = pass_breakdown::DEFAULT;
                let size = sized(g, size);
                let frames = g.frames.unwrap_or(frames);
                if dev.is_none() && matches!(self.cli.command, Some(Command::PassBreakdown)) {
                    return Err(ReportError::Device(
                        "pass-breakdown times the subsurface pass's steps on a wgpu device: the CPU twin has none (--backend cpu, or no adapter)".into(),
                    ));
                }
                pass_breakdown::write(self.out(), dev, size, frames, progress).map(plain)
            }
        }
    }
}

/// Frames `job` renders on `dev` (for the progress bar).
fn frames_of(g: &Global, job: &Job<'_>, dev: Option<&GpuDevice>) -> Result<u64, ReportError> {
    Ok(match job {
        Job::Subsurface(s) => subsurface_plan(g, s)?.0.frames_to_render(),
        Job::Motion(m) => motion::frames_to_render(&motion_options(g, m)?),
        Job::Separable => u64::from(separable::focus_frames(&separable::options(
            dev,
            size_flag(g, [160, 120]),
            g.frames,
            g.full,
        ))),
        Job::Budget => {
            let o = BudgetOptions::for_command(size_flag(g, [96, 72]), g.frames, g.full);
            o.runs() * u64::from(o.frames)
        }
        Job::Cost => {
            CostOptions::for_command(size_flag(g, [480, 270]), g.frames, g.full).frames_to_render()
        }
        Job::Governor(a) => {
            let o = governor_options(g, *a)?;
            o.twin_frames()
                + if dev.is_some() {
                    u64::from(o.frames)
                } else {
                    0
                }
        }
        // The study's stages are its progress (its runs take different times).
        Job::Floor(_) => 0,
        Job::Readiness(w) if dev.is_some() => {
            gpu_readiness::ReadinessOptions::for_command(size_flag(g, [1920, 1080]), g.frames, *w)
                .frames_to_render()
        }
        Job::Breakdown if dev.is_some() => {
            2 * u64::from(g.frames.unwrap_or(pass_breakdown::DEFAULT.1))
        }
        Job::Readiness(_) | Job::Breakdown => 0,
    })
}

/// `report.md`: the verdict, the command, then each section.
fn report_md(
    cli: &Cli,
    r: &Resolved,
    verdict: &Verdict,
    sections: &[Section],
    wall_s: f64,
) -> String {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut md = format!("# spvg report\n\n{}\n\n## This command\n\n", verdict.line);
    let _ = writeln!(
        md,
        "- `spvg-report{}{}`: the sections {}; the {} suite (`--full` runs and judges every line).",
        if args.is_empty() { "" } else { " " },
        args.join(" "),
        sections
            .iter()
            .map(|s| format!("`{}`", s.name))
            .collect::<Vec<_>>()
            .join(", "),
        if cli.global.full { "full" } else { "default" }
    );
    let _ = writeln!(md, "- Backend: {}.", r.description);
    let _ = writeln!(md, "- Wall time {wall_s:.1} s.\n");
    for s in sections {
        md.push_str(&s.markdown);
        md.push('\n');
    }
    md
}

fn run(cli: &Cli) -> Result<Verdict, ReportError> {
    let started = Instant::now();
    let jobs = jobs(cli);
    let subsurface = jobs.iter().find_map(|j| match j {
        Job::Subsurface(s) => Some(*s),
        _ => None,
    });
    cli::validate(cli, subsurface)?;
    let r = backend::resolve(cli.global.backend.into())?;
    eprintln!("spvg-report: backend {}", r.description);
    let frames = jobs
        .iter()
        .map(|j| frames_of(&cli.global, j, r.device()))
        .sum::<Result<u64, ReportError>>()?;
    let progress = Progress::new("spvg-report", frames);
    let run = Run {
        cli,
        r: &r,
        progress: &progress,
    };
    let mut sections = Vec::new();
    let mut summaries = String::new();
    for job in &jobs {
        let (section, summary) = run.section(job)?;
        summaries.push_str(&summary);
        sections.push(section);
    }
    progress.finish();
    let verdict = Verdict::of(&sections);
    let md = report_md(
        cli,
        &r,
        &verdict,
        &sections,
        started.elapsed().as_secs_f64(),
    );
    let path = cli.global.out.join("report.md");
    std::fs::write(&path, md).map_err(|e| ReportError::io(&path, e))?;
    print!("{summaries}");
    for s in &sections {
        let judged: Vec<_> = s.judged().collect();
        if !judged.is_empty() {
            let failed = judged.iter().filter(|c| !c.pass).count();
            println!(
                "{} section: {} of {} lines hold",
                s.name,
                judged.len() - failed,
                judged.len()
            );
            for c in judged.iter().filter(|c| !c.pass) {
                println!("{}", c.line());
            }
        }
    }
    println!("{}", verdict.line);
    println!("wrote {}", path.display());
    Ok(verdict)
}

fn main() -> ExitCode {
    // clap exits with status 2 on a usage error, the status of a failed line here: a bad
    // flag exits with 1, as every other error does (help and version still exit with 0).
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    match run(&cli) {
        Ok(v) if v.judged == 0 || v.passed() => ExitCode::SUCCESS,
        Ok(_) => ExitCode::from(2),
        Err(e) => {
            eprintln!("spvg-report: error: {e}");
            ExitCode::FAILURE
        }
    }
}
