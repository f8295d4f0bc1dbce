//! The per-pass time table (the shape of the dissertation's Table 7.1): the estimate, the
//! sampling and the update of the subsurface pass timed apart, for the fixed count 64 and
//! the adaptive count (AS), on the static scene at 1920x1080. Each step is submitted and
//! waited for on its own ([`SssPass::run_frame_per_pass`]): wall time, so on a software
//! adapter these are CPU time.

use std::fmt::Write as _;
use std::path::Path;

use spvg::burley::presets;

use crate::error::ReportError;
use crate::progress::Progress;
use crate::scene::{Scene, SceneKind};
use crate::section::Section;
use crate::wgpu_api::{GpuDevice, Model, PassConfig, PassTimes, SssPass, check_frame_size};

/// The table's frame size and frames by default.
pub const DEFAULT: ([u32; 2], u32) = ([1920, 1080], 3);

/// One model's mean step times over the measured frames.
#[derive(Clone, Debug, PartialEq)]
pub struct Breakdown {
    /// The model's name (`fixed64`, `as`).
    pub model: String,
    /// Mean times per step (ms).
    pub times: PassTimes,
    /// Mean samples per pixel.
    pub spp: f64,
}

/// Runs the breakdown at `size` for `frames` frames (the first, which compiles the
/// shaders, not measured). `None` without a device: the twin has no passes to time.
///
/// # Errors
///
/// A pass error.
pub fn run_breakdown(
    device: Option<&GpuDevice>,
    size: [u32; 2],
    frames: u32,
) -> Result<Option<Vec<Breakdown>>, ReportError> {
    let Some(d) = device else {
        return Ok(None);
    };
    let [w, h] = size;
    let scene = Scene::new(SceneKind::Static, w, h);
    let cfg = PassConfig::default();
    let mut out = Vec::new();
    for model in [Model::Fixed(64), Model::As] {
        let mut pass = SssPass::new(&d.device, &d.queue, w, h, model, false);
        let mut sum = PassTimes::default();
        let mut spp = 0.0;
        let measured = f64::from(frames.saturating_sub(1).max(1));
        for t in 0..frames {
            let inputs = scene.inputs(t);
            let p = pass.frame_params(&cfg, &presets::SKIN1, t)?;
            let (o, times) = pass.run_frame_per_pass(&p, &inputs)?;
            if t == 0 {
                continue;
            }
            sum.estimate_ms += times.estimate_ms / measured;
            sum.sampling_ms += times.sampling_ms / measured;
            sum.update_ms += times.update_ms / measured;
            spp += crate::metrics::mean_spp(&o.count, &inputs.mask) / measured;
        }
        out.push(Breakdown {
            model: model.name(),
            times: sum,
            spp,
        });
    }
    Ok(Some(out))
}

/// The table's markdown.
#[must_use]
pub fn markdown(rows: Option<&[Breakdown]>, size: [u32; 2], frames: u32, cpu_time: bool) -> String {
    let mut s = String::new();
    let [w, h] = size;
    let _ = writeln!(s, "## Per-pass time (Table 7.1's shape)\n");
    let Some(rows) = rows else {
        let _ = writeln!(
            s,
            "Not run: no wgpu device (the CPU twin has no passes to time)."
        );
        return s;
    };
    let _ = writeln!(
        s,
        "The static scene at {w}x{h}, skin1, {frames} frames (the first not measured); each \
         step submitted and waited for on its own, wall time{}.\n",
        if cpu_time {
            " (a software adapter: CPU time)"
        } else {
            ""
        }
    );
    let _ = writeln!(
        s,
        "| model | spp | estimate (ms) | sampling (ms) | update (ms) | total (ms) |"
    );
    let _ = writeln!(s, "| --- | --- | --- | --- | --- | --- |");
    for r in rows {
        let t = r.times;
        let _ = writeln!(
            s,
            "| {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
            r.model,
            r.spp,
            t.estimate_ms,
            t.sampling_ms,
            t.update_ms,
            t.estimate_ms + t.sampling_ms + t.update_ms
        );
    }
    s
}

/// Runs the table on `device` at `size` for `frames` frames, writes `pass_breakdown.md`
/// into `dir` and returns the section (no acceptance lines: a timing study).
///
/// # Errors
///
/// A pass error, or a file that cannot be written (naming it).
pub fn write(
    dir: &Path,
    device: Option<&GpuDevice>,
    size: [u32; 2],
    frames: u32,
    progress: &Progress,
) -> Result<Section, ReportError> {
    progress.stage(&format!(
        "pass-breakdown: the steps timed apart at {}x{}",
        size[0], size[1]
    ));
    if let Some(d) = device {
        check_frame_size(&d.device, size[0], size[1])?;
    }
    let rows = run_breakdown(device, size, frames)?;
    progress.inc(2 * u64::from(frames));
    let cpu_time = device.is_none_or(GpuDevice::is_software);
    let md = markdown(rows.as_deref(), size, frames, cpu_time);
    std::fs::create_dir_all(dir).map_err(|e| ReportError::io(dir, e))?;
    let path = dir.join("pass_breakdown.md");
    std::fs::write(&path, &md).map_err(|e| ReportError::io(&path, e))?;
    Ok(Section {
        name: "pass-breakdown",
        markdown: md,
        groups: Vec::new(),
    })
}
