//! The budget table (the shape of the dissertation's Table 7.2): on the static scene, at
//! sample budgets 64, 128 and 512, a fixed count against the adaptive count (AS with
//! `beta_max` = the budget): time, PSNR, `err1` (RMSE over the pixels the adaptive run
//! leaves at `n = beta_min`: already at the target), `err2` (over the pixels that need more)
//! and the sample ratio `SRatio` = adaptive samples / fixed samples (docs/algorithms.md §7).
//!
//! The adaptive run's target variance is chosen per budget: each budget sweeps
//! [`SWEEP`] and takes, by [`pick`], the smallest target whose mean count stays within
//! [`SAMPLE_SHARE`] of the fixed run's; the published `sigma0^2 = 1e-4` is the sweep's first
//! point and stays in the table as the reference row. The rule reads only the runs' sample
//! counts, never the reference image. Each budget runs the sweep with the published
//! `beta_min = 8` and, where it differs, with the whole interval scaled with the budget,
//! `[B / 8, B]` ([`beta_mins`]), the published `[8, 64]`'s ratio; the acceptance judges the
//! second (docs/algorithms.md §7 says why the floor matters).

//! The allocation exponent's line ([`exponent`]) runs the core's controller and governor
//! on the AO static camera's image at a 12-spp frame budget; the second moment's line
//! ([`moment`]) runs the controller on that camera under sub-pixel jitter.

//! Files: the runs ([`run`]), the acceptance line ([`acceptance`]), the markdown
//! ([`mod@markdown`]); this file writes the section.

pub mod acceptance;
pub mod exponent;
pub mod markdown;
pub mod moment;
pub mod run;

use std::path::Path;

use crate::error::ReportError;
use crate::progress::Progress;
use crate::section::{Group, Section};
use crate::wgpu_api::GpuDevice;

pub use acceptance::{checks, judged_row, picked_row, row_ratio, sample_ratio};
pub use run::{
    BUDGETS, BudgetOptions, BudgetRow, INTERVAL_RATIO, Measured, PUBLISHED_TARGET, SAMPLE_SHARE,
    SWEEP, Scores, beta_mins, pick, run_budgets, run_budgets_with, run_model, scene_and_reference,
    score,
};

/// Runs the table on `device` (the CPU twin without one), writes `budget.md` into `dir`
/// and returns the section.
///
/// # Errors
///
/// A pass error, a refused configuration, or a file that cannot be written (naming it).
pub fn write(
    dir: &Path,
    device: Option<&GpuDevice>,
    opts: &BudgetOptions,
    progress: &Progress,
) -> Result<Section, ReportError> {
    progress.stage("budget: the sample-budget table");
    let rows = run_budgets(device, opts)?;
    progress.inc(opts.runs() * u64::from(opts.frames));
    let cpu_time = device.is_none_or(GpuDevice::is_software);
    progress.stage("budget: the allocation exponent (core crate, AO static's image)");
    let q = exponent::static_ao(exponent::SIZE, exponent::GRID);
    let (runs, fixed) = exponent::run_all(&q)?;
    let mut lines = checks(&rows);
    lines.push(exponent::check(&q, &runs, &fixed));
    progress.stage("budget: irreducible variance (core crate, AO static under jitter)");
    lines.push(moment::check(&moment::jittered_ao(
        moment::SIZE,
        moment::GRID,
    ))?);
    let groups = vec![Group::judged("Acceptance (budget)", lines)];
    let mut md = markdown::markdown(&rows, opts, cpu_time);
    for g in &groups {
        md.push_str(&g.markdown());
    }
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let path = dir.join("budget.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    Ok(Section {
        name: "budget",
        markdown: md,
        groups,
    })
}
