//! The command line of `spvg-report`: the global flags (parsed once, the same meaning in
//! every subcommand), the subcommands and their flags, their parsers and the checks that
//! need several flags or the file system, all before a device is requested.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use spvg_report::backend::Choice;
use spvg_report::error::ReportError;
use spvg_report::studies::gpu_readiness;
use spvg_report::wgpu_api::{Model, PassConfig};

/// Largest fixed sample count (the core's budget limit).
const MAX_FIXED: u32 = 1024;

/// Largest frame side the command line accepts; the adapter's own limit is checked once
/// the device exists (lavapipe: 16384).
const MAX_SIDE: u32 = 32768;

/// Speed and accuracy report of the spvg passes.
///
/// Runs the report's sections on the best backend found (a GPU adapter, else Mesa's
/// software Vulkan; the CPU twin only with --backend cpu or when no adapter exists), holds
/// every frame against converged quadrature references, and writes report.md (the verdict
/// first, then each section), each section's own markdown and CSV files, SVG charts and
/// PNG frame images into --out. Without a subcommand it runs `all`.
///
/// The default suite judges a line for every capability in about six minutes of CPU time
/// (a few minutes of wall time on an idle 2-core machine with software Vulkan, whose
/// rasterizer threads use both cores); --full runs and judges every line.
#[derive(Debug, Parser)]
#[command(
    name = "spvg-report",
    version,
    about,
    long_about,
    args_conflicts_with_subcommands = true,
    after_help = "Exit status: 0 when every judged line holds (or nothing was judged), 2 when a line fails, 1 on an error (a bad flag, a device that fails, a file that cannot be written)."
)]
pub(crate) struct Cli {
    #[command(flatten)]
    pub(crate) global: Global,

    #[command(subcommand)]
    pub(crate) command: Option<Command>,

    /// `all`'s flags, when no subcommand is named.
    #[command(flatten)]
    pub(crate) all: AllArgs,
}

/// The flags every subcommand takes, with one meaning everywhere.
#[derive(Debug, Args)]
pub(crate) struct Global {
    /// Which implementation runs the passes: `auto` takes a GPU adapter (software Vulkan
    /// counts) and the CPU twin only when no adapter exists; a device that exists but
    /// fails is an error.
    #[arg(long, value_enum, default_value_t = BackendArg::Auto, global = true)]
    pub(crate) backend: BackendArg,

    /// Output folder (created if missing).
    #[arg(long, value_name = "DIR", default_value = "out", global = true)]
    pub(crate) out: PathBuf,

    /// Frame width in pixels [1, 32768] of every run of the command (default: each
    /// section's own: subsurface 128, motion 384 for the pans and 128 for the rest,
    /// separable 160, budget 96, gpu-readiness 1920 and 3840, pass-breakdown 1920); the
    /// adapter's limits also apply.
    #[arg(long, value_name = "PX", allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)), global = true)]
    pub(crate) width: Option<u32>,

    /// Frame height in pixels [1, 32768] of every run of the command (default: each
    /// section's own: subsurface 96, motion 192 for the pans and 96 for the rest, separable
    /// 120, budget 72, gpu-readiness 1080 and 2160, pass-breakdown 1080).
    #[arg(long, value_name = "PX", allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)), global = true)]
    pub(crate) height: Option<u32>,

    /// Frames per run [2, 100000] of every section (default: each section's own:
    /// subsurface 96, motion 48, separable 16, budget 16, gpu-readiness 20 measured,
    /// pass-breakdown 3); frame 0 (shader compilation) is left out of the timings.
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(2..=100_000), global = true)]
    pub(crate) frames: Option<u32>,

    /// The whole suite, every line judged: in `subsurface` the occluders scene, fixed8 and
    /// fixed32, the budget run and the TAA-guided AS on every scene, the sweep of the
    /// target variance and kappa (shown, not judged); in `motion` every pan, the
    /// young-history and knob rows, the TAA-guided update and every frame scored; in
    /// `separable` the timing rows at 640x480; the budget table at 160x120; and `all` adds
    /// the timing studies (`gpu-readiness`, `pass-breakdown`).
    #[arg(long, global = true)]
    pub(crate) full: bool,
}

