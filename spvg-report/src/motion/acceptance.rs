//! The acceptance lines of the motion report, each judged from the runs alone.

use super::baseline::baseline_name;
use super::runs::{MotionReport, MotionRun, WARM_UP, mean};
use super::scenes::{
    AGE_WEIGHT, BORDER_TEXEL, DOLLY, NEAREST_ONLY, NO_DILATION, NO_NEIGHBOUR_PRIOR, NO_PRIOR,
    NO_REPROJECTED_DEPTH, NO_SPATIAL, SPATIAL, TIGHTER_TARGETS, YOUNG, pans, tighter_name,
};
use super::uncovered::AgeErrors;
use crate::acceptance::Check;
use crate::equal_quality::{EqualQuality, FixedPoint, psnr_at_or_extrapolated};
use crate::wgpu_api::Motion;

fn find<'a>(rep: &'a MotionReport, scene: &str, mode: &str) -> Option<&'a MotionRun> {
    rep.runs.iter().find(|r| r.scene == scene && r.mode == mode)
}

/// The knob rows of `scene` in words (entering pixels at the border texel's count, no
/// count dilation, no footprint search, the young-history rules), or nothing where they
/// were not run.
fn knob_rows(rep: &MotionReport, scene: &str) -> String {
    [
        (BORDER_TEXEL, "entering pixels at the border texel's count"),
        (NO_DILATION, "without count dilation"),
        (NEAREST_ONLY, "without the footprint search"),
        (AGE_WEIGHT, "with the age-aware weight"),
        (SPATIAL, "with the spatial variance of young histories"),
        (
            NO_SPATIAL,
            "without the spatial variance of young histories",
        ),
        (NO_NEIGHBOUR_PRIOR, "without the neighbour prior"),
        (YOUNG, "with every young-history rule"),
    ]
    .iter()
    .filter_map(|(mode, what)| {
        find(rep, scene, mode)
            .map(|b| format!("; {what}: {:.1} spp, {:.2} dB", b.mean_spp(), b.mean_psnr()))
    })
    .collect()
}

/// The second consumer at rest, at both sizes: AS within 1 dB of fixed 64 at <= 32 spp.
fn static_cameras(rep: &MotionReport) -> Vec<Check> {
    let mut lines = Vec::new();
    for st_name in ["static", "static-pan"] {
        let (Some(st), Some(fixed)) = (find(rep, st_name, "as"), find(rep, st_name, "fixed64"))
        else {
            continue;
        };
        lines.push(Check::new(
            st.mean_psnr() >= fixed.mean_psnr() - 1.0 && st.mean_spp() <= 32.0,
            format!(
                "Second consumer (AO), {st_name} camera: AS {:.2} dB at {:.1} spp vs fixed 64 \
                 {:.2} dB (within 1 dB at <= 32 spp){}",
                st.mean_psnr(),
                st.mean_spp(),
                fixed.mean_psnr(),
                knob_rows(rep, st_name)
            ),
        ));
    }
    lines
}

/// The pan criterion: at most 1.25x the static camera's samples and at most 1 dB below it;
/// the spp ratio and the dB loss.
fn meets_pan_criterion(a: &MotionRun, st: &MotionRun) -> (bool, f64, f64) {
    let ratio = a.mean_spp() / st.mean_spp();
    let loss = st.mean_psnr() - a.mean_psnr();
    (ratio <= 1.25 && loss <= 1.0, ratio, loss)
}

/// The dolly's run without the reprojected depth against the static camera, in words.
fn without_reprojected_depth(rep: &MotionReport, scene: &str, st: &MotionRun) -> String {
    find(rep, scene, NO_REPROJECTED_DEPTH).map_or(String::new(), |b| {
        let (ok, ratio, loss) = meets_pan_criterion(b, st);
        format!(
            "; without the reprojected depth (this frame's depth in the depth test): {:.1} spp \
             = {ratio:.2}x, {:.2} dB = {loss:+.2} dB below ({})",
            b.mean_spp(),
            b.mean_psnr(),
            if ok {
                "meets the criterion"
            } else {
                "fails the criterion"
            }
        )
    })
}

