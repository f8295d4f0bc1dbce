//! The acceptance lines of the motion section, each judged from the runs alone.
//!
//! Where a line judges a loss under motion (the pan criterion, the young-history lines,
//! the uncovered pixels), it judges AS's loss beyond `fixed64`'s own loss on the same
//! pixels and cameras: `fixed64` has no history, so its loss is what the moving content
//! costs by itself; the raw figures stay in the line.

use super::data::{MotionReport, MotionRun, StillBaseline, TwinCheck, WARM_UP, mean};
use super::scenes::{
    AGE_WEIGHT, BORDER_TEXEL, DOLLY, NEAREST_ONLY, NO_DILATION, NO_NEIGHBOUR_PRIOR, NO_PRIOR,
    NO_REPROJECTED_DEPTH, NO_SPATIAL, OBJECTS, RESOLVED, RESOLVED_FLOOR, SPATIAL, TIGHTER_TARGETS,
    YOUNG, pans, tighter_name,
};
use super::uncovered::AgeErrors;
use crate::acceptance::Check;
use crate::equal_quality::{EqualQuality, FixedPoint, flicker_at_psnr, psnr_at_or_extrapolated};
use crate::section::Group;
use crate::wgpu_api::Motion;

/// The pan criterion's bounds: AS at most 1.25x the static camera's samples, and its loss
/// beyond `fixed64`'s own at most 1 dB.
pub const PAN_SPP_RATIO: f64 = 1.25;
/// See [`PAN_SPP_RATIO`].
pub const PAN_LOSS_DB: f64 = 1.0;
/// The young-history and uncovered-pixel lines' bound on AS's loss beyond `fixed64`'s own.
pub const YOUNG_LOSS_DB: f64 = 0.5;

/// The scenes whose equal quality after TAA the resolved-image rule is judged on against
/// the variance-equalizing rule's ideal `1/f` ([`MotionRun::mean_allocation_bounds`]),
/// with the share of it the rule must reach: 0.90 on the static cameras, 0.80 on the pan
/// (its entering pixels start without history). A fixed ratio target (2.5x) was retired:
/// it lay above the ideal itself (2.39x static, 2.56x pan8).
pub const IDEAL_SHARE_TARGETS: [(&str, f64); 3] =
    [("static", 0.90), ("static-pan", 0.90), ("pan8", 0.80)];

/// Scenes whose resolved-image run must save samples at all (equal quality after TAA at
/// least 1.0x): the moving objects, where the resolve rejects and clamps the most.
pub const SAVES_SCENES: [&str; 1] = ["objects5"];

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
        rep.find(scene, mode)
            .map(|b| format!("; {what}: {:.1} spp, {:.2} dB", b.mean_spp(), b.mean_psnr()))
    })
    .collect()
}