/// The subcommands: the report's sections, and the timing studies.
#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Every section (the default): subsurface, motion, separable, budget, cost, governor; with --full
    /// also gpu-readiness and pass-breakdown.
    All(AllArgs),
    /// The subsurface pass on the dynamic-lighting scenes: every model, the frame budget,
    /// the TAA guide, the core's damped policy and firefly clamp.
    Subsurface(SubsurfaceArgs),
    /// The adaptive component with motion-vector reprojection on the ambient-occlusion
    /// consumer: pans, a rotation, moving objects, a dolly; every GPU frame held against
    /// the CPU twin.
    Motion(MotionArgs),
    /// The separable profile's fit per preset and the focus-region scene run
    /// separable-only, AS, CCV and hybrid.
    Separable,
    /// The sample-budget table: fixed against adaptive counts at budgets 64, 128 and 512; the allocation exponent at a 12-spp frame budget (core crate).
    Budget,
    /// The component's cost: AS's frame time against the fixed-count line at its own
    /// mean count, in each form of the component (one pass, two passes, classified), on
    /// the static subsurface and AO scenes, interleaved frame by frame (needs a wgpu
    /// device; judged at 480x270, and with --full also shown at 1920x1080).
    Cost,
    /// The frame-time governor (spvg::frame_time) steering the subsurface pass to a time
    /// in ms: its band judged on the CPU twin's deterministic cost model (lavapipe's
    /// recorded noise replayed) and its reach on unreachable targets; the same loop on the
    /// device's clock shown (its effect, scene, target and dispatch set by the flags).
    Governor(GovernorArgs),
    /// Study (judges nothing): fractional floors and the resolved-image rule swept after a
    /// TAA resolve against fixed counts and AS [8, 64], on the subsurface static scene and
    /// on ambient occlusion (static, pan4, object3), on the CPU twins (a few minutes: AO
    /// takes most of them).
    Floor(FloorArgs),
    /// Timing study (judges nothing): the component's estimate and update against a copy
    /// kernel moving the same bytes, at 1920x1080 and 3840x2160 (needs a wgpu device;
    /// GPU timestamps where the adapter has them, else wall time, which is CPU time on a
    /// software adapter).
    GpuReadiness(ReadinessArgs),
    /// Timing study (judges nothing): the subsurface pass's estimate, sampling and update
    /// timed apart at 1920x1080 (needs a wgpu device).
    PassBreakdown,
}

/// `all`'s flags: the subsurface and motion sections' and which sections to skip.
#[derive(Debug, Default, Args)]
pub(crate) struct AllArgs {
    #[command(flatten)]
    pub(crate) subsurface: SubsurfaceArgs,

    #[command(flatten)]
    pub(crate) motion: MotionArgs,

    /// Sections to leave out, comma-separated: subsurface, motion, separable, budget, cost,
    /// governor
    /// (--no-reference leaves out motion, separable and budget, which need references).
    #[arg(long, value_enum, value_delimiter = ',', value_name = "LIST")]
    pub(crate) skip: Vec<SectionArg>,
}

/// The sections `all` runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum SectionArg {
    /// The subsurface section.
    Subsurface,
    /// The motion section.
    Motion,
    /// The separable section.
    Separable,
    /// The budget table.
    Budget,
    /// The component's cost.
    Cost,
    /// The frame-time governor.
    Governor,
}

/// The subsurface section's flags.
#[derive(Debug, Args)]
pub(crate) struct SubsurfaceArgs {
    /// Subsurface material preset.
    #[arg(long, value_enum, default_value_t = MaterialArg::Skin1)]
    pub(crate) material: MaterialArg,

    /// Frame whose images are written [0, frames - 1] (default: 63, or the last frame of
    /// shorter runs).
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub(crate) image_frame: Option<u32>,

    /// Target variance sigma0^2 of the subsurface pass's adaptive models: finite, > 0 (the
    /// library default is the published 1e-4; the report's 5e-7 is explained in
    /// ARCHITECTURE.md).
    #[arg(long, value_name = "X", default_value = "5e-7", allow_negative_numbers = true, value_parser = parse_sigma0_sq)]
    pub(crate) sigma0_sq: f32,

    /// Scenes to run, comma-separated [default: static,flash,switch (the scenes the
    /// acceptance checks judge),bunny (the scanned mesh); with --full:
    /// static,flash,switch,occluders,bunny].
    #[arg(long, value_enum, value_delimiter = ',', value_name = "LIST")]
    pub(crate) scenes: Option<Vec<SceneArg>>,

