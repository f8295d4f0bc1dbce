//! The separable section of the report: the Burley fit per preset, the focus-region scene
//! (separable-only, AS, CCV, hybrid), the sample-budget table and, in the full suite, the
//! per-pass times at 1920x1080 and the GPU-readiness table (the component's steps against
//! a copy kernel at 1080p and 2160p); written to `separable.md` with its acceptance lines.

use std::path::Path;

use crate::acceptance::Check;
use crate::budget_table::{self, BudgetOptions, run_budgets};
use crate::error::ReportError;
use crate::gpu_readiness::{self, ReadinessOptions};
use crate::pass_breakdown::{self, run_breakdown};
use crate::progress::Progress;
use crate::separable::{FocusOptions, checks, fit_rows, markdown, run_focus};
use crate::wgpu_api::GpuDevice;

/// Acceptance lines by group name.
pub type CheckGroups = Vec<(String, Vec<Check>)>;

/// What the section runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionOptions {
    /// The focus scene.
    pub focus: FocusOptions,
    /// The budget table.
    pub budgets: BudgetOptions,
    /// Whether the per-pass table at 1920x1080 and the GPU-readiness table run (fixed 64
    /// there costs tens of seconds a frame on a software adapter, so only the full suite
    /// runs them).
    pub per_pass: bool,
}

impl SectionOptions {
    /// The default suite (`full` false: the budget table at 96x72 and 16 frames, no
    /// per-pass table) or the full one (160x120, the per-pass table).
    #[must_use]
    pub fn new(full: bool) -> Self {
        let mut budgets = BudgetOptions::default();
        if full {
            budgets.size = [160, 120];
        }
        Self {
            focus: FocusOptions::default(),
            budgets,
            per_pass: full,
        }
    }
}

/// The per-pass table's frame size and frames.
const PER_PASS: ([u32; 2], u32) = ([1920, 1080], 3);

/// Measured frames of the GPU-readiness table in the full suite (its command defaults to
/// more).
const READINESS_FRAMES: u32 = 5;

/// Runs the section on `device` (the CPU twins without one), writes `separable.md` into
/// `dir`, and returns the markdown with the acceptance lines by group (`separable`: the
/// focus scene's; `budget`: the table's).
///
/// # Errors
///
/// A pass error, a configuration the passes refuse, or a file that cannot be written
/// (naming it).
pub fn write(
    dir: &Path,
    device: Option<&GpuDevice>,
    opts: &SectionOptions,
    progress: &Progress,
) -> Result<(String, CheckGroups), ReportError> {
    progress.stage("separable: the Burley fit per preset");
    let fits = fit_rows()?;
    progress.stage("separable: the focus scene");
    let result = run_focus(device, &opts.focus)?;
    progress.stage("separable: the sample-budget table");
    let rows = run_budgets(device, &opts.budgets)?;
    let mut md = markdown(&fits, &result, &opts.focus);
    md.push('\n');
    md.push_str(&budget_table::markdown(
        &rows,
        &opts.budgets,
        result.cpu_time,
    ));
    md.push('\n');
    let (size, frames) = PER_PASS;
    if opts.per_pass {
        progress.stage("separable: per-pass times at 1920x1080");
        let breakdown = run_breakdown(device, size, frames)?;
        md.push_str(&pass_breakdown::markdown(
            breakdown.as_deref(),
            size,
            frames,
            result.cpu_time,
        ));
        md.push('\n');
        if let Some(d) = device {
            progress.stage("separable: GPU readiness at 1920x1080 and 3840x2160");
            let opts = ReadinessOptions {
                frames: READINESS_FRAMES,
                ..ReadinessOptions::default()
            };
            md.push_str(&gpu_readiness::markdown(&gpu_readiness::run(d, &opts)?));
        } else {
            md.push_str(gpu_readiness::HEADING);
            md.push_str("Not run: no wgpu device (the CPU twin has no passes to time).\n");
        }
    } else {
        md.push_str(
            "## Per-pass time (Table 7.1's shape)\n\nNot run in the default suite (1920x1080 \
             frames at fixed 64 cost tens of seconds each on a software adapter): `--full` \
             runs it.\n\n",
        );
        md.push_str(gpu_readiness::HEADING);
        md.push_str(
            "Not run in the default suite (2160p frames on a software adapter): `--full` \
             runs it, and so does `cargo run --release -p spvg-report --bin \
             spvg-gpu-readiness`.\n",
        );
    }
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let path = dir.join("separable.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    Ok((
        md,
        vec![
            ("separable".into(), checks(&result)),
            ("budget".into(), budget_table::checks(&rows)),
        ],
    ))
}
