//! The separable section: the separable profile's fit to each preset ([`fit`]) and the
//! focus-region scene run separable-only, AS, CCV and hybrid ([`focus`]) with the work
//! each dispatches ([`work`]), its acceptance lines ([`acceptance`]) and markdown
//! ([`mod@markdown`]); written to `separable.md`.

pub mod acceptance;
pub mod fit;
pub mod focus;
pub mod markdown;
pub mod work;

use std::path::Path;

use crate::error::ReportError;
use crate::progress::Progress;
use crate::section::{Group, Section};
use crate::wgpu_api::GpuDevice;

pub use focus::{
    FocusOptions, FocusResult, FocusRun, FocusTiming, FocusWork, hybrid_time_bound, run_focus,
};

/// The focus scene's options for a command: the defaults, `size` and `frames` where given,
/// and the timing rows where they are judged (a hardware adapter with timestamps) or the
/// whole suite runs (`full`).
#[must_use]
pub fn options(
    device: Option<&GpuDevice>,
    size: Option<[u32; 2]>,
    frames: Option<u32>,
    full: bool,
) -> FocusOptions {
    let mut o = FocusOptions::default();
    if let Some(s) = size {
        o.size = s;
    }
    if let Some(f) = frames {
        o.frames = f;
    }
    if !(full || focus::judges_time(device)) {
        o.timing = None;
    }
    o
}

/// Runs the section on `device` (the CPU twins without one), writes `separable.md` into
/// `dir`, and returns the section.
///
/// # Errors
///
/// A pass error, a configuration the passes refuse, or a file that cannot be written
/// (naming it).
pub fn write(
    dir: &Path,
    device: Option<&GpuDevice>,
    opts: &FocusOptions,
    progress: &Progress,
) -> Result<Section, ReportError> {
    progress.stage("separable: the Burley fit per preset");
    let fits = fit::fit_rows()?;
    progress.stage("separable: the focus scene");
    let result = run_focus(device, opts)?;
    progress.inc(u64::from(focus_frames(opts)));
    let groups = vec![Group::judged(
        "Acceptance (separable)",
        acceptance::checks(&result),
    )];
    let mut md = markdown::markdown(&fits, &result, opts);
    md.push('\n');
    for g in &groups {
        md.push_str(&g.markdown());
    }
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let path = dir.join("separable.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    Ok(Section {
        name: "separable",
        markdown: md,
        groups,
    })
}

/// Frames the section renders (for a progress bar): the four runs, and the timing rows'
/// four per frame.
#[must_use]
pub fn focus_frames(opts: &FocusOptions) -> u32 {
    4 * opts.frames
        + opts
            .timing
            .map_or(0, |(_, frames)| 4 * (frames + focus::TIMING_WARMUP))
}
