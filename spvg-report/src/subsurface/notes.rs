//! The notes computed from a run's figures: what each scene's numbers mean, where the
//! budget runs' counts sit, the damped policy, the zero-sample rule, clipped chart points.

use std::fmt::Write as _;

use super::acceptance::{find, guide_figures};
use super::data::Report;
use super::figures;
use super::run::{BUDGET_BAND, BUDGET_WARMUP, FrameRecord, RunSpec};
use super::scene_runs::SceneRuns;
use crate::scene::SceneKind;
use crate::wgpu_api::PassConfig;

/// Mean of `f` over the records with `frame >= from` (NaN when none).
fn mean_from(records: &[FrameRecord], from: u32, f: fn(&FrameRecord) -> f64) -> f64 {
    let v: Vec<f64> = records.iter().filter(|r| r.frame >= from).map(f).collect();
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// The per-frame records of run `label` of a scene (report-setting runs only).
fn per_frame<'a>(s: &'a SceneRuns, label: &str) -> Option<&'a [FrameRecord]> {
    s.per_frame
        .iter()
        .find(|(l, _)| l == label)
        .map(|(_, r)| &r[..])
}

/// The per-pixel sample budget `beta_max`.
fn budget() -> f64 {
    f64::from(PassConfig::default().spvg.max_samples())
}

/// Static: AS against fixed64 by target variance, and after the warm-up.
fn static_notes(r: &Report, st: &SceneRuns, o: &mut String) {
    let Some(f) = find(&st.summaries, "fixed64") else {
        return;
    };
    let mut parts = Vec::new();
    for (set, cfg) in &r.inputs.settings {
        if !set.is_empty() && !set.contains("s0^2") {
            continue;
        }
        if let Some(a) = find(&st.summaries, &format!("as{set}")) {
            parts.push((
                cfg.spvg.target_variance(),
                f.mean_psnr - a.mean_psnr,
                a.mean_spp,
            ));
        }
    }
    parts.sort_by(|a, b| b.0.total_cmp(&a.0));
    if !parts.is_empty() {
        let list: Vec<String> = parts
            .iter()
            .map(|(s, d, n)| format!("{s:e}: {d:.2} dB at {n:.1} spp"))
            .collect();
        let _ = writeln!(
            o,
            "- Static, AS against fixed64 ({:.2} dB at 64 spp) by target variance: {}. The target is absolute (squared luminance): the static check needs a target below fixed64's per-pixel error in the noisy bands.",
            f.mean_psnr,
            list.join("; ")
        );
    }
    let from = 16;
    if let (Some(a), Some(fr)) = (per_frame(st, "as"), per_frame(st, "fixed64"))
        && r.inputs.frames > from + 8
    {
        let gap = mean_from(fr, from, |r| r.psnr) - mean_from(a, from, |r| r.psnr);
        let _ = writeln!(
            o,
            "- Static warm-up: the mean PSNR includes the first frames, where a pixel without history starts at beta_min (docs/algorithms.md §2.3). From frame {from} on the AS gap to fixed64 is {gap:.2} dB at {:.1} spp.",
            mean_from(a, from, |r| r.spp)
        );
    }
}

/// Flash: what AS spends on the light's temporal change, and what the CV models spend.
fn flash_note(fl: &SceneRuns, o: &mut String) {
    let Some(a) = find(&fl.summaries, "as") else {
        return;
    };
    let cv: Vec<String> = ["ccv", "ocv"]
        .iter()
        .filter_map(|m| {
            find(&fl.summaries, m)
                .map(|c| format!("{m} {:.1} spp at {:.2} dB", c.mean_spp, c.mean_psnr))
        })
        .collect();
    let _ = writeln!(
        o,
        "- Flash: AS averages {:.1} spp ({:.0}% of the {:.0}-sample budget) at {:.2} dB: its monitored variance is mostly the light's temporal change. The CV models monitor the residual: {}.",
        a.mean_spp,
        100.0 * a.mean_spp / budget(),
        budget(),
        a.mean_psnr,
        if cv.is_empty() {
            "not run".into()
        } else {
            cv.join(", ")
        }
    );
}

/// Switch: how many frames AS spends near the budget.
fn switch_note(sw: &SceneRuns, o: &mut String) {
    let Some(recs) = per_frame(sw, "as") else {
        return;
    };
    let high = recs.iter().filter(|r| r.spp >= 0.9 * budget()).count();
    let cv: Vec<String> = ["ccv", "ocv"]
        .iter()
        .filter_map(|m| {
            find(&sw.summaries, m)
                .map(|c| format!("{m} worst {:.1} vs mean {:.1} spp", c.worst_spp, c.mean_spp))
        })
        .collect();
    let _ = writeln!(
        o,
        "- Switch: AS spends {high} of {} frames at 90% of the budget or more (the switch fills its variance); {}.",
        recs.len(),
        if cv.is_empty() {
            "no CV runs".into()
        } else {
            cv.join(", ")
        }
    );
}