/// The pans and the rotation, each against the static camera of its size, and the dolly
/// against static cameras at its heights ([`baseline_name`]): at most 1.25x its samples and
/// at most 1 dB below it.
fn pan_criterion(rep: &MotionReport) -> Vec<Check> {
    let moving = pans()
        .into_iter()
        .map(|m| (m, "static-pan".to_string()))
        .chain([
            (Motion::Rotate { degrees: 2.0 }, "static".to_string()),
            (DOLLY, baseline_name(DOLLY)),
        ]);
    let mut lines = Vec::new();
    for (scene, st_name) in moving {
        let name = scene.name();
        let (Some(a), Some(st)) = (find(rep, &name, "as"), find(rep, &st_name, "as")) else {
            continue;
        };
        let identity = find(rep, &name, "as-identity").map_or(String::new(), |id| {
            format!(
                "; identity history: {:.1} spp ({:.2}x), {:.2} dB",
                id.mean_spp(),
                id.mean_spp() / st.mean_spp(),
                id.mean_psnr()
            )
        });
        let without = find(rep, &name, NO_PRIOR).map_or(String::new(), |b| {
            format!(
                "; without the border prior (beta_min for entering pixels): {:.1} spp, {:.2} dB",
                b.mean_spp(),
                b.mean_psnr()
            )
        });
        let (ok, ratio, loss) = meets_pan_criterion(a, st);
        let no_depth = without_reprojected_depth(rep, &name, st);
        // The dolly against the static camera at rest height too (its content differs).
        let rest = match (scene, find(rep, "static", "as")) {
            (Motion::Dolly { .. }, Some(r)) => {
                let (_, ratio, loss) = meets_pan_criterion(a, r);
                format!(
                    "; against the static camera at rest height (`static`): {ratio:.2}x, \
                     {loss:+.2} dB below"
                )
            }
            _ => String::new(),
        };
        lines.push(Check::new(
            ok,
            format!(
                "Pan criterion, {name}: AS {:.1} spp = {ratio:.2}x {st_name} (<= 1.25x), {:.2} dB \
                 = {loss:+.2} dB below {st_name} (<= 1 dB); on the pixels on screen for 3 \
                 frames {:.2} dB ({:+.2} dB){identity}{without}{no_depth}{rest}{}",
                a.mean_spp(),
                a.mean_psnr(),
                a.mean_psnr_steady(),
                st.mean_psnr() - a.mean_psnr_steady(),
                knob_rows(rep, &name)
            ),
        ));
    }
    lines
}

/// Disocclusion by motion: at most 10% of the pixels the sphere uncovers at the maximum
/// count in any frame.
fn disocclusion(rep: &MotionReport) -> Vec<Check> {
    let flat = |v: &[Option<f64>]| v.iter().flatten().copied().collect::<Vec<_>>();
    rep.runs
        .iter()
        .filter(|r| r.mode == "as" && r.scene.starts_with("object"))
        .map(|r| {
            let worst = flat(&r.uncovered_at_max)
                .iter()
                .fold(0.0_f64, |m, &x| m.max(x));
            let un = mean(&flat(&r.uncovered_spp));
            let st = mean(&flat(&r.steady_spp));
            let average = mean(&flat(&r.uncovered_at_max));
            // The identity history too: what these pixels get from the stale history left
            // at their pixel by the object that uncovered them.
            let young: String = [
                AGE_WEIGHT,
                SPATIAL,
                NO_SPATIAL,
                NO_NEIGHBOUR_PRIOR,
                YOUNG,
                "as-identity",
            ]
            .iter()
            .filter_map(|mode| find(rep, &r.scene, mode))
            .map(|y| {
                format!(
                    "; {}: uncovered {:.1} spp, at most {:.1}% at the maximum",
                    y.mode,
                    mean(&flat(&y.uncovered_spp)),
                    100.0
                        * flat(&y.uncovered_at_max)
                            .iter()
                            .fold(0.0_f64, |m, &x| m.max(x))
                )
            })
            .collect();
            Check::new(
                worst <= 0.10,
                format!(
                    "Disocclusion by motion, {}: newly uncovered pixels {un:.1} spp vs steady \
                     {st:.1} spp on average; at most {:.1}% of the uncovered pixels at the \
                     maximum count in any frame (<= 10%), {:.1}% on average{young}",
                    r.scene,
                    100.0 * worst,
                    100.0 * average
                ),
            )
        })
        .collect()
}

/// The young-history rows of `scene` against `st` in words: spp ratio and dB below.
fn young_rows(rep: &MotionReport, scene: &str, st: &MotionRun) -> String {
    [AGE_WEIGHT, SPATIAL, NO_SPATIAL, NO_NEIGHBOUR_PRIOR, YOUNG]
        .iter()
        .filter_map(|mode| find(rep, scene, mode))
        .map(|y| {
            let (_, ratio, loss) = meets_pan_criterion(y, st);
            format!(
                "; {}: {:.1} spp = {ratio:.2}x, {:.2} dB = {loss:+.2} dB below",
                y.mode,
                y.mean_spp(),
                y.mean_psnr()
            )
        })
        .collect()
}