    /// Models to run, comma-separated: fixedN (N in [1, 1024]), as, ccv, ocv [default:
    /// fixed16,fixed64,as,ccv,ocv (the models the acceptance checks judge); with --full:
    /// fixed8,fixed16,fixed32,fixed64,as,ccv,ocv].
    #[arg(long, value_delimiter = ',', value_name = "LIST", value_parser = parse_model)]
    pub(crate) models: Option<Vec<Model>>,

    /// Skip the sweep of the target variance and kappa (which only --full runs).
    #[arg(long)]
    pub(crate) no_sweep: bool,

    /// Frame budget of the `budget` run (CCV under the frame budget governor, one per
    /// scene), in samples per subsurface pixel: [beta_min, beta_max] = [8, 64], the
    /// totals the controller can reach.
    #[arg(long, value_name = "SPP", default_value_t = 16.0, allow_negative_numbers = true, value_parser = parse_budget_spp)]
    pub(crate) budget_spp: f64,

    /// Integral gain of the budget governor in (0, 1] (spvg::budget; 0.25 is critically
    /// damped with two frames of feedback latency; the report reads back synchronously,
    /// one frame).
    #[arg(long, value_name = "G", default_value_t = 0.25, allow_negative_numbers = true, value_parser = parse_budget_gain)]
    pub(crate) budget_gain: f64,

    /// Skip the `budget` run.
    #[arg(long)]
    pub(crate) no_budget: bool,

    /// Timing only: no quadrature reference, no PSNR, no acceptance checks, no charts (for
    /// large frames, where the reference would dominate the run time).
    #[arg(long)]
    pub(crate) no_reference: bool,

    /// Lights with a smooth spatial variation instead of constant lighting.
    #[arg(long)]
    pub(crate) gradient: bool,

    /// Read the lighting through its mip chain (filtered sampling, AFIS); references stay
    /// unfiltered.
    #[arg(long)]
    pub(crate) afis: bool,

    /// The firefly clamp's k for the adaptive runs (SpvgConfig::firefly_clamp,
    /// docs/algorithms.md §8.3): each frame's monitored value is clamped to mean +- k
    /// sigma of its history; off by default. The *Firefly clamp* table measures it on the
    /// core whatever this says.
    #[arg(long, value_name = "K", allow_negative_numbers = true, value_parser = parse_firefly_clamp)]
    pub(crate) firefly_clamp: Option<f32>,
}

impl Default for SubsurfaceArgs {
    fn default() -> Self {
        Self {
            material: MaterialArg::Skin1,
            image_frame: None,
            sigma0_sq: 5e-7,
            scenes: None,
            models: None,
            no_sweep: false,
            budget_spp: 16.0,
            budget_gain: 0.25,
            no_budget: false,
            no_reference: false,
            gradient: false,
            afis: false,
            firefly_clamp: None,
        }
    }
}

/// The motion section's flags.
#[derive(Debug, Args)]
pub(crate) struct MotionArgs {
    /// Target variance sigma0^2 of the ambient-occlusion consumer's adaptive runs: finite,
    /// > 0 (the library's published default 1e-4).
    #[arg(long, value_name = "X", default_value = "1e-4", allow_negative_numbers = true, value_parser = parse_sigma0_sq)]
    pub(crate) ao_sigma0_sq: f32,

    /// Run the mesh scene (the scanned bunny under an orbiting, jittered camera) alone.
    #[arg(long)]
    pub(crate) only_mesh: bool,
}

impl Default for MotionArgs {
    fn default() -> Self {
        Self {
            ao_sigma0_sq: 1e-4,
            only_mesh: false,
        }
    }
}

/// `floor`'s flags (lists are comma-separated; each effect has its own defaults).
#[derive(Debug, Args)]
pub(crate) struct FloorArgs {
    /// The effects to sweep.
    #[arg(long, value_enum, default_value_t = FloorEffectArg::Both)]
    pub(crate) effect: FloorEffectArg,

    /// AO: one scene (static, pan4, object3) instead of all three.
    #[arg(long, value_name = "NAME", value_parser = ["static", "pan4", "object3"])]
    pub(crate) scene: Option<String>,