/// What the TAA resolve changes: PSNR after TAA minus single-frame PSNR and the resolved
/// image's flicker, of fixed64 and AS on every scene.
fn taa_note(r: &Report, o: &mut String) {
    if !r.inputs.reference {
        return;
    }
    let rows: Vec<String> = r
        .scenes
        .iter()
        .flat_map(|s| {
            ["fixed64", "as"].into_iter().filter_map(move |m| {
                find(&s.summaries, m).map(|c| {
                    format!(
                        "{} {m} {:+.2} dB (flicker {:.2e})",
                        s.kind.name(),
                        c.mean_psnr_taa - c.mean_psnr,
                        c.flicker_taa
                    )
                })
            })
        })
        .collect();
    if !rows.is_empty() {
        let _ = writeln!(
            o,
            "- PSNR after TAA minus single-frame PSNR: {}. The resolve averages about 1/w = {:.0} frames where the image holds still and follows the current frame's neighbourhood where it changes (the clamp), so it gains most on the static scene. Under changing light it loses at the shadow edge: there the 3x3 box spans lit and shadowed pixels, so last frame's value lies inside it and is kept (ghosting), the known limit of a neighbourhood clamp on one channel.",
            rows.join(", "),
            1.0 / crate::taa::WEIGHT
        );
    }
}

/// The TAA-guided update against AS on every scene that ran both: spp, PSNR single-frame
/// and after TAA, flicker, and which form needs fewer samples at equal PSNR after TAA.
fn guide_note(r: &Report, o: &mut String) {
    if !r.inputs.reference {
        return;
    }
    let rows: Vec<String> = r
        .scenes
        .iter()
        .filter_map(|s| {
            let a = find(&s.summaries, "as")?;
            let g = find(&s.summaries, RunSpec::GUIDED)?;
            let verdict = match guide_figures(&s.summaries, a, g) {
                Some(f) if f.spp_at_as_psnr < a.mean_spp => format!(
                    "the guide wins ({:.2}x AS's spp at equal PSNR after TAA)",
                    f.spp_at_as_psnr / a.mean_spp
                ),
                Some(f) => format!(
                    "AS wins (the guide needs {:.2}x AS's spp at equal PSNR after TAA)",
                    f.spp_at_as_psnr / a.mean_spp
                ),
                None => "not comparable (no slope of the fixed runs after TAA)".into(),
            };
            Some(format!(
                "{} as-guided {:.1} spp, {:.2} / {:.2} dB (single / after TAA), flicker {:.2e} against AS {:.1} spp, {:.2} / {:.2} dB, flicker {:.2e}: {verdict}",
                s.kind.name(),
                g.mean_spp,
                g.mean_psnr,
                g.mean_psnr_taa,
                g.flicker_taa,
                a.mean_spp,
                a.mean_psnr,
                a.mean_psnr_taa,
                a.flicker_taa
            ))
        })
        .collect();
    if !rows.is_empty() {
        let _ = writeln!(
            o,
            "- TAA-guided monitoring (docs/algorithms.md §8.5; the variance follows the deviation from the resolve's clamped history C_t instead of the pixel's own mean): {}. Under changing light the clamp pulls C_t to this frame's neighbourhood, so the light's change is not counted as noise and the count falls; where the image holds still C_t and the mean agree and the two forms spend alike.",
            rows.join("; ")
        );
    }
}

/// Each budget run: the range the governor moved the target in, the worst frame.
fn budget_targets(r: &Report, b: f64, o: &mut String) {
    for sc in &r.scenes {
        let Some(recs) = per_frame(sc, "budget") else {
            continue;
        };
        let (lo, hi) = recs
            .iter()
            .map(|r| r.target)
            .fold((f64::INFINITY, 0.0_f64), |(a, z), t| (a.min(t), z.max(t)));
        let worst = recs
            .iter()
            .filter(|r| r.frame >= BUDGET_WARMUP)
            .map(|r| (r.spp / b - 1.0).abs())
            .fold(0.0_f64, f64::max);
        let _ = writeln!(
            o,
            "- {} budget run: the governor moved sigma0^2 within [{lo:.3e}, {hi:.3e}] (history encoded at the initial {:e}); worst frame from frame {BUDGET_WARMUP} on {:.1}% off the budget.",
            sc.kind.name(),
            r.inputs.sigma0_sq,
            100.0 * worst
        );
    }
}