/// Young history under the fastest motions: `pan8` and `rotate2` at most 0.5 dB below
/// their static camera at no more than 1.25x its spp (AS as the report runs it; the
/// young-history rows quoted). The static camera is the one held still at the moving
/// camera's own poses ([`super::poses`]) where the report ran it, compared on the frames
/// whose poses it held; the static camera at the first pose is quoted beside it.
fn young_history(rep: &MotionReport) -> Vec<Check> {
    let mut lines = Vec::new();
    for (scene, st_name) in [("pan8", "static-pan"), ("rotate2", "static")] {
        let (Some(a), Some(st)) = (find(rep, scene, "as"), find(rep, st_name, "as")) else {
            continue;
        };
        let (_, first_ratio, first_loss) = meets_pan_criterion(a, st);
        let still = rep.still.iter().find(|b| b.scene == scene);
        let (ratio, loss, against) = match still {
            Some(b) => {
                let ((a_spp, a_db), (b_spp, b_db)) = b.compare(a);
                (
                    a_spp / b_spp,
                    b_db - a_db,
                    format!(
                        "the static camera held at its poses (frames {}: {b_spp:.1} spp, \
                         {b_db:.2} dB; AS {a_spp:.1} spp, {a_db:.2} dB on those frames)",
                        b.frames
                            .iter()
                            .map(u32::to_string)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                )
            }
            None => (first_ratio, first_loss, st_name.to_string()),
        };
        let first = if still.is_some() {
            format!(
                "; against {st_name} (the first pose): {first_ratio:.2}x, {first_loss:+.2} dB \
                 below"
            )
        } else {
            String::new()
        };
        // The fixed count's own loss on the same cameras: what the moving camera's content
        // costs at equal samples, with no history involved.
        let content = match (find(rep, scene, "fixed64"), find(rep, st_name, "fixed64")) {
            (Some(f), Some(fs)) => {
                let own = fs.mean_psnr() - f.mean_psnr();
                format!(
                    "; fixed64 loses {own:.2} dB on the same cameras ({:.2} vs {:.2} dB), so \
                     AS's loss beyond the content's is {:+.2} dB",
                    f.mean_psnr(),
                    fs.mean_psnr(),
                    loss - own
                )
            }
            _ => String::new(),
        };
        lines.push(Check::new(
            ratio <= 1.25 && loss <= 0.5,
            format!(
                "Young history, {scene}: AS {ratio:.2}x the spp of {against} (<= 1.25x), \
                 {loss:+.2} dB below it (<= 0.5 dB){first}{content}{}",
                young_rows(rep, scene, st)
            ),
        ));
    }
    lines
}

/// The moving objects: AS with reprojection at least the identity history's PSNR at no
/// more than its spp. AS is a curve, not a point: the identity history, at the same
/// target, spends more (it carries counts left at a pixel by whatever was there), so the
/// line takes AS at the report's target and at the [`TIGHTER_TARGETS`] and passes when
/// one of them reaches the identity history's PSNR at no more of its spp. AS at the
/// report's target is quoted first, and every point after the TAA resolve too.
fn reprojection_beats_identity(rep: &MotionReport) -> Vec<Check> {
    rep.runs
        .iter()
        .filter(|r| r.mode == "as" && r.scene.starts_with("object"))
        .filter_map(|a| {
            let id = find(rep, &a.scene, "as-identity")?;
            let young: String = [AGE_WEIGHT, SPATIAL, NO_SPATIAL, NO_NEIGHBOUR_PRIOR, YOUNG]
                .iter()
                .filter_map(|mode| find(rep, &a.scene, mode))
                .map(|y| {
                    format!(
                        "; {}: {:.2} dB at {:.1} spp",
                        y.mode,
                        y.mean_psnr(),
                        y.mean_spp()
                    )
                })
                .collect();
            let dominates =
                |r: &MotionRun| r.mean_psnr() >= id.mean_psnr() && r.mean_spp() <= id.mean_spp();
            let tighter: Vec<&MotionRun> = TIGHTER_TARGETS
                .iter()
                .filter_map(|&f| find(rep, &a.scene, &tighter_name(f)))
                .collect();
            let curve: String = tighter
                .iter()
                .map(|t| {
                    format!(
                        "; {}: {:.2} dB at {:.1} spp{} (after TAA {:.2} dB)",
                        t.mode,
                        t.mean_psnr(),
                        t.mean_spp(),
                        if dominates(t) { ", dominates" } else { "" },
                        t.mean_psnr_taa()
                    )
                })
                .collect();
            // Where the two differ: the pixels the object uncovers and the object itself
            // (the identity history gives each the count that the history of whatever was
            // at the pixel left there).
            let spp = |v: &[Option<f64>]| mean(&v.iter().flatten().copied().collect::<Vec<_>>());
            Some(Check::new(
                dominates(a) || tighter.iter().any(|t| dominates(t)),
                format!(
                    "Reprojection against the identity history, {}: AS {:.2} dB at {:.1} spp vs \
                     the identity history {:.2} dB at {:.1} spp (need an AS point at >= its \
                     PSNR and <= its spp){curve}; after TAA AS {:.2} dB, the identity history \
                     {:.2} dB; AS against the identity history on the newly uncovered pixels \
                     {:.1} vs {:.1} spp, on the moving object {:.1} vs {:.1} spp{young}",
                    a.scene,
                    a.mean_psnr(),
                    a.mean_spp(),
                    id.mean_psnr(),
                    id.mean_spp(),
                    a.mean_psnr_taa(),
                    id.mean_psnr_taa(),
                    spp(&a.uncovered_spp),
                    spp(&id.uncovered_spp),
                    spp(&a.object_spp),
                    spp(&id.object_spp)
                ),
            ))
        })
        .collect()
}

/// A PSNR in words (`n/a` where its class had no pixel).
fn db(x: Option<f64>) -> String {
    x.map_or_else(|| "n/a".into(), |x| format!("{x:.2} dB"))
}

/// The frames a run's means pool, in words (`16..47`).
fn pooled_frames(frames: usize) -> String {
    let first = if frames > 2 * WARM_UP { WARM_UP } else { 0 };
    format!("{first}..{}", frames.saturating_sub(1))
}

/// Young history where objects move: on every moving-object scene, the newly uncovered
/// pixels at their third frame on screen within 1 dB of the steady pixels (AS; PSNR of the
/// MSE pooled over every pixel-frame of the class after the warm-up), `as-young` and
/// `fixed64` quoted (the fixed run has no history: its gap is what the uncovered pixels'
/// content costs by itself).
fn uncovered_error(rep: &MotionReport) -> Vec<Check> {
    // The third frame against the steady pixels, dB (negative: below them).
    let gap = |e: &AgeErrors| e.psnr(3).zip(e.psnr(0)).map(|(t, s)| t - s);
    let signed = |x: Option<f64>| x.map_or_else(|| "n/a".into(), |x| format!("{x:+.2} dB"));
    rep.runs
        .iter()
        .filter(|r| r.mode == "as" && r.scene.starts_with("object"))
        .filter(|r| !r.uncovered_errors.is_empty())
        .map(|a| {
            let e = a.pooled_uncovered_errors();
            let fixed = find(rep, &a.scene, "fixed64").map(MotionRun::pooled_uncovered_errors);
            let beyond =
                gap(&e)
                    .zip(fixed.as_ref().and_then(gap))
                    .map_or(String::new(), |(g, f)| {
                        format!(
                            "; beyond fixed64's own gap (the content's share): {:+.2} dB",
                            g - f
                        )
                    });
            let quoted: String = [YOUNG, "fixed64"]
                .iter()
                .filter_map(|mode| find(rep, &a.scene, mode))
                .map(|y| {
                    let e = y.pooled_uncovered_errors();
                    format!(
                        "; {}: third frame {} vs steady {} ({}; first {}, second {})",
                        y.mode,
                        db(e.psnr(3)),
                        db(e.psnr(0)),
                        signed(gap(&e)),
                        db(e.psnr(1)),
                        db(e.psnr(2))
                    )
                })
                .collect();
            Check::new(
                gap(&e).is_some_and(|g| g >= -1.0),
                format!(
                    "Uncovered pixels, {}: AS at their third frame on screen {} vs steady {} \
                     ({}; within 1 dB), first frame {}, second {}; PSNR of the MSE pooled \
                     over frames {} ({} pixel-frames at age 3, {} steady){quoted}{beyond}",
                    a.scene,
                    db(e.psnr(3)),
                    db(e.psnr(0)),
                    signed(gap(&e)),
                    db(e.psnr(1)),
                    db(e.psnr(2)),
                    pooled_frames(a.uncovered_errors.len()),
                    e.n[3],
                    e.n[0]
                ),
            )
        })
        .collect()
}

/// The GPU against the CPU twin: counts equal on at least 99% of the pixels of every
/// frame compared.
fn gpu_vs_twin(rep: &MotionReport) -> Vec<Check> {
    rep.agreement
        .iter()
        .map(|(scene, worst, frames)| {
            Check::new(
                *worst >= 0.99,
                format!(
                    "GPU vs twin, {scene}: counts equal on {:.2}% of pixels in the worst of \
                     {frames} frames (>= 99%)",
                    100.0 * worst
                ),
            )
        })
        .collect()
}

/// The motion bound: after one frame of motion vectors at `1e30` on the static camera,
/// the next frame's mean spp within 10% of the frame before the broken one.
fn motion_bound(rep: &MotionReport) -> Vec<Check> {
    rep.motion_bound
        .iter()
        .map(|b| {
            let change = b.after / b.before - 1.0;
            let young: String = rep
                .motion_bound_young
                .iter()
                .map(|(name, y)| {
                    format!(
                        "; {name}: next frame {:.2} spp vs {:.2} ({:+.1}%)",
                        y.after,
                        y.before,
                        100.0 * (y.after / y.before - 1.0)
                    )
                })
                .collect();
            Check::new(
                change.abs() <= 0.10,
                format!(
                    "Motion bound, static: one frame of motion vectors at 1e30 (frame {}): the \
                     next frame {:.2} spp vs {:.2} spp the frame before ({:+.1}%, within 10%); \
                     the broken frame itself {:.2} spp (every pixel disoccluded){young}",
                    b.frame,
                    b.after,
                    b.before,
                    100.0 * change,
                    b.broken
                ),
            )
        })
        .collect()
}

/// The fixed runs of `scene` as (mean spp, PSNR) points: single-frame, or after TAA.
pub(crate) fn fixed_points(rep: &MotionReport, scene: &str, taa: bool) -> Vec<FixedPoint> {
    rep.runs
        .iter()
        .filter(|r| r.scene == scene && r.mode.starts_with("fixed"))
        .map(|r| FixedPoint {
            spp: r.mean_spp(),
            psnr: if taa {
                r.mean_psnr_taa()
            } else {
                r.mean_psnr()
            },
        })
        .collect()
}

/// The final image on every scene with an AS run and at least two fixed runs: after TAA,
/// AS at its mean spp against the fixed runs' PSNR after TAA at the same spp (interpolated
/// in log2(spp), extrapolated from the nearest two and said so outside them), with the
/// equal-quality fixed count single-frame and after TAA.
fn final_image(rep: &MotionReport) -> Vec<Check> {
    let mut scenes: Vec<&str> = Vec::new();
    for r in &rep.runs {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    scenes
        .into_iter()
        .filter_map(|scene| {
            let a = find(rep, scene, "as")?;
            let (single, taa) = (fixed_points(rep, scene, false), fixed_points(rep, scene, true));
            let (f, extrapolated) = psnr_at_or_extrapolated(&taa, a.mean_spp())?;
            let eq = EqualQuality::new(&single, a.mean_spp(), a.mean_psnr());
            let eq_taa = EqualQuality::new(&taa, a.mean_spp(), a.mean_psnr_taa());
            Some(Check::new(
                a.mean_psnr_taa() > f,
                format!(
                    "Final image (AO), {scene}: AS after TAA {:.2} dB at {:.1} spp vs the fixed runs after TAA at the same spp {f:.2} dB ({}; need >), margin {:+.2} dB; equal quality single-frame {eq}, after TAA {eq_taa}",
                    a.mean_psnr_taa(),
                    a.mean_spp(),
                    if extrapolated {
                        "extrapolated in log2(spp) from the nearest two fixed runs"
                    } else {
                        "interpolated in log2(spp)"
                    },
                    a.mean_psnr_taa() - f
                ),
            ))
        })
        .collect()
}

/// Every acceptance line of the motion report, in report order.
#[must_use]
pub fn acceptance(rep: &MotionReport) -> Vec<Check> {
    let mut lines = static_cameras(rep);
    lines.extend(pan_criterion(rep));
    lines.extend(young_history(rep));
    lines.extend(disocclusion(rep));
    lines.extend(reprojection_beats_identity(rep));
    lines.extend(uncovered_error(rep));
    lines.extend(motion_bound(rep));
    lines.extend(final_image(rep));
    lines.extend(gpu_vs_twin(rep));
    lines
}