    /// The fractional floors in [0, 8] [default: ao 0.25; sss 0.25,0.125,0].
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        allow_negative_numbers = true
    )]
    pub(crate) floors: Option<Vec<f32>>,

    /// The targets sigma0^2 of the floors' sweep [default: ao ten from 3.2e-2 to 6.25e-5;
    /// sss nine from 1e-3 to 1.6e-8].
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        allow_negative_numbers = true
    )]
    pub(crate) targets: Option<Vec<f32>>,

    /// AO: the count dilation radii.
    #[arg(long, value_delimiter = ',', value_name = "LIST", default_value = "1")]
    pub(crate) dilations: Vec<u32>,

    /// The resolved-image rule's steady weights in (0, 1], 0 for the per-frame target.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        default_value = "0,0.1",
        allow_negative_numbers = true
    )]
    pub(crate) resolve: Vec<f32>,

    /// AO: beta_max of the fractional runs.
    #[arg(long, value_name = "N", default_value_t = 64)]
    pub(crate) max: u32,

    /// AO: the clamp box of a skipped neighbour: its reprojected history (the default), or
    /// nothing (`sampled`: the box spans the neighbours that sampled).
    #[arg(long, value_name = "BOX", value_parser = ["history", "sampled"], default_value = "history")]
    pub(crate) sparse_box: String,

    /// AO: three targets instead of ten.
    #[arg(long)]
    pub(crate) quick: bool,
}

/// `floor --effect`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum FloorEffectArg {
    /// Ambient occlusion.
    Ao,
    /// The subsurface effect.
    Sss,
    /// Both.
    Both,
}

/// `governor`'s flags: the device run's (the judged runs on the twin are fixed).
#[derive(Debug, Args)]
pub(crate) struct GovernorArgs {
    /// The effect of the device run: `sss` (the sampling step's time) or `ao` (the whole
    /// frame's).
    #[arg(long, value_enum, default_value_t = EffectArg::Sss)]
    pub(crate) effect: EffectArg,

    /// The device run's scene: static, flash or switch for sss; static or pan for ao.
    #[arg(long, value_name = "NAME", default_value = "flash")]
    pub(crate) scene: String,

    /// The device run's target time in ms: finite, > 0.
    #[arg(long, value_name = "MS", default_value_t = spvg_report::governor::TARGET_MS, allow_negative_numbers = true, value_parser = parse_target_ms)]
    pub(crate) target_ms: f64,

    /// The device run with the count-classified dispatch (ao).
    #[arg(long)]
    pub(crate) classified: bool,
}

/// `--effect`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum EffectArg {
    /// The subsurface pass.
    Sss,
    /// Ambient occlusion.
    Ao,
}

impl EffectArg {
    /// The flag's value as written.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Sss => "sss",
            Self::Ao => "ao",
        }
    }
}

/// `--target-ms`: a finite time above 0.
fn parse_target_ms(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|e| format!("{e}; expected a time in ms"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{v} is not a time: it must be finite and above 0"))
    }
}

/// `gpu-readiness`'s flags.
#[derive(Debug, Args)]
pub(crate) struct ReadinessArgs {
    /// Frames run before the measured ones [0, 1000] (shader compilation, first touch).
    #[arg(long, value_name = "N", default_value_t = gpu_readiness::DEFAULT_WARMUP, allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(0..=1_000))]
    pub(crate) warmup: u32,
}

/// `--backend`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum BackendArg {
    /// A GPU adapter (hardware first, then software Vulkan); the CPU twin only when no
    /// adapter exists.
    Auto,
    /// Any wgpu adapter; an error if there is none.
    Gpu,
    /// The multi-threaded CPU twin.
    Cpu,
}

impl From<BackendArg> for Choice {
    fn from(b: BackendArg) -> Self {
        match b {
            BackendArg::Auto => Self::Auto,
            BackendArg::Gpu => Self::Gpu,
            BackendArg::Cpu => Self::Cpu,
        }
    }
}

/// `--material`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub(crate) enum MaterialArg {
    /// Skin (Christensen & Burley's skin1).
    Skin1,
    /// Marble.
    Marble,
}

/// `--scenes`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum SceneArg {
    /// Constant lighting, a shadow edge and a depth step.
    Static,
    /// The key light flashes at 5 Hz.
    Flash,
    /// The key light switches off and on every 3 s, a small light flickers.
    Switch,
    /// A moving shadow and a moving occluder (disocclusion).
    Occluders,
    /// The scanned Stanford bunny under a shadowing key light.
    Bunny,
}

fn parse_sigma0_sq(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|e| format!("{e}; expected a number, finite and > 0"))?;
    let spvg = spvg::SpvgConfig::builder()
        .target_variance(v)
        .build()
        .map_err(|_| format!("{v} is out of range: must be finite and > 0"))?;
    PassConfig {
        spvg,
        ..PassConfig::default()
    }
    .validate()
    .map_err(|_| format!("{v} is out of range: must be finite and > 0"))?;
    Ok(v)
}