/// The second consumer at rest, at both sizes: AS within 1 dB of fixed 64 at <= 32 spp.
fn static_cameras(rep: &MotionReport) -> Vec<Check> {
    let mut lines = Vec::new();
    for st_name in ["static", "static-pan"] {
        let (Some(st), Some(fixed)) = (rep.find(st_name, "as"), rep.find(st_name, "fixed64"))
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

/// A run against its static baseline: the spp ratio, AS's loss, and `fixed64`'s own loss
/// on the same cameras where both fixed runs exist.
#[derive(Clone, Copy, Debug)]
struct Against {
    ratio: f64,
    loss: f64,
    fixed_loss: Option<f64>,
}

impl Against {
    fn of(a: &MotionRun, st: &MotionRun, fixed: Option<(&MotionRun, &MotionRun)>) -> Self {
        Self {
            ratio: a.mean_spp() / st.mean_spp(),
            loss: st.mean_psnr() - a.mean_psnr(),
            fixed_loss: fixed.map(|(f, fs)| fs.mean_psnr() - f.mean_psnr()),
        }
    }

    /// `a` against `b`, a camera held still at some of its poses, on the frames whose
    /// poses were held; `fixed64`'s own loss from `f`, the moving camera's `fixed64`,
    /// against `fixed64` held at the same poses.
    fn held(b: &StillBaseline, a: &MotionRun, f: Option<&MotionRun>) -> Self {
        let ((a_spp, a_db), (b_spp, b_db)) = b.compare(a);
        let fixed_loss = f.filter(|_| !b.fixed_psnr.is_empty()).map(|f| {
            let moving: Vec<f64> = b
                .frames
                .iter()
                .map(|&t| f.psnr.get(t as usize).copied().unwrap_or(f64::NAN))
                .collect();
            mean(&b.fixed_psnr) - mean(&moving)
        });
        Self {
            ratio: a_spp / b_spp,
            loss: b_db - a_db,
            fixed_loss,
        }
    }

    /// AS's loss beyond the content's (NaN without `fixed64`'s).
    fn beyond(&self) -> f64 {
        self.fixed_loss.map_or(f64::NAN, |f| self.loss - f)
    }

    fn meets(&self, ratio: f64, loss: f64) -> bool {
        self.ratio <= ratio && self.beyond() <= loss
    }
}

/// The frames a still baseline held, in words (`16, 20, 24`).
fn held_frames(b: &StillBaseline) -> String {
    b.frames
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The pans and the rotation, each against the static camera of its size, and the dolly
/// against a static camera held at its poses (its heights and zooms; [`super::poses`]):
/// at most 1.25x its samples, and AS's loss below it beyond `fixed64`'s own loss on the
/// same cameras at most 1 dB.
fn pan_criterion(rep: &MotionReport, full: bool) -> Vec<Check> {
    let moving = pans(full).into_iter().map(|m| (m, "static-pan")).chain([
        (Motion::Rotate { degrees: 2.0 }, "static"),
        (DOLLY, "static"),
    ]);
    let mut lines = Vec::new();
    for (scene, st_name) in moving {
        let name = scene.name();
        let Some(a) = rep.find(&name, "as") else {
            continue;
        };
        let fixed = rep.find(&name, "fixed64");
        // The baseline: the static camera of the scene's size, or for the dolly the
        // static camera held at its poses.
        let dolly = matches!(scene, Motion::Dolly { .. });
        let (x, against, st_db, st_spp) = if dolly {
            let Some(b) = rep.still.iter().find(|b| b.scene == name) else {
                continue;
            };
            let x = Against::held(b, a, fixed);
            (
                x,
                format!(
                    "the static camera held at its heights (frames {}: {:.1} spp, {:.2} dB)",
                    held_frames(b),
                    mean(&b.spp),
                    mean(&b.psnr)
                ),
                mean(&b.psnr),
                mean(&b.spp),
            )
        } else {
            let Some(st) = rep.find(st_name, "as") else {
                continue;
            };
            let x = Against::of(a, st, fixed.zip(rep.find(st_name, "fixed64")));
            (x, st_name.to_owned(), st.mean_psnr(), st.mean_spp())
        };
        let identity = rep.find(&name, "as-identity").map_or(String::new(), |id| {
            format!(
                "; identity history: {:.1} spp ({:.2}x), {:.2} dB",
                id.mean_spp(),
                id.mean_spp() / st_spp,
                id.mean_psnr()
            )
        });
        let without = rep.find(&name, NO_PRIOR).map_or(String::new(), |b| {
            format!(
                "; without the border prior (beta_min for entering pixels): {:.1} spp, {:.2} dB",
                b.mean_spp(),
                b.mean_psnr()
            )
        });
        let no_depth = match (
            rep.find(&name, NO_REPROJECTED_DEPTH),
            rep.still.iter().find(|b| b.scene == name),
        ) {
            (Some(r), Some(b)) => {
                let y = Against::held(b, r, fixed);
                format!(
                    "; without the reprojected depth (this frame's depth in the depth test): \
                     {:.1} spp = {:.2}x, {:.2} dB = {:+.2} dB below, {:+.2} dB beyond the \
                     content's ({})",
                    r.mean_spp(),
                    y.ratio,
                    r.mean_psnr(),
                    y.loss,
                    y.beyond(),
                    if y.meets(PAN_SPP_RATIO, PAN_LOSS_DB) {
                        "meets the criterion"
                    } else {
                        "fails the criterion"
                    }
                )
            }
            _ => String::new(),
        };
        // The dolly against the static camera at rest height too (its content differs).
        let rest = match (dolly, rep.find("static", "as")) {
            (true, Some(r)) => {
                let y = Against::of(a, r, None);
                format!(
                    "; against the static camera at rest height (`static`): {:.2}x, {:+.2} dB \
                     below",
                    y.ratio, y.loss
                )
            }
            _ => String::new(),
        };
        let content = match x.fixed_loss {
            Some(f) => format!(
                "fixed64 {:.2} dB = {f:+.2} dB below its own on the same camera{} (the content's \
                 share)",
                fixed.map_or(f64::NAN, MotionRun::mean_psnr),
                if dolly { "s held" } else { "" }
            ),
            None => "fixed64 not run on both cameras: the content's share is unknown".into(),
        };
        lines.push(Check::new(
            x.meets(PAN_SPP_RATIO, PAN_LOSS_DB),
            format!(
                "Pan criterion, {name}: AS {:.1} spp = {:.2}x {against} (<= {PAN_SPP_RATIO}x); AS \
                 {:.2} dB = {:+.2} dB below it, {content}, so AS's loss beyond the content's is \
                 {:+.2} dB (<= {PAN_LOSS_DB} dB); on the pixels on screen for 3 frames {:.2} dB \
                 ({:+.2} dB){identity}{without}{no_depth}{rest}{}",
                a.mean_spp(),
                x.ratio,
                a.mean_psnr(),
                x.loss,
                x.beyond(),
                a.mean_psnr_steady(),
                st_db - a.mean_psnr_steady(),
                knob_rows(rep, &name)
            ),
        ));
    }
    lines
}

/// The young-history rows of `scene` against `st` in words: spp ratio and dB below.
fn young_rows(rep: &MotionReport, scene: &str, st: &MotionRun) -> String {
    [AGE_WEIGHT, SPATIAL, NO_SPATIAL, NO_NEIGHBOUR_PRIOR, YOUNG]
        .iter()
        .filter_map(|mode| rep.find(scene, mode))
        .map(|y| {
            let x = Against::of(y, st, None);
            format!(
                "; {}: {:.1} spp = {:.2}x, {:.2} dB = {:+.2} dB below",
                y.mode,
                y.mean_spp(),
                x.ratio,
                y.mean_psnr(),
                x.loss
            )
        })
        .collect()
}

/// Young history under the fastest motions: `pan8` and `rotate2` at no more than 1.25x the
/// spp of the static camera held at their own poses ([`super::poses`]), and AS's loss
/// against it, beyond `fixed64`'s own loss against `fixed64` held at the same poses, at
/// most 0.5 dB (compared on the frames whose poses it held; the static camera at the
/// first pose and the young-history rows quoted).
fn young_history(rep: &MotionReport) -> Vec<Check> {
    let mut lines = Vec::new();
    for (scene, st_name) in [("pan8", "static-pan"), ("rotate2", "static")] {
        let (Some(a), Some(st)) = (rep.find(scene, "as"), rep.find(st_name, "as")) else {
            continue;
        };
        let Some(b) = rep.still.iter().find(|b| b.scene == scene) else {
            continue;
        };
        let first = Against::of(a, st, None);
        let ((a_spp, a_db), (b_spp, b_db)) = b.compare(a);
        let x = Against::held(b, a, rep.find(scene, "fixed64"));
        let content = match x.fixed_loss {
            Some(f) => format!(
                "fixed64 held at the poses {:.2} dB, {f:+.2} dB above its own on those frames \
                 (the content's share)",
                mean(&b.fixed_psnr)
            ),
            None => "fixed64 not run: the content's share is unknown".into(),
        };
        lines.push(Check::new(
            x.ratio <= PAN_SPP_RATIO && x.beyond() <= YOUNG_LOSS_DB,
            format!(
                "Young history, {scene}: AS {:.2}x the spp of the static camera held at its poses \
                 (frames {}: {b_spp:.1} spp, {b_db:.2} dB; AS {a_spp:.1} spp, {a_db:.2} dB on \
                 those frames) (<= {PAN_SPP_RATIO}x), {:+.2} dB below it; {content}; so AS's loss \
                 beyond the content's is {:+.2} dB (<= {YOUNG_LOSS_DB} dB); against {st_name} \
                 (the first pose): {:.2}x, {:+.2} dB below{}",
                x.ratio,
                held_frames(b),
                x.loss,
                x.beyond(),
                first.ratio,
                first.loss,
                young_rows(rep, scene, st)
            ),
        ));
    }
    lines
}

/// The uncovered pixels over their first three frames on screen (ages 1 to 3 pooled).
fn young_pixels(r: &MotionRun, taa: bool) -> AgeErrors {
    let e = if taa {
        r.pooled_uncovered_errors_taa()
    } else {
        r.pooled_uncovered_errors()
    };
    e.classes(1..=3)
}

/// The share of the uncovered pixels at the maximum count: the worst frame's and the
/// mean over frames.
fn at_max(r: &MotionRun) -> (f64, f64) {
    let v: Vec<f64> = r.uncovered_at_max.iter().flatten().copied().collect();
    (v.iter().fold(0.0_f64, |m, &x| m.max(x)), mean(&v))
}

/// Disocclusion by motion, on every moving-object scene: on the newly uncovered pixels
/// over their first three frames on screen, AS spends no more than the identity history
/// does on them, and its PSNR after TAA there is at least the fixed runs' on the same
/// pixels, interpolated in `log2(spp)` at AS's mean spp on them. The share of the
/// uncovered pixels at the maximum count is quoted.
fn disocclusion(rep: &MotionReport) -> Vec<Check> {
    let mut lines = Vec::new();
    for scene in OBJECTS.map(|m| m.name()) {
        let (Some(a), Some(id)) = (rep.find(&scene, "as"), rep.find(&scene, "as-identity")) else {
            continue;
        };
        let (mine, theirs) = (young_pixels(a, false), young_pixels(id, false));
        let (spp, id_spp) = (mine.spp(0), theirs.spp(0));
        let taa = young_pixels(a, true).psnr(0);
        let fixed: Vec<FixedPoint> = rep
            .runs
            .iter()
            .filter(|r| r.scene == scene && r.is_fixed())
            .filter_map(|r| {
                let e = young_pixels(r, true);
                Some(FixedPoint {
                    spp: e.spp(0)?,
                    psnr: e.psnr(0)?,
                })
            })
            .collect();
        let at = spp.and_then(|s| psnr_at_or_extrapolated(&fixed, s));
        let pass = match (spp, id_spp, taa, at) {
            (Some(s), Some(i), Some(p), Some((f, _))) => s <= i && p >= f,
            _ => false,
        };
        let (worst, average) = at_max(a);
        let num = |x: Option<f64>, unit: &str| {
            x.map_or_else(|| "n/a".into(), |x| format!("{x:.2}{unit}"))
        };
        let fixed_text = match at {
            Some((f, extrapolated)) => format!(
                "{f:.2} dB ({} in log2(spp) from {})",
                if extrapolated {
                    "extrapolated"
                } else {
                    "interpolated"
                },
                fixed
                    .iter()
                    .map(|p| format!("{:.0} spp {:.2} dB", p.spp, p.psnr))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            None => "n/a (fewer than two fixed runs)".into(),
        };
        let rows: String = [NO_NEIGHBOUR_PRIOR, YOUNG]
            .iter()
            .filter_map(|mode| rep.find(&scene, mode))
            .map(|y| {
                let (w, _) = at_max(y);
                format!(
                    "; {}: {} spp, after TAA {}, at most {:.1}% at the maximum",
                    y.mode,
                    num(young_pixels(y, false).spp(0), ""),
                    num(young_pixels(y, true).psnr(0), " dB"),
                    100.0 * w
                )
            })
            .collect();
        let steady = mean(&a.steady_spp.iter().flatten().copied().collect::<Vec<_>>());
        lines.push(Check::new(
            pass,
            format!(
                "Disocclusion cost, {scene}: on the newly uncovered pixels over their first three \
                 frames on screen ({} pixel-frames), AS {} spp vs the identity history {} spp \
                 (need <=); AS after TAA {} vs the fixed runs after TAA on the same pixels at AS's \
                 spp {fixed_text} (need >=); {:.1}% of the uncovered pixels at the maximum count \
                 in the worst frame, {:.1}% on average (the steady pixels {steady:.1} spp){rows}",
                mine.n[0],
                num(spp, ""),
                num(id_spp, ""),
                num(taa, " dB"),
                100.0 * worst,
                100.0 * average
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
        .filter(|r| r.mode == "as" && OBJECTS.iter().any(|m| m.name() == r.scene))
        .filter_map(|a| {
            let id = rep.find(&a.scene, "as-identity")?;
            let young: String = [AGE_WEIGHT, SPATIAL, NO_SPATIAL, NO_NEIGHBOUR_PRIOR, YOUNG]
                .iter()
                .filter_map(|mode| rep.find(&a.scene, mode))
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
                .filter_map(|&f| rep.find(&a.scene, &tighter_name(f)))
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
/// pixels at their third frame on screen against the steady pixels (AS; PSNR of the MSE
/// pooled over every pixel-frame of the class after the warm-up); AS's loss there beyond
/// `fixed64`'s own gap on the same pixels (the content's share) at most 0.5 dB.
fn uncovered_error(rep: &MotionReport) -> Vec<Check> {
    // The third frame against the steady pixels, dB (negative: below them).
    let gap = |e: &AgeErrors| e.psnr(3).zip(e.psnr(0)).map(|(t, s)| t - s);
    let signed = |x: Option<f64>| x.map_or_else(|| "n/a".into(), |x| format!("{x:+.2} dB"));
    rep.runs
        .iter()
        .filter(|r| r.mode == "as" && !r.uncovered_errors.is_empty())
        .map(|a| {
            let e = a.pooled_uncovered_errors();
            let fixed = rep
                .find(&a.scene, "fixed64")
                .map(MotionRun::pooled_uncovered_errors);
            // AS's loss (minus its gap) beyond fixed64's own loss.
            let beyond = gap(&e)
                .zip(fixed.as_ref().and_then(gap))
                .map(|(g, f)| f - g);
            let quoted: String = [YOUNG, "fixed64"]
                .iter()
                .filter_map(|mode| rep.find(&a.scene, mode))
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
                beyond.is_some_and(|b| b <= YOUNG_LOSS_DB),
                format!(
                    "Uncovered pixels, {}: AS at their third frame on screen {} vs steady {} \
                     ({}), fixed64's own gap {} (the content's share), so AS's loss beyond the \
                     content's is {} (<= {YOUNG_LOSS_DB} dB); first frame {}, second {}; PSNR of \
                     the MSE pooled over frames {} ({} pixel-frames at age 3, {} steady){quoted}",
                    a.scene,
                    db(e.psnr(3)),
                    db(e.psnr(0)),
                    signed(gap(&e)),
                    signed(fixed.as_ref().and_then(gap)),
                    signed(beyond),
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
            let a = rep.find(scene, "as")?;
            let (single, taa) = (rep.fixed_points(scene, false), rep.fixed_points(scene, true));
            let (f, extrapolated) = psnr_at_or_extrapolated(&taa, a.mean_spp())?;
            let eq = EqualQuality::new(&single, a.mean_spp(), a.mean_psnr());
            let eq_taa = EqualQuality::new(&taa, a.mean_spp(), a.mean_psnr_taa());
            let eq_var =
                EqualQuality::new(&rep.fixed_variance_points(scene), a.mean_spp(), a.var_db_taa());
            Some(Check::new(
                a.mean_psnr_taa() > f,
                format!(
                    "Final image (AO), {scene}: AS after TAA {:.2} dB at {:.1} spp vs the fixed runs after TAA at the same spp {f:.2} dB ({}; need >), margin {:+.2} dB; equal quality single-frame {eq}, after TAA {eq_taa}, at equal variance after TAA {eq_var} (its error after TAA: variance {:.2e} + bias^2 {:.2e})",
                    a.mean_psnr_taa(),
                    a.mean_spp(),
                    if extrapolated {
                        "extrapolated in log2(spp) from the nearest two fixed runs"
                    } else {
                        "interpolated in log2(spp)"
                    },
                    a.mean_psnr_taa() - f,
                    a.mean_var_taa(),
                    a.mean_bias2_taa()
                ),
            ))
        })
        .collect()
}

/// The resolved-image rule ([`RESOLVED`]) against AS, after TAA, on every scene that ran
/// both, judged on every scene: its margin over the fixed runs at its own spp at least AS's
/// (the per-frame rule) at AS's spp; its equal quality after TAA against the ideal `1/f`
/// ([`IDEAL_SHARE_TARGETS`]) or 1.0x ([`SAVES_SCENES`]); its instability after TAA
/// against the fixed runs' at the same PSNR after TAA. Each line carries the error after
/// TAA split into variance and squared bias, and equal quality at equal variance.
fn resolved_image(rep: &MotionReport) -> Vec<Check> {
    let mut judged = Vec::new();
    let mut scenes: Vec<&str> = Vec::new();
    for r in &rep.runs {
        if r.mode == RESOLVED && !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    for scene in scenes {
        let (Some(r), Some(a)) = (rep.find(scene, RESOLVED), rep.find(scene, "as")) else {
            continue;
        };
        let taa = rep.fixed_points(scene, true);
        let var = rep.fixed_variance_points(scene);
        let eq = |x: &MotionRun| EqualQuality::new(&taa, x.mean_spp(), x.mean_psnr_taa());
        let eq_var = |x: &MotionRun| EqualQuality::new(&var, x.mean_spp(), x.var_db_taa());
        let margin = |x: &MotionRun| {
            psnr_at_or_extrapolated(&taa, x.mean_spp())
                .map_or(f64::NAN, |(f, _)| x.mean_psnr_taa() - f)
        };
        let (eq_r, eq_a) = (eq(r), eq(a));
        let (m_r, m_a) = (margin(r), margin(a));
        let ideal = r.mean_allocation_bounds()[0];
        let split = |x: &MotionRun| {
            format!(
                "variance {:.2e} + bias^2 {:.2e}, equal quality at equal variance {}",
                x.mean_var_taa(),
                x.mean_bias2_taa(),
                eq_var(x)
            )
        };
        let figures = format!(
            "{RESOLVED} (floor {RESOLVED_FLOOR}) {:.1} spp at {:.2} dB after TAA ({m_r:+.2} dB over the fixed runs at its spp), equal quality after TAA {eq_r} ({}); the per-frame rule (as) {:.1} spp at {:.2} dB ({m_a:+.2} dB), {eq_a} ({}); the variance-equalizing rule's ideal 1/f = {ideal:.2}x (independent samples, exact variances, no floor or cap; f the pixels of nonzero variance)",
            r.mean_spp(),
            r.mean_psnr_taa(),
            split(r),
            a.mean_spp(),
            a.mean_psnr_taa(),
            split(a),
        );
        judged.push(Check::new(
            m_r >= m_a,
            format!("Resolved >= per-frame, {scene}: {m_r:+.2} dB against {m_a:+.2} dB at equal spp after TAA (need >=); {figures}"),
        ));
        if let Some((_, need)) = IDEAL_SHARE_TARGETS.iter().find(|(s, _)| *s == scene) {
            let share = eq_r.ratio().map_or(f64::NAN, |x| x / ideal);
            judged.push(Check::new(
                share >= *need,
                format!("Resolved image against its ideal, {scene}: {eq_r} is {share:.2} of 1/f = {ideal:.2}x (need >= {need:.2}); AS {eq_a}"),
            ));
        }
        if SAVES_SCENES.contains(&scene) {
            judged.push(Check::new(
                eq_r.ratio().is_some_and(|x| x >= 1.0),
                format!("Resolved image saves, {scene}: equal quality after TAA {eq_r} (need >= 1.0x); AS {eq_a}"),
            ));
        }
        let flicker = flicker_at_psnr(&rep.fixed_flicker_points(scene), r.mean_psnr_taa());
        if let Some((f, outside)) = flicker {
            judged.push(Check::new(
                r.mean_flicker_taa() <= f,
                format!(
                    "Resolved image, flicker, {scene}: {RESOLVED} after TAA {:.3e} vs the fixed runs after TAA at its PSNR after TAA ({:.2} dB) {f:.3e} ({}; need <=); AS {:.3e}",
                    r.mean_flicker_taa(),
                    r.mean_psnr_taa(),
                    if outside {
                        "extrapolated in PSNR from the nearest two fixed runs"
                    } else {
                        "log-interpolated in PSNR"
                    },
                    a.mean_flicker_taa()
                ),
            ));
        }
    }
    judged
}

/// The GPU against the CPU twin, per scene: every GPU run (and every baseline and bound
/// run) equal to the twin on every frame (counts, and the adaptive component's history
/// texels, on every pixel; the AO values and prefix estimates on the lattice of
/// [`super::render`]). A run that differs on any frame is corrupt: the line fails, names
/// the run and the frame, and the run is not scored. No exception applies: the passes
/// are held bit-equal to the twin (`spvg-wgpu/tests/determinism.rs`).
fn gpu_vs_twin(rep: &MotionReport) -> Vec<Check> {
    let mut scenes: Vec<&str> = Vec::new();
    for c in &rep.twin_checks {
        if !scenes.contains(&c.scene.as_str()) {
            scenes.push(&c.scene);
        }
    }
    scenes
        .into_iter()
        .map(|scene| {
            let checks: Vec<&TwinCheck> = rep
                .twin_checks
                .iter()
                .filter(|c| c.scene == scene)
                .collect();
            let frames: u32 = checks.iter().map(|c| c.frames).sum();
            let lattice: u64 = checks.iter().map(|c| c.lattice).sum();
            let adaptive = checks.iter().filter(|c| c.adaptive).count();
            let mut names: Vec<&str> = Vec::new();
            for c in &checks {
                if !names.contains(&c.run.as_str()) {
                    names.push(&c.run);
                }
            }
            let corrupt: Vec<String> = checks
                .iter()
                .filter_map(|c| {
                    let d = c.corrupt.as_ref()?;
                    Some(format!(
                        "; CORRUPT, not scored: {scene} {} frame {}: {} differs at {} pixels \
                         (first ({}, {}); by x mod 8 {:?}), {} of its {} frames differ",
                        c.run,
                        d.frame,
                        d.what,
                        d.pixels,
                        d.first[0],
                        d.first[1],
                        d.lanes,
                        c.frames_differing,
                        c.frames
                    ))
                })
                .collect();
            Check::new(
                corrupt.is_empty(),
                format!(
                    "GPU vs twin, {scene}: {} GPU run{} ({}), {frames} frames in all, each frame \
                     equal to the twin: counts{} on every pixel (the adaptive runs, {adaptive}: \
                     the twin's component fed the GPU's AO values), AO values and prefix \
                     estimates on the lattice ({lattice} pixel-frames, every x mod 8 and every \
                     row in every frame) (need 100% on every frame; no exception applies){}",
                    checks.len(),
                    if checks.len() == 1 { "" } else { "s" },
                    names.join(", "),
                    if adaptive > 0 {
                        " and history texels"
                    } else {
                        ""
                    },
                    corrupt.concat()
                ),
            )
        })
        .collect()
}

/// Every acceptance line of the motion section, in report order, as one judged group.
#[must_use]
pub fn acceptance(rep: &MotionReport, full: bool) -> Vec<Group> {
    let mut lines = static_cameras(rep);
    lines.extend(pan_criterion(rep, full));
    lines.extend(young_history(rep));
    lines.extend(disocclusion(rep));
    lines.extend(reprojection_beats_identity(rep));
    lines.extend(uncovered_error(rep));
    lines.extend(motion_bound(rep));
    lines.extend(final_image(rep));
    lines.extend(gpu_vs_twin(rep));
    vec![
        Group::judged("Acceptance (motion)", lines),
        Group::judged(
            "The resolved-image rule (as-resolved against AS, after TAA)",
            resolved_image(rep),
        ),
    ]
}