/// One scene's budget run after the warm-up: where its counts sit and how well the
/// clamp-aware feed-forward predicted each frame's total.
fn budget_row(name: &str, recs: &[FrameRecord], b: f64) -> Option<String> {
    let judged: Vec<&FrameRecord> = recs
        .iter()
        .filter(|r| r.frame >= BUDGET_WARMUP && r.at_bounds.iter().all(|v| v.is_finite()))
        .collect();
    if judged.is_empty() {
        return None;
    }
    let n = judged.len() as f64;
    let lo = 100.0 * judged.iter().map(|r| r.at_bounds[0]).sum::<f64>() / n;
    let hi = 100.0 * judged.iter().map(|r| r.at_bounds[1]).sum::<f64>() / n;
    let model: Vec<f64> = judged
        .iter()
        .filter(|r| r.planned_spp.is_finite() && r.spp > 0.0)
        .map(|r| (r.planned_spp / r.spp - 1.0).abs())
        .collect();
    let mean_model = 100.0 * model.iter().sum::<f64>() / model.len().max(1) as f64;
    let worst_model = 100.0 * model.iter().fold(0.0_f64, |m, e| m.max(*e));
    let out: Vec<&&FrameRecord> = judged
        .iter()
        .filter(|r| (r.spp / b - 1.0).abs() > BUDGET_BAND)
        .collect();
    let out_model = out
        .iter()
        .filter(|r| (r.planned_spp / r.spp - 1.0).abs() > 0.5 * BUDGET_BAND)
        .count();
    Some(format!(
        "{name}: {lo:.1}% of the subsurface pixels at beta_min, {hi:.1}% at beta_max, {:.1}% between; the feed-forward's model of the frame total (the previous frame's demand curve at the target the frame ran with) off by {mean_model:.2}% on average, {worst_model:.1}% at worst; {} frames outside the band, {out_model} of them with a model error above {:.0}%",
        100.0 - lo - hi,
        out.len(),
        50.0 * BUDGET_BAND
    ))
}

/// Every budget run's [`budget_row`], in one note.
fn budget_rows(r: &Report, b: f64, o: &mut String) {
    let rows: Vec<String> = r
        .scenes
        .iter()
        .filter_map(|sc| budget_row(sc.kind.name(), per_frame(sc, "budget")?, b))
        .collect();
    if !rows.is_empty() {
        let _ = writeln!(
            o,
            "- The budget runs, frames from frame {BUDGET_WARMUP} on (frames.csv has each frame): {}. The governor's feed-forward solves the clamped total for the budget (docs/algorithms.md §8.2): each pixel's count at {} candidate targets, interpolated in 1/sigma0^2; the integral feedback removes what the model misses.",
            rows.join("; "),
            spvg::budget::CURVE_POINTS
        );
    }
}

/// The kappa sweep's policies on the circle scenario.
fn circle_note(r: &Report, o: &mut String) {
    if r.circle.is_empty() {
        return;
    }
    let rows: Vec<String> = r
        .circle
        .iter()
        .map(|r| {
            format!(
                "{} within 10% from frame {}, steady mean |dn| {:.2}, lag-1 autocorrelation {:.2}, steady mean count {:.2}",
                r.label, r.frames_to_band, r.mean_abs_step, r.lag1, r.steady_mean
            )
        })
        .collect();
    let _ = writeln!(
        o,
        "- Kappa sweep with the damped correction (circle scenario, core crate; the pass does not expose the damped rule yet): {}.",
        rows.join("; ")
    );
}

/// Pixel-frames of the adaptive runs where the zero-sample rule took no samples.
fn zero_sample_note(r: &Report, o: &mut String) {
    let zero: u64 = r
        .scenes
        .iter()
        .flat_map(|s| s.all_frames.iter())
        .filter(|(l, _)| !l.starts_with("fixed"))
        .flat_map(|(_, r)| r.iter().map(|r| r.zero_pixels))
        .sum();
    let _ = writeln!(
        o,
        "- The zero-sample rule (eps_u, docs/algorithms.md §2.4) gave 0 distant samples on {zero} pixel-frames of the adaptive runs."
    );
}

/// The PSNR charts with points drawn at the axis's edge.
fn clipped_notes(clipped: &[(String, usize)], o: &mut String) {
    for (file, n) in clipped {
        if *n > 0 {
            let _ = writeln!(
                o,
                "- `{file}`: {n} points lie off the PSNR axis and are drawn at its edge: the axis leaves out the lowest {:.0}% of points and ends {} dB above the highest run median, so near-black frames (PSNR towards its 120 dB floor) do not flatten the other lines; `*_relmse.svg` shows every frame on a log axis.",
                100.0 * figures::PSNR_CLIP,
                figures::PSNR_SPIKE_DB
            );
        }
    }
}

/// Notes computed from this run's figures (`clipped`: each PSNR chart and its points off
/// the axis).
pub(crate) fn notes(r: &Report, clipped: &[(String, usize)]) -> String {
    let mut o = String::new();
    let scene = |k: SceneKind| r.scenes.iter().find(|s| s.kind == k);
    if let Some(st) = scene(SceneKind::Static) {
        static_notes(r, st, &mut o);
    }
    if let Some(fl) = scene(SceneKind::Flash) {
        flash_note(fl, &mut o);
    }
    if let Some(sw) = scene(SceneKind::Switch) {
        switch_note(sw, &mut o);
    }
    taa_note(r, &mut o);
    guide_note(r, &mut o);
    if let Some(b) = r.inputs.budget_spp {
        budget_targets(r, b, &mut o);
        budget_rows(r, b, &mut o);
    }
    circle_note(r, &mut o);
    zero_sample_note(r, &mut o);
    clipped_notes(clipped, &mut o);
    o
}