fn parse_firefly_clamp(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|e| format!("{e}; expected a number > 0"))?;
    spvg::SpvgConfig::<f32>::builder()
        .firefly_clamp(Some(v))
        .build()
        .map_err(|_| format!("{v} is out of range: must be > 0"))?;
    Ok(v)
}

fn parse_budget_spp(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|e| format!("{e}; expected a number of samples per pixel in [8, 64]"))?;
    let c = PassConfig::default();
    let (lo, hi) = (
        f64::from(c.spvg.min_samples()),
        f64::from(c.spvg.max_samples()),
    );
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
pub(crate) fn flag_error(flag: &str, why: impl std::fmt::Display) -> ReportError {
    ReportError::Usage(format!("{flag}: {why}"))
}

/// Checks what clap's per-flag parsers cannot (relations between flags, the output folder)
/// and creates the output folder: everything before a device is requested.
pub(crate) fn validate(cli: &Cli, subsurface: Option<&SubsurfaceArgs>) -> Result<(), ReportError> {
    if let Some(s) = subsurface {
        let frames = cli.global.frames.unwrap_or(SUBSURFACE_FRAMES);
        if let Some(n) = s.image_frame.filter(|n| *n >= frames) {
            return Err(flag_error(
                "--image-frame",
                format!(
                    "{n} is outside [0, {}] (the subsurface section's {frames} frames)",
                    frames - 1
                ),
            ));
        }
        if s.scenes.as_ref().is_some_and(Vec::is_empty) {
            return Err(flag_error("--scenes", "needs at least one scene"));
        }
        if s.models.as_ref().is_some_and(Vec::is_empty) {
            return Err(flag_error("--models", "needs at least one model"));
        }
    }
    let out = &cli.global.out;
    std::fs::create_dir_all(out)
        .map_err(|e| flag_error("--out", format!("cannot create {}: {e}", out.display())))?;
    let probe = out.join(".spvg-report-write-test");
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .map_err(|e| flag_error("--out", format!("cannot write into {}: {e}", out.display())))?;
    Ok(())
}

/// Frames per run of the subsurface section by default.
pub(crate) const SUBSURFACE_FRAMES: u32 = 96;

/// The subsurface section's frame size by default.
pub(crate) const SUBSURFACE_SIZE: [u32; 2] = [128, 96];

/// The scenes of the default suite: those the acceptance checks judge, and the scanned
/// bunny (content nobody here modelled; its lines are shown).
const DEFAULT_SCENES: [SceneArg; 4] = [
    SceneArg::Static,
    SceneArg::Flash,
    SceneArg::Switch,
    SceneArg::Bunny,
];

/// The scenes of the full suite.
const FULL_SCENES: [SceneArg; 5] = [
    SceneArg::Static,
    SceneArg::Flash,
    SceneArg::Switch,
    SceneArg::Occluders,
    SceneArg::Bunny,
];

/// The models of the default suite (those the acceptance checks judge: fixed16 against
/// the 16-spp budget run, fixed64 against AS on static, the adaptive models).
const DEFAULT_MODELS: [Model; 5] = [
    Model::Fixed(16),
    Model::Fixed(64),
    Model::As,
    Model::Ccv,
    Model::Ocv,
];

/// The models of the full suite.
const FULL_MODELS: [Model; 7] = [
    Model::Fixed(8),
    Model::Fixed(16),
    Model::Fixed(32),
    Model::Fixed(64),
    Model::As,
    Model::Ccv,
    Model::Ocv,
];

impl SubsurfaceArgs {
    /// The scenes to run: `--scenes`, else the suite's.
    pub(crate) fn scenes(&self, full: bool) -> Vec<SceneArg> {
        self.scenes.clone().unwrap_or_else(|| {
            if full {
                FULL_SCENES.to_vec()
            } else {
                DEFAULT_SCENES.to_vec()
            }
        })
    }

    /// The models to run: `--models`, else the suite's.
    pub(crate) fn models(&self, full: bool) -> Vec<Model> {
        self.models.clone().unwrap_or_else(|| {
            if full {
                FULL_MODELS.to_vec()
            } else {
                DEFAULT_MODELS.to_vec()
            }
        })
    }
}
