//! The separable section's markdown: the fit table, the focus scene's runs, their work and
//! the timing rows.

use std::fmt::Write as _;

use super::fit::FitRow;
use super::focus::{BAND_PX, FocusOptions, FocusResult, TIMING_WARMUP};

/// The section's markdown: the fit table, the focus runs, the work, the timing rows.
#[must_use]
pub fn markdown(fits: &[FitRow], r: &FocusResult, opts: &FocusOptions) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## Separable subsurface scattering and the hybrid pass\n"
    );
    let _ = writeln!(
        s,
        "The separable profile fitted to each preset's Burley channels (shape match; \
         residual = sqrt(S_delta / sum (r R_B)^2), the radial profile error; f = 1 is clamped: \
         the Burley profile is wider than any separable one).\n"
    );
    let _ = writeln!(
        s,
        "| preset | falloff R, G, B | radial profile error R, G, B |"
    );
    let _ = writeln!(s, "| --- | --- | --- |");
    for f in fits {
        let _ = writeln!(
            s,
            "| {} | {:.3}, {:.3}, {:.3} | {:.3}, {:.3}, {:.3} |",
            f.name,
            f.falloff[0],
            f.falloff[1],
            f.falloff[2],
            f.residual[0],
            f.residual[1],
            f.residual[2]
        );
    }
    let [w, h] = opts.size;
    let _ = writeln!(
        s,
        "\nFocus scene: the static scene (gradient lighting) at {w}x{h}, {}, a disc of radius \
         {:.0}% of the height tagged for Monte Carlo ({:.1}% of the subsurface pixels), AFIS \
         on; {} frames, metrics over the second half. Band: {BAND_PX} px each side of the \
         disc's edge. Times are {}.\n",
        opts.material.name,
        100.0 * opts.radius,
        100.0 * r.focus_fraction,
        opts.frames,
        if r.cpu_time {
            "CPU time (software adapter or CPU twin; submit to wait)"
        } else {
            "GPU wall time (submit to wait)"
        }
    );
    let sep_ms = r.runs.first().map_or(0.0, |x| x.time_ms).max(1e-9);
    let _ = writeln!(
        s,
        "| run | time (ms) | / separable | spp | PSNR frame (dB) | PSNR focus (dB) | RMSE band | RMSE inside | RMSE outside |"
    );
    let _ = writeln!(s, "| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for x in &r.runs {
        let _ = writeln!(
            s,
            "| {} | {:.3} | {:.2} | {:.2} | {:.2} | {:.2} | {:.5} | {:.5} | {:.5} |",
            x.name,
            x.time_ms,
            x.time_ms / sep_ms,
            x.spp,
            x.psnr_frame,
            x.psnr_focus,
            x.rmse_band,
            x.rmse_inside,
            x.rmse_outside
        );
    }
    if let Some(t) = &r.timing {
        let st = &t.steps;
        let p1 = st.estimate_ms + st.sampling_ms + st.update_ms;
        let _ = writeln!(
            s,
            "\nTiming rows at {}x{} (the quality runs above at {w}x{h} are mostly \
             per-dispatch and per-submit overhead on a software adapter): the same scene and \
             disc ({:.1}% of the subsurface pixels tagged), {} frames after {TIMING_WARMUP} \
             warm-up, the runs interleaved frame by frame, medians. Separable-only {:.3} ms, \
             CCV-only {:.3} ms, hybrid {:.3} ms (one submit: its first step over the 8x8 \
             tiles holding a tagged pixel, the separable passes over those holding an \
             untagged one). The hybrid step by step (each \
             submitted alone): distant ratio and estimate {:.3} ms, sampling {:.3} ms, update \
             {:.3} ms (the first step {:.3} ms = {:.1}% of CCV-only), the AFIS result \
             composed into the separable input {:.3} ms, horizontal separable \
             pass {:.3} ms, vertical {:.3} ms (the separable passes {:.1}% of \
             separable-only). Median over the frames of the time bound's slack, separable \
             + 1.3 x the tagged fraction x (CCV - separable) - hybrid with one frame's runs: \
             {:.3} ms.",
            t.size[0],
            t.size[1],
            100.0 * t.focus_fraction,
            t.frames,
            t.separable_ms,
            t.ccv_ms,
            t.hybrid_ms,
            st.estimate_ms,
            st.sampling_ms,
            st.update_ms,
            p1,
            100.0 * p1 / t.ccv_ms,
            st.compose_ms,
            st.horizontal_ms,
            st.vertical_ms,
            100.0 * (st.horizontal_ms + st.vertical_ms) / t.separable_ms,
            t.slack_ms
        );
    }
    let w = r.work;
    let _ = writeln!(
        s,
        "\nWork of the runs at {w_}x{h_} (fetched texels per frame, the mean over the measured \
         frames; each pass's invocations over the pixels it is dispatched on, each with the \
         texels it loads): separable-only {:.0}, CCV-only {:.0}, hybrid {:.0}. {}",
        w.separable,
        w.ccv,
        w.hybrid,
        if r.judge_time {
            "The time line judges the timing rows' milliseconds (a hardware adapter with timestamp queries)."
        } else {
            "The time line judges this work (no usable timestamps on this adapter); the milliseconds are quoted beside it."
        },
        w_ = opts.size[0],
        h_ = opts.size[1]
    );
    s
}
