//! The acceptance lines of the hybrid pass on the focus scene: its focus PSNR against
//! CCV-only, its cost against the bound, and its seam.
//!
//! The cost line judges milliseconds on a hardware adapter with timestamp queries, and
//! the work the runs dispatch ([`super::work`]: fetched texels) elsewhere: on a software
//! rasterizer the frame times are CPU time, and the bound's slack sits inside their
//! run-to-run noise. The milliseconds are quoted beside the work.

use super::focus::{FocusResult, FocusRun, hybrid_time_bound};
use crate::acceptance::Check;

/// The run `name` of `r` (an empty run where it is missing).
fn run(r: &FocusResult, name: &str) -> FocusRun {
    r.runs
        .iter()
        .find(|x| x.name == name)
        .cloned()
        .unwrap_or_default()
}

/// The hybrid's cost against `separable + 1.3 x tagged fraction x (CCV - separable)`.
fn cost(r: &FocusResult) -> Check {
    let (sep, ccv, hy) = (run(r, "separable"), run(r, "ccv"), run(r, "hybrid-ccv"));
    let samples = format!(
        "samples {:.2} spp per subsurface pixel vs CCV-only {:.2} (the tagged fraction {:.3})",
        hy.spp, ccv.spp, r.focus_fraction
    );
    let f = r.focus_fraction;
    if r.judge_time
        && let Some(t) = &r.timing
    {
        // A hardware adapter with timestamps: the median over the frames of the
        // per-frame slack, each frame's three runs interleaved, so that a change of the
        // machine's load between runs does not decide the line.
        let bound = hybrid_time_bound(t.separable_ms, t.ccv_ms, t.focus_fraction);
        return Check::new(
            t.slack_ms >= 0.0,
            format!(
                "hybrid time at {}x{}, {} frames: median over the frames of (separable + 1.3 x {:.3} x (CCV - separable) - hybrid), each frame's runs interleaved, {:.3} ms >= 0; medians of the runs: hybrid {:.3} ms, separable {:.3}, CCV {:.3} (the bound from them {bound:.3} ms); {samples}",
                t.size[0],
                t.size[1],
                t.frames,
                t.focus_fraction,
                t.slack_ms,
                t.hybrid_ms,
                t.separable_ms,
                t.ccv_ms
            ),
        );
    }
    let w = r.work;
    let bound = hybrid_time_bound(w.separable, w.ccv, f);
    let ms = match &r.timing {
        Some(t) => format!(
            "times at {}x{} (medians of {} interleaved frames, {}): hybrid {:.3} ms, separable {:.3}, CCV {:.3}, the bound from them {:.3}",
            t.size[0],
            t.size[1],
            t.frames,
            if r.cpu_time { "CPU time" } else { "wall time" },
            t.hybrid_ms,
            t.separable_ms,
            t.ccv_ms,
            hybrid_time_bound(t.separable_ms, t.ccv_ms, t.focus_fraction)
        ),
        None => format!(
            "times of the quality runs ({}, mostly per-dispatch overhead at this size): hybrid {:.3} ms, separable {:.3}, CCV {:.3}",
            if r.cpu_time { "CPU time" } else { "wall time" },
            hy.time_ms,
            sep.time_ms,
            ccv.time_ms
        ),
    };
    Check::new(
        w.hybrid <= bound,
        format!(
            "hybrid work: {:.0} fetched texels per frame <= separable {:.0} + 1.3 x {f:.3} x (CCV {:.0} - separable) = {bound:.0} ({:.3} of the bound; the adapter has no usable timestamps, so the line judges the work the passes dispatch); {ms}; {samples}",
            w.hybrid,
            w.separable,
            w.ccv,
            w.hybrid / bound
        ),
    )
}

/// The lines of the focus scene: the hybrid's focus PSNR within 0.2 dB of CCV-only, its
/// cost under the bound (milliseconds or work, as the module says), and its seam's error at most 1.5x the worse interior
/// error of the two techniques.
#[must_use]
pub fn checks(r: &FocusResult) -> Vec<Check> {
    let (sep, ccv, hy) = (run(r, "separable"), run(r, "ccv"), run(r, "hybrid-ccv"));
    let worse = sep.rmse_outside.max(ccv.rmse_inside);
    vec![
        Check::new(
            (hy.psnr_focus - ccv.psnr_focus).abs() <= 0.2,
            format!(
                "hybrid focus PSNR: {:.2} dB vs CCV-only {:.2} dB (within 0.2 dB)",
                hy.psnr_focus, ccv.psnr_focus
            ),
        ),
        cost(r),
        Check::new(
            hy.rmse_band <= 1.5 * worse,
            format!(
                "hybrid seam: band RMSE {:.5} <= 1.5 x {:.5} (the worse interior RMSE: separable outside {:.5}, CCV inside {:.5})",
                hy.rmse_band, worse, sep.rmse_outside, ccv.rmse_inside
            ),
        ),
    ]
}
