//! Two of the controller's policies measured on the core crate alone, each with a judged
//! acceptance line in the subsurface section: the damped correction on the circle
//! scenario ([`damped`]) and the firefly clamp's recovery from one outlier frame
//! ([`firefly`]). Neither runs a pass: the component's consumers do not expose them as
//! settings of their own, so the report measures the rules where they live.

pub mod damped;
pub mod firefly;

use std::fmt::Write as _;

use crate::acceptance::Check;
use damped::PolicyFigures;
use firefly::FireflyFigures;

/// The damped policy's checks on the circle scenario (core crate): the damped
/// correction reaches the steady band no later than kappa = 1 and moves no more than
/// kappa = 0 in the steady state.
#[must_use]
pub fn damped_checks(rows: &[PolicyFigures]) -> Vec<Check> {
    let get = |p: &str| rows.iter().find(|r| r.label.starts_with(p));
    let (Some(k0), Some(k1), Some(d)) = (get("kappa=0"), get("kappa=1"), get("damped")) else {
        return Vec::new();
    };
    vec![
        Check::new(
            d.frames_to_band <= k1.frames_to_band,
            format!(
                "circle {}: within 10% of the steady mean count from frame {} (kappa=1: {}, need <=)",
                d.label, d.frames_to_band, k1.frames_to_band
            ),
        ),
        Check::new(
            d.mean_abs_step <= k0.mean_abs_step,
            format!(
                "circle {}: steady mean |n_t - n_(t-1)| {:.2} (kappa=0: {:.2}, need <=)",
                d.label, d.mean_abs_step, k0.mean_abs_step
            ),
        ),
    ]
}

/// The firefly clamp's check on the core's outlier ensemble: at the recommended `k`, a
/// single 100x outlier holds the mean count outside 10% of the steady count for at most
/// [`firefly::RECOVERY_BOUND`] frames.
#[must_use]
pub fn firefly_checks(rows: &[FireflyFigures]) -> Vec<Check> {
    let off = rows.iter().find(|r| r.k.is_none());
    let on = rows.iter().find(|r| r.k == Some(firefly::RECOMMENDED_K));
    let (Some(off), Some(on)) = (off, on) else {
        return Vec::new();
    };
    let (Some(r_on), Some(r_off)) = (on.recoveries.first(), off.recoveries.first()) else {
        return Vec::new();
    };
    vec![Check::new(
        r_on.frames <= firefly::RECOVERY_BOUND,
        format!(
            "firefly clamp {}: after a single {} outlier the mean count is back within 10% of the steady count ({:.1}) after {} frames (need <= {}; clamp off: {} frames, peak {:.1} spp)",
            on.label,
            firefly::OUTLIERS[0].label(),
            on.steady_mean,
            r_on.frames,
            firefly::RECOVERY_BOUND,
            r_off.frames,
            r_off.peak
        ),
    )]
}

/// The firefly clamp's table: recovery from one outlier frame and the tracking of a real
/// step, for the clamp off and each `k` (core crate, [`firefly`]).
#[must_use]
pub fn firefly_markdown(rows: &[FireflyFigures]) -> String {
    use firefly::{
        AFTER, LEVEL, OUTLIER_FRAME, OUTLIERS, PER_SAMPLE_SD, PIXELS, RECOMMENDED_K, STEP,
    };
    if rows.is_empty() {
        return String::new();
    }
    let mut md = format!(
        "## Firefly clamp\n\n{PIXELS} independent pixels under the published controller (eta 0.2, sigma0^2 1e-4, kappa 0.2, budget [8, 64]), monitored value {LEVEL} plus the mean of n samples' normal noise (per-sample sd {PER_SAMPLE_SD}), seeded at frame 0; at frame {OUTLIER_FRAME} one outlier frame (or, last column, a step of the level to {} for good). *Frames* counts the frames after the outlier whose mean count (over the pixels) lies outside 10% of the steady count (frames {} to {}), up to the last one; *extra* is the samples per pixel spent above the steady count over the {AFTER} frames after it; *step* the updates until the mean of the histories' means is within 10% of the new level (the plain EMA takes 10). The documentation recommends k = {RECOMMENDED_K} (docs/algorithms.md §8.3).\n\n| clamp | steady spp |",
        STEP * LEVEL,
        firefly::STEADY_FROM,
        OUTLIER_FRAME - 1
    );
    for o in OUTLIERS {
        let _ = write!(
            md,
            " {l}: frames | {l}: peak spp | {l}: extra spp |",
            l = o.label()
        );
    }
    md.push_str(" step: updates |\n|---|---|");
    md.push_str(&"---|".repeat(3 * OUTLIERS.len() + 1));
    md.push('\n');
    for f in rows {
        let _ = write!(md, "| {} | {:.2} |", f.label, f.steady_mean);
        for rec in &f.recoveries {
            let _ = write!(
                md,
                " {} | {:.1} | {:.0} |",
                rec.frames, rec.peak, rec.extra_samples
            );
        }
        let _ = writeln!(md, " {} |", f.step_frames);
    }
    let _ = write!(
        md,
        "\nOne pixel (the ensemble's first, the core's `f32` controller at the published defaults), frames at {} spp after one value of {}: ",
        spvg::SpvgConfig::<f32>::published().max_samples(),
        firefly::CEILING_VALUES.map(|v| format!("{v:e}")).join(", ")
    );
    let per_row: Vec<String> = rows
        .iter()
        .map(|f| format!("{} {:?}", f.label, f.ceiling_frames))
        .collect();
    let _ = writeln!(md, "{}.\n", per_row.join("; "));
    md
}
